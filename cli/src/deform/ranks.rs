//! `mpirun -np N meshmove deform MESH --config CASE.toml -o OUT` (the `mpi` feature): rank 0
//! reads the mesh and the case as the serial command does (every mesh format, every key), refuses
//! what the distributed solver does not do yet, splits the cells with METIS and sends each rank
//! its part with one layer of ghost cells and global ids; every rank makes the distributed mesh
//! and solver; each step is one `advance` by the step's increment (sent from rank 0, which
//! computes it as the serial command does); rank 0 gathers the moved points in global order and
//! writes the serial command's files and summary. Rank 0 prints the errors; every rank exits
//! with the same status.

use super::{build, finish, output, step_path, Args, Series};
use crate::distributed::case::{self, code, decode};
use crate::distributed::{partition::partition, parts, vertex_values, wire};
use meshmove::distributed::mpi::topology::SimpleCommunicator;
use meshmove::distributed::mpi::traits::*;
use meshmove::distributed::{DistErrorKind, DistSolveParams, DistributedMesh, DistributedSolver};
use meshmove::mesh::quality::quality;
use meshmove::Method;
use meshmove_cases::report::{patch_measures, CaseResult};
use meshmove_cases::setups::CaseSetup;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

/// What every rank needs of the case beside its part and its conditions.
struct Plan {
    method: Method,
    tol: f64,
    steps: usize,
}

const METHODS: [Method; 3] = [Method::Biharmonic, Method::Laplacian, Method::Spring];

impl Plan {
    /// Rank 0's plan on every rank. Collective.
    fn broadcast(world: &SimpleCommunicator, plan: Option<&Plan>) -> Result<Plan, String> {
        let mut m = plan.map(|p| vec![code(&METHODS, &p.method), p.tol, p.steps as f64]).unwrap_or_default();
        wire::broadcast(world, &mut m);
        match m[..] {
            [method, tol, steps] => Ok(Plan { method: decode(&METHODS, method)?, tol, steps: steps as usize }),
            _ => Err("rank 0 sent a short plan".into()),
        }
    }
}

/// What rank 0 holds: the case as read, and each rank's vertices.
struct Lead {
    setup: CaseSetup,
    series: Series,
    foam: Option<output::PolyMeshSource>,
    plan: Plan,
    /// The global ids of each rank's local vertices.
    gids: Vec<Vec<u64>>,
    parts: Vec<parts::Part>,
    /// The patches whose kinds the ranks are sent.
    patches: Vec<i32>,
}

/// Rank 0's work before the ranks meet: the case read, checked for what only the serial solver
/// does, its cells partitioned.
fn lead(args: &Args, ranks: usize) -> Result<Lead, String> {
    if args.report.is_some() {
        return Err("--report (a line per sub-step) is not written under mpirun; run without mpirun for it".into());
    }
    let (setup, opts, series, foam, serial) = build(args)?;
    if !serial.is_empty() {
        return Err(format!(
            "the case asks for {}, which the distributed solver does not do yet: run `meshmove deform` without mpirun",
            serial.join(", ")
        ));
    }
    let data = setup.mesh.to_data();
    let owner = partition(&data, ranks).map_err(|e| format!("partition of {}: {e}", args.mesh.display()))?;
    let parts = parts::cut(&data, &owner, ranks)?;
    let gids = parts.iter().map(|p| p.gids.clone()).collect();
    let plan = Plan { method: opts.method, tol: opts.solve.tol, steps: setup.steps };
    let patches = case::patches_of(&setup.mesh);
    Ok(Lead { setup, series, foam, plan, gids, parts, patches })
}

pub fn run(args: &Args) -> Result<ExitCode, String> {
    let universe = meshmove::distributed::mpi::initialize().ok_or("MPI is initialised already")?;
    let world = universe.world();
    let rank = world.rank();
    let lead = (rank == 0).then(|| lead(args, world.size() as usize));
    let status = match &lead {
        Some(Err(e)) => Err(e.clone()),
        _ => Ok(()),
    };
    let result =
        wire::broadcast_result(&world, status).and_then(|()| run_ranks(&world, args, lead.and_then(Result::ok)));
    // Rank 0's status on every rank: 1 for an error (rank 0 prints it), else the run's.
    let mut status = [match &result {
        Ok(code) => *code,
        Err(_) => 1,
    }];
    world.process_at_rank(0).broadcast_into(&mut status[..]);
    match result {
        Err(e) if rank == 0 => Err(e),
        _ => Ok(ExitCode::from(status[0])),
    }
}

