//! Restriction Pᵀ as a gather over coarse rows (deterministic and parallel, like every product
//! here) that stores no weights of its own: each entry names its fine row and its slot in that
//! row of P and reads the weight there. An explicit transpose would hold every weight twice.

use crate::sparse::{pair_sum, par_fill, CsrMatrix};
use std::sync::Arc;

pub struct Restriction {
    /// Coarse unknowns.
    pub nrows: usize,
    /// Fine unknowns.
    pub ncols: usize,
    prolong: Arc<CsrMatrix>,
    row_ptr: Vec<u32>,
    /// Fine row of each entry, ascending within a coarse row (as in the explicit transpose).
    rows: Vec<u32>,
    /// Where the entry sits within its row of P.
    slots: Slots,
    /// Every row of P has three entries (no coarse cell with a repeated unknown), so row i
    /// starts at 3i: one random read per entry fewer, which halves the cost over `row_ptr`.
    rows_of_three: bool,
}

/// The slots of the entries: a byte each when every row of P has at most 256 entries (as on
/// most meshes: a fine unknown interpolates from a few coarse ones), else four bytes, for the
/// long rows least-squares interpolation can build on thin wall layers.
enum Slots {
    Byte(Vec<u8>),
    Wide(Vec<u32>),
}

impl Restriction {
    pub fn new(prolong: Arc<CsrMatrix>) -> Restriction {
        let longest = prolong.row_ptr.windows(2).map(|w| w[1] - w[0]).max().unwrap_or(0);
        let start = |i: usize| prolong.row_ptr[i] as usize;
        let (row_ptr, rows, slots) = if longest <= 256 {
            // p − start(i) < longest ≤ 256, so the cast keeps the value.
            let (row_ptr, rows, s) = prolong.transpose_map(|p, i| (p - start(i)) as u8);
            (row_ptr, rows, Slots::Byte(s))
        } else {
            // p − start(i) < longest, a difference of two u32 offsets, so the cast keeps it.
            let (row_ptr, rows, s) = prolong.transpose_map(|p, i| (p - start(i)) as u32);
            (row_ptr, rows, Slots::Wide(s))
        };
        let rows_of_three = prolong.row_ptr.iter().enumerate().all(|(i, &p)| p as usize == 3 * i);
        Restriction { nrows: prolong.ncols, ncols: prolong.nrows, prolong, row_ptr, rows, slots, rows_of_three }
    }

    /// y = Pᵀ x, bitwise as `prolong.transpose().mul_vec(x, y)`: same products, same order.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.ncols, "restrict: x has {} entries, {} fine unknowns", x.len(), self.ncols);
        assert_eq!(y.len(), self.nrows, "restrict: y has {} entries, {} coarse unknowns", y.len(), self.nrows);
        match &self.slots {
            Slots::Byte(s) => self.gather(s, x, y),
            Slots::Wide(s) => self.gather(s, x, y),
        }
    }

    /// y = Pᵀ x with the entries' slots `slots`.
    fn gather<S: Copy + Into<u64> + Sync>(&self, slots: &[S], x: &[f64], y: &mut [f64]) {
        let p = &*self.prolong;
        par_fill(y, |j| {
            let r = self.row_ptr[j] as usize..self.row_ptr[j + 1] as usize;
            let start = |i: u32| if self.rows_of_three { 3 * i as usize } else { p.row_ptr[i as usize] as usize };
            let weight = |i: u32, s: S| p.vals[start(i) + s.into() as usize];
            pair_sum(&self.rows[r.clone()], &slots[r], |i, s| weight(i, s) * x[i as usize])
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_explicit_transpose_bitwise() {
        // Rows of varying length (read through row_ptr), then rows of three (at 3i).
        let ragged =
            vec![(0, 0, 0.3), (0, 2, 0.7), (1, 1, 1.0), (2, 0, 0.1), (2, 1, 0.2), (2, 2, 0.7), (4, 2, 1.0 / 3.0)];
        let three = (0..5u32).flat_map(|i| (0..3u32).map(move |j| (i, j, 1.0 / (i + j + 2) as f64))).collect();
        for t in [ragged, three] {
            let p = CsrMatrix::from_triplets(5, 3, t);
            let x = [1.0 / 7.0, -2.5, 3.0e-3, 9.0, 1.0 / 11.0];
            let (mut want, mut got) = ([0.0; 3], [0.0; 3]);
            p.transpose().mul_vec(&x, &mut want);
            Restriction::new(Arc::new(p)).mul_vec(&x, &mut got);
            assert_eq!(want.map(f64::to_bits), got.map(f64::to_bits));
        }
    }

    /// A row of P of 300 entries (as least-squares interpolation builds on thin wall layers)
    /// needs slots wider than a byte: no panic, and the product is still the transpose's.
    #[test]
    fn rows_of_over_256_entries() {
        let long = (0..300u32).map(|j| (0, j, 1.0 / (j + 1) as f64));
        let t: Vec<(u32, u32, f64)> = long.chain((0..300u32).map(|j| (1, j, 0.5))).collect();
        let p = CsrMatrix::from_triplets(2, 300, t);
        let x = [0.25, -3.0];
        let (mut want, mut got) = (vec![0.0; 300], vec![0.0; 300]);
        p.transpose().mul_vec(&x, &mut want);
        let r = Restriction::new(Arc::new(p));
        assert!(matches!(r.slots, Slots::Wide(_)));
        r.mul_vec(&x, &mut got);
        assert_eq!(want.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), got.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
        assert_eq!(got[299], 0.25 / 300.0 - 1.5);
    }
}
