//! Interpolation weights: for each fine unknown, the smallest weights on nearby coarse unknowns
//! that reproduce linear fields exactly along the unknown's feature.
//!
//! With donors x_j around x_v, offsets r_j = x_j − x_v in the feature's axes (all of space
//! inside, the tangent plane on a wall, the line on a crease), the weights minimise
//! Σ w_j² / ω_j subject to Σ w_j = 1 and Σ w_j r_j = 0, with ω_j = (h / |r_j|)² so near donors
//! weigh more: w = Ω Aᵀ (A Ω Aᵀ)⁻¹ e₀ with A's rows 1 and the offsets. Inside a donor simplex
//! this is the barycentric interpolation; more donors spread the weights. Donors are the kept
//! neighbours first, then kept neighbours of neighbours by distance, added one at a time until
//! the system is well conditioned and the weights are bounded (Σ|w| ≤ 2, no extrapolation far
//! outside the donors). Under wall layers (`Donors::Fewest`) a row starts from as few of its
//! nearest strong kept neighbours as its feature needs, adding the next nearest candidate one
//! at a time up to 12 donors, the one with the smallest Σ|w| when none is bounded (in 3D up to
//! 24 when that one extrapolates beyond Σ|w| = 3): the Galerkin
//! levels' stencils grow with P's rows, and with every strong neighbour the deep levels under
//! the layers turned dense (docs/DESIGN.md §5, "Wall layers").

use super::Features;
use crate::multigrid::level::Level;
use crate::sparse::{offset, CsrMatrix};
use rayon::prelude::*;

/// Rows per parallel task.
const CHUNK: usize = 2048;
/// Most donors of a row with `Donors::Fewest` whose fit of its nearest candidates is bounded
/// or extrapolates little (`EXTRAPOLATES`).
const FEWEST_MAX: usize = 12;
/// Most donors of a row with `Donors::Fewest` whose `FEWEST_MAX` nearest candidates extrapolate
/// beyond `EXTRAPOLATES` whatever their prefix: at an O-grid's block edges and on the deep
/// levels below wall layers such rows are bounded from more candidates.
const FEWEST_WIDE: usize = 24;
/// Σ|w| of the least-spread fit of `FEWEST_MAX` candidates above which a row searches up to
/// `FEWEST_WIDE`.
const EXTRAPOLATES: f64 = 3.0;
/// Most donors whose offsets a fit holds on the stack.
const FIT_ON_STACK: usize = 32;
/// Largest Σ|w| accepted while more donors remain.
const MAX_ABS_SUM: f64 = 2.0;

/// Which donors a row of P starts from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Donors {
    /// Every strongly coupled kept neighbour: the weights spread over them all.
    Strong,
    /// The nearest strongly coupled kept neighbours, as few as fit the feature's linear fields
    /// with bounded weights. Rows of a few donors keep the Galerkin levels sparse.
    Fewest,
    /// `Fewest`, but an unknown on a line of the fine level interpolates along its line
    /// (`along_lines`) where that line has kept unknowns on both sides of it.
    AlongLines,
}

/// What a call of `prolongation` is given beyond the level: the level's strong couplings
/// (`lsq::strong_couplings`) when the selection found them, and with `keep` = (P₀, redo) the rows
/// to keep, P₀'s rows without `redo`.
#[derive(Clone, Copy)]
pub(super) struct Given<'a> {
    pub(super) strong: Option<&'a [f64]>,
    pub(super) keep: Option<(&'a CsrMatrix, &'a [bool])>,
}

impl Given<'_> {
    /// Nothing given: every row is chosen, its strong couplings found as it is.
    pub(super) const NONE: Given<'static> = Given { strong: None, keep: None };
}

