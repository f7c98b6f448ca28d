//! Plane sections of a 3D mesh, for pictures: the polygon each cell cuts from a plane x_axis =
//! value, and the segments a patch's faces cut from it, in the plane's own 2D coordinates.
//!
//! A cell's section is the polygon through the points where its edges cross the plane, ordered
//! by angle about their centroid (exact for a convex cell with planar faces; for a warped
//! hexahedron face or an inverted cell it is the picture's approximation).

use meshmove::mesh::Mesh;

/// The two axes a section of the plane normal to `axis` is drawn in: (horizontal, vertical) =
/// (y, z) for x, (x, z) for y, (x, y) for z.
pub fn section_axes(axis: usize) -> [usize; 2] {
    match axis {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    }
}

/// One cell's section.
#[derive(Clone, Debug, PartialEq)]
pub struct CellSection {
    /// The cell.
    pub cell: usize,
    /// The polygon's corners in the plane's coordinates ([`section_axes`]).
    pub polygon: Vec<[f64; 2]>,
}

/// Where the segment from `a` to `b` (signed distances `sa`, `sb` of opposite signs) crosses the
/// plane, in the plane's coordinates.
fn crossing(a: &[f64], b: &[f64], sa: f64, sb: f64, ax: [usize; 2]) -> [f64; 2] {
    let t = sa / (sa - sb);
    ax.map(|k| a[k] + t * (b[k] - a[k]))
}

/// `pts` ordered by angle about their centroid.
fn by_angle(mut pts: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    let n = pts.len() as f64;
    let c = [pts.iter().map(|p| p[0]).sum::<f64>() / n, pts.iter().map(|p| p[1]).sum::<f64>() / n];
    pts.sort_by(|p, q| (p[1] - c[1]).atan2(p[0] - c[0]).total_cmp(&(q[1] - c[1]).atan2(q[0] - c[0])));
    pts
}

/// The sections of the cells of `mesh`'s topology at positions `coords` (3 per vertex) by the
/// plane x_`axis` = `value`, in cell order. A vertex exactly on the plane counts as above it, so
/// a cell touching the plane at a vertex, edge or face only has no section.
pub fn cell_sections(mesh: &Mesh, coords: &[f64], axis: usize, value: f64) -> Vec<CellSection> {
    assert_eq!(mesh.dim(), 3, "cell_sections: a 3D mesh");
    let ax = section_axes(axis);
    let p = |v: u32| &coords[3 * v as usize..3 * v as usize + 3];
    let s = |v: u32| p(v)[axis] - value;
    let mut out = Vec::new();
    for c in 0..mesh.num_cells() {
        let cell = mesh.cell(c);
        let (below, above) = (cell.iter().any(|&v| s(v) < 0.0), cell.iter().any(|&v| s(v) >= 0.0));
        if !(below && above) {
            continue;
        }
        let mut pts = Vec::new();
        for e in mesh.cell_type(c).edges() {
            let (a, b) = (cell[e[0] as usize], cell[e[1] as usize]);
            let (sa, sb) = (s(a), s(b));
            if (sa < 0.0) != (sb < 0.0) {
                pts.push(crossing(p(a), p(b), sa, sb, ax));
            }
        }
        out.push(CellSection { cell: c, polygon: by_angle(pts) });
    }
    out
}

/// The segments the faces of `patch` at positions `coords` cut from the plane x_`axis` =
/// `value`, in the plane's coordinates (a face crossing the plane cuts one segment).
pub fn patch_section(mesh: &Mesh, coords: &[f64], patch: i32, axis: usize, value: f64) -> Vec<[[f64; 2]; 2]> {
    assert_eq!(mesh.dim(), 3, "patch_section: a 3D mesh");
    let ax = section_axes(axis);
    let p = |v: u32| &coords[3 * v as usize..3 * v as usize + 3];
    let s = |v: u32| p(v)[axis] - value;
    let mut out = Vec::new();
    for f in mesh.patch_faces().filter(|f| f.patch == patch) {
        let v = f.vertices;
        let mut pts = Vec::new();
        for k in 0..v.len() {
            let (a, b) = (v[k], v[(k + 1) % v.len()]);
            if (s(a) < 0.0) != (s(b) < 0.0) {
                pts.push(crossing(p(a), p(b), s(a), s(b), ax));
            }
        }
        if pts.len() == 2 {
            out.push([pts[0], pts[1]]);
        }
    }
    out
}

