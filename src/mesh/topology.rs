//! Faces and the cells beside them, boundary and interface patches, and the cells around
//! vertices.

use super::{Csr, MeshError, PolyhedronFaces};
use crate::geometry::CellType;
use std::collections::HashMap;

/// Key of an undirected edge: the smaller vertex in the high half.
pub(crate) fn edge_key(a: u32, b: u32) -> u64 {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    ((lo as u64) << 32) | hi as u64
}

/// A face's sorted vertices padded with `u32::MAX`: equal for the two sides of one face, and
/// ordered like the edge key for segments.
pub(crate) fn face_key(v: &[u32]) -> [u32; 4] {
    let mut k = [u32::MAX; 4];
    k[..v.len()].copy_from_slice(v);
    k.sort_unstable();
    k
}

/// A cell and one of its local faces.
pub(crate) type CellFace = (u32, u32);

/// Every face of the mesh with the one or two cells beside it.
pub(crate) struct FaceCells {
    /// Faces of up to 4 vertices, sorted by key: (key, the cells beside it; the second is
    /// `u32::MAX` on the boundary).
    pub(crate) faces: Vec<([u32; 4], [CellFace; 2])>,
    /// Faces of more than 4 vertices (polyhedra's), sorted by their sorted vertices.
    pub(crate) large: Vec<(Vec<u32>, [CellFace; 2])>,
}

/// The cells of a mesh being validated, for their faces.
#[derive(Clone, Copy)]
pub(super) struct CellsView<'a> {
    /// The number of vertices (every index in `cells` is below it).
    pub(super) num_vertices: usize,
    pub(super) types: &'a [CellType],
    pub(super) cells: &'a Csr,
    pub(super) polyhedra: &'a PolyhedronFaces,
}

impl CellsView<'_> {
    /// The number of faces of cell `c`.
    fn num_faces(&self, c: usize) -> usize {
        match self.types[c] {
            CellType::Polygon => self.cells.get(c).len(),
            CellType::Polyhedron => self.polyhedra.of(c).len(),
            t => t.faces().len(),
        }
    }

    /// Face `f` of cell `c` with the cell's outward orientation.
    fn face(&self, c: u32, f: u32) -> FaceVertices<'_> {
        let (c, f) = (c as usize, f as usize);
        let t = self.cells.get(c);
        match self.types[c] {
            CellType::Polygon => FaceVertices::inline(&[t[f], t[(f + 1) % t.len()]]),
            CellType::Polyhedron => FaceVertices::Borrowed(self.polyhedra.of(c).nth(f).unwrap_or_default()),
            ty => {
                let local = ty.faces()[f];
                let mut v = [0u32; 4];
                v.iter_mut().zip(local).for_each(|(x, &k)| *x = t[k as usize]);
                FaceVertices::Inline(v, local.len() as u8)
            }
        }
    }
}

/// The vertices of one face of a cell: held in place for the faces of the fixed cell types and
/// the edges of polygons (at most 4 vertices), borrowed for a polyhedron's face (its own loop),
/// so listing the faces of a mesh allocates nothing per face.
enum FaceVertices<'a> {
    Inline([u32; 4], u8),
    Borrowed(&'a [u32]),
}

impl FaceVertices<'_> {
    fn inline(v: &[u32]) -> Self {
        let mut a = [0u32; 4];
        a[..v.len()].copy_from_slice(v);
        FaceVertices::Inline(a, v.len() as u8)
    }
}

impl std::ops::Deref for FaceVertices<'_> {
    type Target = [u32];
    fn deref(&self) -> &[u32] {
        match self {
            FaceVertices::Inline(v, n) => &v[..*n as usize],
            FaceVertices::Borrowed(v) => v,
        }
    }
}

/// The faces of all cells, paired: a face shared by more than two cells is an error, and so is
/// one whose two cells run along it in the same direction (they lie on the same side: the mesh
/// overlaps itself).
pub(super) fn cell_faces(view: CellsView) -> Result<FaceCells, MeshError> {
    let n = view.types.len();
    let listed: usize = (0..n).map(|c| view.num_faces(c)).sum();
    let mut all: Vec<([u32; 4], u32, u32)> = reserved(listed, "the faces of every cell")?;
    let mut large: Vec<(Vec<u32>, u32, u32)> = Vec::new();
    for c in 0..n {
        for f in 0..view.num_faces(c) {
            let v = view.face(c as u32, f as u32);
            if v.len() > 4 {
                let mut key = v.to_vec();
                key.sort_unstable();
                large.push((key, c as u32, f as u32));
            } else {
                all.push((face_key(&v), c as u32, f as u32));
            }
        }
    }
    let all = by_smallest_vertex(all, view.num_vertices)?;
    let faces = paired(all, view, |k| k.iter().copied().filter(|&v| v != u32::MAX).collect())?;
    large.sort_unstable();
    let large = paired(large, view, |k| k.clone())?;
    Ok(FaceCells { faces, large })
}

