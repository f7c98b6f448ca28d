//! The coarse operator of one coarsening step across ranks: Pᵀ A P with its own halo, from the
//! interpolation rows of the owned unknowns in global terms (`donors`).
//!
//! A coarse unknown keeps the global id and the owner of the fine unknown it is. A rank's owned
//! rows of A reach into its fine halo, so it fetches the P rows of its halo entries from their
//! owners, forms Rₒ A P with Rₒ the transpose of its owned rows of P (the serial sparse triple
//! product), and sends the rows of coarse unknowns owned elsewhere to their owners, which add
//! every rank's part in rank order. The coarse halo is every coarse unknown an owned coarse row
//! or an owned row of P names that another rank owns, grouped by owner and ordered by global id,
//! as the fine layouts are.

use super::OwnedRows;
use crate::distributed::agreement::agree;
use crate::distributed::dist_mesh::halo_lists;
use crate::distributed::error::{DistError, DistErrorKind};
use crate::distributed::halo::HaloLayout;
use crate::distributed::reduce::{all_to_all, sum_in_rank_order};
use crate::multigrid::layout::Layout;
use crate::sparse::{triple_product, CsrMatrix};
use std::collections::HashMap;
use std::sync::Arc;

/// A P row in global terms: (coarse global id, its owner rank, weight) per entry.
pub(super) type GlobalRow = Vec<(u64, usize, f64)>;

/// The Galerkin product Pᵀ m P with P's owned rows `owned_rows` (global terms; the rows of
/// `m`'s owned entries, which may come from another operator over the same unknowns) and the
/// prolongation to it (fine local entries × coarse local entries; the fine halo's rows empty),
/// or None when no rank keeps an unknown (collective).
pub(super) fn product(m: &OwnedRows, owned_rows: &[GlobalRow]) -> Result<Option<(OwnedRows, CsrMatrix)>, DistError> {
    let comm = m.halo.shared_comm().clone();
    let (me, size) = (comm.rank(), comm.size());
    let (n, owned) = (m.halo.len(), m.halo.owned());
    let mut rows = owned_rows.to_vec();
    rows.extend(halo_rows(&m.halo, &rows));

    // Coarse unknowns as met: the owned kept ones first (in the fine order), then the others.
    let mut index: HashMap<u64, u32> = HashMap::new();
    let mut met: Vec<(u64, usize)> = Vec::new();
    let mut number = |gid: u64, owner: usize, met: &mut Vec<(u64, usize)>| {
        *index.entry(gid).or_insert_with(|| {
            met.push((gid, owner));
            (met.len() - 1) as u32
        })
    };
    for row in &rows[..owned] {
        for &(gid, owner, _) in row.iter().filter(|e| e.1 == me) {
            number(gid, owner, &mut met);
        }
    }
    let coarse_owned = met.len();
    let mut full = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        for &(gid, owner, w) in row {
            full.push((i as u32, number(gid, owner, &mut met), w));
        }
    }
    let nc = met.len();
    let p_full = CsrMatrix::from_triplets(n, nc, full.clone());
    full.retain(|&(i, _, _)| (i as usize) < owned);
    let p_owned = CsrMatrix::from_triplets(n, nc, full);
    let part = triple_product(&p_owned.transpose(), &m.a, &p_full);

    // Rows of coarse unknowns owned elsewhere go to their owners: (row id, column id, column
    // owner, weight bits) each.
    let mut send: Vec<Vec<u64>> = vec![Vec::new(); size];
    for (r, &(gid, owner)) in met.iter().enumerate() {
        let (cols, vals) = part.row(r);
        for (&c, &v) in cols.iter().zip(vals) {
            let (cg, co) = met[c as usize];
            send[owner].extend([gid, cg, co as u64, v.to_bits()]);
        }
    }
    let received = all_to_all(&comm, &send);
    let entries: Vec<(u64, u64, usize, f64)> = received
        .iter()
        .flat_map(|list| list.chunks_exact(4).map(|e| (e[0], e[1], e[2] as usize, f64::from_bits(e[3]))))
        .collect();
    let total: u64 = sum_in_rank_order(&comm, &[coarse_owned as f64])[0] as u64;
    if total == 0 {
        return Ok(None);
    }

    // The coarse layout: owned unknowns, then the halo by (owner, global id).
    let mut halo: Vec<(usize, u64)> = entries
        .iter()
        .map(|e| (e.2, e.1))
        .chain(p_owned.cols.iter().map(|&c| (met[c as usize].1, met[c as usize].0)))
        .filter(|&(o, _)| o != me)
        .collect();
    halo.sort_unstable();
    halo.dedup();
    let gids: Vec<u64> = met[..coarse_owned].iter().map(|e| e.0).chain(halo.iter().map(|e| e.1)).collect();
    let owners: Vec<usize> = vec![me; coarse_owned].into_iter().chain(halo.iter().map(|e| e.0)).collect();
    let local: HashMap<u64, u32> = gids.iter().zip(0u32..).map(|(&g, i)| (g, i)).collect();
    // A missing unknown is remembered, not returned at once: every rank still reaches the
    // exchanges below, and all return the error together.
    let mut missing = None;
    let mut at = |g: u64| {
        local.get(&g).copied().unwrap_or_else(|| {
            missing.get_or_insert(g);
            0
        })
    };
    let ncl = gids.len();
    let triplets = entries.iter().map(|&(row, col, _, v)| (at(row), at(col), v)).collect();
    let a = CsrMatrix::from_triplets(ncl, ncl, triplets);
    let mut prolong = Vec::with_capacity(p_owned.nnz());
    for i in 0..owned {
        let (cols, vals) = p_owned.row(i);
        for (&c, &w) in cols.iter().zip(vals) {
            prolong.push((i as u32, at(met[c as usize].0), w));
        }
    }
    let prolong = CsrMatrix::from_triplets(n, ncl, prolong);
    let order: Vec<u32> = (0..ncl as u32).collect();
    let (layout, error) = halo_lists(&comm, &order, &gids, &owners);
    let checked = match (missing, error) {
        (Some(g), _) => Err(internal(me, g)),
        (None, Some(e)) => Err(e),
        (None, None) => Ok(()),
    };
    agree(&comm, checked)?;
    Ok(Some((OwnedRows { a, gids, halo: Arc::new(layout) }, prolong)))
}

