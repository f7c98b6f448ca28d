//! The measures of a wall-layered mesh: its cells' shape before a motion, and how its wall
//! layers' volumes changed after one.

use super::ViscousMesh;
use crate::ogrid::measure;
use meshmove::mesh::signed_measures;

/// The shape of a mesh (docs/DESIGN.md, "Mesh quality measures").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshQuality {
    /// Vertices.
    pub vertices: usize,
    /// Cells.
    pub cells: usize,
    /// Largest aspect ratio: a cell's longest edge over its shortest.
    pub max_aspect_ratio: f64,
    /// Smallest angle: between two faces at an edge of a 3D cell (the dihedral angle), between
    /// two edges at a corner of a 2D cell; degrees.
    pub min_angle_deg: f64,
    /// Mean length of the edges leaving the wall: the first layer's height, measured.
    pub wall_normal_edge: f64,
}

/// The [`MeshQuality`] of `v`'s mesh as built.
pub fn mesh_quality(v: &ViscousMesh) -> MeshQuality {
    let s = measure(&v.mesh, super::WALL);
    MeshQuality {
        vertices: v.mesh.num_vertices(),
        cells: v.mesh.num_cells(),
        max_aspect_ratio: s.max_edge_ratio,
        min_angle_deg: s.min_angle_deg,
        wall_normal_edge: s.wall_normal_edge,
    }
}

/// The smallest and largest ratio of a cell's area (volume) at `deformed` to its area as built,
/// over the cells of the wall layers below `below` (1: the first layer only); None when no cell
/// is in those layers or `deformed` has the wrong length.
pub fn layer_volume_ratios(v: &ViscousMesh, deformed: &[f64], below: u32) -> Option<(f64, f64)> {
    if deformed.len() != v.mesh.coords().len() {
        return None;
    }
    let before = signed_measures(&v.mesh, v.mesh.coords());
    let after = signed_measures(&v.mesh, deformed);
    let ratios = (0..before.len()).filter(|&c| v.cell_layer[c] < below).map(|c| after[c] / before[c]);
    ratios.fold(None, |acc, r| match acc {
        None => Some((r, r)),
        Some((lo, hi)) => Some((f64::min(lo, r), f64::max(hi, r))),
    })
}
