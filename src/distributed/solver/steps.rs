//! Steps of a motion on the distributed solver, taken as the serial solver takes them
//! (`crate::solver::steps`): `move_in_steps` in equal steps, the drop-in `advance` and
//! `advance_from`, automatic sub-stepping, both reference modes, one report per sub-step, the
//! progress callback and cancellation.
//!
//! Every decision of a step (converged, inverted cells, the smallest area ratio against the
//! options' minimum) is made on values that are global, the same on every rank, so every rank
//! splits, accepts and fails at the same sub-step without a message of its own. A call is one
//! transaction: when it fails, the reference (the rank's level) and the motion done so far are
//! put back, and only the step reports say how far it got. Where the serial calls return a
//! result with inverted cells and keep the mesh they had, these return `DistErrorKind::Inverted`
//! on every rank, naming the rank of the worst cell, and keep the mesh they had.

use super::options::{dist_params, serial_options};
use super::{build_level, DistSolution, DistSolveParams, DistributedSolver};
use crate::bc::Placements;
use crate::distributed::agreement::agree;
use crate::distributed::dist_mesh::DistributedMesh;
use crate::distributed::error::{DistError, DistErrorKind};
use crate::distributed::reduce::gather;
use crate::mesh::quality::is_inverted;
use crate::multigrid::level::Level;
use crate::solver::steps::{Halving, Step};
use crate::solver::MAX_STEPS;
use crate::{BoundaryConditions, Cancel, Method, Motion, Options, Progress, ReferenceMode, StepReport};
use std::time::Instant;

/// What one sub-step did, over all ranks.
#[derive(Clone, Debug, PartialEq)]
pub struct DistStepReport {
    /// The sub-step as the serial solver reports it, the same on every rank but for the seconds
    /// (this rank's): `cycles` the most conjugate gradient iterations of a group of components,
    /// `inverted` summed over every rank's owned cells, the smallest ratio and angle over all
    /// ranks; `solve_seconds` holds the quality check too (`quality_seconds` is 0); `rebuilt` is
    /// false and `max_slip_offwall` 0 (the slipped vertices are put on their walls).
    pub report: StepReport,
    /// The rank whose owned cells hold the smallest area (volume) ratio (the lowest such rank).
    pub worst_rank: usize,
}

/// The steps' part of a distributed solver: its serial options, the motion done so far in the
/// original-reference mode, the last call's reports and its cancellation request.
pub(super) struct State {
    opts: Options,
    /// `ReferenceMode::Original`: the motion done so far and the positions it gave, both in
    /// layout order; the level stays on the original mesh.
    total: Option<(Motion, Vec<f64>)>,
    /// The sub-steps of the last `advance`, `advance_from` or `move_in_steps` call.
    reports: Vec<DistStepReport>,
    cancel: Cancel,
}

impl State {
    /// The state of a solver of `method` iterating by `params`, before any step.
    pub(super) fn new(method: Method, params: DistSolveParams) -> State {
        State { opts: serial_options(method, &params), total: None, reports: Vec::new(), cancel: Cancel::default() }
    }

    /// The positions the motion done so far gave (layout order), in the original-reference
    /// mode after a step; None when they are the reference's.
    pub(super) fn current(&self) -> Option<&[f64]> {
        self.total.as_ref().map(|(_, x)| x.as_slice())
    }
}

/// What a failed call puts back.
struct Undo {
    /// The level the call started on, once a step replaced it.
    level: Option<Level>,
    total: Option<(Motion, Vec<f64>)>,
    /// Where the slip walls were when the call began.
    placed: Option<Placements>,
}

impl DistributedSolver {
    /// The solver on `mesh` with the conditions `bcs` and the serial solver's options
    /// (collective): the method, the tolerance, the iteration limit, the Chebyshev degree and
    /// the number of levels, and the steps' sub-stepping, reference mode and progress callback.
    /// What the distributed solver does not take (the paper-faithful mode, the
    /// largest-correction criterion, coarse-level smoother settings, other hierarchy
    /// parameters, a memory budget) is refused with an error on every rank; `threads` has no
    /// effect (each rank works on its calling thread).
    pub fn with_options(
        mesh: &DistributedMesh,
        bcs: &BoundaryConditions,
        opts: Options,
    ) -> Result<DistributedSolver, DistError> {
        let params = agree(mesh.halo().comm(), dist_params(mesh.rank(), &opts))?;
        let mut s = DistributedSolver::new(mesh, bcs, opts.method, params)?;
        s.steps.opts = opts;
        Ok(s)
    }