/// The faces of up to 4 vertices in the order of a sort of the whole list, made by a counting
/// sort on the smallest vertex (a key's first entry, below `n`) and a sort of each vertex's few
/// faces: linear in the number of faces where a comparison sort of them all is not.
fn by_smallest_vertex(all: Vec<([u32; 4], u32, u32)>, n: usize) -> Result<Vec<([u32; 4], u32, u32)>, MeshError> {
    let mut start = vec![0usize; n + 1];
    all.iter().for_each(|f| start[f.0[0] as usize + 1] += 1);
    for v in 0..n {
        start[v + 1] += start[v];
    }
    let mut out = reserved(all.len(), "the faces of every cell")?;
    out.resize(all.len(), ([0; 4], 0, 0));
    let mut next = start.clone();
    for f in all {
        let at = &mut next[f.0[0] as usize];
        out[*at] = f;
        *at += 1;
    }
    start.windows(2).for_each(|w| out[w[0]..w[1]].sort_unstable());
    Ok(out)
}

/// Faces keyed by their vertex set, sorted (by key, then cell and face), paired with the cells
/// beside them.
fn paired<K: Ord + Clone>(
    all: Vec<(K, u32, u32)>,
    view: CellsView,
    listed: impl Fn(&K) -> Vec<u32>,
) -> Result<Vec<(K, [CellFace; 2])>, MeshError> {
    let distinct = usize::from(!all.is_empty()) + all.windows(2).filter(|w| w[0].0 != w[1].0).count();
    let mut faces = reserved(distinct, "the faces of the mesh")?;
    let mut i = 0;
    while i < all.len() {
        let mut j = i + 1;
        while j < all.len() && all[j].0 == all[i].0 {
            j += 1;
        }
        if j - i > 2 {
            return Err(MeshError::NonManifoldFace { face: listed(&all[i].0), cells: j - i });
        }
        let second = if j - i == 2 { (all[i + 1].1, all[i + 1].2) } else { (u32::MAX, 0) };
        if second.0 != u32::MAX {
            let fa = view.face(all[i].1, all[i].2);
            let fb = view.face(second.0, second.1);
            if same_direction(&fa, &fb) {
                let face = listed(&all[i].0);
                return Err(MeshError::Overlap { first: all[i].1 as usize, second: second.0 as usize, face });
            }
        }
        faces.push((all[i].0.clone(), [(all[i].1, all[i].2), second]));
        i = j;
    }
    Ok(faces)
}

/// An empty vector with room for `n` items, or `MeshError::OutOfMemory` naming `what` when the
/// system refuses the memory (the tables a mesh's size decides are reserved fallibly: an
/// ordinary allocation that fails aborts the process).
fn reserved<T>(n: usize, what: &'static str) -> Result<Vec<T>, MeshError> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| MeshError::OutOfMemory {
        what,
        bytes: (n as u64).saturating_mul(std::mem::size_of::<T>() as u64),
    })?;
    Ok(v)
}

/// True when two orderings of the same vertex set run the same way round (segments: the same
/// order; polygons: the same cyclic order).
fn same_direction(a: &[u32], b: &[u32]) -> bool {
    if a.len() == 2 {
        return a == b;
    }
    let s = b.iter().position(|&v| v == a[0]).expect("same vertex set");
    a[1] == b[(s + 1) % b.len()]
}

