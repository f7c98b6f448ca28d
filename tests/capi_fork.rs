//! `fork()` while other threads create and free handles: every child can create and free
//! handles (none hangs on a lock a vanished thread held), and a handle in use at the fork can
//! be freed in the child; under a memory cap a large request is a status, not an abort.

#![cfg(unix)]

use meshmove::capi::*;
use std::ptr::{null, null_mut};
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

/// The progress callback's context: it says it was entered, then waits to be released.
struct Gate {
    entered: AtomicBool,
    release: AtomicBool,
}

unsafe extern "C" fn wait_at_gate(user: *mut std::ffi::c_void, _: *const meshmove_step_report, _: i32) -> i32 {
    let g = unsafe { &*(user as *const Gate) };
    g.entered.store(true, Ordering::SeqCst);
    while !g.release.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_millis(1));
    }
    0
}

/// A square of two triangles, every side on patch 0.
fn small_solver() -> (*mut meshmove_mesh, *mut meshmove_bcs, *mut meshmove_solver) {
    let xy = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.5, 0.5];
    let cells = [0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4];
    let (mut m, mut b, mut s) = (null_mut(), null_mut(), null_mut());
    unsafe {
        let st =
            meshmove_mesh_create_triangles(5, xy.as_ptr(), 4, cells.as_ptr(), 0, 0, null(), null(), null(), &mut m);
        assert_eq!(st, meshmove_status::Ok);
        assert_eq!(meshmove_bcs_create(&mut b), meshmove_status::Ok);
        assert_eq!(meshmove_solver_create(m, b, null(), &mut s), meshmove_status::Ok);
    }
    (m, b, s)
}

#[test]
fn a_solver_busy_at_the_fork_is_refused_but_freed_in_the_child() {
    let (m, b, s) = small_solver();
    let gate = Arc::new(Gate { entered: AtomicBool::new(false), release: AtomicBool::new(false) });
    let user = Arc::as_ptr(&gate) as *mut std::ffi::c_void;
    assert_eq!(unsafe { meshmove_solver_set_progress(s, Some(wait_at_gate), user) }, meshmove_status::Ok);
    let sp = s as usize;
    let mover = std::thread::spawn(move || {
        let d = [0.0; 10];
        unsafe { meshmove_solver_move_in_steps(sp as *mut meshmove_solver, 10, d.as_ptr(), 1, 0, null_mut()) }
    });
    while !gate.entered.load(Ordering::SeqCst) {
        std::thread::sleep(Duration::from_millis(1));
    }
    let pid = fork_child(|| unsafe {
        let mut x = [0.0; 10];
        meshmove_solver_get_coords(s, 10, x.as_mut_ptr()) == meshmove_status::InvalidHandle
            && meshmove_solver_free(s) == meshmove_status::Ok
            && meshmove_solver_free(s) == meshmove_status::InvalidHandle
            && create_and_free()
    });
    gate.release.store(true, Ordering::SeqCst);
    assert_eq!(mover.join().unwrap(), meshmove_status::Ok);
    match wait_all(&[pid], Instant::now() + LIMIT) {
        Ok(codes) => assert_eq!(codes, [0]),
        Err(_) => panic!("the child hung"),
    }
    unsafe {
        for st in [meshmove_solver_free(s), meshmove_bcs_free(b), meshmove_mesh_free(m)] {
            assert_eq!(st, meshmove_status::Ok);
        }
    }
}

/// The process's address space in bytes (VmSize), from /proc.
fn address_space() -> u64 {
    let s = std::fs::read_to_string("/proc/self/status").unwrap();
    let line = s.lines().find(|l| l.starts_with("VmSize:")).unwrap();
    line.split_whitespace().nth(1).unwrap().parse::<u64>().unwrap() * 1024
}

/// The coordinates and triangles of an n × n grid of the unit square.
fn grid_arrays(n: usize) -> (Vec<f64>, Vec<i32>) {
    let id = |i: usize, j: usize| (j * (n + 1) + i) as i32;
    let xy: Vec<f64> =
        (0..=n).flat_map(|j| (0..=n).flat_map(move |i| [i as f64 / n as f64, j as f64 / n as f64])).collect();
    let cells: Vec<i32> = (0..n)
        .flat_map(|j| {
            (0..n)
                .flat_map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)])
        })
        .collect();
    (xy, cells)
}

/// Caps this process's address space at its present size and `headroom` bytes more.
fn cap_memory(headroom: u64) -> bool {
    let cap = address_space() + headroom;
    let limit = libc::rlimit { rlim_cur: cap as libc::rlim_t, rlim_max: cap as libc::rlim_t };
    unsafe { libc::setrlimit(libc::RLIMIT_AS, &limit) == 0 }
}

