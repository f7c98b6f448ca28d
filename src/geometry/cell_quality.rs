//! The quality measures of the hexahedron (signed volume, corner Jacobians, smallest dihedral
//! angle) and the tetrahedron (smallest dihedral angle) with their faces, corners and edges as
//! constants: the general functions of `tensor` take the cell type's tables at run time (the
//! dihedral angle's by a lookup per cell), so their loops are neither unrolled nor vectorised. Each value here is formed by the same operations in the
//! same order as `tensor`'s (each lane of a loop over the edges or corners is one of their
//! iterations, and the sums and minima run in their order), so the results are bitwise theirs
//! (unit test `the_same_bits_as_the_general_functions`). Inlined, so a pass run inside
//! `Lanes::run` runs them on those lanes.

use super::{cross, dot3, sub};

/// The volume's triangles: each face of `CellType::Hexahedron.faces()` as the fan from its first
/// corner, (f0, f1, f2) and (f0, f2, f3), in the faces' order.
const TRIANGLES: [[usize; 3]; 12] = [
    [0, 3, 2],
    [0, 2, 1],
    [4, 5, 6],
    [4, 6, 7],
    [0, 1, 5],
    [0, 5, 4],
    [1, 2, 6],
    [1, 6, 5],
    [2, 3, 7],
    [2, 7, 6],
    [3, 0, 4],
    [3, 4, 7],
];

/// Each corner and its edge frame (`tensor::corner_frames`' hexahedron): corner, then the three
/// corners its edges go to, positively oriented.
const FRAMES: [[usize; 4]; 8] = [
    [0, 1, 3, 4],
    [1, 2, 0, 5],
    [2, 3, 1, 6],
    [3, 0, 2, 7],
    [4, 7, 5, 0],
    [5, 4, 6, 1],
    [6, 5, 7, 2],
    [7, 6, 4, 3],
];

/// Each edge of `CellType::Hexahedron.edges()` (a, b) with the corners its two faces are
/// measured by (`tensor::edge_face_corners`): a, b, then those two.
const EDGES: [[usize; 4]; 12] = [
    [0, 1, 3, 5],
    [1, 2, 0, 6],
    [2, 3, 1, 7],
    [3, 0, 2, 4],
    [4, 5, 6, 0],
    [5, 6, 7, 1],
    [6, 7, 4, 2],
    [7, 4, 5, 3],
    [0, 4, 1, 7],
    [1, 5, 4, 2],
    [2, 6, 5, 3],
    [3, 7, 6, 0],
];

/// Each edge of `CellType::Tetra.edges()` with the corners its two faces are measured by, as
/// `EDGES`.
const TET_EDGES: [[usize; 4]; 6] = [[0, 1, 3, 2], [1, 2, 3, 0], [2, 0, 3, 1], [0, 3, 1, 2], [1, 3, 0, 2], [2, 3, 1, 0]];

/// The signed volume by the divergence theorem over the faces (`tensor::volume_by_faces`).
#[inline(always)]
pub(super) fn volume(p: &[[f64; 3]]) -> f64 {
    let p = &p[..8];
    let mut t = [0.0f64; 12];
    for (ti, &[a, b, e]) in t.iter_mut().zip(&TRIANGLES) {
        *ti = dot3(&p[a], &cross(&p[b], &p[e]));
    }
    let mut sum = 0.0;
    for x in t {
        sum += x;
    }
    sum / 6.0
}

/// The smallest corner Jacobian determinant (`tensor::min_corner_jacobian`).
#[inline(always)]
pub(super) fn min_corner_jacobian(p: &[[f64; 3]]) -> f64 {
    let p = &p[..8];
    let mut j = [0.0f64; 8];
    for (jc, &[c, f0, f1, f2]) in j.iter_mut().zip(&FRAMES) {
        let e = |k: usize| sub(&p[k], &p[c]);
        *jc = dot3(&cross(&e(f0), &e(f1)), &e(f2));
    }
    j.into_iter().fold(f64::INFINITY, f64::min)
}

/// The hexahedron's smallest interior dihedral angle, degrees (`tensor::min_dihedral_deg`).
#[inline(always)]
pub(super) fn min_dihedral_deg(p: &[[f64; 3]]) -> f64 {
    min_dihedral_over(&p[..8], &EDGES)
}

/// The tetrahedron's smallest interior dihedral angle, degrees (`tensor::min_dihedral_deg`).
#[inline(always)]
pub(super) fn tet_min_dihedral_deg(p: &[[f64; 3]]) -> f64 {
    min_dihedral_over(&p[..4], &TET_EDGES)
}

