//! The C ABI called from Rust: statuses, messages, NULL and stale-handle safety, a full solve.

use meshmove::capi::*;
use std::ffi::CStr;
use std::ptr::{null, null_mut};

fn last() -> String {
    let mut buf = vec![0 as std::ffi::c_char; 512];
    let mut needed = 0usize;
    unsafe { meshmove_last_error_message(buf.as_mut_ptr(), buf.len(), &mut needed) };
    unsafe { CStr::from_ptr(buf.as_ptr()) }.to_str().unwrap().to_owned()
}

const XY: [f64; 10] = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.5, 0.5];
const CELLS: [i32; 12] = [0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4];

fn square() -> *mut meshmove_mesh {
    let mut m = null_mut();
    let s = unsafe {
        meshmove_mesh_create(5, XY.as_ptr(), 4, CELLS.as_ptr(), 0, 1, [1, 2].as_ptr(), [2].as_ptr(), null(), &mut m)
    };
    assert_eq!(s, meshmove_status::Ok, "{}", last());
    m
}

#[test]
fn constants_match_the_crate() {
    use meshmove::cases::meshes::*;
    assert_eq!(
        (MESHMOVE_FS_BOTTOM, MESHMOVE_FS_RIGHT, MESHMOVE_FS_TOP, MESHMOVE_FS_LEFT),
        (FS_BOTTOM, FS_RIGHT, FS_TOP, FS_LEFT)
    );
    assert_eq!(
        [MESHMOVE_IF_BOTTOM, MESHMOVE_IF_RIGHT, MESHMOVE_IF_INTERFACE, MESHMOVE_IF_LEFT, MESHMOVE_IF_TOP],
        [IF_BOTTOM, IF_RIGHT, IF_INTERFACE, IF_LEFT, IF_TOP]
    );
    assert_eq!((MESHMOVE_CH_WALL, MESHMOVE_CH_CYLINDER), (CH_WALL, CH_CYLINDER));
    let (mut a, mut b, mut c) = (0, 0, 0);
    assert_eq!(unsafe { meshmove_version(&mut a, &mut b, &mut c) }, meshmove_status::Ok);
    assert_eq!((a, b, c), (MESHMOVE_VERSION_MAJOR, MESHMOVE_VERSION_MINOR, MESHMOVE_VERSION_PATCH));
    let o = meshmove::Options::default();
    let mut co = std::mem::MaybeUninit::<meshmove_options>::uninit();
    assert_eq!(unsafe { meshmove_options_default(co.as_mut_ptr()) }, meshmove_status::Ok);
    let co = unsafe { co.assume_init() };
    assert_eq!(
        (co.tol, co.max_cycles as usize, (co.cheb_degree > 0).then_some(co.cheb_degree as usize)),
        (o.solve.tol, o.solve.max_cycles, o.solve.cheb_degree)
    );
}

#[test]
fn status_derives_from_the_error() {
    use meshmove::{Error, MeshError};
    assert_eq!(meshmove_status::from(&Error::Mesh(MeshError::Empty)), meshmove_status::InvalidMesh);
    assert_eq!(meshmove_status::from(&Error::Bc("x".into())), meshmove_status::InvalidBcs);
    assert_eq!(meshmove_status::from(&Error::Diverged("x".into())), meshmove_status::Diverged);
    let name = unsafe { CStr::from_ptr(meshmove_status_name(meshmove_status::IllPosed as i32)) };
    assert_eq!(name.to_str().unwrap(), "MESHMOVE_STATUS_ILL_POSED");
}

#[test]
fn null_and_stale_handles_are_statuses() {
    unsafe {
        assert_eq!(meshmove_mesh_free(null_mut()), meshmove_status::Ok);
        assert_eq!(last(), "");
        let mut n = 0;
        assert_eq!(meshmove_mesh_sizes(null(), &mut n, &mut n), meshmove_status::NullPointer);
        assert!(last().contains("`mesh` is NULL"), "{}", last());
        let m = square();
        let mut b = null_mut();
        assert_eq!(meshmove_bcs_create(&mut b), meshmove_status::Ok);
        assert_eq!(meshmove_mesh_sizes(b as *const meshmove_mesh, &mut n, &mut n), meshmove_status::InvalidHandle);
        assert!(last().contains("meshmove_bcs handle"), "{}", last());
        assert_eq!(meshmove_bcs_set_kinds(b, 0, 3), meshmove_status::InvalidArgument);
        assert!(last().contains("kind 3"));
        assert_eq!(meshmove_mesh_free(m), meshmove_status::Ok);
        assert_eq!(meshmove_mesh_free(m), meshmove_status::InvalidHandle);
        assert!(last().contains("meshmove_mesh handle that was already freed"), "{}", last());
        assert_eq!(meshmove_bcs_free(b), meshmove_status::Ok);
    }
}

