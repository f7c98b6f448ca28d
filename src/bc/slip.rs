//! Slip frames (docs/DESIGN.md §4, "Slip walls"): for every unknown on a SLIP wall, the
//! directions its displacement is constrained in (the wall's normal; two normals on a 3D edge
//! where two walls meet), orthonormal, from the area-weighted normals of the reference mesh's
//! wall faces.
//!
//! The solve works in the subspace these directions leave free: Π projects them out of each
//! slip unknown's vector (all components together), the operator is Π A Π and the values along
//! the directions are prescribed. Coarse levels inherit the frames of the fine unknowns their
//! vertices are (coarse vertices are fine vertices).

use super::{BoundaryConditions, Dofs, P};
use crate::mesh::features::{wall_normals, BoundaryFeatures};
use crate::Mesh;

/// Two wall faces at a vertex belong to one wall (one constrained direction) when their normals
/// differ by less than this angle; beyond it the vertex is on a feature (a corner, an edge) where
/// two walls meet and each wall constrains its own direction. 30° separates the polygon of a
/// coarsely meshed circle (12 segments or more) from the corners of a box.
pub const FEATURE_ANGLE_DEG: f64 = 30.0;

/// A direction whose part orthogonal to the directions already constrained is shorter than this
/// (relative) adds nothing: it lies in their span.
const SPAN_TOL: f64 = 1e-6;

/// A unit direction whose other components are at most this is a coordinate axis: the rounding
/// of an area vector summed over faces normal to the axis.
const AXIS_TOL: f64 = 1e-13;

/// The constrained directions of the slip unknowns of one level.
#[derive(Clone, Debug, PartialEq)]
pub struct SlipFrames {
    /// Components of a displacement (2 or 3).
    pub dim: usize,
    /// The slip unknowns, ascending.
    pub dofs: Vec<u32>,
    /// Constrained directions of slip unknown k: `dirs[ptr[k]..ptr[k + 1]]`, orthonormal, and
    /// orthogonal to the axes of the components the unknown has prescribed (P).
    ptr: Vec<u32>,
    dirs: Vec<[f64; 3]>,
    /// Unknowns on a slip wall whose constraints span every direction (a 2D corner between two
    /// walls, a 3D corner of three): prescribed in every component (P), not slip.
    pub pinned: Vec<u32>,
    /// Slip unknowns whose constrained directions are coordinate axes (walls normal to an axis:
    /// a straight channel's, a box's, a symmetry plane), with the mask of those axes: the
    /// components along them are prescribed (P) and the others free, which is the same
    /// constraint, so these unknowns do not couple the components and a mesh whose slip walls
    /// are all such is solved one component at a time. Ascending.
    pub axes: Vec<(u32, u8)>,
}

/// How a slip unknown is constrained: by the directions of its frame (number `k` of `dofs`), or by
/// the coordinate axes its walls are normal to (a mask of components, prescribed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Constraint {
    /// Frame `k`.
    Frame(usize),
    /// The components of the mask.
    Axes(u8),
}

impl SlipFrames {
    /// Frames of `dim` components with no slip unknown (a rank whose part touches no slip wall
    /// while another rank's walls couple the components).
    #[cfg(feature = "mpi")]
    pub(crate) fn empty(dim: usize) -> SlipFrames {
        SlipFrames { dim, dofs: Vec::new(), ptr: vec![0], dirs: Vec::new(), pinned: Vec::new(), axes: Vec::new() }
    }

