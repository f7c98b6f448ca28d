//! Solving one component to a tolerance: the paper's stationary W-cycle iteration, or the
//! W-cycle as a preconditioner for conjugate gradients (the default, docs/DESIGN.md §5).

use super::cycle::{cycle, Workspace};
use super::group::GroupOp;
use super::hierarchy::Hierarchy;
pub use super::params::{Criterion, Mode, SolveParams};
use super::policy::CycleParams;
use super::smoother::Start;
use super::strain::{LevelEdges, EDGE_STRETCH};
use crate::sparse::{axpy, par_update};
use std::ops::Range;

/// What a solve did, per component or combined.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Report {
    /// W-cycles (stationary mode) or preconditioned CG iterations, each one W-cycle.
    pub cycles: usize,
    /// Largest vertex correction of the last cycle.
    pub max_correction: f64,
    /// ‖b − A x‖₂ / ‖b‖₂ at the end (0 when b = 0).
    pub rel_residual: f64,
    /// True when the criterion is met (for the relative residual, by the true residual, not CG's
    /// updated one).
    pub converged: bool,
    /// Conjugate gradients broke down: pᵀAp was not positive and finite at this iteration (the
    /// operator is not positive definite, e.g. on a tangled reference mesh).
    pub breakdown: Option<usize>,
    /// Wall-clock time of the solve, in seconds (summed over the groups of a combined report).
    pub seconds: f64,
    /// (max correction, relative residual) after each cycle.
    pub history: Vec<(f64, f64)>,
    /// Slip walls: the largest distance of a slipped vertex from its wall in the result (0
    /// without slip walls). The original faces of the wall or its analytic shape measure it.
    pub max_slip_offwall: f64,
    /// Slip walls: the largest distance a slipped vertex was moved onto its wall after the solve
    /// (the solve slides vertices along the wall's tangent planes, which a curved wall leaves by
    /// a second-order distance).
    pub max_slip_correction: f64,
    /// Of `cycles`, those of the polish: a converged result with inverted cells is solved on
    /// from itself to a tighter tolerance before it is reported tangled (docs/DESIGN.md §5,
    /// "Wall layers"); 0 when no polish ran, and in the summary of a call's steps (whose
    /// `cycles` include every polish).
    pub polish_cycles: usize,
}

impl Report {
    /// Combines the reports of two groups of components of one solve.
    pub(crate) fn merge(a: Report, b: Report) -> Report {
        let n = a.history.len().max(b.history.len());
        let at = |h: &Vec<(f64, f64)>, i: usize| h.get(i).or(h.last()).copied().unwrap_or((0.0, 0.0));
        Report {
            cycles: a.cycles.max(b.cycles),
            max_correction: a.max_correction.max(b.max_correction),
            rel_residual: a.rel_residual.max(b.rel_residual),
            converged: a.converged && b.converged,
            breakdown: a.breakdown.or(b.breakdown),
            seconds: a.seconds + b.seconds,
            history: (0..n)
                .map(|i| {
                    let (p, q) = (at(&a.history, i), at(&b.history, i));
                    (p.0.max(q.0), p.1.max(q.1))
                })
                .collect(),
            max_slip_offwall: a.max_slip_offwall.max(b.max_slip_offwall),
            max_slip_correction: a.max_slip_correction.max(b.max_slip_correction),
            polish_cycles: a.polish_cycles.max(b.polish_cycles),
        }
    }
}

impl Report {
    /// The report of two solves run one after the other on the same system (the second from the
    /// first's result): cycles, history and time added, the second's residual and verdict.
    pub(crate) fn chain(a: Report, b: Report) -> Report {
        Report {
            cycles: a.cycles + b.cycles,
            polish_cycles: a.polish_cycles + b.polish_cycles,
            converged: a.converged && b.converged,
            breakdown: a.breakdown.or(b.breakdown),
            seconds: a.seconds + b.seconds,
            history: a.history.into_iter().chain(b.history).collect(),
            ..b
        }
    }
}

/// Solves A x = b for the components `comps` (one group of `Hierarchy::groups`) from the
/// initial guess in `x`; `b` and `x` hold one block of n values per component, and the group is
/// one system: one set of CG scalars over all its blocks. `scale` is the largest prescribed
/// displacement (for the max-correction criterion).
#[cfg(feature = "internals")]
pub fn solve(h: &Hierarchy, comps: Range<usize>, p: &SolveParams, b: &[f64], x: &mut [f64], scale: f64) -> Report {
    solve_until(h, comps, p, b, x, scale, 1.0, &|| false)
}

