//! The bench's unit cubes: [`structured_box`](super::meshes3d::structured_box) on n³ cells of
//! hexahedra or Freudenthal tetrahedra, whose top the 3D free-surface analogue of
//! `meshmove bench` moves.

use super::meshes3d::{self, BOX_BACK, BOX_FRONT, BOX_LEFT, BOX_RIGHT};
pub use super::meshes3d::{BoxCells, BOX_BOTTOM, BOX_TOP};
use meshmove::mesh::Mesh;

/// The four sides of [`structured_box`] and the axis each is normal to.
pub const BOX_SIDES: [(i32, usize); 4] = [(BOX_LEFT, 0), (BOX_RIGHT, 0), (BOX_FRONT, 1), (BOX_BACK, 1)];

/// The unit cube as an `n`×`n`×`n` grid, (n + 1)³ vertices, vertex (i, j, k) at index
/// (k (n + 1) + j)(n + 1) + i and position (i, j, k)/n; every boundary face tagged with its
/// side's patch.
pub fn structured_box(n: usize, cells: BoxCells) -> Mesh {
    let data = meshes3d::structured_box(cells, [n; 3], [0.0, 1.0, 0.0, 1.0, 0.0, 1.0]);
    Mesh::from_data(&data).expect("a structured box is a valid mesh")
}