/// P: fine unknowns × the coarse unknowns `kept` (fine numbering, ascending), donors and weights
/// chosen at the current positions (a moved mesh may need other donors: a set that lay in the
/// plane of its unknown, across a thin layer, no longer does). With `given.keep` = (P₀, redo),
/// the rows without `redo` are P₀'s rows as they are, the others chosen anew.
pub(super) fn prolongation(fine: &Level, f: &Features, kept: &[u32], donors: Donors, given: Given) -> CsrMatrix {
    let Given { strong, keep } = given;
    let points = fine.unknown_points();
    let dim = f.dim();
    let n = fine.n();
    let mut coarse_of = vec![u32::MAX; n];
    for (c, &d) in kept.iter().enumerate() {
        coarse_of[d as usize] = c as u32;
    }
    let kept_nbrs = KeptNeighbours::new(&fine.op.k, &coarse_of);
    let ctx = Context { k: &fine.op.k, f, points: &points, dim, coarse_of: &coarse_of, kept_nbrs: &kept_nbrs, donors, strong };
    let along = if donors == Donors::AlongLines {
        super::along_lines::rows(fine.lines.lines(), &fine.op.k, f, &points, &coarse_of)
    } else {
        Vec::new()
    };
    let chunks: Vec<(Vec<u32>, Vec<u32>, Vec<f64>)> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map_init(|| (Rings::new(n), Vec::new(), super::Shorts::default()), |(rings, near, shorts), c| {
            let (mut lens, mut cols, mut vals) = (Vec::new(), Vec::new(), Vec::new());
            let mut row = Vec::new();
            let rows = c * CHUNK..((c + 1) * CHUNK).min(n);
            for (v, &cv) in coarse_of[rows.clone()].iter().enumerate().map(|(k, cv)| (rows.start + k, cv)) {
                row.clear();
                if let Some((old, _)) = keep.filter(|(_, redo)| !redo[v]) {
                    let (c, w) = old.row(v);
                    row.extend(c.iter().copied().zip(w.iter().copied()));
                } else if cv != u32::MAX {
                    row.push((cv, 1.0));
                } else if let Some(r) = along.get(v).and_then(|r| r.as_ref()) {
                    row.extend_from_slice(r);
                } else {
                    ctx.row(v, ctx.choose(v, rings, near, shorts), &mut row);
                }
                lens.push(row.len() as u32);
                for &(c, w) in &row {
                    cols.push(c);
                    vals.push(w);
                }
            }
            (lens, cols, vals)
        })
        .collect();
    let mut row_ptr = Vec::with_capacity(n + 1);
    row_ptr.push(0);
    let (mut cols, mut vals) = (Vec::new(), Vec::new());
    for (lens, c, v) in chunks {
        for l in lens {
            row_ptr.push(row_ptr.last().expect("starts at 0") + l);
        }
        cols.extend(c);
        vals.extend(v);
    }
    debug_assert_eq!(offset(cols.len()), *row_ptr.last().expect("n + 1 entries"));
    CsrMatrix { nrows: n, ncols: kept.len(), row_ptr, cols, vals }
}

struct Context<'a> {
    k: &'a CsrMatrix,
    f: &'a Features,
    points: &'a [f64],
    dim: usize,
    coarse_of: &'a [u32],
    kept_nbrs: &'a KeptNeighbours,
    donors: Donors,
    /// The level's strong couplings (`lsq::strong_couplings`), when given.
    strong: Option<&'a [f64]>,
}

/// Per fine unknown, its kept neighbours in K's graph (itself among them when it is kept): the
/// second ring of a row's far donors walks these instead of whole rows of K.
struct KeptNeighbours {
    ptr: Vec<usize>,
    cols: Vec<u32>,
}

impl KeptNeighbours {
    fn new(k: &CsrMatrix, coarse_of: &[u32]) -> Self {
        let mut ptr = Vec::with_capacity(k.nrows + 1);
        ptr.push(0);
        let mut cols = Vec::new();
        for i in 0..k.nrows {
            cols.extend(k.row(i).0.iter().copied().filter(|&u| coarse_of[u as usize] != u32::MAX));
            ptr.push(cols.len());
        }
        KeptNeighbours { ptr, cols }
    }

    fn of(&self, w: usize) -> &[u32] {
        &self.cols[self.ptr[w]..self.ptr[w + 1]]
    }
}

