//! Where a 3D box's setup (`Solver::new`) spends its time, and a hash of its first solve's
//! displacement (bitwise checks of a setup change):
//! `cargo run --release -p meshmove-cases --example setup_probe -- [hex|tet] [N] [biharmonic|laplacian] [REPEATS]`
//! (the bench's free-surface box of N³ cells, default 31: 32 768 vertices; one thread). Prints
//! each setup's wall seconds and the process's CPU seconds (Linux, to 1/100 s: a loaded machine
//! stretches them less than the wall time).

use meshmove::{Method, Options, Solver};
use meshmove_cases::boxes::{free_surface_conditions, structured_box, BoxCells};
use std::hash::{Hash, Hasher};
use std::time::Instant;

/// The CPU seconds the process has used, its exited threads' too (Linux: user and system time
/// in /proc/self/stat, in ticks of 1/100 s; 0 where it does not tell).
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let after_name = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
    let fields: Vec<&str> = after_name.split_whitespace().collect();
    let ticks = |k: usize| fields.get(k).and_then(|v| v.parse::<u64>().ok()).unwrap_or(0);
    (ticks(11) + ticks(12)) as f64 / 100.0
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let cells = if args.first().map(|s| s.as_str()) == Some("tet") { BoxCells::Tets } else { BoxCells::Hexes };
    let n: usize = args.get(1).map_or(31, |s| s.parse().expect("cells per side"));
    let method =
        if args.get(2).map(|s| s.as_str()) == Some("laplacian") { Method::Laplacian } else { Method::Biharmonic };
    let repeats: usize = args.get(3).map_or(3, |s| s.parse().expect("repeats"));
    let mesh = structured_box(n, cells);
    // The bench's box: bottom fixed, top clamped and moved in z, each side fixed along its normal.
    let (bcs, motion) = free_surface_conditions(&mesh);
    let opts = Options { method, threads: 1, ..Default::default() };
    let mut setups = Vec::new();
    let mut cpu = Vec::new();
    let mut solver = None;
    for _ in 0..repeats {
        let (t, c) = (Instant::now(), cpu_seconds());
        let s = Solver::new(&mesh, &bcs, opts.clone()).expect("a solver");
        setups.push(t.elapsed().as_secs_f64());
        cpu.push(cpu_seconds() - c);
        let named: Vec<String> = s.phases().named().iter().map(|(k, v)| format!("{k} {v:.3}")).collect();
        println!("setup {:.3} s (CPU {:.3} s): {}", setups.last().unwrap(), cpu.last().unwrap(), named.join(", "));
        solver = Some(s);
    }
    let solver = solver.expect("one repeat");
    let (t, c) = (Instant::now(), cpu_seconds());
    let sol = solver.solve(&motion).expect("a solve");
    let solve_s = t.elapsed().as_secs_f64();
    let solve_cpu = cpu_seconds() - c;
    let mut h = std::collections::hash_map::DefaultHasher::new();
    sol.displacement.iter().for_each(|d| d.to_bits().hash(&mut h));
    setups.sort_by(f64::total_cmp);
    cpu.sort_by(f64::total_cmp);
    let (setup, setup_cpu) = (setups[setups.len() / 2], cpu[cpu.len() / 2]);
    println!(
        "{:?} {} vertices, {} levels: setup median {:.3} s (CPU {:.3} s), solve {:.3} s (CPU {:.3} s; {} iterations, residual {:.3e}), setup / solve {:.2} (CPU {:.2}), hash {:016x}",
        method,
        mesh.num_vertices(),
        solver.num_levels(),
        setup,
        setup_cpu,
        solve_s,
        solve_cpu,
        sol.report.cycles,
        sol.report.rel_residual,
        setup / solve_s,
        setup_cpu / solve_cpu,
        h.finish()
    );
}