/// As [`solve`], asking `stop` after every cycle: true ends the solve there, unconverged (the
/// caller's cancellation); `unit` is the solve's values per unit of the mesh's coordinates
/// (the displacements scaled to the solve, 1 when they are not), for the stop test under wall
/// layers (`strain`).
#[allow(clippy::too_many_arguments)]
pub fn solve_until(
    h: &Hierarchy,
    comps: Range<usize>,
    p: &SolveParams,
    b: &[f64],
    x: &mut [f64],
    scale: f64,
    unit: f64,
    stop: &Stop<'_>,
) -> Report {
    let t0 = std::time::Instant::now();
    let lev = GroupOp::new(h.fine(), comps.clone(), false);
    let bnorm = lev.norm(b);
    let mut rep = Report::default();
    if bnorm == 0.0 {
        x.iter_mut().for_each(|v| *v = 0.0);
        rep.converged = true;
        return rep;
    }
    let mut ws = Workspace::new(h, comps.len());
    let layers = LevelEdges::of_layers(h.fine(), comps.clone());
    let run = Run { h, op: lev, comps: comps.clone(), p, b, bnorm, scale, unit, layers, stop };
    let mut cp = CycleParams::resolve(h, p);
    let mut boost = 0;
    for restart in 0..=TRUE_RESIDUAL_RESTARTS {
        match p.mode {
            Mode::PaperFaithful => run.stationary(x, &mut ws, &mut rep),
            Mode::Default => {
                // A stalled PCG restarts from its iterate with a stronger smoother (see `STALL`).
                while run.pcg(&cp, x, &mut ws, &mut rep, boost < MAX_BOOSTS) {
                    cp = cp.stronger(boost);
                    boost += 1;
                }
            }
        }
        let mut r = vec![0.0; b.len()];
        lev.residual(b, x, &mut r, &mut ws.fine().s);
        rep.rel_residual = lev.norm(&r) / bnorm;
        // PCG's updated residual drifts from the true one by rounding: a solve is converged
        // when the true residual meets the tolerance, and restarts from it while cycles remain.
        let true_ok = p.criterion != Criterion::RelativeResidual || rep.rel_residual <= p.tol;
        if rep.converged && !true_ok {
            rep.converged = false;
            if restart < TRUE_RESIDUAL_RESTARTS && rep.cycles < p.max_cycles && rep.breakdown.is_none() && !stop() {
                continue;
            }
        }
        break;
    }
    rep.seconds = t0.elapsed().as_secs_f64();
    rep
}

/// Restarts from the true residual when the updated one claimed convergence it does not have.
const TRUE_RESIDUAL_RESTARTS: usize = 2;

/// PCG counts as stalled when, after `STALL_AFTER` iterations, the residual fell by less than
/// this over the last `STALL_SPAN` (a rate per iteration well above a healthy solve's). The
/// free surface re-meshed at half its biharmonic motion (tests/convergence.rs) stalls at the
/// default degree and converges at higher ones: distorted cells need stronger smoothing
/// (docs/perf-history.md, step 9).
const STALL: f64 = 0.2;
const STALL_AFTER: usize = 10;
const STALL_SPAN: usize = 5;
/// Smoother strengthenings before a stalled solve runs on as it is (degree 10, the l1 bound's
/// interval, degree 16, 26: see `CycleParams::stronger`).
const MAX_BOOSTS: usize = 4;

/// Diverging when the residual grew this much: stop rather than run to max_cycles.
const DIVERGED: f64 = 1e8;

/// The caller's question after every cycle: true stops the solve.
pub type Stop<'a> = dyn Fn() -> bool + Sync + 'a;

/// What both iterations share: the hierarchy, the components, the parameters and the system.
struct Run<'a> {
    h: &'a Hierarchy,
    /// The group's operator on the finest level.
    op: GroupOp<'a>,
    comps: Range<usize>,
    p: &'a SolveParams,
    b: &'a [f64],
    bnorm: f64,
    scale: f64,
    unit: f64,
    /// The finest level's edges when it has lines across wall layers: a converged iterate's
    /// last correction stretches none by more than `EDGE_STRETCH` (PCG only; `strain`).
    layers: Option<LevelEdges<'a>>,
    stop: &'a Stop<'a>,
}

