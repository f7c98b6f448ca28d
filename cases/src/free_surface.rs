//! The free-surface box \[0,1\]×[−1,0] and the two-region interface mesh built from it by mirroring.

use super::cdt::{mesh_lattice, Loop, Planar};
use super::meshes::{lerp_step, to_mesh};
use glam::DVec2;
use meshmove::mesh::Mesh;

/// [`free_surface`]: the bottom, y = −1.
pub const FS_BOTTOM: i32 = 1;
/// [`free_surface`]: the right side, x = 1 (linked periodically to [`FS_LEFT`]).
pub const FS_RIGHT: i32 = 2;
/// [`free_surface`]: the top, y = 0 (the free surface).
pub const FS_TOP: i32 = 3;
/// [`free_surface`]: the left side, x = 0 (vertices at the same y as [`FS_RIGHT`]'s).
pub const FS_LEFT: i32 = 4;

/// [`two_region_interface`]: the bottom, y = −1.
pub const IF_BOTTOM: i32 = 1;
/// [`two_region_interface`]: both right sides, x = 1.
pub const IF_RIGHT: i32 = 2;
/// [`two_region_interface`]: the interface y = 0, tagged interior edges between the regions.
pub const IF_INTERFACE: i32 = 3;
/// [`two_region_interface`]: both left sides, x = 0.
pub const IF_LEFT: i32 = 4;
/// [`two_region_interface`]: the top, y = +1.
pub const IF_TOP: i32 = 5;

/// Counter-clockwise boundary of [x0, x1] × [y0, y1] with `nx`, `ny` equal segments per side;
/// `patches` = [bottom, right, top, left]. Left and right points share their y exactly.
pub(super) fn rect_loop([x0, x1, y0, y1]: [f64; 4], nx: usize, ny: usize, patches: [i32; 4]) -> Loop {
    let mut points = Vec::with_capacity(2 * (nx + ny));
    let mut tags = Vec::with_capacity(2 * (nx + ny));
    for i in 0..nx {
        points.push(DVec2::new(lerp_step(x0, x1, i, nx), y0));
        tags.push(patches[0]);
    }
    for j in 0..ny {
        points.push(DVec2::new(x1, lerp_step(y0, y1, j, ny)));
        tags.push(patches[1]);
    }
    for i in (1..=nx).rev() {
        points.push(DVec2::new(lerp_step(x0, x1, i, nx), y1));
        tags.push(patches[2]);
    }
    for j in (1..=ny).rev() {
        points.push(DVec2::new(x0, lerp_step(y0, y1, j, ny)));
        tags.push(patches[3]);
    }
    Loop { points, patches: tags }
}

fn free_surface_planar(h: f64) -> Planar {
    assert!(h > 0.0 && h <= 0.5, "free_surface: 0 < h <= 1/2");
    let n = (1.0 / h).round() as usize;
    let s = 1.0 / n as f64;
    let outer = rect_loop([0.0, 1.0, -1.0, 0.0], n, n, [FS_BOTTOM, FS_RIGHT, FS_TOP, FS_LEFT]);
    mesh_lattice(&[outer], s, 0.2, 30.0, 2)
}

/// Unstructured triangles of \[x0, x1\] × \[y0, y1\] with edge length about `h` (the free surface's
/// lattice mesher), patches [`FS_BOTTOM`], [`FS_RIGHT`], [`FS_TOP`], [`FS_LEFT`].
pub fn unstructured_rectangle([x0, x1, y0, y1]: [f64; 4], h: f64) -> Mesh {
    assert!(h > 0.0 && x1 > x0 && y1 > y0, "unstructured_rectangle: h > 0 and a non-empty box");
    let (nx, ny) = (((x1 - x0) / h).round().max(1.0) as usize, ((y1 - y0) / h).round().max(1.0) as usize);
    let outer = rect_loop([x0, x1, y0, y1], nx, ny, [FS_BOTTOM, FS_RIGHT, FS_TOP, FS_LEFT]);
    to_mesh(&mesh_lattice(&[outer], (x1 - x0) / nx as f64, 0.2, 30.0, 2), None, "unstructured_rectangle")
}

