//! Q1 tensor-product cells: bilinear quads (and, in 3D, trilinear hexahedra). Stiffness and
//! lumped mass by 2×2 Gauss quadrature, exact for a parallelogram's bilinear integrands.

use super::{cross, dot3, sub, twice_area2, CellType};

/// The reference corners of the bilinear quad on [−1, 1]², counter-clockwise.
const QUAD_REF: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// Shape function values and reference gradients of the four corners at (ξ, η).
fn quad_basis(xi: f64, eta: f64) -> ([f64; 4], [[f64; 2]; 4]) {
    let mut n = [0.0; 4];
    let mut g = [[0.0; 2]; 4];
    for (k, [a, b]) in QUAD_REF.iter().enumerate() {
        n[k] = 0.25 * (1.0 + a * xi) * (1.0 + b * eta);
        g[k] = [0.25 * a * (1.0 + b * eta), 0.25 * b * (1.0 + a * xi)];
    }
    (n, g)
}

/// The 2×2 Gauss points on [−1, 1]² (weights 1).
fn gauss2() -> [[f64; 2]; 4] {
    let g = 1.0 / 3f64.sqrt();
    [[-g, -g], [g, -g], [g, g], [-g, g]]
}

/// At a quadrature point: the physical gradients of the four shape functions and det J.
fn quad_point(p: &[[f64; 3]], xi: f64, eta: f64) -> ([f64; 4], [[f64; 2]; 4], f64) {
    let (n, g) = quad_basis(xi, eta);
    let mut j = [[0.0; 2]; 2];
    for k in 0..4 {
        for a in 0..2 {
            for b in 0..2 {
                j[a][b] += p[k][a] * g[k][b];
            }
        }
    }
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    // ∇φ = J⁻ᵀ ∇_ref φ.
    let inv = [[j[1][1] / det, -j[1][0] / det], [-j[0][1] / det, j[0][0] / det]];
    let grad = g.map(|r| [inv[0][0] * r[0] + inv[0][1] * r[1], inv[1][0] * r[0] + inv[1][1] * r[1]]);
    (n, grad, det)
}

/// Signed area (shoelace; exact for a bilinear quad).
pub(super) fn quad_area(p: &[[f64; 3]]) -> f64 {
    0.5 * (twice_area2(&p[0], &p[1], &p[2]) + twice_area2(&p[0], &p[2], &p[3]))
}

/// K_ij = ∫∇φ_i·∇φ_j for the quad's couplings (4 sides, then the diagonals 0–2 and 1–3).
pub(super) fn quad_stiffness(p: &[[f64; 3]], k: &mut [f64]) {
    let pairs = CellType::Quad.couplings();
    k[..pairs.len()].iter_mut().for_each(|k| *k = 0.0);
    for [xi, eta] in gauss2() {
        let (_, g, det) = quad_point(p, xi, eta);
        for (m, &[i, j]) in pairs.iter().enumerate() {
            let (a, b) = (g[i as usize], g[j as usize]);
            k[m] += (a[0] * b[0] + a[1] * b[1]) * det;
        }
    }
}

/// ∫φ_i at each corner.
pub(super) fn quad_lumped_mass(p: &[[f64; 3]], m: &mut [f64]) {
    m[..4].iter_mut().for_each(|m| *m = 0.0);
    for [xi, eta] in gauss2() {
        let (n, _, det) = quad_point(p, xi, eta);
        for k in 0..4 {
            m[k] += n[k] * det;
        }
    }
}

/// The reference corners of the trilinear hexahedron on [−1, 1]³, in VTK's order.
#[cfg(test)]
pub(super) const HEX_REF: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// The trilinear shape functions at the 2×2×2 Gauss points: per point, each corner's value
/// and reference gradient, worked out once (they do not depend on the cell).
#[cfg(test)]
struct HexGauss {
    value: [[f64; 8]; 8],
    gradient: [[[f64; 3]; 8]; 8],
}

