//! The coarsest level gathered on every rank: its rows are gathered once at setup and factored
//! redundantly by dense Cholesky (the serial coarsest solve's factor), unknowns ordered by
//! global id, so every rank holds the same factor. Each solve gathers the owned right-hand side
//! values (one collective), and every rank solves and reads the values of its local entries,
//! halo included, so the result needs no exchange.

use super::OwnedRows;
use crate::dense::Cholesky;
use crate::distributed::comm::Comm;
use crate::distributed::error::{DistError, DistErrorKind};
use crate::distributed::reduce::gather_varcount;
use crate::multigrid::coarse_solve::symmetric_cholesky;
use crate::multigrid::layout::Layout;
use std::collections::HashMap;
use std::sync::Arc;

/// The gathered coarsest level of one rank.
pub(super) struct Gathered {
    comm: Arc<Comm>,
    /// This rank's owned unknowns (owned entries with a row).
    free: Vec<usize>,
    /// The dense position of each value of the gathered right-hand side (every rank's owned
    /// entries in rank order).
    gathered_at: Vec<usize>,
    /// The dense position of each local entry; None for a prescribed one.
    local_at: Vec<Option<usize>>,
    /// None when no rank has an unknown.
    chol: Option<Cholesky>,
}

impl Gathered {
    /// Gathers and factors the level `m` (collective; every rank returns the same result).
    pub(super) fn new(m: &OwnedRows) -> Result<Gathered, DistError> {
        let comm = m.halo.shared_comm().clone();
        let owned = m.halo.owned();
        // The unknowns are the owned entries with a row (an empty row is prescribed).
        let free: Vec<usize> = (0..owned).filter(|&i| !m.a.row(i).0.is_empty()).collect();
        let mine: Vec<u64> = free.iter().map(|&i| m.gids[i]).collect();
        let ids = gather_varcount(&comm, &mine);
        let mut sorted: Vec<u64> = ids.iter().flatten().copied().collect();
        sorted.sort_unstable();
        let position: HashMap<u64, usize> = sorted.iter().enumerate().map(|(k, &g)| (g, k)).collect();
        let size = sorted.len();
        let gathered_at: Vec<usize> = ids.iter().flatten().map(|g| position[g]).collect();
        let local_at: Vec<Option<usize>> = m.gids.iter().map(|g| position.get(g).copied()).collect();
        let mut rows: Vec<u64> = Vec::new();
        for &i in &free {
            let (cols, vals) = m.a.row(i);
            // A column with a value has a row on its owner, so it is an unknown.
            for (k, &v) in cols.iter().filter_map(|&j| local_at[j as usize]).zip(vals) {
                rows.extend([position[&m.gids[i]] as u64, k as u64, v.to_bits()]);
            }
        }
        let all = gather_varcount(&comm, &rows);
        let mut a = vec![0.0; size * size];
        for e in all.iter().flat_map(|r| r.chunks_exact(3)) {
            a[e[0] as usize * size + e[1] as usize] += f64::from_bits(e[2]);
        }
        let chol = match size {
            0 => None,
            _ => Some(symmetric_cholesky(size, a).ok_or_else(|| {
                // Every rank has the same matrix, so every rank reaches this verdict.
                let msg = format!("the gathered coarsest level ({size} unknowns) is not positive definite");
                DistError::new(0, DistErrorKind::Solve, msg)
            })?),
        };
        Ok(Gathered { comm, free, gathered_at, local_at, chol })
    }

    /// x = A⁻¹ b on every local entry, from b's owned entries (collective).
    pub(super) fn solve(&self, b: &[f64], x: &mut [f64]) {
        let mine: Vec<f64> = self.free.iter().map(|&i| b[i]).collect();
        let values = gather_varcount(&self.comm, &mine);
        let Some(chol) = &self.chol else {
            x.iter_mut().for_each(|v| *v = 0.0);
            return;
        };
        let mut rhs = vec![0.0; self.gathered_at.len()];
        values.iter().flatten().zip(&self.gathered_at).for_each(|(&v, &k)| rhs[k] = v);
        chol.solve(&mut rhs);
        x.iter_mut().zip(&self.local_at).for_each(|(x, k)| *x = k.map_or(0.0, |k| rhs[k]));
    }
}
