//! Steps of a motion: the reference re-evaluated after each, automatic sub-stepping, a rebuilt
//! hierarchy when a reused one stalls, and one report per sub-step.
//!
//! A step is tried whole; when its result would not converge, invert a cell or fall below the
//! minimum area ratio, and sub-stepping is enabled, the rest of the step is tried in halves
//! (each from the last valid mesh), down to 1/`max_substeps` of the step. A rigid motion is
//! split by its angle and translation (`Motion::between`), so the last sub-step ends exactly
//! where the step does. A call that fails puts the solver back where it was; how far it got is
//! in the reports and in `last_valid_coords`.

use super::{check_converged, warm_start, ReferenceMode, Solution, Solver, Undo};
use crate::mesh::quality::Quality;
use crate::motion::Motion;
use crate::multigrid::solve::Report;
use crate::{Error, Result};
use std::time::Instant;

/// What one sub-step did.
#[derive(Clone, Debug, PartialEq)]
pub struct StepReport {
    /// Step, 1-based.
    pub step: usize,
    /// Attempt within the step, 1-based (a rejected attempt is followed by a shorter one).
    pub substep: usize,
    /// Fraction of the whole motion done when this attempt is accepted.
    pub fraction: f64,
    /// CG iterations (or W-cycles) of the larger component.
    pub cycles: usize,
    /// Final relative residual of the larger component.
    pub rel_residual: f64,
    /// True when the solve reached its tolerance.
    pub converged: bool,
    /// The hierarchy was rebuilt from this sub-step's reference (a reused one stalled).
    pub rebuilt: bool,
    /// Cells of non-positive area in the result.
    pub inverted: usize,
    /// Smallest deformed/reference cell area ratio.
    pub min_volume_ratio: f64,
    /// Smallest angle of any cell, degrees.
    pub min_angle_deg: f64,
    /// Slip walls: the largest distance of a slipped vertex from its wall in the result.
    pub max_slip_offwall: f64,
    /// Wall-clock time of this attempt's solve (a hierarchy rebuild included), in seconds:
    /// `solve_seconds` + `quality_seconds`.
    pub seconds: f64,
    /// Of `seconds`, the solve (with a hierarchy rebuild when a reused one stalled).
    pub solve_seconds: f64,
    /// Of `seconds`, the quality check of the result (inverted cells, volume ratios, angles).
    pub quality_seconds: f64,
    /// Seconds making the solver's hierarchy follow the mesh this attempt starts from, outside
    /// `seconds`: re-evaluating it at the previous step's (or sub-step's) result, or at the
    /// positions `set_reference` or `advance_from` gave. A step's result becomes the reference
    /// at once, but the hierarchy follows only when the next solve needs it, so the last step
    /// of a run pays none.
    pub reference_seconds: f64,
    /// The result became the new mesh (false: rejected and split, or the call failed here).
    pub accepted: bool,
}

impl StepReport {
    /// The one-line summary the command line prints per sub-step.
    pub fn line(&self) -> String {
        format!(
            "step {}.{} at {:.4}: {} cycles, residual {:.2e}{}{}, inverted {}, min volume (2D: area) ratio {:.4}, min angle {:.2}°, {:.3} s (solve {:.3}, quality {:.3}; re-reference {:.3} s){}",
            self.step,
            self.substep,
            self.fraction,
            self.cycles,
            self.rel_residual,
            if self.converged { "" } else { " (NOT converged)" },
            if self.rebuilt { ", hierarchy rebuilt" } else { "" },
            self.inverted,
            self.min_volume_ratio,
            self.min_angle_deg,
            self.seconds,
            self.solve_seconds,
            self.quality_seconds,
            self.reference_seconds,
            if self.accepted { "" } else { ", rejected" }
        )
    }
}

/// One step of a motion: its increment and the fractions of the whole motion it spans (also the
/// distributed solver's).
pub(crate) struct Step<'a> {
    pub(crate) number: usize,
    /// The call's number of steps.
    pub(crate) count: usize,
    pub(crate) increment: &'a Motion,
    pub(crate) from: f64,
    pub(crate) to: f64,
    pub(crate) last: bool,
}

