//! 3D bodies in boxes on graded O-grid meshes ([`super::ogrid`]): a sphere translated along a
//! square channel and a prolate spheroid pitched about its centre.

use super::ogrid::{sphere_in_box, OgridParams, OG_BODY, OG_WALL};
use super::setup::{CaseSetup, Scale};
use meshmove::bc::{BoundaryConditions, Kind};
use meshmove::mesh::Mesh;
use meshmove::motion::{Motion, RigidMotion};

/// [`sphere_channel_mesh`]: the sphere's centre.
pub const SPHERE_CENTER: [f64; 3] = [2.0, 0.0, 0.0];
/// [`sphere_channel_mesh`]: the sphere's radius.
pub const SPHERE_RADIUS: f64 = 0.5;
/// [`sphere_channel_mesh`]: the channel \[0,6\]×\[−1.5,1.5\]².
pub const CHANNEL: [[f64; 2]; 3] = [[0.0, 6.0], [-1.5, 1.5], [-1.5, 1.5]];
/// [`pitching_spheroid_mesh`]: the spheroid's semi-axes (centred at the origin).
pub const SPHEROID_AXES: [f64; 3] = [0.6, 0.15, 0.15];
/// [`pitching_spheroid_mesh`]: the box [−3,3]³.
pub const SPHEROID_BOX: [[f64; 2]; 3] = [[-3.0, 3.0]; 3];
/// [`pitching_spheroid_case`]: the pitch angle, degrees.
pub const PITCH_DEG: f64 = 20.0;

/// The sphere channel's wall and far sizes at `scale`: (0.05, 0.15) as the case states (about
/// 67k vertices, 380k tetrahedra), (0.1, 0.3) for quick runs (about 10k vertices).
pub fn sphere_channel_sizes(scale: Scale) -> (f64, f64) {
    match scale {
        Scale::Paper => (0.05, 0.15),
        Scale::Quick => (0.1, 0.3),
    }
}

/// The pitching spheroid's wall and far sizes at `scale`: (0.03, 0.3) (about 67k vertices),
/// (0.1, 0.75) for quick runs (about 4k vertices, three cells across a quarter of the
/// spheroid's girth: a smoke test of the command line, not a resolved body).
pub fn pitching_spheroid_sizes(scale: Scale) -> (f64, f64) {
    match scale {
        Scale::Paper => (0.03, 0.3),
        Scale::Quick => (0.1, 0.75),
    }
}

/// Tetrahedra of the channel [`CHANNEL`] around the sphere of [`SPHERE_RADIUS`] at
/// [`SPHERE_CENTER`], graded from `wall` at the sphere to `far`. Patches
/// [`OG_WALL`] (every channel wall), [`OG_BODY`].
pub fn sphere_channel_mesh(wall: f64, far: f64) -> Mesh {
    sphere_in_box(&OgridParams::sphere(SPHERE_CENTER, SPHERE_RADIUS, CHANNEL, wall, far))
}

/// Tetrahedra of the box [`SPHEROID_BOX`] around the spheroid of [`SPHEROID_AXES`] at the
/// origin, graded from `wall` at the spheroid to `far`. Patches as [`sphere_channel_mesh`].
pub fn pitching_spheroid_mesh(wall: f64, far: f64) -> Mesh {
    sphere_in_box(&OgridParams::spheroid([0.0; 3], SPHEROID_AXES, SPHEROID_BOX, wall, far))
}

fn body_bcs() -> BoundaryConditions {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(OG_WALL, Kind::Fixed).set_kinds(OG_BODY, Kind::Clamped);
    bcs
}

/// The sphere moved `dx` along the channel by a rigid translation in one step; walls FIXED,
/// sphere CLAMPED.
pub fn sphere_channel_case(name: &str, mesh: Mesh, dx: f64) -> CaseSetup {
    let motion = Motion::zero(&mesh).with_rigid(OG_BODY, RigidMotion::translation([dx, 0.0, 0.0]));
    CaseSetup { name: name.into(), mesh, bcs: body_bcs(), motion, steps: 1, moved_patch: OG_BODY, upper_region: None }
}

/// The spheroid pitched by [`PITCH_DEG`] about the y axis through its centre (a rigid
/// rotation) in `steps` equal steps; walls FIXED, spheroid CLAMPED.
pub fn pitching_spheroid_case(name: &str, mesh: Mesh, steps: usize) -> CaseSetup {
    let rigid = RigidMotion { translation: [0.0; 3], rotation: [0.0, PITCH_DEG.to_radians(), 0.0], center: [0.0; 3] };
    let motion = Motion::zero(&mesh).with_rigid(OG_BODY, rigid);
    CaseSetup { name: name.into(), mesh, bcs: body_bcs(), motion, steps, moved_patch: OG_BODY, upper_region: None }
}

/// The case `name` of this module at `scale`, if it is one.
pub fn case(name: &str, scale: Scale) -> Option<CaseSetup> {
    let sphere = || {
        let (w, f) = sphere_channel_sizes(scale);
        sphere_channel_mesh(w, f)
    };
    let spheroid = || {
        let (w, f) = pitching_spheroid_sizes(scale);
        pitching_spheroid_mesh(w, f)
    };
    Some(match name {
        "sphere_channel_0.5" => sphere_channel_case(name, sphere(), 0.5),
        "sphere_channel_1.0" => sphere_channel_case(name, sphere(), 1.0),
        "pitching_spheroid_1step" => pitching_spheroid_case(name, spheroid(), 1),
        "pitching_spheroid_10steps" => pitching_spheroid_case(name, spheroid(), 10),
        _ => return None,
    })
}
