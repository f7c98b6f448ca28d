//! `mpirun -np N meshmove bench --parts ranks --out DIR` (the `mpi` feature): the distributed
//! solver on the hexahedral box of the 3D part (the 250k-vertex size; `--quick`: the 33k one;
//! `--cells-3d` sets its smaller size) and the graded sphere of the graded part (tetrahedra, 240k vertices; `--quick`: 30k), with the
//! Laplacian (conjugate gradients preconditioned by the distributed multigrid's V-cycle) and the
//! biharmonic (by its W-cycle over K V⁻¹ K assembled across ranks; `--ranks-methods` picks), to
//! `--tol`. Rank 0 makes
//! each mesh, splits its cells with METIS and sends each rank its part, as `deform` under mpirun
//! does. Per run: the seconds to split, to make the distributed mesh and solver, and to solve
//! (the multigrid's hierarchies included: one per component), the iterations, the owned
//! vertices per rank, and per level the unknowns, the halo values and the messages of one
//! exchange over all ranks. Then the solve again on the kept hierarchies (the iterations alone),
//! on one rank the serial `Solver` on the whole mesh (its setup and its solve, one thread), and
//! digests of the prolongations and of the displacement (bitwise the same on a rank count when
//! the results are). Rank 0 appends the rows to `DIR/ranks.csv` and prints them.

use super::cases::{self, Case};
use super::{Args, RanksMesh, RanksMethod};
use crate::distributed::{case, partition::partition, parts, wire};
use meshmove::distributed::mpi::collective::SystemOperation;
use meshmove::distributed::mpi::topology::SimpleCommunicator;
use meshmove::distributed::mpi::traits::*;
use meshmove::distributed::{DistSolution, DistSolveParams, DistributedMesh, DistributedSolver};
use meshmove::{Method, Options, Solver};
use meshmove_cases::boxes::BoxCells;
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::io::Write;
use std::time::Instant;

const HEADER: &str = "case,method,ranks,vertices,partition_s,setup_s,solve_s,iterations,owned_min,owned_max,\
level_unknowns,level_halo_values,level_messages,fine_halo_values,fine_messages,coarsest_gathered,level_ranks,\
resolve_s,serial_setup_s,serial_solve_s,serial_cycles,transfer_digest,displacement_digest";

/// The graded sphere's vertices: the 3D graded part's second size, and its first for `--quick`.
const SPHERE: [usize; 2] = [240_000, 30_000];

pub fn run(a: &Args) -> Result<(), String> {
    let universe = meshmove::distributed::mpi::initialize().ok_or("MPI is initialised already")?;
    let world = universe.world();
    let lead = world.rank() == 0;
    let make = |mesh: RanksMesh| match mesh {
        RanksMesh::Box => cases::free_surface_box(if a.quick { a.cells_3d } else { 2 * a.cells_3d }, BoxCells::Hexes),
        RanksMesh::Sphere => cases::graded_sphere(SPHERE[usize::from(a.quick)]),
    };
    let mut csv = String::new();
    for &mesh in &a.ranks_meshes {
        let case = lead.then(|| make(mesh));
        for m in &a.ranks_methods {
            let method = match m {
                RanksMethod::Laplacian => Method::Laplacian,
                RanksMethod::Biharmonic => Method::Biharmonic,
            };
            match run_one(&world, case.as_ref(), method, a.tol) {
                Ok(Some(row)) => {
                    println!("{row}");
                    csv += &row;
                    csv.push('\n');
                }
                Ok(None) => {}
                Err(e) if lead => println!("FAILED: {method:?} on {} ranks: {e}", world.size()),
                Err(_) => {}
            }
        }
    }
    if lead {
        std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
        let path = a.out.join("ranks.csv");
        let new = !path.exists();
        let mut f = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        let head = if new { format!("{HEADER}\n") } else { String::new() };
        write!(f, "{head}{csv}").map_err(|e| format!("{}: {e}", path.display()))?;
        println!("appended to {}", path.display());
    }
    Ok(())
}