/// One step of `increment` from the current positions, or first from `from` (the caller moved
/// the mesh itself: those positions become the current mesh in the same transaction). A result
/// with inverted cells is returned but not adopted: the solver stays as before the call.
pub(super) fn advance(s: &mut Solver, from: Option<&[f64]>, increment: &Motion) -> Result<Solution> {
    let t0 = Instant::now();
    run(
        s,
        |s, undo| {
            if let Some(x) = from {
                let t = Instant::now();
                rebase(s, x)?;
                s.rebase_seconds = t.elapsed().as_secs_f64();
            }
            let before = s.current_coords().to_vec();
            let whole = do_step(s, &Step { number: 1, count: 1, increment, from: 0.0, to: 1.0, last: true }, undo)?;
            let after = &s.last_valid;
            let displacement: Vec<f64> = after.iter().zip(&before).map(|(a, b)| a - b).collect();
            // A step made by one attempt has already measured the result against `before`.
            let quality = whole.unwrap_or_else(|| crate::mesh::quality::quality(&s.mesh().with_coords(before), after));
            // Every output finite, or the call fails (and the transaction restores the solver).
            let q = [quality.min_area_ratio, quality.max_area_ratio, quality.min_angle_deg];
            if after.iter().chain(&displacement).any(|p| !p.is_finite()) || q.iter().any(|v| !v.is_finite()) {
                return Err(Error::Diverged(
                    "the moved positions, their displacement or quality are not finite".into(),
                ));
            }
            Ok(Solution { displacement, report: summary(&s.steps, t0), quality })
        },
        |sol| sol.quality.inverted == 0,
    )
}

/// `steps` equal steps of `motion`. When the last step's result has inverted cells it is
/// reported (the last step report) and not adopted: the solver stays as before the call.
pub(super) fn move_in_steps(s: &mut Solver, motion: &Motion, steps: usize) -> Result<()> {
    run(
        s,
        |s, undo| {
            for i in 0..steps {
                let increment = motion.increment(i, steps);
                let (from, to) = (i as f64 / steps as f64, (i + 1) as f64 / steps as f64);
                let step = Step { number: i + 1, count: steps, increment: &increment, from, to, last: i + 1 == steps };
                do_step(s, &step, undo)?;
            }
            Ok(s.steps.last().map_or(0, |r| r.inverted))
        },
        |&inverted| inverted == 0,
    )
    .map(|_| ())
}

/// Makes `x` the current mesh: the reference (incremental) or the original mesh with no motion
/// done yet (original).
fn rebase(s: &mut Solver, x: &[f64]) -> Result<()> {
    s.check_reference(x)?;
    if x != s.mesh().coords() {
        s.set_reference_inner(x.to_vec());
        s.increments.clear();
    }
    s.drop_total();
    Ok(())
}

/// Runs `f` as one transaction: reports cleared, the solver restored when `f` fails or its
/// result is not to be `kept`.
fn run<T>(
    s: &mut Solver,
    f: impl FnOnce(&mut Solver, &mut Undo) -> Result<T>,
    keep: impl FnOnce(&T) -> bool,
) -> Result<T> {
    s.steps.clear();
    s.rebase_seconds = 0.0;
    s.last_valid = s.current_coords().to_vec();
    let mut undo = s.undo();
    let total = s.total.clone();
    let increments = s.increments.clone();
    let placed = s.walls.as_ref().map(|w| w.placements().clone());
    let r = f(s, &mut undo);
    if !r.as_ref().is_ok_and(keep) {
        s.restore(undo);
        s.total = total;
        s.increments = increments;
        if let (Some(w), Some(p)) = (s.walls.as_mut(), placed) {
            w.set_placements(p);
        }
    }
    r
}

fn report(
    step: &Step,
    substep: usize,
    end: f64,
    sol: &Solution,
    rebuilt: bool,
    t0: Instant,
    quality_s: f64,
) -> StepReport {
    let q: &Quality = &sol.quality;
    let seconds = t0.elapsed().as_secs_f64();
    StepReport {
        step: step.number,
        substep,
        fraction: step.from + (step.to - step.from) * end,
        cycles: sol.report.cycles,
        rel_residual: sol.report.rel_residual,
        converged: sol.report.converged,
        rebuilt,
        inverted: q.inverted,
        min_volume_ratio: q.min_area_ratio,
        min_angle_deg: q.min_angle_deg,
        max_slip_offwall: sol.report.max_slip_offwall,
        seconds,
        solve_seconds: (seconds - quality_s).max(0.0),
        quality_seconds: quality_s,
        reference_seconds: 0.0,
        accepted: false,
    }
}

