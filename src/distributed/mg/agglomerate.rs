//! Coarse levels agglomerated onto fewer ranks as they shrink. A coarse level with fewer than a
//! threshold of unknowns per rank is moved whole onto the first ranks of its communicator: rank r
//! gives its owned rows to rank r >> s (s halvings, the fewest that bring the level back to the
//! threshold per rank, or to one rank), which owns its senders' rows end to end in rank order.
//! The receiving ranks get a communicator of their own, split once when the hierarchy is built
//! and freed with it, and the level and every level below it live on it; the other ranks are
//! idle below: in each cycle they send their part of the level's right-hand side to their
//! receiving rank and wait for their part of its correction (`Mover`).
//!
//! The rule needs only the level's size and the rank count, so every rank takes it alike, and
//! moving rows changes no unknown and no entry: the levels (their unknowns) are those made
//! without agglomeration, which the global-id priorities of `select` keep independent of which
//! rank holds a row.

use super::mover::Mover;
use super::OwnedRows;
use crate::distributed::agreement::agree;
use crate::distributed::comm::Comm;
use crate::distributed::dist_mesh::halo_lists;
use crate::distributed::error::{DistError, DistErrorKind};
use crate::distributed::halo::HaloLayout;
use crate::distributed::reduce::all_to_all;
use crate::multigrid::layout::Layout;
use crate::sparse::CsrMatrix;
use std::collections::HashMap;
use std::sync::Arc;

/// The halvings that move a level of `rows` unknowns over `ranks` ranks onto ranks with at
/// least `per_rank` unknowns each (or onto one rank): 0 when it has enough already.
pub(super) fn halvings(rows: u64, ranks: usize, per_rank: u64) -> u32 {
    let mut s = 0;
    while active(ranks, s) > 1 && rows < per_rank.saturating_mul(active(ranks, s) as u64) {
        s += 1;
    }
    s
}

/// The ranks left when each rank r of `ranks` gives its rows to r >> `shift`.
pub(super) fn active(ranks: usize, shift: u32) -> usize {
    ((ranks.max(1) - 1) >> shift) + 1
}

/// How a level's vectors reach the next coarser level agglomerated onto fewer ranks: the coarse
/// layout the prolongation's columns refer to (on the finer level's ranks) and the move of its
/// owned entries onto the agglomerated level's ranks.
pub(super) struct Landing {
    pub(super) layout: Arc<HaloLayout>,
    pub(super) mover: Mover,
}

/// The agglomeration of one coarse level onto the first ranks of its communicator.
pub(super) struct Agglomeration {
    shift: u32,
    /// The receiving ranks' communicator (None on the others).
    sub: Option<Arc<Comm>>,
}

impl Agglomeration {
    /// Splits the receiving ranks of `comm` off for `shift` halvings (collective over `comm`).
    pub(super) fn new(comm: &Comm, shift: u32) -> Agglomeration {
        let sub = comm.split_first(active(comm.size(), shift)).map(Arc::new);
        Agglomeration { shift, sub }
    }

    /// The landing of the level `m` (its layout and the move of its owned entries; collective
    /// over `m`'s communicator).
    pub(super) fn landing(&self, m: &OwnedRows) -> Landing {
        let mover = Mover::new(m.halo.shared_comm(), self.shift, m.halo.owned());
        Landing { layout: m.halo.clone(), mover }
    }

    /// `m`'s rows sent to the receiving ranks (collective over `m`'s communicator): what
    /// `assemble` makes the moved level from.
    pub(super) fn send(&self, m: &OwnedRows) -> Vec<Vec<u64>> {
        let comm = m.halo.comm();
        let owners = m.halo.owner_ranks();
        let owned = m.halo.owned();
        // To rank me >> shift: the owned global ids, then each row's length and (column id,
        // the column's new owner, value bits) per entry.
        let mut words: Vec<u64> = vec![owned as u64];
        words.extend(&m.gids[..owned]);
        for i in 0..owned {
            let (cols, vals) = m.a.row(i);
            words.push(cols.len() as u64);
            for (&j, &v) in cols.iter().zip(vals) {
                words.extend([m.gids[j as usize], (owners[j as usize] >> self.shift) as u64, v.to_bits()]);
            }
        }
        let mut send = vec![Vec::new(); comm.size()];
        send[comm.rank() >> self.shift] = words;
        all_to_all(comm, &send)
    }