    /// Every slip unknown, the framed ones first, then the axis ones, with its constraint.
    pub fn constrained(&self) -> impl Iterator<Item = (u32, Constraint)> + '_ {
        let framed = self.dofs.iter().enumerate().map(|(k, &d)| (d, Constraint::Frame(k)));
        framed.chain(self.axes.iter().map(|&(d, mask)| (d, Constraint::Axes(mask))))
    }

    /// How many directions `c` constrains.
    pub fn count(&self, c: Constraint) -> usize {
        match c {
            Constraint::Frame(k) => self.directions(k).len(),
            Constraint::Axes(mask) => mask.count_ones() as usize,
        }
    }

    /// Whether the displacement `v` (`dim` values) has a part along the directions `c` constrains.
    pub fn has_normal_part(&self, c: Constraint, v: &[f64]) -> bool {
        match c {
            Constraint::Frame(k) => {
                let mut y = [0.0; 3];
                y[..self.dim].copy_from_slice(&v[..self.dim]);
                self.normal_part(k, &y).iter().any(|&a| a != 0.0)
            }
            Constraint::Axes(mask) => (0..self.dim).any(|c| mask & 1 << c != 0 && v[c] != 0.0),
        }
    }

    /// The constrained directions of slip unknown number `k` (an index into `dofs`).
    pub fn directions(&self, k: usize) -> &[[f64; 3]] {
        &self.dirs[self.ptr[k] as usize..self.ptr[k + 1] as usize]
    }

    /// The mask of the axes unknown `d`'s walls prescribe, if it is an axis unknown.
    pub fn axes_of(&self, d: u32) -> Option<u8> {
        self.axes.binary_search_by_key(&d, |e| e.0).ok().map(|k| self.axes[k].1)
    }

    /// The directions of unknown `d`, if it is a slip unknown.
    pub fn directions_of(&self, d: u32) -> Option<&[[f64; 3]]> {
        self.dofs.binary_search(&d).ok().map(|k| self.directions(k))
    }

    /// u ← Π u: the constrained directions removed from every slip unknown of `u`, a vector of
    /// `dim` blocks of `n` values (component-major).
    pub fn project(&self, n: usize, u: &mut [f64]) {
        debug_assert_eq!(u.len(), self.dim * n);
        for (k, &d) in self.dofs.iter().enumerate() {
            let mut v = self.gather(n, u, d);
            for e in self.directions(k) {
                let a = dot(e, &v);
                (0..3).for_each(|c| v[c] -= a * e[c]);
            }
            self.scatter(n, u, d, &v);
        }
    }

    /// As `project`, on a vector given as one slice of n values per component.
    pub fn project_blocks(&self, blocks: &mut [&mut [f64]]) {
        debug_assert_eq!(blocks.len(), self.dim);
        for (k, &d) in self.dofs.iter().enumerate() {
            let mut v = [0.0; 3];
            (0..self.dim).for_each(|c| v[c] = blocks[c][d as usize]);
            for e in self.directions(k) {
                let a = dot(e, &v);
                (0..3).for_each(|c| v[c] -= a * e[c]);
            }
            (0..self.dim).for_each(|c| blocks[c][d as usize] = v[c]);
        }
    }

    /// The prescribed part of a displacement `v` at slip unknown number `k`: its components along
    /// the constrained directions, Σ (e · v) e.
    pub fn normal_part(&self, k: usize, v: &[f64; 3]) -> [f64; 3] {
        let mut out = [0.0; 3];
        for e in self.directions(k) {
            let a = dot(e, v);
            (0..3).for_each(|c| out[c] += a * e[c]);
        }
        out
    }

    /// A basis of the free (tangential) directions of slip unknown number `k`, given the
    /// components `p_axes` it has prescribed: orthonormal, orthogonal to both.
    pub fn tangents(&self, k: usize, prescribed: &[bool]) -> Vec<[f64; 3]> {
        let mut taken: Vec<[f64; 3]> = self.directions(k).to_vec();
        taken.extend((0..self.dim).filter(|&c| prescribed[c]).map(axis));
        let mut out = Vec::new();
        for c in 0..self.dim {
            if let Some(t) = orthogonal_part(&axis(c), &taken, self.dim) {
                taken.push(t);
                out.push(t);
            }
        }
        out
    }

    fn gather(&self, n: usize, u: &[f64], d: u32) -> [f64; 3] {
        let mut v = [0.0; 3];
        (0..self.dim).for_each(|c| v[c] = u[c * n + d as usize]);
        v
    }

    fn scatter(&self, n: usize, u: &mut [f64], d: u32, v: &[f64; 3]) {
        (0..self.dim).for_each(|c| u[c * n + d as usize] = v[c]);
    }
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn axis(c: usize) -> [f64; 3] {
    let mut e = [0.0; 3];
    e[c] = 1.0;
    e
}

/// The unit part of `v` orthogonal to the orthonormal `basis`, or None when `v` lies in its span.
fn orthogonal_part(v: &[f64; 3], basis: &[[f64; 3]], dim: usize) -> Option<[f64; 3]> {
    let len0 = dot(v, v).sqrt();
    if basis.len() >= dim || len0 == 0.0 {
        return None;
    }
    let mut w = *v;
    // Twice, for orthogonality to rounding (classical Gram–Schmidt, reorthogonalised).
    for _ in 0..2 {
        for b in basis {
            let a = dot(b, &w);
            (0..3).for_each(|c| w[c] -= a * b[c]);
        }
    }
    let len = dot(&w, &w).sqrt();
    (len > SPAN_TOL * len0).then(|| w.map(|x| x / len))
}

