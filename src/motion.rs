//! Prescribed boundary motion: per-vertex displacements and rigid motions of patches, and the
//! increments of a motion split into equal steps (docs/DESIGN.md §3 last paragraph, §4).

use crate::{Error, Mesh, Result};
use glam::DVec2;

/// Rotation by `angle` (radians, counter-clockwise) about `center`, then translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidMotion {
    pub translation: DVec2,
    pub angle: f64,
    pub center: DVec2,
}

impl RigidMotion {
    pub fn translation(t: DVec2) -> Self {
        RigidMotion { translation: t, angle: 0.0, center: DVec2::ZERO }
    }

    /// L(x) = (R − I)(x − c) + t.
    pub fn displacement(&self, x: DVec2) -> DVec2 {
        let r = x - self.center;
        DVec2::from_angle(self.angle).rotate(r) - r + self.translation
    }

    /// Step `step` (0-based) of `steps` equal steps: the angle and translation are ramped, not
    /// the displacement, so a rotating body keeps its shape half-way (docs/DESIGN.md §4).
    pub fn increment(&self, step: usize, steps: usize) -> RigidMotion {
        let f = 1.0 / steps as f64;
        RigidMotion {
            translation: self.translation * f,
            angle: self.angle * f,
            center: self.center + self.translation * (step as f64 * f),
        }
    }

    /// The part of this motion from fraction `a` to fraction `b` of it (0 ≤ a < b ≤ 1), applied
    /// to the body where fraction `a` left it: angle and translation ramped, the centre carried
    /// along by the translation done so far. `between(0, 1)` is the motion itself, bitwise.
    pub fn between(&self, a: f64, b: f64) -> RigidMotion {
        RigidMotion {
            translation: self.translation * (b - a),
            angle: self.angle * (b - a),
            center: self.center + self.translation * a,
        }
    }

    /// This motion followed by `next`, as one rigid motion about this motion's centre. Angles add
    /// up (a rotation past 360° keeps its angle), so a sum of increments ramps as a whole.
    pub fn then(&self, next: &RigidMotion) -> RigidMotion {
        let r2 = DVec2::from_angle(next.angle);
        let c1 = self.center;
        let translation = r2.rotate(c1 + self.translation - next.center) + next.center + next.translation - c1;
        RigidMotion { translation, angle: self.angle + next.angle, center: c1 }
    }

    /// True when the motion moves nothing.
    pub fn is_identity(&self) -> bool {
        self.angle == 0.0 && self.translation == DVec2::ZERO
    }
}

/// What the boundary does in one solve.
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    /// Displacement of every vertex; read only where a component is prescribed.
    pub displacement: Vec<DVec2>,
    /// Rigid motions of whole patches; they override `displacement` on their vertices.
    pub rigid: Vec<(i32, RigidMotion)>,
}

impl Motion {
    /// No motion, for a mesh of `nv` vertices.
    pub fn zero(nv: usize) -> Self {
        Motion { displacement: vec![DVec2::ZERO; nv], rigid: Vec::new() }
    }

    pub fn from_displacement(displacement: Vec<DVec2>) -> Self {
        Motion { displacement, rigid: Vec::new() }
    }

    pub fn with_rigid(mut self, patch: i32, m: RigidMotion) -> Self {
        self.rigid.push((patch, m));
        self
    }

    pub fn check(&self, mesh: &Mesh) -> Result<()> {
        if self.displacement.len() != mesh.num_vertices() {
            return Err(Error::InvalidArgument(format!(
                "displacement has {} entries, the mesh has {} vertices",
                self.displacement.len(),
                mesh.num_vertices()
            )));
        }
        if let Some(v) = self.displacement.iter().position(|d| !d.is_finite()) {
            return Err(Error::InvalidArgument(format!("displacement of vertex {v} is not finite")));
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
            if !(m.translation.is_finite() && m.angle.is_finite() && m.center.is_finite()) {
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

    /// This motion followed by `next` (displacements added, rigid motions of a patch composed):
    /// the total motion of a sequence of increments, for solves from the original mesh.
    pub fn then(&self, next: &Motion) -> Motion {
        let displacement = self.displacement.iter().zip(&next.displacement).map(|(a, b)| *a + *b).collect();
        let mut rigid = self.rigid.clone();
        for &(p, m) in &next.rigid {
            match rigid.iter_mut().find(|(q, _)| *q == p) {
                Some((_, r)) => *r = r.then(&m),
                None => rigid.push((p, m)),
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
    pub fn vertex_values(&self, mesh: &Mesh) -> std::borrow::Cow<'_, [DVec2]> {
        if self.rigid.is_empty() {
            return std::borrow::Cow::Borrowed(&self.displacement);
        }
        let mut d = self.displacement.clone();
        for &(p, m) in &self.rigid {
            for v in mesh.patch_vertices(p) {
                d[v as usize] = m.displacement(mesh.coords()[v as usize]);
            }
        }
        std::borrow::Cow::Owned(d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stepped_rotation_composes_to_the_whole() {
        let m = RigidMotion { translation: DVec2::new(1.0, -2.0), angle: 1.2, center: DVec2::new(0.3, 0.1) };
        let x0 = DVec2::new(2.0, 0.5);
        let mut x = x0;
        for i in 0..7 {
            x += m.increment(i, 7).displacement(x);
        }
        assert!((x - (x0 + m.displacement(x0))).length() < 1e-14);
    }

    #[test]
    fn composed_increments_are_the_whole_motion() {
        let m = RigidMotion { translation: DVec2::new(0.4, -0.1), angle: 7.5, center: DVec2::new(1.0, 2.0) };
        let mut total = m.between(0.0, 0.25);
        for (a, b) in [(0.25, 0.5), (0.5, 0.75), (0.75, 1.0)] {
            total = total.then(&m.between(a, b));
        }
        assert!((total.angle - m.angle).abs() < 1e-14);
        for x in [DVec2::new(0.3, 0.2), DVec2::new(-2.0, 5.0)] {
            assert!((total.displacement(x) - m.displacement(x)).length() < 1e-13);
        }
        assert_eq!(m.between(0.0, 1.0), m);
    }
}
