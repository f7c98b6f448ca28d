//! The worker threads of one solver. Every parallel loop of a solve runs inside
//! [`Pool::install`], so rayon's global pool is never used: the thread count set on a solver
//! bounds all of its work (an MPI rank with `threads = 1` runs on one worker thread), and a
//! process that forks does not depend on threads it no longer has.
//!
//! `fork()`: the child inherits the pool's memory but none of its threads; a pool used there
//! would wait forever. `install` compares the process id stored at creation with the current one
//! and, in a child, builds a fresh pool of the same size first. The parent's pool object is
//! leaked in the child (not dropped): its locks may have been held by a thread that does not
//! exist there, so dropping it could block (also when a pool never used in the child is dropped
//! there). Results do not depend on the rebuild: every
//! reduction's order is fixed by the data, not by the threads (`sparse.rs`).

use crate::limits::MAX_THREADS;
use crate::{Error, Result};
use std::sync::{Arc, Mutex};

pub(crate) struct Pool {
    threads: usize,
    /// The process that built `pool`, and the pool.
    inner: Mutex<(u32, Arc<rayon::ThreadPool>)>,
}

impl std::fmt::Debug for Pool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Pool").field("threads", &self.threads).finish()
    }
}

/// The count a `threads` option asks for: 0 is the machine's available parallelism (1 when it
/// cannot be read), anything above [`MAX_THREADS`] is refused before a thread is spawned.
pub(crate) fn resolve_threads(threads: usize) -> Result<usize> {
    if threads > MAX_THREADS {
        return Err(Error::InvalidArgument(format!(
            "threads is {threads}; at most {MAX_THREADS} (0 = one per available core)"
        )));
    }
    Ok(match threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()).min(MAX_THREADS),
        n => n,
    })
}

fn build(threads: usize) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("meshmove-{i}"))
        .build()
        .map_err(|e| Error::InvalidArgument(format!("cannot start {threads} worker threads: {e}")))
}

impl Pool {
    /// A pool of `threads` workers (0: one per available core; at most [`MAX_THREADS`]).
    pub(crate) fn new(threads: usize) -> Result<Pool> {
        let threads = resolve_threads(threads)?;
        let pool = build(threads)?;
        Ok(Pool { threads, inner: Mutex::new((std::process::id(), Arc::new(pool))) })
    }

    /// Worker threads (the resolved count, never 0).
    #[cfg(test)]
    pub(crate) fn threads(&self) -> usize {
        self.threads
    }

    /// Runs `f` on this pool's workers (its parallel loops too), rebuilding the pool first when
    /// the process is a child forked after the pool was built. Fails only if that rebuild cannot
    /// start its threads.
    pub(crate) fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> Result<R> {
        let pool = {
            let mut g = self.inner.lock().unwrap_or_else(|p| p.into_inner());
            let pid = std::process::id();
            if g.0 != pid {
                let fresh = Arc::new(build(self.threads)?);
                // The parent's pool has no threads here and its locks may be held: leak it.
                std::mem::forget(std::mem::replace(&mut g.1, fresh));
                g.0 = pid;
            }
            Arc::clone(&g.1)
        };
        Ok(pool.install(f))
    }
}

impl Drop for Pool {
    fn drop(&mut self) {
        let g = self.inner.get_mut().unwrap_or_else(|p| p.into_inner());
        if g.0 != std::process::id() {
            // Dropped in a forked child before any use there: the parent's pool (see `install`).
            std::mem::forget(Arc::clone(&g.1));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;

    #[test]
    fn honours_the_thread_count() {
        for n in [1, 3] {
            let p = Pool::new(n).unwrap();
            assert_eq!(p.threads(), n);
            let seen = p
                .install(|| {
                    (0..10_000)
                        .into_par_iter()
                        .map(|_| std::thread::current().id())
                        .collect::<std::collections::HashSet<_>>()
                })
                .unwrap();
            assert!(seen.len() <= n, "{n} threads asked, {} seen", seen.len());
            assert_eq!(p.install(rayon::current_num_threads).unwrap(), n);
        }
    }

    #[test]
    fn bounds_are_checked_before_spawning() {
        let t = std::time::Instant::now();
        let e = Pool::new(i32::MAX as usize).unwrap_err();
        assert!(e.to_string().contains("at most 1024"), "{e}");
        assert!(t.elapsed().as_secs_f64() < 0.1);
        assert!(Pool::new(0).unwrap().threads() >= 1);
    }
}
