//! The biharmonic's iterations on the wall-layered meshes, with the hierarchy's levels:
//! `cargo run --release -p meshmove-cases --example galerkin_probe -- airfoil 64 [pitch|plunge] [STEPS] [METHOD] [TOL] [DEGREE] [COARSE_DEGREE] [MAX_LEVELS]`
//! (kinds and sizes as in `viscous_sizes`; the Chebyshev degrees the solver's own unless given;
//! MAX_LEVELS cuts the hierarchy, its last level then factored when small enough).

use meshmove::{Method, Options, Solver};
use meshmove_cases::viscous::*;
use std::time::Instant;

#[path = "common/solve_line.rs"]
mod solve_line;
use solve_line::solve_line;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let kind = args.first().map_or("airfoil", |s| s.as_str());
    let size = args.get(1).map_or("64", |s| s.as_str());
    let m = match args.get(2).map(|s| s.as_str()) {
        Some("plunge") => BodyMotion::Plunge,
        _ => BodyMotion::Pitch,
    };
    let steps: usize = args.get(3).map_or(1, |s| s.parse().expect("steps"));
    let method = match args.get(4).map(|s| s.as_str()) {
        Some("laplacian") => Method::Laplacian,
        Some("spring") => Method::Spring,
        _ => Method::Biharmonic,
    };
    let tol: f64 = args.get(5).map_or(1e-8, |s| s.parse().expect("a tolerance"));
    let degree = |i: usize| args.get(i).map(|s| s.parse::<usize>().expect("a degree"));
    let (cheb_degree, cheb_coarse_degree) = (degree(6), degree(7));
    let mut hierarchy = meshmove::HierarchyParams::default();
    if let Some(m) = degree(8) {
        hierarchy.max_levels = m;
    }
    let v = by_name(kind, size).expect("a mesh");
    let bcs = boundary_conditions(&v);
    let motion = motion(&v, m);
    let t = Instant::now();
    let mut solver = Solver::new(
        &v.mesh,
        &bcs,
        Options {
            method,
            solve: meshmove::SolveParams { tol, cheb_degree, cheb_coarse_degree, ..Default::default() },
            hierarchy,
            ..Default::default()
        },
    )
    .expect("a solver");
    println!(
        "{kind} {size} {method:?} {}: {} vertices, setup {:.2} s",
        m.name(),
        v.mesh.num_vertices(),
        t.elapsed().as_secs_f64()
    );
    print!("{}", solver.describe());
    let mut its = Vec::new();
    if steps == 1 {
        // One step by `solve`, whose report tells the polish's cycles apart.
        let t = Instant::now();
        match solver.solve(&motion) {
            Ok(sol) => {
                let moved: Vec<f64> = v.mesh.coords().iter().zip(&sol.displacement).map(|(x, d)| x + d).collect();
                println!(
                    "step 1: {}, first layer {:?}, first 10 layers {:?}, solve {:.2} s, step {:.2} s",
                    solve_line(&sol),
                    layer_volume_ratios(&v, &moved, 1),
                    layer_volume_ratios(&v, &moved, 10),
                    sol.report.seconds,
                    t.elapsed().as_secs_f64()
                );
            }
            Err(e) => println!("step 1: {e}"),
        }
        return;
    }
    for i in 0..steps {
        let t = Instant::now();
        match solver.advance(&motion.increment(i, steps)) {
            Ok(sol) => {
                its.push(sol.report.cycles);
                println!(
                    "step {}: {} iterations, residual {:.2e}, converged {}, inverted {}, min volume {:.4}, solve {:.2} s, step {:.2} s",
                    i + 1,
                    sol.report.cycles,
                    sol.report.rel_residual,
                    sol.report.converged,
                    sol.quality.inverted,
                    sol.quality.min_area_ratio,
                    sol.report.seconds,
                    t.elapsed().as_secs_f64()
                );
                println!("re-reference phases (the one this step began with): {:?}", solver.phases());
            }
            Err(e) => {
                println!("step {}: {e}", i + 1);
                break;
            }
        }
    }
    println!("iterations max {:?} of {:?}", its.iter().max(), its);
}
