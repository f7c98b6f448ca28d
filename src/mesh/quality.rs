//! Quality of a (deformed) mesh: signed measures, inverted cells, angles, measure ratios
//! (docs/DESIGN.md §7).

use super::Mesh;
use crate::geometry::CellGeometry;

/// Cell `c` of `mesh`'s topology at positions `coords`.
fn points(mesh: &Mesh, coords: &[f64], c: usize) -> CellGeometry {
    mesh.cell_geometry(coords, c)
}

/// Signed area (2D) or volume (3D) of every cell of `mesh`'s topology at positions `coords`.
pub fn signed_measures(mesh: &Mesh, coords: &[f64]) -> Vec<f64> {
    (0..mesh.num_cells()).map(|c| points(mesh, coords, c).signed_measure()).collect()
}

/// True when cell `c` at positions `coords` is inverted: a corner Jacobian or its signed measure
/// ≤ 0 (or NaN).
pub(crate) fn is_inverted(mesh: &Mesh, coords: &[f64], c: usize) -> bool {
    points(mesh, coords, c).is_inverted()
}

/// The cells of `mesh`'s topology inverted at positions `coords` (a corner Jacobian or the signed
/// measure ≤ 0),
/// ascending.
pub fn inverted_cells(mesh: &Mesh, coords: &[f64]) -> Vec<usize> {
    (0..mesh.num_cells()).filter(|&c| is_inverted(mesh, coords, c)).collect()
}

/// Summary of a deformed mesh against its reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quality {
    /// Inverted cells: cells with a non-positive corner Jacobian or a non-positive signed area
    /// (volume) (the solver's test). A cell can fail at one corner with a positive volume (a
    /// hexahedron folded at a corner), so this can exceed [`Quality::non_positive_measure`]; it
    /// is never below it.
    pub inverted: usize,
    /// Cells whose signed area (volume) is not positive: what VTK's cell area (volume) finds.
    pub non_positive_measure: usize,
    /// Smallest deformed/reference ratio of a cell's smallest corner Jacobian (negative when a
    /// corner inverted); for simplices the area (volume) ratio.
    pub min_corner_jacobian_ratio: f64,
    /// Smallest deformed/reference area (volume) ratio over all cells (negative when a cell
    /// inverted).
    pub min_area_ratio: f64,
    /// Largest deformed/reference area (volume) ratio.
    pub max_area_ratio: f64,
    /// Smallest angle between two edges at a corner of any cell, degrees.
    pub min_angle_deg: f64,
}

/// Quality of `mesh`'s topology at `deformed` positions, measures against `mesh` itself.
pub fn quality(mesh: &Mesh, deformed: &[f64]) -> Quality {
    quality_of_cells(mesh, deformed, 0..mesh.num_cells())
}

/// `quality` over the cells `cells` of `mesh` alone (a rank's owned cells); no cell gives the
/// neutral values (infinite ratios, 180°).
pub(crate) fn quality_of_cells(mesh: &Mesh, deformed: &[f64], cells: impl Iterator<Item = usize>) -> Quality {
    let mut q = Quality {
        inverted: 0,
        non_positive_measure: 0,
        min_corner_jacobian_ratio: f64::INFINITY,
        min_area_ratio: f64::INFINITY,
        max_area_ratio: f64::NEG_INFINITY,
        min_angle_deg: 180.0,
    };
    for c in cells {
        let (p0, p1) = (points(mesh, mesh.coords(), c), points(mesh, deformed, c));
        let (a0, a1) = (p0.signed_measure(), p1.signed_measure());
        let r = a1 / a0;
        let j1 = p1.min_corner_jacobian_with_measure(a1);
        // NaN counts as inverted, as in `CellPoints::is_inverted`.
        let positive = |x: f64| x.partial_cmp(&0.0) == Some(std::cmp::Ordering::Greater);
        q.inverted += usize::from(!positive(j1) || !positive(a1));
        q.non_positive_measure += usize::from(!positive(a1));
        q.min_corner_jacobian_ratio = q.min_corner_jacobian_ratio.min(j1 / p0.min_corner_jacobian_with_measure(a0));
        q.min_area_ratio = q.min_area_ratio.min(r);
        q.max_area_ratio = q.max_area_ratio.max(r);
        q.min_angle_deg = q.min_angle_deg.min(p1.min_angle_deg());
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::IndexBase;

    #[test]
    fn right_triangle_numbers() {
        let m = Mesh::triangles(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], &[[0u32, 1, 2]], IndexBase::Zero, &[], None)
            .unwrap();
        assert_eq!(signed_measures(&m, m.coords()), vec![0.5]);
        let q = quality(&m, m.coords());
        assert_eq!(q.inverted, 0);
        assert!((q.min_angle_deg - 45.0).abs() < 1e-12);
        let flipped = vec![0.0, 0.0, 1.0, 0.0, 0.0, -2.0];
        let q = quality(&m, &flipped);
        assert_eq!(q.inverted, 1);
        assert!((q.min_area_ratio + 2.0).abs() < 1e-12);
        // A simplex's two counts and two ratios agree.
        assert_eq!(q.non_positive_measure, 1);
        assert!((q.min_corner_jacobian_ratio + 2.0).abs() < 1e-12);
    }

    /// The unit cube as one hexahedron with its corner (1, 1, 1) pushed in to (0.3, 0.3, 0.3):
    /// that corner's Jacobian turns from −1 to +1.1 (its three edges' determinant, in the
    /// opposite sense), so the cell is inverted, while its volume stays positive, as VTK's
    /// cell volume finds it: the two measures say different things.
    #[test]
    fn hexahedron_inverted_at_one_corner_keeps_a_positive_volume() {
        use crate::geometry::CellType;
        use crate::mesh::MeshData;
        let mut d = MeshData::new(3);
        for p in [
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0., 0., 1.],
            [1., 0., 1.],
            [1., 1., 1.],
            [0., 1., 1.],
        ] {
            d.push_vertex(&p);
        }
        d.push_cell(CellType::Hexahedron, &[0, 1, 2, 3, 4, 5, 6, 7], 0);
        let m = Mesh::from_data(&d).unwrap();
        let mut x = m.coords().to_vec();
        x[18..21].copy_from_slice(&[0.3, 0.3, 0.3]);
        let q = quality(&m, &x);
        assert_eq!((q.inverted, q.non_positive_measure), (1, 0));
        assert!((q.min_corner_jacobian_ratio + 1.1).abs() < 1e-12, "{}", q.min_corner_jacobian_ratio);
        let v = signed_measures(&m, &x)[0];
        assert!(v > 0.4 && v < 0.9 && (q.min_area_ratio - v).abs() < 1e-15, "{v} {}", q.min_area_ratio);
    }
}
