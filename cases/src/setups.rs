//! The paper's cases (docs/DESIGN.md §7) as complete set-ups: mesh, boundary conditions, motion, steps.
//!
//! Every set-up is the one stated in docs/DESIGN.md §7; nothing here is tuned to make a finding hold.
//! `Scale::Quick` only coarsens the meshes (for smoke tests of the CLI); the findings are
//! asserted at `Scale::Paper`.

use super::meshes::*;
use meshmove::bc::{BoundaryConditions, InterfaceVariant, Kind, Link};
use meshmove::mesh::Mesh;
use meshmove::motion::{Motion, RigidMotion};
use std::f64::consts::TAU;

pub use crate::setup::{CaseSetup, Scale};

/// The case names of the CLI's `results.csv`, in order: the 2D cases, then the 3D ones
/// ([`super::setups3d`], [`super::bodies3d`]), then the slip-wall comparisons.
pub const CASE_NAMES: [&str; 25] = [
    "free_surface_a0.1",
    "free_surface_a0.25",
    "free_surface_a0.25_10steps",
    "rising_interface_0.5",
    "rising_interface_0.75",
    "deforming_interface_A",
    "deforming_interface_B",
    "cylinder_channel",
    "boundary_layer_cylinder",
    "boundary_layer_cylinder_hybrid",
    "free_surface_3d_tets_a0.1",
    "free_surface_3d_hexes_a0.1",
    "free_surface_3d_prisms_a0.1",
    "free_surface_3d_tets_a0.25",
    "free_surface_3d_hexes_a0.25",
    "free_surface_3d_prisms_a0.25",
    "boundary_layer_cylinder_3d",
    "sphere_channel_0.5",
    "sphere_channel_1.0",
    "pitching_spheroid_1step",
    "pitching_spheroid_10steps",
    "cylinder_channel_1.5D_fixed",
    "cylinder_channel_1.5D_slip",
    "sphere_channel_1.5D_fixed",
    "sphere_channel_1.5D_slip",
];

fn free_surface_bcs() -> BoundaryConditions {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(FS_BOTTOM, Kind::Fixed).set_kinds(FS_TOP, Kind::Clamped);
    for p in [FS_LEFT, FS_RIGHT] {
        bcs.set_kind(p, 0, Kind::Clamped).unwrap().set_kind(p, 1, Kind::Free).unwrap();
    }
    bcs.add_link(Link::ByOffset { a: FS_LEFT, b: FS_RIGHT, offset: [1.0, 0.0, 0.0], tol: 1e-9 });
    bcs
}

/// The free surface \[0,1\]×[−1,0]: sides linked (X CLAMPED, Y FREE), bottom FIXED, top CLAMPED
/// and moved to y = `a` cos 2πx in `steps` equal steps.
pub fn free_surface_case(name: &'static str, h: f64, a: f64, steps: usize) -> CaseSetup {
    let mesh = free_surface(h);
    let mut motion = Motion::zero(&mesh);
    for v in mesh.patch_vertices(FS_TOP) {
        let x = mesh.point(v as usize)[0];
        motion.displacement[2 * v as usize + 1] = a * (TAU * x).cos();
    }
    CaseSetup {
        name: name.to_string(),
        mesh,
        bcs: free_surface_bcs(),
        motion,
        steps,
        moved_patch: FS_TOP,
        upper_region: None,
    }
}

/// The two-region mesh \[0,1\]×[−1,1] (the free-surface mesh and its mirror): bottom and top
/// FIXED, sides linked (X CLAMPED, Y FREE), the interface CLAMPED with `variant`, moved to
/// y = `target(x)` in `steps` equal steps.
pub fn interface_case(
    name: &'static str,
    h: f64,
    variant: InterfaceVariant,
    target: impl Fn(f64) -> f64,
    steps: usize,
) -> CaseSetup {
    let mesh = two_region_interface(h);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(IF_BOTTOM, Kind::Fixed).set_kinds(IF_TOP, Kind::Fixed).set_kinds(IF_INTERFACE, Kind::Clamped);
    for p in [IF_LEFT, IF_RIGHT] {
        bcs.set_kind(p, 0, Kind::Clamped).unwrap().set_kind(p, 1, Kind::Free).unwrap();
    }
    bcs.add_link(Link::ByOffset { a: IF_LEFT, b: IF_RIGHT, offset: [1.0, 0.0, 0.0], tol: 1e-9 });
    bcs.set_interface(IF_INTERFACE, variant);
    let mut motion = Motion::zero(&mesh);
    for v in mesh.patch_vertices(IF_INTERFACE) {
        let x = mesh.point(v as usize)[0];
        motion.displacement[2 * v as usize + 1] = target(x);
    }
    CaseSetup { name: name.to_string(), mesh, bcs, motion, steps, moved_patch: IF_INTERFACE, upper_region: Some(1) }
}

/// \[0,8\]×[−1,1], cylinder D = 1 at (2,0) moved +1 D in x by a rigid translation; channel FIXED,
/// cylinder CLAMPED.
pub fn cylinder_channel_case(h: f64) -> CaseSetup {
    let mesh = cylinder_channel(h);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(CH_WALL, Kind::Fixed).set_kinds(CH_CYLINDER, Kind::Clamped);
    let motion = Motion::zero(&mesh).with_rigid(CH_CYLINDER, RigidMotion::translation([1.0, 0.0, 0.0]));
    CaseSetup {
        name: "cylinder_channel".into(),
        mesh,
        bcs,
        motion,
        steps: 1,
        moved_patch: CH_CYLINDER,
        upper_region: None,
    }
}

