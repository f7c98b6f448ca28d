//! The faces of polyhedral cells: read from `MeshData::polyhedron_faces` (VTK's layout) and
//! checked: every face a loop of at least 3 of the cell's corners, every corner on a face, and
//! the faces closing the cell (each side of a face is run along once each way).

use super::{Csr, MeshData, MeshError, PolyhedronFaces};
use crate::geometry::CellType;

/// The faces of `d`'s polyhedra (whose corners `cells` holds, already checked against the
/// vertex range), one after another in cell order.
pub(super) fn faces(d: &MeshData, cells: &Csr) -> Result<PolyhedronFaces, MeshError> {
    let stream = &d.polyhedron_faces;
    let any = d.cell_types.contains(&CellType::Polyhedron);
    if !any {
        if !stream.is_empty() {
            return Err(MeshError::PolyhedronFaces {
                cell: None,
                problem: "given for a mesh without polyhedra".into(),
            });
        }
        return Ok(PolyhedronFaces::default());
    }
    let mut out = PolyhedronFaces { first: vec![0], faces: Csr::new() };
    let mut at = 0usize;
    let mut next = |what: &str, cell: usize| -> Result<u32, MeshError> {
        let v = stream.get(at).copied().ok_or_else(|| MeshError::PolyhedronFaces {
            cell: Some(cell),
            problem: format!("end of the list where {what} is expected"),
        })?;
        at += 1;
        Ok(v)
    };
    for (c, &ty) in d.cell_types.iter().enumerate() {
        if ty == CellType::Polyhedron {
            let corners = cells.get(c);
            let nf = next("the number of faces", c)?;
            if nf < 4 {
                let problem = format!("has {nf} faces; a polyhedron has at least 4");
                return Err(MeshError::PolyhedronFaces { cell: Some(c), problem });
            }
            let mut on_face = vec![false; corners.len()];
            let mut face = Vec::new();
            for f in 0..nf {
                let m = next("a face's vertex count", c)?;
                face.clear();
                for _ in 0..m {
                    let v = next("a face vertex", c)?;
                    let Some(k) = corners.iter().position(|&w| w == v) else {
                        let problem = format!("face {f} has vertex {v}, which is not a corner of the cell");
                        return Err(MeshError::PolyhedronFaces { cell: Some(c), problem });
                    };
                    if face.contains(&v) {
                        let problem = format!("face {f} has vertex {v} twice");
                        return Err(MeshError::PolyhedronFaces { cell: Some(c), problem });
                    }
                    on_face[k] = true;
                    face.push(v);
                }
                if m < 3 {
                    let problem = format!("face {f} has {m} vertices; a face has at least 3");
                    return Err(MeshError::PolyhedronFaces { cell: Some(c), problem });
                }
                out.faces.push(&face);
            }
            if let Some(k) = on_face.iter().position(|&x| !x) {
                let problem = format!("corner {} is on none of its faces", corners[k]);
                return Err(MeshError::PolyhedronFaces { cell: Some(c), problem });
            }
            let first = *out.first.last().unwrap_or(&0) as usize;
            closed(c, (first..out.faces.len()).map(|f| out.faces.get(f)))?;
        }
        out.first.push(out.faces.len() as u32);
    }
    if at != stream.len() {
        let problem = format!("{} values left after the last polyhedron's faces", stream.len() - at);
        return Err(MeshError::PolyhedronFaces { cell: None, problem });
    }
    Ok(out)
}

/// The faces of cell `cell` close it: every directed side a → b of a face is the side b → a of
/// exactly one other face, and no side is run along twice the same way.
pub(super) fn closed<'a>(cell: usize, faces: impl Iterator<Item = &'a [u32]>) -> Result<(), MeshError> {
    let mut sides: Vec<(u32, u32)> = Vec::new();
    for f in faces {
        sides.extend((0..f.len()).map(|k| (f[k], f[(k + 1) % f.len()])));
    }
    sides.sort_unstable();
    if let Some(w) = sides.windows(2).find(|w| w[0] == w[1]) {
        return Err(MeshError::OpenCell { cell, from: w[0].0, to: w[0].1, twice: true });
    }
    match sides.iter().find(|&&(a, b)| sides.binary_search(&(b, a)).is_err()) {
        Some(&(from, to)) => Err(MeshError::OpenCell { cell, from, to, twice: false }),
        None => Ok(()),
    }
}

/// `d.polyhedron_faces` for a mesh's polyhedra, in VTK's layout.
pub(super) fn stream(mesh: &super::Mesh) -> Vec<u32> {
    let mut out = Vec::new();
    for c in 0..mesh.num_cells() {
        if mesh.cell_type(c) == CellType::Polyhedron {
            out.push(mesh.polyhedron_faces(c).len() as u32);
            for f in mesh.polyhedron_faces(c) {
                out.push(f.len() as u32);
                out.extend_from_slice(f);
            }
        }
    }
    out
}