    /// The options in force (for a solver made with [`DistributedSolver::new`], the serial
    /// options its method and parameters amount to).
    pub fn options(&self) -> &Options {
        &self.steps.opts
    }

    /// Changes the options that need nothing rebuilt (iteration, sub-stepping, reference mode,
    /// progress; collective, every rank giving the same); the method stays. Switching the
    /// reference mode makes the current positions the reference (or the original mesh).
    pub fn set_options(&mut self, opts: Options) -> Result<(), DistError> {
        let me = self.mesh.rank();
        let checked = dist_params(me, &opts).and_then(|p| match opts.method == self.method() {
            true => Ok(p),
            false => Err(DistError::new(
                me,
                DistErrorKind::Input,
                "the method is fixed when the solver is made: make a new solver",
            )),
        });
        let params = agree(self.halo().comm(), checked)?;
        if opts.reference != self.steps.opts.reference {
            if let Some((m, x)) = self.steps.total.take() {
                self.level = self.level_at(x);
                self.multigrids.clear();
                // The slip walls stay where the motion done so far took them.
                self.move_walls(&m);
            }
        }
        self.params = params;
        self.steps.opts = opts;
        Ok(())
    }

    /// Sets the progress callback of the following calls on this rank (not collective): only
    /// rank 0's is called, after every sub-step with its global report; its `false` stops the
    /// call on every rank with `DistErrorKind::Cancelled`.
    pub fn set_progress(&mut self, progress: Option<Progress>) {
        self.steps.opts.progress = progress;
    }

    /// The sub-steps of the last [`DistributedSolver::advance`], `advance_from` or
    /// `move_in_steps` call, also when it failed.
    pub fn step_reports(&self) -> &[DistStepReport] {
        &self.steps.reports
    }

    /// The solver's cancellation request, for another thread of this rank: the running call
    /// (or the next) stops after its current sub-step on every rank with
    /// `DistErrorKind::Cancelled`, leaving the solver as it was.
    pub fn canceller(&self) -> Cancel {
        self.steps.cancel.clone()
    }

    /// Moves the boundary to `motion` (its total for this call, host order) in `steps` equal
    /// steps, the reference re-evaluated after each, with the sub-stepping of the options
    /// (collective). Returns one report per sub-step (also kept in
    /// [`DistributedSolver::step_reports`]); on any error, and when the last step's result
    /// inverts cells (`DistErrorKind::Inverted`), the solver is as before the call.
    pub fn move_in_steps(&mut self, motion: &Motion, steps: usize) -> Result<Vec<DistStepReport>, DistError> {
        let me = self.mesh.rank();
        let counts = gather(self.halo().comm(), &[steps as u64]);
        let input = |msg: String| Err(DistError::new(me, DistErrorKind::Input, msg));
        let checked = if steps == 0 || steps > MAX_STEPS {
            input(format!("step count is {steps}; it must be 1 to {MAX_STEPS}"))
        } else if counts[me] != counts[0] {
            input(format!("step count is {steps}, rank 0's is {}: every rank gives the same", counts[0]))
        } else {
            self.layout_values(motion).map(|_| ())
        };
        agree(self.halo().comm(), checked)?;
        run(self, |s, undo| {
            for i in 0..steps {
                let increment = motion.increment(i, steps);
                let (from, to) = (i as f64 / steps as f64, (i + 1) as f64 / steps as f64);
                let step = Step { number: i + 1, count: steps, increment: &increment, from, to, last: i + 1 == steps };
                do_step(s, &step, undo)?;
            }
            Ok(())
        })?;
        Ok(self.steps.reports.clone())
    }

    /// [`DistributedSolver::advance`] from the positions `coords` (`dim` per local vertex, host
    /// order; an owned vertex's value counts), when the host moved the mesh itself since the last
    /// call: they become the current mesh (the reference, or in `ReferenceMode::Original` the new
    /// original mesh) in the same transaction (collective). Positions with an inverted owned
    /// cell on any rank are `DistErrorKind::Tangled`.
    pub fn advance_from(&mut self, coords: &[f64], increment: &Motion) -> Result<DistSolution, DistError> {
        advance(self, Some(coords), increment)
    }

