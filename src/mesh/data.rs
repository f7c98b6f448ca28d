//! A mesh as plain arrays: what the file readers and the case generators produce, what
//! [`Mesh::from_data`](super::Mesh::from_data) validates, and what the writers take.

use crate::geometry::CellType;

/// A mesh as plain 0-based arrays, in the layout of VTK's unstructured grid and of most FV
/// codes: coordinates interleaved (`dim` per vertex), cells and faces as CSR lists.
///
/// Nothing here is checked; [`Mesh::from_data`](super::Mesh::from_data) does that.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    /// 2 or 3.
    pub dim: usize,
    /// `dim` values per vertex: x0, y0, (z0,) x1, ...
    pub coords: Vec<f64>,
    /// The type of each cell.
    pub cell_types: Vec<CellType>,
    /// Cell `c`'s corners are `cell_vertices[cell_offsets[c]..cell_offsets[c + 1]]`; starts at 0.
    pub cell_offsets: Vec<u32>,
    /// Corners of every cell, in VTK's local order for its type.
    pub cell_vertices: Vec<u32>,
    /// Region of each cell; empty means every cell is in region 0.
    pub regions: Vec<i32>,
    /// Tagged faces (segments in 2D, triangles and quads in 3D): face `f`'s vertices are
    /// `face_vertices[face_offsets[f]..face_offsets[f + 1]]`; starts at 0.
    pub face_offsets: Vec<u32>,
    /// Vertices of every tagged face.
    pub face_vertices: Vec<u32>,
    /// Patch id of each tagged face.
    pub face_patch: Vec<i32>,
    /// The faces of the polyhedral cells ([`CellType::Polyhedron`]) in VTK's layout: for each
    /// polyhedron in cell order, its number of faces, then each face's vertex count and its
    /// vertices, a loop whose right-hand normal points out of the cell (or into it, for every
    /// cell of a mesh given in the other orientation). A polyhedron's corners in
    /// `cell_vertices` are its distinct vertices, in any order. Empty when there is no
    /// polyhedron.
    pub polyhedron_faces: Vec<u32>,
}

impl MeshData {
    /// An empty mesh of dimension `dim`.
    pub fn new(dim: usize) -> MeshData {
        MeshData { dim, cell_offsets: vec![0], face_offsets: vec![0], ..MeshData::default() }
    }

    /// Number of vertices (`coords.len() / dim`).
    pub fn num_vertices(&self) -> usize {
        self.coords.len().checked_div(self.dim).unwrap_or(0)
    }

    /// Number of cells.
    pub fn num_cells(&self) -> usize {
        self.cell_types.len()
    }

    /// Number of tagged faces.
    pub fn num_faces(&self) -> usize {
        self.face_patch.len()
    }

    /// Appends a vertex; returns its index.
    pub fn push_vertex(&mut self, x: &[f64]) -> u32 {
        debug_assert_eq!(x.len(), self.dim);
        self.coords.extend_from_slice(x);
        (self.num_vertices() - 1) as u32
    }

    /// Appends a cell in region `region`.
    pub fn push_cell(&mut self, ty: CellType, vertices: &[u32], region: i32) {
        if self.cell_offsets.is_empty() {
            self.cell_offsets.push(0);
        }
        // Regions are stored only once a cell is outside region 0.
        if region != 0 || !self.regions.is_empty() {
            self.regions.resize(self.cell_types.len(), 0);
            self.regions.push(region);
        }
        self.cell_types.push(ty);
        self.cell_vertices.extend_from_slice(vertices);
        self.cell_offsets.push(self.cell_vertices.len() as u32);
    }

    /// Appends a polyhedron in region `region` given by its faces (loops of vertices whose
    /// right-hand normals point out of it); its corners are the faces' distinct vertices in the
    /// order they first appear.
    pub fn push_polyhedron(&mut self, faces: &[&[u32]], region: i32) {
        let mut corners: Vec<u32> = Vec::new();
        self.polyhedron_faces.push(faces.len() as u32);
        for f in faces {
            self.polyhedron_faces.push(f.len() as u32);
            self.polyhedron_faces.extend_from_slice(f);
            f.iter().for_each(|v| {
                if !corners.contains(v) {
                    corners.push(*v)
                }
            });
        }
        self.push_cell(CellType::Polyhedron, &corners, region);
    }

