//! The assembled Galerkin biharmonic's rows bounded (`galerkin_biharmonic.rs`): its entries far
//! smaller than their row's and column's diagonals dropped, their magnitudes added to the
//! diagonal.
//!
//! Across thin wall layers A_c = Pᵀ A P couples unknowns several spacings apart along the wall
//! by entries ten orders of magnitude below those through the layer, and each level's product of
//! the level above fills its rows with more of them: on the deepest levels of a wing most of a row's
//! entries are below 10⁻⁶ of its diagonal. Entry (i, j) is dropped when |a_ij| and |a_ji| are
//! both below `DROP_BELOW` √(a_ii a_jj); the pattern stays symmetric, and adding each dropped
//! magnitude to its row's diagonal adds a sum of terms |a_ij| (x_i ± x_j)², so the kept operator
//! stays symmetric and at least as stiff as the product (positive definite where it is). The
//! pattern is decided once, when the product is made; a moved mesh refills the values into it
//! (`Dropped::fill`), so the levels below keep their own patterns.

use crate::sparse::{offset, CsrMatrix};

/// An entry is dropped below this fraction of √(a_ii a_jj). Larger bounds lump enough onto the
/// diagonals to stiffen the smooth modes the coarse levels correct, and the wing's count rises
/// (docs/DESIGN.md §5, "Wall layers").
pub(crate) const DROP_BELOW: f64 = 1e-6;

/// Where each entry of the full product goes in the kept matrix.
#[derive(Clone)]
pub(crate) struct Dropped {
    /// Per entry of the full product, its position in the kept matrix, or `LUMPED` when it is
    /// added to its row's diagonal.
    to: Vec<u32>,
    /// Per row, the position of its diagonal in the kept matrix (`LUMPED` where the product
    /// has none: then nothing in the row is dropped).
    diag: Vec<u32>,
}

/// Marks a dropped entry, or a row without a diagonal.
const LUMPED: u32 = u32::MAX;

impl Dropped {
    /// The kept pattern of the product `full` (square, symmetric pattern) and the kept matrix
    /// with its values (`fill`).
    pub(crate) fn new(full: &CsrMatrix) -> (Dropped, CsrMatrix) {
        let n = full.nrows;
        let diagonal: Vec<Option<f64>> = (0..n).map(|i| full.find(i, i).map(|p| full.vals[p].abs())).collect();
        let small = |i: usize, j: usize, x: f64| match (diagonal[i], diagonal[j]) {
            (Some(di), Some(dj)) => i != j && x.abs() < DROP_BELOW * (di * dj).sqrt(),
            _ => false,
        };
        let mut to = Vec::with_capacity(full.nnz());
        let mut diag = vec![LUMPED; n];
        let mut row_ptr = Vec::with_capacity(n + 1);
        row_ptr.push(0u32);
        let mut cols = Vec::new();
        for (i, d) in diag.iter_mut().enumerate() {
            let (c, v) = full.row(i);
            for (&j, &x) in c.iter().zip(v) {
                if small(i, j as usize, x) && small(j as usize, i, full.get(j as usize, i)) {
                    to.push(LUMPED);
                } else {
                    if i == j as usize {
                        *d = offset(cols.len());
                    }
                    to.push(offset(cols.len()));
                    cols.push(j);
                }
            }
            row_ptr.push(offset(cols.len()));
        }
        let nnz = cols.len();
        let mut kept = CsrMatrix { nrows: n, ncols: full.ncols, row_ptr, cols, vals: vec![0.0; nnz] };
        let dropped = Dropped { to, diag };
        dropped.fill(full, &mut kept);
        (dropped, kept)
    }

    /// The kept matrix's values from the full product's, in the pattern `new` chose: each kept
    /// entry as it is, each dropped one's magnitude added to its row's diagonal (in the row's
    /// order, so the sums are the same on any thread count).
    pub(crate) fn fill(&self, full: &CsrMatrix, kept: &mut CsrMatrix) {
        kept.vals.iter_mut().for_each(|v| *v = 0.0);
        for i in 0..full.nrows {
            let range = full.row_ptr[i] as usize..full.row_ptr[i + 1] as usize;
            for p in range {
                match self.to[p] {
                    LUMPED => kept.vals[self.diag[i] as usize] += full.vals[p].abs(),
                    q => kept.vals[q as usize] += full.vals[p],
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3×3 symmetric matrix with one pair of tiny entries: they leave the pattern, their
    /// magnitude goes onto both diagonals, the rest is kept as it is; a refill with new values
    /// keeps the pattern.
    #[test]
    fn tiny_pairs_are_lumped_on_the_diagonal_and_the_pattern_kept() {
        let t = vec![
            (0, 0, 4.0),
            (0, 1, -1.0),
            (0, 2, 1e-11),
            (1, 0, -1.0),
            (1, 1, 4.0),
            (1, 2, -2.0),
            (2, 0, 1e-11),
            (2, 1, -2.0),
            (2, 2, 9.0),
        ];
        let mut full = CsrMatrix::from_triplets(3, 3, t);
        let (dropped, mut kept) = Dropped::new(&full);
        assert_eq!(kept.nnz(), 7);
        assert_eq!(kept.find(0, 2), None);
        assert_eq!(kept.find(2, 0), None);
        assert_eq!(kept.get(0, 0), 4.0 + 1e-11);
        assert_eq!(kept.get(2, 2), 9.0 + 1e-11);
        assert_eq!(kept.get(1, 2), -2.0);
        // New values in the same pattern: an entry that is no longer small stays dropped.
        full.vals.iter_mut().for_each(|v| *v *= 2.0);
        let p = full.find(0, 2).expect("in the product's pattern");
        full.vals[p] = -0.5;
        dropped.fill(&full, &mut kept);
        assert_eq!(kept.nnz(), 7);
        assert_eq!(kept.get(0, 0), 8.0 + 0.5);
        assert_eq!(kept.get(2, 2), 18.0 + 2e-11);
    }

    /// One side of a pair below the bound and the other above it keeps both.
    #[test]
    fn a_pair_is_dropped_only_when_both_sides_are_small() {
        let t = vec![(0, 0, 1.0), (0, 1, 1e-11), (1, 0, 0.5), (1, 1, 1.0)];
        let (_, kept) = Dropped::new(&CsrMatrix::from_triplets(2, 2, t));
        assert_eq!(kept.nnz(), 4);
    }
}