/// The shape functions at the Gauss points (`HexGauss`).
#[cfg(test)]
fn hex_gauss() -> &'static HexGauss {
    static TABLE: std::sync::OnceLock<HexGauss> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let g = 1.0 / 3f64.sqrt();
        let mut t = HexGauss { value: [[0.0; 8]; 8], gradient: [[[0.0; 3]; 8]; 8] };
        for q in 0..8 {
            let xi = [if q & 1 == 0 { -g } else { g }, if q & 2 == 0 { -g } else { g }, if q & 4 == 0 { -g } else { g }];
            for (k, r) in HEX_REF.iter().enumerate() {
                let f = [1.0 + r[0] * xi[0], 1.0 + r[1] * xi[1], 1.0 + r[2] * xi[2]];
                t.value[q][k] = 0.125 * f[0] * f[1] * f[2];
                t.gradient[q][k] = [0.125 * r[0] * f[1] * f[2], 0.125 * r[1] * f[0] * f[2], 0.125 * r[2] * f[0] * f[1]];
            }
        }
        t
    })
}

/// At Gauss point `q` of the cell `p` with reference gradients `g`: the cofactor columns
/// c_b (det·J⁻ᵀ = [c0 c1 c2]) and det J.
#[cfg(test)]
#[inline(always)]
fn hex_cofactors(p: &[[f64; 3]], g: &[[f64; 3]; 8]) -> ([[f64; 3]; 3], f64) {
    let mut j = [[0.0; 3]; 3];
    for (pk, gk) in p[..8].iter().zip(g) {
        for a in 0..3 {
            for b in 0..3 {
                j[a][b] += pk[a] * gk[b];
            }
        }
    }
    let col = |b: usize| [j[0][b], j[1][b], j[2][b]];
    let (c0, c1, c2) = (cross(&col(1), &col(2)), cross(&col(2), &col(0)), cross(&col(0), &col(1)));
    let det = dot3(&col(0), &c0);
    ([c0, c1, c2], det)
}

/// K_ij = ∫∇φ_i·∇φ_j of the trilinear hexahedron for its 28 corner pairs, 2×2×2 Gauss.
#[cfg(test)]
pub(super) fn hex_stiffness(p: &[[f64; 3]], k: &mut [f64]) {
    hex_stiffness_and_mass_by_points(p, k, &mut [0.0; 8]);
}

/// `hex_stiffness` and `hex_lumped_mass` point by point, from one evaluation of each Gauss point:
/// the formulation the modal kernel (`hex_kernel`) is tested against.
/// With ∇φ = J⁻ᵀ ∇_ref φ = C ∇_ref φ / det (C the cofactors), each point adds
/// (C∇_ref φ_i)·(C∇_ref φ_j) / det to K_ij (weights 1) and φ_i det to the mass.
#[cfg(test)]
pub(super) fn hex_stiffness_and_mass_by_points(p: &[[f64; 3]], k: &mut [f64], m: &mut [f64]) {
    let t = hex_gauss();
    let mut kk = [0.0; 28];
    let mut mm = [0.0; 8];
    for q in 0..8 {
        let g = &t.gradient[q];
        let ([c0, c1, c2], det) = hex_cofactors(p, g);
        let w = 1.0 / det;
        let mut s = [[0.0; 3]; 8];
        for (sk, r) in s.iter_mut().zip(g) {
            *sk = [0, 1, 2].map(|a| c0[a] * r[0] + c1[a] * r[1] + c2[a] * r[2]);
        }
        // The pairs in `CellType::Hexahedron.couplings()` order: (0,1), (0,2), …, (6,7).
        let mut at = 0;
        for i in 0..8 {
            for j in i + 1..8 {
                kk[at] += dot3(&s[i], &s[j]) * w;
                at += 1;
            }
        }
        for (mc, n) in mm.iter_mut().zip(&t.value[q]) {
            *mc += n * det;
        }
    }
    k[..28].copy_from_slice(&kk);
    m[..8].copy_from_slice(&mm);
}

/// ∫φ_i at each corner of the trilinear hexahedron, 2×2×2 Gauss.
#[cfg(test)]
pub(super) fn hex_lumped_mass(p: &[[f64; 3]], m: &mut [f64]) {
    let t = hex_gauss();
    let mut mm = [0.0; 8];
    for q in 0..8 {
        let (_, det) = hex_cofactors(p, &t.gradient[q]);
        for (mc, n) in mm.iter_mut().zip(&t.value[q]) {
            *mc += n * det;
        }
    }
    m[..8].copy_from_slice(&mm);
}

