//! When does keeping the multigrid hierarchy across steps pay? Runs multi-step motions twice:
//! the solver re-evaluating its hierarchy on the moved mesh (`advance`, the default), and a new
//! solver built on every step's mesh. Prints cycles and seconds of both.
//!
//! `cargo run --release -p meshmove-cases --example reuse_probe`

use meshmove::{InterfaceVariant, Method, Options, Solver};
use meshmove_cases::setups::{free_surface_case, interface_case, CaseSetup};
use std::time::Instant;

fn reused(setup: &CaseSetup, method: Method) -> (usize, f64) {
    let t0 = Instant::now();
    let mut s = Solver::new(&setup.mesh, &setup.bcs, Options { method, ..Default::default() }).unwrap();
    let mut cycles = 0;
    for i in 0..setup.steps {
        cycles += s.advance(&setup.motion.increment(i, setup.steps)).unwrap().report.cycles;
    }
    (cycles, t0.elapsed().as_secs_f64())
}

fn rebuilt(setup: &CaseSetup, method: Method) -> (usize, f64) {
    let t0 = Instant::now();
    let mut mesh = setup.mesh.clone();
    let mut cycles = 0;
    for i in 0..setup.steps {
        let s = Solver::new(&mesh, &setup.bcs, Options { method, ..Default::default() }).unwrap();
        let sol = s.solve(&setup.motion.increment(i, setup.steps)).unwrap();
        cycles += sol.report.cycles;
        mesh = mesh.with_coords(mesh.coords().iter().zip(&sol.displacement).map(|(x, d)| *x + *d).collect());
    }
    (cycles, t0.elapsed().as_secs_f64())
}

fn main() {
    let cos = |x: f64| 0.375 * (std::f64::consts::TAU * x).cos();
    let cases = [
        free_surface_case("free surface h=1/32, 10 steps", 1.0 / 32.0, 0.25, 10),
        free_surface_case("free surface h=1/128, 10 steps", 1.0 / 128.0, 0.25, 10),
        interface_case("deforming interface A, 15 steps", 1.0 / 32.0, InterfaceVariant::Separate, cos, 15),
    ];
    println!("case | method | reused: cycles, s | rebuilt every step: cycles, s");
    for c in &cases {
        for m in [Method::Biharmonic, Method::Laplacian] {
            let (a, ta) = reused(c, m);
            let (b, tb) = rebuilt(c, m);
            println!("{} | {m:?} | {a}, {ta:.3} | {b}, {tb:.3}", c.name);
        }
    }
}
