//! The graded sphere of the bench (`ogrid::sphere_with_vertices`, tetrahedra, the body clamped
//! and moved 0.1 in x, the box's walls fixed) at a given vertex count: per method its levels,
//! whether lines were found, iterations and seconds, and optionally the two-level analysis of
//! the biharmonic's x component:
//! `cargo run --release -p meshmove-cases --example sphere_probe -- 25000 [METHODS] [PAIRS] [DEGREE] [COARSE_DEGREE] [COARSEST] [GROWTH]`
//! (METHODS: `b`, `l`, `s` letters, default `bl`; PAIRS: the two-level pairs' finer levels,
//! comma-separated, none when empty or `-`; the Chebyshev degrees and
//! the coarsest level's largest size the solver's own unless given; GROWTH: the shell's layer
//! growth rate instead of the bench's 1.2, the wall size chosen again for the vertex count).
//! Each pair's slow mode's
//! energy is printed binned by radius and by the coordinates beyond 10 (the box's corners).
//! The mesh's radial and tangential edge lengths are printed binned by radius: how anisotropic
//! the cells are between the body and the box.

use meshmove::multigrid::policy::CycleParams;
use meshmove::multigrid::two_level::analyse_pair;
use meshmove::{BoundaryConditions, HierarchyParams, Kind, Method, Motion, Options, RigidMotion, SolveParams, Solver};
use meshmove_cases::ogrid::{self, CellKind, OgridParams};
use std::collections::HashSet;
use std::hash::{Hash, Hasher};
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
    let mesh = match args.get(6).filter(|s| *s != "-") {
        Some(g) => sphere_with_growth(vertices, g.parse().expect("a growth rate")),
        None => ogrid::sphere_with_vertices(vertices, CellKind::Simplex).expect("the sphere"),
    };
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
    spacing_by_radius(&mesh);
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
        // The stop test under lines (`strain`) may run past the residual's tolerance: the
        // iteration where the residual alone met it.
        let by_residual = sol.report.history.iter().position(|h| h.1 <= 1e-8).map_or(0, |k| k + 1);
        // A hash of the displacement's bits: a setup change that keeps the hierarchy bitwise
        // keeps it too.
        let mut hash = std::collections::hash_map::DefaultHasher::new();
        sol.displacement.iter().for_each(|d| d.to_bits().hash(&mut hash));
        println!(
            "{method:?}: {} iterations, {by_residual} to the residual's 1e-8 (converged {}, residual {:.2e}), min volume ratio {:.4}, solve {:.2} s, hash {:016x}",
            sol.report.cycles,
            sol.report.converged,
            sol.report.rel_residual,
            sol.quality.min_area_ratio,
            t.elapsed().as_secs_f64(),
            hash.finish()
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
            where_energy_lies(h, &a);
        }
    }
}

/// The slow mode's energy (before, after the smoother, after the exact coarse correction) summed
/// over bins of its unknowns' radius and over how many coordinates lie beyond 10 (the box's
/// corners, where the O-grid's blocks stretch the cells, hold 3).
fn where_energy_lies(h: &meshmove::multigrid::hierarchy::Hierarchy, a: &meshmove::multigrid::two_level::PairAnalysis) {
    let level = &h.levels[a.level];
    let points = level.unknown_points();
    let edges = [0.0, 0.6, 1.0, 2.0, 5.0, 10.0, 20.0, f64::INFINITY];
    let mut by_r = vec![[0.0f64; 4]; edges.len() - 1];
    let mut by_corner = [[0.0f64; 4]; 4];
    for i in 0..level.n() {
        let x = &points[3 * i..3 * i + 3];
        let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
        let b = edges.windows(2).position(|w| r >= w[0] && r < w[1]).unwrap_or(0);
        let k = x.iter().filter(|v| v.abs() > 10.0).count();
        for (bin, add) in [(&mut by_r[b], 1.0), (&mut by_corner[k], 1.0)] {
            bin[0] += add;
            bin[1] += a.density[i];
            bin[2] += a.smoothed_density[i];
            bin[3] += a.corrected_density[i];
        }
    }
    for (b, v) in by_r.iter().enumerate() {
        println!(
            "  r in [{}, {}): {} unknowns, energy {:.3}, smoothed {:.3}, coarse-corrected {:.3}",
            edges[b],
            edges[b + 1],
            v[0],
            v[1],
            v[2],
            v[3]
        );
    }
    for (k, v) in by_corner.iter().enumerate() {
        println!(
            "  {k} coordinates beyond 10: {} unknowns, energy {:.3}, smoothed {:.3}, coarse-corrected {:.3}",
            v[0], v[1], v[2], v[3]
        );
    }
}

/// The medians of the mesh's radial edges (within 18° of the radius at their midpoint) and of
/// its tangential edges (within 12° of normal to it), binned by the midpoint's radius, and their
/// ratio: where the O-grid's cells are longer across the shell than along it.
fn spacing_by_radius(mesh: &meshmove::Mesh) {
    let edges = [0.5, 1.0, 2.0, 3.0, 5.0, 10.0, 15.0];
    let mut radial = vec![Vec::new(); edges.len() - 1];
    let mut tangential = vec![Vec::new(); edges.len() - 1];
    let mut seen = HashSet::new();
    for c in 0..mesh.num_cells() {
        let cell = mesh.cell(c);
        for (i, &a) in cell.iter().enumerate() {
            for &b in &cell[i + 1..] {
                if !seen.insert((a.min(b), a.max(b))) {
                    continue;
                }
                let (pa, pb) = (mesh.point(a as usize), mesh.point(b as usize));
                let mid: Vec<f64> = (0..3).map(|k| 0.5 * (pa[k] + pb[k])).collect();
                let d: Vec<f64> = (0..3).map(|k| pb[k] - pa[k]).collect();
                let r = mid.iter().map(|x| x * x).sum::<f64>().sqrt();
                let len = d.iter().map(|x| x * x).sum::<f64>().sqrt();
                let cos = (0..3).map(|k| d[k] * mid[k]).sum::<f64>().abs() / (len * r);
                let Some(bin) = edges.windows(2).position(|w| r >= w[0] && r < w[1]) else { continue };
                if cos > 0.95 {
                    radial[bin].push(len);
                } else if cos < 0.2 {
                    tangential[bin].push(len);
                }
            }
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
    };
    for (b, (rad, tan)) in radial.iter_mut().zip(&mut tangential).enumerate() {
        let (r, t) = (median(rad), median(tan));
        println!(
            "  r in [{}, {}): radial edge {r:.3} ({} edges), tangential {t:.3} ({}), ratio {:.2}",
            edges[b],
            edges[b + 1],
            rad.len(),
            tan.len(),
            r / t
        );
    }
}

/// The bench's sphere (`ogrid::sphere_with_vertices`: wall cells 1/50 of the far ones) with the
/// shell's layers growing by `growth`, its wall size the largest whose mesh has at most
/// `vertices` vertices (bisection).
fn sphere_with_growth(vertices: usize, growth: f64) -> meshmove::Mesh {
    let at =
        |wall: f64| OgridParams { growth, ..OgridParams::sphere([0.0; 3], 0.5, [[-20.0, 20.0]; 3], wall, 50.0 * wall) };
    let count = |wall: f64| ogrid::plan(&at(wall)).map_or(usize::MAX, |p| p.num_vertices(CellKind::Simplex));
    let (mut lo, mut hi) = (1e-4f64, 0.125f64);
    for _ in 0..40 {
        let mid = (lo * hi).sqrt();
        if count(mid) > vertices {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    ogrid::ogrid(&at(hi)).expect("the sphere")
}
