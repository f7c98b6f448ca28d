//! The 3D cases (docs/RESULTS.md, "3D"): the free surface on the unit cube, on tetrahedra,
//! hexahedra and prisms, and the boundary-layer cylinder extruded in z. Their motions and
//! boundary conditions are the 2D cases' (setups.rs) with the third component added.
//!
//! Names: `free_surface_3d_{tets,hexes,prisms}_a{A}` (A = 0.1 and 0.25, one step) and
//! `boundary_layer_cylinder_3d`.

use super::meshes::{BL_CYLINDER, BL_FAR};
use super::meshes3d::*;
use super::setup::{CaseSetup, Scale};
use meshmove::bc::{BoundaryConditions, Kind};
use meshmove::mesh::Mesh;
use meshmove::motion::{Motion, RigidMotion};
use std::f64::consts::TAU;

/// [`boundary_layer_cylinder_3d`]: the bottom, z = 0.
pub const BL_Z0: i32 = 3;
/// [`boundary_layer_cylinder_3d`]: the top, z = [`BL3_DEPTH`].
pub const BL_Z1: i32 = 4;
/// [`boundary_layer_cylinder_3d`]: the depth of the extrusion (one cylinder diameter).
pub const BL3_DEPTH: f64 = 1.0;

/// Cells per side of the free-surface cube at `scale`: 16 (`Paper`) or 6 (`Quick`).
pub fn free_surface_3d_cells(scale: Scale) -> usize {
    match scale {
        Scale::Paper => 16,
        Scale::Quick => 6,
    }
}

/// Layers of the boundary-layer cylinder's extrusion at `scale`: 4 (`Paper`) or 1 (`Quick`).
pub fn boundary_layer_cylinder_3d_layers(scale: Scale) -> usize {
    match scale {
        Scale::Paper => 4,
        Scale::Quick => 1,
    }
}

/// The amplitudes of the free-surface cube cases of `CASE_NAMES`: the 2D case's two (one step
/// each).
pub const FREE_SURFACE_3D_AMPLITUDES: [f64; 2] = [0.1, 0.25];

/// The name of the free-surface cube case: `free_surface_3d_{cells}_a{a}`.
pub fn free_surface_3d_name(cells: BoxCells, a: f64) -> String {
    format!("free_surface_3d_{}_a{a}", cells.name())
}

/// The free surface's boundary conditions in 3D: bottom FIXED, top CLAMPED (as in 2D), and the
/// four sides sliding in their planes: the normal component FIXED (zero), the two others FREE.
/// The sides are walls, not periodic: the top's motion is symmetric about every side (its
/// derivative normal to the side is zero there), so a wall sees the same motion a periodic side
/// would.
pub fn free_surface_3d_bcs() -> BoundaryConditions {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BOX_BOTTOM, Kind::Fixed).set_kinds(BOX_TOP, Kind::Clamped);
    for (patches, normal) in [([BOX_LEFT, BOX_RIGHT], 0), ([BOX_FRONT, BOX_BACK], 1)] {
        for p in patches {
            for c in 0..3 {
                let kind = if c == normal { Kind::Fixed } else { Kind::Free };
                bcs.set_kind(p, c, kind).expect("component < 3");
            }
        }
    }
    bcs
}

/// The free surface on the unit cube \[0,1\]³ of `n`³ grid cubes made of `cells`: bottom FIXED,
/// sides sliding ([`free_surface_3d_bcs`]), the top (z = 1) CLAMPED and moved vertically by
/// `a` cos 2πx cos 2πy in `steps` equal steps.
pub fn free_surface_3d_case(cells: BoxCells, n: usize, a: f64, steps: usize) -> CaseSetup {
    let data = structured_box(cells, [n; 3], [0.0, 1.0, 0.0, 1.0, 0.0, 1.0]);
    let mesh = Mesh::from_data(&data).expect("valid box mesh");
    let mut motion = Motion::zero(&mesh);
    for v in mesh.patch_vertices(BOX_TOP) {
        let p = mesh.point(v as usize);
        motion.displacement[3 * v as usize + 2] = a * (TAU * p[0]).cos() * (TAU * p[1]).cos();
    }
    CaseSetup {
        name: free_surface_3d_name(cells, a),
        mesh,
        bcs: free_surface_3d_bcs(),
        motion,
        steps,
        moved_patch: BOX_TOP,
        upper_region: None,
    }
}

