//! The mesh: vertices, cells of any type, boundary and interface faces with patch ids, regions
//! (docs/DESIGN.md §2).
//!
//! Cells are stored as CSR lists with a [`CellType`] each, in VTK's local corner order; faces
//! (segments in 2D, triangles and quads in 3D) likewise. Everything downstream works on the
//! per-cell element contributions of `crate::geometry` and on adjacency derived from the
//! cells, so nothing outside the geometry module knows the dimension or the cell type.

mod data;
mod error;
pub(crate) mod features;
#[cfg(test)]
pub(crate) mod fixtures;
mod from_faces;
mod polyhedra;
/// Cell quality (public with the `internals` feature: the paper's cases measure with it).
#[cfg(feature = "internals")]
#[doc(hidden)]
pub mod quality;
#[cfg(not(feature = "internals"))]
pub(crate) mod quality;
mod refine;
mod topology;
pub(crate) mod validate;

pub use data::MeshData;
pub(crate) use data::{faces_in, polyhedron_list_end};
pub use error::MeshError;
pub use from_faces::FaceMeshData;
pub use quality::{inverted_cells, quality, signed_measures, Quality};
pub(crate) use topology::{edge_key, EdgeCells, VertexCells};

use crate::geometry::{CellGeometry, CellPoints, CellType, GeneralPoints};

/// First index of the caller's vertex numbering: C passes 0, Fortran 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IndexBase {
    /// 0-based (C, C++, Rust).
    Zero = 0,
    /// 1-based (Fortran).
    One = 1,
}

/// A face on a patch: a boundary face (patch 0 when the caller did not tag it) or an interior
/// face the caller tagged, typically an interface between two regions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PatchFace<'a> {
    /// Boundary faces: ordered so their right-hand normal points out of the domain (in 2D the
    /// domain lies on the left of the segment). Interior faces: as given.
    pub vertices: &'a [u32],
    /// The patch id.
    pub patch: i32,
    /// True for a tagged face with a cell on each side.
    pub interior: bool,
}

/// Lists of vertex indices: item `i` is `items[i * stride..(i + 1) * stride]` while every item
/// has the same length (a mesh of one cell type, every coarse level), else
/// `items[ptr[i]..ptr[i + 1]]`. The offsets of a single-type mesh are not stored: at 4 bytes a
/// cell on every level they would be a twentieth of the solver's memory.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Csr {
    /// Offsets (`len + 1` of them) once the items differ in length; empty before.
    ptr: Vec<u32>,
    items: Vec<u32>,
    /// The common length of the items while `ptr` is empty (0 before the first push).
    stride: u32,
    len: u32,
}

impl Csr {
    pub(crate) fn new() -> Csr {
        Csr::default()
    }
    /// The number of items.
    pub(crate) fn len(&self) -> usize {
        self.len as usize
    }
    /// Item `i`.
    #[inline]
    pub(crate) fn get(&self, i: usize) -> &[u32] {
        if self.ptr.is_empty() {
            let s = self.stride as usize;
            &self.items[i * s..(i + 1) * s]
        } else {
            &self.items[self.ptr[i] as usize..self.ptr[i + 1] as usize]
        }
    }
    /// Item `i`, to change in place (its length is kept).
    pub(crate) fn get_mut(&mut self, i: usize) -> &mut [u32] {
        let r = if self.ptr.is_empty() {
            let s = self.stride as usize;
            i * s..(i + 1) * s
        } else {
            self.ptr[i] as usize..self.ptr[i + 1] as usize
        };
        &mut self.items[r]
    }
    /// All items, one after another.
    pub(crate) fn items(&self) -> &[u32] {
        &self.items
    }
    /// Appends an item.
    pub(crate) fn push(&mut self, items: &[u32]) {
        let n = items.len() as u32;
        if self.ptr.is_empty() && self.len > 0 && n != self.stride {
            self.ptr = (0..=self.len).map(|i| i * self.stride).collect();
        }
        if self.len == 0 {
            self.stride = n;
        }
        self.items.extend_from_slice(items);
        self.len += 1;
        if !self.ptr.is_empty() {
            self.ptr.push(self.items.len() as u32);
        }
    }
    fn shrink(&mut self) {
        self.ptr.shrink_to_fit();
        self.items.shrink_to_fit();
    }
}

/// The faces of a mesh's polyhedra, each a loop of vertices whose right-hand normal points out
/// of its cell: cell `c`'s faces are `faces.get(f)` for `f` in `first[c]..first[c + 1]`. Both
/// are empty when the mesh has no polyhedron (every other cell's faces come from its type).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct PolyhedronFaces {
    first: Vec<u32>,
    faces: Csr,
}

