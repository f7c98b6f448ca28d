//! Cylinder cases: a cylinder in a channel, and a cylinder with a structured wall layer.

use super::cdt::{mesh_domain, mesh_lattice, Loop, Planar};
use super::free_surface::rect_loop;
use super::meshes::to_mesh;
use glam::DVec2;
use meshmove::mesh::Mesh;
use std::f64::consts::PI;

/// [`cylinder_channel`]: the four channel walls (y = ±1, x = 0, x = 8).
pub const CH_WALL: i32 = 1;
/// [`cylinder_channel`]: the cylinder.
pub const CH_CYLINDER: i32 = 2;

/// [`boundary_layer_cylinder`]: the far-field rectangle [−10,20]×[−10,10].
pub const BL_FAR: i32 = 1;
/// [`boundary_layer_cylinder`]: the cylinder.
pub const BL_CYLINDER: i32 = 2;
/// [`boundary_layer_cylinder`]: height of the first wall layer.
pub const BL_FIRST_HEIGHT: f64 = 0.005;
/// [`boundary_layer_cylinder`]: ratio of successive layer heights.
pub const BL_GROWTH: f64 = 1.2;
/// [`boundary_layer_cylinder`]: number of structured layers.
pub const BL_LAYERS: usize = 15;
/// [`boundary_layer_cylinder`]: vertices around the cylinder (and around every layer).
pub const BL_N_THETA: usize = 128;

/// [`ellipse_in_box`]: the box [−3,3]×[−2,2].
pub const EL_BOX: i32 = 1;
/// [`ellipse_in_box`]: the ellipse.
pub const EL_ELLIPSE: i32 = 2;

/// The box [−3,3]×[−2,2] minus the ellipse of semi-axes `a` (along x) and `b` about the origin
/// (a polygon of 96 vertices), graded from the ellipse's spacing to about 0.3 at the box.
/// Patches [`EL_BOX`], [`EL_ELLIPSE`].
pub fn ellipse_in_box(a: f64, b: f64) -> Mesh {
    assert!(a > 0.0 && b > 0.0 && a < 2.5 && b < 1.5, "ellipse_in_box: the ellipse must fit the box");
    let n = 96;
    let ell: Vec<DVec2> = (0..n)
        .map(|j| {
            let t = 2.0 * PI * j as f64 / n as f64;
            DVec2::new(a * t.cos(), b * t.sin())
        })
        .collect();
    let h = ell.windows(2).map(|w| (w[1] - w[0]).length()).fold(0.0, f64::max);
    let outer = rect_loop([-3.0, 3.0, -2.0, 2.0], 20, 14, [EL_BOX; 4]);
    let hole = Loop { points: ell, patches: vec![EL_ELLIPSE; n] };
    let size = |p: DVec2| {
        let d = ((p.x / a).powi(2) + (p.y / b).powi(2)).sqrt().max(1.0) - 1.0;
        (h + 0.12 * d * b.max(a)).min(0.3)
    };
    let p = mesh_domain(&[outer, hole], &size, 30.0, 2);
    to_mesh(&p, None, "ellipse_in_box")
}

/// `n` points on the circle of radius `r` about `c`, counter-clockwise from angle 0.
fn circle(c: DVec2, r: f64, n: usize) -> Vec<DVec2> {
    (0..n)
        .map(|j| {
            let t = 2.0 * PI * j as f64 / n as f64;
            c + r * DVec2::new(t.cos(), t.sin())
        })
        .collect()
}