/// The cylinder of `cylinder_channel_case` moved 1.5 D along the channel in one step, the
/// channel's walls (all four sides) `walls`: FIXED, or SLIP (its vertices slide along the walls,
/// the corners stay).
pub fn cylinder_channel_far(h: f64, walls: Kind) -> CaseSetup {
    let mut c = cylinder_channel_case(h);
    c.name = format!("cylinder_channel_1.5D_{}", if walls == Kind::Slip { "slip" } else { "fixed" });
    c.bcs.set_kinds(CH_WALL, walls);
    c.motion = Motion::zero(&c.mesh).with_rigid(CH_CYLINDER, RigidMotion::translation([1.5, 0.0, 0.0]));
    c
}

/// 3D: a sphere of diameter 0.4 at (1.6, 0, 0) in the duct [0, 4] × [−1, 1] × [−1, 1] (hexahedra,
/// `spheres3d::sphere_channel`), moved 1.5 D along the duct in one step; the sphere CLAMPED, the
/// duct's walls and ends `walls` (SLIP: they slide, their edges along the edges, the corners stay).
pub fn sphere_channel_case(walls: Kind) -> CaseSetup {
    use super::spheres3d::{sphere_channel, SC_SPHERE, SC_WALL};
    let mesh = sphere_channel(10, 4.0, 1.6, 0.4, 2, 3);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(SC_WALL, walls).set_kinds(SC_SPHERE, Kind::Clamped);
    let motion = Motion::zero(&mesh).with_rigid(SC_SPHERE, RigidMotion::translation([0.6, 0.0, 0.0]));
    CaseSetup {
        name: format!("sphere_channel_1.5D_{}", if walls == Kind::Slip { "slip" } else { "fixed" }),
        mesh,
        bcs,
        motion,
        steps: 1,
        moved_patch: SC_SPHERE,
        upper_region: None,
    }
}

/// [−10,20]×[−10,10] with the wall-layer cylinder moved 4.5 D along (−1, 1)/√2 by a rigid
/// translation; far field FIXED, cylinder CLAMPED.
pub fn boundary_layer_cylinder_case() -> CaseSetup {
    bl_case("boundary_layer_cylinder", boundary_layer_cylinder())
}

/// The same case on the hybrid mesh: the 15 wall layers as quads, triangles outside.
pub fn boundary_layer_cylinder_hybrid_case() -> CaseSetup {
    let mesh = Mesh::from_data(&super::hybrid::boundary_layer_cylinder_hybrid()).expect("valid hybrid mesh");
    bl_case("boundary_layer_cylinder_hybrid", mesh)
}

fn bl_case(name: &str, mesh: Mesh) -> CaseSetup {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BL_FAR, Kind::Fixed).set_kinds(BL_CYLINDER, Kind::Clamped);
    let t = [-4.5 / 2f64.sqrt(), 4.5 / 2f64.sqrt(), 0.0];
    let motion = Motion::zero(&mesh).with_rigid(BL_CYLINDER, RigidMotion::translation(t));
    CaseSetup { name: name.into(), mesh, bcs, motion, steps: 1, moved_patch: BL_CYLINDER, upper_region: None }
}

/// The case called `name` (one of [`CASE_NAMES`]) at `scale`.
pub fn case(name: &str, scale: Scale) -> Option<CaseSetup> {
    let (h, hc) = match scale {
        Scale::Paper => (1.0 / 32.0, 1.0 / 12.0),
        Scale::Quick => (1.0 / 12.0, 1.0 / 6.0),
    };
    let deformed = |x: f64| 0.375 * (TAU * x).cos();
    Some(match name {
        "free_surface_a0.1" => free_surface_case("free_surface_a0.1", h, 0.1, 1),
        "free_surface_a0.25" => free_surface_case("free_surface_a0.25", h, 0.25, 1),
        "free_surface_a0.25_10steps" => free_surface_case("free_surface_a0.25_10steps", h, 0.25, 10),
        "rising_interface_0.5" => interface_case("rising_interface_0.5", h, InterfaceVariant::Separate, |_| 0.5, 1),
        "rising_interface_0.75" => interface_case("rising_interface_0.75", h, InterfaceVariant::Separate, |_| 0.75, 1),
        "deforming_interface_A" => interface_case("deforming_interface_A", h, InterfaceVariant::Separate, deformed, 15),
        "deforming_interface_B" => {
            interface_case("deforming_interface_B", h, InterfaceVariant::Continuous, deformed, 15)
        }
        "cylinder_channel" => cylinder_channel_case(hc),
        "cylinder_channel_1.5D_fixed" => cylinder_channel_far(hc, Kind::Fixed),
        "cylinder_channel_1.5D_slip" => cylinder_channel_far(hc, Kind::Slip),
        "sphere_channel_1.5D_fixed" => sphere_channel_case(Kind::Fixed),
        "sphere_channel_1.5D_slip" => sphere_channel_case(Kind::Slip),
        "boundary_layer_cylinder" => boundary_layer_cylinder_case(),
        "boundary_layer_cylinder_hybrid" => boundary_layer_cylinder_hybrid_case(),
        other => return super::setups3d::case3d(other, scale).or_else(|| super::bodies3d::case(other, scale)),
    })
}
