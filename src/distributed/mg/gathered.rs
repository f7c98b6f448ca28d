//! The coarsest level gathered onto one rank: its rows are sent once at setup to rank 0 of the
//! level's communicator, which factors it by dense Cholesky (the serial coarsest solve's factor)
//! with the unknowns in global id order. Each solve moves the owned right-hand side values onto
//! that rank (one message per rank, `Mover`), solves there and sends each rank its values back;
//! the halo entries of the result are left zero for the caller's exchange.

use super::mover::Mover;
use super::OwnedRows;
use crate::dense::Cholesky;
use crate::distributed::agreement::agree;
use crate::distributed::error::{DistError, DistErrorKind};
use crate::distributed::reduce::all_to_all;
use crate::multigrid::coarse_solve::symmetric_cholesky;
use crate::multigrid::layout::Layout;
use std::collections::HashMap;

/// The gathered coarsest level, as one rank holds it.
pub(super) struct Gathered {
    /// This rank's owned unknowns (owned entries with a row).
    free: Vec<usize>,
    /// Every rank's unknowns' values onto rank 0 and back.
    mover: Mover,
    /// On rank 0: the dense position of each moved value.
    at: Vec<usize>,
    /// On rank 0, when some rank has an unknown: the factor.
    chol: Option<Cholesky>,
}

impl Gathered {
    /// Gathers the level `m` onto rank 0 and factors it there (collective; every rank returns
    /// the same result).
    pub(super) fn new(m: &OwnedRows) -> Result<Gathered, DistError> {
        let comm = m.halo.shared_comm().clone();
        let owned = m.halo.owned();
        // The unknowns are the owned entries with a row (an empty row is prescribed).
        let free: Vec<usize> = (0..owned).filter(|&i| !m.a.row(i).0.is_empty()).collect();
        // To rank 0: the unknowns' global ids, then (row id, column id, value bits) per entry.
        let mut mine: Vec<u64> = vec![free.len() as u64];
        mine.extend(free.iter().map(|&i| m.gids[i]));
        for &i in &free {
            let (cols, vals) = m.a.row(i);
            mine.extend(cols.iter().zip(vals).flat_map(|(&j, &v)| [m.gids[i], m.gids[j as usize], v.to_bits()]));
        }
        let mut send = vec![Vec::new(); comm.size()];
        send[0] = mine;
        let received = all_to_all(&comm, &send);
        let (at, factored) = if comm.rank() == 0 { factor(&received) } else { (Vec::new(), Ok(None)) };
        let chol = agree(&comm, factored)?;
        // Every rank sends to rank 0: the shift that takes the highest rank there.
        let shift = usize::BITS - (comm.size() - 1).leading_zeros();
        let mover = Mover::new(&comm, shift, free.len());
        Ok(Gathered { free, mover, at, chol })
    }

    /// x = A⁻¹ b on the owned entries (the halo's zero), from b's owned entries (collective).
    pub(super) fn solve(&self, b: &[f64], x: &mut [f64]) {
        let mut mine: Vec<f64> = self.free.iter().map(|&i| b[i]).collect();
        let mut moved = vec![0.0; self.mover.len()];
        self.mover.gather(&mine, &mut moved);
        if let Some(chol) = &self.chol {
            let mut rhs = vec![0.0; moved.len()];
            moved.iter().zip(&self.at).for_each(|(&v, &k)| rhs[k] = v);
            chol.solve(&mut rhs);
            moved.iter_mut().zip(&self.at).for_each(|(v, &k)| *v = rhs[k]);
        }
        self.mover.scatter(&moved, &mut mine);
        x.iter_mut().for_each(|v| *v = 0.0);
        self.free.iter().zip(&mine).for_each(|(&i, &v)| x[i] = v);
    }
}

/// On rank 0, from every rank's message (`new`): the dense position of each moved value and the
/// factor of the gathered matrix (None without unknowns).
fn factor(received: &[Vec<u64>]) -> (Vec<usize>, Result<Option<Cholesky>, DistError>) {
    let mut ids: Vec<u64> = Vec::new();
    let mut entries: Vec<&[u64]> = Vec::new();
    for words in received {
        let n = words.first().map_or(0, |&n| n as usize).min(words.len().saturating_sub(1));
        ids.extend(&words[1..1 + n]);
        entries.extend(words[1 + n..].chunks_exact(3));
    }
    let mut sorted = ids.clone();
    sorted.sort_unstable();
    let position: HashMap<u64, usize> = sorted.iter().enumerate().map(|(k, &g)| (g, k)).collect();
    let at: Vec<usize> = ids.iter().map(|g| position[g]).collect();
    let size = sorted.len();
    let mut a = vec![0.0; size * size];
    for e in entries {
        // A column with a value has a row on its owner, so it is an unknown.
        if let (Some(&i), Some(&j)) = (position.get(&e[0]), position.get(&e[1])) {
            a[i * size + j] += f64::from_bits(e[2]);
        }
    }
    let chol = match size {
        0 => Ok(None),
        _ => symmetric_cholesky(size, a).map(Some).ok_or_else(|| {
            let msg = format!("the gathered coarsest level ({size} unknowns) is not positive definite");
            DistError::new(0, DistErrorKind::Solve, msg)
        }),
    };
    (at, chol)
}