/// The corners adjacent to each corner, in the order that makes the corner's edge frame
/// positively oriented (2D: next, previous; 3D: three edges).
pub(super) fn corner_frames(ty: CellType) -> &'static [&'static [u8]] {
    match ty {
        CellType::Quad => &[&[1, 3], &[2, 0], &[3, 1], &[0, 2]],
        CellType::Hexahedron => {
            &[&[1, 3, 4], &[2, 0, 5], &[3, 1, 6], &[0, 2, 7], &[7, 5, 0], &[4, 6, 1], &[5, 7, 2], &[6, 4, 3]]
        }
        // VTK's wedge: triangle 0-1-2 has its normal away from 3-4-5.
        CellType::Wedge => &[&[2, 1, 3], &[0, 2, 4], &[1, 0, 5], &[4, 5, 0], &[5, 3, 1], &[3, 4, 2]],
        CellType::Pyramid => &[&[1, 3, 4], &[2, 0, 4], &[3, 1, 4], &[0, 2, 4]],
        CellType::Triangle => &[&[1, 2], &[2, 0], &[0, 1]],
        CellType::Tetra => &[&[1, 2, 3], &[2, 0, 3], &[0, 1, 3], &[1, 0, 2]],
        CellType::Polygon | CellType::Polyhedron => &[],
    }
}

/// The Jacobian determinant of the edge frame at every corner (the apex of a pyramid has none
/// of its own: four edges meet there, and the base corners' frames cover it).
fn corner_jacobians(ty: CellType, p: &[[f64; 3]]) -> impl Iterator<Item = f64> + '_ {
    corner_frames(ty).iter().enumerate().map(move |(c, f)| {
        let e = |k: usize| sub(&p[f[k] as usize], &p[c]);
        if f.len() == 2 {
            let (a, b) = (e(0), e(1));
            a[0] * b[1] - a[1] * b[0]
        } else {
            dot3(&cross(&e(0), &e(1)), &e(2))
        }
    })
}

/// The smallest corner Jacobian determinant: ≤ 0 means the cell is inverted or folded.
pub(super) fn min_corner_jacobian(ty: CellType, p: &[[f64; 3]]) -> f64 {
    corner_jacobians(ty, p).fold(f64::INFINITY, f64::min)
}

/// The signed volume of a 3D cell by the divergence theorem over its outward faces, each a fan
/// of triangles from its first corner (exact for planar faces).
pub(super) fn volume_by_faces(ty: CellType, p: &[[f64; 3]]) -> f64 {
    let mut sum = 0.0;
    for f in ty.faces() {
        for k in 1..f.len() - 1 {
            let (a, b, e) = (&p[f[0] as usize], &p[f[k] as usize], &p[f[k + 1] as usize]);
            sum += dot3(a, &cross(b, e));
        }
    }
    sum / 6.0
}

/// The smallest interior dihedral angle of a 3D cell, degrees: at each edge, the angle between
/// its two faces, each represented by the direction from the edge into the face (towards the
/// face's corner next to the edge), orthogonal to the edge. A sliver tetrahedron, whose edge
/// angles can all be fine, has a dihedral angle near 0 (or 180°).
///
/// The angle at an edge is atan2(|u × v|, u · v); the smallest is the one of largest cosine
/// (u · v) / √(|u × v|² + (u · v)²), so the edges are compared by that and only the chosen
/// one's atan2 is evaluated. An edge whose directions vanish (a degenerate cell) has the angle
/// atan2(0, ±0), 0 or 180°, and is compared as such.
pub(super) fn min_dihedral_deg(ty: CellType, p: &[[f64; 3]]) -> f64 {
    // The chosen edge's (|u × v|², u · v) and its cosine; NaN angles are passed over, as
    // `f64::min` passes them over.
    let mut best: Option<(f64, f64, f64)> = None;
    for (&[a, b], off) in ty.edges().iter().zip(edge_face_corners(ty)) {
        let (pa, pb) = (&p[a as usize], &p[b as usize]);
        let e = sub(pb, pa);
        let ee = dot3(&e, &e);
        let dirs = off.map(|o| {
            let w = sub(&p[o as usize], pa);
            let t = dot3(&w, &e) / ee;
            [w[0] - t * e[0], w[1] - t * e[1], w[2] - t * e[2]]
        });
        let (u, v) = (&dirs[0], &dirs[1]);
        let s = cross(u, v);
        let (ss, cos) = (dot3(&s, &s), dot3(u, v));
        if ss.is_nan() || cos.is_nan() {
            continue;
        }
        let r = (ss + cos * cos).sqrt();
        let c = if r > 0.0 { cos / r } else if cos.is_sign_negative() { -1.0 } else { 1.0 };
        if best.is_none_or(|(_, _, bc)| c > bc) {
            best = Some((ss, cos, c));
        }
    }
    best.map_or(180.0, |(ss, cos, _)| ss.sqrt().atan2(cos).to_degrees().min(180.0))
}

