//! P1 simplices: triangles (and, in 3D, tetrahedra). The triangle's formulas are the cotangent
//! form of ∫∇φ_i·∇φ_j, evaluated in a fixed order so results do not depend on anything else.

use super::{cross, dot3, sub, twice_area2};
use glam::DVec2;

fn p2(p: &[f64; 3]) -> DVec2 {
    DVec2::new(p[0], p[1])
}

/// Signed area of triangle p0 p1 p2 (positive counter-clockwise).
#[inline]
pub(super) fn triangle_area(p: &[[f64; 3]]) -> f64 {
    0.5 * twice_area2(&p[0], &p[1], &p[2])
}

/// Signed volume of tetrahedron p0 p1 p2 p3 (positive when p3 lies on the side where
/// (p1 − p0) × (p2 − p0) points).
pub(super) fn tet_volume(p: &[[f64; 3]]) -> f64 {
    dot3(&cross(&sub(&p[1], &p[0]), &sub(&p[2], &p[0])), &sub(&p[3], &p[0])) / 6.0
}

/// The gradients of a tetrahedron's four barycentric functions (independent of the corner
/// order's orientation) and its signed volume.
pub(super) fn tet_gradients(p: &[[f64; 3]]) -> ([[f64; 3]; 4], f64) {
    let (e1, e2, e3) = (sub(&p[1], &p[0]), sub(&p[2], &p[0]), sub(&p[3], &p[0]));
    let (c23, c31, c12) = (cross(&e2, &e3), cross(&e3, &e1), cross(&e1, &e2));
    let det = dot3(&e1, &c23);
    let g1 = c23.map(|x| x / det);
    let g2 = c31.map(|x| x / det);
    let g3 = c12.map(|x| x / det);
    let g0 = [0, 1, 2].map(|i| -(g1[i] + g2[i] + g3[i]));
    ([g0, g1, g2, g3], det / 6.0)
}

/// K_ij = V ∇λ_i·∇λ_j for the six edges of a tetrahedron, in `CellType::Tetra.edges()` order:
/// with ∇λ_i = c_i / det (c_1, c_2, c_3 the cross products of the other edges, c_0 minus their
/// sum) and V = det / 6, K_ij = c_i·c_j / (6 det), one division per cell.
pub(super) fn tet_stiffness(p: &[[f64; 3]], k: &mut [f64]) {
    let (e1, e2, e3) = (sub(&p[1], &p[0]), sub(&p[2], &p[0]), sub(&p[3], &p[0]));
    let (c23, c31, c12) = (cross(&e2, &e3), cross(&e3, &e1), cross(&e1, &e2));
    let w = 1.0 / (6.0 * dot3(&e1, &c23));
    let c0 = [0, 1, 2].map(|i| -(c23[i] + c31[i] + c12[i]));
    let c = [c0, c23, c31, c12];
    for (m, &[i, j]) in super::CellType::Tetra.couplings().iter().enumerate() {
        k[m] = dot3(&c[i as usize], &c[j as usize]) * w;
    }
}

/// A quarter of the volume at each corner.
pub(super) fn tet_lumped_mass(p: &[[f64; 3]], m: &mut [f64]) {
    let q = tet_volume(p) / 4.0;
    m[..4].iter_mut().for_each(|m| *m = q);
}

/// K for the edges (0,1), (1,2), (2,0): −½ cot of the opposite angle, as
/// −(e_oi · e_oj) / (2 · 2A).
#[inline]
pub(super) fn triangle_stiffness(p: &[[f64; 3]], k: &mut [f64]) {
    let p = [p2(&p[0]), p2(&p[1]), p2(&p[2])];
    let twice_area = (p[1] - p[0]).perp_dot(p[2] - p[0]);
    for (m, k) in k[..3].iter_mut().enumerate() {
        let (i, j, o) = (m, (m + 1) % 3, (m + 2) % 3);
        *k = -(0.5 * (p[i] - p[o]).dot(p[j] - p[o]) / twice_area);
    }
}

/// A third of the area at each corner.
#[inline]
pub(super) fn triangle_lumped_mass(p: &[[f64; 3]], m: &mut [f64]) {
    let third = twice_area2(&p[0], &p[1], &p[2]) / 6.0;
    m[..3].iter_mut().for_each(|m| *m = third);
}

/// Smallest interior angle in degrees (0 for an inverted or flat cell).
pub(super) fn triangle_min_angle_deg(p: &[[f64; 3]]) -> f64 {
    let [a, b, c] = [p2(&p[0]), p2(&p[1]), p2(&p[2])];
    if (b - a).perp_dot(c - a) <= 0.0 {
        return 0.0;
    }
    let ang = |p: DVec2, q: DVec2, r: DVec2| (q - p).angle_to(r - p).abs();
    ang(a, b, c).min(ang(b, c, a)).min(ang(c, a, b)).to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn right_triangle() {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert_eq!(triangle_area(&p), 0.5);
        let mut k = [0.0; 3];
        triangle_stiffness(&p, &mut k);
        // Edge (0,1) faces the 45° corner 2: −½ cot 45° = −½; edge (1,2) faces the right angle.
        assert_eq!(k, [-0.5, 0.0, -0.5]);
        assert!((triangle_min_angle_deg(&p) - 45.0).abs() < 1e-12);
        let t = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert!((tet_volume(&t) - 1.0 / 6.0).abs() < 1e-16);
        // The unit tetrahedron: the edges at the right-angled corner 0 carry −1/6, the others 0.
        let mut k = [0.0; 6];
        tet_stiffness(&t, &mut k);
        let want = [-1.0 / 6.0, 0.0, -1.0 / 6.0, -1.0 / 6.0, 0.0, 0.0];
        for m in 0..6 {
            assert!((k[m] - want[m]).abs() < 1e-16, "{m}: {}", k[m]);
        }
    }
}