    /// Appends a tagged face on patch `patch`.
    pub fn push_face(&mut self, vertices: &[u32], patch: i32) {
        if self.face_offsets.is_empty() {
            self.face_offsets.push(0);
        }
        self.face_vertices.extend_from_slice(vertices);
        self.face_offsets.push(self.face_vertices.len() as u32);
        self.face_patch.push(patch);
    }

    /// The corners of cell `c`.
    pub fn cell(&self, c: usize) -> &[u32] {
        &self.cell_vertices[self.cell_offsets[c] as usize..self.cell_offsets[c + 1] as usize]
    }

    /// The vertices of tagged face `f`.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.face_vertices[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }

    /// The coordinates of vertex `v`.
    pub fn point(&self, v: usize) -> &[f64] {
        &self.coords[v * self.dim..(v + 1) * self.dim]
    }

    /// Where each polyhedron's faces lie in `polyhedron_faces` (None for the other cells),
    /// checked: each polyhedron's list is whole, its vertices are below the vertex count, and
    /// nothing follows the last one (`n`: the vertex count). The error says what is wrong.
    pub(crate) fn polyhedron_spans(&self, n: usize) -> Result<Vec<Option<std::ops::Range<usize>>>, String> {
        let s = &self.polyhedron_faces;
        let mut at = 0usize;
        let mut out = Vec::with_capacity(self.num_cells());
        for (c, &t) in self.cell_types.iter().enumerate() {
            if t != CellType::Polyhedron {
                out.push(None);
                continue;
            }
            let start = at;
            at = polyhedron_list_end(s, at, n).map_err(|p| format!("polyhedron {c}: {p}"))?;
            out.push(Some(start..at));
        }
        if at != s.len() {
            return Err(format!("{} values follow the last polyhedron's faces", s.len() - at));
        }
        Ok(out)
    }
}

/// Where the face list of one polyhedron starting at `at` in `s` ends, checked: whole, and its
/// vertices below `n`.
pub(crate) fn polyhedron_list_end(s: &[u32], mut at: usize, n: usize) -> Result<usize, String> {
    let short = || "its face list is cut short".to_string();
    let faces = *s.get(at).ok_or_else(short)?;
    at += 1;
    for _ in 0..faces {
        let len = *s.get(at).ok_or_else(short)? as usize;
        let face = s.get(at + 1..at + 1 + len).ok_or_else(short)?;
        if let Some(v) = face.iter().find(|&&v| v as usize >= n) {
            return Err(format!("a face has vertex {v}, outside 0..{n}"));
        }
        at += 1 + len;
    }
    Ok(at)
}

/// The faces of one polyhedron's checked list (its number of faces, then each face's vertex
/// count and vertices; see [`MeshData::polyhedron_spans`]).
pub(crate) fn faces_in(list: &[u32]) -> impl Iterator<Item = &[u32]> + '_ {
    let mut at = 1usize;
    (0..list.first().copied().unwrap_or(0)).map(move |_| {
        let len = list[at] as usize;
        let face = &list[at + 1..at + 1 + len];
        at += 1 + len;
        face
    })
}

impl super::Mesh {
    /// The mesh as plain arrays; its faces are every patch face (boundary faces on patch 0
    /// included), so `Mesh::from_data(&m.to_data())` gives the same mesh.
    pub fn to_data(&self) -> MeshData {
        let mut d = MeshData::new(self.dim());
        d.coords = self.coords().to_vec();
        for c in 0..self.num_cells() {
            d.push_cell(self.cell_type(c), self.cell(c), self.regions()[c]);
        }
        for f in self.patch_faces() {
            d.push_face(f.vertices, f.patch);
        }
        d.polyhedron_faces = super::polyhedra::stream(self);
        d
    }
}
