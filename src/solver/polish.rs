//! The polish of a tangled result. A solve stopped at the caller's tolerance leaves an error in
//! the displacement; in the thinnest cells of wall layers (the wing's trailing edge,
//! docs/PERFORMANCE.md) that error can be larger than the cell, and the moved mesh inverts
//! cells the exact solution keeps valid. Before such a result is reported tangled, the solver
//! solves on from it to a tighter tolerance and checks the mesh again; a motion that truly
//! tangles stays tangled and is reported so. A count of iterations bounds the polish, never a
//! time, so the result does not depend on the machine.

use crate::multigrid::solve::{Report, SolveParams};

/// The polish's tolerance as a fraction of the caller's.
const TIGHTER: f64 = 1e-3;

/// The tightest tolerance a polish asks for: below it double precision's rounding in the
/// operator's products of wall-layer cells leaves the residual where it is, and the iteration
/// would only stall (docs/perf-history.md, "The polish of a tangled result").
const FLOOR: f64 = 1e-13;

/// The parameters of the polish after a converged first solve with `p` that took `first`'s
/// cycles, or None when it cannot gain (the first did not converge, the tolerance is at the
/// floor already, or no cycles are left). The polish runs at most as many cycles as the first
/// solve, and the two together at most `p.max_cycles`.
pub(super) fn params(p: &SolveParams, first: &Report) -> Option<SolveParams> {
    let tol = (p.tol * TIGHTER).max(FLOOR);
    let max_cycles = p.max_cycles.saturating_sub(first.cycles).min(first.cycles.max(1));
    (first.converged && tol < p.tol && max_cycles > 0).then_some(SolveParams { tol, max_cycles, ..*p })
}

/// The report of a first solve and its polish: cycles, history and seconds added, the polish's
/// residual and correction, converged (the caller checked the polish against its criterion),
/// and the polish's cycles counted apart.
pub(super) fn chain(first: Report, polish: Report) -> Report {
    let polish_cycles = polish.cycles;
    Report { converged: true, polish_cycles, ..Report::chain(first, polish) }
}
