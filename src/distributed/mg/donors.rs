//! The serial kept levels' interpolation across ranks: a dropped unknown interpolates from the
//! kept unknowns near it with least-squares weights that reproduce linear fields, chosen by the
//! serial rule (`multigrid::lsq::choose_donors`): its kept strong neighbours, then, while they
//! fit no bounded linear field, the kept unknowns within two rings of K's graph, nearest first,
//! one at a time. Where no bounded fit exists the row keeps the operator's weights
//! (`interpolate`).
//!
//! The two rings reach past a rank's halo, so each rank fetches the graph rows of its halo
//! entries from their owners and lays the unknowns they name out with their own exchange
//! lists, over which the kept state and the positions come from the owners. The candidates are
//! named by global id, their ties in distance broken by it and each donor set fitted in
//! ascending global id, so a row depends on the operator and the positions alone: the same on
//! every partition and rank count.

use super::along_lines;
use super::galerkin::{halo_rows, GlobalRow};
use super::interpolate::weights;
use super::mover::Mover;
use super::select::{select, strong, OnLines, DROPPED, KEPT};
use super::OwnedRows;
use crate::distributed::agreement::agree;
use crate::distributed::dist_mesh::halo_lists;
use crate::distributed::error::DistError;
use crate::distributed::halo::HaloLayout;
use crate::multigrid::layout::Layout;
use crate::multigrid::lines::Lines;
use crate::multigrid::lsq::{bounded, choose_donors, fit_offsets};
use std::collections::HashMap;

/// The positions of a level's local entries: a kept unknown keeps its fine vertex's position,
/// as on the serial kept levels.
pub(crate) struct Positions {
    /// Coordinates per local entry (owned first, then the halo, the owners' values).
    pub(crate) coords: Vec<[f64; 3]>,
    /// The space's dimension: the linear fields the rows reproduce.
    pub(crate) dim: usize,
}

impl Positions {
    /// The positions of `n` local entries from interleaved coordinates, `dim` per entry.
    pub(crate) fn from_interleaved(points: &[f64], dim: usize, n: usize) -> Positions {
        let coords = (0..n)
            .map(|v| {
                let mut p = [0.0; 3];
                p[..dim].copy_from_slice(&points[v * dim..(v + 1) * dim]);
                p
            })
            .collect();
        Positions { coords, dim }
    }

    /// Makes the halo entries of `halo`'s layout their owners' positions (collective).
    pub(crate) fn refresh(&mut self, halo: &HaloLayout) {
        let mut c = vec![0.0; self.coords.len()];
        for d in 0..self.dim {
            c.iter_mut().zip(&self.coords).for_each(|(c, p)| *c = p[d]);
            halo.refresh(&mut c);
            self.coords.iter_mut().zip(&c).for_each(|(p, &c)| p[d] = c);
        }
    }

    /// The owned entries' positions moved by `mover` onto the ranks of an agglomerated level, in
    /// its order (collective over the mover's ranks); the halo's follow by `refresh`.
    pub(super) fn moved(&self, mover: &Mover) -> Positions {
        let mut coords = vec![[0.0; 3]; mover.len()];
        let (mut mine, mut got) = (vec![0.0; mover.count()], vec![0.0; mover.len()]);
        for d in 0..self.dim {
            mine.iter_mut().zip(&self.coords).for_each(|(m, p)| *m = p[d]);
            mover.gather(&mine, &mut got);
            coords.iter_mut().zip(&got).for_each(|(p, &g)| p[d] = g);
        }
        Positions { coords, dim: self.dim }
    }
}

