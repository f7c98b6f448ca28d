//! Mesh files, 2D and 3D, as [`MeshData`]: Gmsh `.msh` in (2.2 and 4.1, ASCII and binary) and
//! out (ASCII 2.2); VTK XML `.vtu` in (ASCII, base64 and appended data, raw or zlib-compressed:
//! what VTK, ParaView and meshio write) and out (appended raw binary by default; zlib-compressed
//! or ASCII when asked).
//!
//! Cells of every [cell type](crate::geometry::CellType) (triangles and quads in 2D; tetrahedra,
//! hexahedra, wedges and pyramids in 3D) are read and written, in VTK's corner order; `.vtu`
//! files also carry polygons and polyhedra (VTK types 7 and 42), which `.msh` files do not. `.msh` files
//! carry the tagged faces (lines in 2D, triangles and quads in 3D) with their patch ids as
//! physical groups; `.vtu` files as cells of one dimension less with a cell array of patch ids
//! (`vtu` says which), beside point and cell fields. The readers return `MeshData`
//! ([`parse_msh_data`], [`VtuData::mesh`]) and build a [`Mesh`](crate::mesh::Mesh) from it
//! ([`parse_msh`], [`VtuData::to_mesh`]) with [`Mesh::from_data`](crate::mesh::Mesh::from_data),
//! which checks what the core handles.
//!
//! OpenFOAM's polyMesh directories are read (ASCII or binary, gzip-compressed or not) as a
//! [`FaceMeshData`](crate::FaceMeshData) with patch names ([`read_polymesh`]), and moved points
//! written back in the format read ([`write_points`], [`write_polymesh`]); `foam` says how.
//!
//! All formats are handled by small parsers of our own; `msh` and `vtu` say why the crates
//! that exist (`mshio`, `vtkio`) were not used. XML tokenising is `quick-xml`'s, inflating
//! `flate2`'s.

mod foam;
mod msh;
mod vtu;

pub use foam::{format_points, polymesh_dir, read_polymesh, write_points, write_polymesh, FoamFormat, FoamMesh};
pub use msh::{parse_msh, parse_msh_data, read_msh, read_msh_data, write_msh22, write_msh22_data, MshMesh, MshParts};
pub use vtu::{
    parse_vtu, read_vtu, write_deformed, write_deformed_as, write_deformed_data, write_deformed_with, write_vtu,
    write_vtu_as, CellField, PointField, VtuData, VtuEncoding,
};

use crate::geometry::CellType;
use crate::mesh::{MeshData, MeshError};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// What can go wrong reading or writing a mesh file.
///
/// `Clone` and `PartialEq` are implemented by hand so that the crate's `Error` keeps them: an
/// `std::io::Error` is cloned as a new error of the same kind and message, and two I/O errors are
/// equal when their paths and kinds are.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum IoError {
    /// The file could not be opened, read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file's path as the caller gave it.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A malformed file. `line` is 1-based, 0 inside binary data; `offset` is the byte offset in
    /// the file where known. The message names the section or element and what was expected.
    #[error("{}{message}", where_(*line, *offset))]
    Parse {
        /// The line of the error (1-based), or 0 inside binary data.
        line: usize,
        /// The byte offset of the error in the file (0-based), where known.
        offset: Option<usize>,
        /// What is wrong: the section or element, and what was expected.
        message: String,
    },
    /// A well-formed file with something this crate does not handle (a format version, an
    /// element type, compressed data, ...).
    #[error("unsupported: {0}")]
    Unsupported(String),
    /// The caller's arguments do not fit together (a field of the wrong length, ...).
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// The file was read but does not make a valid mesh.
    #[error("invalid mesh in file: {0}")]
    Mesh(#[from] MeshError),
}

fn where_(line: usize, offset: Option<usize>) -> String {
    match (line, offset) {
        (0, Some(o)) => format!("byte {o}: "),
        (0, None) => String::new(),
        (l, _) => format!("line {l}: "),
    }
}

impl Clone for IoError {
    fn clone(&self) -> Self {
        match self {
            IoError::Io { path, source } => {
                IoError::Io { path: path.clone(), source: std::io::Error::new(source.kind(), source.to_string()) }
            }
            IoError::Parse { line, offset, message } => {
                IoError::Parse { line: *line, offset: *offset, message: message.clone() }
            }
            IoError::Unsupported(s) => IoError::Unsupported(s.clone()),
            IoError::InvalidArgument(s) => IoError::InvalidArgument(s.clone()),
            IoError::Mesh(e) => IoError::Mesh(e.clone()),
        }
    }
}

