//! Unknowns ("dofs") of a level: linked vertices merged into one, and vertices of a variant-A
//! interface split into one unknown per region (docs/DESIGN.md §3, last paragraph; §4).

use super::numbering::reverse_cuthill_mckee;
use crate::sparse::bucket_by_key;
use crate::geometry::Corners;
use crate::mesh::Csr;
use crate::Mesh;

/// The unknowns of a mesh. Only the vertex maps are stored in full; how cell corners, linked
/// vertices and split regions map to unknowns is derived from them plus short exception lists
/// (a level's memory is dominated by per-cell and per-unknown arrays).
#[derive(Clone, Debug)]
pub struct Dofs {
    pub n: usize,
    /// One unknown of each vertex (for a split vertex, that of its first cell: all its copies
    /// are prescribed alike).
    pub vertex_dof: Vec<u32>,
    /// A vertex of each unknown (the smallest), for its position and flags.
    pub dof_vertex: Vec<u32>,
    /// Unknowns with more than one vertex (linked vertices), ascending, and their vertices as
    /// CSR (`shared_ptr`); every other unknown has `dof_vertex` alone.
    shared_dofs: Vec<u32>,
    shared_ptr: Vec<u32>,
    shared_vertices: Vec<u32>,
    /// (vertex, region, unknown) of every corner at a split vertex, sorted; empty without splits.
    split_corners: Vec<(u32, i32, u32)>,
    /// (unknown, region) of every split unknown, ascending.
    split_regions: Vec<(u32, i32)>,
    /// Where each connected part of the cells' graph over the unknowns starts (ascending, the
    /// first 0): the numbering gives each part one run. Empty on a level without a mesh.
    part_starts: Vec<u32>,
}

fn find(parent: &mut [u32], mut v: u32) -> u32 {
    while parent[v as usize] != v {
        parent[v as usize] = parent[parent[v as usize] as usize];
        v = parent[v as usize];
    }
    v
}

