//! Times the distributed mesh and the distributed Laplacian (or spring) solve on an n³
//! hexahedral box split into slabs by x (the `mpi` feature). Run under MPI, e.g.
//! `mpirun -np 4 --oversubscribe target/release/examples/distributed_laplacian 24`
//! (further arguments: `tets` splits every cube into six tetrahedra, `tri` makes an n × n square
//! of triangles instead; `blocks` partitions into hashed blocks instead of slabs; `one-level`
//! preconditions by the smoother alone instead of the multigrid; `spring` solves by the spring
//! analogy instead; `serial` also solves the whole mesh on rank 0 with the serial `Solver` and
//! prints its cycles).

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
    let (d, cells, owner) = slabs::from_args(&args, size);
    let p = slabs::part(&d, &owner, rank, true);
    let boundary: Vec<f64> = p.global.iter().flat_map(|&v| slabs::motion(d.point(v))[..d.dim].to_vec()).collect();

    world.barrier();
    let t0 = Instant::now();
    let dm = DistributedMesh::new(&world, &p.data, &p.gids, &p.ghost).expect("a valid partition");
    world.barrier();
    let t_mesh = t0.elapsed().as_secs_f64();
    let max_levels = if has("one-level") { 1 } else { DistSolveParams::default().max_levels };
    let params = DistSolveParams { tol: 1e-8, max_levels, ..Default::default() };
    let method = if has("spring") { Method::Spring } else { Method::Laplacian };
    let t1 = Instant::now();
    let solver = DistributedSolver::new(&dm, &BoundaryConditions::new(), method, params).expect("a solver");
    let sol = solver.solve(&Motion::from_displacement(boundary)).expect("a converged solve");
    world.barrier();
    let t_solve = t1.elapsed().as_secs_f64();

    let mine = [dm.num_owned_vertices() as u64, dm.num_local_vertices() as u64, dm.halo_values_sent() as u64];
    let mut all = vec![0u64; 3 * size];
    world.all_gather_into(&mine[..], &mut all[..]);
    if rank == 0 && has("serial") {
        let all: Vec<f64> = (0..d.num_vertices()).flat_map(|v| slabs::motion(d.point(v))[..d.dim].to_vec()).collect();
        let mut o = Options { method, threads: 1, ..Default::default() };
        o.solve.tol = params.tol;
        let mesh = Mesh::from_data(&d).expect("a valid mesh");
        let serial = Solver::new(&mesh, &BoundaryConditions::new(), o).expect("a serial solver");
        let s = serial.solve(&Motion::from_displacement(all)).expect("a converged serial solve");
        println!("serial {method:?}: {} cycles to {:e}", s.report.cycles, params.tol);
    }
    if rank == 0 {
        let col = |k: usize| all.chunks_exact(3).map(move |r| r[k]);
        println!(
            "{size} ranks, {} vertices ({}): owned per rank {}..{}, local up to {}, halo values sent per \
             exchange up to {}; mesh {t_mesh:.3} s, solve {t_solve:.3} s to 1e-8, iterations {:?}",
            dm.num_global_vertices(),
            cells,
            col(0).min().unwrap_or(0),
            col(0).max().unwrap_or(0),
            col(1).max().unwrap_or(0),
            col(2).max().unwrap_or(0),
            sol.iterations
        );
        println!(
            "  levels (unknowns over all ranks) {:?}, halo values per exchange {:?}, coarsest {}",
            sol.level_rows,
            sol.level_halo_values,
            if sol.coarsest_gathered { "gathered onto one rank" } else { "smoothed" }
        );
    }
}
