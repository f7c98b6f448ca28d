//! Who owns each vertex a rank holds, and the global numbering of owned vertices.
//!
//! A vertex held by several ranks is owned by the lowest rank that has it in one of its owned
//! cells: deterministic, and settled by one exchange. The exchange goes through a directory:
//! global id g is looked after by rank g mod size, which hears from every rank holding g
//! (whether in an owned cell, and where), names the owner back, and checks that every copy of g
//! sits at the owner's position, bit for bit (ghost copies are the owner's values).

use super::comm::Comm;
use super::error::{DistError, DistErrorKind};
use super::reduce::{all_to_all, gather};
use std::collections::HashMap;

/// What one rank tells the directory of one of its vertices.
struct Held<'a> {
    rank: usize,
    gid: u64,
    in_owned_cell: bool,
    point: &'a [u64],
}

/// The owner rank of each of this rank's vertices (collective). `in_owned_cell[v]`: vertex v
/// lies in one of this rank's owned cells. Every rank gets its answer even when some global id
/// fails a check; the first failure this rank's directory found is returned with it.
pub(crate) fn owners(
    comm: &Comm,
    dim: usize,
    gids: &[u64],
    coords: &[f64],
    in_owned_cell: &[bool],
) -> (Vec<usize>, Option<DistError>) {
    let size = comm.size();
    // One record per vertex: global id, owned-cell flag, the coordinates' bits.
    let record = 2 + dim;
    let mut send = vec![Vec::new(); size];
    for (v, &g) in gids.iter().enumerate() {
        let to = &mut send[(g % size as u64) as usize];
        to.extend([g, in_owned_cell[v] as u64]);
        to.extend(coords[v * dim..(v + 1) * dim].iter().map(|x| x.to_bits()));
    }
    let heard = all_to_all(comm, &send);
    let (owner_of, error) = decide(dim, &heard);
    // The answers, in the order each rank sent its records.
    let replies: Vec<Vec<u64>> = heard
        .iter()
        .map(|recs| recs.chunks_exact(record).map(|r| owner_of.get(&r[0]).copied().unwrap_or(u64::MAX)).collect())
        .collect();
    let answers = all_to_all(comm, &replies);
    let mut next = vec![0usize; size];
    let owners = gids
        .iter()
        .map(|&g| {
            let d = (g % size as u64) as usize;
            let o = answers[d].get(next[d]).copied().unwrap_or(u64::MAX);
            next[d] += 1;
            usize::try_from(o).unwrap_or(usize::MAX)
        })
        .collect();
    (owners, error)
}

/// The directory's decisions on the records `heard` (by source rank): each global id's owner,
/// and the first inconsistency found (in global id order).
fn decide(dim: usize, heard: &[Vec<u64>]) -> (HashMap<u64, u64>, Option<DistError>) {
    let mut held: Vec<Held> = heard
        .iter()
        .enumerate()
        .flat_map(|(rank, recs)| {
            recs.chunks_exact(2 + dim).map(move |r| Held { rank, gid: r[0], in_owned_cell: r[1] != 0, point: &r[2..] })
        })
        .collect();
    held.sort_by_key(|h| (h.gid, h.rank));
    let mut owner_of = HashMap::with_capacity(held.len());
    let mut error: Option<DistError> = None;
    for same in held.chunk_by(|a, b| a.gid == b.gid) {
        let g = same[0].gid;
        let Some(owner) = same.iter().find(|h| h.in_owned_cell) else {
            let rank = same[0].rank;
            let msg = format!("global id {g} lies in no rank's owned cells (rank {rank} has it only in ghost cells)");
            error.get_or_insert(DistError::new(rank, DistErrorKind::Inconsistent, msg));
            continue;
        };
        owner_of.insert(g, owner.rank as u64);
        if let Some(bad) = same.iter().find(|h| h.point != owner.point) {
            let at = |h: &Held| h.point.iter().map(|b| f64::from_bits(*b)).collect::<Vec<_>>();
            let msg = format!(
                "global id {g} is at {:?} on rank {} but at {:?} on its owner, rank {} (a global id names one \
                 position on every rank)",
                at(bad),
                bad.rank,
                at(owner),
                owner.rank
            );
            error.get_or_insert(DistError::new(bad.rank, DistErrorKind::Inconsistent, msg));
        }
    }
    (owner_of, error)
}

/// The global number of each owned vertex: ranks in order, each rank's owned vertices in
/// global id order, numbered contiguously (collective). Returns this rank's first number and the
/// number of vertices over all ranks.
pub(crate) fn first_global_number(comm: &Comm, owned: usize) -> (u64, u64) {
    let counts = gather(comm, &[owned as u64]);
    let first = counts[..comm.rank()].iter().sum();
    (first, counts.iter().sum())
}
