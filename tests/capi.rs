//! The C ABI called from Rust: statuses, messages, NULL and stale-handle safety, the generic mesh
//! call and its checks, the options handle, a full solve.

use meshmove::capi::*;
use std::ffi::CStr;
use std::ptr::{null, null_mut};

fn last() -> String {
    let mut buf = vec![0 as std::ffi::c_char; 512];
    let mut needed = 0usize;
    let _ = unsafe { meshmove_last_error_message(buf.as_mut_ptr(), buf.len(), &mut needed) };
    unsafe { CStr::from_ptr(buf.as_ptr()) }.to_str().unwrap().to_owned()
}

const XY: [f64; 10] = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.5, 0.5];
const CELLS: [i32; 12] = [0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4];
const TRI: i32 = meshmove_cell_type::Triangle as i32;

/// The unit square in four triangles around its centre, the right side on patch 2.
fn square() -> *mut meshmove_mesh {
    let mut m = null_mut();
    let s = unsafe {
        meshmove_mesh_create_triangles(
            5,
            XY.as_ptr(),
            4,
            CELLS.as_ptr(),
            0,
            1,
            [1, 2].as_ptr(),
            [2].as_ptr(),
            null(),
            &mut m,
        )
    };
    assert_eq!(s, meshmove_status::Ok, "{}", last());
    m
}

/// The generic call on the square's arrays: `offsets` NULL or given, faces the right side.
fn generic(cells: &[i32], offsets: Option<&[i32]>, types: &[i32], base: i32) -> (meshmove_status, *mut meshmove_mesh) {
    let mut m = null_mut();
    let right = [1 + base, 2 + base];
    let s = unsafe {
        meshmove_mesh_create(
            2,
            5,
            XY.as_ptr(),
            types.len() as i32,
            offsets.map_or(null(), |o| o.as_ptr()),
            cells.len() as i32,
            cells.as_ptr(),
            types.as_ptr(),
            1,
            null(),
            2,
            right.as_ptr(),
            [2].as_ptr(),
            null(),
            base,
            &mut m,
        )
    };
    (s, m)
}

#[test]
fn constants_match_the_crate() {
    let (mut a, mut b, mut c) = (0, 0, 0);
    assert_eq!(unsafe { meshmove_version(&mut a, &mut b, &mut c) }, meshmove_status::Ok);
    assert_eq!((a, b, c), (MESHMOVE_VERSION_MAJOR, MESHMOVE_VERSION_MINOR, MESHMOVE_VERSION_PATCH));
    assert_eq!(env!("CARGO_PKG_VERSION"), format!("{a}.{b}.{c}"));
    for t in meshmove::CellType::ALL {
        assert!([5, 9, 10, 12, 13, 14].contains(&(t.vtk_id() as i32)), "{t} is not a meshmove_cell_type");
    }
}

#[test]
fn status_derives_from_the_error() {
    use meshmove::{Error, MeshError};
    assert_eq!(meshmove_status::from(&Error::Mesh(MeshError::Empty)), meshmove_status::InvalidMesh);
    assert_eq!(meshmove_status::from(&Error::Bc("x".into())), meshmove_status::InvalidBcs);
    assert_eq!(meshmove_status::from(&Error::Diverged("x".into())), meshmove_status::Diverged);
    for (s, name) in [(meshmove_status::IllPosed, "ILL_POSED"), (meshmove_status::Unsupported, "UNSUPPORTED")] {
        let got = unsafe { CStr::from_ptr(meshmove_status_name(s as i32)) };
        assert_eq!(got.to_str().unwrap(), format!("MESHMOVE_STATUS_{name}"));
    }
}

