//! Wedges and pyramids as the average of their symmetric decompositions into tetrahedra: a
//! wedge over the six ways of cutting it into three tetrahedra (one per order of its triangle's
//! corners), a pyramid over its two cuts along a base diagonal. Each tetrahedron is P1, so the
//! element reproduces linear fields exactly, and the average has the cell's own symmetry (no
//! diagonal is preferred). Stiffness couples every pair of corners, face diagonals included (the
//! spring analogy still uses the cell's edges only).

use super::simplex::tet_gradients;
use super::{dot3, CellType};

/// A tetrahedron of a decomposition: its corners (local to the cell) and the sign that orients
/// it positively in a valid cell of the type.
type Tet = ([u8; 4], f64);

/// A wedge's six decompositions into three tetrahedra, one per order (a, b, c) of its triangle's
/// corners: [a, b, c, a′], [b, c, a′, b′], [c, a′, b′, c′] (′: the corner above), each signed by
/// its volume in the reference wedge. Constants, not tables built on first use: nothing lazy
/// can be half-built in a forked child (the unit test rebuilds them from the reference cells).
const WEDGE: [[Tet; 3]; 6] = [
    [([0, 1, 2, 3], -1.0), ([1, 2, 3, 4], -1.0), ([2, 3, 4, 5], -1.0)],
    [([1, 2, 0, 4], -1.0), ([2, 0, 4, 5], -1.0), ([0, 4, 5, 3], -1.0)],
    [([2, 0, 1, 5], -1.0), ([0, 1, 5, 3], -1.0), ([1, 5, 3, 4], -1.0)],
    [([0, 2, 1, 3], 1.0), ([2, 1, 3, 5], 1.0), ([1, 3, 5, 4], 1.0)],
    [([2, 1, 0, 5], 1.0), ([1, 0, 5, 4], 1.0), ([0, 5, 4, 3], 1.0)],
    [([1, 0, 2, 4], 1.0), ([0, 2, 4, 3], 1.0), ([2, 4, 3, 5], 1.0)],
];

/// A pyramid's two cuts along a base diagonal, signed as the wedge's.
const PYRAMID: [[Tet; 2]; 2] =
    [[([0, 1, 2, 4], 1.0), ([0, 2, 3, 4], 1.0)], [([0, 1, 3, 4], 1.0), ([1, 2, 3, 4], 1.0)]];

/// The decompositions of `ty` and the weight of each (1 / their number).
fn decompositions(ty: CellType) -> (&'static [&'static [Tet]], f64) {
    const W: [&[Tet]; 6] = [&WEDGE[0], &WEDGE[1], &WEDGE[2], &WEDGE[3], &WEDGE[4], &WEDGE[5]];
    const P: [&[Tet]; 2] = [&PYRAMID[0], &PYRAMID[1]];
    let list: &'static [&'static [Tet]] = match ty {
        CellType::Wedge => &W,
        CellType::Pyramid => &P,
        t => unreachable!("{t} cells are not decomposed"),
    };
    (list, 1.0 / list.len() as f64)
}

/// The index of corner pair (i, j), i < j, in the all-pairs list of `n` corners.
fn pair(n: usize, i: usize, j: usize) -> usize {
    let (i, j) = if i < j { (i, j) } else { (j, i) };
    i * n - i * (i + 1) / 2 + (j - i - 1)
}

/// The averaged stiffness of every corner pair (in `ty.couplings()` order) and lumped mass.
pub(super) fn element(ty: CellType, p: &[[f64; 3]], k: Option<&mut [f64]>, m: Option<&mut [f64]>) {
    let n = ty.num_corners();
    let (list, w) = decompositions(ty);
    let (mut k, mut m) = (k, m);
    if let Some(k) = k.as_deref_mut() {
        k[..n * (n - 1) / 2].iter_mut().for_each(|k| *k = 0.0);
    }
    if let Some(m) = m.as_deref_mut() {
        m[..n].iter_mut().for_each(|m| *m = 0.0);
    }
    for tets in list {
        for &(t, sign) in *tets {
            let q = t.map(|c| p[c as usize]);
            let (g, v) = tet_gradients(&q);
            let v = sign * v * w;
            if let Some(k) = k.as_deref_mut() {
                for a in 0..4 {
                    for b in a + 1..4 {
                        k[pair(n, t[a] as usize, t[b] as usize)] += v * dot3(&g[a], &g[b]);
                    }
                }
            }
            if let Some(m) = m.as_deref_mut() {
                t.iter().for_each(|&c| m[c as usize] += 0.25 * v);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::simplex::tet_volume;

    /// The tetrahedra with the sign of their volume in the reference cell.
    fn oriented(tets: &[[u8; 4]], reference: &[[f64; 3]]) -> Vec<Tet> {
        tets.iter().map(|t| (*t, tet_volume(&t.map(|k| reference[k as usize])).signum())).collect()
    }

    #[test]
    fn the_constant_decompositions_are_the_reference_cells_cuts() {
        let orders = [[0u8, 1, 2], [1, 2, 0], [2, 0, 1], [0, 2, 1], [2, 1, 0], [1, 0, 2]];
        let wedge =
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 1.0], [1.0, 0.0, 1.0]];
        for (k, &[a, b, c]) in orders.iter().enumerate() {
            let tets = [[a, b, c, a + 3], [b, c, a + 3, b + 3], [c, a + 3, b + 3, c + 3]];
            assert_eq!(oriented(&tets, &wedge), WEDGE[k].to_vec(), "wedge order {k}");
        }
        let pyramid = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 1.0]];
        let cuts = [[[0u8, 1, 2, 4], [0, 2, 3, 4]], [[0, 1, 3, 4], [1, 2, 3, 4]]];
        for (k, tets) in cuts.iter().enumerate() {
            assert_eq!(oriented(tets, &pyramid), PYRAMID[k].to_vec(), "pyramid cut {k}");
        }
    }

    /// The pair numbering agrees with `couplings()`, and a valid cell's averaged mass sums to its
    /// volume and is the same at symmetric corners.
    #[test]
    fn pairs_and_masses() {
        for ty in [CellType::Wedge, CellType::Pyramid] {
            let n = ty.num_corners();
            for (idx, &[i, j]) in ty.couplings().iter().enumerate() {
                assert_eq!(pair(n, i as usize, j as usize), idx);
            }
        }
        let wedge =
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 1.0], [1.0, 0.0, 1.0]];
        let mut m = [0.0; 8];
        element(CellType::Wedge, &wedge, None, Some(&mut m));
        assert!((m[..6].iter().sum::<f64>() - 0.5).abs() < 1e-15);
        assert!(m[..6].iter().all(|&x| (x - 0.5 / 6.0).abs() < 1e-15), "{m:?}");
        let pyramid = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 1.0]];
        element(CellType::Pyramid, &pyramid, None, Some(&mut m));
        assert!((m[..5].iter().sum::<f64>() - 1.0 / 3.0).abs() < 1e-15);
        assert!(m[..4].iter().all(|&x| (x - m[0]).abs() < 1e-16));
    }
}
