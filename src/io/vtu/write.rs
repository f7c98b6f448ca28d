//! The `.vtu` writer: ASCII, shortest round-trip floats.

use super::{CellField, PointField};
use crate::io::{io_err, IoError};
use crate::mesh::quality::{min_angle_deg, signed_areas};
use crate::mesh::Mesh;
use glam::DVec2;
use std::fmt::Write as _;
use std::path::Path;

/// Writes `mesh`'s cells at positions `coords` (one per vertex) with the given named fields.
pub fn write_vtu(
    path: &Path,
    mesh: &Mesh,
    coords: &[DVec2],
    point_data: &[(&str, PointField)],
    cell_data: &[(&str, CellField)],
) -> Result<(), IoError> {
    let (n, m) = (mesh.num_vertices(), mesh.num_cells());
    if coords.len() != n {
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
            PointField::Vector(v) => (v.len(), 3),
        };
        if len != n {
            return Err(IoError::InvalidArgument(format!(
                "write_vtu: point field `{name}` has {len} values for {n} vertices"
            )));
        }
        open_array(&mut s, "Float64", Some(name), comps);
        match f {
            PointField::Scalar(v) => v.iter().for_each(|x| push_f64(&mut s, *x)),
            PointField::Vector(v) => v.iter().for_each(|p| push_xyz(&mut s, *p)),
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
    coords.iter().for_each(|p| push_xyz(&mut s, *p));
    s.push_str("\n</DataArray>\n</Points>\n<Cells>\n");
    s.push_str("<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for c in mesh.cells() {
        let _ = write!(s, "{} {} {} ", c[0], c[1], c[2]);
    }
    s.push_str("\n</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for i in 1..=m {
        let _ = write!(s, "{} ", 3 * i);
    }
    s.push_str("\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    s.push_str(&"5 ".repeat(m));
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

fn push_xyz(s: &mut String, p: DVec2) {
    let _ = write!(s, "{:?} {:?} 0 ", p.x, p.y);
}

/// Writes `reference` moved by `displacement`, with point data `displacement` and cell data
/// `region` (Int32), `area_ratio` (deformed over reference signed area), `inverted` (1 where the
/// deformed signed area is not positive) and `min_angle` (degrees, 0 for inverted cells).
pub fn write_deformed(path: &Path, reference: &Mesh, displacement: &[DVec2]) -> Result<(), IoError> {
    if displacement.len() != reference.num_vertices() {
        return Err(IoError::InvalidArgument(format!(
            "write_deformed: {} displacements for a mesh of {} vertices",
            displacement.len(),
            reference.num_vertices()
        )));
    }
    let moved: Vec<DVec2> = reference.coords().iter().zip(displacement).map(|(p, d)| *p + *d).collect();
    let a0 = signed_areas(reference, reference.coords());
    let a1 = signed_areas(reference, &moved);
    let ratio: Vec<f64> = a1.iter().zip(&a0).map(|(a, b)| a / b).collect();
    let inverted: Vec<i32> = a1.iter().map(|&a| i32::from(a <= 0.0)).collect();
    let min_angle: Vec<f64> = reference
        .cells()
        .iter()
        .map(|c| min_angle_deg(moved[c[0] as usize], moved[c[1] as usize], moved[c[2] as usize]))
        .collect();
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