impl Run<'_> {
    /// Records cycle `k` (its largest correction and the residual `r`) in the report; true when
    /// the iteration should stop (converged, diverged or stopped by the caller). `held` is
    /// asked when the criterion is met: whether the correction also meets the stop test under
    /// wall layers.
    fn record(&self, rep: &mut Report, k: usize, max_corr: f64, r: &[f64], held: impl FnOnce() -> bool) -> bool {
        let rel = self.op.norm(r) / self.bnorm;
        rep.history.push((max_corr, rel));
        rep.cycles = k;
        rep.max_correction = max_corr;
        rep.converged = self.p.met(max_corr, rel, self.scale) && held();
        rep.converged || !rel.is_finite() || rel > DIVERGED || (self.stop)()
    }

    fn stationary(&self, x: &mut [f64], ws: &mut Workspace, rep: &mut Report) {
        let Run { h, p, b, .. } = *self;
        let comps = self.comps.clone();
        let cp = CycleParams::resolve(h, p);
        let lev = self.op;
        let mut r = vec![0.0; b.len()];
        for k in rep.history.len() + 1..=p.max_cycles {
            let mc = cycle(h, comps.clone(), &cp, b, x, Start::Guess, ws);
            lev.residual(b, x, &mut r, &mut ws.fine().s);
            if self.record(rep, k, mc, &r, || true) {
                return;
            }
        }
    }

    /// PCG from `x`, numbering its iterations after those already in `rep`. Returns true when
    /// it stopped because it stalled (only if `may_stall`); the caller then strengthens `cp`.
    fn pcg(&self, cp: &CycleParams, x: &mut [f64], ws: &mut Workspace, rep: &mut Report, may_stall: bool) -> bool {
        let Run { h, p, b, .. } = *self;
        let comps = self.comps.clone();
        let cp = *cp;
        let first = rep.history.len();
        let lev = self.op;
        let n = b.len();
        // Three vectors: the preconditioned residual z shares q's storage (q = A dir is spent
        // once r is updated), and the products' scratch S is the fine level's, free between
        // preconditioner applications.
        let (mut r, mut dir, mut q) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        lev.residual(b, x, &mut r, &mut ws.fine().s);
        // A guess already at the tolerance (a step's warm start that continues the last step
        // exactly) needs no iteration, and a zero residual has no direction to take. Under wall
        // layers a guess at the tolerance still takes one: the residual does not see the error
        // it leaves in the thinnest cells (docs/DESIGN.md §5), which a warm start carries from
        // step to step, and one iteration corrects it and gives the stop test under wall layers
        // a correction to judge.
        let rn = lev.norm(&r);
        let at_tol = p.criterion == Criterion::RelativeResidual && rn <= p.tol * self.bnorm;
        if rn == 0.0 || (at_tol && !h.has_lines()) {
            rep.converged = true;
            return false;
        }
        cycle(h, comps.clone(), &cp, &r, &mut dir, Start::Zero, ws);
        let mut rz = lev.dot(&r, &dir);
        for k in first + 1..=p.max_cycles {
            lev.apply(&mut dir, &mut q, &mut ws.fine().s);
            let pq = lev.dot(&dir, &q);
            if pq <= 0.0 || !pq.is_finite() {
                // Not positive definite: the iterate is not improved by this direction. Reported
                // (the caller turns it into an error), never taken as a zero update.
                rep.breakdown = Some(k);
                rep.converged = false;
                return false;
            }
            let alpha = rz / pq;
            axpy(alpha, &dir, x);
            axpy(-alpha, &q, &mut r);
            let held = || self.layers.as_ref().is_none_or(|e| e.largest(alpha, &dir, self.unit) <= EDGE_STRETCH);
            if self.record(rep, k, alpha.abs() * lev.max_abs(&dir), &r, held) {
                return false;
            }
            let hist = &rep.history;
            if may_stall && k - first >= STALL_AFTER && hist[k - 1].1 > STALL * hist[k - 1 - STALL_SPAN].1 {
                return true;
            }
            let z = &mut q;
            cycle(h, comps.clone(), &cp, &r, z, Start::Zero, ws);
            let rz_new = lev.dot(&r, z);
            let beta = rz_new / rz;
            rz = rz_new;
            let zr = &*z;
            par_update(&mut dir, |i, d| zr[i] + beta * d);
        }
        false
    }
}
