//! A `FaceMeshData` handed to `meshmove_mesh_create_from_faces` as a C caller would: 32-bit
//! arrays, indices in `base`, neighbour −1 (below the base) on the boundary. Shared by the
//! library's C ABI tests and the command line's polyMesh tests (included by path there).

use meshmove::capi::{meshmove_mesh, meshmove_mesh_create_from_faces, meshmove_status};
use meshmove::FaceMeshData;
use std::ptr::{null, null_mut};

/// Creates the mesh of `f` through the C call in index base `base`, with `num_cells` cells.
pub fn create_from_faces(f: &FaceMeshData, base: i32, num_cells: i32) -> (meshmove_status, *mut meshmove_mesh) {
    let b = |v: &[u32]| v.iter().map(|&x| x as i32 + base).collect::<Vec<i32>>();
    let cells = |v: &[i64]| v.iter().map(|&x| if x < 0 { -1 } else { x as i32 + base }).collect::<Vec<i32>>();
    let off: Vec<i32> = f.face_offsets.iter().map(|&o| o as i32).collect();
    let (conn, owner, neighbour) = (b(&f.face_vertices), cells(&f.owner), cells(&f.neighbour));
    let mut m = null_mut();
    // SAFETY: every array holds the length passed with it; `m` is writable.
    let s = unsafe {
        meshmove_mesh_create_from_faces(
            f.dim as i32,
            (f.coords.len() / f.dim) as i32,
            f.coords.as_ptr(),
            owner.len() as i32,
            off.as_ptr(),
            conn.len() as i32,
            conn.as_ptr(),
            owner.as_ptr(),
            neighbour.as_ptr(),
            f.patch.as_ptr(),
            num_cells,
            null(),
            base,
            &mut m,
        )
    };
    (s, m)
}