/// The P rows of `m`'s owned unknowns in global terms (coarse global id, its owner, weight): a
/// kept unknown (`select`) its own value, the dropped ones by the serial donor rule from the
/// positions `at` of `m`'s local entries, or with `lines` (the level's, given on every rank or
/// on none) along them where they can (`along_lines`); couplings are strong at `theta`
/// (`select::strong`), the entries `first` prescribes are kept first and the unknowns on
/// `on_lines` kept along their lines (`select::select`) (collective).
pub(super) fn interpolation(
    m: &OwnedRows,
    at: &Positions,
    lines: Option<&Lines>,
    (theta, first, on_lines): (f64, Option<&[u8]>, Option<OnLines>),
) -> Result<Vec<GlobalRow>, DistError> {
    let (owned, me) = (m.halo.owned(), m.halo.comm().rank());
    let owners = m.halo.owner_ranks();
    let strong = strong(m, theta);
    let state = select(m, &strong, first, on_lines);
    let direct = weights(m, &strong, &state);

    // K's graph in global terms: the owned rows, then the halo's from their owners.
    let mut graph: Vec<GlobalRow> = (0..owned)
        .map(|i| m.a.row(i).0.iter().map(|&j| (m.gids[j as usize], owners[j as usize], 0.0)).collect())
        .collect();
    graph.extend(halo_rows(&m.halo, &graph));

    // The second ring's unknowns beyond the halo, with exchange lists of their own: those the
    // graph rows of a dropped unknown's neighbours name that are not local.
    let local: HashMap<u64, u32> = m.gids.iter().zip(0u32..).map(|(&g, i)| (g, i)).collect();
    let dropped = || (0..owned).filter(|&i| state[i] == DROPPED);
    let mut reached = vec![false; m.halo.len()];
    dropped().flat_map(|i| m.a.row(i).0).for_each(|&j| reached[j as usize] = true);
    let mut beyond: Vec<(usize, u64)> = (0..m.halo.len())
        .filter(|&j| reached[j])
        .flat_map(|j| &graph[j])
        .filter(|e| !local.contains_key(&e.0))
        .map(|e| (e.1, e.0))
        .collect();
    beyond.sort_unstable();
    beyond.dedup();
    let mut halo: Vec<(usize, u64)> = (owned..m.halo.len()).map(|j| (owners[j], m.gids[j])).chain(beyond).collect();
    halo.sort_unstable();
    let gids: Vec<u64> = m.gids[..owned].iter().copied().chain(halo.iter().map(|e| e.1)).collect();
    let ring_owners: Vec<usize> = vec![me; owned].into_iter().chain(halo.iter().map(|e| e.0)).collect();
    let order: Vec<u32> = (0..gids.len() as u32).collect();
    let (rings, error) = halo_lists(m.halo.shared_comm(), &order, &gids, &ring_owners);
    agree(m.halo.comm(), error.map_or(Ok(()), Err))?;
    let mut kept = vec![0u8; gids.len()];
    kept[..owned].iter_mut().zip(&state).for_each(|(k, &s)| *k = u8::from(s == KEPT));
    let mut coords = Positions { coords: vec![[0.0; 3]; gids.len()], dim: at.dim };
    coords.coords[..owned].copy_from_slice(&at.coords[..owned]);
    rings.refresh(&mut kept);
    coords.refresh(&rings);
    // The candidates are (global id, entry of the rings' layout): ordered by global id alone, as
    // the ids are unique, and read from the layout without a lookup by id.
    let index: HashMap<u64, u32> = gids.iter().zip(0u32..).map(|(&g, i)| (g, i)).collect();
    let entry = |g: u64| index.get(&g).map(|&k| (g, k));
    let of_local: Vec<Option<(u64, u32)>> = m.gids.iter().map(|&g| entry(g)).collect();
    let graph: Vec<Vec<(u64, u32)>> = (0..m.halo.len())
        .map(|j| match reached[j] {
            true => graph[j].iter().filter_map(|e| entry(e.0)).collect(),
            false => Vec::new(),
        })
        .collect();
    let is_kept = |k: u32| kept.get(k as usize) == Some(&1);
    let along = lines
        .map(|l| along_lines::rows(m, &at.coords, l, |v| of_local[v].is_some_and(|c| is_kept(c.1))))
        .unwrap_or_default();

    // The row that last met each entry of the rings' layout as a far candidate.
    let mut seen = vec![usize::MAX; gids.len()];
    let rows = (0..owned)
        .map(|i| {
            let row = || direct[i].iter().map(|&(j, w)| (m.gids[j as usize], owners[j as usize], w)).collect();
            if state[i] != DROPPED {
                return row();
            }
            if let Some(Some(r)) = along.get(i) {
                return r.clone();
            }
            let (gi, xi) = (m.gids[i], at.coords[i]);
            let offset = |(_, k): (u64, u32)| {
                let p = coords.coords[k as usize];
                [p[0] - xi[0], p[1] - xi[1], p[2] - xi[2]]
            };
            // Nearest first, ties by global id.
            let by_distance = |list: Vec<(u64, u32)>| -> Vec<(u64, u32)> {
                let mut keyed: Vec<(f64, (u64, u32))> = list.into_iter().map(|c| (norm2(offset(c)), c)).collect();
                keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                keyed.into_iter().map(|(_, c)| c).collect()
            };
            let near = by_distance(
                strong[i]
                    .iter()
                    .filter(|&&j| state[j as usize] == KEPT)
                    .filter_map(|&j| of_local[j as usize])
                    .collect(),
            );
            // Each candidate once (marked with the row), in any order: `by_distance` orders them.
            let far = |near: &[(u64, u32)]| {
                let cols = m.a.row(i).0;
                let mut far: Vec<(u64, u32)> = Vec::new();
                let reach = cols.iter().filter_map(|&j| of_local[j as usize]);
                for c in reach.chain(cols.iter().flat_map(|&j| graph[j as usize].iter().copied())) {
                    let first = std::mem::replace(&mut seen[c.1 as usize], i) != i;
                    if first && c.0 != gi && is_kept(c.1) && !near.contains(&c) {
                        far.push(c);
                    }
                }
                by_distance(far)
            };
            let fit = |set: &[(u64, u32)]| {
                let rel: Vec<[f64; 3]> = set.iter().map(|&c| offset(c)).collect();
                fit_offsets(&rel, at.dim)
            };
            match choose_donors(near, far, at.dim, false, false, fit) {
                (donors, Some(w)) if bounded(&w) => {
                    donors.iter().zip(w).map(|(&(g, k), w)| (g, ring_owners[k as usize], w)).collect()
                }
                _ => row(),
            }
        })
        .collect();
    Ok(rows)
}

fn norm2(r: [f64; 3]) -> f64 {
    r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
}
