//! The serial solver's [`Options`] on the distributed solver: one vocabulary for both. What the
//! distributed solver does with each option, and which it refuses:
//!
//! - `method`, `solve.tol`, `solve.max_cycles` (conjugate gradient iterations per component),
//!   `solve.cheb_degree` (the Chebyshev–Jacobi smoother's degree on every level; None: the
//!   biharmonic's of the serial levels of kept unknowns, 8, or under wall layers 16 on every
//!   level; 4 otherwise) and
//!   `hierarchy.max_levels` give the iteration ([`DistSolveParams`]);
//! - `max_substeps`, `min_volume_ratio`, `reference` and `progress` drive the steps as they do
//!   serially (`steps.rs`);
//! - `threads` is accepted and has no effect: each rank works on the thread that calls it;
//! - the paper-faithful mode, the largest-correction criterion, a coarse-level Chebyshev degree, a
//!   first-kind Chebyshev interval, hierarchy parameters other than `max_levels` and a memory
//!   budget are not distributed: refused with an error on every rank rather than ignored.

use super::DistSolveParams;
use crate::distributed::error::{DistError, DistErrorKind};
use crate::{Criterion, HierarchyParams, Method, Mode, Options};

/// The iteration parameters `opts` give, or the error naming the first option the distributed
/// solver does not take (blamed on `me`).
pub(super) fn dist_params(me: usize, opts: &Options) -> Result<DistSolveParams, DistError> {
    let input = |msg: String| DistError::new(me, DistErrorKind::Input, msg);
    crate::solver::check_options(opts).map_err(|e| input(e.to_string()))?;
    let s = &opts.solve;
    let not_distributed = [
        (s.mode != Mode::Default, "the paper-faithful mode (stationary W-cycles): use Mode::Default"),
        (s.criterion != Criterion::RelativeResidual, "the largest-correction criterion: use the relative residual"),
        (s.cheb_coarse_degree.is_some(), "a coarse-level Chebyshev degree: the degree is the same on every level"),
        (s.cheb_lower_ratio.is_some(), "the first-kind Chebyshev smoother: the fourth kind needs no interval"),
        (
            opts.hierarchy != HierarchyParams { max_levels: opts.hierarchy.max_levels, ..Default::default() },
            "hierarchy parameters other than max_levels: the distributed multigrid chooses its own levels",
        ),
        (opts.memory_budget != 0, "a memory budget: leave it 0"),
    ];
    if let Some((_, what)) = not_distributed.iter().find(|(refused, _)| *refused) {
        return Err(input(format!("the distributed solver does not take {what}")));
    }
    let default = DistSolveParams::default();
    Ok(DistSolveParams {
        tol: s.tol,
        max_iterations: s.max_cycles,
        degree: s.cheb_degree.unwrap_or(default.degree),
        max_levels: opts.hierarchy.max_levels,
        ..default
    })
}

/// The serial options that say what `method` and `params` say (the rest the defaults): what a
/// solver made without options reports as its options.
pub(super) fn serial_options(method: Method, params: &DistSolveParams) -> Options {
    let mut o = Options { method, ..Default::default() };
    o.solve.tol = params.tol;
    o.solve.max_cycles = params.max_iterations;
    o.solve.cheb_degree = (params.degree != 0).then_some(params.degree);
    o.hierarchy.max_levels = params.max_levels;
    o
}
