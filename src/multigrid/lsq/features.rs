//! Where each unknown lies: inside the domain, or on smooth pieces of the boundary.
//!
//! A piece is a connected set of patch faces of one patch whose normals turn by less than the
//! corner angle from face to neighbouring face (a sphere is one piece, a box's walls are six).
//! An unknown on one piece lies on a surface (3D) or a curve (2D), on two pieces on a crease
//! (3D) or at a corner (2D), on three or more at a corner. An unknown interpolates only from
//! coarse unknowns that lie on every piece it lies on, so corrections along a wall stay on the
//! wall and a prescribed component stays prescribed (docs/DESIGN.md §5).

use crate::bc::Dofs;
use crate::mesh::features::BoundaryFeatures;
use crate::mesh::Mesh;
use std::collections::HashMap;
use std::sync::Arc;

/// The pieces each unknown lies on, and its region, for one level.
#[derive(Clone, Debug)]
pub(crate) struct Features {
    /// Sorted piece lists, interned; list 0 is empty (inside the domain).
    sets: Arc<Vec<Vec<u32>>>,
    /// The piece list of each unknown.
    set_of: Vec<u32>,
    /// The region of each unknown when it lies in one (or is one region's copy of a split
    /// interface vertex); None on an interface shared by regions.
    region: Vec<Option<i32>>,
    /// The unknown stands for several vertices (linked by a periodic offset).
    linked: Vec<bool>,
    /// The offsets between linked vertices (both signs, and sums of two for the corners of
    /// doubly periodic meshes): a linked unknown's neighbour may sit one offset away.
    offsets: Arc<Vec<[f64; 3]>>,
    /// Space dimension.
    dim: usize,
    /// Every unknown lies on the boundary (`one_layer`).
    all_on_boundary: bool,
    /// The level is coarsened within the planes of its layer (`in_plane`).
    in_plane: bool,
}

impl Features {
    /// The features of the unknowns `dofs` of `mesh` (with its link pairs and the regions of
    /// the unknowns), pieces separated where normals turn by more than `corner_angle_deg`.
    pub(crate) fn build(
        mesh: &Mesh,
        dofs: &Dofs,
        pairs: &[[u32; 2]],
        region: Vec<Option<i32>>,
        corner_angle_deg: f64,
    ) -> Features {
        let dim = mesh.dim();
        let boundary = BoundaryFeatures::new(mesh);
        let (piece, _) = boundary.pieces(corner_angle_deg, pairs);
        let mut vertex_pieces: Vec<Vec<u32>> = vec![Vec::new(); mesh.num_vertices()];
        for (v, pieces) in vertex_pieces.iter_mut().enumerate() {
            pieces.extend(boundary.faces_at(v).iter().map(|&k| piece[k as usize]));
        }
        let mut sets = vec![Vec::new()];
        let mut index: HashMap<Vec<u32>, u32> = HashMap::from([(Vec::new(), 0)]);
        let mut linked = vec![false; dofs.n];
        let set_of: Vec<u32> = (0..dofs.n)
            .map(|d| {
                let vs = dofs.vertices_of(d);
                linked[d] = vs.len() > 1;
                let mut s: Vec<u32> = vs.iter().flat_map(|&v| vertex_pieces[v as usize].iter().copied()).collect();
                if s.is_empty() {
                    // Inside the domain: list 0, without a look-up.
                    return 0;
                }
                s.sort_unstable();
                s.dedup();
                *index.entry(s).or_insert_with_key(|s| {
                    sets.push(s.clone());
                    sets.len() as u32 - 1
                })
            })
            .collect();
        let offsets = link_offsets(mesh, pairs);
        let all_on_boundary = set_of.iter().all(|&s| s != 0);
        Features { sets: Arc::new(sets), set_of, region, linked, offsets: Arc::new(offsets), dim, all_on_boundary, in_plane: false }
    }

    /// The features of the unknowns `kept` (ascending) of this level, for the next coarser one.
    pub(crate) fn subset(&self, kept: &[u32]) -> Features {
        let pick = |k: &u32| *k as usize;
        Features {
            sets: Arc::clone(&self.sets),
            set_of: kept.iter().map(|k| self.set_of[pick(k)]).collect(),
            region: kept.iter().map(|k| self.region[pick(k)]).collect(),
            linked: kept.iter().map(|k| self.linked[pick(k)]).collect(),
            offsets: Arc::clone(&self.offsets),
            dim: self.dim,
            all_on_boundary: self.all_on_boundary,
            in_plane: false,
        }
    }

