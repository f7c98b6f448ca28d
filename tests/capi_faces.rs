//! `meshmove_mesh_create_from_faces`: a face-based mesh through the C ABI, in both index bases,
//! is the mesh the Rust call builds; its errors name the face in the caller's numbering.

use meshmove::capi::*;
use meshmove::{FaceMeshData, Mesh};
use std::ffi::CStr;
use std::ptr::null_mut;

#[path = "common/faces_c.rs"]
mod faces_c;
use faces_c::create_from_faces;

fn last() -> String {
    let mut buf = vec![0 as std::ffi::c_char; 512];
    let mut needed = 0usize;
    let _ = unsafe { meshmove_last_error_message(buf.as_mut_ptr(), buf.len(), &mut needed) };
    unsafe { CStr::from_ptr(buf.as_ptr()) }.to_str().unwrap().to_owned()
}

/// A triangle (cell 0) and a pentagon above it (cell 1), as faces (edges) with owners and
/// neighbours.
fn faces() -> FaceMeshData {
    FaceMeshData {
        dim: 2,
        coords: vec![0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.5, 2.0, 1.0, 2.0],
        face_offsets: vec![0, 2, 4, 6, 8, 10, 12, 14],
        // 0–1, 3–1 (shared: out of cell 1, into cell 0), 3–0, 1–2, 2–5, 5–4, 4–3
        face_vertices: vec![0, 1, 3, 1, 3, 0, 1, 2, 2, 5, 5, 4, 4, 3],
        owner: vec![0, 1, 0, 1, 1, 1, 1],
        neighbour: vec![-1, 0, -1, -1, -1, -1, -1],
        patch: vec![1, -1, 2, 3, 3, 4, 4],
        regions: Vec::new(),
    }
}

/// Creates the mesh through the C call in `base`, with `edit` applied to the arrays.
fn create(base: i32, edit: impl Fn(&mut FaceMeshData)) -> (meshmove_status, *mut meshmove_mesh) {
    let mut f = faces();
    edit(&mut f);
    create_from_faces(&f, base, 2)
}

#[test]
fn face_based_mesh_through_the_c_abi() {
    let rust = Mesh::from_faces(&faces()).unwrap();
    assert_eq!(rust.cell_types(), [meshmove::CellType::Triangle, meshmove::CellType::Polygon]);
    assert_eq!(rust.cell(1), [1, 2, 5, 4, 3]);
    for base in [0, 1] {
        let (s, m) = create(base, |_| {});
        assert_eq!(s, meshmove_status::Ok, "{}", last());
        let (mut dim, mut nv, mut nc, mut ncv, mut nf, mut nfv) = (0, 0, 0, 0, 0, 0);
        let s = unsafe { meshmove_mesh_sizes(m, &mut dim, &mut nv, &mut nc, &mut ncv, &mut nf, &mut nfv) };
        assert_eq!(s, meshmove_status::Ok);
        assert_eq!((dim, nv, nc, ncv, nf, nfv), (2, 6, 2, 8, 6, 12));
        assert_eq!(unsafe { meshmove_mesh_free(m) }, meshmove_status::Ok);
    }
    let (s, m) = create(1, |f| f.patch[3] = -1);
    assert_eq!((s, m), (meshmove_status::InvalidMesh, null_mut()));
    assert!(last().contains("face 4 is a boundary face"), "{}", last());
    let (s, _) = create(0, |f| f.owner[5] = 7);
    assert_eq!(s, meshmove_status::InvalidMesh);
    assert!(last().contains("face 5's owner is 7, outside 0..2"), "{}", last());
    let (s, _) = create(0, |f| f.face_vertices.swap(8, 9));
    assert_eq!(s, meshmove_status::InvalidMesh);
    assert!(last().contains("cell 1"), "{}", last());
}
