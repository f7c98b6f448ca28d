//! Edges and the cells beside them, boundary and interface patches, and the cells around vertices.

use super::{MeshError, PatchEdge};
use std::collections::HashMap;

/// Key of an undirected edge: the smaller vertex in the high half.
pub fn edge_key(a: u32, b: u32) -> u64 {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    ((lo as u64) << 32) | hi as u64
}

/// Every edge of the mesh with the one or two cells beside it.
pub struct EdgeCells {
    /// Sorted by key; `cells[1] == u32::MAX` for a boundary edge.
    pub edges: Vec<(u64, [u32; 2])>,
}

impl EdgeCells {
    pub fn build(cells: &[[u32; 3]]) -> Result<EdgeCells, MeshError> {
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
                let k = all[i].0;
                return Err(MeshError::NonManifoldEdge {
                    a: (k >> 32) as usize,
                    b: (k & 0xffff_ffff) as usize,
                    cells: j - i,
                });
            }
            let second = if j - i == 2 { all[i + 1].1 } else { u32::MAX };
            edges.push((all[i].0, [all[i].1, second]));
            i = j;
        }
        Ok(EdgeCells { edges })
    }

    pub fn get(&self, a: u32, b: u32) -> Option<[u32; 2]> {
        let k = edge_key(a, b);
        self.edges.binary_search_by_key(&k, |e| e.0).ok().map(|i| self.edges[i].1)
    }
}

/// Counter-clockwise cells on both sides of an interior edge run along it in opposite
/// directions; the same direction means they lie on the same side: the mesh overlaps itself.
pub(super) fn check_no_overlap(cells: &[[u32; 3]], edges: &EdgeCells) -> Result<(), MeshError> {
    for &(key, [c0, c1]) in &edges.edges {
        if c1 == u32::MAX {
            continue;
        }
        let (a, b) = ((key >> 32) as u32, (key & 0xffff_ffff) as u32);
        if oriented(cells[c0 as usize], a, b) == oriented(cells[c1 as usize], a, b) {
            return Err(MeshError::Overlap { first: c0 as usize, second: c1 as usize, a: a as usize, b: b as usize });
        }
    }
    Ok(())
}

/// Orients edge (a, b) of `cell` so the cell lies on its left (cells are counter-clockwise).
fn oriented(cell: [u32; 3], a: u32, b: u32) -> [u32; 2] {
    for k in 0..3 {
        if cell[k] == a && cell[(k + 1) % 3] == b {
            return [a, b];
        }
    }
    [b, a]
}

/// Every boundary edge (with its tag, or patch 0) and every tagged interior edge.
pub(super) fn patch_edges(
    cells: &[[u32; 3]],
    edges: &EdgeCells,
    tagged: &[([u32; 2], i32)],
) -> Result<Vec<PatchEdge>, MeshError> {
    let mut tags: HashMap<u64, (usize, i32)> = HashMap::with_capacity(tagged.len());
    for (e, &([a, b], patch)) in tagged.iter().enumerate() {
        if edges.get(a, b).is_none() {
            return Err(MeshError::TaggedEdgeNotAnEdge { edge: e, a: a as usize, b: b as usize });
        }
        if let Some(&(_, first)) = tags.get(&edge_key(a, b)) {
            if first != patch {
                return Err(MeshError::TaggedEdgeTwice { edge: e, a: a as usize, b: b as usize, first, second: patch });
            }
        }
        tags.insert(edge_key(a, b), (e, patch));
    }
    let mut out = Vec::new();
    for &(key, [c0, c1]) in &edges.edges {
        let (a, b) = ((key >> 32) as u32, (key & 0xffff_ffff) as u32);
        let tag = tags.get(&key).map(|&(_, p)| p);
        if c1 == u32::MAX {
            out.push(PatchEdge {
                vertices: oriented(cells[c0 as usize], a, b),
                patch: tag.unwrap_or(0),
                interior: false,
            });
        } else if let Some(patch) = tag {
            out.push(PatchEdge { vertices: [a, b], patch, interior: true });
        }
    }
    Ok(out)
}

/// The cells around each vertex (CSR, ascending cell index): a vertex's neighbours are the
/// vertices of these cells, so this serves as the vertex graph at about half its memory.
pub struct VertexCells {
    ptr: Vec<u32>,
    cells: Vec<u32>,
}

impl VertexCells {
    pub fn build(nv: usize, cells: &[[u32; 3]]) -> VertexCells {
        let total = u32::try_from(3 * cells.len()).expect("vertex-cell incidence: more than 2^32 corners");
        let mut ptr = vec![0u32; nv + 1];
        for t in cells {
            for &v in t {
                ptr[v as usize + 1] += 1;
            }
        }
        for i in 0..nv {
            ptr[i + 1] += ptr[i];
        }
        debug_assert_eq!(ptr[nv], total);
        let mut next = ptr.clone();
        let mut inc = vec![0u32; total as usize];
        for (c, t) in cells.iter().enumerate() {
            for &v in t {
                inc[next[v as usize] as usize] = c as u32;
                next[v as usize] += 1;
            }
        }
        VertexCells { ptr, cells: inc }
    }

    /// The cells having `v` as a corner.
    pub fn of(&self, v: usize) -> &[u32] {
        &self.cells[self.ptr[v] as usize..self.ptr[v + 1] as usize]
    }
}
