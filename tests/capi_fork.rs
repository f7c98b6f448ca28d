//! `fork()` while other threads create and free handles: every child can create and free
//! handles (none hangs on a lock a vanished thread held), and a handle in use at the fork can
//! be freed in the child.

#![cfg(unix)]

use meshmove::capi::*;
use std::ptr::null_mut;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A generous limit for all children together: a hang, not a slow machine, exceeds it.
const LIMIT: Duration = Duration::from_secs(120);

/// Creates and frees a bcs handle and an options handle: true when every call returned OK.
fn create_and_free() -> bool {
    let (mut b, mut o) = (null_mut(), null_mut());
    unsafe {
        meshmove_bcs_create(&mut b) == meshmove_status::Ok
            && meshmove_options_create(&mut o) == meshmove_status::Ok
            && meshmove_options_free(o) == meshmove_status::Ok
            && meshmove_bcs_free(b) == meshmove_status::Ok
    }
}

/// Forks a child that runs `f` and exits with 0 when it returns true, 1 otherwise.
fn fork_child(f: impl FnOnce() -> bool) -> libc::pid_t {
    let pid = unsafe { libc::fork() };
    assert!(pid >= 0, "fork failed");
    if pid == 0 {
        let ok = f();
        unsafe { libc::_exit(if ok { 0 } else { 1 }) };
    }
    pid
}

/// Waits for every child until the deadline: the exit codes, or the pids still running (killed).
fn wait_all(pids: &[libc::pid_t], deadline: Instant) -> Result<Vec<i32>, Vec<libc::pid_t>> {
    let mut codes = vec![None; pids.len()];
    while codes.iter().any(Option::is_none) {
        for (i, &pid) in pids.iter().enumerate() {
            if codes[i].is_some() {
                continue;
            }
            let mut status = 0;
            if unsafe { libc::waitpid(pid, &mut status, libc::WNOHANG) } == pid {
                codes[i] = Some(if libc::WIFEXITED(status) { libc::WEXITSTATUS(status) } else { -1 });
            }
        }
        if Instant::now() > deadline {
            let hung: Vec<libc::pid_t> =
                pids.iter().zip(&codes).filter(|(_, c)| c.is_none()).map(|(&p, _)| p).collect();
            for &p in &hung {
                unsafe {
                    libc::kill(p, libc::SIGKILL);
                    libc::waitpid(p, null_mut(), 0);
                }
            }
            return Err(hung);
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    Ok(codes.into_iter().map(|c| c.expect("all done")).collect())
}

#[test]
fn children_forked_during_handle_traffic_create_and_free_handles() {
    let stop = Arc::new(AtomicBool::new(false));
    let workers: Vec<_> = (0..3)
        .map(|_| {
            let stop = Arc::clone(&stop);
            std::thread::spawn(move || {
                let mut n = 0usize;
                while !stop.load(Ordering::Relaxed) {
                    assert!(create_and_free());
                    n += 1;
                }
                n
            })
        })
        .collect();
    let pids: Vec<libc::pid_t> = (0..120).map(|_| fork_child(|| (0..10).all(|_| create_and_free()))).collect();
    stop.store(true, Ordering::Relaxed);
    let made: usize = workers.into_iter().map(|w| w.join().unwrap()).sum();
    assert!(made > 0);
    match wait_all(&pids, Instant::now() + LIMIT) {
        Ok(codes) => assert!(codes.iter().all(|&c| c == 0), "exit codes {codes:?}"),
        Err(hung) => panic!("{} of {} children hung: {hung:?}", hung.len(), pids.len()),
    }
}
