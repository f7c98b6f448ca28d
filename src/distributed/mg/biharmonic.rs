//! The biharmonic's owned rows assembled across ranks, the finest level of its distributed
//! multigrid. The solve applies A = K V⁻¹ K in two passes with an exchange of S between them;
//! the multigrid needs A's rows as a matrix:
//!
//!   A_ij = Σ_k K_ik (1/V_k) K_kj  over k without Z (S held at zero there),
//!
//! for i and j without P (prescribed unknowns are out of the solve), the serial operator's
//! entries. Row i of K is complete on i's owner, but row k of a halo vertex is not (its cells
//! beyond the ghost layer are elsewhere), so each owner sends its rows (1/V_k) K_k· of the
//! vertices other ranks hold in their halo, in global ids. A row of A then reaches two rings of
//! vertices: its columns get a halo of their own (owned entries as the mesh's, the others
//! grouped by owner and ordered by global id), with exchange lists made as the mesh's are.

use super::along_lines;
use super::donors::{interpolation, Positions};
use super::galerkin::{halo_rows, product, GlobalRow};
use super::lines::{kept_segments, smoothed};
use super::select::OnLines;
use super::{any_lines, OwnedRows};
use crate::bc::{P, Z};
use crate::distributed::agreement::agree;
use crate::distributed::dist_mesh::halo_lists;
use crate::distributed::error::{DistError, DistErrorKind};
use crate::distributed::halo::HaloLayout;
use crate::multigrid::layout::Layout;
use crate::multigrid::lines::Lines;
use crate::sparse::CsrMatrix;
use std::collections::HashMap;
use std::sync::Arc;

/// The owned rows of one component's biharmonic A on a rank's part of the mesh (collective):
/// `k` is the rank's K over its local vertices (owned rows complete), `inv_v` 1/V on every local
/// vertex (the owners' values), `flags` the component's flags (the owned ones read), `gids` the
/// global id of each local vertex and `halo` the mesh's layout; `extra` (owner, global id) are
/// unknowns of other ranks the columns include besides those A reaches (a prolongation's).
pub(crate) fn biharmonic_rows(
    k: &CsrMatrix,
    inv_v: &[f64],
    flags: &[u8],
    gids: &[u64],
    halo: &Arc<HaloLayout>,
    extra: &[(usize, u64)],
) -> Result<OwnedRows, DistError> {
    let comm = halo.shared_comm().clone();
    let me = comm.rank();
    let owned = halo.owned();
    let owners = halo.owner_ranks();
    // P and Z of every local vertex as its owner sets them.
    let mut f = flags.to_vec();
    halo.refresh(&mut f);
    let free = |j: usize| f[j] & P == 0;
    let mut rows: Vec<GlobalRow> = (0..owned)
        .map(|v| {
            if f[v] & Z != 0 {
                return Vec::new();
            }
            let (cols, vals) = k.row(v);
            cols.iter()
                .zip(vals)
                .filter(|(&j, _)| free(j as usize))
                .map(|(&j, &w)| (gids[j as usize], owners[j as usize], w * inv_v[v]))
                .collect()
        })
        .collect();
    rows.extend(halo_rows(halo, &rows));

    // The columns: the owned vertices in the mesh's order, then every other vertex a free owned
    // row reaches through K twice, by (owner, global id).
    let equations: Vec<usize> = (0..owned).filter(|&i| free(i)).collect();
    let mut needed = vec![false; rows.len()];
    equations.iter().flat_map(|&i| k.row(i).0).for_each(|&m| needed[m as usize] = true);
    let mut reached: Vec<(usize, u64)> = extra.to_vec();
    for (row, _) in rows.iter().zip(&needed).filter(|(_, &n)| n) {
        reached.extend(row.iter().filter(|e| e.1 != me).map(|e| (e.1, e.0)));
    }
    reached.sort_unstable();
    reached.dedup();
    let col_gids: Vec<u64> = gids[..owned].iter().copied().chain(reached.iter().map(|e| e.1)).collect();
    let col_owners: Vec<usize> = vec![me; owned].into_iter().chain(reached.iter().map(|e| e.0)).collect();
    let index: HashMap<u64, u32> = col_gids.iter().zip(0u32..).map(|(&g, i)| (g, i)).collect();
    let n = col_gids.len();
    // A column not in the layout cannot occur (the layout is made from these rows); it is
    // remembered rather than returned, so every rank still reaches the exchanges below.
    let mut missing = None;
    let local: Vec<Vec<(u32, f64)>> = rows
        .iter()
        .zip(&needed)
        .map(|(row, &n)| {
            row.iter()
                .take(if n { row.len() } else { 0 })
                .filter_map(|&(g, _, w)| match index.get(&g) {
                    Some(&j) => Some((j, w)),
                    None => {
                        missing.get_or_insert(g);
                        None
                    }
                })
                .collect()
        })
        .collect();
    let a = assemble(k, &local, &equations, n, owned).ok_or_else(|| too_large(me, owned));
    let order: Vec<u32> = (0..n as u32).collect();
    let (layout, error) = halo_lists(&comm, &order, &col_gids, &col_owners);
    let checked = match (missing, error) {
        (Some(g), _) => Err(DistError::new(me, DistErrorKind::Solve, format!("rank {me} lacks global id {g}"))),
        (None, Some(e)) => Err(e),
        (None, None) => a,
    };
    let a = agree(&comm, checked)?;
    Ok(OwnedRows { a, gids: col_gids, halo: Arc::new(layout) })
}