impl Dofs {
    /// `pairs`: linked vertices; `split_patches`: interior patches whose vertices get one unknown
    /// per adjacent region.
    pub fn build(mesh: &Mesh, pairs: &[[u32; 2]], split_patches: &[i32]) -> Dofs {
        let nv = mesh.num_vertices();
        let mut parent: Vec<u32> = (0..nv as u32).collect();
        for &[a, b] in pairs {
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            // The smaller index becomes the root, so the result does not depend on pair order.
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            parent[hi as usize] = lo;
        }
        let root: Vec<u32> = (0..nv as u32).map(|v| find(&mut parent, v)).collect();
        let mut split = vec![false; nv];
        for e in mesh.patch_faces() {
            if e.interior && split_patches.contains(&e.patch) {
                for &v in e.vertices {
                    split[root[v as usize] as usize] = true;
                }
            }
        }
        // Key of a cell corner: (root vertex, region when split). Unknowns are first numbered in
        // key order (deterministic), then renumbered for locality. Counted per root vertex
        // rather than sorted: one key per used unsplit root, one per region at a split root (a
        // sort of every corner's key would take a third of a million-vertex setup).
        let regions = mesh.regions();
        let mut used = vec![false; nv];
        let mut split_keys: Vec<(u32, i32)> = Vec::new();
        for (c, &region) in regions.iter().enumerate() {
            for &v in mesh.cell(c) {
                let r = root[v as usize];
                used[r as usize] = true;
                if split[r as usize] {
                    split_keys.push((r, region));
                }
            }
        }
        split_keys.sort_unstable();
        split_keys.dedup();
        // base[r]: the first key of root r in key order.
        let mut base = vec![0u32; nv];
        let mut n = 0usize;
        let mut s = 0usize;
        for r in 0..nv {
            base[r] = n as u32;
            if split[r] {
                let e = s + split_keys[s..].partition_point(|k| k.0 as usize == r);
                n += e - s;
                s = e;
            } else if used[r] {
                n += 1;
            }
        }
        // The key-order number of (root r, region when split).
        let key_index = |r: u32, region: i32| -> u32 {
            if !split[r as usize] {
                return base[r as usize];
            }
            let first = split_keys.partition_point(|k| k.0 < r);
            let k = split_keys.binary_search(&(r, region)).expect("key was collected");
            base[r as usize] + (k - first) as u32
        };
        let index = |v: u32, c: usize| key_index(root[v as usize], regions[c]);
        let mut by_vertex = Csr::new();
        // A cell's corners, of any number (a polyhedron's too).
        let mut corners = Vec::new();
        for c in 0..mesh.num_cells() {
            let t = mesh.cell(c);
            corners.clear();
            corners.extend(t.iter().map(|&v| index(v, c)));
            by_vertex.push(&corners);
        }
        // Renumber for locality of the operators' gathers (see `numbering`).
        let (order, part_starts) = reverse_cuthill_mckee(n, &by_vertex);
        let mut new_of = vec![0u32; n];
        for (new, &old) in order.iter().enumerate() {
            new_of[old as usize] = new as u32;
        }
        drop(by_vertex);
        let mut vertex_dof = vec![u32::MAX; nv];
        let mut split_corners: Vec<(u32, i32, u32)> = Vec::new();
        for c in 0..mesh.num_cells() {
            let t = mesh.cell(c);
            corners.clear();
            corners.extend(t.iter().map(|&v| new_of[index(v, c) as usize]));
            let d = &corners;
            for k in 0..t.len() {
                if vertex_dof[t[k] as usize] == u32::MAX {
                    vertex_dof[t[k] as usize] = d[k];
                }
                if split[root[t[k] as usize] as usize] {
                    split_corners.push((t[k], regions[c], d[k]));
                }
            }
        }
        split_corners.sort_unstable();
        split_corners.dedup();
        // The vertices of every unknown (a split vertex belongs to each of its copies), grouped
        // by unknown with a counting sort; each group comes out ascending because vertices are
        // visited in order (an unknown is either unsplit or split, never both).
        let mut member_d: Vec<(u32, u32)> = (0..nv as u32)
            .filter(|&v| vertex_dof[v as usize] != u32::MAX && !split[root[v as usize] as usize])
            .map(|v| (vertex_dof[v as usize], v))
            .collect();
        member_d.extend(split_corners.iter().map(|&(v, _, d)| (d, v)));
        let (ptr, members) = bucket_by_key(n, &member_d);
        drop(member_d);
        let mut dof_vertex = Vec::with_capacity(n);
        let (mut shared_dofs, mut shared_ptr, mut shared_vertices) = (Vec::new(), vec![0u32], Vec::new());
        for d in 0..n {
            let group = &members[ptr[d] as usize..ptr[d + 1] as usize];
            dof_vertex.push(group[0]);
            if group.len() > 1 {
                shared_dofs.push(d as u32);
                shared_vertices.extend_from_slice(group);
                shared_ptr.push(shared_vertices.len() as u32);
            }
        }
        // The split unknowns are split_keys: renumbered, sorted by unknown.
        let mut split_regions: Vec<(u32, i32)> =
            split_keys.iter().map(|&(r, reg)| (new_of[key_index(r, reg) as usize], reg)).collect();
        split_regions.sort_unstable();
        Dofs { n, vertex_dof, dof_vertex, shared_dofs, shared_ptr, shared_vertices, split_corners, split_regions, part_starts }
    }

    /// The unknowns of a level without a mesh: unknown i is its own vertex i.
    pub(crate) fn identity(n: usize) -> Dofs {
        let ids: Vec<u32> = (0..n as u32).collect();
        Dofs {
            n,
            vertex_dof: ids.clone(),
            dof_vertex: ids,
            shared_dofs: Vec::new(),
            shared_ptr: vec![0],
            shared_vertices: Vec::new(),
            split_corners: Vec::new(),
            split_regions: Vec::new(),
            part_starts: Vec::new(),
        }
    }

    /// The unknowns of each connected part of the cells' graph (K's graph) as runs: where each
    /// starts, ascending from 0. None on a level without a mesh (`identity`).
    pub(crate) fn part_starts(&self) -> Option<&[u32]> {
        (!self.part_starts.is_empty()).then_some(&self.part_starts[..])
    }

    /// Every vertex of unknown `d` (several when linked), to gather flags from all.
    pub fn vertices_of(&self, d: usize) -> &[u32] {
        match self.shared_dofs.binary_search(&(d as u32)) {
            Ok(s) => &self.shared_vertices[self.shared_ptr[s] as usize..self.shared_ptr[s + 1] as usize],
            Err(_) => std::slice::from_ref(&self.dof_vertex[d]),
        }
    }

