//! `--output OUT.pvtu` under mpirun: ParaView's parallel unstructured grid. Every rank writes its
//! own piece `OUT_<rank>.vtu` — the cells it owns with their vertices and tagged faces, moved,
//! with the serial file's fields and each vertex's global id (`global_id`: its index in the mesh
//! as read) — and rank 0 the index `OUT.pvtu`, which names the pieces and their arrays.

use crate::distributed::parts::{copy_cell, face_cells, polyhedron_spans, Part};
use meshmove::io::{write_deformed_with, PointField, VtuEncoding};
use meshmove::MeshData;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// True when `path` names a `.pvtu` file.
pub fn is_pvtu(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("pvtu"))
}

/// Where rank `rank` writes its piece of `output` (`OUT.pvtu`): `OUT_<rank>.vtu` beside it.
pub fn piece_path(output: &Path, rank: usize) -> PathBuf {
    let stem = output.file_stem().and_then(|s| s.to_str()).unwrap_or("out");
    output.with_file_name(format!("{stem}_{rank}.vtu"))
}

/// The piece of `part` (this rank's part as it was sent) moved to `coords` (its local vertices'
/// positions): the owned cells, their vertices (in global order) and the tagged faces whose
/// first cell in the mesh is owned, so that every cell and face is in one piece.
fn piece(part: &Part, coords: &[f64]) -> Result<(MeshData, Vec<f64>, Vec<f64>), String> {
    let d = &part.data;
    let dim = d.dim;
    let owned = |c: usize| !part.ghost[c];
    let mut local_of = vec![u32::MAX; d.num_vertices()];
    (0..d.num_cells()).filter(|&c| owned(c)).for_each(|c| d.cell(c).iter().for_each(|&v| local_of[v as usize] = 0));
    let mut out = MeshData::new(dim);
    let (mut moved, mut gids) = (Vec::new(), Vec::new());
    for (v, l) in local_of.iter_mut().enumerate() {
        if *l == 0 {
            *l = out.push_vertex(d.point(v));
            moved.extend_from_slice(&coords[v * dim..(v + 1) * dim]);
            gids.push(part.gids[v] as f64);
        }
    }
    let local = |vs: &[u32]| -> Vec<u32> { vs.iter().map(|&v| local_of[v as usize]).collect() };
    let spans = polyhedron_spans(d)?;
    for c in (0..d.num_cells()).filter(|&c| owned(c)) {
        copy_cell(&mut out, d, c, spans[c].as_ref(), &local);
    }
    for (f, cells) in face_cells(d).iter().enumerate() {
        if cells.first().is_some_and(|&c| owned(c as usize)) {
            out.push_face(&local(d.face(f)), d.face_patch[f]);
        }
    }
    let disp = moved.iter().zip(&out.coords).map(|(x, x0)| x - x0).collect();
    Ok((out, disp, gids))
}

/// Writes this rank's piece of `output` (`part` moved to `coords`); returns whether it has
/// tagged faces (then its cells have the array `patch`).
pub fn write_piece(
    output: &Path,
    rank: usize,
    part: &Part,
    coords: &[f64],
    encoding: VtuEncoding,
) -> Result<bool, String> {
    let path = piece_path(output, rank);
    let (data, disp, gids) = piece(part, coords)?;
    write_deformed_with(&path, &data, &disp, &[("global_id", PointField::Scalar(&gids))], encoding)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(data.num_faces() > 0)
}

/// Writes the index `output` of `ranks` pieces of a `dim`-dimensional mesh: their point and cell
/// arrays as each piece holds them (`patch` when every piece has tagged faces) and their files.
pub fn write_index(output: &Path, ranks: usize, dim: usize, patch: bool) -> Result<(), String> {
    let ratio = if dim == 2 { "area_ratio" } else { "volume_ratio" };
    let mut x = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">\n<PUnstructuredGrid GhostLevel=\"0\">\n<PPointData>\n\
         <PDataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\"/>\n\
         <PDataArray type=\"Float64\" Name=\"global_id\" NumberOfComponents=\"1\"/>\n</PPointData>\n<PCellData>\n\
         <PDataArray type=\"Int32\" Name=\"region\" NumberOfComponents=\"1\"/>\n",
    );
    let _ = writeln!(x, "<PDataArray type=\"Float64\" Name=\"{ratio}\" NumberOfComponents=\"1\"/>");
    x.push_str("<PDataArray type=\"Int32\" Name=\"inverted\" NumberOfComponents=\"1\"/>\n");
    x.push_str("<PDataArray type=\"Float64\" Name=\"min_angle\" NumberOfComponents=\"1\"/>\n");
    if patch {
        x.push_str("<PDataArray type=\"Int32\" Name=\"patch\" NumberOfComponents=\"1\"/>\n");
    }
    x.push_str("</PCellData>\n<PPoints>\n<PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n</PPoints>\n");
    for r in 0..ranks {
        let piece = piece_path(output, r);
        let name = piece.file_name().and_then(|n| n.to_str()).unwrap_or_default();
        let _ = writeln!(x, "<Piece Source=\"{name}\"/>");
    }
    x.push_str("</PUnstructuredGrid>\n</VTKFile>\n");
    std::fs::write(output, x).map_err(|e| format!("{}: {e}", output.display()))
}
