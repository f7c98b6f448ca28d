//! Deterministic mesh generators for the cases of docs/DESIGN.md §7.
//!
//! Every generator returns a validated [`Mesh`] and produces the same mesh on every run (no
//! randomness; spade's refinement is deterministic for a fixed insertion order). Patch ids are
//! the `pub const`s below; boundary edges are all tagged, so patch 0 is never used.

use super::cdt::Planar;
use glam::DVec2;
use meshmove::mesh::{IndexBase, Mesh};

pub use super::cylinder::{
    boundary_layer_cylinder, cylinder_channel, ellipse_in_box, BL_CYLINDER, BL_FAR, BL_FIRST_HEIGHT, BL_GROWTH,
    BL_LAYERS, BL_N_THETA, CH_CYLINDER, CH_WALL, EL_BOX, EL_ELLIPSE,
};
pub use super::free_surface::{
    free_surface, two_region_interface, unstructured_rectangle, FS_BOTTOM, FS_LEFT, FS_RIGHT, FS_TOP, IF_BOTTOM,
    IF_INTERFACE, IF_LEFT, IF_RIGHT, IF_TOP,
};

/// [`structured_rectangle`]: the side y = y0.
pub const RECT_BOTTOM: i32 = 1;
/// [`structured_rectangle`]: the side x = x1.
pub const RECT_RIGHT: i32 = 2;
/// [`structured_rectangle`]: the side y = y1.
pub const RECT_TOP: i32 = 3;
/// [`structured_rectangle`]: the side x = x0.
pub const RECT_LEFT: i32 = 4;

/// `i`-th of `n` equal steps from `a` to `b`, hitting both ends exactly.
pub(super) fn lerp_step(a: f64, b: f64, i: usize, n: usize) -> f64 {
    if i == n {
        b
    } else {
        a + (b - a) * (i as f64 / n as f64)
    }
}

/// [x0, x1] × [y0, y1] as (nx + 1)(ny + 1) vertices, vertex (i, j) at index j (nx + 1) + i; each
/// quad split along the same diagonal, from its lower-left to its upper-right corner, into
/// 2 nx ny triangles. Patches [`RECT_BOTTOM`], [`RECT_RIGHT`], [`RECT_TOP`], [`RECT_LEFT`].
pub fn structured_rectangle(nx: usize, ny: usize, x0: f64, x1: f64, y0: f64, y1: f64) -> Mesh {
    assert!(nx >= 1 && ny >= 1, "structured_rectangle: nx, ny >= 1");
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut coords = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            coords.push([lerp_step(x0, x1, i, nx), lerp_step(y0, y1, j, ny)]);
        }
    }
    let mut tris = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mut tagged = Vec::with_capacity(2 * (nx + ny));
    for i in 0..nx {
        tagged.push(([id(i, 0), id(i + 1, 0)], RECT_BOTTOM));
        tagged.push(([id(i, ny), id(i + 1, ny)], RECT_TOP));
    }
    for j in 0..ny {
        tagged.push(([id(nx, j), id(nx, j + 1)], RECT_RIGHT));
        tagged.push(([id(0, j), id(0, j + 1)], RECT_LEFT));
    }
    Mesh::triangles(&coords, &tris, IndexBase::Zero, &tagged, None).expect("structured_rectangle")
}

/// Builds the validated mesh of a planar triangulation; tags with patch 0 are left untagged.
pub(super) fn to_mesh(p: &Planar, regions: Option<&[i32]>, what: &str) -> Mesh {
    let coords: Vec<[f64; 2]> = p.coords.iter().map(|v: &DVec2| [v.x, v.y]).collect();
    let tagged: Vec<([u32; 2], i32)> = p.tagged.iter().copied().filter(|t| t.1 != 0).collect();
    Mesh::triangles(&coords, &p.tris, IndexBase::Zero, &tagged, regions)
        .unwrap_or_else(|e| panic!("{what}: invalid mesh: {e}"))
}

#[cfg(test)]
pub(super) mod test_util {
    use meshmove::mesh::signed_measures;
    use meshmove::mesh::Mesh;

    pub fn total_area(m: &Mesh) -> f64 {
        signed_measures(m, m.coords()).iter().sum()
    }

    pub fn min_angle(m: &Mesh) -> f64 {
        meshmove::mesh::quality::quality(m, m.coords()).min_angle_deg
    }

    /// (min, mean, max) edge length.
    pub fn edge_lengths(m: &Mesh) -> (f64, f64, f64) {
        let mut e: Vec<(u32, u32)> = m
            .tris()
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])].map(|(a, b)| (a.min(b), a.max(b))))
            .collect();
        e.sort_unstable();
        e.dedup();
        let c = m.points_2d();
        let l: Vec<f64> = e.iter().map(|&(a, b)| (c[a as usize] - c[b as usize]).length()).collect();
        let mean = l.iter().sum::<f64>() / l.len() as f64;
        (l.iter().copied().fold(f64::INFINITY, f64::min), mean, l.iter().copied().fold(0.0, f64::max))
    }

    /// Area of a regular n-gon inscribed in a circle of radius r.
    pub fn polygon_area(n: usize, r: f64) -> f64 {
        0.5 * n as f64 * r * r * (2.0 * std::f64::consts::PI / n as f64).sin()
    }
}

#[cfg(test)]
mod tests {
    use super::test_util::*;
    use super::*;

    #[test]
    fn structured_rectangle_counts_and_patches() {
        let m = structured_rectangle(8, 4, 0.0, 2.0, -1.0, 0.0);
        assert_eq!(m.num_vertices(), 9 * 5);
        assert_eq!(m.num_cells(), 2 * 8 * 4);
        assert!((total_area(&m) - 2.0).abs() < 1e-12);
        assert_eq!(m.patch_ids(), vec![1, 2, 3, 4]);
        assert_eq!(m.patch_vertices(RECT_BOTTOM).len(), 9);
        assert_eq!(m.patch_vertices(RECT_TOP).len(), 9);
        assert_eq!(m.patch_vertices(RECT_LEFT).len(), 5);
        assert_eq!(m.patch_vertices(RECT_RIGHT).len(), 5);
        for &v in &m.patch_vertices(RECT_RIGHT) {
            assert_eq!(m.point(v as usize)[0], 2.0);
        }
        for &v in &m.patch_vertices(RECT_BOTTOM) {
            assert_eq!(m.point(v as usize)[1], -1.0);
        }
        // Cells: right triangles with legs 0.25, 0.25: min angle 45°.
        assert!((min_angle(&m) - 45.0).abs() < 1e-9);
    }
}