/// An n × n grid of the unit square in triangles (every side on patch 0).
fn grid_mesh(n: usize) -> Result<*mut meshmove_mesh, meshmove_status> {
    let (xy, cells) = grid_arrays(n);
    grid_mesh_of(n, &xy, &cells)
}

/// The mesh of the n × n grid's arrays (`grid_arrays`).
fn grid_mesh_of(n: usize, xy: &[f64], cells: &[i32]) -> Result<*mut meshmove_mesh, meshmove_status> {
    let mut m = null_mut();
    let nv = ((n + 1) * (n + 1)) as i32;
    let st = unsafe {
        meshmove_mesh_create_triangles(
            nv,
            xy.as_ptr(),
            (2 * n * n) as i32,
            cells.as_ptr(),
            0,
            0,
            null(),
            null(),
            null(),
            &mut m,
        )
    };
    if st == meshmove_status::Ok {
        Ok(m)
    } else {
        Err(st)
    }
}

#[test]
fn under_a_memory_cap_large_requests_are_a_status_not_an_abort() {
    let pid = fork_child(|| {
        if !cap_memory(300 << 20) {
            return false;
        }
        let xy = [0.0; 6];
        let mut m = null_mut();
        // The most cells with no cell array: refused before anything is allocated.
        let st = unsafe {
            meshmove_mesh_create_triangles(
                3,
                xy.as_ptr(),
                MESHMOVE_MAX_CELLS,
                null(),
                0,
                0,
                null(),
                null(),
                null(),
                &mut m,
            )
        };
        if st != meshmove_status::NullPointer {
            return false;
        }
        // A mesh that fits, and a solver for it that does not.
        let Ok(m) = grid_mesh(600) else { return false };
        let mut b = null_mut();
        let mut s = null_mut();
        unsafe {
            meshmove_bcs_create(&mut b) == meshmove_status::Ok
                && meshmove_solver_create(m, b, null(), &mut s) == meshmove_status::OutOfMemory
                && s.is_null()
                && meshmove_bcs_free(b) == meshmove_status::Ok
                && meshmove_mesh_free(m) == meshmove_status::Ok
        }
    });
    match wait_all(&[pid], Instant::now() + LIMIT) {
        Ok(codes) => assert_eq!(codes, [0], "the child under a memory cap failed a check or died"),
        Err(_) => panic!("the child hung"),
    }
}

#[test]
fn a_memory_budget_below_the_estimate_refuses_the_solver() {
    let Ok(m) = grid_mesh(20) else { panic!("mesh") };
    let (mut b, mut o, mut s) = (null_mut(), null_mut(), null_mut());
    unsafe {
        assert_eq!(meshmove_bcs_create(&mut b), meshmove_status::Ok);
        assert_eq!(meshmove_options_create(&mut o), meshmove_status::Ok);
        assert_eq!(meshmove_options_set_memory_budget(o, -1), meshmove_status::InvalidArgument);
        assert_eq!(meshmove_options_set_memory_budget(o, 10_000), meshmove_status::Ok);
        assert_eq!(meshmove_solver_create(m, b, o, &mut s), meshmove_status::OutOfMemory);
        assert!(s.is_null());
        assert_eq!(meshmove_options_set_memory_budget(o, 0), meshmove_status::Ok);
        assert_eq!(meshmove_solver_create(m, b, o, &mut s), meshmove_status::Ok);
        for st in [meshmove_solver_free(s), meshmove_options_free(o), meshmove_bcs_free(b), meshmove_mesh_free(m)] {
            assert_eq!(st, meshmove_status::Ok);
        }
    }
}

/// A genuinely large mesh (2.25 million vertices, 4.5 million triangles) whose arrays the caller
/// holds, under a cap of 300 MB more than they take: the mesh's estimate is refused with
/// OUT_OF_MEMORY (no abort), and a small mesh still fits afterwards.
#[test]
fn under_a_memory_cap_a_large_mesh_is_out_of_memory_not_an_abort() {
    let pid = fork_child(|| {
        let n = 1500;
        let (xy, cells) = grid_arrays(n);
        if !cap_memory(300 << 20) {
            return false;
        }
        let refused = grid_mesh_of(n, &xy, &cells) == Err(meshmove_status::OutOfMemory);
        let message = unsafe { std::ffi::CStr::from_ptr(meshmove_last_error()) }.to_string_lossy().into_owned();
        refused
            && message.contains("the mesh")
            && grid_mesh(10).is_ok_and(|m| unsafe { meshmove_mesh_free(m) } == meshmove_status::Ok)
    });
    match wait_all(&[pid], Instant::now() + LIMIT) {
        Ok(codes) => assert_eq!(codes, [0], "the child under a memory cap failed a check or died"),
        Err(_) => panic!("the child hung"),
    }
}