/// Keeps the report of a sub-step and tells the caller's progress hook, which may cancel the call.
fn record(s: &mut Solver, step: &Step, mut rep: StepReport) -> Result<()> {
    // The caller decides how many reports a call makes (steps × sub-steps): kept fallibly.
    s.steps.try_reserve(1).map_err(|_| {
        Error::OutOfMemory(format!("the report of step {}.{} could not be kept", rep.step, rep.substep))
    })?;
    // The caller's positions made the reference before the first attempt.
    rep.reference_seconds += std::mem::take(&mut s.rebase_seconds);
    s.steps.push(rep);
    let Some(p) = &s.opts.progress else { return Ok(()) };
    let r = s.steps.last().expect("pushed");
    if p.go_on(r, step.count) {
        return Ok(());
    }
    Err(Error::Cancelled(format!(
        "the progress callback stopped the call after step {}.{} of {} ({:.4} of the motion); the solver is as \
         before the call",
        r.step, r.substep, step.count, r.fraction
    )))
}

/// Makes one step. Returns the quality of its result against the mesh it started from when one
/// attempt made the whole step from there (incremental reference: the attempt's own quality
/// check is that measure, on the same two meshes), else None.
fn do_step(s: &mut Solver, step: &Step, undo: &mut Undo) -> Result<Option<Quality>> {
    if s.opts.reference == ReferenceMode::Original {
        let reference_s = s.settle(undo)?;
        return original_step(s, step, reference_s).map(|()| None);
    }
    let split = s.opts.max_substeps > 1;
    let mut halving = Halving::new(s.opts.max_substeps);
    let mut substep = 0usize;
    while !halving.finished() {
        substep += 1;
        // The previous step's (or sub-step's) result is the reference: the hierarchy follows.
        let reference_s = s.settle(undo)?;
        let end = halving.end();
        let part = step.increment.between(halving.done, end);
        let t0 = Instant::now();
        let vals = part.vertex_values(s.mesh()).into_owned();
        let prescribed = warm_start::prescribed_values(s.h().fine(), &vals);
        let guess = s.increments.guess(&prescribed);
        let (sol, rebuilt, quality_s) = solve_part(s, &part, guess.as_deref(), undo)?;
        let mut rep = report(step, substep, end, &sol, rebuilt, t0, quality_s);
        rep.reference_seconds = reference_s;
        let q = &sol.quality;
        let valid = q.inverted == 0 && (!split || q.min_area_ratio >= s.opts.min_volume_ratio);
        if sol.report.converged && valid {
            let moved: Vec<f64> = crate::solver::moved(s.mesh().coords(), &sol.displacement);
            // The hierarchy follows when the next solve needs it (never, after a call's last step).
            s.set_reference_inner(moved.clone());
            s.increments.push(prescribed, sol.displacement);
            if let Some(w) = s.walls.as_mut() {
                w.move_walls(&part.rigid);
            }
            rep.accepted = true;
            s.last_valid = moved;
            record(s, step, rep)?;
            if substep == 1 && end >= 1.0 {
                return Ok(Some(sol.quality));
            }
            halving.done = end;
            continue;
        }
        if halving.halve() {
            record(s, step, rep)?;
            continue;
        }
        if sol.report.converged && !split {
            // The method's honest answer: a converged result with inverted cells. It is the
            // call's result when nothing follows it (reported, not accepted: it never becomes
            // the mesh); a later step cannot start from it.
            record(s, step, rep)?;
            if end >= 1.0 && step.last {
                s.last_valid = crate::solver::moved(s.mesh().coords(), &sol.displacement);
                return Ok((substep == 1).then_some(sol.quality));
            }
            return Err(Error::Tangled(format!(
                "step {}: the result has {} inverted cell(s) (min volume (2D: area) ratio {:.3e}); the next step cannot \
                 start from a tangled mesh: enable sub-stepping or use more steps",
                step.number, q.inverted, q.min_area_ratio
            )));
        }
        record(s, step, rep)?;
        check_converged(&sol.report, Some((step.number, substep)))?;
        let why = if q.inverted > 0 {
            format!("{} inverted cell(s)", q.inverted)
        } else {
            format!(
                "min volume (2D: area) ratio {:.3e} below the minimum {}",
                q.min_area_ratio, s.opts.min_volume_ratio
            )
        };
        return Err(Error::NotConverged(format!(
            "step {}: sub-stepping reached its limit of {} sub-steps at {:.4} of the motion: the next sub-step would \
             give {why}; the mesh stays at the last valid state",
            step.number,
            s.opts.max_substeps,
            step.from + (step.to - step.from) * halving.done
        )));
    }
    Ok(None)
}