impl PartialEq for IoError {
    fn eq(&self, other: &Self) -> bool {
        use IoError::*;
        match (self, other) {
            (Io { path: a, source: x }, Io { path: b, source: y }) => a == b && x.kind() == y.kind(),
            (Parse { line: a, offset: b, message: c }, Parse { line: d, offset: e, message: f }) => {
                a == d && b == e && c == f
            }
            (Unsupported(a), Unsupported(b)) => a == b,
            (InvalidArgument(a), InvalidArgument(b)) => a == b,
            (Mesh(a), Mesh(b)) => a == b,
            _ => false,
        }
    }
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> IoError + '_ {
    move |source| IoError::Io { path: path.to_path_buf(), source }
}

/// Checks that points given as (x, y, z) lie in one plane z = constant, so that dropping z keeps
/// the mesh as it is. A mesh in another plane (the xz plane, a tilted one) would otherwise reach
/// the mesh checks as cells of zero area. The tolerance is relative to the points' extent.
pub(crate) fn check_planar(points: impl Iterator<Item = [f64; 3]> + Clone) -> Result<(), IoError> {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    if hi[2] - lo[2] > 1e-9 * extent {
        return Err(IoError::Unsupported(format!(
            "the mesh is not planar in the xy plane: z ranges from {} to {} (meshmove reads 2D meshes from \
             x and y, with one z for every node)",
            lo[2], hi[2]
        )));
    }
    Ok(())
}

/// Checks that the arrays of `d` fit together, as the writers need: dimension 2 or 3, whole
/// vertices, CSR offsets from 0 with each cell's corner count its type's, vertex indices in range,
/// regions empty or one per cell, one patch per face. `what` names the writer in errors.
pub(crate) fn check_data(d: &MeshData, what: &str) -> Result<(), IoError> {
    let bad = |msg: String| Err(IoError::InvalidArgument(format!("{what}: {msg}")));
    if d.dim != 2 && d.dim != 3 {
        return bad(format!("dimension {}; 2 or 3 expected", d.dim));
    }
    if d.coords.len() % d.dim != 0 {
        return bad(format!("{} coordinates are not whole vertices of {} values", d.coords.len(), d.dim));
    }
    let n = d.num_vertices();
    let lists = [
        ("cell", &d.cell_offsets, &d.cell_vertices, d.num_cells()),
        ("face", &d.face_offsets, &d.face_vertices, d.num_faces()),
    ];
    for (name, offsets, vertices, count) in lists {
        let starts_at_0 = offsets.first().is_none_or(|&o| o == 0);
        if !starts_at_0
            || offsets.len().max(1) != count + 1
            || offsets.last().map_or(0, |&o| o as usize) != vertices.len()
        {
            return bad(format!(
                "{count} {name}s with {} {name} offsets (starting at {:?}) and {} vertices",
                offsets.len(),
                offsets.first(),
                vertices.len()
            ));
        }
        if let Some(w) = offsets.windows(2).position(|w| w[1] < w[0]) {
            return bad(format!("{name} {w}: its offsets decrease"));
        }
        if let Some(&v) = vertices.iter().find(|&&v| v as usize >= n) {
            return bad(format!("a {name} refers to vertex {v}, outside 0..{n}"));
        }
    }
    for (c, t) in d.cell_types.iter().enumerate() {
        let least = if *t == CellType::Polyhedron { 4 } else { 3 };
        if t.is_general() && d.cell(c).len() < least {
            return bad(format!("cell {c} is a {t} of {} corners; it needs at least {least}", d.cell(c).len()));
        }
        if !t.is_general() && d.cell(c).len() != t.num_corners() {
            return bad(format!("cell {c} is a {t} of {} corners; a {t} has {}", d.cell(c).len(), t.num_corners()));
        }
    }
    if let Some(f) = (0..d.num_faces()).find(|&f| if d.dim == 2 { d.face(f).len() != 2 } else { d.face(f).len() < 3 }) {
        let want = if d.dim == 2 { "2" } else { "at least 3" };
        return bad(format!("face {f} has {} vertices; a face in {}D has {want}", d.face(f).len(), d.dim));
    }
    if let Err(problem) = d.polyhedron_spans(d.num_vertices()) {
        return bad(format!("polyhedron faces: {problem}"));
    }
    if !d.regions.is_empty() && d.regions.len() != d.num_cells() {
        return bad(format!("{} regions for {} cells", d.regions.len(), d.num_cells()));
    }
    Ok(())
}

/// 1-based line of byte `offset` in `bytes`.
pub(crate) fn line_of(bytes: &[u8], offset: usize) -> usize {
    1 + bytes[..offset.min(bytes.len())].iter().filter(|&&b| b == b'\n').count()
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_cells;
