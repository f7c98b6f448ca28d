//! VTK XML UnstructuredGrid (`.vtu`) writer and reader, for looking at meshes in ParaView.
//!
//! Our own writer and reader, with `quick-xml` tokenising, rather than the `vtkio` crate: its
//! XML support is in a release candidate (0.7.0-rc2; the stable 0.6 line has old dependencies),
//! its default features pull in three compressors, and its errors do not say which element or
//! attribute was wrong, which the reader's errors must. What we need is small: one piece of
//! triangles with Float64 points and a few named arrays.
//!
//! The writer writes ASCII (`format="ascii"`) with shortest round-trip float formatting, so
//! reading back gives the same bits. The reader takes one `<Piece>` of triangles (cell type 5),
//! with DataArrays in `ascii` or inline `binary` (base64, uncompressed, UInt32 or UInt64 header,
//! either byte order); `appended` data and compressed files are `Unsupported`.

mod read;
mod write;

pub use read::{parse_vtu, read_vtu};
pub use write::{write_deformed, write_vtu};

use super::IoError;
use crate::mesh::{IndexBase, Mesh};

/// A field with one value per vertex.
#[derive(Clone, Copy, Debug)]
pub enum PointField<'a> {
    Scalar(&'a [f64]),
    /// Written with three components, z = 0 (ParaView's vectors are 3D).
    Vector(&'a [f64]),
}

/// A field with one value per cell.
#[derive(Clone, Copy, Debug)]
pub enum CellField<'a> {
    F64(&'a [f64]),
    I32(&'a [i32]),
}

/// What `read_vtu` returns: 2D points (z dropped), triangles, and every named array as `f64`
/// values with its number of components (tuples stored one after another).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VtuData {
    pub points: Vec<[f64; 2]>,
    pub cells: Vec<[u32; 3]>,
    pub point_data: Vec<(String, Vec<f64>, usize)>,
    pub cell_data: Vec<(String, Vec<f64>, usize)>,
}

impl VtuData {
    /// The mesh of these points and cells; regions from a one-component cell array `region` if
    /// present. A `.vtu` has no boundary patches: every boundary edge is on patch 0.
    pub fn to_mesh(&self) -> Result<Mesh, IoError> {
        let regions = match self.cell_data.iter().find(|(n, _, _)| n == "region") {
            Some((_, v, 1)) => Some(
                v.iter()
                    .enumerate()
                    .map(|(c, &r)| {
                        if r.fract() == 0.0 && r.abs() <= i32::MAX as f64 {
                            Ok(r as i32)
                        } else {
                            Err(IoError::InvalidArgument(format!("cell data `region` of cell {c} is {r}, not an i32")))
                        }
                    })
                    .collect::<Result<Vec<i32>, _>>()?,
            ),
            Some((_, _, k)) => {
                return Err(IoError::InvalidArgument(format!("cell data `region` has {k} components; 1 expected")))
            }
            None => None,
        };
        let tagged: [([u32; 2], i32); 0] = [];
        Ok(Mesh::triangles(&self.points, &self.cells, IndexBase::Zero, &tagged, regions.as_deref())?)
    }
}
