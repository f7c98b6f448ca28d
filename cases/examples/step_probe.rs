//! A re-referenced time step of the bench's 3D box, in CPU seconds: the box of N³ cells (sides
//! sliding, bottom fixed, top clamped and moved by 0.1 cos 2πx cos 2πy in z, as `meshmove bench
//! --parts steps` moves it) advanced in STEPS equal steps by `Solver::advance`, one thread; per
//! step the CPU seconds of the call, its solve's and re-reference's wall seconds, the iterations
//! and the hierarchy's re-reference phases; then the final mesh's smallest volume ratio and a
//! hash of its positions (bitwise checks of a change):
//! `cargo run --release -p meshmove-cases --example step_probe -- [hex|tet] [N] [laplacian|biharmonic] [STEPS]`
//! (default `hex 31 laplacian 10`: 32 768 vertices; `hex 62` is the bench's 250k box).

use meshmove::{Method, Options, Solver};
use meshmove_cases::boxes::{free_surface_conditions, structured_box, BoxCells};
use meshmove_cases::report::thread_cpu_seconds;
use std::hash::{Hash, Hasher};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let cells = if args.first().map(|s| s.as_str()) == Some("tet") { BoxCells::Tets } else { BoxCells::Hexes };
    let n: usize = args.get(1).map_or(31, |s| s.parse().expect("cells per side"));
    let method = match args.get(2).map(|s| s.as_str()) {
        Some("biharmonic") => Method::Biharmonic,
        _ => Method::Laplacian,
    };
    let steps: usize = args.get(3).map_or(10, |s| s.parse().expect("steps"));
    let mesh = structured_box(n, cells);
    let (bcs, motion) = free_surface_conditions(&mesh);
    let original = mesh.coords().to_vec();
    let opts = Options { method, threads: 1, ..Default::default() };
    let c0 = thread_cpu_seconds();
    let mut solver = Solver::new(&mesh, &bcs, opts).expect("a solver");
    println!("{} vertices, {method:?}: setup {:.3} CPU s", mesh.num_vertices(), thread_cpu_seconds() - c0);
    let (mut outside, mut solves) = (Vec::new(), Vec::new());
    for i in 0..steps {
        let inc = motion.increment(i, steps);
        let c = thread_cpu_seconds();
        let t = std::time::Instant::now();
        let sol = solver.advance(&inc).expect("a step");
        let (cpu, wall) = (thread_cpu_seconds() - c, t.elapsed().as_secs_f64());
        let reps = solver.step_reports();
        let solve: f64 = reps.iter().map(|r| r.seconds).sum();
        let reference: f64 = reps.iter().map(|r| r.reference_seconds).sum();
        let p = solver.phases();
        println!(
            "step {:2}: {} iterations, CPU {cpu:.4} s; wall {wall:.4} s, solve {solve:.4}, outside it {:.4} (re-reference {reference:.4}: assemble {:.4}, galerkin {:.4}, bounds {:.4})",
            i + 1,
            sol.report.cycles,
            wall - solve,
            p.assemble,
            p.galerkin,
            p.bounds
        );
        if i > 0 {
            outside.push(wall - solve);
            solves.push(solve);
        }
    }
    let sum = |v: &[f64]| v.iter().sum::<f64>();
    println!("steps 2..: outside the solve / solve {:.3} (sums of wall s)", sum(&outside) / sum(&solves));
    let q = meshmove::mesh::quality(&mesh.with_coords(original), solver.current_coords());
    let mut h = std::collections::hash_map::DefaultHasher::new();
    solver.current_coords().iter().for_each(|v| v.to_bits().hash(&mut h));
    println!("min volume ratio {:.6}, positions hash {:016x}", q.min_area_ratio, h.finish());
}
