//! `mpirun -np N meshmove deform MESH --config CASE.toml -o OUT` (the `mpi` feature): rank 0
//! reads the mesh and the case as the serial command does (every mesh format, every key), splits
//! the cells with METIS and sends each rank its part with one layer of ghost cells (and the
//! tagged faces of its cells: the SLIP walls and linked sides with them) and global ids, the
//! case's options, conditions (kinds, analytic walls, links, interfaces) and each step's
//! increment (computed as the serial command does). Every rank makes the distributed mesh and
//! the solver with the case's options and takes each step as the serial command does: one
//! `advance` per step, sub-steps and the reference mode as the options say. What the library
//! refuses fails on every rank with its message. Rank 0 prints the sub-steps' report lines (and
//! writes `--report` with the rank of each sub-step's worst cell), gathers the moved points in
//! global order and writes the serial command's files and summary (or, for a `.pvtu` output,
//! every rank its piece: `pieces`). Every rank exits with the same status.

use super::carried::{self, Carried};
use super::pieces;
use super::{build, finish, json_line, on_ctrl_c, output, print_line, progress, step_bar, step_path, write_report};
use super::{Args, Series, INTERRUPTED};
use crate::distributed::case::{self, code, decode};
use crate::distributed::{partition::partition, parts, vertex_values, wire};
use meshmove::distributed::mpi::topology::SimpleCommunicator;
use meshmove::distributed::mpi::traits::*;
use meshmove::distributed::{DistErrorKind, DistSolveParams, DistStepReport, DistributedMesh, DistributedSolver};
use meshmove::mesh::quality::quality;
use meshmove::solver::{ReferenceMode, StepReport};
use meshmove::{Method, Motion, Options};
use meshmove_cases::report::{patch_measures, CaseResult};
use meshmove_cases::setups::CaseSetup;
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::time::Instant;

/// What every rank needs of the case beside its part and its conditions: the solver's options
/// and the number of steps.
struct Plan {
    opts: Options,
    steps: usize,
}

const METHODS: [Method; 3] = [Method::Biharmonic, Method::Laplacian, Method::Spring];
const REFERENCES: [ReferenceMode; 2] = [ReferenceMode::Incremental, ReferenceMode::Original];

impl Plan {
    /// Rank 0's plan on every rank: the options the case file gives (method, tolerance,
    /// sub-stepping, reference mode), the rest the defaults. Collective.
    fn broadcast(world: &SimpleCommunicator, plan: Option<&Plan>) -> Result<Plan, String> {
        let mut m = plan
            .map(|p| {
                let o = &p.opts;
                let reference = code(&REFERENCES, &o.reference);
                vec![
                    code(&METHODS, &o.method),
                    o.solve.tol,
                    p.steps as f64,
                    o.max_substeps as f64,
                    o.min_volume_ratio,
                    reference,
                ]
            })
            .unwrap_or_default();
        wire::broadcast(world, &mut m);
        let [method, tol, steps, max_substeps, min_volume_ratio, reference] = m[..] else {
            return Err("rank 0 sent a short plan".into());
        };
        let mut opts = Options {
            method: decode(&METHODS, method)?,
            max_substeps: max_substeps as usize,
            min_volume_ratio,
            reference: decode(&REFERENCES, reference)?,
            ..Default::default()
        };
        opts.solve.tol = tol;
        // The distributed multigrid is weaker than the serial one (and links make the biharmonic
        // precondition by the smoother alone): the distributed solver's own iteration limit.
        opts.solve.max_cycles = DistSolveParams::default().max_iterations;
        Ok(Plan { opts, steps: steps as usize })
    }
}

/// What rank 0 holds: the case as read, and each rank's vertices.
struct Lead {
    setup: CaseSetup,
    series: Series,
    foam: Option<output::PolyMeshSource>,
    plan: Plan,
    carried: Carried,
    /// The global ids of each rank's local vertices.
    gids: Vec<Vec<u64>>,
    parts: Vec<parts::Part>,
    /// The patches whose kinds the ranks are sent.
    patches: Vec<i32>,
}

