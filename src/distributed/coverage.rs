//! The check that a rank holds every cell around each vertex it owns: an owned vertex's row of
//! an operator sums over all its cells, so the owner needs them all (the host's ghost layer).
//! Each rank sends each of its owned cells, by its global vertex ids, to the owners of the cell's
//! vertices; an owner that lacks one is at fault. Fetching the missing cells instead of failing
//! is left for later.

use super::comm::Comm;
use super::error::{DistError, DistErrorKind};
use super::reduce::all_to_all;
use std::collections::HashSet;

/// Most corners of a cell (a hexahedron's).
const MAX_CORNERS: usize = 8;

/// A cell by its sorted global vertex ids, padded.
type CellKey = [u64; MAX_CORNERS];

fn key(corners: impl Iterator<Item = u64>) -> CellKey {
    let mut k = [u64::MAX; MAX_CORNERS];
    corners.take(MAX_CORNERS).enumerate().for_each(|(i, g)| k[i] = g);
    k.sort_unstable();
    k
}

/// Checks (collectively) that every owner holds every cell touching its vertices. `cells` lists
/// each local cell's local vertices, `owned_cell` says which are this rank's; `gids` and
/// `owners` are per local vertex. Returns the first cell this rank lacks, as its error.
pub(crate) fn check(
    comm: &Comm,
    cells: &[&[u32]],
    owned_cell: &[bool],
    gids: &[u64],
    owners: &[usize],
) -> Option<DistError> {
    let me = comm.rank();
    // Per owner rank: (cell key, the owned vertex's global id) records.
    let mut send = vec![Vec::new(); comm.size()];
    for corners in cells.iter().zip(owned_cell).filter(|(_, o)| **o).map(|(t, _)| t) {
        let k = key(corners.iter().map(|&v| gids[v as usize]));
        let mut told: Vec<usize> = Vec::new();
        for &v in corners.iter() {
            let o = owners[v as usize];
            if o != me && o < comm.size() && !told.contains(&o) {
                told.push(o);
                send[o].extend_from_slice(&k);
                send[o].push(gids[v as usize]);
            }
        }
    }
    let heard = all_to_all(comm, &send);
    let mine: HashSet<CellKey> = cells.iter().map(|t| key(t.iter().map(|&v| gids[v as usize]))).collect();
    let mut missing: Vec<(u64, CellKey)> = heard
        .iter()
        .flat_map(|recs| recs.chunks_exact(MAX_CORNERS + 1))
        .filter_map(|r| {
            let k: CellKey = r[..MAX_CORNERS].try_into().ok()?;
            (!mine.contains(&k)).then_some((r[MAX_CORNERS], k))
        })
        .collect();
    missing.sort_unstable();
    missing.first().map(|(g, k)| {
        let corners: Vec<u64> = k.iter().copied().filter(|&x| x != u64::MAX).collect();
        let msg = format!(
            "rank {me} owns global id {g} but lacks its cell {corners:?} (another rank's owned cell): the ghost \
             layer must hold every cell around a rank's owned vertices"
        );
        DistError::new(me, DistErrorKind::MissingGhostCell, msg)
    })
}