/// One case and method on every rank (`case`: on rank 0): its csv row on rank 0. Collective.
fn run_one(
    world: &SimpleCommunicator,
    case: Option<&Case>,
    method: Method,
    tol: f64,
) -> Result<Option<String>, String> {
    let ranks = world.size() as usize;
    let t = Instant::now();
    let split = case.map(|c| -> Result<_, String> {
        let data = c.mesh.to_data();
        let owner = partition(&data, ranks)?;
        let parts = parts::cut(&data, &owner, ranks)?;
        Ok((parts.iter().map(|p| p.gids.clone()).collect::<Vec<_>>(), parts))
    });
    let status = match &split {
        Some(Err(e)) => Err(e.clone()),
        _ => Ok(()),
    };
    wire::broadcast_result(world, status)?;
    let (gids, parts) = match split {
        Some(Ok((g, p))) => (Some(g), Some(p)),
        _ => (None, None),
    };
    let partition_s = t.elapsed().as_secs_f64();
    let patches = case.map(|c| case::patches_of(&c.mesh));
    let bcs = case::broadcast_conditions(world, case.zip(patches.as_deref()).map(|(c, p)| (&c.bcs, p)))?;
    let part = parts::distribute(world, parts);
    let dim = part.data.dim;
    let motion = case::scatter_motion(world, gids.as_deref().zip(case).map(|(g, c)| (g, &c.motion)), dim)?;
    world.barrier();
    let t = Instant::now();
    let dm = DistributedMesh::new(world, &part.data, &part.gids, &part.ghost).map_err(|e| e.to_string())?;
    let params = DistSolveParams { tol, ..Default::default() };
    let solver = DistributedSolver::new(&dm, &bcs, method, params).map_err(|e| e.to_string())?;
    let setup_s = slowest(world, t.elapsed().as_secs_f64());
    world.barrier();
    let t = Instant::now();
    let sol = solver.solve(&motion).map_err(|e| e.to_string())?;
    let solve_s = slowest(world, t.elapsed().as_secs_f64());
    world.barrier();
    let t = Instant::now();
    solver.solve(&motion).map_err(|e| e.to_string())?;
    let resolve_s = slowest(world, t.elapsed().as_secs_f64());
    let serial = match (case, ranks) {
        (Some(c), 1) => Some(serial(c, method, tol)?),
        _ => None,
    };
    let displacement = displacement_digest(world, &dm, &sol.displacement);
    let owned = dm.num_owned_vertices() as f64;
    let fine = sum(world, &[dm.halo_values_sent() as f64, dm.neighbour_ranks().len() as f64]);
    let (fewest, most) = (-slowest(world, -owned), slowest(world, owned));
    let Some(c) = case else { return Ok(None) };
    let list = |v: &[u64]| v.iter().map(u64::to_string).collect::<Vec<_>>().join(";");
    let DistSolution {
        iterations,
        level_rows,
        level_halo_values,
        level_messages,
        level_ranks,
        coarsest_gathered,
        level_transfers,
        ..
    } = sol;
    let transfers = level_transfers.iter().fold(0u64, |d, &t| d.rotate_left(7) ^ t);
    let serial = serial.map_or(",,".to_string(), |(setup, solve, cycles)| format!("{setup:.3},{solve:.3},{cycles}"));
    Ok(Some(format!(
        "{},{method:?},{ranks},{},{partition_s:.3},{setup_s:.3},{solve_s:.3},{},{fewest},{most},{},{},{},{},{},{},{},{resolve_s:.3},{serial},{transfers:016x},{displacement:016x}",
        c.name,
        c.mesh.num_vertices(),
        iterations.iter().map(usize::to_string).collect::<Vec<_>>().join(";"),
        list(&level_rows),
        list(&level_halo_values),
        list(&level_messages),
        fine[0],
        fine[1],
        coarsest_gathered && !level_rows.is_empty(),
        list(&level_ranks)
    )))
}

/// The serial `Solver` of `method` on the whole mesh of `c` to `tol` on one thread: the seconds
/// of its setup and of its solve, and its cycles.
fn serial(c: &Case, method: Method, tol: f64) -> Result<(f64, f64, usize), String> {
    let mut o = Options { method, threads: 1, ..Default::default() };
    o.solve.tol = tol;
    let t = Instant::now();
    let solver = Solver::new(&c.mesh, &c.bcs, o).map_err(|e| e.to_string())?;
    let setup_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let sol = solver.solve(&c.motion).map_err(|e| e.to_string())?;
    Ok((setup_s, t.elapsed().as_secs_f64(), sol.report.cycles))
}

/// A digest of the displacement over all ranks: each owned vertex's global id and values hashed,
/// the hashes added, so that it does not depend on which rank holds a vertex (collective).
fn displacement_digest(world: &SimpleCommunicator, dm: &DistributedMesh, displacement: &[f64]) -> u64 {
    let (me, dim) = (dm.rank(), dm.dim());
    let owners = dm.owner_ranks();
    let mut mine = 0u64;
    for (v, gid) in dm.global_ids().into_iter().enumerate().filter(|&(v, _)| owners[v] == me) {
        let mut h = DefaultHasher::new();
        gid.hash(&mut h);
        displacement[v * dim..(v + 1) * dim].iter().for_each(|x| x.to_bits().hash(&mut h));
        mine = mine.wrapping_add(h.finish());
    }
    let mut all = vec![0u64; dm.num_ranks()];
    world.all_gather_into(&mine, &mut all[..]);
    all.iter().fold(0, |d, &x| d.wrapping_add(x))
}

/// The largest `x` over the ranks (collective).
fn slowest(world: &SimpleCommunicator, x: f64) -> f64 {
    let mut out = 0.0;
    world.all_reduce_into(&x, &mut out, SystemOperation::max());
    out
}

/// The sums of `x` over the ranks (collective).
fn sum(world: &SimpleCommunicator, x: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; x.len()];
    world.all_reduce_into(x, &mut out[..], SystemOperation::sum());
    out
}
