//! Prescribed boundary motion: per-vertex displacements and rigid motions of patches, and the
//! increments of a motion split into equal steps (docs/DESIGN.md §3 last paragraph, §4).

use crate::geometry::rotation::{compose, rotate};
use crate::{Error, Mesh, Result};

/// A rigid motion: rotation about `center`, then translation. Vectors have three components;
/// a 2D mesh reads x and y of `translation` and `center` and the angle `rotation[2]` (a rotation
/// about z). In 3D `rotation` is the rotation vector: axis × angle (radians, right-handed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidMotion {
    /// Translation, applied after the rotation.
    pub translation: [f64; 3],
    /// Rotation vector (2D: `[0, 0, angle]`, counter-clockwise).
    pub rotation: [f64; 3],
    /// Centre of rotation.
    pub center: [f64; 3],
}

impl RigidMotion {
    /// A pure translation.
    pub fn translation(t: [f64; 3]) -> Self {
        RigidMotion { translation: t, rotation: [0.0; 3], center: [0.0; 3] }
    }

    /// A 2D motion: rotation by `angle` (radians, counter-clockwise) about `center`, then
    /// translation by `t`.
    pub fn planar(t: [f64; 2], angle: f64, center: [f64; 2]) -> Self {
        RigidMotion { translation: [t[0], t[1], 0.0], rotation: [0.0, 0.0, angle], center: [center[0], center[1], 0.0] }
    }

    /// The rotation angle (the rotation vector's length; in 2D the signed angle).
    pub fn angle(&self, dim: usize) -> f64 {
        crate::geometry::rotation::angle(&self.rotation, dim)
    }

    /// L(x) = (R − I)(x − c) + t at a point `x` of `x.len()` (2 or 3) coordinates.
    pub fn displacement(&self, x: &[f64]) -> [f64; 3] {
        let dim = x.len();
        let mut r = [0.0; 3];
        for i in 0..dim {
            r[i] = x[i] - self.center[i];
        }
        let q = rotate(&self.rotation, dim, &r);
        let mut out = [0.0; 3];
        for i in 0..dim {
            out[i] = q[i] - r[i] + self.translation[i];
        }
        out
    }

    /// Step `step` (0-based) of `steps` equal steps: the angle and translation are ramped, not
    /// the displacement, so a rotating body keeps its shape half-way (docs/DESIGN.md §4).
    pub fn increment(&self, step: usize, steps: usize) -> RigidMotion {
        let f = 1.0 / steps as f64;
        let done = step as f64 * f;
        RigidMotion {
            translation: self.translation.map(|t| t * f),
            rotation: self.rotation.map(|w| w * f),
            center: [0, 1, 2].map(|i| self.center[i] + self.translation[i] * done),
        }
    }

    /// The part of this motion from fraction `a` to fraction `b` of it (0 ≤ a < b ≤ 1), applied
    /// to the body where fraction `a` left it: angle and translation ramped, the centre carried
    /// along by the translation done so far. `between(0, 1)` is the motion itself, bitwise.
    pub fn between(&self, a: f64, b: f64) -> RigidMotion {
        RigidMotion {
            translation: self.translation.map(|t| t * (b - a)),
            rotation: self.rotation.map(|w| w * (b - a)),
            center: [0, 1, 2].map(|i| self.center[i] + self.translation[i] * a),
        }
    }

    /// This motion followed by `next`, as one rigid motion about this motion's centre, on a mesh
    /// of dimension `dim`. Angles about one axis add up (a rotation past 360° keeps its angle),
    /// so a sum of increments ramps as a whole.
    pub fn then(&self, next: &RigidMotion, dim: usize) -> RigidMotion {
        let c1 = self.center;
        let r = [0, 1, 2].map(|i| c1[i] + self.translation[i] - next.center[i]);
        let q = rotate(&next.rotation, dim, &r);
        let translation = [0, 1, 2].map(|i| q[i] + next.center[i] + next.translation[i] - c1[i]);
        RigidMotion { translation, rotation: compose(&self.rotation, &next.rotation, dim), center: c1 }
    }

    /// The motion that undoes this one: x = R⁻¹(y − c − t) + c, a rotation by the opposite
    /// vector about the moved centre c + t, then the translation −t.
    pub fn inverse(&self) -> RigidMotion {
        RigidMotion {
            translation: self.translation.map(|t| -t),
            rotation: self.rotation.map(|w| -w),
            center: [0, 1, 2].map(|i| self.center[i] + self.translation[i]),
        }
    }

