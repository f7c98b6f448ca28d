//! The C calls a host moving its mesh in several calls needs: the total displacement and quality
//! since the initial mesh, `meshmove_solver_write_vtu(s, path, 0, NULL)` writing them, and
//! NULL `face_offsets` inferred for a hexahedral mesh's quadrilateral faces.

use meshmove::capi::*;
use meshmove::io::read_vtu;
use std::ffi::{CStr, CString};
use std::ptr::{null, null_mut};

fn last() -> String {
    unsafe { CStr::from_ptr(meshmove_last_error()) }.to_str().unwrap().to_owned()
}

/// The unit cube in n³ hexahedra, the top's quads on patch 2, the bottom's on patch 1; the face
/// arrays without offsets.
fn cube(n: i32) -> (Vec<f64>, Vec<i32>, Vec<i32>, Vec<i32>) {
    let id = |i: i32, j: i32, k: i32| (k * (n + 1) + j) * (n + 1) + i;
    let mut xyz = Vec::new();
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                xyz.extend([i, j, k].map(|c| f64::from(c) / f64::from(n)));
            }
        }
    }
    let (mut cells, mut faces, mut patch) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let b = [id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k)];
                cells.extend(b);
                cells.extend(b.map(|v| v + (n + 1) * (n + 1)));
            }
        }
    }
    for j in 0..n {
        for i in 0..n {
            faces.extend([id(i, j, 0), id(i, j + 1, 0), id(i + 1, j + 1, 0), id(i + 1, j, 0)]);
            patch.push(1);
            faces.extend([id(i, j, n), id(i + 1, j, n), id(i + 1, j + 1, n), id(i, j + 1, n)]);
            patch.push(2);
        }
    }
    (xyz, cells, faces, patch)
}

fn create(n: i32, faces: &[i32], patch: &[i32], num_face_vertices: i32) -> (meshmove_status, *mut meshmove_mesh) {
    let (xyz, cells, _, _) = cube(n);
    let types = vec![meshmove_cell_type::Hexahedron as i32; (n * n * n) as usize];
    let mut m = null_mut();
    let nv = (n + 1).pow(3);
    let s = unsafe {
        meshmove_mesh_create(
            3,
            nv,
            xyz.as_ptr(),
            n * n * n,
            null(),
            cells.len() as i32,
            cells.as_ptr(),
            types.as_ptr(),
            patch.len() as i32,
            null(),
            num_face_vertices,
            faces.as_ptr(),
            patch.as_ptr(),
            null(),
            0,
            &mut m,
        )
    };
    (s, m)
}

#[test]
fn null_face_offsets_take_quads_from_the_counts() {
    let (_, _, faces, patch) = cube(3);
    let (s, m) = create(3, &faces, &patch, faces.len() as i32);
    assert_eq!(s, meshmove_status::Ok, "{}", last());
    let (mut nv, mut nf, mut nfv) = (0, 0, 0);
    let mut top = vec![0i32; 64];
    let mut count = 0;
    unsafe {
        assert_eq!(
            meshmove_mesh_patch_vertices(m, 2, 0, top.len() as i32, top.as_mut_ptr(), &mut count),
            meshmove_status::Ok,
            "{}",
            last()
        );
        assert_eq!(
            meshmove_mesh_sizes(m, null_mut(), &mut nv, null_mut(), null_mut(), &mut nf, &mut nfv),
            meshmove_status::Ok
        );
        assert_eq!(meshmove_mesh_free(m), meshmove_status::Ok);
    }
    assert_eq!((nv, count, nf, nfv), (64, 16, 54, 216));
    // A count that is neither 3 nor 4 per face is refused, naming both counts.
    let (s, m) = create(3, &faces[..71], &patch, 71);
    assert_eq!(s, meshmove_status::InvalidArgument);
    assert!(m.is_null());
    let msg = last();
    assert!(msg.contains("face_offsets NULL") && msg.contains("71") && msg.contains("18"), "{msg}");
}