/// How a step is split into sub-steps (also the distributed solver's): the part of it done, the
/// size of the next attempt, halved after a rejected one down to 1/`max_substeps` of the step.
pub(crate) struct Halving {
    /// The fraction of the step done.
    pub(crate) done: f64,
    size: f64,
    smallest: f64,
    split: bool,
}

impl Halving {
    /// A step not begun; `max_substeps` 0 or 1 never splits it.
    pub(crate) fn new(max_substeps: usize) -> Halving {
        let split = max_substeps > 1;
        let smallest = if split { 1.0 / max_substeps as f64 } else { 1.0 };
        Halving { done: 0.0, size: 1.0, smallest, split }
    }

    /// True once the whole step is done.
    pub(crate) fn finished(&self) -> bool {
        self.done >= 1.0
    }

    /// The fraction of the step the next attempt ends at.
    pub(crate) fn end(&self) -> f64 {
        if self.done + self.size >= 1.0 {
            1.0
        } else {
            self.done + self.size
        }
    }

    /// Halves the next attempt; false when sub-stepping is off or at its limit.
    pub(crate) fn halve(&mut self) -> bool {
        let halved = self.split && self.size / 2.0 >= self.smallest * (1.0 - 1e-12);
        if halved {
            self.size /= 2.0;
        }
        halved
    }
}

/// Solves one part of a step; a solve that stops above its tolerance on a hierarchy moved from
/// another mesh is retried once on a hierarchy rebuilt from the current reference. Returns the
/// solution, whether the hierarchy was rebuilt and the seconds of the result's quality check.
fn solve_part(s: &mut Solver, part: &Motion, guess: Option<&[f64]>, undo: &mut Undo) -> Result<(Solution, bool, f64)> {
    let (sol, quality_s) = s.solve_timed(part, guess)?;
    if sol.report.converged || s.h().fresh {
        return Ok((sol, false, quality_s));
    }
    s.rebuild(undo)?;
    let (sol, quality_s) = s.solve_timed(part, guess)?;
    Ok((sol, true, quality_s))
}

/// `ReferenceMode::Original`: the total motion so far solved from the original mesh.
fn original_step(s: &mut Solver, step: &Step, reference_s: f64) -> Result<()> {
    let total = match &s.total {
        Some((m, _)) => m.then(step.increment, s.mesh()),
        None => step.increment.clone(),
    };
    let t0 = Instant::now();
    let (sol, quality_s) = s.solve_timed(&total, None)?;
    let mut rep = report(step, 1, 1.0, &sol, false, t0, quality_s);
    rep.reference_seconds = reference_s;
    if !sol.report.converged {
        record(s, step, rep)?;
        return check_converged(&sol.report, Some((step.number, 1)));
    }
    let moved: Vec<f64> = crate::solver::moved(s.mesh().coords(), &sol.displacement);
    if sol.quality.inverted > 0 && !step.last {
        record(s, step, rep)?;
        return Err(Error::Tangled(format!(
            "step {}: the total motion so far inverts {} cell(s) of the original mesh",
            step.number, sol.quality.inverted
        )));
    }
    // A last step with inverted cells is the call's result, reported but not accepted.
    rep.accepted = sol.quality.inverted == 0;
    s.last_valid = moved.clone();
    s.total = Some((total, moved));
    record(s, step, rep)
}

/// One report for a whole call: cycles summed over the accepted sub-steps and the last one (the
/// result, also when it has inverted cells and is not accepted), the worst residual.
fn summary(steps: &[StepReport], t0: Instant) -> Report {
    let n = steps.len();
    let acc = steps.iter().enumerate().filter(|&(i, r)| r.accepted || i + 1 == n).map(|(_, r)| r);
    Report {
        cycles: acc.clone().map(|r| r.cycles).sum(),
        max_correction: 0.0,
        rel_residual: acc.clone().map(|r| r.rel_residual).fold(0.0, f64::max),
        converged: acc.clone().all(|r| r.converged),
        breakdown: None,
        seconds: t0.elapsed().as_secs_f64(),
        history: Vec::new(),
        max_slip_offwall: acc.clone().map(|r| r.max_slip_offwall).fold(0.0, f64::max),
        max_slip_correction: 0.0,
        polish_cycles: 0,
    }
}