impl PolyhedronFaces {
    /// The faces of cell `c` (none for a cell that is not a polyhedron).
    pub(crate) fn of(&self, c: usize) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        let r = if self.first.is_empty() { 0..0 } else { self.first[c] as usize..self.first[c + 1] as usize };
        r.map(move |f| self.faces.get(f))
    }
    /// Reverses every face loop of cell `c`: the polyhedron in the opposite orientation.
    fn reverse(&mut self, c: usize) {
        if self.first.is_empty() {
            return;
        }
        for f in self.first[c] as usize..self.first[c + 1] as usize {
            self.faces.get_mut(f).reverse();
        }
    }
}

/// A validated mesh in 2 or 3 dimensions. Cells are stored positively oriented whatever the
/// input orientation (a mesh given entirely in the other orientation is flipped as a whole).
///
/// Coordinates are plain `f64`, `dim` per vertex, interleaved (x0, y0, x1, y1, … in 2D): the
/// layout of C and Fortran hosts, with no vector type of a third-party crate in the API. The
/// dimension is a run-time value rather than a type parameter: hosts choose it at run time, one
/// `Solver` type serves both, and the dimension never appears in the solver's inner loops (they
/// run on scalar sparse rows; only the cell kernels of `crate::geometry` see points).
#[derive(Clone, Debug)]
pub struct Mesh {
    dim: usize,
    coords: Vec<f64>,
    types: Vec<CellType>,
    cells: Csr,
    regions: Vec<i32>,
    faces: Csr,
    face_patch: Vec<i32>,
    face_interior: Vec<bool>,
    polyhedra: PolyhedronFaces,
}

impl Mesh {
    /// A 2D triangle mesh from caller arrays: `triangles` and `tagged` (boundary or interface
    /// edges with a patch id) in the caller's index `base`; `regions`, when given, one per cell.
    ///
    /// ```
    /// use meshmove::{IndexBase, Mesh};
    /// let coords = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    /// let mesh = Mesh::triangles(&coords, &[[1u32, 2, 3], [1, 3, 4]], IndexBase::One, &[([2, 3], 7)], None).unwrap();
    /// assert_eq!(mesh.patch_vertices(7), vec![1, 2]);
    /// ```
    pub fn triangles<I: Copy + TryInto<i64>>(
        coords: &[[f64; 2]],
        triangles: &[[I; 3]],
        base: IndexBase,
        tagged: &[([I; 2], i32)],
        regions: Option<&[i32]>,
    ) -> Result<Mesh, MeshError> {
        let n = coords.len();
        let mut d = MeshData::new(2);
        d.coords = coords.iter().flatten().copied().collect();
        for (c, t) in triangles.iter().enumerate() {
            let t = validate::indices(t, base, n).map_err(|(_, index)| validate::out_of_range(c, index, base, n))?;
            d.push_cell(CellType::Triangle, &t, 0);
        }
        for (e, (v, patch)) in tagged.iter().enumerate() {
            let v = validate::indices(v, base, n).map_err(|(_, index)| MeshError::TaggedIndexOutOfRange {
                edge: e,
                index,
                base: base as i64,
                end: n as i64 + base as i64,
            })?;
            d.push_face(&v, *patch);
        }
        if let Some(r) = regions {
            d.regions = r.to_vec();
        }
        Mesh::from_data(&d)
    }

    /// Validates `data` and builds the mesh: dimension 2 or 3, finite coordinates, cells of the
    /// mesh's dimension with valid indices, no repeated vertex in a cell, no unused vertex, no
    /// degenerate or inverted cell, one orientation for all cells, no two cells on the same side
    /// of a face, no face shared by more than two cells, no repeated cell, tagged faces that are
    /// faces of the mesh, one region per cell. Boundary faces not tagged go to patch 0.
    pub fn from_data(data: &MeshData) -> Result<Mesh, MeshError> {
        validate::mesh(data)
    }

