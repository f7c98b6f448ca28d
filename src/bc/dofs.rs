//! Unknowns ("dofs") of a level: linked vertices merged into one, and vertices of a variant-A
//! interface split into one unknown per region (DESIGN §3, last paragraph; §4).

use super::numbering::reverse_cuthill_mckee;
use crate::Mesh;

#[derive(Clone, Debug)]
pub struct Dofs {
    pub n: usize,
    /// The unknown of each cell corner.
    pub cell_dofs: Vec<[u32; 3]>,
    /// One unknown of each vertex (for a split vertex, that of its first cell: all its copies
    /// are prescribed alike).
    pub vertex_dof: Vec<u32>,
    /// A vertex of each unknown (the smallest), for its position and flags.
    pub dof_vertex: Vec<u32>,
    /// Every vertex of each unknown, as CSR (`dof_vertices_ptr`), to gather flags from all.
    pub dof_vertices_ptr: Vec<u32>,
    pub dof_vertices: Vec<u32>,
    /// The region of a split unknown; None when the unknown is not split.
    pub dof_region: Vec<Option<i32>>,
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
        for e in mesh.patch_edges() {
            if e.interior && split_patches.contains(&e.patch) {
                for v in e.vertices {
                    split[root[v as usize] as usize] = true;
                }
            }
        }
        // Key of a cell corner: (root vertex, region when split). Sorting keys numbers unknowns
        // in vertex order, deterministically; they are then renumbered for locality.
        const NONE: i64 = i64::MIN;
        let key = |v: u32, c: usize| -> (u32, i64) {
            let r = root[v as usize];
            (r, if split[r as usize] { mesh.regions()[c] as i64 } else { NONE })
        };
        let mut keys: Vec<(u32, i64)> = Vec::with_capacity(nv);
        for (c, t) in mesh.cells().iter().enumerate() {
            keys.extend(t.iter().map(|&v| key(v, c)));
        }
        keys.sort_unstable();
        keys.dedup();
        let index = |k: (u32, i64)| keys.binary_search(&k).expect("key was collected") as u32;
        let by_vertex: Vec<[u32; 3]> =
            mesh.cells().iter().enumerate().map(|(c, t)| t.map(|v| index(key(v, c)))).collect();
        // Renumber for locality of the operators' gathers (see `numbering`).
        let order = reverse_cuthill_mckee(keys.len(), &by_vertex);
        let mut new_of = vec![0u32; keys.len()];
        for (new, &old) in order.iter().enumerate() {
            new_of[old as usize] = new as u32;
        }
        let cell_dofs: Vec<[u32; 3]> = by_vertex.iter().map(|t| t.map(|d| new_of[d as usize])).collect();
        let keys: Vec<(u32, i64)> = order.iter().map(|&old| keys[old as usize]).collect();
        let mut vertex_dof = vec![u32::MAX; nv];
        for (t, d) in mesh.cells().iter().zip(&cell_dofs) {
            for k in 0..3 {
                if vertex_dof[t[k] as usize] == u32::MAX {
                    vertex_dof[t[k] as usize] = d[k];
                }
            }
        }
        let n = keys.len();
        // Gather the vertices of every unknown (a split vertex belongs to each of its copies).
        let mut members: Vec<(u32, u32)> = Vec::with_capacity(nv);
        for (t, d) in mesh.cells().iter().zip(&cell_dofs) {
            for k in 0..3 {
                members.push((d[k], t[k]));
            }
        }
        members.sort_unstable();
        members.dedup();
        let mut dof_vertices_ptr = vec![0u32; n + 1];
        for &(d, _) in &members {
            dof_vertices_ptr[d as usize + 1] += 1;
        }
        for i in 0..n {
            dof_vertices_ptr[i + 1] += dof_vertices_ptr[i];
        }
        let dof_vertices: Vec<u32> = members.iter().map(|&(_, v)| v).collect();
        let dof_vertex = (0..n).map(|d| dof_vertices[dof_vertices_ptr[d] as usize]).collect();
        let dof_region = keys.iter().map(|&(_, r)| (r != NONE).then_some(r as i32)).collect();
        Dofs { n, cell_dofs, vertex_dof, dof_vertex, dof_vertices_ptr, dof_vertices, dof_region }
    }

    pub fn vertices_of(&self, d: usize) -> &[u32] {
        &self.dof_vertices[self.dof_vertices_ptr[d] as usize..self.dof_vertices_ptr[d + 1] as usize]
    }
}