impl Context<'_> {
    fn rel(&self, v: usize, u: usize) -> [f64; 3] {
        let d = self.dim;
        self.f.relative(v, u, &self.points[v * d..(v + 1) * d], &self.points[u * d..(u + 1) * d])
    }

    /// The donors of fine unknown `v` (fine numbering), ascending, and their fitted weights (None:
    /// no fit exists): its strongly coupled kept neighbours (`strong`) nearest first, then (only
    /// when those do not determine a bounded fit) its other kept neighbours and kept neighbours
    /// of neighbours, nearest first, one at a time (`choose_donors`). `found` and `shorts` are
    /// buffers for `strong`, reused from row to row.
    fn choose(&self, v: usize, rings: &mut Rings, found: &mut Vec<f64>, shorts: &mut super::Shorts) -> (Vec<u32>, Option<Vec<f64>>) {
        let is_donor = |u: u32| self.coarse_of[u as usize] != u32::MAX && self.f.donor_ok(v, u as usize);
        let key = |u: u32| (norm2(self.rel(v, u as usize)), u);
        let row = self.k.row(v).0;
        let d2 = match self.strong {
            Some(s) => &s[self.k.row_ptr[v] as usize..self.k.row_ptr[v + 1] as usize],
            None => {
                found.resize(row.len(), 0.0);
                super::strong(self.k, self.f, v, |u| self.rel(v, u), found, shorts);
                &found[..]
            }
        };
        // Each strong neighbour's squared distance is `key`'s.
        let mut near: Vec<(f64, u32)> =
            row.iter().zip(d2).filter(|&(&u, d)| !d.is_nan() && is_donor(u)).map(|(&u, &d)| (d, u)).collect();
        let near = nearest(&mut near, usize::MAX);
        let fewest = self.donors != Donors::Strong;
        let far = |near: &[u32]| {
            // The kept unknowns within two rings, each once (`Rings`) before the costlier
            // checks: on dense Galerkin levels a row's two rings reach most unknowns many times
            // over. A row of the fewest donors takes only as many of them as it can hold.
            let ring2 = row.iter().flat_map(|&w| self.kept_nbrs.of(w as usize).iter().copied());
            let kept = rings.once(v, self.kept_nbrs.of(v).iter().copied().chain(ring2));
            let mut far: Vec<(f64, u32)> =
                kept.iter().copied().filter(|&u| u as usize != v && is_donor(u) && !near.contains(&u)).map(key).collect();
            let most = if self.dim == 3 { FEWEST_WIDE } else { FEWEST_MAX };
            nearest(&mut far, if fewest { most.saturating_sub(near.len()) } else { usize::MAX })
        };
        choose_donors(near, far, self.f.feature_dim(v), fewest, self.dim == 3, |set| self.fit(v, set))
    }

    /// Row `v` of P from `donors` (fine numbering, ascending) and their `weights`, or the
    /// nearest donor alone when no fit exists (constants are still reproduced).
    fn row(&self, v: usize, (donors, weights): (Vec<u32>, Option<Vec<f64>>), row: &mut Vec<(u32, f64)>) {
        match weights {
            Some(w) => row.extend(donors.iter().zip(w).map(|(&u, w)| (self.coarse_of[u as usize], w))),
            None => {
                let near = donors
                    .iter()
                    .copied()
                    .min_by(|&a, &b| norm2(self.rel(v, a as usize)).total_cmp(&norm2(self.rel(v, b as usize))))
                    .expect("every dropped unknown has a kept neighbour");
                row.push((self.coarse_of[near as usize], 1.0));
            }
        }
    }

    /// The weights of `donors` for `v`, or None when they do not determine a linear field
    /// along `v`'s feature.
    fn fit(&self, v: usize, donors: &[u32]) -> Option<Vec<f64>> {
        // The offsets on the stack for the usual few donors: one fit per dropped unknown.
        let mut on_stack = [[0.0; 3]; FIT_ON_STACK];
        let mut on_heap = Vec::new();
        let rel = match on_stack.get_mut(..donors.len()) {
            Some(r) => r,
            None => {
                on_heap.resize(donors.len(), [0.0; 3]);
                &mut on_heap[..]
            }
        };
        rel.iter_mut().zip(donors).for_each(|(r, &u)| *r = self.rel(v, u as usize));
        fit_offsets(rel, self.f.feature_dim(v))
    }
}

