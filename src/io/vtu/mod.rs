//! VTK XML UnstructuredGrid (`.vtu`) writer and reader, for looking at meshes in ParaView and
//! reading what VTK, ParaView and meshio write.
//!
//! Our own writer and reader, with `quick-xml` tokenising and `flate2` inflating, rather than the
//! `vtkio` crate: its XML support is in a release candidate (0.7.0-rc2; the stable 0.6 line has
//! old dependencies), its default features pull in three compressors, and its errors do not say
//! which element or attribute was wrong, which the reader's errors must. What we need is small:
//! one piece of cells with Float64 points and a few named arrays.
//!
//! The writer writes appended raw binary by default (`<AppendedData encoding="raw">`, UInt64
//! headers, little-endian), zlib-compressed appended binary or ASCII (shortest round-trip floats)
//! when asked ([`VtuEncoding`]); each reads back to the same bits. Cells of any
//! [`CellType`](crate::geometry::CellType) (the `connectivity`, `offsets` and `types` arrays), 2D
//! points with z = 0.
//!
//! The reader takes one `<Piece>` of cells of the types of
//! [`CellType`](crate::geometry::CellType) (VTK ids 5, 9, 10, 12, 13, 14, mixed; any other type is
//! `Unsupported`), with DataArrays in `ascii`, inline `binary` (base64) or `appended` format
//! (`<AppendedData>` with `raw` or `base64` encoding, located by each array's `offset`), of any
//! of VTK's integer and float types, uncompressed or compressed by `vtkZLibDataCompressor`
//! (another compressor is `Unsupported`), with a UInt32 or UInt64 header, in either byte order.
//! `<InformationKey>` elements inside a DataArray are skipped. The mesh is 3D if any cell is a
//! solid, else 2D: then z must be one value for every point (else `Unsupported`: the mesh is not
//! planar) and is dropped.
//!
//! Patches: the file's cells of dimension D − 1 (lines in 2D; triangles and quads in 3D) are the
//! mesh's tagged faces, with their patch ids from a one-component cell array `gmsh:physical`
//! (meshio's export of a Gmsh mesh), `patch` (ours) or `CellEntityIds` (VTK, ParaView), the first
//! found; vertices, and edges of a 3D mesh, are skipped. The cells' regions come from a cell array
//! `region`, else from that same id array. Patch names come from `<FieldData>`: an integer array
//! named after the patch whose values are its id and, optionally, the dimension D − 1 (meshio's
//! form of Gmsh's physical names). The writer writes the faces back the same way (array `patch`,
//! names as field data).

mod read;
mod write;

pub use read::{parse_vtu, read_vtu};
#[cfg(test)]
#[cfg(test)]
pub(crate) use write::signed_measure;
pub use write::{
    write_deformed, write_deformed_as, write_deformed_data, write_deformed_with, write_vtu, write_vtu_as, VtuEncoding,
};

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

/// What `read_vtu` returns: the mesh (points, cells, regions, patch faces) and every named array as `f64` values with its number of components (tuples
/// stored one after another).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VtuData {
    /// The points (z dropped for a 2D mesh), the cells and their regions; not validated.
    pub mesh: MeshData,
    /// The `<PointData>` arrays in file order: (name, values, components per vertex).
    pub point_data: Vec<(String, Vec<f64>, usize)>,
    /// The `<CellData>` arrays in file order, `region` and the patch ids included, on the mesh's
    /// cells only (the faces' values dropped): (name, values, components per cell).
    pub cell_data: Vec<(String, Vec<f64>, usize)>,
    /// Patch names from the `<FieldData>`: (patch id, name).
    pub patch_names: Vec<(i32, String)>,
}

impl VtuData {
    /// The validated mesh of these points, cells, regions and patch faces (boundary faces that
    /// are not among the file's faces are on patch 0).
    pub fn to_mesh(&self) -> Result<Mesh, IoError> {
        Ok(Mesh::from_data(&self.mesh)?)
    }
}