/// The hybrid boundary-layer cylinder ([`boundary_layer_cylinder_hybrid`](super::hybrid::boundary_layer_cylinder_hybrid))
/// extruded over z in [0, [`BL3_DEPTH`]] in `layers` layers: the wall-layer quads become
/// hexahedra, the triangles wedges; patches [`BL_FAR`], [`BL_CYLINDER`], [`BL_Z0`], [`BL_Z1`].
pub fn boundary_layer_cylinder_3d(layers: usize) -> Mesh {
    let flat = super::hybrid::boundary_layer_cylinder_hybrid();
    Mesh::from_data(&extrude(&flat, layers, [0.0, BL3_DEPTH], [BL_Z0, BL_Z1])).expect("valid extruded mesh")
}

/// The 2D boundary-layer case on [`boundary_layer_cylinder_3d`]`(layers)`: far field FIXED,
/// cylinder CLAMPED and moved 4.5 D along (−1, 1, 0)/√2 by a rigid translation, the z sides
/// sliding (z FIXED, x and y FREE).
pub fn boundary_layer_cylinder_3d_case(layers: usize) -> CaseSetup {
    let mesh = boundary_layer_cylinder_3d(layers);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BL_FAR, Kind::Fixed).set_kinds(BL_CYLINDER, Kind::Clamped);
    for p in [BL_Z0, BL_Z1] {
        bcs.set_kinds(p, Kind::Free).set_kind(p, 2, Kind::Fixed).expect("component < 3");
    }
    let t = [-4.5 / 2f64.sqrt(), 4.5 / 2f64.sqrt(), 0.0];
    let motion = Motion::zero(&mesh).with_rigid(BL_CYLINDER, RigidMotion::translation(t));
    CaseSetup {
        name: "boundary_layer_cylinder_3d".into(),
        mesh,
        bcs,
        motion,
        steps: 1,
        moved_patch: BL_CYLINDER,
        upper_region: None,
    }
}

/// The 3D case called `name` at `scale`, if it is one.
pub fn case3d(name: &str, scale: Scale) -> Option<CaseSetup> {
    if name == "boundary_layer_cylinder_3d" {
        return Some(boundary_layer_cylinder_3d_case(boundary_layer_cylinder_3d_layers(scale)));
    }
    let n = free_surface_3d_cells(scale);
    BoxCells::ALL
        .into_iter()
        .flat_map(|c| FREE_SURFACE_3D_AMPLITUDES.map(|a| (c, a)))
        .find(|&(c, a)| name == free_surface_3d_name(c, a))
        .map(|(c, a)| free_surface_3d_case(c, n, a, 1))
}

/// [`slab_case`]: the bottom symmetry plane, z = 0.
pub const SLAB_Z0: i32 = 3;
/// [`slab_case`]: the top symmetry plane, z = the thickness.
pub const SLAB_Z1: i32 = 4;

/// How a quasi-2D slab's two symmetry planes hold their vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SymmetryPlanes {
    /// SLIP: the normal (z) displacement prescribed zero, the tangential free.
    Slip,
    /// Per component: x and y FREE, z FIXED (OpenFOAM's "empty" patches, code_saturne's
    /// symmetry planes seen by the mesh).
    PerComponent,
}

/// A quasi-2D finite-volume mesh: the 2D case `flat` (its mesh extruded one layer of
/// `thickness`, its triangles wedges and its quads hexahedra) between the symmetry planes
/// [`SLAB_Z0`] and [`SLAB_Z1`] held as `planes` says; the 2D case's patches, kinds and rigid
/// motions carried over with a zero z component. The 2D mesh's patch ids must differ from the
/// planes'.
pub fn slab_case(flat: &CaseSetup, thickness: f64, planes: SymmetryPlanes) -> CaseSetup {
    let data = extrude(&flat.mesh.to_data(), 1, [0.0, thickness], [SLAB_Z0, SLAB_Z1]);
    let mesh = Mesh::from_data(&data).expect("valid extruded mesh");
    let mut bcs = flat.bcs.clone();
    for p in [SLAB_Z0, SLAB_Z1] {
        match planes {
            SymmetryPlanes::Slip => bcs.set_kinds(p, Kind::Slip),
            SymmetryPlanes::PerComponent => {
                bcs.set_kinds(p, Kind::Free).set_kind(p, 2, Kind::Fixed).expect("component < 3")
            }
        };
    }
    let mut motion = Motion::zero(&mesh);
    for &(p, m) in &flat.motion.rigid {
        motion = motion.with_rigid(p, m);
    }
    CaseSetup {
        name: format!("{}_slab", flat.name),
        mesh,
        bcs,
        motion,
        steps: flat.steps,
        moved_patch: flat.moved_patch,
        upper_region: None,
    }
}