/// Every rank's part of the run (`lead` on rank 0): the exit status on rank 0.
fn run_ranks(world: &SimpleCommunicator, args: &Args, mut lead: Option<Lead>) -> Result<u8, String> {
    let t0 = Instant::now();
    let plan = Plan::broadcast(world, lead.as_ref().map(|l| &l.plan))?;
    let bcs = case::broadcast_conditions(world, lead.as_ref().map(|l| (&l.setup.bcs, &l.patches[..])))?;
    let part = parts::distribute(world, lead.as_mut().map(|l| std::mem::take(&mut l.parts)));
    let dm = DistributedMesh::new(world, &part.data, &part.gids, &part.ghost).map_err(|e| e.to_string())?;
    let params = DistSolveParams { tol: plan.tol, ..Default::default() };
    let mut solver = DistributedSolver::new(&dm, &bcs, plan.method, params).map_err(|e| e.to_string())?;
    let dim = dm.dim();
    let owned: Vec<bool> = dm.owner_ranks().iter().map(|&o| o == dm.rank()).collect();
    let ids = (&part.gids[..], &owned[..]);
    let global = lead.as_ref().map_or(0, |l| l.setup.mesh.num_vertices());
    let (mut iterations, mut failure, mut inverted_result, mut done) = (0, None, None, 0);
    let mut step_file_error = None;
    for i in 0..plan.steps {
        let increment = lead.as_ref().map(|l| l.series.increment(&l.setup.motion, i, plan.steps));
        let motion =
            case::scatter_motion(world, lead.as_ref().zip(increment.as_ref()).map(|(l, m)| (&l.gids[..], m)), dim)?;
        match solver.advance(&motion) {
            Ok(sol) => {
                iterations += sol.iterations.iter().max().copied().unwrap_or(0);
                done = i + 1;
            }
            Err(e) if e.kind == DistErrorKind::Inverted && i + 1 == plan.steps => {
                // The last step's result is written anyway, as the serial command does.
                let sol = solver.solve(&motion).map_err(|e| e.to_string())?;
                iterations += sol.iterations.iter().max().copied().unwrap_or(0);
                let moved: Vec<f64> =
                    solver.current_coords().iter().zip(&sol.displacement).map(|(x, d)| x + d).collect();
                inverted_result = Some(moved);
                done = i + 1;
            }
            Err(e) => {
                failure = Some(format!("step {}: {e}", i + 1));
                break;
            }
        }
        let last = i + 1 == plan.steps;
        if args.every.is_some_and(|k| (i + 1) % k.get() == 0 || last) && inverted_result.is_none() {
            let coords = vertex_values::gather(world, ids, &solver.current_coords(), dim, global);
            if let (Some(l), Some(coords)) = (&lead, coords) {
                let path = step_path(&args.output, i + 1, plan.steps, l.foam.is_some());
                let disp: Vec<f64> = coords.iter().zip(l.setup.mesh.coords()).map(|(a, b)| a - b).collect();
                if let Err(e) = output::write(&path, &l.setup.mesh, &disp, args.encoding.vtu(), l.foam.as_ref()) {
                    step_file_error.get_or_insert(e);
                }
            }
        }
    }
    let last_valid = vertex_values::gather(world, ids, &solver.current_coords(), dim, global);
    let coords = match &inverted_result {
        Some(moved) => vertex_values::gather(world, ids, moved, dim, global),
        None => last_valid.clone(),
    };
    let seconds = t0.elapsed().as_secs_f64();
    drop(solver);
    drop(dm);
    let (Some(l), Some(coords), Some(last_valid)) = (lead, coords, last_valid) else { return Ok(0) };
    if let Some(e) = step_file_error {
        return Err(e);
    }
    let setup = &l.setup;
    let q = quality(&setup.mesh, &coords);
    let r = CaseResult {
        case: setup.name.clone(),
        dim,
        method: plan.method,
        steps: plan.steps,
        inverted: q.inverted,
        negative_volume_cells: q.non_positive_measure,
        min_area_ratio: q.min_area_ratio,
        min_corner_jacobian_ratio: q.min_corner_jacobian_ratio,
        min_angle_deg: q.min_angle_deg,
        patch: patch_measures(&setup.mesh, &coords, setup.moved_patch, None),
        cycles: iterations,
        seconds,
        max_y_upper: None,
        first_inverted_step: inverted_result.as_ref().map(|_| plan.steps),
        failure,
        coords,
        last_valid,
        reports: Vec::new(),
    };
    let how = format!(
        "{:?}, {} step(s) on {} ranks (cells split by METIS), {iterations} CG iterations (the largest component's, \
         summed over the steps), {seconds:.3} s, converged",
        plan.method,
        plan.steps,
        world.size()
    );
    let encoding = args.encoding.vtu();
    let write = |path: &Path, disp: &[f64]| output::write(path, &setup.mesh, disp, encoding, l.foam.as_ref());
    let code = finish(args, setup, &r, (&how, done as f64 / plan.steps as f64), write)?;
    Ok(if code == ExitCode::SUCCESS { 0 } else { exit_code(&r) })
}

/// The status `finish` returned for a result it did not call a success: 4 for a failed step,
/// 3 for inverted cells.
fn exit_code(r: &CaseResult) -> u8 {
    if r.failure.is_some() {
        4
    } else {
        3
    }
}
