//! Mesh files: Gmsh `.msh` in (2.2 and 4.1, ASCII and binary), `.msh` 2.2 out, VTK XML `.vtu`
//! out and in (ParaView).
//!
//! Both formats are handled by small parsers of our own; `msh.rs` and `vtu.rs` say why the crates
//! that exist (`mshio`, `vtkio`) were not used. XML tokenising is `quick-xml`'s.

mod msh;
mod vtu;

pub use msh::{parse_msh, read_msh, write_msh22, MshMesh};
pub use vtu::{parse_vtu, read_vtu, write_deformed, write_vtu, CellField, PointField, VtuData};

use crate::mesh::MeshError;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// What can go wrong reading or writing a mesh file.
///
/// `Clone` and `PartialEq` are implemented by hand so that [`crate::Error`] keeps them: an
/// `std::io::Error` is cloned as a new error of the same kind and message, and two I/O errors are
/// equal when their paths and kinds are.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum IoError {
    #[error("{}: {source}", path.display())]
    Io { path: PathBuf, source: std::io::Error },
    /// A malformed file. `line` is 1-based, 0 inside binary data; `offset` is the byte offset in
    /// the file where known. The message names the section or element and what was expected.
    #[error("{}{message}", where_(*line, *offset))]
    Parse { line: usize, offset: Option<usize>, message: String },
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

/// 1-based line of byte `offset` in `bytes`.
pub(crate) fn line_of(bytes: &[u8], offset: usize) -> usize {
    1 + bytes[..offset.min(bytes.len())].iter().filter(|&&b| b == b'\n').count()
}

#[cfg(test)]
mod tests;
