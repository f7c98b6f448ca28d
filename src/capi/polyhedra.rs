//! The faces of a mesh's polyhedral cells, which `meshmove_mesh_get_cells` does not give (it
//! gives a polyhedron's corners): their sizes, then the faces of every cell as CSR lists.

use super::error::CError;
use super::handles::{self, get};
use super::mesh::{meshmove_mesh, out_array, write_counts};
use super::status::meshmove_status;
use crate::Mesh;

/// The number of polyhedron faces of `m` and of vertex indices in them, each counted once per
/// cell (a face between two polyhedra is counted for both).
fn totals(m: &Mesh) -> (usize, usize) {
    (0..m.num_cells())
        .flat_map(|c| m.polyhedron_faces(c))
        .fold((0, 0), |(faces, vertices), f| (faces + 1, vertices + f.len()))
}

/// The sizes of the polyhedra's faces (either pointer may be NULL): `num_faces`, the faces of
/// every polyhedral cell together (a face shared by two polyhedra counted for each), and
/// `num_face_vertices`, the vertex indices in them: the lengths
/// `meshmove_mesh_get_polyhedron_faces` needs (faces + 1 offsets). Both are 0 for a mesh
/// without polyhedra.
///
/// # Safety
/// Non-NULL pointers must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_polyhedron_sizes(
    mesh: *const meshmove_mesh,
    num_faces: *mut i32,
    num_face_vertices: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_polyhedron_sizes, {
        let m = get(mesh, "mesh")?;
        let (nf, nfv) = totals(&m);
        check_fits(nf, nfv)?;
        // SAFETY: the caller guarantees non-NULL pointers are writable.
        unsafe { write_counts(&[(num_faces, nf, "num_faces"), (num_face_vertices, nfv, "num_face_vertices")]) }
    })
}

/// A mesh whose polyhedra hold more faces or face vertices than an `int32_t` counts is refused.
fn check_fits(nf: usize, nfv: usize) -> Result<(), CError> {
    if nf >= i32::MAX as usize || nfv > i32::MAX as usize {
        return Err(CError::arg(format!(
            "the polyhedra have {nf} faces with {nfv} vertex indices: more than int32_t offsets hold"
        )));
    }
    Ok(())
}

/// Copies the faces of every polyhedral cell: `cell_faces` (`num_cell_faces` = cells + 1, from
/// 0): cell c's faces are `cell_faces[c] .. cell_faces[c + 1]` of the face list (none for a cell
/// of another type); `face_offsets` (`num_face_offsets` = the faces of
/// `meshmove_mesh_polyhedron_sizes` + 1, from 0): face f's vertices are
/// `connectivity[face_offsets[f] .. face_offsets[f + 1]]` (`num_connectivity` = its
/// `num_face_vertices`; indices plus `index_base`), a loop whose right-hand normal points out of
/// the cell. Any of the three may be NULL with its length 0 to skip it; every length is checked
/// before anything is written.
///
/// # Safety
/// Each non-NULL array must hold its stated number of `int32_t`.
#[no_mangle]
#[must_use]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn meshmove_mesh_get_polyhedron_faces(
    mesh: *const meshmove_mesh,
    index_base: i32,
    num_cell_faces: i32,
    cell_faces: *mut i32,
    num_face_offsets: i32,
    face_offsets: *mut i32,
    num_connectivity: i32,
    connectivity: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_get_polyhedron_faces, {
        let m = get(mesh, "mesh")?;
        let base = handles::index_base(index_base)?;
        let (nc, (nf, nfv)) = (m.num_cells(), totals(&m));
        check_fits(nf, nfv)?;
        let of = format!("the mesh has {nc} cells whose polyhedra have {nf} faces and {nfv} vertex indices in them");
        // SAFETY: the caller guarantees each non-NULL array holds its stated length.
        let (cells, offsets, conn) = unsafe {
            (
                out_array(cell_faces, num_cell_faces, nc + 1, "cell_faces", &of)?,
                out_array(face_offsets, num_face_offsets, nf + 1, "face_offsets", &of)?,
                out_array(connectivity, num_connectivity, nfv, "connectivity", &of)?,
            )
        };
        // The counts fit in an int32_t (`check_fits`), so every running total does.
        if let Some(cells) = cells {
            cells[0] = 0;
            for c in 0..nc {
                cells[c + 1] = cells[c] + m.polyhedron_faces(c).len() as i32;
            }
        }
        let faces = || (0..nc).flat_map(|c| m.polyhedron_faces(c));
        if let Some(offsets) = offsets {
            offsets[0] = 0;
            for (k, f) in faces().enumerate() {
                offsets[k + 1] = offsets[k] + f.len() as i32;
            }
        }
        if let Some(conn) = conn {
            for (x, &v) in conn.iter_mut().zip(faces().flatten()) {
                *x = v as i32 + base;
            }
        }
        Ok(())
    })
}