/// \[0,8\]×[−1,1] minus the cylinder of diameter 1 about (2, 0) (a regular polygon of
/// 4 round(π / 4h) ≥ 16 vertices), uniform edge length about `h` (n = round(1/h) segments per
/// unit of wall; jittered hexagonal lattice inside). Patches [`CH_WALL`], [`CH_CYLINDER`].
/// h = 1/8: 1,171 vertices, 24 on the cylinder, min angle 36°; pass h = 1/12 for ≈ 2,600.
pub fn cylinder_channel(h: f64) -> Mesh {
    assert!(h > 0.0 && h <= 0.25, "cylinder_channel: 0 < h <= 1/4");
    let n = (1.0 / h).round() as usize;
    let s = 1.0 / n as f64;
    let outer = rect_loop([0.0, 8.0, -1.0, 1.0], 8 * n, 2 * n, [CH_WALL, CH_WALL, CH_WALL, CH_WALL]);
    let nc = (4 * (PI / (4.0 * s)).round() as usize).max(16);
    let cyl = Loop { points: circle(DVec2::new(2.0, 0.0), 0.5, nc), patches: vec![CH_CYLINDER; nc] };
    let p = mesh_lattice(&[outer, cyl], s, 0.2, 30.0, 2);
    to_mesh(&p, None, "cylinder_channel")
}

/// Radius of ring `k` of the wall layer (ring 0 is the cylinder, radius 1/2).
fn ring_radius(k: usize) -> f64 {
    0.5 + BL_FIRST_HEIGHT * (BL_GROWTH.powi(k as i32) - 1.0) / (BL_GROWTH - 1.0)
}

/// Domain [−10,20]×[−10,10], cylinder of diameter 1 at the origin (a regular polygon of
/// [`BL_N_THETA`] vertices). Around it [`BL_LAYERS`] structured layers of quads split into
/// triangles, the first [`BL_FIRST_HEIGHT`] high, each [`BL_GROWTH`] times the last, all on the
/// same radial lines; outside the layer, unstructured triangles graded from the layer's
/// tangential spacing (≈ 0.042) to about 1 at the far boundary. Patches [`BL_FAR`],
/// [`BL_CYLINDER`]. Vertex order: the unstructured part first (its far boundary, then the
/// layer's outer ring, then the Steiner points), then the rings 0 (the cylinder), 1, …,
/// [`BL_LAYERS`] − 1 of [`BL_N_THETA`] vertices each, counter-clockwise from angle 0.
pub fn boundary_layer_cylinder() -> Mesh {
    let (mut p, quads) = boundary_layer_parts();
    // Each quad a, b, c, d as the triangles a c d and a b c.
    for [a, b, c, d] in quads {
        p.tris.push([a, c, d]);
        p.tris.push([a, b, c]);
    }
    to_mesh(&p, None, "boundary_layer_cylinder")
}

/// The parts of [`boundary_layer_cylinder`]: every vertex, the unstructured triangles and the
/// tagged edges (the layer's outer ring on patch 0) as a `Planar`, and the wall layers' quads,
/// ring by ring from the cylinder, counter-clockwise (ring k at angles j and j + 1 are corners
/// 0 and 3, ring k + 1 corners 1 and 2).
pub(super) fn boundary_layer_parts() -> (Planar, Vec<[u32; 4]>) {
    let nt = BL_N_THETA;
    let nl = BL_LAYERS;
    let r_out = ring_radius(nl);
    let far = 1.0;
    let outer = rect_loop([-10.0, 20.0, -10.0, 10.0], 30, 20, [BL_FAR, BL_FAR, BL_FAR, BL_FAR]);
    let n_outer = outer.points.len();
    let ring = Loop {
        points: circle(DVec2::ZERO, r_out, nt),
        patches: vec![0; nt], // interior edges: untagged
    };
    let s0 = 2.0 * PI * r_out / nt as f64;
    let size = move |p: DVec2| (s0 + 0.2 * (p.length() - r_out).max(0.0)).min(far);
    let mut p = mesh_domain(&[outer, ring], &size, 30.0, 0);

    let base = p.coords.len();
    for k in 0..nl {
        p.coords.extend(circle(DVec2::ZERO, ring_radius(k), nt));
    }
    let id = |k: usize, j: usize| -> u32 {
        let j = j % nt;
        if k == nl {
            (n_outer + j) as u32
        } else {
            (base + k * nt + j) as u32
        }
    };
    // Ring k + 1 lies outside ring k.
    let quads = (0..nl).flat_map(|k| (0..nt).map(move |j| [id(k, j), id(k + 1, j), id(k + 1, j + 1), id(k, j + 1)]));
    let quads = quads.collect();
    p.tagged.extend((0..nt).map(|j| ([id(0, j), id(0, j + 1)], BL_CYLINDER)));
    (p, quads)
}