/// Per edge of `ty` (in `edges` order), the corners of its two faces after it: the faces'
/// corners off the edge, beside it, which `min_dihedral_deg` measures the faces by. Worked out
/// once per cell type (the search over the faces cost more than the angles).
pub(super) fn edge_face_corners(ty: CellType) -> &'static [[u8; 2]] {
    static TABLES: std::sync::OnceLock<Vec<Vec<[u8; 2]>>> = std::sync::OnceLock::new();
    let tables = TABLES.get_or_init(|| CellType::ALL.iter().map(|&t| search_edge_face_corners(t)).collect());
    let at = CellType::ALL.iter().position(|&t| t == ty).unwrap_or(0);
    &tables[at]
}

/// `edge_face_corners` by a search of the faces: for each edge, the corner after it in the
/// first two faces that hold it (the edge's first corner where a face is missing).
fn search_edge_face_corners(ty: CellType) -> Vec<[u8; 2]> {
    let faces = if ty.dim() == 3 { ty.faces() } else { &[] };
    ty.edges()
        .iter()
        .map(|&[a, b]| {
            let mut off = [a; 2];
            let mut found = 0;
            for f in faces {
                let n = f.len();
                for k in 0..n {
                    let (u, v) = (f[k], f[(k + 1) % n]);
                    if ((u, v) == (a, b) || (u, v) == (b, a)) && found < 2 {
                        off[found] = f[(k + 2) % n];
                        found += 1;
                    }
                }
            }
            off
        })
        .collect()
}