    /// The region of a split unknown; None when the unknown is not split.
    pub fn region_of(&self, d: usize) -> Option<i32> {
        let k = self.split_regions.binary_search_by_key(&(d as u32), |&(d, _)| d).ok()?;
        Some(self.split_regions[k].1)
    }

    /// The unknown of each corner of cell `c` of `mesh`, the mesh these unknowns were built on.
    #[inline]
    pub(crate) fn cell_dofs(&self, mesh: &Mesh, c: usize) -> Corners<u32> {
        let t = mesh.cell(c);
        if self.split_corners.is_empty() {
            return Corners::from_fn(t.len(), |k| self.vertex_dof[t[k] as usize]);
        }
        let r = mesh.regions()[c];
        Corners::from_fn(t.len(), |k| self.corner_dof(t[k], r))
    }

    /// The unknown of each corner of cell `c` of any corner count (a polygon's or a
    /// polyhedron's; [`Dofs::cell_dofs`] holds at most `MAX_CORNERS`).
    pub(crate) fn general_cell_dofs(&self, mesh: &Mesh, c: usize) -> Vec<u32> {
        let r = mesh.regions()[c];
        mesh.cell(c).iter().map(|&v| self.corner_dof(v, r)).collect()
    }

    /// The unknown of vertex `v` as a corner of a cell in region `r`.
    #[inline]
    fn corner_dof(&self, v: u32, r: i32) -> u32 {
        if self.split_corners.is_empty() {
            return self.vertex_dof[v as usize];
        }
        match self.split_corners.binary_search_by(|e| (e.0, e.1).cmp(&(v, r))) {
            Ok(k) => self.split_corners[k].2,
            Err(_) => self.vertex_dof[v as usize],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::fixtures::two_regions;
    use std::collections::BTreeMap;

    /// Links (left and right sides) and a split interface: corners with the same key (root
    /// vertex, region when split) share one unknown, and the derived tables agree with the keys.
    #[test]
    fn derived_tables_match_corner_keys() {
        let m = two_regions(6);
        let x = |v: u32| m.point(v as usize);
        let nv = m.num_vertices() as u32;
        let pairs: Vec<[u32; 2]> = (0..nv)
            .filter(|&a| x(a)[0] == 0.0)
            .map(|a| [a, (0..nv).find(|&b| x(b)[0] == x(a)[0] + 1.0 && x(b)[1] == x(a)[1]).unwrap()])
            .collect();
        let dofs = Dofs::build(&m, &pairs, &[9]);
        let root = |v: u32| pairs.iter().find(|p| p[1] == v).map_or(v, |p| p[0]);
        let split = |v: u32| (x(root(v))[1] - 0.5).abs() < 1e-12;
        let key = |v: u32, c: usize| (root(v), split(v).then(|| m.regions()[c]));
        let mut members: BTreeMap<(u32, Option<i32>), Vec<u32>> = BTreeMap::new();
        for c in 0..m.num_cells() {
            m.cell(c).iter().for_each(|&v| members.entry(key(v, c)).or_default().push(v));
        }
        assert_eq!(dofs.n, members.len());
        // Unknowns are numbered for locality, so corners map to keys one-to-one, in some order.
        let mut key_of: Vec<Option<(u32, Option<i32>)>> = vec![None; dofs.n];
        for c in 0..m.num_cells() {
            let (t, d) = (m.cell(c), dofs.cell_dofs(&m, c));
            for k in 0..3 {
                let e = key_of[d[k] as usize].get_or_insert(key(t[k], c));
                assert_eq!(*e, key(t[k], c), "unknown {} has two keys", d[k]);
            }
        }
        for (d, k) in key_of.iter().enumerate() {
            let k = k.expect("every unknown is a corner's");
            let vs = members.get_mut(&k).expect("a key of the mesh");
            vs.sort_unstable();
            vs.dedup();
            assert_eq!(dofs.vertices_of(d), &vs[..]);
            assert_eq!(dofs.dof_vertex[d], vs[0]);
            assert_eq!(dofs.region_of(d), k.1);
        }
        // Both exception tables are exercised: 7 interface vertices × 2 regions; 7 linked rows,
        // the interface one split in two.
        assert_eq!((dofs.split_corners.len(), dofs.shared_dofs.len()), (14, 8));
    }
}
