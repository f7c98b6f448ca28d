//! VTK XML UnstructuredGrid (`.vtu`) writer and reader, for looking at meshes in ParaView and
//! reading what VTK, ParaView and meshio write.
//!
//! Our own writer and reader, with `quick-xml` tokenising and `flate2` inflating, rather than the
//! `vtkio` crate: its XML support is in a release candidate (0.7.0-rc2; the stable 0.6 line has
//! old dependencies), its default features pull in three compressors, and its errors do not say
//! which element or attribute was wrong, which the reader's errors must. What we need is small:
//! one piece of cells with Float64 points and a few named arrays.
//!
//! The writer writes ASCII (`format="ascii"`) with shortest round-trip float formatting, so
//! reading back gives the same bits; cells of any [`CellType`](crate::geometry::CellType) (the
//! `connectivity`, `offsets` and `types` arrays), 2D points with z = 0.
//!
//! The reader takes one `<Piece>` of cells of the types of
//! [`CellType`](crate::geometry::CellType) (VTK ids 5, 9, 10, 12, 13, 14, mixed; any other type is
//! `Unsupported`), with DataArrays in `ascii`, inline `binary` (base64) or `appended` format
//! (`<AppendedData>` with `raw` or `base64` encoding, located by each array's `offset`), of any
//! of VTK's integer and float types, uncompressed or compressed by `vtkZLibDataCompressor`
//! (another compressor is `Unsupported`), with a UInt32 or UInt64 header, in either byte order.
//! `<InformationKey>` elements inside a DataArray are skipped. The mesh is 3D if any cell is a
//! solid, else 2D: then z must be one value for every point (else `Unsupported`: the mesh is not
//! planar) and is dropped. A one-component cell array named `region` gives the cells' regions.
//! A `.vtu` has no tagged faces.

mod read;
mod write;

pub use read::{parse_vtu, read_vtu};
#[cfg(test)]
#[cfg(test)]
pub(crate) use write::signed_measure;
pub use write::{write_deformed, write_deformed_data, write_vtu};

use super::IoError;
use crate::mesh::{Mesh, MeshData};

/// A field with one value per vertex.
#[derive(Clone, Copy, Debug)]
pub enum PointField<'a> {
    /// One value per vertex, written as a one-component `Float64` array.
    Scalar(&'a [f64]),
    /// The values and the number of components per vertex (tuples one after another). Two
    /// components are written as three, z = 0 (ParaView's vectors are 3D).
    Vector(&'a [f64], usize),
}

/// A field with one value per cell.
#[derive(Clone, Copy, Debug)]
pub enum CellField<'a> {
    /// One floating-point value per cell, written as a `Float64` array.
    F64(&'a [f64]),
    /// One integer per cell (regions, flags), written as an `Int32` array.
    I32(&'a [i32]),
}

/// What `read_vtu` returns: the mesh (points, cells, regions from the cell array `region`; no
/// tagged faces) and every named array as `f64` values with its number of components (tuples
/// stored one after another).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VtuData {
    /// The points (z dropped for a 2D mesh), the cells and their regions; not validated.
    pub mesh: MeshData,
    /// The `<PointData>` arrays in file order: (name, values, components per vertex).
    pub point_data: Vec<(String, Vec<f64>, usize)>,
    /// The `<CellData>` arrays in file order, `region` included: (name, values, components per cell).
    pub cell_data: Vec<(String, Vec<f64>, usize)>,
}

impl VtuData {
    /// The validated mesh of these points, cells and regions. A `.vtu` has no boundary patches:
    /// every boundary face is on patch 0.
    pub fn to_mesh(&self) -> Result<Mesh, IoError> {
        Ok(Mesh::from_data(&self.mesh)?)
    }
}
