//! 2D meshes with quads, as [`MeshData`]: a structured quad rectangle, and the boundary-layer
//! cylinder with its wall layers as quads.
//!
//! They are plain arrays, as a host code would hand them over; `Mesh::from_data` validates them.

use super::cylinder::boundary_layer_parts;
use super::meshes::{lerp_step, RECT_BOTTOM, RECT_LEFT, RECT_RIGHT, RECT_TOP};
use meshmove::geometry::CellType;
use meshmove::mesh::MeshData;

/// [x0, x1] × [y0, y1] (`bounds` = [x0, x1, y0, y1]) as (nx + 1)(ny + 1) vertices, vertex (i, j)
/// at index j (nx + 1) + i, and nx ny counter-clockwise quads, row by row from (0, 0). Tagged
/// faces, each with the domain on its left: [`RECT_BOTTOM`] (1), [`RECT_RIGHT`] (2),
/// [`RECT_TOP`] (3), [`RECT_LEFT`] (4), in that order.
pub fn structured_quads(nx: usize, ny: usize, bounds: [f64; 4]) -> MeshData {
    assert!(nx >= 1 && ny >= 1, "structured_quads: nx, ny >= 1");
    let [x0, x1, y0, y1] = bounds;
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut d = MeshData::new(2);
    for j in 0..=ny {
        for i in 0..=nx {
            d.push_vertex(&[lerp_step(x0, x1, i, nx), lerp_step(y0, y1, j, ny)]);
        }
    }
    for j in 0..ny {
        for i in 0..nx {
            d.push_cell(CellType::Quad, &[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)], 0);
        }
    }
    (0..nx).for_each(|i| d.push_face(&[id(i, 0), id(i + 1, 0)], RECT_BOTTOM));
    (0..ny).for_each(|j| d.push_face(&[id(nx, j), id(nx, j + 1)], RECT_RIGHT));
    (0..nx).rev().for_each(|i| d.push_face(&[id(i + 1, ny), id(i, ny)], RECT_TOP));
    (0..ny).rev().for_each(|j| d.push_face(&[id(0, j + 1), id(0, j)], RECT_LEFT));
    d
}

/// [`boundary_layer_cylinder`](super::meshes::boundary_layer_cylinder) with its wall layers as
/// quads: the same vertices in the same order, the same patches ([`BL_FAR`](super::meshes::BL_FAR),
/// [`BL_CYLINDER`](super::meshes::BL_CYLINDER)); the unstructured triangles first, then
/// [`BL_LAYERS`](super::meshes::BL_LAYERS) × [`BL_N_THETA`](super::meshes::BL_N_THETA)
/// counter-clockwise quads, ring by ring from the cylinder (each the pair of triangles the
/// triangle mesh splits it into).
pub fn boundary_layer_cylinder_hybrid() -> MeshData {
    let (p, quads) = boundary_layer_parts();
    let mut d = MeshData::new(2);
    p.coords.iter().for_each(|v| {
        d.push_vertex(&[v.x, v.y]);
    });
    p.tris.iter().for_each(|t| d.push_cell(CellType::Triangle, t, 0));
    quads.iter().for_each(|q| d.push_cell(CellType::Quad, q, 0));
    // As the triangle mesh: the layer's outer ring (patch 0) is not tagged.
    p.tagged.iter().filter(|t| t.1 != 0).for_each(|(e, patch)| d.push_face(e, *patch));
    d
}

#[cfg(test)]
mod tests {
    use super::super::meshes::{boundary_layer_cylinder, BL_CYLINDER, BL_FAR, BL_LAYERS, BL_N_THETA};
    use super::*;
    use meshmove::mesh::signed_measures;

    /// Twice the signed area of the triangle (a, b, c).
    fn cross(a: &[f64], b: &[f64], c: &[f64]) -> f64 {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    }

    /// The sum of `v`, compensated (Neumaier): meshes of thousands of cells of area up to 1 sum
    /// to about 600 with rounding errors of 1e-11 otherwise.
    fn sum(v: impl Iterator<Item = f64>) -> f64 {
        let (mut s, mut c) = (0.0f64, 0.0);
        for x in v {
            let t = s + x;
            c += if s.abs() >= x.abs() { (s - t) + x } else { (x - t) + s };
            s = t;
        }
        s + c
    }