    /// The rank's level at the positions `x` (layout order; collective).
    fn level_at(&self, x: Vec<f64>) -> Level {
        build_level(self.halo(), self.local().with_coords(x), &self.bcs, &self.base, self.method(), self.ties.as_ref())
    }

    /// Moves the slip walls rigidly with the rigid motions of `motion`.
    fn move_walls(&mut self, motion: &Motion) {
        if let Some(w) = self.walls.as_mut() {
            w.move_walls(&motion.rigid);
        }
    }

    /// The positions after the last step (layout order).
    fn current_layout(&self) -> &[f64] {
        self.steps.current().unwrap_or(self.local().coords())
    }

    /// `motion` with its displacement in layout order.
    pub(super) fn to_layout(&self, motion: &Motion) -> Motion {
        let d = self.mesh.to_layout_order(&motion.displacement, self.mesh.dim());
        Motion { displacement: d, rigid: motion.rigid.clone() }
    }

    /// The host's positions `coords` in layout order with the owners' values on the halo;
    /// checked (size, finite) over every rank.
    fn positions(&self, coords: &[f64]) -> Result<Vec<f64>, DistError> {
        let (me, dim) = (self.mesh.rank(), self.mesh.dim());
        let n = self.mesh.num_local_vertices() * dim;
        let checked = if coords.len() != n {
            Err(format!("{} positions given for {n} values ({} local vertices × {dim})", coords.len(), n / dim))
        } else if let Some(i) = coords.iter().position(|x| !x.is_finite()) {
            Err(format!(
                "the position of local vertex {} (global id {}) is not finite",
                i / dim,
                self.mesh.global_ids()[i / dim]
            ))
        } else {
            Ok(())
        };
        agree(self.halo().comm(), checked.map_err(|m| DistError::new(me, DistErrorKind::Input, m)))?;
        Ok(self.mesh.to_layout_order_exchanged(coords, dim))
    }

    /// True on every rank when `local` is true on any rank.
    fn any_rank(&self, local: bool) -> bool {
        gather(self.halo().comm(), &[i32::from(local)]).iter().any(|&f| f != 0)
    }
}

/// One step of `increment` from the current positions, or first from `from` (host order: the
/// host moved the mesh itself). Returns the displacement from the positions before the call
/// (host order) and its quality against them.
pub(super) fn advance(
    s: &mut DistributedSolver,
    from: Option<&[f64]>,
    increment: &Motion,
) -> Result<DistSolution, DistError> {
    agree(s.halo().comm(), s.layout_values(increment).map(|_| ()))?;
    let from = from.map(|x| s.positions(x)).transpose()?;
    run(s, |s, undo| {
        if let Some(x) = from {
            rebase(s, x, undo)?;
        }
        let before = s.current_layout().to_vec();
        let mut sol = do_step(s, &Step { number: 1, count: 1, increment, from: 0.0, to: 1.0, last: true }, undo)?;
        let after = s.current_layout();
        let d: Vec<f64> = after.iter().zip(&before).map(|(a, b)| a - b).collect();
        let (quality, worst_rank) = s.quality_between(&s.local().with_coords(before), after);
        sol.displacement = s.mesh.to_host_order(&d, s.mesh.dim());
        (sol.quality, sol.worst_rank) = (quality, worst_rank);
        Ok(sol)
    })
}

/// Makes `x` (layout order) the current mesh when it differs from the current positions on any
/// rank: the reference (incremental) or the original mesh with no motion done yet (original).
fn rebase(s: &mut DistributedSolver, x: Vec<f64>, undo: &mut Undo) -> Result<(), DistError> {
    if !s.any_rank(x != s.current_layout()) {
        return Ok(());
    }
    let local = s.local();
    let owned = s.mesh.owned_cells();
    let bad = (0..local.num_cells()).filter(|&c| owned[c] && is_inverted(local, &x, c)).count();
    let counts = gather(s.halo().comm(), &[bad as u64]);
    if let Some(rank) = counts.iter().position(|&n| n > 0) {
        let total: u64 = counts.iter().sum();
        return Err(DistError::new(
            rank,
            DistErrorKind::Tangled,
            format!(
                "the positions given have {total} inverted cell(s) ({} of rank {rank}'s owned cells); nothing is solved on \
                 a tangled mesh",
                counts[rank]
            ),
        ));
    }
    if s.any_rank(x != s.local().coords()) {
        set_level(s, x, undo);
    }
    // The motion done so far is forgotten; the slip walls stay where it took them.
    if let Some((m, _)) = s.steps.total.take() {
        s.move_walls(&m);
    }
    Ok(())
}

