//! What can be wrong with a mesh a caller hands us; each variant names the offending item.

use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MeshError {
    #[error("the mesh has no vertices or no cells")]
    Empty,
    #[error("vertex {vertex} has a non-finite coordinate: component {component} is {value}")]
    NonFiniteCoordinate { vertex: usize, component: usize, value: f64 },
    #[error("{values} coordinate values are not a whole number of {dim}D points")]
    CoordinateCount { values: usize, dim: usize },
    #[error("cell offsets: {offsets} given for {cells} cells and {vertices} corner indices (n_cells + 1 ascending offsets from 0 to the corner count are expected)")]
    CellOffsets { cells: usize, offsets: usize, vertices: usize },
    #[error("face offsets: {offsets} given for {faces} faces and {vertices} vertex indices (n_faces + 1 ascending offsets from 0 to the vertex count are expected)")]
    FaceOffsets { faces: usize, offsets: usize, vertices: usize },
    #[error("cell {cell} is a {cell_type} with {count} corners")]
    CornerCount { cell: usize, cell_type: crate::geometry::CellType, count: i64 },
    #[error("cell {cell} is a {cell_type}: this cell type is not supported yet")]
    CellTypeNotSupported { cell: usize, cell_type: crate::geometry::CellType },
    #[error("cell {cell} (a {cell_type}) has a corner with a non-positive Jacobian: it is not convex or it is folded")]
    InvertedCorner { cell: usize, cell_type: crate::geometry::CellType },
    #[error("cell {cell} refers to vertex index {index}, outside {base}..{end} (index base {base})")]
    IndexOutOfRange { cell: usize, index: i64, base: i64, end: i64 },
    #[error("cell {cell} repeats vertex {vertex}")]
    RepeatedVertex { cell: usize, vertex: usize },
    #[error("vertex {vertex} is not used by any cell")]
    UnusedVertex { vertex: usize },
    #[error("cell {cell} has zero area or volume ({measure:e})")]
    DegenerateCell { cell: usize, measure: f64 },
    #[error(
        "cell {cell} is oriented against the rest of the mesh ({negative} cells negatively oriented (clockwise in 2D), \
         {positive} positively): a cell is inverted or the mesh folds over itself"
    )]
    InconsistentOrientation { cell: usize, negative: usize, positive: usize },
    #[error("cells {first} and {second} lie on the same side of their shared face {face:?}: the mesh overlaps itself")]
    Overlap { first: usize, second: usize, face: Vec<u32> },
    #[error("cells {first} and {second} have the same vertices")]
    RepeatedCell { first: usize, second: usize },
    #[error("face {face:?} is shared by {cells} cells; at most two may share a face")]
    NonManifoldFace { face: Vec<u32>, cells: usize },
    #[error("tagged face {edge} refers to vertex index {index}, outside {base}..{end}")]
    TaggedIndexOutOfRange { edge: usize, index: i64, base: i64, end: i64 },
    #[error("tagged face {face} {vertices:?} is not a face of any cell")]
    TaggedFaceNotAFace { face: usize, vertices: Vec<u32> },
    #[error("tagged face {face} {vertices:?} is tagged twice, with patches {first} and {second}")]
    TaggedFaceTwice { face: usize, vertices: Vec<u32>, first: i32, second: i32 },
    #[error("{regions} region ids given for {cells} cells")]
    RegionCount { regions: usize, cells: usize },
    #[error("a mesh of dimension {dim}: meshmove handles 2 and 3")]
    Dimension { dim: usize },
    #[error("cell {cell} is a {cell_type}, which is not a cell of a {dim}D mesh")]
    CellTypeNotInDimension { cell: usize, cell_type: crate::geometry::CellType, dim: usize },
    #[error("the mesh has {vertices} vertices; at most {max} are supported")]
    TooLarge { vertices: usize, max: usize },
}