#[test]
fn drop_in_move_matches_the_rust_api() {
    unsafe {
        let m = square();
        let mut b = null_mut();
        assert_eq!(meshmove_bcs_create(&mut b), meshmove_status::Ok);
        let mut s = null_mut();
        assert_eq!(meshmove_solver_create(m, b, null(), &mut s), meshmove_status::Ok, "{}", last());
        let mut bd = [0.0; 10];
        bd[5] = 0.1; // vertex 2 up
        bd[3] = 0.1; // vertex 1 up (on patch 2 and patch 0)
        let mut xy = XY;
        let mut rep = meshmove_report::default();
        let mut q = meshmove_quality::default();
        assert_eq!(
            meshmove_solver_move(s, 10, bd.as_ptr(), xy.as_mut_ptr(), &mut rep, &mut q),
            meshmove_status::Ok,
            "{}",
            last()
        );
        assert_eq!(rep.converged, 1);
        assert_eq!(q.inverted, 0);
        assert_eq!(xy[3], 0.1);
        assert!(xy[9] > 0.5);
        let mut back = [0.0; 10];
        assert_eq!(meshmove_solver_get_coords(s, 10, back.as_mut_ptr()), meshmove_status::Ok);
        assert_eq!(back, xy);
        assert_eq!(
            meshmove_solver_move(s, 9, bd.as_ptr(), xy.as_mut_ptr(), null_mut(), null_mut()),
            meshmove_status::InvalidArgument
        );
        assert!(last().starts_with("meshmove_solver_move: `coords` has length 9"), "{}", last());
        for h in [meshmove_solver_free(s), meshmove_bcs_free(b), meshmove_mesh_free(m)] {
            assert_eq!(h, meshmove_status::Ok);
        }
    }
}

#[test]
fn mesh_messages_count_from_the_callers_base() {
    // cell 2 (1-based) = second cell repeats vertex 5 (1-based)
    let cells1: [i32; 12] = [1, 2, 5, 2, 5, 5, 3, 4, 5, 4, 1, 5];
    let mut m = null_mut();
    let s = unsafe {
        meshmove_mesh_create(5, XY.as_ptr(), 4, cells1.as_ptr(), 1, 1, [2, 3].as_ptr(), [2].as_ptr(), null(), &mut m)
    };
    assert_eq!(s, meshmove_status::InvalidMesh);
    assert!(last().contains("cell 2 repeats vertex 5"), "{}", last());
    let cells0: Vec<i32> = cells1.iter().map(|c| c - 1).collect();
    let s = unsafe {
        meshmove_mesh_create(5, XY.as_ptr(), 4, cells0.as_ptr(), 0, 1, [1, 2].as_ptr(), [2].as_ptr(), null(), &mut m)
    };
    assert_eq!(s, meshmove_status::InvalidMesh);
    assert!(last().contains("cell 1 repeats vertex 4"), "{}", last());
}

#[test]
fn a_busy_handle_is_refused_and_a_freed_one_stays_refused() {
    unsafe {
        let m = square();
        // Many handles after the free: none takes the freed address.
        assert_eq!(meshmove_mesh_free(m), meshmove_status::Ok);
        let fresh: Vec<_> = (0..32).map(|_| square()).collect();
        assert!(fresh.iter().all(|&f| f != m));
        let mut n = 0;
        assert_eq!(meshmove_mesh_sizes(m, &mut n, null_mut()), meshmove_status::InvalidHandle);
        assert!(last().contains("already freed"), "{}", last());
        for f in fresh {
            assert_eq!(meshmove_mesh_free(f), meshmove_status::Ok);
        }
        let name = CStr::from_ptr(meshmove_status_name(meshmove_status::Busy as i32));
        assert_eq!(name.to_str().unwrap(), "MESHMOVE_STATUS_BUSY");
    }
}