#[cfg(test)]
mod tests {
    use super::super::meshes::test_util::*;
    use super::*;

    #[test]
    fn cylinder_channel_h8() {
        let m = cylinder_channel(0.125);
        let nv = m.num_vertices();
        let nc = m.patch_vertices(CH_CYLINDER).len();
        eprintln!(
            "cylinder_channel(1/8): {nv} vertices, {} cells, {nc} on cylinder, min angle {:.2}",
            m.num_cells(),
            min_angle(&m)
        );
        assert_eq!(nc, 24);
        assert_eq!(m.patch_vertices(CH_WALL).len(), 2 * (64 + 16));
        assert_eq!(m.patch_ids(), vec![1, 2]);
        assert!((total_area(&m) - (16.0 - polygon_area(nc, 0.5))).abs() < 1e-10);
        for &v in &m.patch_vertices(CH_CYLINDER) {
            let d = m.points_2d()[v as usize] - DVec2::new(2.0, 0.0);
            assert!((d.length() - 0.5).abs() < 1e-14);
        }
        assert!(min_angle(&m) >= 25.0, "min angle {}", min_angle(&m));
        assert!((1000..=6000).contains(&nv), "{nv} vertices");
    }

    #[test]
    fn boundary_layer() {
        let m = boundary_layer_cylinder();
        let nv = m.num_vertices();
        let c = m.points_2d();
        let r_out = ring_radius(BL_LAYERS);
        // Unstructured part: cells with a vertex outside the layer.
        let angles: Vec<f64> = (0..m.num_cells()).map(|c| crate::ogrid::cell_min_angle(&m, c)).collect();
        let unstructured_min = m
            .tris()
            .iter()
            .zip(&angles)
            .filter(|(t, _)| t.iter().any(|&v| c[v as usize].length() > r_out + 1e-9))
            .map(|(_, &a)| a)
            .fold(180.0, f64::min);
        eprintln!(
            "boundary_layer_cylinder: {nv} vertices, {} cells, min angle {:.2} (unstructured {:.2}), layer thickness {:.4}",
            m.num_cells(),
            min_angle(&m),
            unstructured_min,
            r_out - 0.5
        );
        assert!(nv <= 20_000, "{nv} vertices");
        assert!(nv >= BL_N_THETA * (BL_LAYERS + 1) + 100);
        assert_eq!(m.patch_ids(), vec![1, 2]);
        let cyl = m.patch_vertices(BL_CYLINDER);
        assert_eq!(cyl.len(), BL_N_THETA);
        assert_eq!(m.patch_vertices(BL_FAR).len(), 100);
        let hole = polygon_area(BL_N_THETA, 0.5);
        assert!((total_area(&m) - (600.0 - hole)).abs() < 1e-9);
        // First layer height: every ring-1 vertex is 0.005 outside the cylinder, radially.
        let n = m.num_vertices();
        let ring1 = &c[n - (BL_LAYERS - 1) * BL_N_THETA..n - (BL_LAYERS - 2) * BL_N_THETA];
        for (j, p) in ring1.iter().enumerate() {
            assert!((p.length() - 0.5 - BL_FIRST_HEIGHT).abs() < 1e-9, "ring 1 vertex {j}");
        }
        for &v in &cyl {
            assert!((c[v as usize].length() - 0.5).abs() < 1e-14);
        }
        assert!(unstructured_min >= 20.0, "unstructured min angle {unstructured_min}");
        // Wall cells: thin, aspect about (2π·0.5/128)/0.005 ≈ 4.9.
        assert!(min_angle(&m) > 5.0);
    }
}