/// The rows of `halo`'s halo entries, from their owners (`rows` holds the owned ones): a
/// matrix's rows in global terms, such as P's (collective).
pub(super) fn halo_rows(halo: &HaloLayout, rows: &[GlobalRow]) -> Vec<GlobalRow> {
    let comm = halo.comm();
    let mut send: Vec<Vec<u64>> = vec![Vec::new(); comm.size()];
    for (rank, idx) in halo.send_lists() {
        for &i in idx {
            let row = &rows[i as usize];
            send[*rank].push(row.len() as u64);
            send[*rank].extend(row.iter().flat_map(|&(g, o, w)| [g, o as u64, w.to_bits()]));
        }
    }
    let received = all_to_all(comm, &send);
    let mut out = Vec::with_capacity(halo.len() - halo.owned());
    for (rank, range) in halo.recv_ranges() {
        let mut words = received[*rank].iter().copied();
        for _ in range.clone() {
            let len = words.next().unwrap_or(0) as usize;
            let row: GlobalRow = (0..len)
                .filter_map(|_| Some((words.next()?, words.next()? as usize, f64::from_bits(words.next()?))))
                .collect();
            out.push(row);
        }
    }
    out
}

/// A coarse unknown named in a row that is not in the rank's coarse layout: the ranks disagree
/// about the hierarchy, which consistent input cannot cause.
fn internal(me: usize, gid: u64) -> DistError {
    let msg = format!("the coarse level built on rank {me} lacks the unknown of global id {gid}");
    DistError::new(me, DistErrorKind::Solve, msg)
}