/// The rows of A for the `equations` (free owned vertices): row i is Σ_m K_im rows[m], summed in
/// the order of K's row and each of `rows` (a fixed order, so the result is bitwise the same on
/// every run); n columns, rows past `owned` and those of prescribed vertices empty. None past the
/// limit of 2³² entries.
fn assemble(k: &CsrMatrix, rows: &[Vec<(u32, f64)>], equations: &[usize], n: usize, owned: usize) -> Option<CsrMatrix> {
    let mut acc = vec![0.0f64; n];
    let mut seen = vec![false; n];
    let mut touched: Vec<u32> = Vec::new();
    let mut row_ptr = vec![0u32; n + 1];
    let (mut cols, mut vals) = (Vec::new(), Vec::new());
    let mut next = equations.iter().peekable();
    for i in 0..n {
        if i < owned && next.peek() == Some(&&i) {
            next.next();
            let (ks, kv) = k.row(i);
            for (&m, &kim) in ks.iter().zip(kv) {
                for &(j, w) in &rows[m as usize] {
                    if !seen[j as usize] {
                        seen[j as usize] = true;
                        touched.push(j);
                    }
                    acc[j as usize] += kim * w;
                }
            }
            touched.sort_unstable();
            for &j in &touched {
                cols.push(j);
                vals.push(acc[j as usize]);
                acc[j as usize] = 0.0;
                seen[j as usize] = false;
            }
            touched.clear();
        }
        row_ptr[i + 1] = u32::try_from(cols.len()).ok()?;
    }
    Some(CsrMatrix { nrows: n, ncols: n, row_ptr, cols, vals })
}

/// A rank's biharmonic rows past the sparse matrices' limit of 2³² entries.
fn too_large(me: usize, owned: usize) -> DistError {
    let msg = format!("the biharmonic's rows of {owned} owned vertices hold 2^32 entries or more: use more ranks");
    DistError::new(me, DistErrorKind::Solve, msg)
}

/// What the biharmonic's coarse levels are made from: the rows of K on a level (its owned rows
/// over its local columns) of every unknown that carries S, the free ones and the prescribed
/// ones without Z, as the serial kept levels keep them; each local entry's flags P and Z, its
/// lumped mass V (the owners' values) and its position, which the interpolation's least-squares
/// rows are fitted to.
pub(crate) struct Guide {
    pub(crate) k: OwnedRows,
    pub(crate) flags: Vec<u8>,
    pub(crate) mass: Vec<f64>,
    pub(crate) at: Positions,
}