/// The `most` first of `keyed` (squared distance, unknown) by distance, ties by index: the
/// unknowns, nearest first. Distinct unknowns make the order total, so selecting the `most`
/// nearest before sorting them gives the prefix of the whole list sorted.
fn nearest(keyed: &mut [(f64, u32)], most: usize) -> Vec<u32> {
    let by = |a: &(f64, u32), b: &(f64, u32)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
    let keyed = if most < keyed.len() {
        if most == 0 {
            return Vec::new();
        }
        keyed.select_nth_unstable_by(most - 1, by);
        &mut keyed[..most]
    } else {
        keyed
    };
    keyed.sort_unstable_by(by);
    keyed.iter().map(|&(_, u)| u).collect()
}

/// Marks of the unknowns a row's two rings have reached: each unknown is taken once per row
/// without sorting the rings (a row's stamp is its unknown + 1, so no mark is ever cleared).
struct Rings {
    stamp: Vec<u32>,
    found: Vec<u32>,
}

impl Rings {
    fn new(n: usize) -> Self {
        Rings { stamp: vec![0; n], found: Vec::new() }
    }

    /// The distinct unknowns of `reached` for row `v`, in order of first appearance.
    fn once(&mut self, v: usize, reached: impl Iterator<Item = u32>) -> &[u32] {
        let mark = v as u32 + 1;
        self.found.clear();
        for u in reached {
            let s = &mut self.stamp[u as usize];
            if *s != mark {
                *s = mark;
                self.found.push(u);
            }
        }
        &self.found
    }
}

/// The donors of an unknown and their weights: its candidates `near` (its strongly coupled kept
/// neighbours), nearest first, then, only when no bounded fit exists among them, `far(near)`
/// (its other kept unknowns within two rings of K's graph), nearest first, one at a time; ties
/// in distance broken by `T`'s order, and each donor set fitted in ascending order (`fit`: its
/// weights, or None). `fdim` is the dimension of the unknown's feature. With `fewest` a row
/// starts from as few donors as the feature needs and holds `FEWEST_MAX` at most, the one of
/// smallest Σ|w| when none is bounded (with `wide`, in 3D, `FEWEST_WIDE` when that one exceeds
/// `EXTRAPOLATES`: in 2D the boundary-layer cylinder's kept levels lost an iteration with it); without, it starts from all of `near` and, when no
/// prefix is bounded, takes every candidate's fit (None when there is none). The serial levels
/// pass their unknowns' indices; the distributed levels the global ids, so that a row does not
/// depend on how the unknowns are numbered on a rank.
pub(crate) fn choose_donors<T: Copy + Ord>(
    mut cands: Vec<T>,
    far: impl FnOnce(&[T]) -> Vec<T>,
    fdim: usize,
    fewest: bool,
    wide: bool,
    fit: impl Fn(&[T]) -> Option<Vec<f64>>,
) -> (Vec<T>, Option<Vec<f64>>) {
    if fewest {
        // Only the nearest few: a far donor widens the Galerkin levels' stencils more than
        // its weight improves the interpolation.
        cands.truncate(FEWEST_MAX);
    }
    let near = cands.len();
    let start = if fewest { (fdim + 1).min(near) } else { near };
    if let Some(found) = first_bounded(&cands, start.max(1), &fit) {
        return found;
    }
    let more = far(&cands[..near]);
    cands.extend(more);
    let second = (near + 1).max(fdim + 1).min(cands.len());
    if fewest {
        let few = cands.len().min(FEWEST_MAX);
        if let Some(found) = first_bounded(&cands[..few], second.min(few), &fit) {
            return found;
        }
        let (set, w) = least_spread(&cands[..few], fdim + 1, &fit);
        if !wide || w.as_ref().is_some_and(|w| w.iter().map(|w| w.abs()).sum::<f64>() <= EXTRAPOLATES) || cands.len() <= few {
            return (set, w);
        }
        cands.truncate(FEWEST_WIDE);
        return first_bounded(&cands, few + 1, &fit).unwrap_or_else(|| least_spread(&cands, fdim + 1, &fit));
    }
    first_bounded(&cands, second, &fit).unwrap_or_else(|| {
        cands.sort_unstable();
        let w = fit(&cands);
        (cands, w)
    })
}