    /// Assembles a mesh from already-validated parts (refinement and coarsening produce these).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn from_parts(
        dim: usize,
        coords: Vec<f64>,
        types: Vec<CellType>,
        cells: Csr,
        regions: Vec<i32>,
        faces: Csr,
        face_patch: Vec<i32>,
        face_interior: Vec<bool>,
    ) -> Mesh {
        let polyhedra = PolyhedronFaces::default();
        let mut m = Mesh { dim, coords, types, cells, regions, faces, face_patch, face_interior, polyhedra };
        // Multigrid levels keep their meshes for the solver's life: no spare capacity.
        m.coords.shrink_to_fit();
        m.types.shrink_to_fit();
        m.cells.shrink();
        m.regions.shrink_to_fit();
        m.faces.shrink();
        m.face_patch.shrink_to_fit();
        m.face_interior.shrink_to_fit();
        m
    }

    /// The dimension: 2 or 3.
    pub fn dim(&self) -> usize {
        self.dim
    }
    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.coords.len() / self.dim
    }
    /// Number of cells.
    pub fn num_cells(&self) -> usize {
        self.types.len()
    }
    /// All coordinates, `dim` per vertex, interleaved.
    pub fn coords(&self) -> &[f64] {
        &self.coords
    }
    /// The coordinates of vertex `v`.
    #[inline]
    pub fn point(&self, v: usize) -> &[f64] {
        &self.coords[v * self.dim..(v + 1) * self.dim]
    }
    /// The corners of cell `c`, in VTK's local order for its type, positively oriented.
    #[inline]
    pub fn cell(&self, c: usize) -> &[u32] {
        self.cells.get(c)
    }
    /// The type of cell `c`.
    #[inline]
    pub fn cell_type(&self, c: usize) -> CellType {
        self.types[c]
    }
    /// The types of all cells.
    pub fn cell_types(&self) -> &[CellType] {
        &self.types
    }
    /// The faces of cell `c` if it is a polyhedron (none otherwise), each a loop of vertices
    /// whose right-hand normal points out of the cell.
    pub fn polyhedron_faces(&self, c: usize) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        self.polyhedra.of(c)
    }
    /// True when a cell is a polygon or a polyhedron.
    pub(crate) fn has_general_cells(&self) -> bool {
        self.types.iter().any(|t| t.is_general())
    }
    /// The corners of a general cell `c` (a polygon or a polyhedron) at positions `coords`.
    pub(crate) fn general_points(&self, coords: &[f64], c: usize) -> GeneralPoints {
        GeneralPoints::gather(self.cell(c), self.polyhedra.of(c), coords, self.dim)
    }
    /// Cell `c` at positions `coords`, whatever its type.
    pub(crate) fn cell_geometry(&self, coords: &[f64], c: usize) -> CellGeometry {
        let ty = self.types[c];
        if ty.is_general() {
            CellGeometry::General(self.general_points(coords, c))
        } else {
            CellGeometry::Fixed(CellPoints::gather(ty, self.cell(c), coords, self.dim))
        }
    }
    /// Region of each cell.
    pub fn regions(&self) -> &[i32] {
        &self.regions
    }
    /// The corners of all cells together (the length of the cells' connectivity list).
    pub(crate) fn num_cell_corners(&self) -> usize {
        self.cells.items().len()
    }
    /// The vertices of all patch faces together (the length of their connectivity list).
    pub(crate) fn num_patch_face_vertices(&self) -> usize {
        self.faces.items().len()
    }
    /// Number of patch faces (boundary faces and tagged interior faces).
    pub fn num_patch_faces(&self) -> usize {
        self.face_patch.len()
    }
    /// Patch face `f`.
    pub fn patch_face(&self, f: usize) -> PatchFace<'_> {
        PatchFace { vertices: self.faces.get(f), patch: self.face_patch[f], interior: self.face_interior[f] }
    }
    /// Every patch face: boundary faces (with their tag, or patch 0) and tagged interior faces,
    /// in the order of their sorted vertex sets.
    pub fn patch_faces(&self) -> impl ExactSizeIterator<Item = PatchFace<'_>> + '_ {
        (0..self.num_patch_faces()).map(|f| self.patch_face(f))
    }

    /// The cells around each vertex, computed on demand (meshes are held by every multigrid
    /// level, so adjacency is not stored with them).
    pub(crate) fn vertex_cells(&self) -> VertexCells {
        VertexCells::build(self.num_vertices(), &self.cells)
    }

    /// The same topology at new vertex positions (a deformed mesh). Positions must be finite.
    pub fn with_coords(&self, coords: Vec<f64>) -> Mesh {
        assert_eq!(coords.len(), self.coords.len(), "with_coords: vertex count changed");
        // The topology cloned field by field: cloning the whole mesh would copy the old
        // positions too, only to drop them.
        Mesh {
            dim: self.dim,
            coords,
            types: self.types.clone(),
            cells: self.cells.clone(),
            regions: self.regions.clone(),
            faces: self.faces.clone(),
            face_patch: self.face_patch.clone(),
            face_interior: self.face_interior.clone(),
            polyhedra: self.polyhedra.clone(),
        }
    }

    /// Sorted, deduplicated patch ids present in the mesh.
    pub fn patch_ids(&self) -> Vec<i32> {
        let mut ids = self.face_patch.clone();
        ids.sort_unstable();
        ids.dedup();
        ids
    }

    /// Sorted vertices lying on a patch.
    pub fn patch_vertices(&self, patch: i32) -> Vec<u32> {
        let mut v: Vec<u32> =
            self.patch_faces().filter(|f| f.patch == patch).flat_map(|f| f.vertices.iter().copied()).collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Each cell split at its edge midpoints (a triangle into four, a quad into four); patches
    /// and regions inherited. The splitting is written for 2D cells: a 3D mesh gives
    /// [`MeshError::RefinementDimension`], a mesh with polygons
    /// [`MeshError::RefinementCellType`].
    pub fn refined(&self) -> Result<Mesh, MeshError> {
        if self.dim() != 2 {
            return Err(MeshError::RefinementDimension { dim: self.dim() });
        }
        if let Some(cell) = self.types.iter().position(|t| t.is_general()) {
            return Err(MeshError::RefinementCellType { cell, cell_type: self.types[cell] });
        }
        Ok(refine::uniform(self))
    }

    /// [`Mesh::refined`] of a mesh the crate's tests know to be 2D.
    #[cfg(test)]
    pub(crate) fn refine_uniform(&self) -> Mesh {
        self.refined().expect("a 2D test mesh")
    }
}

