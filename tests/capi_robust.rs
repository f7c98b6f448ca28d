//! The C ABI under a host's hard cases: a move from the original mesh after a cleared rigid
//! motion, failing calls that leave every getter as it was, callbacks that fail, progress and
//! cancellation.

use meshmove::capi::*;
use std::ffi::CStr;
use std::ptr::{null, null_mut};

fn last() -> String {
    let mut buf = vec![0 as std::ffi::c_char; 1024];
    let mut needed = 0usize;
    let _ = unsafe { meshmove_last_error_message(buf.as_mut_ptr(), buf.len(), &mut needed) };
    unsafe { CStr::from_ptr(buf.as_ptr()) }.to_str().unwrap().to_owned()
}

const TOP: i32 = 3;

/// An n × n grid of the unit square in triangles, its top edges on patch `TOP`, the rest on
/// patch 0: the coordinates and the mesh handle.
fn grid(n: usize) -> (Vec<f64>, *mut meshmove_mesh) {
    let id = |i: usize, j: usize| (j * (n + 1) + i) as i32;
    let mut xy = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            xy.extend([i as f64 / n as f64, j as f64 / n as f64]);
        }
    }
    let mut cells = Vec::new();
    for j in 0..n {
        for i in 0..n {
            cells.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let edges: Vec<i32> = (0..n).flat_map(|i| [id(i, n), id(i + 1, n)]).collect();
    let patches = vec![TOP; n];
    let mut m = null_mut();
    let s = unsafe {
        meshmove_mesh_create_triangles(
            ((n + 1) * (n + 1)) as i32,
            xy.as_ptr(),
            (2 * n * n) as i32,
            cells.as_ptr(),
            0,
            n as i32,
            edges.as_ptr(),
            patches.as_ptr(),
            null(),
            &mut m,
        )
    };
    assert_eq!(s, meshmove_status::Ok, "{}", last());
    (xy, m)
}

/// A solver on the grid with every boundary FIXED, and its bcs handle.
fn solver(n: usize) -> (Vec<f64>, *mut meshmove_mesh, *mut meshmove_bcs, *mut meshmove_solver) {
    let (xy, m) = grid(n);
    let mut b = null_mut();
    let mut s = null_mut();
    unsafe {
        assert_eq!(meshmove_bcs_create(&mut b), meshmove_status::Ok);
        assert_eq!(meshmove_solver_create(m, b, null(), &mut s), meshmove_status::Ok, "{}", last());
    }
    (xy, m, b, s)
}

fn free(m: *mut meshmove_mesh, b: *mut meshmove_bcs, s: *mut meshmove_solver) {
    unsafe {
        for st in [meshmove_solver_free(s), meshmove_bcs_free(b), meshmove_mesh_free(m)] {
            assert_eq!(st, meshmove_status::Ok);
        }
    }
}

/// Every getter of a solver: positions, displacement.
fn observe(s: *mut meshmove_solver, len: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut x, mut d) = (vec![0.0; len], vec![0.0; len]);
    unsafe {
        assert_eq!(meshmove_solver_get_coords(s, len as i32, x.as_mut_ptr()), meshmove_status::Ok);
        assert_eq!(meshmove_solver_get_displacement(s, len as i32, d.as_mut_ptr()), meshmove_status::Ok);
    }
    (x, d)
}

#[test]
fn a_prescribed_displacement_after_cleared_rigid_motions_moves_the_patch() {
    for mode in [meshmove_reference::Incremental, meshmove_reference::Original] {
        let n = 4;
        let (xy0, m, b, s) = solver(n);
        let len = xy0.len();
        unsafe {
            assert_eq!(meshmove_solver_set_reference_mode(s, mode as i32), meshmove_status::Ok);
            let t = [0.1, 0.0];
            assert_eq!(
                meshmove_solver_set_rigid_motion(s, TOP, t.as_ptr(), [0.0].as_ptr(), [0.0, 0.0].as_ptr()),
                meshmove_status::Ok
            );
            let mut xy = xy0.clone();
            let zero = vec![0.0; len];
            let st = meshmove_solver_move(s, len as i32, zero.as_ptr(), xy.as_mut_ptr(), null_mut(), null_mut());
            assert_eq!(st, meshmove_status::Ok, "{}", last());
            assert_eq!(meshmove_solver_clear_rigid_motions(s), meshmove_status::Ok);
            let mut up = vec![0.0; len];
            for i in 0..=n {
                up[2 * (n * (n + 1) + i) + 1] = 0.05;
            }
            let st = meshmove_solver_move(s, len as i32, up.as_ptr(), xy.as_mut_ptr(), null_mut(), null_mut());
            assert_eq!(st, meshmove_status::Ok, "{}", last());
            for i in 0..=n {
                let v = n * (n + 1) + i;
                assert!((xy[2 * v] - (xy0[2 * v] + 0.1)).abs() < 1e-12, "{mode:?}: vertex {v}");
                assert!((xy[2 * v + 1] - (xy0[2 * v + 1] + 0.05)).abs() < 1e-12, "{mode:?}: vertex {v}");
            }
        }
        free(m, b, s);
    }
}

