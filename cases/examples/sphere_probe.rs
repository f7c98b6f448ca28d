//! The graded sphere of the bench (`ogrid::sphere_with_vertices`, tetrahedra, the body clamped
//! and moved 0.1 in x, the box's walls fixed) at a given vertex count: per method its levels,
//! whether lines were found, iterations and seconds, and optionally the two-level analysis of
//! the biharmonic's x component:
//! `cargo run --release -p meshmove-cases --example sphere_probe -- 25000 [METHODS] [PAIRS] [DEGREE] [COARSE_DEGREE] [COARSEST]`
//! (METHODS: `b`, `l`, `s` letters, default `bl`; PAIRS: the two-level pairs' finer levels,
//! comma-separated, none when empty or `-`; the Chebyshev degrees and
//! the coarsest level's largest size the solver's own unless given).

use meshmove::multigrid::policy::CycleParams;
use meshmove::multigrid::two_level::analyse_pair;
use meshmove::{BoundaryConditions, HierarchyParams, Kind, Method, Motion, Options, RigidMotion, SolveParams, Solver};
use meshmove_cases::ogrid::{self, CellKind};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let vertices: usize = args.first().map_or(25_000, |s| s.parse().expect("a vertex count"));
    let methods = args.get(1).map_or("bl", |s| s.as_str());
    let pairs: Vec<usize> = args.get(2).map_or(Vec::new(), |s| {
        s.split(',').filter(|x| !x.is_empty() && *x != "-").map(|x| x.parse().expect("a level")).collect()
    });
    let degree = |i: usize| args.get(i).filter(|s| *s != "-").map(|s| s.parse::<usize>().expect("a number"));
    let (cheb_degree, cheb_coarse_degree) = (degree(3), degree(4));
    let mut hierarchy = HierarchyParams::default();
    hierarchy.coarsen.coarsest_unknowns = degree(5);
    let t = Instant::now();
    let mesh = ogrid::sphere_with_vertices(vertices, CellKind::Simplex).expect("the sphere");
    let s = ogrid::measure(&mesh, ogrid::OG_BODY);
    println!(
        "sphere: {} vertices, {} cells, min angle {:.2}, max edge ratio {:.1}, body edge {:.4}, wall-normal edge {:.4}; {:.1} s",
        mesh.num_vertices(),
        mesh.num_cells(),
        s.min_angle_deg,
        s.max_edge_ratio,
        s.body_edge,
        s.wall_normal_edge,
        t.elapsed().as_secs_f64()
    );
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(ogrid::OG_WALL, Kind::Fixed).set_kinds(ogrid::OG_BODY, Kind::Clamped);
    let r = RigidMotion { translation: [0.1, 0.0, 0.0], rotation: [0.0; 3], center: [0.0; 3] };
    let motion = Motion::zero(&mesh).with_rigid(ogrid::OG_BODY, r);
    for c in methods.chars() {
        let method = match c {
            'b' => Method::Biharmonic,
            'l' => Method::Laplacian,
            's' => Method::Spring,
            _ => panic!("methods are b, l, s"),
        };
        let solve = SolveParams { cheb_degree, cheb_coarse_degree, ..Default::default() };
        let t = Instant::now();
        let solver = Solver::new(
            &mesh,
            &bcs,
            Options { method, solve, threads: 1, hierarchy: hierarchy.clone(), ..Default::default() },
        )
        .expect("a solver");
        let setup = t.elapsed().as_secs_f64();
        let h = solver.hierarchy();
        println!("{method:?}: lines {}, setup {setup:.2} s", h.has_lines());
        print!("{}", solver.describe());
        let t = Instant::now();
        let sol = solver.solve(&motion).expect("a solution");
        println!(
            "{method:?}: {} iterations (converged {}, residual {:.2e}), min volume ratio {:.4}, solve {:.2} s",
            sol.report.cycles,
            sol.report.converged,
            sol.report.rel_residual,
            sol.quality.min_area_ratio,
            t.elapsed().as_secs_f64()
        );
        if method != Method::Biharmonic || pairs.is_empty() {
            continue;
        }
        let h = solver.hierarchy();
        let cp = CycleParams::resolve(h, &SolveParams { cheb_degree, cheb_coarse_degree, ..Default::default() });
        let comps = h.groups().into_iter().find(|g| g.contains(&0)).expect("a group with x");
        for &l in &pairs {
            let t = Instant::now();
            let Some(a) = analyse_pair(h, &cp, comps.clone(), l, 1e-8, 12) else { continue };
            println!("{}; {:.1} s", a.summary(h), t.elapsed().as_secs_f64());
        }
    }
}
