//! A viscous mesh's one-step biharmonic solve with each PCG iteration's largest correction and
//! relative residual: `cargo run --release -p meshmove-cases --example history_probe -- spheroid 8
//! pitch|plunge [layers|zero] [TOL]` (kinds and sizes as in `viscous_sizes`). `zero` starts from
//! a zero guess instead of the start along the lines.

use meshmove::{Options, Solver};
use meshmove_cases::viscous::*;

#[path = "common/viscous_args.rs"]
mod viscous_args;
use viscous_args::kind_size_motion;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (kind, size, m) = kind_size_motion(&args);
    let zero = args.get(3).is_some_and(|s| s == "zero");
    let tol: f64 = args.get(4).map_or(1e-8, |s| s.parse().expect("a tolerance"));
    let v = by_name(kind, size).expect("a mesh");
    let bcs = boundary_conditions(&v);
    let motion = motion(&v, m);
    let opts = Options { solve: meshmove::SolveParams { tol, ..Default::default() }, ..Default::default() };
    let solver = Solver::new(&v.mesh, &bcs, opts).expect("a solver");
    let guess = zero.then(|| vec![0.0; v.mesh.coords().len()]);
    let sol = solver.solve_report(&motion, guess.as_deref()).expect("a solve");
    println!(
        "{kind} {size} {} start {}: {} vertices",
        m.name(),
        if zero { "zero" } else { "layers" },
        v.mesh.num_vertices()
    );
    for (k, (c, r)) in sol.report.history.iter().enumerate() {
        println!("  {:3} max correction {c:.3e} residual {r:.3e}", k + 1);
    }
    let moved: Vec<f64> = v.mesh.coords().iter().zip(&sol.displacement).map(|(x, d)| x + d).collect();
    println!(
        "{} iterations, residual {:.2e}, converged {}, min volume {:.4}, first layer {:?}",
        sol.report.cycles,
        sol.report.rel_residual,
        sol.report.converged,
        sol.quality.min_area_ratio,
        layer_volume_ratios(&v, &moved, 1)
    );
}