/// Makes the positions `x` (layout order) the reference, the level replaced kept in `undo` (the
/// first time).
fn set_level(s: &mut DistributedSolver, x: Vec<f64>, undo: &mut Undo) {
    let level = s.level_at(x);
    let old = std::mem::replace(&mut s.level, level);
    undo.level.get_or_insert(old);
    // The kept multigrids were built on the level replaced.
    s.multigrids.clear();
}

/// Runs `f` as one transaction: reports cleared, the reference and the motion done so far put
/// back when `f` fails.
fn run<T>(
    s: &mut DistributedSolver,
    f: impl FnOnce(&mut DistributedSolver, &mut Undo) -> Result<T, DistError>,
) -> Result<T, DistError> {
    s.steps.reports.clear();
    let placed = s.walls.as_ref().map(|w| w.placements().clone());
    let mut undo = Undo { level: None, total: s.steps.total.clone(), placed };
    let r = f(s, &mut undo);
    if r.is_err() {
        if let Some(level) = undo.level {
            s.level = level;
            s.multigrids.clear();
        }
        s.steps.total = undo.total;
        if let (Some(w), Some(p)) = (s.walls.as_mut(), undo.placed) {
            w.set_placements(p);
        }
    }
    r
}

/// The report of a sub-step that ends at fraction `end` of its step.
fn report(step: &Step, substep: usize, end: f64, sol: &DistSolution, converged: bool, t0: Instant) -> DistStepReport {
    let seconds = t0.elapsed().as_secs_f64();
    let q = &sol.quality;
    DistStepReport {
        report: StepReport {
            step: step.number,
            substep,
            fraction: step.from + (step.to - step.from) * end,
            cycles: sol.iterations.iter().copied().max().unwrap_or(0),
            rel_residual: sol.rel_residual,
            converged,
            rebuilt: false,
            inverted: q.inverted,
            min_volume_ratio: q.min_area_ratio,
            min_angle_deg: q.min_angle_deg,
            max_slip_offwall: 0.0,
            seconds,
            solve_seconds: seconds,
            quality_seconds: 0.0,
            reference_seconds: 0.0,
            accepted: false,
        },
        worst_rank: sol.worst_rank,
    }
}

/// Keeps the report of a sub-step, tells rank 0's progress callback, and agrees whether any
/// rank stops the call (its callback or a cancellation request).
fn record(s: &mut DistributedSolver, step: &Step, rep: DistStepReport) -> Result<(), DistError> {
    let cancelled = s.steps.cancel.take();
    let stopped =
        s.mesh.rank() == 0 && s.steps.opts.progress.as_ref().is_some_and(|p| !p.go_on(&rep.report, step.count));
    let (number, substep, fraction) = (rep.report.step, rep.report.substep, rep.report.fraction);
    s.steps.reports.push(rep);
    let flags = gather(s.halo().comm(), &[i32::from(cancelled || stopped)]);
    match flags.iter().position(|&f| f != 0) {
        None => Ok(()),
        Some(rank) => Err(DistError::new(
            rank,
            DistErrorKind::Cancelled,
            format!(
                "the progress callback or a cancellation request stopped the call after step {number}.{substep} of {} \
                 ({fraction:.4} of the motion); the solver is as before the call",
                step.count
            ),
        )),
    }
}

/// The moved positions (layout order) of the reference moved by `displacement` (host order).
fn moved(s: &DistributedSolver, displacement: &[f64]) -> Vec<f64> {
    // The fetched vertices move with their owners.
    let d = s.mesh.to_layout_order_exchanged(displacement, s.mesh.dim());
    s.local().coords().iter().zip(&d).map(|(x, d)| x + d).collect()
}

/// The error of a solve that stopped above its tolerance at `step`.`substep`.
fn not_converged(step: &Step, substep: usize, why: String) -> DistError {
    DistError::new(0, DistErrorKind::Solve, format!("step {}.{substep}: {why}", step.number))
}