    /// The moved level from what `send` delivered (collective over the receiving ranks only):
    /// the rows of the rank's senders, owned entries in the senders' rank order and the halo by
    /// (owner, global id); None on the ranks that receive nothing.
    pub(super) fn assemble(&self, received: &[Vec<u64>]) -> Result<Option<OwnedRows>, DistError> {
        let Some(sub) = &self.sub else {
            return Ok(None);
        };
        let me = sub.rank();
        let (mut gids, mut rows) = (Vec::new(), Vec::new());
        for words in received {
            let Some((&n, rest)) = words.split_first() else {
                continue;
            };
            let n = (n as usize).min(rest.len());
            gids.extend(&rest[..n]);
            let mut rest = rest[n..].iter().copied();
            for _ in 0..n {
                let len = rest.next().unwrap_or(0) as usize;
                let row: Vec<(u64, usize, f64)> = (0..len)
                    .filter_map(|_| Some((rest.next()?, rest.next()? as usize, f64::from_bits(rest.next()?))))
                    .collect();
                rows.push(row);
            }
        }
        let owned = gids.len();
        let mut halo: Vec<(usize, u64)> = rows.iter().flatten().filter(|e| e.1 != me).map(|e| (e.1, e.0)).collect();
        halo.sort_unstable();
        halo.dedup();
        gids.extend(halo.iter().map(|e| e.1));
        let owners: Vec<usize> = vec![me; owned].into_iter().chain(halo.iter().map(|e| e.0)).collect();
        let index: HashMap<u64, u32> = gids.iter().zip(0u32..).map(|(&g, i)| (g, i)).collect();
        let n = gids.len();
        // A column this rank should own but does not: the ranks disagree about the level, which
        // consistent input cannot cause. Remembered, so every rank still reaches the exchanges.
        let mut missing = None;
        let mut triplets = Vec::new();
        for (i, row) in rows.iter().enumerate() {
            for &(g, _, v) in row {
                match index.get(&g) {
                    Some(&j) => triplets.push((i as u32, j, v)),
                    None => {
                        missing.get_or_insert(g);
                    }
                }
            }
        }
        let a = CsrMatrix::from_triplets(n, n, triplets);
        let order: Vec<u32> = (0..n as u32).collect();
        let (layout, error) = halo_lists(sub, &order, &gids, &owners);
        let checked = match (missing, error) {
            (Some(g), _) => {
                let msg = format!("the agglomerated level on rank {me} lacks the unknown of global id {g}");
                Err(DistError::new(me, DistErrorKind::Solve, msg))
            }
            (None, Some(e)) => Err(e),
            (None, None) => Ok(()),
        };
        agree(sub, checked)?;
        Ok(Some(OwnedRows { a, gids, halo: Arc::new(layout) }))
    }
}

#[cfg(test)]
mod tests {
    use super::{active, halvings};

    #[test]
    fn halvings_reach_the_threshold_per_rank() {
        // 582 unknowns on 4 ranks: 145 each; two ranks hold 291 each.
        assert_eq!(halvings(582, 4, 200), 1);
        assert_eq!(halvings(582, 4, 100), 0);
        assert_eq!(halvings(582, 4, 1000), 2);
        assert_eq!(halvings(10, 1, 1000), 0);
        assert_eq!(active(3, 1), 2);
        assert_eq!(active(4, 2), 1);
        assert_eq!(active(1000, 3), 125);
    }
}
