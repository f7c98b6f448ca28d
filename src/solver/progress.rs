//! The caller's progress hook, told of every sub-step of a motion and able to cancel it, and
//! the request to cancel a running call from another thread.

use super::StepReport;
use std::sync::atomic::{AtomicBool, Ordering};
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

/// A request to stop a solver's running call, from any thread:
/// [`Solver::canceller`](super::Solver::canceller) hands out clones of the solver's own. The
/// call checks it after every multigrid cycle of a solve (a count, not a clock, so a check comes
/// within one cycle of the request) and fails with `Error::Cancelled`, leaving the solver as it
/// was. A request made while no call runs stops the next call that solves at its first check;
/// the call that stops consumes the request.
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// Asks the running (or next) call to stop.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Release);
    }

    /// True while a request waits to be consumed.
    pub fn is_requested(&self) -> bool {
        self.0.load(Ordering::Acquire)
    }

    /// Consumes the request: true when there was one.
    pub(crate) fn take(&self) -> bool {
        self.0.swap(false, Ordering::AcqRel)
    }
}