/// A plane normal to `axis` at `target`, moved half-way to the next vertex coordinate of
/// `coords` (3 per vertex) when vertices lie on it (a structured grid's middle plane; at the
/// largest coordinate, half-way to the one before), so that no vertex lies on the plane.
pub fn plane_off_vertices(coords: &[f64], axis: usize, target: f64) -> f64 {
    let mut c: Vec<f64> = coords.iter().skip(axis).step_by(3).copied().collect();
    c.sort_by(f64::total_cmp);
    c.dedup();
    let eps = 1e-9 * (c[c.len() - 1] - c[0]).max(f64::MIN_POSITIVE);
    match c.iter().position(|&x| x > target - eps) {
        Some(k) if (c[k] - target).abs() <= eps => match (c.get(k + 1), k.checked_sub(1)) {
            (Some(next), _) => 0.5 * (c[k] + next),
            (None, Some(before)) => 0.5 * (c[before] + c[k]),
            (None, None) => target,
        },
        _ => target,
    }
}

/// A plane normal to `axis` through the middle of `coords`' extent along it, off the vertices
/// ([`plane_off_vertices`]).
pub fn middle_plane(coords: &[f64], axis: usize) -> f64 {
    let (lo, hi) =
        coords.iter().skip(axis).step_by(3).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    plane_off_vertices(coords, axis, 0.5 * (lo + hi))
}

/// A plane normal to `axis` through the centroid of `patch`'s vertices (a moved body or
/// surface), off the vertices ([`plane_off_vertices`]); through the middle of the mesh when the
/// patch has no vertex.
pub fn plane_through_patch(mesh: &Mesh, axis: usize, patch: i32) -> f64 {
    let v = mesh.patch_vertices(patch);
    if v.is_empty() {
        return middle_plane(mesh.coords(), axis);
    }
    let target = v.iter().map(|&v| mesh.point(v as usize)[axis]).sum::<f64>() / v.len() as f64;
    plane_off_vertices(mesh.coords(), axis, target)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::meshes3d::{structured_box, BoxCells, BOX_TOP};

    /// The sum of the polygon's signed area (shoelace).
    fn area(poly: &[[f64; 2]]) -> f64 {
        (0..poly.len())
            .map(|k| {
                let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum::<f64>()
            / 2.0
    }

    #[test]
    fn sections_of_a_box_tile_the_plane() {
        for cells in BoxCells::ALL {
            let m = Mesh::from_data(&structured_box(cells, [4, 4, 4], [0.0, 1.0, 0.0, 2.0, -1.0, 0.0])).unwrap();
            let y = middle_plane(m.coords(), 1);
            assert_eq!(y, 1.25, "{cells:?}: the middle y = 1 is a grid plane: half-way to 1.5");
            assert_eq!(plane_through_patch(&m, 1, BOX_TOP), 1.25);
            assert_eq!(plane_through_patch(&m, 2, BOX_TOP), -0.125, "{cells:?}: below the top");
            assert_eq!(plane_off_vertices(m.coords(), 0, 0.3), 0.3);
            let secs = cell_sections(&m, m.coords(), 1, y);
            let total: f64 = secs.iter().map(|s| area(&s.polygon).abs()).sum();
            assert!((total - 1.0).abs() < 1e-12, "{cells:?}: {total}");
            let top = patch_section(&m, m.coords(), BOX_TOP, 1, y);
            let len: f64 = top.iter().map(|s| (s[1][0] - s[0][0]).hypot(s[1][1] - s[0][1])).sum();
            assert!((len - 1.0).abs() < 1e-12, "{cells:?}: {len}");
            assert!(top.iter().all(|s| s[0][1] == 0.0 && s[1][1] == 0.0));
        }
    }
}
