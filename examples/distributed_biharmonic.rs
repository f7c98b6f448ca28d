//! Times the distributed biharmonic on an n³ hexahedral box split into slabs by x (the `mpi`
//! feature): one solve of the boundary motion with one level (the smoother alone) and with the
//! multigrid, then `steps` calls of `advance`, each moving the boundary by a share of the
//! motion (each step builds the hierarchy of its new reference), then `steps` solves from one
//! reference (the first builds it, the others reuse it). Run under MPI, e.g.
//! `mpirun -np 4 --oversubscribe target/release/examples/distributed_biharmonic 16`
//! (further arguments: `tets` splits every cube into six tetrahedra, `tri` makes an n × n
//! square of triangles; `serial` also solves on one process with the serial `Solver` and prints
//! its iterations; `steps=K` runs K advance steps, 10 unless given; `degree=D` sets the
//! smoother's degree; `blocks` partitions into hashed blocks instead of slabs; `mg` skips the
//! one-level solve).

#[path = "../tests/slabs/mod.rs"]
mod slabs;

use meshmove::distributed::{DistSolveParams, DistributedMesh, DistributedSolver};
use meshmove::{BoundaryConditions, Mesh, Method, Motion, Options, Solver};
use mpi::traits::*;
use std::time::Instant;

fn main() {
    let universe = mpi::initialize().expect("MPI initialises once");
    let world = universe.world();
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let args: Vec<String> = std::env::args().collect();
    let has = |w: &str| args.iter().skip(2).any(|a| a == w);
    let arg =
        |key: &str, default: usize| args.iter().find_map(|a| a.strip_prefix(key)?.parse().ok()).unwrap_or(default);
    let (steps, degree) = (arg("steps=", 10), arg("degree=", DistSolveParams::default().degree));
    let (d, shape, owner) = slabs::from_args(&args, size);
    let dim = d.dim;
    let all: Vec<f64> = (0..d.num_vertices()).flat_map(|v| slabs::motion(d.point(v))[..dim].to_vec()).collect();
    if has("serial") && rank == 0 {
        let mut o = Options { method: Method::Biharmonic, threads: 1, ..Default::default() };
        o.solve.tol = 1e-8;
        let serial = Solver::new(&Mesh::from_data(&d).expect("a valid mesh"), &BoundaryConditions::new(), o)
            .expect("a serial solver");
        let t = Instant::now();
        let sol = serial.solve(&Motion::from_displacement(all.clone())).expect("a serial solve");
        println!(
            "serial, {} vertices ({shape}): iterations {}, {:.3} s; levels {:?}",
            d.num_vertices(),
            sol.report.cycles,
            t.elapsed().as_secs_f64(),
            serial.hierarchy().levels.iter().map(|l| l.n()).collect::<Vec<_>>()
        );
    }
    let p = slabs::part(&d, &owner, rank, true);
    let local: Vec<f64> = p.global.iter().flat_map(|&v| all[v * dim..(v + 1) * dim].to_vec()).collect();
    let dm = DistributedMesh::new(&world, &p.data, &p.gids, &p.ghost).expect("a valid partition");
    let bcs = BoundaryConditions::new();
    let one_level: &[usize] = if has("mg") { &[] } else { &[1] };
    for &max_levels in one_level.iter().chain(&[DistSolveParams::default().max_levels]) {
        let params = DistSolveParams { tol: 1e-8, max_levels, degree, ..Default::default() };
        world.barrier();
        let t = Instant::now();
        let solver = DistributedSolver::new(&dm, &bcs, Method::Biharmonic, params).expect("a solver");
        let sol = solver.solve(&Motion::from_displacement(local.clone())).expect("a converged solve");
        world.barrier();
        if rank == 0 {
            println!(
                "{size} ranks, {} vertices ({shape}), {max_levels} levels at most: iterations {:?}, {:.3} s; \
                 levels {:?}, halo values per exchange {:?}, coarsest {}",
                d.num_vertices(),
                sol.iterations,
                t.elapsed().as_secs_f64(),
                sol.level_rows,
                sol.level_halo_values,
                if sol.coarsest_gathered { "gathered" } else { "smoothed" }
            );
        }
    }
    if steps == 0 {
        return;
    }
    let params = DistSolveParams { tol: 1e-8, degree, ..Default::default() };
    let mut solver = DistributedSolver::new(&dm, &bcs, Method::Biharmonic, params).expect("a solver");
    let share: Vec<f64> = local.iter().map(|x| x / steps as f64).collect();
    let mut iterations = Vec::new();
    world.barrier();
    let t = Instant::now();
    for _ in 0..steps {
        let sol = solver.advance(&Motion::from_displacement(share.clone())).expect("a step");
        iterations.push(sol.iterations.iter().max().copied().unwrap_or(0));
    }
    world.barrier();
    if rank == 0 {
        let per_step = t.elapsed().as_secs_f64() / steps as f64;
        println!("{size} ranks, {steps} advance steps: {per_step:.3} s per step, iterations {iterations:?}");
    }
    // The same number of solves from one reference: the first builds the hierarchy, the others
    // reuse it.
    let solver = DistributedSolver::new(&dm, &bcs, Method::Biharmonic, params).expect("a solver");
    let mut seconds = Vec::new();
    for _ in 0..steps {
        world.barrier();
        let t = Instant::now();
        solver.solve(&Motion::from_displacement(share.clone())).expect("a solve");
        world.barrier();
        seconds.push(t.elapsed().as_secs_f64());
    }
    if rank == 0 {
        let later = seconds[1..].iter().sum::<f64>() / (steps - 1).max(1) as f64;
        println!("{size} ranks, {steps} solves from one reference: first {:.3} s, later {later:.3} s each", seconds[0]);
    }
}
