//! Boundary features: where the boundary of a mesh stops being smooth.
//!
//! [`BoundaryFeatures`] holds the patch faces as the feature tests see them (each face's area
//! vector and the faces at each vertex) and answers the three questions the solver asks, each
//! with its caller's angle:
//! - the smooth pieces of the boundary (faces joined across ridges where their normals turn by
//!   less than an angle; `pieces`), which the least-squares coarsener's interpolation respects;
//! - the 2D corners (a vertex where the boundary chain turns by more than an angle, changes
//!   patch or side, or branches; `is_chain_corner`), which the vertex-removal coarsener keeps;
//! - the walls at a vertex (its faces' area vectors grouped by normal angle; `wall_normals`),
//!   whose normals the slip frames constrain.
//!
//! The three tests differ on purpose: the slip walls ignore a face's orientation (a wall is a
//! plane, either side) and weight by area, the pieces compare unit normals of oriented faces,
//! and the 2D corners compare the turn of the chain's segments whatever their orientation (the
//! faces between regions keep the orientation they are given).

use crate::Mesh;
use std::collections::hash_map::Entry;
use std::collections::HashMap;

/// The patch faces of a mesh with their area vectors and the faces at each vertex.
pub(crate) struct BoundaryFeatures<'a> {
    mesh: &'a Mesh,
    /// Area vector of each patch face (`geometry::face_area_vector`), pointing out of the domain
    /// for boundary faces.
    area: Vec<[f64; 3]>,
    /// The patch faces at vertex v: `at[at_ptr[v]..at_ptr[v + 1]]`, ascending.
    at_ptr: Vec<usize>,
    at: Vec<u32>,
}

impl<'a> BoundaryFeatures<'a> {
    /// The patch faces of `mesh`.
    pub(crate) fn new(mesh: &'a Mesh) -> BoundaryFeatures<'a> {
        let nv = mesh.num_vertices();
        let area = mesh.patch_faces().map(|f| face_area_vector(mesh, f.vertices)).collect();
        let mut at_ptr = vec![0usize; nv + 1];
        for f in mesh.patch_faces() {
            for &v in f.vertices {
                at_ptr[v as usize + 1] += 1;
            }
        }
        for i in 0..nv {
            at_ptr[i + 1] += at_ptr[i];
        }
        let mut next = at_ptr.clone();
        let mut at = vec![0u32; at_ptr[nv]];
        for (k, f) in mesh.patch_faces().enumerate() {
            for &v in f.vertices {
                at[next[v as usize]] = k as u32;
                next[v as usize] += 1;
            }
        }
        BoundaryFeatures { mesh, area, at_ptr, at }
    }

    /// The number of patch faces.
    pub(crate) fn len(&self) -> usize {
        self.area.len()
    }

    /// Patch face `k`.
    pub(crate) fn face(&self, k: usize) -> crate::mesh::PatchFace<'a> {
        self.mesh.patch_face(k)
    }

    /// The area vector of patch face `k`.
    pub(crate) fn area(&self, k: usize) -> [f64; 3] {
        self.area[k]
    }

    /// The patch faces at vertex `v`, ascending.
    pub(crate) fn faces_at(&self, v: usize) -> &[u32] {
        &self.at[self.at_ptr[v]..self.at_ptr[v + 1]]
    }

    /// The smooth piece of every patch face, numbered by first face: faces of one patch and side
    /// meeting at a ridge (a vertex in 2D, an edge in 3D) join when their unit normals turn by at
    /// most `corner_angle_deg`; the two sides of a link pair (periodic sides) join when their
    /// normals are opposite within that angle. Returns the pieces and their number.
    pub(crate) fn pieces(&self, corner_angle_deg: f64, pairs: &[[u32; 2]]) -> (Vec<u32>, u32) {
        let mesh = self.mesh;
        let dim = mesh.dim();
        let normals: Vec<[f64; 3]> = self.area.iter().map(|&a| unit(a)).collect();
        let mut parent: Vec<u32> = (0..self.len() as u32).collect();
        let cos_corner = corner_angle_deg.to_radians().cos();
        let mut at_ridge: HashMap<[u32; 2], u32> = HashMap::new();
        for (k, f) in mesh.patch_faces().enumerate() {
            let nf = f.vertices.len();
            for r in 0..nf {
                let key = if dim == 2 {
                    [f.vertices[r], u32::MAX]
                } else {
                    let (a, b) = (f.vertices[r], f.vertices[(r + 1) % nf]);
                    [a.min(b), a.max(b)]
                };
                match at_ridge.entry(key) {
                    Entry::Vacant(e) => {
                        e.insert(k as u32);
                    }
                    Entry::Occupied(e) => {
                        let j = *e.get() as usize;
                        let g = mesh.patch_face(j);
                        if g.patch == f.patch && g.interior == f.interior && dot(normals[j], normals[k]) >= cos_corner {
                            union(&mut parent, j as u32, k as u32);
                        }
                    }
                }
            }
        }
        // Linked vertices put their two sides' pieces together (a periodic side is one piece);
        // each vertex speaks for the last face it lies on.
        let last_face = |v: u32| self.faces_at(v as usize).last().copied();
        for &[a, b] in pairs {
            if let (Some(fa), Some(fb)) = (last_face(a), last_face(b)) {
                if dot(normals[fa as usize], normals[fb as usize]) <= -cos_corner {
                    union(&mut parent, fa, fb);
                }
            }
        }
        let mut piece_of_root = vec![u32::MAX; self.len()];
        let mut n_pieces = 0u32;
        let piece = (0..self.len() as u32)
            .map(|k| {
                let r = find(&mut parent, k) as usize;
                if piece_of_root[r] == u32::MAX {
                    piece_of_root[r] = n_pieces;
                    n_pieces += 1;
                }
                piece_of_root[r]
            })
            .collect();
        (piece, n_pieces)
    }