/// Of the prefixes of `cands` at least `start` long, the one whose fit has the smallest Σ|w|:
/// its donors ascending and their weights; without any fit, `cands` with none (the nearest of
/// them then interpolates alone).
fn least_spread<T: Copy + Ord>(
    cands: &[T],
    start: usize,
    fit: impl Fn(&[T]) -> Option<Vec<f64>>,
) -> (Vec<T>, Option<Vec<f64>>) {
    let mut best: Option<(f64, Vec<T>, Vec<f64>)> = None;
    let mut set = Vec::with_capacity(cands.len());
    for m in start.max(1)..=cands.len() {
        grow_sorted(&mut set, cands, m);
        if let Some(w) = fit(&set) {
            let spread: f64 = w.iter().map(|w| w.abs()).sum();
            if best.as_ref().is_none_or(|b| spread < b.0) {
                best = Some((spread, set.clone(), w));
            }
        }
    }
    match best {
        Some((_, set, w)) => (set, Some(w)),
        None => (cands.to_vec(), None),
    }
}

/// The shortest prefix of `cands`, at least `start` long, whose fit exists with Σ|w| bounded:
/// its donors ascending and their weights.
fn first_bounded<T: Copy + Ord>(
    cands: &[T],
    start: usize,
    fit: impl Fn(&[T]) -> Option<Vec<f64>>,
) -> Option<(Vec<T>, Option<Vec<f64>>)> {
    let mut set = Vec::with_capacity(cands.len());
    for m in start.max(1)..=cands.len() {
        grow_sorted(&mut set, cands, m);
        if let Some(w) = fit(&set) {
            if bounded(&w) {
                return Some((set, Some(w)));
            }
        }
    }
    None
}

/// Makes `set`, which holds the first `set.len()` of `cands` ascending (none, or `m` − 1 of
/// them), hold the first `m` ascending: the prefixes a row tries one after the other, each
/// from the one before by an insertion rather than a copy and a sort.
fn grow_sorted<T: Copy + Ord>(set: &mut Vec<T>, cands: &[T], m: usize) {
    if set.len() + 1 != m {
        set.clear();
        set.extend_from_slice(&cands[..m]);
        set.sort_unstable();
        return;
    }
    let u = cands[m - 1];
    let at = set.partition_point(|&x| x <= u);
    set.insert(at, u);
}

/// Whether weights are bounded (Σ|w| ≤ `MAX_ABS_SUM`): no extrapolation far outside the donors.
pub(crate) fn bounded(w: &[f64]) -> bool {
    w.iter().map(|w| w.abs()).sum::<f64>() <= MAX_ABS_SUM
}

