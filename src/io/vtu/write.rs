//! The `.vtu` writer: ASCII, shortest round-trip floats.

use super::{CellField, PointField};
use crate::io::{io_err, IoError};
use crate::mesh::quality::signed_measures;
use crate::mesh::Mesh;
use std::fmt::Write as _;
use std::path::Path;

/// Writes `mesh`'s cells at positions `coords` (one per vertex) with the given named fields.
pub fn write_vtu(
    path: &Path,
    mesh: &Mesh,
    coords: &[f64],
    point_data: &[(&str, PointField)],
    cell_data: &[(&str, CellField)],
) -> Result<(), IoError> {
    let (n, m) = (mesh.num_vertices(), mesh.num_cells());
    let dim = mesh.dim();
    if coords.len() != n * dim {
        return Err(IoError::InvalidArgument(format!(
            "write_vtu: {} coordinates for a mesh of {n} vertices",
            coords.len()
        )));
    }
    let mut s = String::with_capacity(80 * n + 40 * m);
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n");
    let _ = writeln!(s, "<Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{m}\">");
    s.push_str("<PointData>\n");
    for (name, f) in point_data {
        let (len, comps) = match f {
            PointField::Scalar(v) => (v.len(), 1),
            PointField::Vector(v) => (v.len() / dim, 3),
        };
        if len != n {
            return Err(IoError::InvalidArgument(format!(
                "write_vtu: point field `{name}` has {len} values for {n} vertices"
            )));
        }
        open_array(&mut s, "Float64", Some(name), comps);
        match f {
            PointField::Scalar(v) => v.iter().for_each(|x| push_f64(&mut s, *x)),
            PointField::Vector(v) => v.chunks_exact(dim).for_each(|p| push_xyz(&mut s, p)),
        }
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
            }
            CellField::I32(v) => {
                open_array(&mut s, "Int32", Some(name), 1);
                v.iter().for_each(|x| {
                    let _ = write!(s, "{x} ");
                });
            }
        }
        s.push_str("\n</DataArray>\n");
    }
    s.push_str("</CellData>\n<Points>\n");
    open_array(&mut s, "Float64", None, 3);
    coords.chunks_exact(dim).for_each(|p| push_xyz(&mut s, p));
    s.push_str("\n</DataArray>\n</Points>\n<Cells>\n");
    s.push_str("<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for c in 0..m {
        for v in mesh.cell(c) {
            let _ = write!(s, "{v} ");
        }
    }
    s.push_str("\n</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    let mut end = 0;
    for c in 0..m {
        end += mesh.cell(c).len();
        let _ = write!(s, "{end} ");
    }
    s.push_str("\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for &t in mesh.cell_types() {
        let _ = write!(s, "{} ", t.vtk_id());
    }
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

fn push_xyz(s: &mut String, p: &[f64]) {
    match p {
        [x, y] => {
            let _ = write!(s, "{x:?} {y:?} 0 ");
        }
        _ => {
            let _ = write!(s, "{:?} {:?} {:?} ", p[0], p[1], p[2]);
        }
    }
}

/// Writes `reference` moved by `displacement`, with point data `displacement` and cell data
/// `region` (Int32), `area_ratio` (deformed over reference signed area), `inverted` (1 where the
/// deformed signed area is not positive) and `min_angle` (degrees, 0 for inverted cells).
pub fn write_deformed(path: &Path, reference: &Mesh, displacement: &[f64]) -> Result<(), IoError> {
    if displacement.len() != reference.coords().len() {
        return Err(IoError::InvalidArgument(format!(
            "write_deformed: {} displacements for a mesh of {} vertices",
            displacement.len(),
            reference.num_vertices()
        )));
    }
    let moved: Vec<f64> = reference.coords().iter().zip(displacement).map(|(p, d)| p + d).collect();
    let a0 = signed_measures(reference, reference.coords());
    let a1 = signed_measures(reference, &moved);
    let ratio: Vec<f64> = a1.iter().zip(&a0).map(|(a, b)| a / b).collect();
    let inverted: Vec<i32> = (0..reference.num_cells())
        .map(|c| i32::from(crate::mesh::quality::is_inverted(reference, &moved, c)))
        .collect();
    let min_angle = crate::mesh::quality::min_angles(reference, &moved);
    write_vtu(
        path,
        reference,
        &moved,
        &[("displacement", PointField::Vector(displacement))],
        &[
            ("region", CellField::I32(reference.regions())),
            ("area_ratio", CellField::F64(&ratio)),
            ("inverted", CellField::I32(&inverted)),
            ("min_angle", CellField::F64(&min_angle)),
        ],
    )
}
