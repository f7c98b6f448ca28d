//! Faces and the cells beside them, boundary and interface patches, and the cells around
//! vertices.

use super::{Csr, MeshError};
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
pub(crate) type CellFace = (u32, u8);

/// Every face of the mesh with the one or two cells beside it.
pub(crate) struct FaceCells {
    /// Sorted by key: (key, the cells beside it; the second is `u32::MAX` on the boundary).
    pub(crate) faces: Vec<([u32; 4], [CellFace; 2])>,
}

/// The faces of all cells, paired: a face shared by more than two cells is an error, and so is
/// one whose two cells run along it in the same direction (they lie on the same side: the mesh
/// overlaps itself).
pub(super) fn cell_faces(types: &[CellType], cells: &Csr) -> Result<FaceCells, MeshError> {
    let listed: usize = types.iter().map(|t| t.faces().len()).sum();
    let mut all: Vec<([u32; 4], u32, u8)> = reserved(listed, "the faces of every cell")?;
    for (c, &ty) in types.iter().enumerate() {
        let t = cells.get(c);
        for (f, local) in ty.faces().iter().enumerate() {
            let v: Vec<u32> = local.iter().map(|&k| t[k as usize]).collect();
            all.push((face_key(&v), c as u32, f as u8));
        }
    }
    all.sort_unstable();
    let distinct = 1 + all.windows(2).filter(|w| w[0].0 != w[1].0).count();
    let mut faces = reserved(distinct, "the faces of the mesh")?;
    let mut i = 0;
    while i < all.len() {
        let mut j = i + 1;
        while j < all.len() && all[j].0 == all[i].0 {
            j += 1;
        }
        let key = all[i].0;
        let listed: Vec<u32> = key.iter().copied().filter(|&v| v != u32::MAX).collect();
        if j - i > 2 {
            return Err(MeshError::NonManifoldFace { face: listed, cells: j - i });
        }
        let second = if j - i == 2 { (all[i + 1].1, all[i + 1].2) } else { (u32::MAX, 0) };
        if second.0 != u32::MAX {
            let fa = oriented_face(types, cells, all[i].1, all[i].2);
            let fb = oriented_face(types, cells, second.0, second.1);
            if same_direction(&fa, &fb) {
                return Err(MeshError::Overlap { first: all[i].1 as usize, second: second.0 as usize, face: listed });
            }
        }
        faces.push((key, [(all[i].1, all[i].2), second]));
        i = j;
    }
    Ok(FaceCells { faces })
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

/// Local face `f` of cell `c` with the cell's outward orientation.
fn oriented_face(types: &[CellType], cells: &Csr, c: u32, f: u8) -> Vec<u32> {
    let t = cells.get(c as usize);
    types[c as usize].faces()[f as usize].iter().map(|&k| t[k as usize]).collect()
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
/// of its cell, and every tagged interior face as given, in key order.
pub(super) fn patch_faces(
    types: &[CellType],
    cells: &Csr,
    faces: &FaceCells,
    tagged: &[(Vec<u32>, i32)],
) -> Result<(Csr, Vec<i32>, Vec<bool>), MeshError> {
    let mut tags: HashMap<[u32; 4], (usize, i32)> = HashMap::with_capacity(tagged.len());
    for (e, (v, patch)) in tagged.iter().enumerate() {
        let key = face_key(v);
        if v.len() < 2 || v.len() > 4 || faces.faces.binary_search_by(|f| f.0.cmp(&key)).is_err() {
            return Err(MeshError::TaggedFaceNotAFace { face: e, vertices: v.clone() });
        }
        if let Some(&(_, first)) = tags.get(&key) {
            if first != *patch {
                return Err(MeshError::TaggedFaceTwice { face: e, vertices: v.clone(), first, second: *patch });
            }
        }
        tags.insert(key, (e, *patch));
    }
    let (mut out, mut patch, mut interior) = (Csr::new(), Vec::new(), Vec::new());
    for (key, [(c0, f0), (c1, _)]) in &faces.faces {
        let tag = tags.get(key).map(|&(e, p)| (e, p));
        if *c1 == u32::MAX {
            out.push(&oriented_face(types, cells, *c0, *f0));
            patch.push(tag.map_or(0, |t| t.1));
            interior.push(false);
        } else if let Some((e, p)) = tag {
            out.push(&tagged[e].0);
            patch.push(p);
            interior.push(true);
        }
    }
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
