//! The caller's progress hook: told of every sub-step of a motion, and able to cancel it.

use super::StepReport;
use std::sync::Arc;

/// A hook called after every sub-step attempt of [`Solver::advance`](super::Solver::advance)
/// and [`Solver::move_in_steps`](super::Solver::move_in_steps) (accepted or rejected) with its
/// report and the call's number of steps; it returns `true` to go on and `false` to cancel the
/// call, which then fails with `Error::Cancelled` and leaves the solver as it was. It runs on
/// the thread that made the call, between solves.
#[derive(Clone)]
pub struct Progress(Arc<Hook>);

/// A sub-step's report and the call's number of steps to "go on".
type Hook = dyn Fn(&StepReport, usize) -> bool + Send + Sync;

impl Progress {
    /// A hook from a function of the sub-step's report and the call's number of steps.
    pub fn new(f: impl Fn(&StepReport, usize) -> bool + Send + Sync + 'static) -> Progress {
        Progress(Arc::new(f))
    }

    /// Tells the hook of `report`: true to go on.
    pub fn go_on(&self, report: &StepReport, steps: usize) -> bool {
        (self.0)(report, steps)
    }
}

impl std::fmt::Debug for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Progress(..)")
    }
}