#[test]
fn null_and_stale_handles_are_statuses() {
    unsafe {
        assert_eq!(meshmove_mesh_free(null_mut()), meshmove_status::Ok);
        assert_eq!(last(), "");
        let mut n = 0;
        assert_eq!(
            meshmove_mesh_sizes(null(), &mut n, &mut n, null_mut(), null_mut(), null_mut(), null_mut()),
            meshmove_status::NullPointer
        );
        assert!(last().contains("`mesh` is NULL"), "{}", last());
        let m = square();
        let mut b = null_mut();
        assert_eq!(meshmove_bcs_create(&mut b), meshmove_status::Ok);
        let sizes = |m: *const meshmove_mesh, n: &mut i32| {
            meshmove_mesh_sizes(m, n, null_mut(), null_mut(), null_mut(), null_mut(), null_mut())
        };
        assert_eq!(sizes(b as *const meshmove_mesh, &mut n), meshmove_status::InvalidHandle);
        assert!(last().contains("meshmove_bcs handle"), "{}", last());
        assert_eq!(meshmove_bcs_set_kinds(b, 0, 4), meshmove_status::InvalidArgument);
        assert!(last().contains("kind 4"));
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
        assert!(last().contains("5 vertices in 2D, so 2 × 5 = 10"), "{}", last());
        let (mut dim, mut nv, mut levels) = (0, 0, 0);
        assert_eq!(meshmove_solver_sizes(s, &mut dim, &mut nv, &mut levels), meshmove_status::Ok);
        assert_eq!((dim, nv), (2, 5));
        assert!(levels >= 1);
        for h in [meshmove_solver_free(s), meshmove_bcs_free(b), meshmove_mesh_free(m)] {
            assert_eq!(h, meshmove_status::Ok);
        }
    }
}

#[test]
fn mesh_messages_count_from_the_callers_base() {
    // cell 2 (1-based) = second cell repeats vertex 5 (1-based)
    let cells1: [i32; 12] = [1, 2, 5, 2, 5, 5, 3, 4, 5, 4, 1, 5];
    let (s, _) = generic(&cells1, None, &[TRI; 4], 1);
    assert_eq!(s, meshmove_status::InvalidMesh);
    assert!(last().contains("cell 2 repeats vertex 5"), "{}", last());
    let cells0: Vec<i32> = cells1.iter().map(|c| c - 1).collect();
    let (s, _) = generic(&cells0, None, &[TRI; 4], 0);
    assert_eq!(s, meshmove_status::InvalidMesh);
    assert!(last().contains("cell 1 repeats vertex 4"), "{}", last());
    // An index out of range names the raw index and the base.
    let mut bad = CELLS.map(|c| c + 1);
    bad[7] = 0;
    let (s, _) = generic(&bad, None, &[TRI; 4], 1);
    assert_eq!(s, meshmove_status::InvalidMesh);
    assert!(last().contains("cell 3 refers to vertex index 0, outside 1..6"), "{}", last());
    assert!(last().contains("numbered from 1"), "{}", last());
}