    /// Whether vertex `v` of a 2D mesh is a corner of the boundary chains: it lies on patch
    /// faces but not on exactly two of one patch and side, or the chain turns there by more than
    /// `corner_angle_deg` (the segments' directions along the chain, whatever the faces'
    /// orientation), or a segment has zero length.
    pub(crate) fn is_chain_corner(&self, v: usize, corner_angle_deg: f64, x: &[glam::DVec2]) -> bool {
        let es = self.faces_at(v);
        if es.len() != 2 {
            return !es.is_empty();
        }
        let (e1, e2) = (self.face(es[0] as usize), self.face(es[1] as usize));
        if e1.patch != e2.patch || e1.interior != e2.interior {
            return true;
        }
        let other = |f: &[u32]| if f[0] == v as u32 { f[1] } else { f[0] };
        let (u, w) = (other(e1.vertices), other(e2.vertices));
        let d1 = x[v] - x[u as usize];
        let d2 = x[w as usize] - x[v];
        let (l1, l2) = (d1.length(), d2.length());
        let cos_corner = corner_angle_deg.to_radians().cos();
        l1 == 0.0 || l2 == 0.0 || d1.dot(d2) < cos_corner * l1 * l2
    }
}

/// Groups area vectors (the faces at one place, in a fixed order) into walls: a vector joins the
/// first wall whose summed normal is within `feature_angle_deg` of it (either orientation), else
/// starts a wall. Returns each wall's unit normal, heaviest wall first (ties in order of
/// appearance).
pub(crate) fn wall_normals(areas: &[[f64; 3]], feature_angle_deg: f64) -> Vec<[f64; 3]> {
    let cos_feature = feature_angle_deg.to_radians().cos();
    let mut sums: Vec<[f64; 3]> = Vec::new();
    let mut weights: Vec<f64> = Vec::new();
    for &a in areas {
        let len = dot(a, a).sqrt();
        if len == 0.0 {
            continue;
        }
        let found = sums.iter().position(|&s| dot(s, a).abs() >= cos_feature * len * dot(s, s).sqrt());
        match found {
            Some(k) => {
                let sign = if dot(sums[k], a) < 0.0 { -1.0 } else { 1.0 };
                (0..3).for_each(|c| sums[k][c] += sign * a[c]);
                weights[k] += len;
            }
            None => {
                sums.push(a);
                weights.push(len);
            }
        }
    }
    let mut order: Vec<usize> = (0..sums.len()).collect();
    order.sort_by(|&i, &j| weights[j].total_cmp(&weights[i]).then(i.cmp(&j)));
    order
        .into_iter()
        .filter_map(|k| {
            let s = sums[k];
            let l = dot(s, s).sqrt();
            (l > 0.0).then(|| s.map(|x| x / l))
        })
        .collect()
}

/// The area vector of a patch face (2D: the segment's right-hand normal times its length; 3D:
/// Newell's vector, the polygon's normal times its area), pointing out of the domain for a
/// boundary face.
fn face_area_vector(mesh: &Mesh, vertices: &[u32]) -> [f64; 3] {
    crate::geometry::face_area_vector(mesh.dim(), vertices.len(), |k| {
        let x = mesh.point(vertices[k] as usize);
        [x[0], x[1], if x.len() > 2 { x[2] } else { 0.0 }]
    })
}

/// `a` normalised (a zero vector stays zero). Scaling an area vector by ½ is exact, so the unit
/// vector does not depend on whether the area or twice it is given.
fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    if l > 0.0 {
        [a[0] / l, a[1] / l, a[2] / l]
    } else {
        a
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn find(parent: &mut [u32], mut v: u32) -> u32 {
    while parent[v as usize] != v {
        parent[v as usize] = parent[parent[v as usize] as usize];
        v = parent[v as usize];
    }
    v
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    parent[ra.max(rb) as usize] = ra.min(rb);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walls_merge_a_curve_and_split_a_corner() {
        let a = |t: f64| [t.cos(), t.sin(), 0.0];
        // Two segments of a 16-gon: one wall; two sides of a box: two walls.
        assert_eq!(wall_normals(&[a(0.0), a(std::f64::consts::TAU / 16.0)], 30.0).len(), 1);
        assert_eq!(wall_normals(&[[1.0, 0.0, 0.0], [0.0, 2.0, 0.0]], 30.0).len(), 2);
        // Opposite orientations of one plane: one wall.
        assert_eq!(wall_normals(&[[0.0, 0.0, 1.0], [0.0, 0.0, -3.0]], 30.0), vec![[0.0, 0.0, 1.0]]);
    }
}