/// Unstructured triangles of \[0,1\]×[−1,0] with edge length about `h`: n = round(1/h) equal
/// boundary segments per side (left and right vertices at bitwise-equal y; the top has n + 1
/// vertices), the interior a deterministically jittered hexagonal lattice, triangulated,
/// Delaunay-refined (boundary segments never split) and smoothed. Patches [`FS_BOTTOM`],
/// [`FS_RIGHT`], [`FS_TOP`], [`FS_LEFT`]. h = 1/32: 1,227 vertices, 2,324 cells, min angle 33.6°,
/// edge lengths 0.71–1.45 h.
pub fn free_surface(h: f64) -> Mesh {
    to_mesh(&free_surface_planar(h), None, "free_surface")
}

/// [`free_surface`]`(h)` (region 0) and its exact mirror y → −y (region 1), sharing the n + 1
/// vertices of y = 0: \[0,1\]×[−1,1]. The mirror of lower vertex (x, y) is (x, −y) bitwise.
/// Patches [`IF_BOTTOM`], [`IF_RIGHT`] (both halves), [`IF_TOP`], [`IF_LEFT`] (both halves),
/// and [`IF_INTERFACE`] on y = 0 as tagged interior edges. Lower vertices keep the indices of
/// `free_surface(h)`; upper vertices not on y = 0 follow in the same order.
pub fn two_region_interface(h: f64) -> Mesh {
    let lower = free_surface_planar(h);
    let n = lower.coords.len();
    let mut coords = lower.coords.clone();
    let mut mirror = vec![0u32; n];
    for (i, p) in lower.coords.iter().enumerate() {
        if p.y == 0.0 {
            mirror[i] = i as u32;
        } else {
            mirror[i] = coords.len() as u32;
            coords.push(DVec2::new(p.x, -p.y));
        }
    }
    let mut tris = lower.tris.clone();
    // Mirroring reverses orientation; swap two vertices to keep the cells counter-clockwise.
    tris.extend(lower.tris.iter().map(|t| [mirror[t[0] as usize], mirror[t[2] as usize], mirror[t[1] as usize]]));
    let mut regions = vec![0; lower.tris.len()];
    regions.resize(tris.len(), 1);
    let mut tagged = Vec::with_capacity(2 * lower.tagged.len());
    for &(e, patch) in &lower.tagged {
        let (lo, up) = match patch {
            FS_BOTTOM => (IF_BOTTOM, Some(IF_TOP)),
            FS_RIGHT => (IF_RIGHT, Some(IF_RIGHT)),
            FS_LEFT => (IF_LEFT, Some(IF_LEFT)),
            FS_TOP => (IF_INTERFACE, None),
            _ => unreachable!("free_surface patch {patch}"),
        };
        tagged.push((e, lo));
        if let Some(up) = up {
            tagged.push((e.map(|v| mirror[v as usize]), up));
        }
    }
    let planar = Planar { coords, tris, tagged };
    to_mesh(&planar, Some(&regions), "two_region_interface")
}

#[cfg(test)]
mod tests {
    use super::super::meshes::test_util::*;
    use super::*;

