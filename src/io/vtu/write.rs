//! The `.vtu` writer: ASCII, shortest round-trip floats.

use super::{CellField, PointField};
use crate::geometry::CellPoints;
use crate::io::{check_data, io_err, IoError};
use crate::mesh::{Mesh, MeshData};
use std::fmt::Write as _;
use std::path::Path;

/// Writes the points, cells and tagged faces of `mesh` with the given named fields. 2D points are
/// written with z = 0. The faces follow the cells as VTK cells of one dimension less (lines in
/// 2D, triangles and quads in 3D) with an Int32 cell array `patch` (the faces' patch ids, the
/// cells' regions), which [`read_vtu`](super::read_vtu) reads back as the patches; the caller's
/// cell fields hold the cells' values, and the faces' are written as NaN (`F64`) or 0 (`I32`).
/// Regions are read back from a cell field `region` where the caller passes one.
pub fn write_vtu(
    path: &Path,
    mesh: &MeshData,
    point_data: &[(&str, PointField)],
    cell_data: &[(&str, CellField)],
) -> Result<(), IoError> {
    check_data(mesh, "write_vtu")?;
    let (n, m) = (mesh.num_vertices(), mesh.num_cells());
    let nf = mesh.num_faces();
    let face_vtk = |f: usize| match (mesh.dim, mesh.face(f).len()) {
        (2, _) => 3u8,
        (_, 3) => 5,
        _ => 9,
    };
    let mut s = String::with_capacity(80 * n + 40 * m);
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n");
    let _ = writeln!(s, "<Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{}\">", m + nf);
    s.push_str("<PointData>\n");
    for (name, f) in point_data {
        let (values, comps) = match *f {
            PointField::Scalar(v) => (v, 1),
            PointField::Vector(v, k) => (v, k),
        };
        if comps == 0 || values.len() != n * comps {
            return Err(IoError::InvalidArgument(format!(
                "write_vtu: point field `{name}` has {} values of {comps} components for {n} vertices",
                values.len()
            )));
        }
        open_array(&mut s, "Float64", Some(name), comps.max(3 * usize::from(comps == 2)));
        push_tuples(&mut s, values, comps);
        s.push_str("\n</DataArray>\n");
    }
    s.push_str("</PointData>\n<CellData>\n");
    for (name, f) in cell_data {
        let len = match f {
            CellField::F64(v) => v.len(),
            CellField::I32(v) => v.len(),
        };
        if len != m {
            return Err(IoError::InvalidArgument(format!(
                "write_vtu: cell field `{name}` has {len} values for {m} cells"
            )));
        }
        match f {
            CellField::F64(v) => {
                open_array(&mut s, "Float64", Some(name), 1);
                v.iter().for_each(|x| push_f64(&mut s, *x));
                (0..nf).for_each(|_| s.push_str("NaN "));
            }
            CellField::I32(v) => {
                open_array(&mut s, "Int32", Some(name), 1);
                push_ints(&mut s, v);
                (0..nf).for_each(|_| s.push_str("0 "));
            }
        }
        s.push_str("\n</DataArray>\n");
    }
    if nf > 0 {
        open_array(&mut s, "Int32", Some("patch"), 1);
        push_ints(&mut s, &(0..m).map(|c| mesh.regions.get(c).copied().unwrap_or(0)).collect::<Vec<_>>());
        push_ints(&mut s, &mesh.face_patch);
        s.push_str("\n</DataArray>\n");
    }
    s.push_str("</CellData>\n<Points>\n");
    open_array(&mut s, "Float64", None, 3);
    push_tuples(&mut s, &mesh.coords, mesh.dim);
    s.push_str("\n</DataArray>\n</Points>\n<Cells>\n");
    s.push_str("<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    push_ints(&mut s, &mesh.cell_vertices);
    push_ints(&mut s, &mesh.face_vertices);
    s.push_str("\n</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    push_ints(&mut s, mesh.cell_offsets.get(1..).unwrap_or_default());
    let end = mesh.cell_vertices.len();
    push_ints(
        &mut s,
        &mesh.face_offsets.get(1..).unwrap_or_default().iter().map(|&o| end + o as usize).collect::<Vec<_>>(),
    );
    s.push_str("\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    push_ints(&mut s, &mesh.cell_types.iter().map(|t| t.vtk_id()).collect::<Vec<_>>());
    push_ints(&mut s, &(0..nf).map(face_vtk).collect::<Vec<_>>());
    s.push_str("\n</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    std::fs::write(path, s).map_err(io_err(path))
}

fn open_array(s: &mut String, ty: &str, name: Option<&str>, comps: usize) {
    let _ = write!(s, "<DataArray type=\"{ty}\"");
    if let Some(name) = name {
        let _ = write!(s, " Name=\"{}\"", quick_xml::escape::escape(name));
    }
    let _ = writeln!(s, " NumberOfComponents=\"{comps}\" format=\"ascii\">");
}

/// Shortest representation that parses back to the same `f64` (`{:?}` is Rust's round-trip form).
fn push_f64(s: &mut String, x: f64) {
    let _ = write!(s, "{x:?} ");
}

fn push_ints<T: std::fmt::Display>(s: &mut String, v: &[T]) {
    v.iter().for_each(|x| {
        let _ = write!(s, "{x} ");
    });
}

/// Tuples of `comps` values; pairs are written as (x, y, 0).
fn push_tuples(s: &mut String, values: &[f64], comps: usize) {
    for t in values.chunks_exact(comps) {
        t.iter().for_each(|x| push_f64(s, *x));
        if comps == 2 {
            s.push_str("0 ");
        }
    }
}

/// Writes `reference` moved by `displacement` (`dim` values per vertex), with point data
/// `displacement` and cell data `region` (Int32), `area_ratio` in 2D or `volume_ratio` in 3D
/// (deformed over reference signed measure), `inverted` (1 where a corner Jacobian of the
/// deformed cell is not positive) and `min_angle` (degrees: the smallest angle between two edges
/// at a corner; 0 for inverted cells).
pub fn write_deformed(path: &Path, reference: &Mesh, displacement: &[f64]) -> Result<(), IoError> {
    write_deformed_data(path, &reference.to_data(), displacement)
}

/// [`write_deformed`] of a mesh given as plain arrays (any cell types, 2D or 3D).
pub fn write_deformed_data(path: &Path, data: &MeshData, displacement: &[f64]) -> Result<(), IoError> {
    check_data(data, "write_deformed")?;
    let (dim, n) = (data.dim, data.num_vertices());
    if displacement.len() != dim * n {
        return Err(IoError::InvalidArgument(format!(
            "write_deformed: {} displacement values for a mesh of {n} vertices in {dim}D ({} expected)",
            displacement.len(),
            dim * n
        )));
    }
    let moved_coords: Vec<f64> = data.coords.iter().zip(displacement).map(|(x, d)| x + d).collect();
    let moved = MeshData { coords: moved_coords, ..data.clone() };
    let m = data.num_cells();
    let (mut ratio, mut inverted, mut min_angle) =
        (Vec::with_capacity(m), Vec::with_capacity(m), Vec::with_capacity(m));
    for c in 0..m {
        let (p0, p1) = (cell_points(data, c), cell_points(&moved, c));
        let a1 = p1.signed_measure();
        ratio.push(a1 / p0.signed_measure());
        let bad = p1.inverted_with_measure(a1);
        inverted.push(i32::from(bad));
        min_angle.push(if bad { 0.0 } else { p1.min_angle_deg() });
    }
    let regions = if data.regions.is_empty() { vec![0; m] } else { data.regions.clone() };
    write_vtu(
        path,
        &moved,
        &[("displacement", PointField::Vector(displacement, dim))],
        &[
            ("region", CellField::I32(&regions)),
            (if dim == 2 { "area_ratio" } else { "volume_ratio" }, CellField::F64(&ratio)),
            ("inverted", CellField::I32(&inverted)),
            ("min_angle", CellField::F64(&min_angle)),
        ],
    )
}

/// Signed area (2D) or volume (3D) of cell `c` (the geometry module's).
#[cfg(test)]
pub(crate) fn signed_measure(d: &MeshData, c: usize) -> f64 {
    cell_points(d, c).signed_measure()
}

fn cell_points(d: &MeshData, c: usize) -> CellPoints {
    CellPoints::gather(d.cell_types[c], d.cell(c), &d.coords, d.dim)
}