/// The smallest angle between the two (2D) or three (3D) edges of any corner's frame, degrees.
pub(super) fn min_corner_angle_deg(ty: CellType, p: &[[f64; 3]]) -> f64 {
    let mut min = 180.0f64;
    for (c, f) in corner_frames(ty).iter().enumerate() {
        if f.len() == 2 {
            let (a, b) = (sub(&p[f[0] as usize], &p[c]), sub(&p[f[1] as usize], &p[c]));
            let cross = a[0] * b[1] - a[1] * b[0];
            if cross <= 0.0 {
                return 0.0;
            }
            min = min.min(cross.atan2(a[0] * b[0] + a[1] * b[1]).to_degrees());
        } else {
            for k in 0..f.len() {
                let (a, b) = (sub(&p[f[k] as usize], &p[c]), sub(&p[f[(k + 1) % f.len()] as usize], &p[c]));
                let s = cross(&a, &b);
                min = min.min(dot3(&s, &s).sqrt().atan2(dot3(&a, &b)).to_degrees());
            }
        }
    }
    min
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a parallelogram the Gauss rule is exact: the unit square's Q1 stiffness has the known
    /// entries (sides −1/6, diagonals −1/3), the mass a quarter of the area at each corner.
    #[test]
    fn unit_square_entries() {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        let mut k = [0.0; 6];
        quad_stiffness(&p, &mut k);
        for (m, want) in [-1.0 / 6.0, -1.0 / 6.0, -1.0 / 6.0, -1.0 / 6.0, -1.0 / 3.0, -1.0 / 3.0].iter().enumerate() {
            assert!((k[m] - want).abs() < 1e-15, "{m}: {}", k[m]);
        }
        let mut m = [0.0; 4];
        quad_lumped_mass(&p, &mut m);
        assert!(m.iter().all(|&m| (m - 0.25).abs() < 1e-15));
        assert_eq!(quad_area(&p), 1.0);
        assert_eq!(min_corner_jacobian(CellType::Quad, &p), 1.0);
        assert!((min_corner_angle_deg(CellType::Quad, &p) - 90.0).abs() < 1e-12);
        // A dart (non-convex) quad has a negative corner.
        let dart = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.5, 0.5, 0.0], [0.0, 2.0, 0.0]];
        assert!(min_corner_jacobian(CellType::Quad, &dart) < 0.0);
        // Unit hexahedron: every corner frame has determinant 1.
        let mut h = [[0.0; 3]; 8];
        for (k, c) in
            [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]].iter().enumerate()
        {
            h[k] = c.map(|x| x as f64);
        }
        assert_eq!(min_corner_jacobian(CellType::Hexahedron, &h), 1.0);
        assert_eq!(volume_by_faces(CellType::Hexahedron, &h), 1.0);
        assert!((min_dihedral_deg(CellType::Hexahedron, &h) - 90.0).abs() < 1e-12);
        // The unit right tetrahedron: 90° at its three right edges, arccos(1/√3) = 54.7356° where
        // the slanted face meets the others; a sliver (four nearly coplanar corners) near 0.
        let t = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let want = (1.0 / 3f64.sqrt()).acos().to_degrees();
        assert!((min_dihedral_deg(CellType::Tetra, &t) - want).abs() < 1e-12);
        let sliver = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.01], [0.0, 1.0, 0.0]];
        assert!(min_dihedral_deg(CellType::Tetra, &sliver) < 2.0);
        // Every edge's atan2, the smallest taken: the same value on distorted cells.
        let by_atan2 = |ty: CellType, p: &[[f64; 3]]| {
            ty.edges().iter().zip(edge_face_corners(ty)).fold(180.0f64, |min, (&[a, b], off)| {
                let (pa, pb) = (&p[a as usize], &p[b as usize]);
                let e = sub(pb, pa);
                let [u, v] = off.map(|o| {
                    let w = sub(&p[o as usize], pa);
                    let t = dot3(&w, &e) / dot3(&e, &e);
                    [w[0] - t * e[0], w[1] - t * e[1], w[2] - t * e[2]]
                });
                let s = cross(&u, &v);
                min.min(dot3(&s, &s).sqrt().atan2(dot3(&u, &v)).to_degrees())
            })
        };
        let mut seed = 12345u64;
        let mut jitter = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..200 {
            let hex = h.map(|c| c.map(|x| x + 0.4 * jitter()));
            assert_eq!(min_dihedral_deg(CellType::Hexahedron, &hex), by_atan2(CellType::Hexahedron, &hex));
            let tet: [[f64; 3]; 4] = std::array::from_fn(|k| t[k].map(|x| x + 0.4 * jitter()));
            assert_eq!(min_dihedral_deg(CellType::Tetra, &tet), by_atan2(CellType::Tetra, &tet));
        }
        assert!(min_corner_angle_deg(CellType::Tetra, &sliver) > 40.0);
        // The unit cube's trilinear element: mass 1/8 per corner, rows of K summing to zero,
        // edge couplings 0, face diagonals −1/12, body diagonals −1/12 (the classic values).
        let mut m = [0.0; 8];
        hex_lumped_mass(&h, &mut m);
        assert!(m.iter().all(|&m| (m - 0.125).abs() < 1e-15));
        let mut k = [0.0; 28];
        hex_stiffness(&h, &mut k);
        for (idx, &[i, j]) in CellType::Hexahedron.couplings().iter().enumerate() {
            let d: f64 = (0..3).map(|a| (h[i as usize][a] - h[j as usize][a]).abs()).sum();
            let want = if d == 1.0 { 0.0 } else { -1.0 / 12.0 };
            assert!((k[idx] - want).abs() < 1e-15, "pair {i}-{j}: {}", k[idx]);
        }
    }
}