#[test]
fn totals_since_the_initial_mesh_after_several_moves() {
    let n = 4;
    let (_, _, faces, patch) = cube(n);
    let (s, m) = create(n, &faces, &patch, faces.len() as i32);
    assert_eq!(s, meshmove_status::Ok, "{}", last());
    let nv = (n + 1).pow(3) as usize;
    let (mut bcs, mut sol) = (null_mut(), null_mut());
    let mut x = vec![0.0; 3 * nv];
    unsafe {
        assert_eq!(meshmove_bcs_create(&mut bcs), meshmove_status::Ok);
        assert_eq!(meshmove_solver_create(m, bcs, null(), &mut sol), meshmove_status::Ok, "{}", last());
        assert_eq!(meshmove_solver_get_coords(sol, x.len() as i32, x.as_mut_ptr()), meshmove_status::Ok);
    }
    let x0 = x.clone();
    // Three moves of the top by 0.05 in z each (increments).
    let mut inc = vec![0.0; 3 * nv];
    for v in 0..nv {
        if x0[3 * v + 2] == 1.0 {
            inc[3 * v + 2] = 0.05;
        }
    }
    let mut q = meshmove_quality::default();
    for _ in 0..3 {
        let s = unsafe { meshmove_solver_move(sol, x.len() as i32, inc.as_ptr(), x.as_mut_ptr(), null_mut(), &mut q) };
        assert_eq!(s, meshmove_status::Ok, "{}", last());
    }
    let (mut total, mut d) = (vec![0.0; 3 * nv], vec![0.0; 3 * nv]);
    let mut qt = meshmove_quality::default();
    unsafe {
        assert_eq!(
            meshmove_solver_get_total_displacement(sol, total.len() as i32, total.as_mut_ptr()),
            meshmove_status::Ok
        );
        assert_eq!(meshmove_solver_get_displacement(sol, d.len() as i32, d.as_mut_ptr()), meshmove_status::Ok);
        assert_eq!(meshmove_solver_total_quality(sol, &mut qt), meshmove_status::Ok);
    }
    for v in 0..nv {
        if x0[3 * v + 2] == 1.0 {
            assert!((total[3 * v + 2] - 0.15).abs() < 1e-15 && (d[3 * v + 2] - 0.05).abs() < 1e-15, "vertex {v}");
        }
    }
    assert!(total.iter().zip(x.iter().zip(&x0)).all(|(t, (a, b))| t.to_bits() == (a - b).to_bits()));
    // Against the initial mesh the cells under the top stretch more than three times as much as
    // in the last move (whose quality compares with the mesh before it).
    assert!(qt.max_volume_ratio - 1.0 > 3.0 * (q.max_volume_ratio - 1.0), "{qt:?} {q:?}");
    assert_eq!(qt.inverted, 0);
    // The default .vtu: the initial mesh and the total displacement.
    let path = std::env::temp_dir().join(format!("meshmove-totals-{}.vtu", std::process::id()));
    let c = CString::new(path.to_str().unwrap()).unwrap();
    assert_eq!(unsafe { meshmove_solver_write_vtu(sol, c.as_ptr(), 0, null()) }, meshmove_status::Ok, "{}", last());
    let back = read_vtu(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    let (_, disp, _) = back.point_data.iter().find(|f| f.0 == "displacement").unwrap();
    assert_eq!(disp, &total);
    assert_eq!(back.mesh.coords, x);
    let (_, ratio, _) = back.cell_data.iter().find(|f| f.0 == "volume_ratio").unwrap();
    let max = ratio.iter().copied().fold(f64::MIN, f64::max);
    assert_eq!(max, qt.max_volume_ratio);
    unsafe {
        assert_eq!(meshmove_solver_free(sol), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_free(bcs), meshmove_status::Ok);
        assert_eq!(meshmove_mesh_free(m), meshmove_status::Ok);
    }
}
