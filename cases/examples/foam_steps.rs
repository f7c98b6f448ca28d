//! The time loop of `scripts/peer-openfoam-steps.sh` through the library: the sphere of an
//! OpenFOAM case of that script oscillating along x by 0.1 sin(2πk/20) over 20 steps, one
//! `Solver::advance` a step (re-referenced after each), the cube's walls fixed; per step the
//! iterations, the seconds of its re-reference and solve, and the smallest volume ratio against
//! the step's start:
//! `cargo run --release -p meshmove-cases --example foam_steps -- CASE_DIR [METHOD] [DEGREE [COARSE_DEGREE]]`
//! (METHOD `b` biharmonic with the sphere clamped, the default, or `l` Laplacian with it fixed;
//! DEGREE and COARSE_DEGREE the Chebyshev degrees, else the method's defaults; one thread).

use meshmove::io::read_polymesh;
use meshmove::{BoundaryConditions, Kind, Method, Motion, Options, RigidMotion, Solver};
use std::path::PathBuf;
use std::time::Instant;

/// Steps over the period, and the sphere's amplitude along x.
const STEPS: usize = 20;
const AMPLITUDE: f64 = 0.1;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = PathBuf::from(args.first().expect("an OpenFOAM case directory"));
    let (method, body) = match args.get(1).map_or("b", |s| s.as_str()) {
        "b" => (Method::Biharmonic, Kind::Clamped),
        "l" => (Method::Laplacian, Kind::Fixed),
        m => panic!("method is b or l, got {m}"),
    };
    let degree: Option<usize> = args.get(2).map(|d| d.parse().expect("a degree"));
    let coarse: Option<usize> = args.get(3).map(|d| d.parse().expect("a coarse degree"));
    let foam = read_polymesh(&dir).expect("a polyMesh");
    let mesh = foam.to_mesh().expect("a mesh");
    let sphere = foam.patch_names.iter().find(|(_, n)| n == "sphere").expect("a patch `sphere`").0;
    let mut bcs = BoundaryConditions::new();
    for (id, _) in &foam.patch_names {
        bcs.set_kinds(*id, if *id == sphere { body } else { Kind::Fixed });
    }
    let mut opts = Options { method, threads: 1, ..Default::default() };
    opts.solve.tol = 1e-8;
    opts.solve.cheb_degree = degree;
    opts.solve.cheb_coarse_degree = coarse;
    let t = Instant::now();
    let mut solver = Solver::new(&mesh, &bcs, opts).expect("a solver");
    println!(
        "{}: {} vertices, {method:?}, lines {}, degrees {degree:?}/{coarse:?}, setup {:.3} s",
        dir.display(),
        mesh.num_vertices(),
        solver.hierarchy().has_lines(),
        t.elapsed().as_secs_f64()
    );
    let at = |k: usize| AMPLITUDE * (2.0 * std::f64::consts::PI * k as f64 / STEPS as f64).sin();
    let (mut cycles, mut reference, mut solve, mut worst) = (0usize, 0.0, 0.0, f64::INFINITY);
    println!("step  cycles  reference_s  solve_s  min_volume_ratio");
    for k in 1..=STEPS {
        let increment = Motion::zero(&mesh).with_rigid(sphere, RigidMotion::translation([at(k) - at(k - 1), 0.0, 0.0]));
        let sol = solver.advance(&increment).expect("a step");
        let rep = solver.step_reports().last().expect("a report").clone();
        cycles += sol.report.cycles;
        reference += rep.reference_seconds;
        solve += rep.solve_seconds;
        worst = worst.min(sol.quality.min_area_ratio);
        println!(
            "{k:4}  {:6}  {:11.3}  {:7.3}  {:.4}",
            sol.report.cycles, rep.reference_seconds, rep.solve_seconds, sol.quality.min_area_ratio
        );
    }
    let n = STEPS as f64;
    println!(
        "mean: {:.2} cycles, reference {:.3} s, solve {:.3} s a step; smallest step's volume ratio {worst:.4}",
        cycles as f64 / n,
        reference / n,
        solve / n
    );
}