#[test]
fn the_generic_call_builds_the_same_mesh_and_checks_every_array() {
    unsafe {
        let offsets = [0, 3, 6, 9, 12];
        let (s, m) = generic(&CELLS, Some(&offsets), &[TRI; 4], 0);
        assert_eq!(s, meshmove_status::Ok, "{}", last());
        let (s, m0) = generic(&CELLS, None, &[TRI; 4], 0);
        assert_eq!(s, meshmove_status::Ok, "{}", last());
        let t = square();
        // Sizes and the lists read back: the same mesh three ways.
        for mesh in [m, m0, t] {
            let mut z = [0i32; 6];
            let [a, b, c, d, e, f] = &mut z;
            assert_eq!(meshmove_mesh_sizes(mesh, a, b, c, d, e, f), meshmove_status::Ok);
            // Every boundary edge is a face (4 sides, the right one on patch 2).
            assert_eq!(z, [2, 5, 4, 12, 4, 8]);
            let (mut off, mut conn, mut ty) = ([0i32; 5], [0i32; 12], [0i32; 4]);
            let st = meshmove_mesh_get_cells(mesh, 1, 5, off.as_mut_ptr(), 12, conn.as_mut_ptr(), 4, ty.as_mut_ptr());
            assert_eq!(st, meshmove_status::Ok, "{}", last());
            assert_eq!((off, ty), (offsets, [TRI; 4]));
            assert!(conn.iter().all(|&v| (1..=5).contains(&v)));
            let (mut foff, mut fconn, mut patch) = ([0i32; 5], [0i32; 8], [0i32; 4]);
            let st =
                meshmove_mesh_get_faces(mesh, 0, 5, foff.as_mut_ptr(), 8, fconn.as_mut_ptr(), 4, patch.as_mut_ptr());
            assert_eq!(st, meshmove_status::Ok, "{}", last());
            assert_eq!(foff, [0, 2, 4, 6, 8]);
            assert_eq!(patch.iter().filter(|&&p| p == 2).count(), 1);
            // Only the types, the others skipped (NULL with length 0).
            let st = meshmove_mesh_get_cells(mesh, 0, 0, null_mut(), 0, null_mut(), 4, ty.as_mut_ptr());
            assert_eq!(st, meshmove_status::Ok, "{}", last());
            let st = meshmove_mesh_get_cells(mesh, 0, 4, off.as_mut_ptr(), 0, null_mut(), 0, null_mut());
            assert_eq!(st, meshmove_status::InvalidArgument);
            assert!(last().contains("`offsets` has length 4"), "{}", last());
            assert_eq!(meshmove_mesh_free(mesh), meshmove_status::Ok);
        }
        // Offsets, types and lengths are checked before anything else, each named.
        type Case<'a> = (&'a [i32], Option<&'a [i32]>, &'a [i32], &'a str);
        let cases: [Case; 6] = [
            (&CELLS, Some(&[1, 3, 6, 9, 12]), &[TRI; 4], "`cell_offsets[0]` is 1"),
            (&CELLS, Some(&[0, 3, 7, 9, 12]), &[TRI; 4], "give cell 1 4 vertices; it is a triangle (type 5)"),
            (&CELLS, Some(&[0, 3, 2, 9, 12]), &[TRI; 4], "`cell_offsets` decreases at entry 2"),
            (&CELLS, None, &[TRI, TRI, 7, TRI], "cell 2 has type 7, which is not a meshmove_cell_type"),
            (&CELLS[..11], None, &[TRI; 4], "12 vertex indices are needed, 11 were given"),
            (
                &CELLS[..11],
                Some(&[0, 3, 6, 9, 12]),
                &[TRI; 4],
                "`cell_offsets[4]` is 12; it must be num_cell_vertices, 11",
            ),
        ];
        for (cells, offsets, types, needle) in cases {
            let (s, m) = generic(cells, offsets, types, 0);
            assert_eq!((s, m), (meshmove_status::InvalidArgument, null_mut()), "{needle}: {}", last());
            assert!(last().contains(needle), "{needle}: {}", last());
        }
        // A quad, a tetrahedron where triangles are: the dimension check is the core's.
        let (s, _) = generic(
            &[0, 1, 2, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4],
            None,
            &[meshmove_cell_type::Tetra as i32, TRI, TRI, TRI],
            0,
        );
        assert_eq!(s, meshmove_status::InvalidMesh, "{}", last());
        assert!(last().contains("cell 0 is a tetrahedron, which is not a cell of a 2D mesh"), "{}", last());
    }
}

/// The square as 4 quads and a tetrahedron through the generic create call; the C layer's checks
/// of 3D faces.
#[test]
fn quads_and_tetrahedra_through_the_generic_call() {
    unsafe {
        // 3 × 3 vertices, 2 × 2 quads.
        let xy: Vec<f64> = (0..9).flat_map(|v| [(v % 3) as f64 * 0.5, (v / 3) as f64 * 0.5]).collect();
        let quads = [0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7];
        let q = meshmove_cell_type::Quad as i32;
        let mut m = null_mut();
        let s = meshmove_mesh_create(
            2,
            9,
            xy.as_ptr(),
            4,
            null(),
            16,
            quads.as_ptr(),
            [q; 4].as_ptr(),
            0,
            null(),
            0,
            null(),
            null(),
            null(),
            0,
            &mut m,
        );
        assert_eq!(s, meshmove_status::Ok, "{}", last());
        assert_eq!(meshmove_mesh_free(m), meshmove_status::Ok);
        // One tetrahedron, its four faces tagged (NULL face offsets: triangles in 3D).
        let (s, m) = tetrahedron(3, None, &[0, 1, 3, 1, 2, 3, 2, 0, 3, 0, 2, 1], &[1, 1, 1, 2]);
        assert_eq!(s, meshmove_status::Ok, "{}", last());
        let mut sizes = [0i32; 6];
        let [a, b, c, d, e, f] = sizes.each_mut();
        assert_eq!(meshmove_mesh_sizes(m, a, b, c, d, e, f), meshmove_status::Ok);
        assert_eq!(sizes, [3, 4, 1, 4, 4, 12]);
        assert_eq!(meshmove_mesh_free(m), meshmove_status::Ok);
        // 3D face sizes and indices are checked by the C layer whatever the core supports.
        let (s, _) = tetrahedron(3, Some(&[0, 3, 5]), &[0, 1, 3, 1, 2], &[1, 1]);
        assert_eq!(s, meshmove_status::InvalidArgument);
        assert!(last().contains("give face 1 2 vertices; a face of a 3D mesh has [3, 4]"), "{}", last());
        let (s, _) = tetrahedron(3, None, &[0, 1, 4], &[1]);
        assert_eq!(s, meshmove_status::InvalidMesh);
        assert!(last().contains("tagged face 0 refers to vertex index 4, outside 0..4"), "{}", last());
        let (s, _) = tetrahedron(4, None, &[], &[]);
        assert_eq!(s, meshmove_status::InvalidArgument);
        assert!(last().contains("dim is 4"), "{}", last());
    }
}