/// The weights of donors at offsets `rel` from an unknown whose feature has dimension `fdim`
/// (the smallest Σ w²/ω that reproduces constants and linear fields along the feature), or
/// None when they do not determine a linear field along it.
pub(crate) fn fit_offsets(rel: &[[f64; 3]], fdim: usize) -> Option<Vec<f64>> {
    let m = rel.len();
    if fdim == 0 || m == 0 {
        return None;
    }
    let h2 = rel.iter().map(|&r| norm2(r)).fold(0.0, f64::max);
    if h2 == 0.0 {
        return None;
    }
    let h = h2.sqrt();
    // The feature's axes from the donors' spread; the fit uses those across which the
    // donors spread (all of them, unless the donors lie in a plane or on a line through
    // `v`, as across a thin layer), and is then checked exact along all of them.
    let (axes, spread) = principal_axes(rel);
    let k = (0..fdim).filter(|&i| spread[i] > SPREAD * spread[0]).count();
    let q = k + 1;
    // Row r of A (1, then the offsets along the axes over h) and the donor's ω, formed where
    // they are used (twice) rather than stored: one small fit per dropped unknown.
    let along = |r: &[f64; 3], ax: &[f64; 3]| (r[0] * ax[0] + r[1] * ax[1] + r[2] * ax[2]) / h;
    let a = |r: &[f64; 3]| {
        let mut c = [1.0, 0.0, 0.0, 0.0];
        for (i, ax) in axes.iter().enumerate().take(k) {
            c[i + 1] = along(r, ax);
        }
        c
    };
    let omega = |r: [f64; 3]| h2 / norm2(r).max(1e-300 * h2);
    let mut mat = [[0.0; 4]; 4];
    for r in rel {
        let (c, w) = (a(r), omega(*r));
        for i in 0..q {
            for j in 0..q {
                mat[i][j] += w * c[i] * c[j];
            }
        }
    }
    let lambda = solve_spd(mat, q)?;
    let w: Vec<f64> = rel.iter().map(|r| (a(r), omega(*r))).map(|(c, w)| w * (0..q).map(|r| c[r] * lambda[r]).sum::<f64>()).collect();
    // Constants and linear fields along every axis of the feature hold to rounding, or the
    // donors were too nearly degenerate (or `v` lies off their plane or line).
    let sum_ok = (w.iter().sum::<f64>() - 1.0).abs() <= 1e-10;
    let linear_ok = axes.iter().take(fdim).all(|ax| rel.iter().zip(&w).map(|(r, w)| w * along(r, ax)).sum::<f64>().abs() <= 1e-10);
    (sum_ok && linear_ok).then_some(w)
}

/// Smallest spread (eigenvalue of the donors' offset moments) across an axis, relative to the
/// largest, for the fit to use that axis: a thousandth of the donors' extent squared.
const SPREAD: f64 = 1e-6;

fn norm2(r: [f64; 3]) -> f64 {
    r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
}

/// The principal axes of the offsets `rel` (unit vectors, by decreasing spread) and their
/// spreads Σ (r·a)²: on a wall the first two span its tangent plane, on a crease the first is
/// its line.
pub(super) fn principal_axes(rel: &[[f64; 3]]) -> ([[f64; 3]; 3], [f64; 3]) {
    principal_axes_of_moments(moments(rel.iter().copied()))
}

/// The offset moments Σ r rᵀ of the offsets `rel` yields, summed in its order.
pub(super) fn moments(rel: impl IntoIterator<Item = [f64; 3]>) -> [[f64; 3]; 3] {
    let mut c = [[0.0; 3]; 3];
    for r in rel {
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] += r[i] * r[j];
            }
        }
    }
    c
}

/// How far above `ratio` the bound of `spans_every_axis` must lie: far more than the rounding of
/// the determinant and of the eigenvalues `principal_axes_of_moments` finds, so that a yes here
/// is a yes there.
const SPAN_MARGIN: f64 = 1.01;

/// Whether the smallest spread (eigenvalue) of the offset moments `c` (symmetric, positive
/// semi-definite) is surely at least `ratio` of the largest, without solving the eigenproblem:
/// λ_min = det / (λ_mid λ_max) ≥ det / (tr / 2)² and λ_max ≤ tr. A no says nothing (the caller
/// then solves it); every spread of moderately shaped cells' neighbours passes.
pub(super) fn spans_every_axis(c: &[[f64; 3]; 3], ratio: f64) -> bool {
    let tr = c[0][0] + c[1][1] + c[2][2];
    let det = c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1]) - c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0])
        + c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]);
    tr > 0.0 && det * 4.0 >= SPAN_MARGIN * ratio * tr * tr * tr
}

/// `principal_axes` of the offset moments `c` (`moments`).
pub(super) fn principal_axes_of_moments(c: [[f64; 3]; 3]) -> ([[f64; 3]; 3], [f64; 3]) {
    let (vals, vecs) = symmetric_eigen3(c);
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&a, &b| vals[b].total_cmp(&vals[a]));
    (idx.map(|i| [vecs[0][i], vecs[1][i], vecs[2][i]]), idx.map(|i| vals[i].max(0.0)))
}