/// The smallest dihedral angle over the edges `edges` (each edge's corners, then the corners its
/// faces are measured by), degrees, as `tensor::min_dihedral_deg` (whose comment gives the
/// measure) forms it: every edge's (|u × v|², u · v) and cosine side by side, then the edges
/// compared in their order.
#[inline(always)]
fn min_dihedral_over<const E: usize>(p: &[[f64; 3]], edges: &[[usize; 4]; E]) -> f64 {
    let (mut ss, mut cos, mut c) = ([0.0f64; E], [0.0f64; E], [0.0f64; E]);
    for (i, &[a, b, o0, o1]) in edges.iter().enumerate() {
        let (pa, pb) = (&p[a], &p[b]);
        let e = sub(pb, pa);
        let ee = dot3(&e, &e);
        let dir = |o: usize| {
            let w = sub(&p[o], pa);
            let t = dot3(&w, &e) / ee;
            [w[0] - t * e[0], w[1] - t * e[1], w[2] - t * e[2]]
        };
        let (u, v) = (dir(o0), dir(o1));
        let s = cross(&u, &v);
        (ss[i], cos[i]) = (dot3(&s, &s), dot3(&u, &v));
        let r = (ss[i] + cos[i] * cos[i]).sqrt();
        c[i] = if r > 0.0 {
            cos[i] / r
        } else if cos[i].is_sign_negative() {
            -1.0
        } else {
            1.0
        };
    }
    let mut best: Option<usize> = None;
    for i in 0..E {
        if ss[i].is_nan() || cos[i].is_nan() {
            continue;
        }
        if best.is_none_or(|b| c[i] > c[b]) {
            best = Some(i);
        }
    }
    best.map_or(180.0, |b| ss[b].sqrt().atan2(cos[b]).to_degrees().min(180.0))
}

#[cfg(test)]
mod tests {
    use super::super::tensor;
    use super::super::{CellType, Lanes};

    /// The constant tables are the cell type's.
    #[test]
    fn the_tables_are_the_cell_types() {
        let hex = CellType::Hexahedron;
        let fans: Vec<[usize; 3]> = hex
            .faces()
            .iter()
            .flat_map(|f| (1..f.len() - 1).map(move |k| [f[0], f[k], f[k + 1]].map(usize::from)))
            .collect();
        assert_eq!(fans, super::TRIANGLES);
        for (c, f) in tensor::corner_frames(hex).iter().enumerate() {
            assert_eq!(super::FRAMES[c], [c, f[0].into(), f[1].into(), f[2].into()], "corner {c}");
        }
        for (ty, table) in [(hex, &super::EDGES[..]), (CellType::Tetra, &super::TET_EDGES[..])] {
            let offs = tensor::edge_face_corners(ty);
            assert_eq!(table.len(), ty.edges().len(), "{ty}");
            for (k, e) in ty.edges().iter().enumerate() {
                let want = [e[0], e[1], offs[k][0], offs[k][1]].map(usize::from);
                assert_eq!(table[k], want, "{ty} edge {k}");
            }
        }
    }

    /// Distorted, inverted, flat and collapsed hexahedra far from the origin, and cells with NaN
    /// corners, and tetrahedra of their corners: every measure bitwise the general function's, compiled for the baseline and
    /// (where the processor has it, inside `Lanes::run`) for AVX2.
    #[test]
    fn the_same_bits_as_the_general_functions() {
        let cube = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.], [0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]];
        let mut seed = 1234567u64;
        let mut jitter = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let hex = CellType::Hexahedron;
        let (mut inverted, mut degenerate) = (0, 0);
        for cell in 0..4000 {
            let size = [0.3, 1.0, 2.5][cell % 3];
            let shift = [3.0, -7.0, 11.0];
            let mut p: [[f64; 3]; 8] = cube.map(|c| [0, 1, 2].map(|a| 1e2 * (c[a] + size * jitter()) + shift[a]));
            match cell % 50 {
                // Two corners on one point (a collapsed edge), a flat cell, a NaN corner.
                1 => p[1] = p[0],
                2 => p.iter_mut().for_each(|x| x[2] = shift[2]),
                3 => p[6][1] = f64::NAN,
                _ => {}
            }
            let want = [
                tensor::volume_by_faces(hex, &p),
                tensor::min_corner_jacobian(hex, &p),
                tensor::min_dihedral_deg(hex, &p),
            ];
            inverted += usize::from(want[1].partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater));
            degenerate += usize::from(want[2] == 0.0 || want[2] == 180.0);
            for lanes in [Lanes::Baseline, Lanes::detect()] {
                let got = lanes.run(|| [super::volume(&p), super::min_corner_jacobian(&p), super::min_dihedral_deg(&p)]);
                for (g, w) in got.iter().zip(&want) {
                    assert_eq!(g.to_bits(), w.to_bits(), "cell {cell} {lanes:?}: {got:?} against {want:?}");
                }
                // The tetrahedron of the cell's corners 0, 1, 3, 4 (a corner tetrahedron).
                let tet = [p[0], p[1], p[3], p[4]];
                let (g, w) = (lanes.run(|| super::tet_min_dihedral_deg(&tet)), tensor::min_dihedral_deg(CellType::Tetra, &tet));
                assert_eq!(g.to_bits(), w.to_bits(), "cell {cell} {lanes:?}: tetrahedron {g} against {w}");
            }
        }
        // The cells span the cases: many inverted, some degenerate.
        assert!(inverted > 500 && degenerate > 10, "{inverted} inverted, {degenerate} degenerate");
    }
}