    /// Whether every unknown lies on the boundary: a layer one cell thick, as a quasi-2D
    /// finite-volume mesh between two symmetry planes is. When its unknowns couple most
    /// strongly across the thickness, to unknowns on the other plane that may not interpolate
    /// them, the general rule drops none, and it is coarsened within each plane instead
    /// (`set_in_plane`).
    pub(crate) fn one_layer(&self) -> bool {
        self.all_on_boundary
    }

    /// Whether this level is coarsened within the planes of its layer (`lsq::strong`,
    /// `lsq::select`).
    pub(crate) fn in_plane(&self) -> bool {
        self.in_plane
    }

    /// Coarsens this level (a `one_layer` level) within the planes of its layer.
    pub(crate) fn set_in_plane(&mut self) {
        self.in_plane = true;
    }

    /// The space dimension.
    pub(crate) fn dim(&self) -> usize {
        self.dim
    }

    /// The dimension of the feature unknown `d` lies on: the space's inside, one less per piece,
    /// down to 0 (a corner).
    pub(crate) fn feature_dim(&self, d: usize) -> usize {
        let s = self.sets[self.set_of[d] as usize].len();
        if s == 0 {
            self.dim
        } else {
            self.dim.saturating_sub(s)
        }
    }

    /// Whether unknown `u` may take part in interpolating unknown `v`: it lies on every piece
    /// `v` lies on, and in `v`'s region (or on an interface of it).
    #[inline]
    pub(crate) fn donor_ok(&self, v: usize, u: usize) -> bool {
        let (sv, su) = (self.set_of[v], self.set_of[u]);
        let pieces_ok = sv == 0 || sv == su || is_subset(&self.sets[sv as usize], &self.sets[su as usize]);
        pieces_ok && (self.region[v].is_none() || self.region[u].is_none() || self.region[u] == self.region[v])
    }

    /// The position of `u` relative to `v` given their stored positions: the difference, or for
    /// a linked unknown the shortest of the differences shifted by a link offset.
    #[inline]
    pub(crate) fn relative(&self, v: usize, u: usize, pv: &[f64], pu: &[f64]) -> [f64; 3] {
        let mut r = [0.0; 3];
        for k in 0..self.dim {
            r[k] = pu[k] - pv[k];
        }
        if !(self.linked[v] || self.linked[u]) {
            return r;
        }
        let mut best = r;
        for o in self.offsets.iter() {
            let s = [r[0] + o[0], r[1] + o[1], r[2] + o[2]];
            if dot(s, s) < dot(best, best) {
                best = s;
            }
        }
        best
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn is_subset(a: &[u32], b: &[u32]) -> bool {
    a.iter().all(|x| b.binary_search(x).is_ok())
}

/// The distinct offsets between linked vertices, both signs, and the sums of two different
/// ones (a vertex on two periodic sides links across both).
fn link_offsets(mesh: &Mesh, pairs: &[[u32; 2]]) -> Vec<[f64; 3]> {
    let mut base: Vec<[f64; 3]> = Vec::new();
    for &[a, b] in pairs {
        let (pa, pb) = (mesh.point(a as usize), mesh.point(b as usize));
        let mut o = [0.0; 3];
        for k in 0..mesh.dim() {
            o[k] = pa[k] - pb[k];
        }
        let scale = dot(o, o).sqrt();
        let same = |q: &[f64; 3]| {
            let d = [q[0] - o[0], q[1] - o[1], q[2] - o[2]];
            dot(d, d).sqrt() <= 1e-6 * scale
        };
        if scale > 0.0 && !base.iter().any(same) {
            base.push(o);
        }
    }
    let mut all: Vec<[f64; 3]> = Vec::new();
    for o in &base {
        all.push(*o);
        all.push([-o[0], -o[1], -o[2]]);
    }
    let singles = all.clone();
    for (i, a) in singles.iter().enumerate() {
        for b in &singles[i + 1..] {
            let s = [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
            if dot(s, s) > 1e-12 * dot(*a, *a) {
                all.push(s);
            }
        }
    }
    all
}