    /// Signed area of cell `c` (its corners as a polygon).
    fn area(d: &MeshData, c: usize) -> f64 {
        let v = d.cell(c);
        let p = |k: usize| d.point(v[k % v.len()] as usize);
        (1..v.len() - 1).map(|k| 0.5 * cross(p(0), p(k), p(k + 1))).sum()
    }

    /// Every corner of cell `c` turns left: a convex counter-clockwise polygon.
    fn convex(d: &MeshData, c: usize) -> bool {
        let v = d.cell(c);
        let p = |k: usize| d.point(v[k % v.len()] as usize);
        (0..v.len()).all(|k| cross(p(k), p(k + 1), p(k + 2)) > 0.0)
    }

    #[test]
    fn structured_quads_counts_patches_and_orientation() {
        let d = structured_quads(4, 3, [0.0, 2.0, -1.0, 0.5]);
        assert_eq!((d.num_vertices(), d.num_cells(), d.num_faces()), (20, 12, 14));
        assert!(d.cell_types.iter().all(|&t| t == CellType::Quad));
        assert!(d.regions.is_empty());
        assert!((0..12).all(|c| convex(&d, c)));
        let total: f64 = (0..12).map(|c| area(&d, c)).sum();
        assert!((total - 3.0).abs() < 1e-12, "{total}");
        let on = |patch: i32, axis: usize, value: f64| {
            let faces: Vec<usize> = (0..d.num_faces()).filter(|&f| d.face_patch[f] == patch).collect();
            assert!(faces.iter().all(|&f| d.face(f).iter().all(|&v| d.point(v as usize)[axis] == value)));
            faces.len()
        };
        assert_eq!(on(RECT_BOTTOM, 1, -1.0), 4);
        assert_eq!(on(RECT_RIGHT, 0, 2.0), 3);
        assert_eq!(on(RECT_TOP, 1, 0.5), 4);
        assert_eq!(on(RECT_LEFT, 0, 0.0), 3);
        // The faces run counter-clockwise around the domain, each ending where the next starts.
        for f in 0..d.num_faces() {
            assert_eq!(d.face(f)[1], d.face((f + 1) % d.num_faces())[0]);
        }
    }

    #[test]
    fn hybrid_boundary_layer_matches_the_triangle_mesh() {
        let d = boundary_layer_cylinder_hybrid();
        let m = boundary_layer_cylinder();
        assert_eq!(d.num_vertices(), m.num_vertices());
        for (v, p) in m.points_2d().iter().enumerate() {
            assert_eq!(d.point(v), &[p.x, p.y]);
        }
        let quads: Vec<usize> = (0..d.num_cells()).filter(|&c| d.cell_types[c] == CellType::Quad).collect();
        assert_eq!(quads.len(), BL_LAYERS * BL_N_THETA);
        assert_eq!(d.num_cells() + quads.len(), m.num_cells());
        assert!(quads.iter().all(|&c| convex(&d, c)), "a wall-layer quad is not convex");
        assert!((0..d.num_cells()).all(|c| area(&d, c) > 0.0), "a cell is not counter-clockwise");
        let total = sum((0..d.num_cells()).map(|c| area(&d, c)));
        let triangles = sum(signed_measures(&m, m.coords()).into_iter());
        assert!((total - triangles).abs() < 1e-12, "{total} vs {triangles}");
        // The same tagged faces as the triangle mesh's patches (whose edges are oriented by it).
        let sorted = |a: u32, b: u32| [a.min(b), a.max(b)];
        let mut faces: Vec<_> =
            (0..d.num_faces()).map(|f| (sorted(d.face(f)[0], d.face(f)[1]), d.face_patch[f])).collect();
        let mut edges: Vec<_> =
            m.patch_edges().iter().map(|e| (sorted(e.vertices[0], e.vertices[1]), e.patch)).collect();
        faces.sort_unstable();
        edges.sort_unstable();
        assert_eq!(faces, edges);
        assert_eq!(faces.iter().filter(|f| f.1 == BL_CYLINDER).count(), BL_N_THETA);
        assert_eq!(faces.iter().filter(|f| f.1 == BL_FAR).count(), 100);
    }
}
