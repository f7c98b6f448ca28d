//! Which rows of a kept-unknown transfer a re-reference chooses again. A row of P reproduces
//! linear fields at the positions its weights were chosen at (Σ w_j r_j = 0 for the donor
//! offsets r_j); after its donors' offsets moved by δ_j the error is Σ w_j δ_j, at most
//! Σ|w| max|δ_j| ≤ 2 max|δ_j|. So a row whose offsets changed by less than a small fraction of
//! their length keeps its weights (and its donors), and only the rows near the large motions
//! pay for new ones.

use crate::sparse::CsrMatrix;
use rayon::prelude::*;

/// Largest change of a donor offset, relative to its length at the last choice, with which a
/// row keeps its weights (the iteration counts per step in docs/PERFORMANCE.md).
pub(crate) const KEEP_WEIGHTS_BELOW: f64 = 0.05;

/// The offset (donor minus fine unknown, `dim` values) of every entry of `prolong` at the fine
/// unknowns' positions `points`; coarse unknown c is fine unknown `kept[c]`.
pub(crate) fn donor_offsets(prolong: &CsrMatrix, kept: &[u32], points: &[f64], dim: usize) -> Vec<f64> {
    let mut out = vec![0.0; prolong.nnz() * dim];
    for i in 0..prolong.nrows {
        let (a, b) = (prolong.row_ptr[i] as usize, prolong.row_ptr[i + 1] as usize);
        for (e, &c) in (a..b).zip(&prolong.cols[a..b]) {
            let j = kept[c as usize] as usize;
            for k in 0..dim {
                out[e * dim + k] = points[j * dim + k] - points[i * dim + k];
            }
        }
    }
    out
}

/// Per row of `prolong`: whether some donor offset at `points` differs from its stored one
/// (`offsets`, as `donor_offsets` made them) by `KEEP_WEIGHTS_BELOW` of its length or more.
pub(crate) fn rows_to_redo(prolong: &CsrMatrix, kept: &[u32], offsets: &[f64], points: &[f64], dim: usize) -> Vec<bool> {
    let tau2 = KEEP_WEIGHTS_BELOW * KEEP_WEIGHTS_BELOW;
    (0..prolong.nrows)
        .into_par_iter()
        .with_min_len(1024)
        .map(|i| {
            let (a, b) = (prolong.row_ptr[i] as usize, prolong.row_ptr[i + 1] as usize);
            (a..b).zip(&prolong.cols[a..b]).any(|(e, &c)| {
                let j = kept[c as usize] as usize;
                let (mut old2, mut diff2) = (0.0, 0.0);
                for k in 0..dim {
                    let r_old = offsets[e * dim + k];
                    let r_new = points[j * dim + k] - points[i * dim + k];
                    old2 += r_old * r_old;
                    diff2 += (r_new - r_old) * (r_new - r_old);
                }
                diff2 >= tau2 * old2 && diff2 > 0.0
            })
        })
        .collect()
}

/// The stored offsets of `new`, made from `old` (offsets `old_offsets`) by choosing the rows
/// `redo` again at `points`: the kept rows keep theirs, the others are measured at `points`.
pub(crate) fn updated_offsets(
    old: &CsrMatrix,
    old_offsets: &[f64],
    new: &CsrMatrix,
    redo: &[bool],
    kept: &[u32],
    points: &[f64],
    dim: usize,
) -> Vec<f64> {
    let mut out = donor_offsets(new, kept, points, dim);
    for i in (0..new.nrows).filter(|&i| !redo[i]) {
        let (a, b) = (old.row_ptr[i] as usize * dim, old.row_ptr[i + 1] as usize * dim);
        let at = new.row_ptr[i] as usize * dim;
        out[at..at + b - a].copy_from_slice(&old_offsets[a..b]);
    }
    out
}