#[test]
fn an_inverted_move_in_steps_leaves_every_getter_as_it_was() {
    let n = 4;
    let (xy0, m, b, s) = solver(n);
    let len = xy0.len();
    unsafe {
        // A first call that succeeds, so the displacement getter holds something.
        let mut up = vec![0.0; len];
        for i in 0..=n {
            up[2 * (n * (n + 1) + i) + 1] = 0.05;
        }
        let st = meshmove_solver_move_in_steps(s, len as i32, up.as_ptr(), 2, 0, null_mut());
        assert_eq!(st, meshmove_status::Ok, "{}", last());
        let before = observe(s, len);
        assert!(before.1.iter().any(|&d| d != 0.0));
        // The top pushed through the bottom: the last step's result inverts cells.
        let down: Vec<f64> = up.iter().map(|d| d * -40.0).collect();
        let st = meshmove_solver_move_in_steps(s, len as i32, down.as_ptr(), 1, 0, null_mut());
        assert_eq!(st, meshmove_status::Inverted, "{}", last());
        assert_eq!(observe(s, len), before);
        // So does an inverted drop-in move, whose result only the caller's array receives.
        let mut xy = before.0.clone();
        let st = meshmove_solver_move(s, len as i32, down.as_ptr(), xy.as_mut_ptr(), null_mut(), null_mut());
        assert_eq!(st, meshmove_status::Inverted, "{}", last());
        assert_ne!(xy, before.0);
        assert_eq!(observe(s, len), before);
    }
    free(m, b, s);
}

/// Counts its calls in `*user_data` (an `i32`) and cancels at the third.
unsafe extern "C" fn cancel_at_three(user: *mut std::ffi::c_void, r: *const meshmove_step_report, steps: i32) -> i32 {
    let n = unsafe { &mut *(user as *mut i32) };
    *n += 1;
    assert_eq!(steps, 10);
    assert_eq!(unsafe { (*r).step }, *n);
    i32::from(*n >= 3)
}

#[test]
fn a_progress_callback_cancels_and_the_solver_is_as_before() {
    let n = 4;
    let (xy0, m, b, s) = solver(n);
    let len = xy0.len();
    let mut up = vec![0.0; len];
    for i in 0..=n {
        up[2 * (n * (n + 1) + i) + 1] = 0.05;
    }
    let mut calls = 0i32;
    unsafe {
        let st = meshmove_solver_move_in_steps(s, len as i32, up.as_ptr(), 2, 0, null_mut());
        assert_eq!(st, meshmove_status::Ok, "{}", last());
        let before = observe(s, len);
        let user = &mut calls as *mut i32 as *mut std::ffi::c_void;
        assert_eq!(meshmove_solver_set_progress(s, Some(cancel_at_three), user), meshmove_status::Ok);
        let st = meshmove_solver_move_in_steps(s, len as i32, up.as_ptr(), 10, 0, null_mut());
        assert_eq!(st, meshmove_status::Cancelled, "{}", last());
        assert!(last().contains("after step 3.1 of 10"), "{}", last());
        assert_eq!(calls, 3);
        assert_eq!(observe(s, len), before);
        // Removed, the callback is no longer called.
        assert_eq!(meshmove_solver_set_progress(s, None, null_mut()), meshmove_status::Ok);
        let st = meshmove_solver_move_in_steps(s, len as i32, up.as_ptr(), 10, 0, null_mut());
        assert_eq!(st, meshmove_status::Ok, "{}", last());
        assert_eq!(calls, 3);
    }
    free(m, b, s);
}

