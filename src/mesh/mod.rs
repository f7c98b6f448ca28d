//! The mesh: vertices, cells, boundary patches and regions (docs/DESIGN.md §2).
//!
//! Cells are triangles today. Everything downstream (operators, multigrid) works on per-cell
//! element contributions and on adjacency derived from the cells, so tetrahedra and mixed cells
//! add a cell kind here and an element routine in `operator`, not a new data model.

mod data;
mod error;
pub mod quality;
mod refine;
mod topology;
pub(crate) mod validate;

pub use data::MeshData;
pub use error::MeshError;
pub use topology::{edge_key, EdgeCells, VertexCells};

use glam::DVec2;

/// First index of the caller's vertex numbering: C passes 0, Fortran 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IndexBase {
    Zero = 0,
    One = 1,
}

/// A patch edge: a boundary edge (patch 0 when the caller did not tag it) or an interior edge the
/// caller tagged, typically an interface between two regions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PatchEdge {
    /// For boundary edges: oriented with the domain on the left. Interior edges: as given.
    pub vertices: [u32; 2],
    pub patch: i32,
    /// True for a tagged edge with a cell on each side.
    pub interior: bool,
}

/// A validated 2D triangle mesh. Cells are stored counter-clockwise whatever the input orientation.
#[derive(Clone, Debug)]
pub struct Mesh {
    coords: Vec<DVec2>,
    cells: Vec<[u32; 3]>,
    regions: Vec<i32>,
    patch_edges: Vec<PatchEdge>,
}

/// A tagged edge as the caller gives it: two vertex indices (in the caller's base) and a patch id.
pub type TaggedEdge<I> = ([I; 2], i32);

impl Mesh {
    /// Validates and builds a mesh.
    ///
    /// `triangles` and `tagged` use `base`; `regions`, when given, has one entry per triangle.
    /// Boundary edges that are not in `tagged` go to patch 0. A tagged edge must be a boundary
    /// edge or an interior edge between two cells (an internal interface).
    pub fn new<I: Copy + TryInto<i64>>(
        coords: &[[f64; 2]],
        triangles: &[[I; 3]],
        base: IndexBase,
        tagged: &[TaggedEdge<I>],
        regions: Option<&[i32]>,
    ) -> Result<Mesh, MeshError> {
        let coords = validate::coordinates(coords)?;
        let mut cells = validate::cells(triangles, base, coords.len())?;
        validate::all_used(&cells, coords.len())?;
        validate::orient(&coords, &mut cells)?;
        validate::distinct(&cells)?;
        let regions = match regions {
            Some(r) if r.len() != cells.len() => {
                return Err(MeshError::RegionCount { regions: r.len(), cells: cells.len() })
            }
            Some(r) => r.to_vec(),
            None => vec![0; cells.len()],
        };
        let edges = EdgeCells::build(&cells)?;
        topology::check_no_overlap(&cells, &edges)?;
        let tagged = validate::tagged_edges(tagged, base, coords.len())?;
        let patch_edges = topology::patch_edges(&cells, &edges, &tagged)?;
        Ok(Mesh::from_parts(coords, cells, regions, patch_edges))
    }

    /// Assembles a mesh from already-validated parts (refinement and coarsening produce these).
    pub(crate) fn from_parts(
        coords: Vec<DVec2>,
        cells: Vec<[u32; 3]>,
        regions: Vec<i32>,
        patch_edges: Vec<PatchEdge>,
    ) -> Mesh {
        let mut m = Mesh { coords, cells, regions, patch_edges };
        // Multigrid levels keep their meshes for the solver's life: no spare capacity.
        m.coords.shrink_to_fit();
        m.cells.shrink_to_fit();
        m.regions.shrink_to_fit();
        m.patch_edges.shrink_to_fit();
        m
    }

    pub fn num_vertices(&self) -> usize {
        self.coords.len()
    }
    pub fn num_cells(&self) -> usize {
        self.cells.len()
    }
    pub fn coords(&self) -> &[DVec2] {
        &self.coords
    }
    pub fn cells(&self) -> &[[u32; 3]] {
        &self.cells
    }
    pub fn regions(&self) -> &[i32] {
        &self.regions
    }
    pub fn patch_edges(&self) -> &[PatchEdge] {
        &self.patch_edges
    }
    /// The cells around each vertex, computed on demand (meshes are held by every multigrid
    /// level, so adjacency is not stored with them).
    pub fn vertex_cells(&self) -> VertexCells {
        VertexCells::build(self.coords.len(), &self.cells)
    }

    /// Coordinates as plain pairs, for callers without glam.
    pub fn coords_xy(&self) -> Vec<[f64; 2]> {
        self.coords.iter().map(|p| [p.x, p.y]).collect()
    }

    /// The same topology at new vertex positions (a deformed mesh). Positions must be finite.
    pub fn with_coords(&self, coords: Vec<DVec2>) -> Mesh {
        assert_eq!(coords.len(), self.coords.len(), "with_coords: vertex count changed");
        Mesh { coords, ..self.clone() }
    }

    /// Sorted, deduplicated patch ids present in the mesh.
    pub fn patch_ids(&self) -> Vec<i32> {
        let mut ids: Vec<i32> = self.patch_edges.iter().map(|e| e.patch).collect();
        ids.sort_unstable();
        ids.dedup();
        ids
    }

    /// Sorted vertices lying on a patch.
    pub fn patch_vertices(&self, patch: i32) -> Vec<u32> {
        let mut v: Vec<u32> = self.patch_edges.iter().filter(|e| e.patch == patch).flat_map(|e| e.vertices).collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Each triangle split into four at its edge midpoints; patches and regions inherited.
    pub fn refine_uniform(&self) -> Mesh {
        refine::uniform(self)
    }
}