    /// Where the motion takes the point `x` (2 or 3 coordinates; the rest of the result 0).
    pub fn apply(&self, x: &[f64]) -> [f64; 3] {
        let d = self.displacement(x);
        let mut y = [0.0; 3];
        for (i, xi) in x.iter().enumerate() {
            y[i] = xi + d[i];
        }
        y
    }

    /// True when the motion moves nothing.
    pub fn is_identity(&self) -> bool {
        self.rotation == [0.0; 3] && self.translation == [0.0; 3]
    }

    fn is_finite(&self) -> bool {
        self.translation.iter().chain(&self.rotation).chain(&self.center).all(|x| x.is_finite())
    }
}

/// What the boundary does in one solve.
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    /// Displacement of every vertex, `dim` values per vertex (interleaved like the mesh's
    /// coordinates); read only where a component is prescribed.
    pub displacement: Vec<f64>,
    /// Rigid motions of whole patches; they override `displacement` on their vertices.
    pub rigid: Vec<(i32, RigidMotion)>,
}

impl Motion {
    /// No motion of `mesh`.
    pub fn zero(mesh: &Mesh) -> Self {
        Motion { displacement: vec![0.0; mesh.coords().len()], rigid: Vec::new() }
    }

    /// A per-vertex displacement (`dim` values per vertex), no rigid motion.
    pub fn from_displacement(displacement: Vec<f64>) -> Self {
        Motion { displacement, rigid: Vec::new() }
    }

    /// This motion with `patch` moved rigidly by `m`.
    pub fn with_rigid(mut self, patch: i32, m: RigidMotion) -> Self {
        self.rigid.push((patch, m));
        self
    }

    /// Checks the motion against `mesh`: one finite displacement per vertex and component,
    /// rigid motions of existing patches, finite, one per patch.
    pub fn check(&self, mesh: &Mesh) -> Result<()> {
        let dim = mesh.dim();
        if self.displacement.len() != mesh.coords().len() {
            return Err(Error::InvalidArgument(format!(
                "displacement has {} values, the mesh has {} vertices × {dim} components",
                self.displacement.len(),
                mesh.num_vertices()
            )));
        }
        if let Some(i) = self.displacement.iter().position(|d| !d.is_finite()) {
            return Err(Error::InvalidArgument(format!("displacement of vertex {} is not finite", i / dim)));
        }
        let ids = mesh.patch_ids();
        for (k, (p, m)) in self.rigid.iter().enumerate() {
            if self.rigid[..k].iter().any(|(q, _)| q == p) {
                return Err(Error::InvalidArgument(format!(
                    "patch {p} is given two rigid motions: give one (compose them first)"
                )));
            }
            if ids.binary_search(p).is_err() {
                return Err(Error::InvalidArgument(format!("rigid motion of patch {p}, which is not in the mesh")));
            }
            if !m.is_finite() {
                return Err(Error::InvalidArgument(format!("rigid motion of patch {p} is not finite")));
            }
        }
        Ok(())
    }

    /// The part of this motion from fraction `a` to fraction `b` of it (see
    /// [`RigidMotion::between`]); displacements are scaled by `b − a`.
    pub fn between(&self, a: f64, b: f64) -> Motion {
        if a == 0.0 && b == 1.0 {
            return self.clone();
        }
        Motion {
            displacement: self.displacement.iter().map(|&d| d * (b - a)).collect(),
            rigid: self.rigid.iter().map(|&(p, m)| (p, m.between(a, b))).collect(),
        }
    }