/// Which coarse operator `coarsen` forms.
#[derive(Clone, Copy)]
pub(super) enum Product<'a> {
    /// A_c = K_c V_c⁻¹ K_c.
    Guided,
    /// The Galerkin product A_c = Pᵀ A P.
    Galerkin,
    /// The Galerkin product where the coarse level keeps a line of these segments (the level's,
    /// `lines::kept_segments`) on some rank, else K_c V_c⁻¹ K_c.
    GalerkinWhereLinesKept(&'a Lines),
}

/// The next coarser level of the biharmonic, as the serial kept levels are made: kept unknowns
/// from K's strong couplings and the interpolation P by the serial donor rule (`donors`), both
/// over the guide's unknowns (those that carry S, prescribed or not; in 2D and with `lines` the
/// prescribed ones kept first, `select::select`), K_c = Pᵀ K P and V_c = P₊ᵀ V (the positive
/// weights, so V_c stays positive), and A_c = K_c V_c⁻¹ K_c assembled across ranks over the
/// coarse unknowns without P, S summed over those without Z (a kept CLAMPED vertex carries it, as
/// serially), with the columns of P's owned rows in its layout, or by `product` the Galerkin
/// product A_c = Pᵀ A P of `fine`'s own rows (under wall layers: docs/DESIGN.md §5, "Wall layers
/// across ranks"). Returns A_c, P (`fine`'s local entries × A_c's; the rows of `fine`'s
/// prescribed entries empty), the coarse guide and whether A_c is the Galerkin product; None when
/// no rank keeps an unknown (collective). With `lines` (the level's lines across wall layers,
/// given on every rank or on none: the hierarchies that interpolate along them) a dropped unknown
/// on a line interpolates along it, cubic in the distance along the line, where the line
/// gives its row (`along_lines`), and in 3D the lines of a wall's layers are coarsened along
/// themselves (`select::OnLines`, the serial rule). Couplings of K are strong at `theta`
/// (`select::strong`).
pub(super) fn coarsen(
    fine: &OwnedRows,
    guide: &Guide,
    product_of: Product,
    lines: Option<&Lines>,
    theta: f64,
) -> Result<Option<(OwnedRows, CsrMatrix, Guide, bool)>, DistError> {
    let me = guide.k.halo.comm().rank();
    let first = (guide.at.dim == 2 || lines.is_some()).then_some(&guide.flags[..]);
    let marks = lines
        .filter(|_| guide.at.dim == 3)
        .map(|l| along_lines::marks(&guide.k, &guide.at.coords, l, |i| guide.flags[i] & P != 0));
    let on = marks.as_deref().map(|marks| OnLines { marks });
    let rows = interpolation(&guide.k, &guide.at, lines, (theta, first, on))?;
    let Some((k, to_coarse)) = product(&guide.k, &rows)? else {
        return Ok(None);
    };
    let mut mass = vec![0.0; k.halo.len()];
    for i in 0..guide.k.halo.owned() {
        let (cols, w) = to_coarse.row(i);
        cols.iter().zip(w).for_each(|(&c, &w)| mass[c as usize] += w.max(0.0) * guide.mass[i]);
    }
    k.halo.add_to_owners(&mut mass);
    k.halo.refresh(&mut mass);
    let (at, flags) = coarse_entries(&guide.k, (&guide.at, Some(&guide.flags)), &k)?;
    let galerkin = match product_of {
        Product::Guided => false,
        Product::Galerkin => true,
        // K_c's owned entries are the coarse level's (`fine`'s kept owned unknowns in one order).
        Product::GalerkinWhereLinesKept(segments) => {
            any_lines(k.halo.comm(), &smoothed(&kept_segments(segments, &fine.gids, &k)))
        }
    };
    if galerkin {
        // The rows of P are `fine`'s owned unknowns' too (A and K share their owned entries in
        // one order), so the product fetches P's halo rows over A's wider halo.
        return Ok(product(fine, &rows)?
            .map(|(a, prolong)| (a, unknowns_only(prolong, fine), Guide { k, flags, mass, at }, true)));
    }
    let inv_v: Vec<f64> = mass.iter().map(|&v| 1.0 / v).collect();
    let mut extra: Vec<(usize, u64)> = rows.iter().flatten().filter(|e| e.1 != me).map(|e| (e.1, e.0)).collect();
    extra.sort_unstable();
    extra.dedup();
    let a = biharmonic_rows(&k.a, &inv_v, &flags, &k.gids, &k.halo, &extra)?;
    let index: HashMap<u64, u32> = a.gids.iter().zip(0u32..).map(|(&g, i)| (g, i)).collect();
    // Every column of P is in A_c's layout (`extra`), so the lookups find them all.
    let index = &index;
    let prolong: Vec<(u32, u32, f64)> = (0u32..)
        .zip(&rows)
        .flat_map(|(i, row)| row.iter().filter_map(move |&(g, _, w)| Some((i, *index.get(&g)?, w))))
        .collect();
    let prolong = CsrMatrix::from_triplets(fine.halo.len(), a.halo.len(), prolong);
    Ok(Some((a, unknowns_only(prolong, fine), Guide { k, flags, mass, at }, false)))
}