/// The patch faces: every boundary face (with its tag, or patch 0) with the outward orientation
/// of its cell, and every tagged interior face as given, in key order (faces of up to 4
/// vertices first).
pub(super) fn patch_faces(
    view: CellsView,
    faces: &FaceCells,
    tagged: &[(Vec<u32>, i32)],
) -> Result<(Csr, Vec<i32>, Vec<bool>), MeshError> {
    // Tags of faces of up to 4 vertices by their key, of larger faces by their sorted vertices.
    let mut tags: HashMap<[u32; 4], (usize, i32)> = HashMap::with_capacity(tagged.len());
    let mut large_tags: HashMap<Vec<u32>, (usize, i32)> = HashMap::new();
    for (e, (v, patch)) in tagged.iter().enumerate() {
        let earlier = if v.len() > 4 {
            let mut key = v.clone();
            key.sort_unstable();
            if faces.large.binary_search_by(|f| f.0.cmp(&key)).is_err() {
                return Err(MeshError::TaggedFaceNotAFace { face: e, vertices: v.clone() });
            }
            large_tags.insert(key, (e, *patch))
        } else {
            let key = face_key(v);
            if v.len() < 2 || faces.faces.binary_search_by(|f| f.0.cmp(&key)).is_err() {
                return Err(MeshError::TaggedFaceNotAFace { face: e, vertices: v.clone() });
            }
            tags.insert(key, (e, *patch))
        };
        if let Some((_, first)) = earlier {
            if first != *patch {
                return Err(MeshError::TaggedFaceTwice { face: e, vertices: v.clone(), first, second: *patch });
            }
        }
    }
    let (mut out, mut patch, mut interior) = (Csr::new(), Vec::new(), Vec::new());
    let mut add = |tag: Option<(usize, i32)>, [(c0, f0), (c1, _)]: [CellFace; 2]| {
        if c1 == u32::MAX {
            out.push(&view.face(c0, f0));
            patch.push(tag.map_or(0, |t| t.1));
            interior.push(false);
        } else if let Some((e, p)) = tag {
            out.push(&tagged[e].0);
            patch.push(p);
            interior.push(true);
        }
    };
    faces.faces.iter().for_each(|(key, cells)| add(tags.get(key).copied(), *cells));
    faces.large.iter().for_each(|(key, cells)| add(large_tags.get(key).copied(), *cells));
    Ok((out, patch, interior))
}

/// Every edge of a triangle list with the one or two triangles beside it (the 2D coarsener's
/// check of its coarse triangulations).
pub(crate) struct EdgeCells {
    /// Sorted by key; `cells[1] == u32::MAX` for a boundary edge.
    pub(crate) edges: Vec<(u64, [u32; 2])>,
}

impl EdgeCells {
    /// The edges of `cells`; None when an edge has more than two triangles.
    pub(crate) fn build(cells: &[[u32; 3]]) -> Option<EdgeCells> {
        let mut all: Vec<(u64, u32)> = Vec::with_capacity(3 * cells.len());
        for (c, t) in cells.iter().enumerate() {
            for k in 0..3 {
                all.push((edge_key(t[k], t[(k + 1) % 3]), c as u32));
            }
        }
        all.sort_unstable();
        let mut edges = Vec::with_capacity(all.len() / 2 + 1);
        let mut i = 0;
        while i < all.len() {
            let mut j = i + 1;
            while j < all.len() && all[j].0 == all[i].0 {
                j += 1;
            }
            if j - i > 2 {
                return None;
            }
            let second = if j - i == 2 { all[i + 1].1 } else { u32::MAX };
            edges.push((all[i].0, [all[i].1, second]));
            i = j;
        }
        Some(EdgeCells { edges })
    }

    /// The triangles beside edge (a, b).
    pub(crate) fn get(&self, a: u32, b: u32) -> Option<[u32; 2]> {
        let k = edge_key(a, b);
        self.edges.binary_search_by_key(&k, |e| e.0).ok().map(|i| self.edges[i].1)
    }
}

/// The cells around each vertex (CSR, ascending cell index): a vertex's neighbours are the
/// vertices of these cells, so this serves as the vertex graph at about half its memory.
pub(crate) struct VertexCells {
    ptr: Vec<u32>,
    cells: Vec<u32>,
}

impl VertexCells {
    pub(crate) fn build(nv: usize, cells: &Csr) -> VertexCells {
        let total = u32::try_from(cells.items().len()).expect("vertex-cell incidence: more than 2^32 corners");
        let mut ptr = vec![0u32; nv + 1];
        for &v in cells.items() {
            ptr[v as usize + 1] += 1;
        }
        for i in 0..nv {
            ptr[i + 1] += ptr[i];
        }
        debug_assert_eq!(ptr[nv], total);
        let mut next = ptr.clone();
        let mut inc = vec![0u32; total as usize];
        for c in 0..cells.len() {
            for &v in cells.get(c) {
                inc[next[v as usize] as usize] = c as u32;
                next[v as usize] += 1;
            }
        }
        VertexCells { ptr, cells: inc }
    }

    /// The cells having `v` as a corner.
    pub(crate) fn of(&self, v: usize) -> &[u32] {
        &self.cells[self.ptr[v] as usize..self.ptr[v + 1] as usize]
    }
}