/// The error of a step whose converged result inverts cells: `Inverted` when it is the call's
/// result, `Tangled` when later steps would start from it.
fn inverted(step: &Step, sol: &DistSolution) -> DistError {
    let q = &sol.quality;
    let (kind, then) = match step.last {
        true => (DistErrorKind::Inverted, "nothing was changed"),
        false => (
            DistErrorKind::Tangled,
            "the next step cannot start from a tangled mesh: enable sub-stepping or use more steps; nothing was changed",
        ),
    };
    DistError::new(
        sol.worst_rank,
        kind,
        format!(
            "step {}: the result has {} inverted cell(s) (smallest area or volume ratio {:e}, on rank {}); {then}",
            step.number, q.inverted, q.min_area_ratio, sol.worst_rank
        ),
    )
}

/// `sol` after `acc`: its iterations, and those of its polish, added to those of the sub-steps
/// before.
fn accumulate(acc: Option<DistSolution>, mut sol: DistSolution) -> DistSolution {
    if let Some(a) = acc {
        sol.iterations.iter_mut().zip(&a.iterations).for_each(|(n, m)| *n += m);
        sol.polish_iterations += a.polish_iterations;
    }
    sol
}

/// One step, split into sub-steps as the options say; returns the last sub-step's solution with
/// the iterations of every accepted one.
fn do_step(s: &mut DistributedSolver, step: &Step, undo: &mut Undo) -> Result<DistSolution, DistError> {
    if s.steps.opts.reference == ReferenceMode::Original {
        return original_step(s, step);
    }
    let (max_substeps, min_ratio) = (s.steps.opts.max_substeps, s.steps.opts.min_volume_ratio);
    let split = max_substeps > 1;
    let mut halving = Halving::new(max_substeps);
    let (mut substep, mut acc) = (0usize, None);
    while !halving.finished() {
        substep += 1;
        let end = halving.end();
        let part = step.increment.between(halving.done, end);
        let t0 = Instant::now();
        let (sol, failure) = s.solve_report(&part)?;
        let mut rep = report(step, substep, end, &sol, failure.is_none(), t0);
        let q = &sol.quality;
        let valid = q.inverted == 0 && (!split || q.min_area_ratio >= min_ratio);
        if failure.is_none() && valid {
            let t1 = Instant::now();
            let x = moved(s, &sol.displacement);
            set_level(s, x, undo);
            // The slip walls move rigidly with the reference.
            s.move_walls(&part);
            rep.report.reference_seconds = t1.elapsed().as_secs_f64();
            rep.report.accepted = true;
            record(s, step, rep)?;
            acc = Some(accumulate(acc, sol));
            halving.done = end;
            continue;
        }
        if halving.halve() {
            record(s, step, rep)?;
            continue;
        }
        record(s, step, rep)?;
        if let Some(why) = failure {
            return Err(not_converged(step, substep, why));
        }
        if !split {
            return Err(inverted(step, &sol));
        }
        let why = match q.inverted > 0 {
            true => format!("{} inverted cell(s)", q.inverted),
            false => format!("min area (volume) ratio {:.3e} below the minimum {min_ratio}", q.min_area_ratio),
        };
        return Err(DistError::new(
            sol.worst_rank,
            DistErrorKind::Solve,
            format!(
                "step {}: sub-stepping reached its limit of {max_substeps} sub-steps at {:.4} of the motion: the next \
                 sub-step would give {why}; nothing was changed",
                step.number,
                step.from + (step.to - step.from) * halving.done
            ),
        ));
    }
    Ok(acc.expect("a step accepts at least one sub-step or fails"))
}

/// `ReferenceMode::Original`: the total motion so far solved from the original mesh.
fn original_step(s: &mut DistributedSolver, step: &Step) -> Result<DistSolution, DistError> {
    let increment = s.to_layout(step.increment);
    let total = match &s.steps.total {
        Some((m, _)) => m.then(&increment, s.local()),
        None => increment,
    };
    let host =
        Motion { displacement: s.mesh.to_host_order(&total.displacement, s.mesh.dim()), rigid: total.rigid.clone() };
    let t0 = Instant::now();
    let (sol, failure) = s.solve_report(&host)?;
    let mut rep = report(step, 1, 1.0, &sol, failure.is_none(), t0);
    if let Some(why) = failure {
        record(s, step, rep)?;
        return Err(not_converged(step, 1, why));
    }
    if sol.quality.inverted > 0 {
        record(s, step, rep)?;
        return Err(inverted(step, &sol));
    }
    rep.report.accepted = true;
    s.steps.total = Some((total, moved(s, &sol.displacement)));
    record(s, step, rep)?;
    Ok(sol)
}
