//! Quality of a (deformed) mesh: signed areas, inverted cells, angles, area ratios (docs/DESIGN.md §7).

use super::validate::twice_signed_area;
use super::Mesh;
use glam::DVec2;

/// Signed area of every cell of `mesh`'s topology at positions `coords`.
pub fn signed_areas(mesh: &Mesh, coords: &[DVec2]) -> Vec<f64> {
    mesh.cells()
        .iter()
        .map(|t| 0.5 * twice_signed_area(coords[t[0] as usize], coords[t[1] as usize], coords[t[2] as usize]))
        .collect()
}

/// The cells of `mesh`'s topology with non-positive signed area at positions `coords`, ascending.
pub fn inverted_cells(mesh: &Mesh, coords: &[DVec2]) -> Vec<usize> {
    signed_areas(mesh, coords).iter().enumerate().filter(|(_, &a)| a <= 0.0 || a.is_nan()).map(|(c, _)| c).collect()
}

/// Smallest interior angle of triangle (a, b, c) in degrees (0 for an inverted or flat cell).
pub fn min_angle_deg(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    if twice_signed_area(a, b, c) <= 0.0 {
        return 0.0;
    }
    let ang = |p: DVec2, q: DVec2, r: DVec2| (q - p).angle_to(r - p).abs();
    ang(a, b, c).min(ang(b, c, a)).min(ang(c, a, b)).to_degrees()
}

/// Summary of a deformed mesh against its reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quality {
    /// Cells of non-positive signed area.
    pub inverted: usize,
    /// Smallest deformed/reference area ratio over all cells (negative when a cell inverted).
    pub min_area_ratio: f64,
    /// Largest deformed/reference area ratio.
    pub max_area_ratio: f64,
    /// Smallest angle of any cell, degrees.
    pub min_angle_deg: f64,
}

/// Quality of `mesh`'s topology at `deformed` positions, areas measured against `mesh` itself.
pub fn quality(mesh: &Mesh, deformed: &[DVec2]) -> Quality {
    let a0 = signed_areas(mesh, mesh.coords());
    let a1 = signed_areas(mesh, deformed);
    let mut q =
        Quality { inverted: 0, min_area_ratio: f64::INFINITY, max_area_ratio: f64::NEG_INFINITY, min_angle_deg: 180.0 };
    for (c, t) in mesh.cells().iter().enumerate() {
        let r = a1[c] / a0[c];
        q.inverted += usize::from(a1[c] <= 0.0);
        q.min_area_ratio = q.min_area_ratio.min(r);
        q.max_area_ratio = q.max_area_ratio.max(r);
        let [p, s, u] = t.map(|v| deformed[v as usize]);
        q.min_angle_deg = q.min_angle_deg.min(min_angle_deg(p, s, u));
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::IndexBase;

    #[test]
    fn right_triangle_numbers() {
        let m = Mesh::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], &[[0u32, 1, 2]], IndexBase::Zero, &[], None).unwrap();
        assert_eq!(signed_areas(&m, m.coords()), vec![0.5]);
        let q = quality(&m, m.coords());
        assert_eq!(q.inverted, 0);
        assert!((q.min_angle_deg - 45.0).abs() < 1e-12);
        let flipped = vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(0.0, -2.0)];
        let q = quality(&m, &flipped);
        assert_eq!(q.inverted, 1);
        assert!((q.min_area_ratio + 2.0).abs() < 1e-12);
    }
}
