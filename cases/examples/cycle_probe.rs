//! The cycle's PCG iterations per level and per cycle shape on the wall-layered meshes:
//! `cargo run --release -p meshmove-cases --example cycle_probe -- spheroid 12 [LEVELS,…] [ONCE_FROM,…] [TOL]`
//! (kinds and sizes as in `galerkin_probe`; LEVELS the levels whose systems are solved, 0 when
//! empty; ONCE_FROM the first levels visited once to compare, the solver's own when empty,
//! `w` for the W-cycle on every level, `l1` for the solver's own with λmax = 1, the l1 bound,
//! instead of each level's estimate). On one hierarchy, per level l and cycle: PCG on level
//! l's system from a fixed pseudo-random right-hand side to TOL (1e-8), preconditioned by the
//! cycle from l, so a level's count says what the levels below it cost, and the same level
//! across sizes where the growth with size comes in.

use meshmove::multigrid::policy::CycleParams;
use meshmove::multigrid::two_level::multilevel_iterations;
use meshmove::{Options, SolveParams, Solver};
use meshmove_cases::viscous::*;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let kind = args.first().map_or("spheroid", |s| s.as_str());
    let size = args.get(1).map_or("8", |s| s.as_str());
    let list = |i: usize| -> Vec<String> {
        args.get(i).map_or(Vec::new(), |s| s.split(',').filter(|x| !x.is_empty()).map(str::to_string).collect())
    };
    let levels: Vec<usize> = list(2).iter().map(|x| x.parse().expect("a level")).collect();
    let levels = if levels.is_empty() { vec![0] } else { levels };
    let tol: f64 = args.get(4).map_or(1e-8, |s| s.parse().expect("a tolerance"));
    let v = by_name(kind, size).expect("a mesh");
    let bcs = boundary_conditions(&v);
    let t = Instant::now();
    let solver = Solver::new(&v.mesh, &bcs, Options::default()).expect("a solver");
    let h = solver.hierarchy();
    let own = CycleParams::resolve(h, &SolveParams::default());
    let comps = h.groups().into_iter().find(|g| g.contains(&1)).expect("a group with y");
    println!("{kind} {size}: {} vertices, setup {:.1} s", v.mesh.num_vertices(), t.elapsed().as_secs_f64());
    print!("{}", solver.describe());
    let shapes: Vec<(String, CycleParams)> = {
        let given = list(3);
        if given.is_empty() {
            vec![(format!("once from {}", own.once_from), own)]
        } else {
            given
                .iter()
                .map(|x| {
                    if x == "l1" {
                        return (
                            format!("once from {}, λmax = 1 (the l1 bound)", own.once_from),
                            CycleParams { l1_bound: true, ..own },
                        );
                    }
                    let once_from = if x == "w" { usize::MAX } else { x.parse().expect("a level, w or l1") };
                    (format!("once from {x}"), CycleParams { once_from, ..own })
                })
                .collect()
        }
    };
    for &l in &levels {
        for (name, cp) in &shapes {
            let t = Instant::now();
            match multilevel_iterations(h, cp, comps.clone(), l, tol, 200) {
                Some((its, rel)) => println!(
                    "level {l} ({} unknowns), {name}: {its} iterations, residual {rel:.2e}, {:.1} s",
                    h.levels[l].n(),
                    t.elapsed().as_secs_f64()
                ),
                None => println!("level {l}: not in the hierarchy"),
            }
        }
    }
}