/// Rank 0's work before the ranks meet: the case read, its cells partitioned.
fn lead(args: &Args, ranks: usize) -> Result<Lead, String> {
    let (setup, opts, series, foam, carried) = build(args)?;
    let data = setup.mesh.to_data();
    let owner = partition(&data, ranks).map_err(|e| format!("partition of {}: {e}", args.mesh.display()))?;
    let parts = parts::cut(&data, &owner, ranks)?;
    let gids = parts.iter().map(|p| p.gids.clone()).collect();
    let plan = Plan { opts, steps: setup.steps };
    let patches = case::patches_of(&setup.mesh);
    Ok(Lead { setup, series, foam, plan, carried, gids, parts, patches })
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
    // Rank 0's status on every rank: 1 for an error, else the run's. Rank 0 prints its error
    // before the broadcast: the other ranks exit only after it, so mpirun, which stops the job
    // when the first rank exits with an error, cannot stop rank 0 before its message is out.
    let mut status = [match &result {
        Ok(code) => *code,
        Err(e) => {
            if rank == 0 {
                eprintln!("meshmove: error: {e}");
            }
            1
        }
    }];
    world.process_at_rank(0).broadcast_into(&mut status[..]);
    Ok(ExitCode::from(status[0]))
}

/// How the steps went, on every rank (the reports on rank 0).
#[derive(Default)]
struct Run {
    /// Conjugate gradient iterations of the accepted sub-steps (and of an inverted result).
    iterations: usize,
    failure: Option<String>,
    /// The result of a last step that inverts cells (not adopted by the solver), local vertices
    /// in host order.
    inverted: Option<Vec<f64>>,
    /// Every sub-step, numbered as the serial command numbers them.
    reports: Vec<DistStepReport>,
}