/// `p` without the rows of `fine`'s prescribed entries (its empty rows): the guide interpolates
/// them for K_c, but the cycle neither corrects them nor restricts from them.
fn unknowns_only(mut p: CsrMatrix, fine: &OwnedRows) -> CsrMatrix {
    let owned = fine.halo.owned();
    let keep = |i: usize| i < owned && !fine.a.row(i).0.is_empty();
    let (mut cols, mut vals, mut row_ptr) = (Vec::new(), Vec::new(), vec![0u32]);
    for i in 0..p.nrows {
        if keep(i) {
            let (c, v) = p.row(i);
            cols.extend_from_slice(c);
            vals.extend_from_slice(v);
        }
        // At most p's entries, whose count fits its u32 row pointers.
        row_ptr.push(cols.len() as u32);
    }
    (p.cols, p.vals, p.row_ptr) = (cols, vals, row_ptr);
    p
}

/// The positions of the coarse level `coarse`'s local entries: each its fine unknown's (the one
/// of the same global id, owned by the same rank), the halo's from their owners (collective).
pub(super) fn coarse_positions(fine: &OwnedRows, at: &Positions, coarse: &OwnedRows) -> Result<Positions, DistError> {
    Ok(coarse_entries(fine, (at, None), coarse)?.0)
}

/// The positions and the flags of the coarse level `coarse`'s local entries, each its fine
/// unknown's (see `coarse_positions`; `flags` over `fine`'s local entries, if given)
/// (collective).
fn coarse_entries(
    fine: &OwnedRows,
    (at, flags): (&Positions, Option<&[u8]>),
    coarse: &OwnedRows,
) -> Result<(Positions, Vec<u8>), DistError> {
    let me = fine.halo.comm().rank();
    let index: HashMap<u64, usize> = fine.gids[..fine.halo.owned()].iter().zip(0..).map(|(&g, i)| (g, i)).collect();
    let n = coarse.halo.len();
    let mut coords = vec![[0.0; 3]; n];
    let mut coarse_flags = vec![0u8; if flags.is_some() { n } else { 0 }];
    // A coarse unknown owned here is a fine unknown owned here; one that is not cannot occur,
    // and is reported after the exchange, which every rank reaches.
    let mut missing = None;
    for (c, &g) in coarse.gids[..coarse.halo.owned()].iter().enumerate() {
        match index.get(&g) {
            Some(&i) => {
                coords[c] = at.coords[i];
                if let Some(f) = flags {
                    coarse_flags[c] = f[i];
                }
            }
            None => {
                missing.get_or_insert(g);
            }
        }
    }
    let mut coarse_at = Positions { coords, dim: at.dim };
    coarse_at.refresh(&coarse.halo);
    if flags.is_some() {
        coarse.halo.refresh(&mut coarse_flags);
    }
    let checked = match missing {
        Some(g) => {
            Err(DistError::new(me, DistErrorKind::Solve, format!("rank {me} has no position for global id {g}")))
        }
        None => Ok((coarse_at, coarse_flags)),
    };
    agree(coarse.halo.comm(), checked)
}
