//! What can be wrong with a mesh a caller hands us; each variant names the offending item.

use thiserror::Error;

/// Why [`Mesh::from_data`](super::Mesh::from_data) or [`Mesh::triangles`](super::Mesh::triangles)
/// refuses a mesh.
///
/// Cells, vertices and tagged faces are numbered from 0 in the order given, whatever the caller's
/// [`IndexBase`](super::IndexBase); only the `index`, `base` and `end` fields of the out-of-range
/// variants are in the caller's numbering.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MeshError {
    /// The mesh has no vertices or no cells.
    #[error("the mesh has no vertices or no cells")]
    Empty,
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate: component {component} is {value}")]
    NonFiniteCoordinate {
        /// The offending vertex (0-based).
        vertex: usize,
        /// The offending component: 0 for x, 1 for y, 2 for z.
        component: usize,
        /// The value found: NaN or an infinity.
        value: f64,
    },
    /// The number of coordinate values is not a multiple of the dimension.
    #[error("{values} coordinate values are not a whole number of {dim}D points")]
    CoordinateCount {
        /// The number of coordinate values given.
        values: usize,
        /// The mesh dimension.
        dim: usize,
    },
    /// The cell offsets are not `n_cells + 1` values ascending from 0 to the number of corner indices.
    #[error("cell offsets: {offsets} given for {cells} cells and {vertices} corner indices (n_cells + 1 ascending offsets from 0 to the corner count are expected)")]
    CellOffsets {
        /// The number of cells (the number of cell types given).
        cells: usize,
        /// The number of offsets given.
        offsets: usize,
        /// The number of corner indices given.
        vertices: usize,
    },
    /// The tagged-face offsets are not `n_faces + 1` values ascending from 0 to the number of face
    /// vertex indices.
    #[error("face offsets: {offsets} given for {faces} faces and {vertices} vertex indices (n_faces + 1 ascending offsets from 0 to the vertex count are expected)")]
    FaceOffsets {
        /// The number of tagged faces (the number of patch ids given).
        faces: usize,
        /// The number of offsets given.
        offsets: usize,
        /// The number of face vertex indices given.
        vertices: usize,
    },
    /// A cell's number of corners does not match its type.
    #[error("cell {cell} is a {cell_type} with {count} corners")]
    CornerCount {
        /// The offending cell (0-based).
        cell: usize,
        /// The cell's type.
        cell_type: crate::geometry::CellType,
        /// The number of corners given: the difference of the cell's two offsets (negative when
        /// they descend).
        count: i64,
    },
    /// Once the mesh is oriented, a corner of a cell has a non-positive Jacobian: the cell is not
    /// convex or it is folded.
    #[error("cell {cell} (a {cell_type}) has a corner with a non-positive Jacobian: it is not convex or it is folded")]
    InvertedCorner {
        /// The offending cell (0-based).
        cell: usize,
        /// The cell's type.
        cell_type: crate::geometry::CellType,
    },
    /// A cell refers to a vertex index outside the vertex range.
    #[error("cell {cell} refers to vertex index {index}, outside {base}..{end} (index base {base})")]
    IndexOutOfRange {
        /// The offending cell (0-based).
        cell: usize,
        /// The index as the caller gave it.
        index: i64,
        /// The caller's index base: 0 or 1 (always 0 for [`MeshData`](super::MeshData)).
        base: i64,
        /// One past the last valid index: the number of vertices plus `base`.
        end: i64,
    },
    /// A cell lists the same vertex twice.
    #[error("cell {cell} repeats vertex {vertex}")]
    RepeatedVertex {
        /// The offending cell (0-based).
        cell: usize,
        /// The repeated vertex (0-based).
        vertex: usize,
    },
    /// A vertex belongs to no cell, so it has no equation to move it.
    #[error("vertex {vertex} is not used by any cell")]
    UnusedVertex {
        /// The first unused vertex (0-based).
        vertex: usize,
    },
    /// A cell has zero or non-finite area or volume (relative to its longest edge, so the test does
    /// not depend on the mesh's scale).
    #[error("cell {cell} has zero area or volume ({measure:e})")]
    DegenerateCell {
        /// The first degenerate cell (0-based).
        cell: usize,
        /// The cell's signed area (2D) or volume (3D), in the units of the coordinates.
        measure: f64,
    },
    /// A cell's area or volume is outside the range of `f64` (an overflow or underflow of the
    /// products of its coordinates), though its coordinates are finite.
    #[error(
        "cell {cell}'s area or volume overflows or underflows double precision (longest edge {longest_edge:e}, \
         coordinates up to {largest:e}): express the mesh in units where cells are between about 1e-90 and 1e90 long"
    )]
    MeasureOutOfRange {
        /// The cell (0-based).
        cell: usize,
        /// Its longest edge (infinite when its square overflows).
        longest_edge: f64,
        /// Its largest coordinate in absolute value.
        largest: f64,
    },
    /// The system refused the memory for a table of the mesh (its topology).
    #[error("out of memory: {what} need {bytes} bytes, which the system refused")]
    OutOfMemory {
        /// The table.
        what: &'static str,
        /// Its size.
        bytes: u64,
    },
    /// Cells of both orientations are present: a cell is inverted or the mesh folds over itself.
    #[error(
        "cell {cell} is oriented against the rest of the mesh ({negative} cells negatively oriented (clockwise in 2D), \
         {positive} positively): a cell is inverted or the mesh folds over itself"
    )]
    InconsistentOrientation {
        /// The first cell of the smaller orientation group, or of the negative one on a tie (0-based).
        cell: usize,
        /// The number of negatively oriented cells (clockwise in 2D).
        negative: usize,
        /// The number of positively oriented cells (counter-clockwise in 2D).
        positive: usize,
    },
    /// Two cells lie on the same side of their shared face: the mesh overlaps itself.
    #[error("cells {first} and {second} lie on the same side of their shared face {face:?}: the mesh overlaps itself")]
    Overlap {
        /// One of the two cells (0-based).
        first: usize,
        /// The other cell (0-based).
        second: usize,
        /// The shared face's vertices (0-based, sorted).
        face: Vec<u32>,
    },
    /// Two cells have the same set of vertices.
    #[error("cells {first} and {second} have the same vertices")]
    RepeatedCell {
        /// One of the two cells (0-based).
        first: usize,
        /// The other cell (0-based).
        second: usize,
    },
    /// More than two cells share a face.
    #[error("face {face:?} is shared by {cells} cells; at most two may share a face")]
    NonManifoldFace {
        /// The face's vertices (0-based, sorted).
        face: Vec<u32>,
        /// The number of cells sharing it.
        cells: usize,
    },
    /// A tagged face refers to a vertex index outside the vertex range.
    #[error("tagged face {edge} refers to vertex index {index}, outside {base}..{end}")]
    TaggedIndexOutOfRange {
        /// The offending tagged face (an edge in 2D), by its position in the caller's list (0-based).
        edge: usize,
        /// The index as the caller gave it.
        index: i64,
        /// The caller's index base: 0 or 1 (always 0 for [`MeshData`](super::MeshData)).
        base: i64,
        /// One past the last valid index: the number of vertices plus `base`.
        end: i64,
    },
    /// A tagged face is not a face of any cell (or it has fewer than 2 or more than 4 vertices).
    #[error("tagged face {face} {vertices:?} is not a face of any cell")]
    TaggedFaceNotAFace {
        /// The offending tagged face, by its position in the caller's list (0-based).
        face: usize,
        /// Its vertices (0-based, in the order given).
        vertices: Vec<u32>,
    },
    /// The same face is tagged twice, with different patch ids.
    #[error("tagged face {face} {vertices:?} is tagged twice, with patches {first} and {second}")]
    TaggedFaceTwice {
        /// The second tagging of the face, by its position in the caller's list (0-based).
        face: usize,
        /// Its vertices (0-based, in the order given).
        vertices: Vec<u32>,
        /// The patch id of the earlier tagging.
        first: i32,
        /// The patch id of the later tagging.
        second: i32,
    },
    /// The number of region ids is neither 0 nor the number of cells.
    #[error("{regions} region ids given for {cells} cells")]
    RegionCount {
        /// The number of region ids given.
        regions: usize,
        /// The number of cells.
        cells: usize,
    },
    /// The mesh dimension is neither 2 nor 3.
    #[error("a mesh of dimension {dim}: meshmove handles 2 and 3")]
    Dimension {
        /// The dimension given.
        dim: usize,
    },
    /// A cell's type is not of the mesh's dimension (a triangle in a 3D mesh, say).
    #[error("cell {cell} is a {cell_type}, which is not a cell of a {dim}D mesh")]
    CellTypeNotInDimension {
        /// The offending cell (0-based).
        cell: usize,
        /// The cell's type.
        cell_type: crate::geometry::CellType,
        /// The mesh dimension.
        dim: usize,
    },
    /// Uniform refinement of a mesh whose cells it does not split (it splits 2D cells).
    #[error("uniform refinement splits the cells of 2D meshes; this mesh is {dim}D")]
    RefinementDimension {
        /// The mesh dimension.
        dim: usize,
    },
    /// The faces of the polyhedra (`MeshData::polyhedron_faces`) do not describe them: the
    /// list is too short or too long, a face has fewer than 3 vertices or a vertex that is not
    /// a corner of its cell, or a corner is on no face.
    #[error("the faces of the polyhedra{}: {problem}", cell_note(.cell))]
    PolyhedronFaces {
        /// The offending cell (0-based), when the problem is one cell's.
        cell: Option<usize>,
        /// What is wrong.
        problem: String,
    },
    /// A cell's faces do not close it: a side of a face is not run along the other way by
    /// another face (the cell is open or its faces are not oriented alike), or it is run along
    /// twice the same way.
    #[error("the faces of cell {cell} do not close it: its side {from} → {to} {}", if *.twice { "is run along twice in the same direction" } else { "has no face running back along it" })]
    OpenCell {
        /// The offending cell (0-based).
        cell: usize,
        /// The side's first vertex (0-based).
        from: u32,
        /// The side's second vertex (0-based).
        to: u32,
        /// True when the side is run along twice the same way (else it is not run back).
        twice: bool,
    },
    /// A face of a face-based mesh has too few vertices (fewer than 3 in 3D, not 2 in 2D).
    #[error("face {face} has {count} vertices; a face of a {dim}D mesh has {}", if *.dim == 2 { "2" } else { "at least 3" })]
    FaceSize {
        /// The offending face (0-based).
        face: usize,
        /// Its number of vertices.
        count: usize,
        /// The mesh dimension.
        dim: usize,
    },
    /// A face of a face-based mesh names a vertex or a cell outside the range given.
    #[error("face {face}'s {what} is {index}, outside 0..{end}")]
    FaceIndexOutOfRange {
        /// The offending face (0-based).
        face: usize,
        /// What is out of range: "owner", "neighbour" or "vertex".
        what: &'static str,
        /// The index found (0-based).
        index: i64,
        /// One past the last valid index.
        end: i64,
    },
    /// A boundary face of a face-based mesh (one without a neighbour) has no patch.
    #[error("face {face} is a boundary face (no neighbour) without a patch (patch id {patch})")]
    BoundaryFaceWithoutPatch {
        /// The offending face (0-based).
        face: usize,
        /// The patch id found (negative).
        patch: i32,
    },
    /// The arrays of a face-based mesh do not agree in length.
    #[error("face-based mesh: {problem}")]
    FaceArrays {
        /// Which arrays disagree, and how.
        problem: String,
    },
    /// A cell of a face-based mesh has no face, or faces of one side only in 2D that do not
    /// make one loop.
    #[error("cell {cell} of the face-based mesh: {problem}")]
    FaceBasedCell {
        /// The offending cell (0-based).
        cell: usize,
        /// What is wrong.
        problem: String,
    },
    /// Uniform refinement of a mesh with cells it does not split (polygons).
    #[error("uniform refinement splits triangles and quads; cell {cell} is a {cell_type}")]
    RefinementCellType {
        /// The first such cell (0-based).
        cell: usize,
        /// Its type.
        cell_type: crate::geometry::CellType,
    },
    /// The mesh has more vertices than 32-bit vertex indices can number.
    #[error("the mesh has {vertices} vertices; at most {max} are supported")]
    TooLarge {
        /// The number of vertices given.
        vertices: usize,
        /// The largest number of vertices supported (`u32::MAX - 1`).
        max: usize,
    },
}

/// " of cell c" when the problem is one cell's.
fn cell_note(cell: &Option<usize>) -> String {
    cell.map(|c| format!(" of cell {c}")).unwrap_or_default()
}
