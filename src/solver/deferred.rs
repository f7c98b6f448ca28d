//! The solver's hierarchy with its re-reference deferred: a step that makes its result the next
//! reference records that mesh, and the hierarchy is moved there (K, V, interpolation weights,
//! Galerkin products, bounds) only when a later call needs it. A one-shot run pays nothing after
//! its last step; a time loop pays each re-reference once, at the start of the next step.
//!
//! Calls that only read (`Solver::solve`, `Solver::cycle`) hold the solver by `&self`, so the
//! hierarchy waits behind a lock and, once moved, is kept in a cell that hands out shared
//! references; calls that mutate (`&mut self`) reach it directly.

use crate::multigrid::hierarchy::Hierarchy;
use crate::multigrid::phases::Phases;
use crate::{Mesh, Result};
use std::sync::{Mutex, OnceLock, PoisonError};

/// What moves a waiting hierarchy to the reference mesh: `Ok(None)` when moved in place,
/// `Ok(Some(new))` when a new hierarchy was built there instead (the waiting one left as it was),
/// an error with the waiting one as it was before.
pub(super) type Settle<'a> = &'a dyn Fn(&mut Hierarchy, &Mesh) -> Result<Option<Hierarchy>>;

pub(super) struct Deferred {
    /// The hierarchy at the reference mesh; unset while a re-reference waits.
    ready: OnceLock<Hierarchy>,
    /// While a re-reference waits: the hierarchy at an earlier reference.
    waiting: Mutex<Option<Hierarchy>>,
    /// While a re-reference waits: the reference mesh (after a read-only call moved the
    /// hierarchy, also its finest level's mesh until the next mutating call drops this copy).
    pending: Option<Mesh>,
}

impl Deferred {
    pub(super) fn new(h: Hierarchy) -> Deferred {
        Deferred { ready: OnceLock::from(h), waiting: Mutex::new(None), pending: None }
    }

    /// The reference mesh.
    pub(super) fn mesh(&self) -> &Mesh {
        match &self.pending {
            Some(m) => m,
            None => self.ready.get().expect("a hierarchy is ready when no re-reference waits").fine().mesh(),
        }
    }

    /// The hierarchy when it is at the reference mesh.
    pub(super) fn ready(&self) -> Option<&Hierarchy> {
        self.ready.get()
    }

    /// The hierarchy; it is at the reference mesh (no re-reference waits).
    pub(super) fn ready_mut(&mut self) -> &mut Hierarchy {
        self.ready.get_mut().expect("no re-reference waits")
    }

    /// The positions of the reference mesh while a re-reference to it waits.
    pub(super) fn waits_for(&self) -> Option<&[f64]> {
        match self.ready.get() {
            None => self.pending.as_ref().map(|m| m.coords()),
            Some(_) => None,
        }
    }

    /// Drops the copy of the reference mesh a read-only call left after moving the hierarchy.
    pub(super) fn tidy(&mut self) {
        if self.ready.get().is_some() {
            self.pending = None;
        }
    }

    /// The hierarchy at the reference mesh, moved there first when a re-reference waits.
    pub(super) fn get(&self, settle: Settle) -> Result<&Hierarchy> {
        if let Some(h) = self.ready.get() {
            return Ok(h);
        }
        // A panic cannot leave the waiting hierarchy half moved: `settle` restores it on errors.
        let mut waiting = self.waiting.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(h) = self.ready.get() {
            // Another thread moved it while this one waited for the lock.
            return Ok(h);
        }
        let mut h = waiting.take().expect("a hierarchy waits when none is ready");
        let mesh = self.pending.as_ref().expect("a reference waits with its hierarchy");
        let settled = match settle(&mut h, mesh) {
            Ok(None) => h,
            Ok(Some(built)) => built,
            Err(e) => {
                *waiting = Some(h);
                return Err(e);
            }
        };
        Ok(self.ready.get_or_init(|| settled))
    }

    /// `get` for a mutating call: the pending mesh's copy is dropped once the hierarchy is there.
    /// A hierarchy replaced by a new one is handed to `replaced`.
    pub(super) fn get_mut(&mut self, settle: Settle, replaced: impl FnOnce(Hierarchy)) -> Result<&mut Hierarchy> {
        if self.ready.get().is_none() {
            let mut h =
                self.waiting.get_mut().unwrap_or_else(PoisonError::into_inner).take().expect("a waiting hierarchy");
            let mesh = self.pending.as_ref().expect("a reference waits with its hierarchy");
            match settle(&mut h, mesh) {
                Ok(None) => self.ready.get_or_init(|| h),
                Ok(Some(built)) => {
                    replaced(h);
                    self.ready.get_or_init(|| built)
                }
                Err(e) => {
                    *self.waiting.get_mut().unwrap_or_else(PoisonError::into_inner) = Some(h);
                    return Err(e);
                }
            };
        }
        self.pending = None;
        Ok(self.ready.get_mut().expect("set above"))
    }

    /// The hierarchy, at the reference mesh or waiting to be moved there; for what does not
    /// depend on the positions.
    pub(super) fn with_any<T>(&self, f: impl FnOnce(&Hierarchy) -> T) -> T {
        if let Some(h) = self.ready.get() {
            return f(h);
        }
        let waiting = self.waiting.lock().unwrap_or_else(PoisonError::into_inner);
        match (self.ready.get(), waiting.as_ref()) {
            (Some(h), _) | (None, Some(h)) => f(h),
            (None, None) => unreachable!("a hierarchy is ready or waiting"),
        }
    }

    /// The seconds per phase of the hierarchy's last build or re-reference (a waiting
    /// re-reference not done yet).
    pub(super) fn phases(&self) -> Phases {
        self.with_any(|h| h.phases())
    }

    /// Makes `mesh` the reference: the hierarchy waits until a call needs it there.
    pub(super) fn defer(&mut self, mesh: Mesh) {
        if let Some(h) = self.ready.take() {
            *self.waiting.get_mut().unwrap_or_else(PoisonError::into_inner) = Some(h);
        }
        self.pending = Some(mesh);
    }

    /// Forgets a waiting re-reference: the hierarchy's own mesh is the reference again.
    pub(super) fn cancel(&mut self) {
        if let Some(h) = self.waiting.get_mut().unwrap_or_else(PoisonError::into_inner).take() {
            // The hierarchy waited: no read-only call moved it.
            let _ = self.ready.set(h);
        }
        self.pending = None;
    }

    /// Replaces the hierarchy (a rebuild): it is at the reference mesh.
    pub(super) fn replace(&mut self, h: Hierarchy) -> Option<Hierarchy> {
        self.pending = None;
        let waiting = self.waiting.get_mut().unwrap_or_else(PoisonError::into_inner).take();
        let old = self.ready.take().or(waiting);
        let _ = self.ready.set(h);
        old
    }
}