/// What the frames of a level add to its flags and directions, before they are stored.
struct Builder {
    dim: usize,
    dofs: Vec<u32>,
    ptr: Vec<u32>,
    dirs: Vec<[f64; 3]>,
    pinned: Vec<u32>,
    axes: Vec<(u32, u8)>,
}

/// The mask of the coordinate axes `dirs` are, or None when one of them is not an axis.
fn axis_mask(dirs: &[[f64; 3]]) -> Option<u8> {
    dirs.iter().try_fold(0u8, |mask, e| {
        let c = (0..3).max_by(|&a, &b| e[a].abs().total_cmp(&e[b].abs())).expect("three components");
        (0..3).all(|k| k == c || e[k].abs() <= AXIS_TOL).then_some(mask | 1 << c)
    })
}

impl Builder {
    fn new(dim: usize) -> Builder {
        Builder { dim, dofs: Vec::new(), ptr: vec![0], dirs: Vec::new(), pinned: Vec::new(), axes: Vec::new() }
    }

    /// Adds unknown `d` with its candidate wall normals, orthogonalised against the axes of its
    /// prescribed components (`flags`, per component); an unknown whose constraints span every
    /// direction is pinned, one with no constraint left is not slip, one whose constraints are
    /// coordinate axes is an axis unknown when `axes_ok`.
    fn push(&mut self, d: u32, normals: &[[f64; 3]], flags: &[Vec<u8>], axes_ok: bool) {
        let dim = self.dim;
        let prescribed: Vec<bool> = (0..dim).map(|c| flags[c][d as usize] & P != 0).collect();
        if prescribed.iter().all(|&p| p) {
            return;
        }
        let mut basis: Vec<[f64; 3]> = (0..dim).filter(|&c| prescribed[c]).map(axis).collect();
        let mut dirs = Vec::new();
        for nrm in normals {
            if let Some(e) = orthogonal_part(nrm, &basis, dim) {
                basis.push(e);
                dirs.push(e);
            }
        }
        if dirs.is_empty() {
            return;
        }
        if basis.len() == dim {
            self.pinned.push(d);
            return;
        }
        if let Some(mask) = axis_mask(&dirs).filter(|_| axes_ok) {
            self.axes.push((d, mask));
            return;
        }
        self.dofs.push(d);
        self.dirs.extend(dirs);
        self.ptr.push(self.dirs.len() as u32);
    }

    /// The frames, with every pinned unknown made P in every component of `flags` and every
    /// unknown on walls normal to axes in those axes' components; None when no unknown is slip
    /// or pinned.
    fn finish(self, flags: &mut [Vec<u8>]) -> Option<SlipFrames> {
        for &d in &self.pinned {
            flags.iter_mut().for_each(|f| f[d as usize] |= P);
        }
        for &(d, mask) in &self.axes {
            flags.iter_mut().enumerate().filter(|(c, _)| mask & 1 << c != 0).for_each(|(_, f)| f[d as usize] |= P);
        }
        if self.dofs.is_empty() && self.pinned.is_empty() && self.axes.is_empty() {
            return None;
        }
        let Builder { dim, dofs, ptr, dirs, pinned, axes } = self;
        Some(SlipFrames { dim, dofs, ptr, dirs, pinned, axes })
    }
}

/// The area vectors of the SLIP faces at each vertex of a mesh, in face order.
pub(crate) struct WallAreas<'a> {
    boundary: BoundaryFeatures<'a>,
    /// Whether each patch face is on a SLIP patch.
    slip: Vec<bool>,
}

impl<'a> WallAreas<'a> {
    /// The SLIP faces of `mesh` under `bcs`.
    pub(crate) fn new(mesh: &'a Mesh, bcs: &BoundaryConditions) -> WallAreas<'a> {
        let boundary = BoundaryFeatures::new(mesh);
        let slip = (0..boundary.len()).map(|k| bcs.is_slip(boundary.face(k).patch)).collect();
        WallAreas { boundary, slip }
    }

    /// Whether some face is on a SLIP patch.
    pub(crate) fn any(&self) -> bool {
        self.slip.iter().any(|&s| s)
    }

    /// The area vectors of the SLIP faces at vertex `v`, in face order.
    pub(crate) fn at(&self, v: usize) -> impl Iterator<Item = [f64; 3]> + '_ {
        let faces = self.boundary.faces_at(v).iter().filter(|&&k| self.slip[k as usize]);
        faces.map(|&k| self.boundary.area(k as usize))
    }
}