/// The generic call on one tetrahedron (told it is in `dim` dimensions) with tagged faces.
fn tetrahedron(
    dim: i32,
    offsets: Option<&[i32]>,
    faces: &[i32],
    patches: &[i32],
) -> (meshmove_status, *mut meshmove_mesh) {
    let xyz = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let mut m = null_mut();
    let s = unsafe {
        meshmove_mesh_create(
            dim,
            4,
            xyz.as_ptr(),
            1,
            null(),
            4,
            [0, 1, 2, 3].as_ptr(),
            [meshmove_cell_type::Tetra as i32].as_ptr(),
            patches.len() as i32,
            offsets.map_or(null(), |o| o.as_ptr()),
            faces.len() as i32,
            faces.as_ptr(),
            patches.as_ptr(),
            null(),
            0,
            &mut m,
        )
    };
    (s, m)
}

#[test]
fn options_are_a_handle_with_checked_setters() {
    unsafe {
        let mut o = null_mut();
        assert_eq!(meshmove_options_create(&mut o), meshmove_status::Ok);
        let refused: [(meshmove_status, &str); 12] = [
            (meshmove_options_set_method(o, 3), "method 3"),
            (meshmove_options_set_mode(o, -1), "mode -1"),
            (meshmove_options_set_criterion(o, 2), "criterion 2"),
            (meshmove_options_set_threads(o, -2), "threads is -2"),
            (meshmove_options_set_threads(o, MESHMOVE_MAX_THREADS + 1), "threads is 1025"),
            (meshmove_options_set_tol(o, f64::NAN), "tol is NaN"),
            (meshmove_options_set_max_cycles(o, 0), "max_cycles is 0"),
            (meshmove_options_set_cheb_degree(o, MESHMOVE_MAX_CHEB_DEGREE + 1), "cheb_degree is 65"),
            (meshmove_options_set_cheb_coarse_degree(o, -1), "cheb_coarse_degree is -1"),
            (meshmove_options_set_cheb_lower_ratio(o, 0.5), "cheb_lower_ratio is 0.5"),
            (meshmove_options_set_substepping(o, 4, 1.0), "min_volume_ratio is 1"),
            (meshmove_options_set_reference_mode(o, 2), "reference mode 2"),
        ];
        for (s, needle) in refused {
            assert_eq!(s, meshmove_status::InvalidArgument, "{needle}");
        }
        assert_eq!(meshmove_options_set_reference_mode(o, 2), meshmove_status::InvalidArgument);
        assert!(last().starts_with("meshmove_options_set_reference_mode: reference mode 2"), "{}", last());
        // The same displacement from default options as from NULL; another method differs.
        let m = square();
        let mut b = null_mut();
        assert_eq!(meshmove_bcs_create(&mut b), meshmove_status::Ok);
        let mut d = [0.0; 10];
        d[2] = 0.1;
        d[4] = 0.1;
        let solve = |opts: *const meshmove_options| {
            let mut s = null_mut();
            assert_eq!(meshmove_solver_create(m, b, opts, &mut s), meshmove_status::Ok, "{}", last());
            let mut out = [0.0; 10];
            assert_eq!(
                meshmove_solver_solve(s, 10, d.as_ptr(), null(), out.as_mut_ptr(), null_mut()),
                meshmove_status::Ok
            );
            assert_eq!(meshmove_solver_free(s), meshmove_status::Ok);
            out
        };
        let default = solve(null());
        assert_eq!(solve(o), default);
        assert_eq!(meshmove_options_set_method(o, meshmove_method::Laplacian as i32), meshmove_status::Ok);
        assert_eq!(meshmove_options_set_threads(o, 1), meshmove_status::Ok);
        assert_eq!(meshmove_options_set_tol(o, 1e-10), meshmove_status::Ok);
        assert_ne!(solve(o), default);
        assert_eq!(meshmove_options_free(o), meshmove_status::Ok);
        let mut s = null_mut();
        assert_eq!(meshmove_solver_create(m, b, o, &mut s), meshmove_status::InvalidHandle);
        assert!(last().contains("meshmove_options handle that was already freed"), "{}", last());
        assert_eq!(meshmove_options_set_tol(o, 1.0), meshmove_status::InvalidHandle);
        assert_eq!(meshmove_bcs_free(b), meshmove_status::Ok);
        assert_eq!(meshmove_mesh_free(m), meshmove_status::Ok);
    }
}