/// Every rank's part of the run (`lead` on rank 0): the exit status on rank 0.
fn run_ranks(world: &SimpleCommunicator, args: &Args, mut lead: Option<Lead>) -> Result<u8, String> {
    let t0 = Instant::now();
    let mut plan = Plan::broadcast(world, lead.as_ref().map(|l| &l.plan))?;
    let mut bcs = case::broadcast_conditions(world, lead.as_ref().map(|l| (&l.setup.bcs, &l.patches[..])))?;
    carried::broadcast(world, lead.as_ref().map(|l| &l.carried))?.apply(&mut bcs);
    let part = parts::distribute(world, lead.as_mut().map(|l| std::mem::take(&mut l.parts)));
    let dm = DistributedMesh::new(world, &part.data, &part.gids, &part.ghost).map_err(|e| e.to_string())?;
    // Ctrl-C on any rank: rank 0's progress callback stops the call on every rank.
    on_ctrl_c(&mut plan.opts);
    let mut solver = DistributedSolver::with_options(&dm, &bcs, plan.opts.clone()).map_err(|e| e.to_string())?;
    let dim = dm.dim();
    let owned: Vec<bool> = dm.owner_ranks().iter().map(|&o| o == dm.rank()).collect();
    let ids = (&part.gids[..], &owned[..]);
    let global = lead.as_ref().map_or(0, |l| l.setup.mesh.num_vertices());
    let original = plan.opts.reference == ReferenceMode::Original;
    let steps = plan.steps;
    let bar = step_bar(if lead.is_some() { steps } else { 0 });
    let mut run = Run::default();
    // The total motion so far on rank 0 in the original-reference mode.
    let mut total: Option<Motion> = None;
    let mut step_file_error = None;
    for i in 0..steps {
        let increment = lead.as_ref().map(|l| l.series.increment(&l.setup.motion, i, steps));
        let motion =
            case::scatter_motion(world, lead.as_ref().zip(increment.as_ref()).map(|(l, m)| (&l.gids[..], m)), dim)?;
        if let (true, Some(l), Some(inc)) = (original, &lead, &increment) {
            total = Some(match &total {
                Some(t) => t.then(inc, &l.setup.mesh),
                None => inc.clone(),
            });
        }
        let result = solver.advance(&motion);
        let reports: Vec<DistStepReport> = solver.step_reports().iter().map(|r| numbered(r, i, steps)).collect();
        if lead.is_some() {
            reports.iter().for_each(|r| print_line(&bar, r.report.line()));
        }
        let accepted: usize = reports.iter().filter(|r| r.report.accepted).map(|r| r.report.cycles).sum();
        run.iterations += accepted;
        let last = reports.last().map(|r| (r.report.cycles, r.report.inverted)).unwrap_or_default();
        run.reports.extend(reports);
        match result {
            Ok(_) => {}
            Err(e) if e.kind == DistErrorKind::Inverted && i + 1 == steps => {
                // The last step's result is written anyway, as the serial command does.
                run.iterations += last.0;
                let whole = total.as_ref().or(increment.as_ref());
                let m = case::scatter_motion(world, lead.as_ref().zip(whole).map(|(l, m)| (&l.gids[..], m)), dim)?;
                let sol = solver.solve(&m).map_err(|e| e.to_string())?;
                // In the original-reference mode the solve is from the original mesh.
                let from = if original { part.data.coords.clone() } else { solver.current_coords() };
                run.inverted = Some(from.iter().zip(&sol.displacement).map(|(x, d)| x + d).collect());
            }
            Err(e) if e.kind == DistErrorKind::Inverted => {
                run.failure = Some(format!(
                    "step {}: {} inverted cells; the later steps cannot start from a tangled mesh",
                    i + 1,
                    last.1
                ));
            }
            Err(e) => {
                run.failure = Some(format!("step {}: {e}", i + 1));
                replay_accepted(&mut solver, &motion, &plan.opts)?;
            }
        }
        if args.every.is_some_and(|k| (i + 1) % k.get() == 0 || i + 1 == steps) {
            let coords = vertex_values::gather(world, ids, &solver.current_coords(), dim, global);
            if let (Some(l), Some(coords)) = (&lead, coords) {
                let path = step_path(&args.output, i + 1, steps, l.foam.is_some());
                let disp: Vec<f64> = coords.iter().zip(l.setup.mesh.coords()).map(|(a, b)| a - b).collect();
                if let Err(e) = output::write(&path, &l.setup.mesh, &disp, args.encoding.vtu(), l.foam.as_ref()) {
                    step_file_error.get_or_insert(e);
                }
            }
        }
        bar.inc(1);
        if run.failure.is_some() {
            break;
        }
    }
    bar.finish_and_clear();
    let current = solver.current_coords();
    let last_valid = vertex_values::gather(world, ids, &current, dim, global);
    let coords = match &run.inverted {
        Some(moved) => vertex_values::gather(world, ids, moved, dim, global),
        None => last_valid.clone(),
    };
    // A `.pvtu`: every rank's piece of the result (a failed run writes the last valid mesh only).
    let patch = match pieces::is_pvtu(&args.output) && run.failure.is_none() {
        true => Some(write_pieces(world, args, &part, run.inverted.as_deref().unwrap_or(&current))?),
        false => None,
    };
    let seconds = t0.elapsed().as_secs_f64();
    drop(solver);
    drop(dm);
    let (Some(l), Some(coords), Some(last_valid)) = (lead, coords, last_valid) else { return Ok(0) };
    if let Some(e) = step_file_error {
        return Err(e);
    }
    if let Some(path) = &args.report {
        write_report(path, run.reports.iter().map(|r| json_line(&r.report, Some(r.worst_rank))))?;
    }
    let setup = &l.setup;
    let q = quality(&setup.mesh, &coords);
    let reports: Vec<StepReport> = run.reports.iter().map(|r| r.report.clone()).collect();
    let (done, substeps) = progress(&reports);
    let r = CaseResult {
        case: setup.name.clone(),
        dim,
        method: plan.opts.method,
        steps,
        inverted: q.inverted,
        negative_volume_cells: q.non_positive_measure,
        min_area_ratio: q.min_area_ratio,
        min_corner_jacobian_ratio: q.min_corner_jacobian_ratio,
        min_angle_deg: q.min_angle_deg,
        patch: patch_measures(&setup.mesh, &coords, setup.moved_patch, None),
        cycles: run.iterations,
        seconds,
        max_y_upper: None,
        first_inverted_step: run.inverted.as_ref().map(|_| steps),
        failure: run.failure,
        coords,
        last_valid,
        reports,
    };
    let how = format!(
        "{:?}, {steps} step(s) in {substeps} sub-step(s) on {} ranks (cells split by METIS), {} CG iterations (the \
         largest group's per sub-step, summed), {seconds:.3} s, converged",
        plan.opts.method,
        world.size(),
        run.iterations
    );
    let encoding = args.encoding.vtu();
    let write = |path: &Path, disp: &[f64]| match patch {
        Some(patch) if path == args.output => pieces::write_index(path, world.size() as usize, dim, patch),
        _ => output::write(path, &setup.mesh, disp, encoding, l.foam.as_ref()),
    };
    let code = finish(args, setup, &r, (&how, done), write)?;
    Ok(if code == ExitCode::SUCCESS { 0 } else { exit_code(&r) })
}