/// The slip frames of the fine level: for every unknown with a vertex on a SLIP patch, the walls
/// its vertices' SLIP faces form (`wall_normals`), their normals as constrained directions. Pinned
/// unknowns are made P in every component of `flags`. None when the conditions have no SLIP wall.
pub(crate) fn fine_slip_frames(
    mesh: &Mesh,
    dofs: &Dofs,
    bcs: &BoundaryConditions,
    flags: &mut [Vec<u8>],
) -> Option<SlipFrames> {
    let walls = WallAreas::new(mesh, bcs);
    if !walls.any() {
        return None;
    }
    let areas = |d: usize, out: &mut Vec<[f64; 3]>| {
        dofs.vertices_of(d).iter().for_each(|&v| out.extend(walls.at(v as usize)));
    };
    slip_frames_from_areas(mesh.dim(), dofs.n, areas, flags)
}

/// The slip frames of `n` unknowns of dimension `dim` whose SLIP faces' area vectors `areas(d,
/// out)` appends (in a fixed order; none off the walls): the walls they form (`wall_normals`),
/// their normals as constrained directions. Pinned unknowns are made P in every component of
/// `flags`. None when no unknown is slip or pinned.
pub(crate) fn slip_frames_from_areas(
    dim: usize,
    n: usize,
    areas: impl Fn(usize, &mut Vec<[f64; 3]>),
    flags: &mut [Vec<u8>],
) -> Option<SlipFrames> {
    let mut b = Builder::new(dim);
    let mut normals: Vec<[f64; 3]> = Vec::new();
    for d in 0..n {
        normals.clear();
        areas(d, &mut normals);
        if normals.is_empty() {
            continue;
        }
        b.push(d as u32, &wall_normals(&normals, FEATURE_ANGLE_DEG), flags, true);
    }
    b.finish(flags)
}

/// The slip frames of a coarse level whose unknown d is the fine level's unknown `fine_dof[d]`:
/// each takes the directions of its fine unknown (re-orthogonalised against its own prescribed
/// components), pinned fine unknowns stay pinned, axis ones axis and framed ones framed. Pinned
/// unknowns are made P in `flags`, axis ones in their axes' components.
pub(crate) fn inherit_slip_frames(fine: &SlipFrames, fine_dof: &[u32], flags: &mut [Vec<u8>]) -> Option<SlipFrames> {
    let mut b = Builder::new(fine.dim);
    for (d, &fd) in fine_dof.iter().enumerate() {
        if fine.pinned.binary_search(&fd).is_ok() {
            let all: Vec<[f64; 3]> = (0..fine.dim).map(axis).collect();
            b.push(d as u32, &all, flags, false);
        } else if let Some(dirs) = fine.directions_of(fd) {
            b.push(d as u32, dirs, flags, false);
        } else if let Some(mask) = fine.axes_of(fd) {
            let dirs: Vec<[f64; 3]> = (0..fine.dim).filter(|c| mask & 1 << c != 0).map(axis).collect();
            b.push(d as u32, &dirs, flags, true);
        }
    }
    b.finish(flags)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_directions_to_rounding() {
        assert_eq!(axis_mask(&[[0.0, -1.0, 0.0]]), Some(0b010));
        assert_eq!(axis_mask(&[[1.0, 3e-17, 0.0], [0.0, 0.0, 1.0]]), Some(0b101));
        assert_eq!(axis_mask(&[[1.0, 1e-9, 0.0]]), None);
        assert_eq!(axis_mask(&[[0.0, 1.0, 0.0], [0.6, 0.0, 0.8]]), None);
    }

    #[test]
    fn projection_removes_the_normal_and_keeps_the_tangent() {
        let s = 0.5f64.sqrt();
        let f = SlipFrames { dim: 2, dofs: vec![1], ptr: vec![0, 1], dirs: vec![[s, s, 0.0]], pinned: vec![], axes: vec![] };
        // Two unknowns, blocks x then y.
        let mut u = vec![7.0, 1.0, 9.0, 3.0];
        f.project(2, &mut u);
        assert_eq!((u[0], u[2]), (7.0, 9.0));
        assert!((u[1] + u[3]).abs() < 1e-15 && (u[1] - (-1.0)).abs() < 1e-15);
        let t = f.tangents(0, &[false, false]);
        assert_eq!(t.len(), 1);
        assert!(dot(&t[0], &[s, s, 0.0]).abs() < 1e-15);
    }
}