#[test]
fn rigid_motions_and_offsets_take_dim_values() {
    unsafe {
        let m = square();
        let mut b = null_mut();
        assert_eq!(meshmove_bcs_create(&mut b), meshmove_status::Ok);
        let off = [1.0, 0.0, 0.0];
        // A 3-vector offset is taken whatever the mesh (its z is ignored in 2D).
        let mut b3 = null_mut();
        assert_eq!(meshmove_bcs_create(&mut b3), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_link_periodic(b3, 1, 2, 3, off.as_ptr(), 1e-9), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_free(b3), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_link_periodic(b, 1, 2, 1, off.as_ptr(), 1e-9), meshmove_status::InvalidArgument);
        assert_eq!(meshmove_bcs_link_periodic(b, 1, 2, 2, null(), 1e-9), meshmove_status::NullPointer);
        // z (component 2) is a component of 3D meshes: accepted, and ignored on a 2D mesh.
        assert_eq!(meshmove_bcs_set_kind(b, 2, 2, 0), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_set_kind(b, 2, 3, 0), meshmove_status::InvalidArgument);
        assert!(last().contains("component 3 does not exist"), "{}", last());
        let mut s = null_mut();
        assert_eq!(meshmove_solver_create(m, b, null(), &mut s), meshmove_status::Ok);
        // The right side (patch 2) turns by 0.1 about (1, 0.5).
        let (t, r, c) = ([0.0, 0.0], [0.1], [1.0, 0.5]);
        assert_eq!(meshmove_solver_set_rigid_motion(s, 2, t.as_ptr(), r.as_ptr(), c.as_ptr()), meshmove_status::Ok);
        assert_eq!(
            meshmove_solver_set_rigid_motion(s, 2, t.as_ptr(), null(), c.as_ptr()),
            meshmove_status::NullPointer
        );
        assert!(last().contains("`rotation` is NULL"), "{}", last());
        let nan = [f64::NAN, 0.0];
        assert_eq!(
            meshmove_solver_set_rigid_motion(s, 2, nan.as_ptr(), r.as_ptr(), c.as_ptr()),
            meshmove_status::InvalidArgument
        );
        let mut out = [0.0; 10];
        let zero = [0.0; 10];
        let st = meshmove_solver_solve(s, 10, zero.as_ptr(), null(), out.as_mut_ptr(), null_mut());
        assert_eq!(st, meshmove_status::Ok, "{}", last());
        // Vertex 1, (1, 0), is 0.5 below the centre: it moves by (0.5 sin 0.1, 0.5 − 0.5 cos 0.1).
        let want = [0.5 * 0.1f64.sin(), 0.5 - 0.5 * 0.1f64.cos()];
        assert!((out[2] - want[0]).abs() < 1e-15 && (out[3] - want[1]).abs() < 1e-15, "{out:?}");
        assert_eq!(meshmove_solver_free(s), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_free(b), meshmove_status::Ok);
        assert_eq!(meshmove_mesh_free(m), meshmove_status::Ok);
    }
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
        assert_eq!(
            meshmove_mesh_sizes(m, null_mut(), &mut n, null_mut(), null_mut(), null_mut(), null_mut()),
            meshmove_status::InvalidHandle
        );
        assert!(last().contains("already freed"), "{}", last());
        for f in fresh {
            assert_eq!(meshmove_mesh_free(f), meshmove_status::Ok);
        }
        let name = CStr::from_ptr(meshmove_status_name(meshmove_status::Busy as i32));
        assert_eq!(name.to_str().unwrap(), "MESHMOVE_STATUS_BUSY");
    }
}

