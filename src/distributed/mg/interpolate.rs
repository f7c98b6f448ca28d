//! Interpolation weights of a dropped unknown from its kept strong neighbours, from the operator's
//! row alone (direct interpolation, Stüben 2001): the row's negative couplings are spread over
//! the kept ones, its positive couplings lumped on the diagonal,
//!
//!   w_ij = −α a_ij / (a_ii + Σ_{k≠i, a_ik>0} a_ik),  α = Σ_{k≠i, a_ik<0} a_ik / Σ_{j kept} a_ij,
//!
//! so a row whose couplings sum to zero interpolates constants exactly, and one next to a
//! prescribed unknown (a positive row sum) interpolates less. Each row needs only the rank's own
//! row and the roles of its columns, so a rank computes the rows of its owned unknowns alone.
//!
//! Every level fits least-squares weights to positions by the serial donor rule (`donors`) and
//! keeps these rows where no bounded fit exists.

use super::select::{DROPPED, KEPT};
use super::OwnedRows;
use crate::multigrid::layout::Layout;

/// The row of P of each owned unknown: (local column of a kept unknown, weight). A kept unknown
/// takes its own value, a dropped one its weights, one out of the solve an empty row.
pub(super) fn weights(m: &OwnedRows, strong: &[Vec<u32>], state: &[u8]) -> Vec<Vec<(u32, f64)>> {
    (0..m.halo.owned())
        .map(|i| match state[i] {
            KEPT => vec![(i as u32, 1.0)],
            DROPPED => direct(m, i, &strong[i], state),
            _ => Vec::new(),
        })
        .collect()
}

/// The weights of the dropped unknown `i` from its kept strong neighbours.
fn direct(m: &OwnedRows, i: usize, strong: &[u32], state: &[u8]) -> Vec<(u32, f64)> {
    let (cols, vals) = m.a.row(i);
    let (mut diag, mut negative) = (0.0, 0.0);
    for (&j, &v) in cols.iter().zip(vals) {
        if j as usize == i || v > 0.0 {
            diag += v;
        } else {
            negative += v;
        }
    }
    let kept: Vec<(u32, f64)> =
        strong.iter().filter(|&&j| state[j as usize] == KEPT).map(|&j| (j, m.a.get(i, j as usize))).collect();
    let kept_sum: f64 = kept.iter().map(|&(_, v)| v).sum();
    // A dropped unknown has a kept strong neighbour (`select`), whose coupling is negative.
    debug_assert!(state[i] == DROPPED && kept_sum < 0.0 && diag > 0.0);
    let scale = -(negative / kept_sum) / diag;
    kept.into_iter().map(|(j, v)| (j, scale * v)).collect()
}