/// The closest point of the square's sides x = 0, x = 1 and y = 0 (patch 0); fails when
/// `*user_data` (an `i32`) is not zero.
unsafe extern "C" fn sides_or_fail(user: *mut std::ffi::c_void, dim: i32, x: *const f64, out: *mut f64) -> i32 {
    assert_eq!(dim, 2);
    let fail = unsafe { *(user as *const i32) } != 0;
    let (x, out) = unsafe { (std::slice::from_raw_parts(x, 2), std::slice::from_raw_parts_mut(out, 2)) };
    let best = [[0.0, x[1]], [1.0, x[1]], [x[0], 0.0]]
        .into_iter()
        .min_by(|a, b| {
            let d = |p: &[f64; 2]| (p[0] - x[0]).hypot(p[1] - x[1]);
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    out.copy_from_slice(&best);
    i32::from(fail)
}

#[test]
fn a_slip_callback_that_fails_gives_its_status_and_changes_nothing() {
    let n = 4;
    let (xy0, m) = grid(n);
    let len = xy0.len();
    let (mut b, mut s) = (null_mut(), null_mut());
    let mut fail = 0i32;
    let user = &mut fail as *mut i32 as *mut std::ffi::c_void;
    let mut side = vec![0.0; len];
    for i in 0..=n {
        side[2 * (n * (n + 1) + i)] = 0.05;
    }
    unsafe {
        assert_eq!(meshmove_bcs_create(&mut b), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_set_kinds(b, 0, meshmove_kind::Slip as i32), meshmove_status::Ok, "{}", last());
        assert_eq!(meshmove_bcs_set_slip_surface_checked(b, 0, Some(sides_or_fail), user), meshmove_status::Ok);
        assert_eq!(meshmove_solver_create(m, b, null(), &mut s), meshmove_status::Ok, "{}", last());
        let st = meshmove_solver_move_in_steps(s, len as i32, side.as_ptr(), 2, 0, null_mut());
        assert_eq!(st, meshmove_status::Ok, "{}", last());
        let before = observe(s, len);
        *(user as *mut i32) = 1;
        let st = meshmove_solver_move_in_steps(s, len as i32, side.as_ptr(), 2, 0, null_mut());
        assert_eq!(st, meshmove_status::CallbackFailed, "{}", last());
        assert!(last().contains("closest-point function reported a failure"), "{}", last());
        assert_eq!(observe(s, len), before);
        let mut xy = before.0.clone();
        let st = meshmove_solver_move(s, len as i32, side.as_ptr(), xy.as_mut_ptr(), null_mut(), null_mut());
        assert_eq!(st, meshmove_status::CallbackFailed, "{}", last());
        assert_eq!(xy, before.0);
        let mut d = vec![7.0; len];
        let st = meshmove_solver_solve(s, len as i32, side.as_ptr(), null(), d.as_mut_ptr(), null_mut());
        assert_eq!(st, meshmove_status::CallbackFailed, "{}", last());
        assert!(d.iter().all(|&v| v == 7.0));
        assert_eq!(observe(s, len), before);
        *(user as *mut i32) = 0;
        let st = meshmove_solver_move_in_steps(s, len as i32, side.as_ptr(), 2, 0, null_mut());
        assert_eq!(st, meshmove_status::Ok, "{}", last());
    }
    free(m, b, s);
}

/// A slip surface's closest point 1e300 away from every vertex in x and in y.
unsafe extern "C" fn far_away(_: *mut std::ffi::c_void, dim: i32, x: *const f64, out: *mut f64) {
    let (x, out) = unsafe { (std::slice::from_raw_parts(x, dim as usize), std::slice::from_raw_parts_mut(out, 2)) };
    out.copy_from_slice(&[x[0] + 1e300, x[1] + 1e300]);
}

#[test]
fn a_slip_surface_far_beyond_the_mesh_is_an_overflow_not_a_divergence() {
    let n = 4;
    let (xy0, m) = grid(n);
    let len = xy0.len();
    let (mut b, mut s) = (null_mut(), null_mut());
    let mut top = vec![0.0; len];
    for i in 0..=n {
        top[2 * (n * (n + 1) + i) + 1] = 0.05;
    }
    unsafe {
        assert_eq!(meshmove_bcs_create(&mut b), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_set_kinds(b, 0, meshmove_kind::Slip as i32), meshmove_status::Ok, "{}", last());
        assert_eq!(meshmove_bcs_set_slip_surface(b, 0, Some(far_away), null_mut()), meshmove_status::Ok);
        assert_eq!(meshmove_solver_create(m, b, null(), &mut s), meshmove_status::Ok, "{}", last());
        let before = observe(s, len);
        let mut xy = before.0.clone();
        let st = meshmove_solver_move(s, len as i32, top.as_ptr(), xy.as_mut_ptr(), null_mut(), null_mut());
        assert_eq!(st, meshmove_status::InvalidArgument, "{}", last());
        assert!(last().contains("overflow"), "{}", last());
        assert_eq!(xy, before.0);
        assert_eq!(observe(s, len), before);
        for st in [meshmove_solver_free(s), meshmove_bcs_free(b), meshmove_mesh_free(m)] {
            assert_eq!(st, meshmove_status::Ok);
        }
    }
}
