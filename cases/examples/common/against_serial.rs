//! Distributed solves against the serial solver, for the distributed probes (included by
//! path): rank 0 solves the whole mesh serially and sends the displacement and its cycles to
//! every rank, each rank solves its part, and rank 0 prints the iterations, the largest
//! difference relative to the motion and the level sizes (the serial levels' free unknowns per
//! component beside them).

use meshmove::distributed::mpi::topology::SimpleCommunicator;
use meshmove::distributed::mpi::traits::*;
use meshmove::distributed::{DistSolveParams, DistributedMesh, DistributedSolver};
use meshmove::{BoundaryConditions, Mesh, Method, Motion, Options, Solver};

/// What one comparison solves: the whole mesh with its conditions and motion, and the rank's
/// part of it (`part`: the whole mesh's vertex of each local vertex).
struct Compared<'a> {
    name: &'a str,
    mesh: &'a Mesh,
    bcs: &'a BoundaryConditions,
    motion: &'a Motion,
    dm: &'a DistributedMesh,
    part: &'a [usize],
    local: &'a Motion,
}

/// The methods `args` name (`method=biharmonic` or `method=laplacian`; both without one).
pub fn methods(args: &[String]) -> Vec<Method> {
    match args.iter().find_map(|a| a.strip_prefix("method=")) {
        Some("biharmonic") => vec![Method::Biharmonic],
        Some("laplacian") => vec![Method::Laplacian],
        _ => vec![Method::Biharmonic, Method::Laplacian],
    }
}

/// The distributed solve's parameters `args` give besides the tolerance: the most iterations
/// (`max=N`; 2000 without one; a count no larger than the first solve's leaves no iterations
/// for the polish of a tangled result) and the size of the level gathered onto one rank
/// (`gather=N`; the default without one: smaller ones make deeper hierarchies).
pub fn solve_params(args: &[String]) -> DistSolveParams {
    let arg = |key: &str| args.iter().find_map(|a| a.strip_prefix(key)?.parse::<u64>().ok());
    let default = DistSolveParams::default();
    DistSolveParams {
        max_iterations: arg("max=").map_or(2000, |m| m as usize),
        gather_at_most: arg("gather=").unwrap_or(default.gather_at_most),
        ..default
    }
}

/// Solves `name` (`mesh` under `bcs` moved by `motion`) on the ranks' parts of it, each cell on
/// the rank `owner` gives it, by every one of `methods` to every one of `tols` with the other
/// parameters of `params`, each against the serial solver (`against_serial`; collective).
pub fn compare(
    world: &SimpleCommunicator,
    name: &str,
    (mesh, bcs, motion): (&Mesh, &BoundaryConditions, &Motion),
    owner: &[usize],
    methods: &[Method],
    tols: &[f64],
    params: DistSolveParams,
) {
    let d = mesh.to_data();
    let dim = d.dim;
    let p = super::slabs::part(&d, owner, world.rank() as usize, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).expect("the distributed mesh");
    let given = &motion.displacement;
    let local: Vec<f64> = p.global.iter().flat_map(|&v| given[v * dim..(v + 1) * dim].to_vec()).collect();
    let local = Motion { displacement: local, rigid: motion.rigid.clone() };
    let c = Compared { name, mesh, bcs, motion, dm: &dm, part: &p.global, local: &local };
    for &method in methods {
        for &tol in tols {
            against_serial(world, &c, method, DistSolveParams { tol, ..params });
        }
    }
}

/// Solves `c` by `method` to `params.tol` serially (rank 0) and on the ranks (with `params`),
/// and prints on rank 0 the distributed iterations beside the serial cycles, the largest
/// difference from the serial displacement relative to the motion and the level sizes, or the
/// distributed solve's error (collective).
fn against_serial(world: &SimpleCommunicator, c: &Compared, method: Method, params: DistSolveParams) {
    let tol = params.tol;
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let (dim, nv) = (c.mesh.dim(), c.mesh.num_vertices());
    let mut reference = vec![0.0; nv * dim];
    // The serial cycles, of them the polish's, the inverted cells and the smallest ratio.
    let mut cycles = [0.0; 4];
    // The serial levels' free unknowns per component.
    let mut serial_levels = Vec::new();
    if rank == 0 {
        let mut o = Options { method, threads: 1, ..Default::default() };
        o.solve.tol = tol;
        o.solve.max_cycles = 1000;
        let solver = Solver::new(c.mesh, c.bcs, o).expect("serial");
        let s = solver.solve(c.motion).expect("solve");
        serial_levels = solver
            .hierarchy()
            .levels
            .iter()
            .map(|l| {
                l.flags().iter().map(|f| f.iter().filter(|&&f| f & meshmove::bc::P == 0).count()).collect::<Vec<_>>()
            })
            .collect::<Vec<_>>();
        reference = s.displacement;
        let q = &s.quality;
        cycles = [s.report.cycles as f64, s.report.polish_cycles as f64, q.inverted as f64, q.min_area_ratio];
    }
    let root = world.process_at_rank(0);
    root.broadcast_into(&mut reference[..]);
    root.broadcast_into(&mut cycles[..]);
    let scale = reference.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let solver = DistributedSolver::new(c.dm, c.bcs, method, params).expect("solver");
    let what = format!("{} ({nv} vertices) {method:?} to {tol:e} on {size} ranks", c.name);
    let sol = match solver.solve(c.local) {
        Ok(sol) => sol,
        Err(e) => {
            if rank == 0 {
                println!("{what}: {e}");
            }
            return;
        }
    };
    let worst = super::slabs::largest_difference(c.part, &sol.displacement, &reference, dim);
    let mut all = vec![0.0; size];
    world.all_gather_into(&worst, &mut all[..]);
    let worst = all.iter().fold(0.0f64, |m, &x| m.max(x));
    if rank == 0 {
        let q = &sol.quality;
        println!(
            "{what}: iterations {:?} ({} of polish), {} inverted, min ratio {:.4} (serial {} cycles, {} of polish, {} inverted, min \
             ratio {:.4}), apart {:.1e} of the motion, levels {:?} (serial, free per component {:?}), transfers {:?}",
            sol.iterations,
            sol.polish_iterations,
            q.inverted,
            q.min_area_ratio,
            cycles[0],
            cycles[1],
            cycles[2],
            cycles[3],
            worst / scale,
            sol.level_rows,
            serial_levels,
            sol.level_transfers
        );
    }
}
