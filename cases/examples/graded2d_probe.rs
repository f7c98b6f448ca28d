//! The graded 2D cylinder's biharmonic iterations per size, with the hierarchy's levels:
//! `cargo run --release -p meshmove-cases --example graded2d_probe -- [VERTICES,…] [TOL] [DEGREE] [COARSE_DEGREE]`
//! (default 30000,120000: the bench's `graded` sizes; the O-grid of `cases::ogrid`, triangles,
//! walls fixed, the body clamped and moved 0.1 in x as in `meshmove bench --parts graded`; the
//! Chebyshev degrees the solver's own unless given).

use meshmove::{BoundaryConditions, Kind, Motion, Options, RigidMotion, SolveParams, Solver};
use meshmove_cases::ogrid::{self, CellKind};
use std::time::Instant;

#[path = "common/solve_line.rs"]
mod solve_line;
use solve_line::solve_line;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let sizes: Vec<usize> = args
        .first()
        .map_or(vec![30_000, 120_000], |s| s.split(',').map(|x| x.parse().expect("a vertex count")).collect());
    let tol: f64 = args.get(1).map_or(1e-8, |s| s.parse().expect("a tolerance"));
    let degree = |i: usize| args.get(i).map(|s| s.parse::<usize>().expect("a degree"));
    let (cheb_degree, cheb_coarse_degree) = (degree(2), degree(3));
    for n in sizes {
        let mesh = ogrid::cylinder_with_vertices(n, CellKind::Simplex).expect("an O-grid");
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(ogrid::OG_WALL, Kind::Fixed).set_kinds(ogrid::OG_BODY, Kind::Clamped);
        let r = RigidMotion { translation: [0.1, 0.0, 0.0], rotation: [0.0; 3], center: [0.0; 3] };
        let motion = Motion::zero(&mesh).with_rigid(ogrid::OG_BODY, r);
        let t = Instant::now();
        let solver = Solver::new(
            &mesh,
            &bcs,
            Options {
                solve: SolveParams { tol, cheb_degree, cheb_coarse_degree, ..Default::default() },
                ..Default::default()
            },
        )
        .expect("a solver");
        println!("cylinder {} vertices, setup {:.2} s", mesh.num_vertices(), t.elapsed().as_secs_f64());
        print!("{}", solver.describe());
        match solver.solve(&motion) {
            Ok(sol) => println!(
                "{}, min volume to six digits {:.6}, solve {:.2} s",
                solve_line(&sol),
                sol.quality.min_area_ratio,
                sol.report.seconds
            ),
            Err(e) => println!("error: {e}"),
        }
    }
}