    #[test]
    fn free_surface_h32() {
        let h = 1.0 / 32.0;
        let m = free_surface(h);
        let nv = m.num_vertices();
        eprintln!("free_surface(1/32): {nv} vertices, {} cells, min angle {:.2}", m.num_cells(), min_angle(&m));
        let (lmin, lmean, lmax) = edge_lengths(&m);
        eprintln!("  edge lengths / h: min {:.3} mean {:.3} max {:.3}", lmin / h, lmean / h, lmax / h);
        assert!((1200..=1500).contains(&nv), "{nv} vertices");
        assert!(lmin > 0.5 * h && lmax < 1.6 * h && (lmean / h - 1.0).abs() < 0.15);
        assert!((total_area(&m) - 1.0).abs() < 1e-10);
        assert_eq!(m.patch_ids(), vec![1, 2, 3, 4]);
        for p in [FS_BOTTOM, FS_RIGHT, FS_TOP, FS_LEFT] {
            assert_eq!(m.patch_vertices(p).len(), 33, "patch {p}");
        }
        let ys = |p: i32| {
            let mut y: Vec<f64> = m.patch_vertices(p).iter().map(|&v| m.point(v as usize)[1]).collect();
            y.sort_by(f64::total_cmp);
            y
        };
        assert_eq!(ys(FS_LEFT), ys(FS_RIGHT));
        for (j, y) in ys(FS_LEFT).iter().enumerate() {
            assert!((y - (-1.0 + j as f64 / 32.0)).abs() < 1e-15);
        }
        for &v in &m.patch_vertices(FS_TOP) {
            assert_eq!(m.point(v as usize)[1], 0.0);
        }
        assert!(min_angle(&m) >= 25.0, "min angle {}", min_angle(&m));
        // Deterministic.
        let again = free_surface(h);
        assert_eq!(again.points_2d(), m.points_2d());
        assert_eq!(again.tris(), m.tris());
    }

    #[test]
    fn free_surface_coarse() {
        let m = free_surface(0.125);
        assert!((total_area(&m) - 1.0).abs() < 1e-10);
        assert_eq!(m.patch_vertices(FS_TOP).len(), 9);
        assert!(min_angle(&m) >= 20.0, "min angle {}", min_angle(&m));
    }

    #[test]
    fn two_region_mirror() {
        let h = 1.0 / 32.0;
        let lower = free_surface(h);
        let m = two_region_interface(h);
        let nl = lower.num_vertices();
        assert_eq!(m.num_vertices(), 2 * nl - 33);
        assert_eq!(m.num_cells(), 2 * lower.num_cells());
        assert!((total_area(&m) - 2.0).abs() < 1e-10);
        assert_eq!(&m.points_2d()[..nl], lower.points_2d());
        // Every vertex's mirror is a vertex, bitwise.
        let key = |p: DVec2| (p.x.to_bits(), p.y.to_bits());
        let set: std::collections::HashSet<_> = m.points_2d().iter().map(|&p| key(p)).collect();
        for p in lower.points_2d() {
            let q = if p.y == 0.0 { p } else { DVec2::new(p.x, -p.y) };
            assert!(set.contains(&key(q)), "no mirror of {p}");
        }
        let upper: Vec<_> = m.points_2d()[nl..].to_vec();
        assert!(upper.iter().all(|p| p.y > 0.0));
        // Regions: equal counts, region 1 above y = 0.
        let r = m.regions();
        assert_eq!(r.iter().filter(|&&x| x == 0).count(), lower.num_cells());
        for (c, t) in m.tris().iter().enumerate() {
            let cy: f64 = t.iter().map(|&v| m.point(v as usize)[1]).sum::<f64>() / 3.0;
            assert_eq!(r[c], i32::from(cy > 0.0));
        }
        assert_eq!(m.patch_ids(), vec![1, 2, 3, 4, 5]);
        assert_eq!(m.patch_vertices(IF_BOTTOM).len(), 33);
        assert_eq!(m.patch_vertices(IF_TOP).len(), 33);
        assert_eq!(m.patch_vertices(IF_INTERFACE).len(), 33);
        assert_eq!(m.patch_vertices(IF_LEFT).len(), 65);
        assert_eq!(m.patch_vertices(IF_RIGHT).len(), 65);
        let iface: Vec<_> = m.patch_edges().into_iter().filter(|e| e.patch == IF_INTERFACE).collect();
        assert_eq!(iface.len(), 32);
        assert!(iface.iter().all(|e| e.interior));
        assert!(m.patch_edges().iter().all(|e| (e.patch == IF_INTERFACE) == e.interior));
        assert!(min_angle(&m) >= 25.0);
    }
}
