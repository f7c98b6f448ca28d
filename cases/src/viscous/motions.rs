//! The motions of the wall-layered meshes' use: the body pitched or plunged as a rigid body, its
//! layers CLAMPED (they move with it, and the biharmonic's rigid flux keeps their spacing), the
//! far field FIXED, the wing's end walls SLIP.

use super::{ViscousMesh, END_WALLS, FARFIELD, WALL};
use meshmove::{BoundaryConditions, Kind, Motion, RigidMotion};

/// Pitch angle, degrees.
pub const PITCH_DEG: f64 = 10.0;
/// Plunge, in body lengths (chords).
pub const PLUNGE: f64 = 0.2;

/// How the body moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyMotion {
    /// Rotation by [`PITCH_DEG`] (nose up) about z through [`ViscousMesh::pitch_center`].
    Pitch,
    /// Translation by [`PLUNGE`] along y.
    Plunge,
}

impl BodyMotion {
    /// `pitch` or `plunge`.
    pub fn name(self) -> &'static str {
        match self {
            BodyMotion::Pitch => "pitch",
            BodyMotion::Plunge => "plunge",
        }
    }
}

/// The body CLAMPED, the far field FIXED, the end walls (if any) SLIP.
pub fn boundary_conditions(v: &ViscousMesh) -> BoundaryConditions {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(WALL, Kind::Clamped).set_kinds(FARFIELD, Kind::Fixed);
    if v.patches.iter().any(|&(p, _)| p == END_WALLS) {
        bcs.set_kinds(END_WALLS, Kind::Slip);
    }
    bcs
}

/// The rigid motion of the body.
pub fn body_motion(v: &ViscousMesh, m: BodyMotion) -> RigidMotion {
    match m {
        // Nose up: the leading edge (at smaller x) rises, a clockwise turn about z.
        BodyMotion::Pitch => {
            RigidMotion { translation: [0.0; 3], rotation: [0.0, 0.0, -PITCH_DEG.to_radians()], center: v.pitch_center }
        }
        BodyMotion::Plunge => RigidMotion::translation([0.0, PLUNGE, 0.0]),
    }
}

/// The motion of the whole boundary: the body's rigid motion on [`WALL`], nothing elsewhere.
pub fn motion(v: &ViscousMesh, m: BodyMotion) -> Motion {
    Motion::zero(&v.mesh).with_rigid(WALL, body_motion(v, m))
}