/// Eigenvalues and eigenvectors (columns) of a symmetric 3×3 matrix by cyclic Jacobi rotations:
/// a dozen sweeps at most, exact to rounding, no dependency for one small matrix per unknown.
fn symmetric_eigen3(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..16 {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        let diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if off <= 1e-30 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (ap, aq) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * ap[k] - s * aq[k];
                a[q][k] = s * ap[k] + c * aq[k];
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

/// Solves M λ = e₀ for the leading q×q block of a symmetric positive semi-definite M by
/// Cholesky; None when a pivot falls below 1e-6 of the largest diagonal: the donors' spread
/// across some direction of the feature is under a thousandth of their distance, and the
/// weights would be huge and cancel.
fn solve_spd(m: [[f64; 4]; 4], q: usize) -> Option<[f64; 4]> {
    let scale = (0..q).map(|i| m[i][i]).fold(0.0, f64::max);
    let mut l = [[0.0; 4]; 4];
    for j in 0..q {
        let d = m[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        if d.is_nan() || d <= 1e-6 * scale {
            return None;
        }
        l[j][j] = d.sqrt();
        for i in j + 1..q {
            l[i][j] = (m[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>()) / l[j][j];
        }
    }
    let mut y = [0.0; 4];
    for i in 0..q {
        let b = if i == 0 { 1.0 } else { 0.0 };
        y[i] = (b - (0..i).map(|k| l[i][k] * y[k]).sum::<f64>()) / l[i][i];
    }
    let mut x = [0.0; 4];
    for i in (0..q).rev() {
        x[i] = (y[i] - (i + 1..q).map(|k| l[k][i] * x[k]).sum::<f64>()) / l[i][i];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::{grow_sorted, moments, principal_axes_of_moments, spans_every_axis};

    /// Where `spans_every_axis` says yes, the eigenproblem's smallest spread is at least the
    /// ratio of its largest; the six face neighbours of a cube pass, a stretched or flat set
    /// does not.
    #[test]
    fn spanning_every_axis_agrees_with_the_eigenproblem() {
        let ratio = 0.1;
        let cube = [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
        assert!(spans_every_axis(&moments(cube), ratio));
        let flat = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.7, 0.7, 0.0]];
        assert!(!spans_every_axis(&moments(flat), ratio));
        assert!(!spans_every_axis(&[[0.0; 3]; 3], ratio));
        // The cube squeezed along z by 1 to 1/20 and turned about y: every yes is a yes of the
        // eigenproblem, the round one is a yes and the flattest a no.
        let mut yes = 0;
        for squeeze in 1..=20 {
            let s = 1.0 / squeeze as f64;
            let (c, d) = ((0.3 * squeeze as f64).cos(), (0.3 * squeeze as f64).sin());
            let turned: Vec<[f64; 3]> = cube.iter().map(|r| [c * r[0] - d * r[2] * s, r[1], d * r[0] + c * r[2] * s]).collect();
            let m = moments(turned.iter().copied());
            let (_, spread) = principal_axes_of_moments(m);
            if spans_every_axis(&m, ratio) {
                yes += 1;
                assert!(spread[2] >= ratio * spread[0], "squeeze {squeeze}: {spread:?}");
            }
        }
        assert!((1..20).contains(&yes), "{yes}");
    }

    /// Each prefix grown from the one before is the prefix sorted, duplicates and all, and a
    /// set not one shorter is rebuilt.
    #[test]
    fn a_grown_prefix_is_the_prefix_sorted() {
        let cands = [20u32, 3, 9, 14, 1, 30, 9, 0];
        let mut set = Vec::new();
        for m in 1..=cands.len() {
            grow_sorted(&mut set, &cands, m);
            let mut want = cands[..m].to_vec();
            want.sort_unstable();
            assert_eq!(set, want);
        }
        grow_sorted(&mut set, &cands, 3);
        assert_eq!(set, [3, 9, 20]);
    }
}