/// Every rank writes its piece of the `.pvtu` output, its part moved to `coords` (collective).
/// Rank 0 learns of every rank's error: the first is its result; else whether every piece has
/// tagged faces (the index then names their array).
fn write_pieces(world: &SimpleCommunicator, args: &Args, part: &parts::Part, coords: &[f64]) -> Result<bool, String> {
    let mine = pieces::write_piece(&args.output, world.rank() as usize, part, coords, args.encoding.vtu());
    let message = |r: &Result<bool, String>| match r {
        Ok(faces) => vec![u8::from(*faces)],
        Err(e) => [2].into_iter().chain(e.bytes()).collect(),
    };
    if world.rank() != 0 {
        wire::send(world, 0, &message(&mine));
        return Ok(false);
    }
    let words: Vec<Vec<u8>> = (1..world.size() as usize).map(|r| wire::receive_from(world, r)).collect();
    let mut faces = mine?;
    for w in &words {
        match w.split_first() {
            Some((0, _)) => faces = false,
            Some((1, _)) => {}
            Some((_, e)) => return Err(String::from_utf8_lossy(e).into_owned()),
            None => return Err("a rank sent no word of its piece".into()),
        }
    }
    Ok(faces)
}

/// A sub-step's report of the `advance` of step `i` (0-based) of `steps`, numbered as the serial
/// command numbers it: step i + 1, its fraction of the whole run's motion.
fn numbered(r: &DistStepReport, i: usize, steps: usize) -> DistStepReport {
    let report =
        StepReport { step: i + 1, fraction: (i as f64 + r.report.fraction) / steps as f64, ..r.report.clone() };
    DistStepReport { report, worst_rank: r.worst_rank }
}

/// After a failed `advance` of `increment` (the solver put back as before it), takes again the
/// sub-steps it accepted, each as one `advance` without sub-stepping, so that the solver stands
/// where the failed call got to: the last valid mesh the serial command writes. Each is solved
/// from the same reference as in the failed call, so the positions are the same. Collective.
fn replay_accepted(solver: &mut DistributedSolver, increment: &Motion, opts: &Options) -> Result<(), String> {
    let ends: Vec<f64> =
        solver.step_reports().iter().filter(|r| r.report.accepted).map(|r| r.report.fraction).collect();
    if ends.is_empty() || opts.reference == ReferenceMode::Original {
        return Ok(());
    }
    let mut one = opts.clone();
    one.max_substeps = 0;
    one.progress = None;
    solver.set_options(one).map_err(|e| e.to_string())?;
    let mut done = 0.0;
    for end in ends {
        solver.advance(&increment.between(done, end)).map_err(|e| e.to_string())?;
        done = end;
    }
    solver.set_options(opts.clone()).map_err(|e| e.to_string())
}

/// The status `finish` returned for a result it did not call a success: 5 for a run Ctrl-C
/// stopped, 4 for a failed step, 3 for inverted cells.
fn exit_code(r: &CaseResult) -> u8 {
    match (&r.failure, INTERRUPTED.load(Ordering::SeqCst)) {
        (Some(_), true) => 5,
        (Some(_), false) => 4,
        _ => 3,
    }
}