/// Access for the 2D triangle code of the Delaunay coarsener and its transfers (coarse levels
/// in 2D are triangulations).
impl Mesh {
    /// Vertex `v` of a 2D mesh as a glam vector.
    #[inline]
    pub(crate) fn xy(&self, v: usize) -> glam::DVec2 {
        glam::DVec2::new(self.coords[2 * v], self.coords[2 * v + 1])
    }
    /// All vertices of a 2D mesh as glam vectors.
    pub(crate) fn xy_all(&self) -> Vec<glam::DVec2> {
        self.coords.chunks_exact(2).map(|p| glam::DVec2::new(p[0], p[1])).collect()
    }
    /// Cell `c` of a triangle mesh.
    #[inline]
    pub(crate) fn tri(&self, c: usize) -> [u32; 3] {
        let t = self.cells.get(c);
        [t[0], t[1], t[2]]
    }
    /// A 2D triangle mesh from validated parts: the coarsener's triangulations, with their
    /// feature segments as patch faces.
    pub(crate) fn from_triangles(
        coords: &[glam::DVec2],
        tris: &[[u32; 3]],
        regions: Vec<i32>,
        segments: &[([u32; 2], i32, bool)],
    ) -> Mesh {
        let mut cells = Csr::new();
        tris.iter().for_each(|t| cells.push(t));
        let mut faces = Csr::new();
        segments.iter().for_each(|s| faces.push(&s.0));
        Mesh::from_parts(
            2,
            coords.iter().flat_map(|p| [p.x, p.y]).collect(),
            vec![CellType::Triangle; tris.len()],
            cells,
            regions,
            faces,
            segments.iter().map(|s| s.1).collect(),
            segments.iter().map(|s| s.2).collect(),
        )
    }
}

impl Mesh {
    /// The same 2D mesh with every quad split into two triangles along its 0–2 diagonal
    /// (regions and patch faces kept): for the triangle-based point location.
    pub(crate) fn split_into_triangles(&self) -> Mesh {
        let mut cells = Csr::new();
        let mut regions = Vec::new();
        for c in 0..self.num_cells() {
            let t = self.cell(c);
            match self.cell_type(c) {
                CellType::Quad => {
                    cells.push(&[t[0], t[1], t[2]]);
                    cells.push(&[t[0], t[2], t[3]]);
                    regions.extend([self.regions[c]; 2]);
                }
                _ => {
                    cells.push(t);
                    regions.push(self.regions[c]);
                }
            }
        }
        let n = cells.len();
        Mesh { types: vec![CellType::Triangle; n], cells, regions, ..self.clone() }
    }
}

/// A patch face of a 2D mesh as a value (tests of the 2D code compare these).
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PatchEdge {
    /// The segment's vertices.
    pub vertices: [u32; 2],
    /// The patch id.
    pub patch: i32,
    /// Tagged face with a cell on each side.
    pub interior: bool,
}

/// Views of a 2D triangle mesh for the tests of the 2D code (internals; not a stable API).
#[cfg(any(test, feature = "internals"))]
impl Mesh {
    /// The coordinates as pairs.
    #[doc(hidden)]
    pub fn coords_xy(&self) -> Vec<[f64; 2]> {
        self.coords.chunks_exact(2).map(|p| [p[0], p[1]]).collect()
    }
    /// The coordinates as glam vectors.
    #[doc(hidden)]
    pub fn points_2d(&self) -> Vec<glam::DVec2> {
        self.xy_all()
    }
    /// The cells of a triangle mesh.
    #[doc(hidden)]
    pub fn tris(&self) -> Vec<[u32; 3]> {
        (0..self.num_cells()).map(|c| self.tri(c)).collect()
    }
    /// The patch faces of a 2D mesh as values.
    #[doc(hidden)]
    pub fn patch_edges(&self) -> Vec<PatchEdge> {
        self.patch_faces()
            .map(|f| PatchEdge { vertices: [f.vertices[0], f.vertices[1]], patch: f.patch, interior: f.interior })
            .collect()
    }
}