/// The closest point of the circle of radius `*user` about the origin (a C callback).
unsafe extern "C" fn circle(user: *mut std::ffi::c_void, dim: i32, x: *const f64, out: *mut f64) {
    let (r, calls) = unsafe { &*(user as *const (f64, std::sync::atomic::AtomicUsize)) };
    calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    assert_eq!(dim, 2);
    let p = unsafe { std::slice::from_raw_parts(x, 2) };
    let len = (p[0] * p[0] + p[1] * p[1]).sqrt();
    unsafe { std::slice::from_raw_parts_mut(out, 2) }.copy_from_slice(&[r * p[0] / len, r * p[1] / len]);
}

/// An annulus through the C ABI, its outer circle MESHMOVE_KIND_SLIP with the circle as a
/// callback: the inner circle turned by 0.3 moves the outer vertices along the circle, exactly
/// on it, and the report says how far off they are.
#[test]
fn slip_wall_with_a_c_callback() {
    let (nr, nt) = (6usize, 40usize);
    let mut xy = Vec::new();
    for i in 0..=nr {
        let r = 1.0 + 2.0 * i as f64 / nr as f64;
        for k in 0..nt {
            let a = std::f64::consts::TAU * k as f64 / nt as f64;
            xy.extend([r * a.cos(), r * a.sin()]);
        }
    }
    let id = |i: usize, k: usize| (i * nt + k % nt) as i32;
    let (mut cells, mut edges, mut patches) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..nr {
        for k in 0..nt {
            cells.extend([id(i, k), id(i + 1, k), id(i + 1, k + 1), id(i, k), id(i + 1, k + 1), id(i, k + 1)]);
        }
    }
    for k in 0..nt {
        edges.extend([id(0, k), id(0, k + 1), id(nr, k), id(nr, k + 1)]);
        patches.extend([1, 2]);
    }
    let nv = xy.len() / 2;
    let (mut m, mut b, mut s) = (null_mut(), null_mut(), null_mut());
    unsafe {
        let st = meshmove_mesh_create_triangles(
            nv as i32,
            xy.as_ptr(),
            (cells.len() / 3) as i32,
            cells.as_ptr(),
            0,
            patches.len() as i32,
            edges.as_ptr(),
            patches.as_ptr(),
            null(),
            &mut m,
        );
        assert_eq!(st, meshmove_status::Ok, "{}", last());
        assert_eq!(meshmove_bcs_create(&mut b), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_set_kinds(b, 1, meshmove_kind::Clamped as i32), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_set_kinds(b, 2, 3), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_set_kinds(b, 2, 4), meshmove_status::InvalidArgument);
        let user = (3.0f64, std::sync::atomic::AtomicUsize::new(0));
        let ptr = &user as *const _ as *mut std::ffi::c_void;
        assert_eq!(meshmove_bcs_set_slip_surface(b, 2, Some(circle), ptr), meshmove_status::Ok);
        assert_eq!(meshmove_solver_create(m, b, null(), &mut s), meshmove_status::Ok, "{}", last());
        let mut bd = vec![0.0; 2 * nv];
        let (c, sn) = (0.3f64.cos(), 0.3f64.sin());
        for k in 0..nt {
            let (x, y) = (xy[2 * k], xy[2 * k + 1]);
            bd[2 * k] = c * x - sn * y - x;
            bd[2 * k + 1] = sn * x + c * y - y;
        }
        let mut coords = xy.clone();
        let (mut rep, mut q) = (meshmove_report::default(), meshmove_quality::default());
        let st = meshmove_solver_move(s, 2 * nv as i32, bd.as_ptr(), coords.as_mut_ptr(), &mut rep, &mut q);
        assert_eq!(st, meshmove_status::Ok, "{}", last());
        assert!(user.1.load(std::sync::atomic::Ordering::Relaxed) >= nt, "the callback was called");
        assert!(rep.max_slip_offwall < 1e-12, "{rep:?}");
        let outer = (0..nt).map(|k| id(nr, k) as usize);
        let (mut off, mut slid) = (0.0f64, 0.0f64);
        for v in outer {
            let (x, y) = (coords[2 * v], coords[2 * v + 1]);
            off = off.max(((x * x + y * y).sqrt() - 3.0).abs());
            slid = slid.max((x - xy[2 * v]).abs() + (y - xy[2 * v + 1]).abs());
        }
        assert!(off < 1e-12 && slid > 0.01, "off the circle {off:e}, slid {slid}");
        assert_eq!(q.inverted, 0);
        assert_eq!(meshmove_solver_free(s), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_free(b), meshmove_status::Ok);
        assert_eq!(meshmove_mesh_free(m), meshmove_status::Ok);
    }
}
