//! The bench's unit cubes: [`structured_box`](super::meshes3d::structured_box) on n³ cells of
//! hexahedra or Freudenthal tetrahedra, whose top the 3D free-surface analogue of
//! `meshmove bench` moves.

use super::meshes3d::{self, BOX_BACK, BOX_FRONT, BOX_LEFT, BOX_RIGHT};
pub use super::meshes3d::{BoxCells, BOX_BOTTOM, BOX_TOP};
use meshmove::mesh::Mesh;
use meshmove::{BoundaryConditions, Kind, Motion};

/// The four sides of [`structured_box`] and the axis each is normal to.
pub const BOX_SIDES: [(i32, usize); 4] = [(BOX_LEFT, 0), (BOX_RIGHT, 0), (BOX_FRONT, 1), (BOX_BACK, 1)];

/// The unit cube as an `n`×`n`×`n` grid, (n + 1)³ vertices, vertex (i, j, k) at index
/// (k (n + 1) + j)(n + 1) + i and position (i, j, k)/n; every boundary face tagged with its
/// side's patch.
pub fn structured_box(n: usize, cells: BoxCells) -> Mesh {
    let data = meshes3d::structured_box(cells, [n; 3], [0.0, 1.0, 0.0, 1.0, 0.0, 1.0]);
    Mesh::from_data(&data).expect("a structured box is a valid mesh")
}

/// The bench's 3D free-surface analogue on [`structured_box`]: its boundary conditions (bottom
/// fixed, top clamped, each side fixed along its normal and free along itself) and its motion
/// (the top moved by 0.1 cos 2πx cos 2πy in z).
pub fn free_surface_conditions(mesh: &Mesh) -> (BoundaryConditions, Motion) {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BOX_BOTTOM, Kind::Fixed).set_kinds(BOX_TOP, Kind::Clamped);
    for (p, normal) in BOX_SIDES {
        for c in 0..3 {
            bcs.set_kind(p, c, if c == normal { Kind::Fixed } else { Kind::Free }).expect("3 components");
        }
    }
    let mut motion = Motion::zero(mesh);
    for v in mesh.patch_vertices(BOX_TOP) {
        let p = mesh.point(v as usize);
        motion.displacement[3 * v as usize + 2] =
            0.1 * (std::f64::consts::TAU * p[0]).cos() * (std::f64::consts::TAU * p[1]).cos();
    }
    (bcs, motion)
}
