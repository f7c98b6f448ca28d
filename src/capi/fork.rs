//! `fork()` safety: handlers registered with `pthread_atfork` once, before the handle registry
//! is first locked, so that a forked child never inherits the registry's lock held by a thread
//! it does not have (see `handles.rs`). The solvers' worker pools rebuild themselves in a child
//! (`pool.rs`). Nothing else is global and built on first use (the wedge and pyramid
//! decompositions are constants, `geometry/decomposed.rs`), so no lock or half-built table can
//! be inherited from a thread the child does not have.

use std::sync::Once;

extern "C" fn prepare() {
    super::handles::lock_for_fork();
}

extern "C" fn parent() {
    super::handles::unlock_in_parent();
}

extern "C" fn child() {
    super::handles::unlock_in_child();
}

/// Registers the fork handlers (once per process; later calls return at once).
pub(crate) fn register_handlers() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        #[cfg(unix)]
        // SAFETY: the handlers are plain `extern "C"` functions that live as long as the
        // process; registration has no other precondition.
        unsafe {
            // A failure (ENOMEM) leaves fork as unsafe as without the handlers; nothing else
            // depends on them.
            let _ = libc::pthread_atfork(Some(prepare), Some(parent), Some(child));
        }
    });
}