    /// This motion followed by `next` on `mesh`: the total motion of a sequence of increments,
    /// for solves from the original mesh. Displacements add up and the rigid motions of a patch
    /// moving rigidly in both compose. A patch whose rigid motion `next` does not continue, or
    /// one that starts moving rigidly after it moved otherwise, cannot stay one rigid motion: its
    /// vertices get their total displacement per vertex (where this motion took them, then
    /// `next` from there), so a prescribed displacement that follows a cleared rigid motion
    /// moves them.
    pub fn then(&self, next: &Motion, mesh: &Mesh) -> Motion {
        let dim = mesh.dim();
        let before = self.vertex_values(mesh);
        let rigid_in = |rigid: &[(i32, RigidMotion)], p: i32| rigid.iter().find(|(q, _)| *q == p).map(|&(_, m)| m);
        let mut displacement: Vec<f64> =
            self.displacement.iter().zip(&next.displacement).map(|(a, b)| *a + *b).collect();
        let mut rigid = Vec::new();
        for &(p, m) in &self.rigid {
            match rigid_in(&next.rigid, p) {
                Some(n) => rigid.push((p, m.then(&n, dim))),
                None => {
                    for v in mesh.patch_vertices(p) {
                        let v = v as usize;
                        for c in v * dim..v * dim + dim {
                            displacement[c] = before[c] + next.displacement[c];
                        }
                    }
                }
            }
        }
        for &(p, n) in &next.rigid {
            if rigid_in(&self.rigid, p).is_some() {
                continue;
            }
            let vs = mesh.patch_vertices(p);
            let moved = |v: usize| before[v * dim..v * dim + dim].iter().any(|&d| d != 0.0);
            if !vs.iter().any(|&v| moved(v as usize)) {
                rigid.push((p, n));
                continue;
            }
            for v in vs {
                let v = v as usize;
                let x: Vec<f64> =
                    mesh.point(v).iter().zip(&before[v * dim..v * dim + dim]).map(|(x, d)| x + d).collect();
                let u = n.displacement(&x);
                for c in 0..dim {
                    displacement[v * dim + c] = before[v * dim + c] + u[c];
                }
            }
        }
        Motion { displacement, rigid }
    }

    /// Step `step` (0-based) of `steps` equal steps toward this motion.
    pub fn increment(&self, step: usize, steps: usize) -> Motion {
        let f = 1.0 / steps as f64;
        Motion {
            displacement: self.displacement.iter().map(|&d| d * f).collect(),
            rigid: self.rigid.iter().map(|&(p, m)| (p, m.increment(step, steps))).collect(),
        }
    }

    /// Displacement of each vertex with the rigid motions applied on their patches (the
    /// per-vertex field itself, not a copy, when there are none).
    pub fn vertex_values(&self, mesh: &Mesh) -> std::borrow::Cow<'_, [f64]> {
        if self.rigid.is_empty() {
            return std::borrow::Cow::Borrowed(&self.displacement);
        }
        let dim = mesh.dim();
        let mut d = self.displacement.clone();
        for &(p, m) in &self.rigid {
            for v in mesh.patch_vertices(p) {
                let v = v as usize;
                let u = m.displacement(mesh.point(v));
                d[v * dim..v * dim + dim].copy_from_slice(&u[..dim]);
            }
        }
        std::borrow::Cow::Owned(d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn add(x: [f64; 3], d: [f64; 3]) -> [f64; 3] {
        [x[0] + d[0], x[1] + d[1], x[2] + d[2]]
    }

    #[test]
    fn stepped_rotation_composes_to_the_whole() {
        for (m, dim) in [
            (RigidMotion::planar([1.0, -2.0], 1.2, [0.3, 0.1]), 2),
            (RigidMotion { translation: [1.0, -2.0, 0.5], rotation: [0.4, -0.8, 0.6], center: [0.3, 0.1, -0.2] }, 3),
        ] {
            let x0 = [2.0, 0.5, 0.7];
            let mut x = x0;
            for i in 0..7 {
                x = add(x, m.increment(i, 7).displacement(&x[..dim]));
            }
            let whole = add(x0, m.displacement(&x0[..dim]));
            for i in 0..dim {
                assert!((x[i] - whole[i]).abs() < 1e-14, "{dim}D");
            }
        }
    }

    #[test]
    fn composed_increments_are_the_whole_motion() {
        for (m, dim) in [
            (RigidMotion::planar([0.4, -0.1], 7.5, [1.0, 2.0]), 2),
            (RigidMotion { translation: [0.4, -0.1, 0.3], rotation: [0.0, 0.0, 2.5], center: [1.0, 2.0, 0.5] }, 3),
        ] {
            let mut total = m.between(0.0, 0.25);
            for (a, b) in [(0.25, 0.5), (0.5, 0.75), (0.75, 1.0)] {
                total = total.then(&m.between(a, b), dim);
            }
            assert!((total.angle(dim) - m.angle(dim)).abs() < 1e-14);
            for x in [[0.3, 0.2, 0.1], [-2.0, 5.0, 1.0]] {
                let (a, b) = (total.displacement(&x[..dim]), m.displacement(&x[..dim]));
                assert!((0..3).all(|i| (a[i] - b[i]).abs() < 1e-13));
            }
            assert_eq!(m.between(0.0, 1.0), m);
        }
    }
}
