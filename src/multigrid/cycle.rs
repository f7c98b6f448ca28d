//! The multigrid cycle that walks a hierarchy: γ = 2 gives the paper's W-cycle.
//!
//! Work vectors are allocated once per solve (`Workspace`), not per cycle.
//! Coarse-level visits start from a zero correction (`Start::Zero`) and skip its residual.

use super::group::{block, block_mut, GroupOp};
use super::hierarchy::Hierarchy;
pub use super::policy::CycleParams;
use super::group::Scratch;
use super::smoother::{smooth, Coefficients, Start};
use crate::bc::P;
use crate::sparse::par_update;

/// Vectors of one level's visit, for a group of g components. The finest level's right-hand
/// side and iterate are the caller's, so its `b` and `x` stay empty.
struct LevelWork {
    b: Vec<f64>,
    x: Vec<f64>,
    /// The group's residual (g blocks).
    r: Vec<f64>,
    /// One smoother scratch per component of the group.
    scratch: Vec<Scratch>,
    /// Per group, by its first component: the smoother's coefficients of its last visit to the
    /// level (kept while its bounds are).
    coefficients: Vec<Coefficients>,
}

pub(crate) struct Workspace {
    levels: Vec<LevelWork>,
}

impl Workspace {
    /// Vectors for solving groups of up to `group` components on `h`.
    pub(crate) fn new(h: &Hierarchy, group: usize) -> Self {
        let levels = h
            .levels
            .iter()
            .enumerate()
            .map(|(l, lev)| {
                let n = lev.n();
                let nbx = if l == 0 { 0 } else { group * n };
                let scratch = (0..group).map(|_| Scratch::new(n, h.method)).collect();
                LevelWork {
                    b: vec![0.0; nbx],
                    x: vec![0.0; nbx],
                    r: vec![0.0; group * n],
                    scratch,
                    coefficients: (0..lev.dim()).map(|_| Coefficients::default()).collect(),
                }
            })
            .collect();
        Workspace { levels }
    }

    /// The finest level's scratch, free between cycles (for the outer iteration's products).
    pub(crate) fn fine(&mut self) -> &mut Scratch {
        &mut self.levels[0].scratch[0]
    }
}

/// One cycle for the components `comps` on the finest level: x ← x + B(b − A x), or x = B b
/// from `Start::Zero` (x's content ignored). `b` and `x` hold one block of n values per
/// component. Components the methods' operators do not couple run one after another, each its
/// own cycle; a group coupled by slip walls runs as one (`multigrid::slip`). Returns the largest
/// correction of the first fine-level smoothing sweep (the paper's measure).
pub(crate) fn cycle(
    h: &Hierarchy,
    comps: std::ops::Range<usize>,
    p: &CycleParams,
    b: &[f64],
    x: &mut [f64],
    start: Start,
    ws: &mut Workspace,
) -> f64 {
    if comps.len() == 1 || GroupOp::new(h.fine(), comps.clone(), false).frames().is_some() {
        return level_cycle(h, comps, p, 0, b, x, start, ws);
    }
    let n = h.fine().n();
    let mut first = 0.0f64;
    for (k, c) in comps.enumerate() {
        first = first.max(level_cycle(h, c..c + 1, p, 0, block(b, n, k), block_mut(x, n, k), start, ws));
    }
    first
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn level_cycle(
    h: &Hierarchy,
    comps: std::ops::Range<usize>,
    p: &CycleParams,
    l: usize,
    b: &[f64],
    x: &mut [f64],
    start: Start,
    ws: &mut Workspace,
) -> f64 {
    let lev = &h.levels[l];
    let op = GroupOp::new(lev, comps.clone(), p.l1_bound);
    let (n, g) = (op.n(), op.len());
    let work = &mut ws.levels[l];
    let Some(down) = &lev.down else {
        let solve = h.coarse_solve(&comps).expect("coarsest level has its solve");
        solve.solve(&op, b, x, start, &mut work.r[..g * n], &mut work.scratch);
        return 0.0;
    };
    let sm = p.smoother_at(l);
    let mut first = 0.0;
    let mut start = start;
    for k in 0..p.pre {
        // Only the first fine-level sweep's correction is reported (the paper's measure).
        let m = smooth(&op, sm, b, x, &mut work.scratch, &mut work.coefficients[comps.start], start, l == 0 && k == 0);
        start = Start::Guess;
        if k == 0 {
            first = m;
        }
    }
    let nc = h.levels[l + 1].n();
    let mut bc = std::mem::take(&mut ws.levels[l + 1].b);
    let mut xc = std::mem::take(&mut ws.levels[l + 1].x);
    let work = &mut ws.levels[l];
    let r: &[f64] = if start == Start::Zero {
        // No pre-smoothing from a zero start: the residual is b itself.
        x.iter_mut().for_each(|v| *v = 0.0);
        b
    } else {
        op.residual(b, x, &mut work.r[..g * n], &mut work.scratch[0].s);
        &work.r[..g * n]
    };
    for k in 0..g {
        down.restrict.mul_vec(block(r, n, k), block_mut(&mut bc, nc, k));
    }
    // Π_c Pᵀ: the coarse right-hand side in the coarse free subspace.
    let coarse = GroupOp::new(&h.levels[l + 1], comps.clone(), p.l1_bound);
    coarse.accumulate(&mut bc[..g * nc]);
    coarse.project(&mut bc[..g * nc]);
    for k in 0..p.gamma_at(l) {
        let cstart = if k == 0 { Start::Zero } else { Start::Guess };
        level_cycle(h, comps.clone(), p, l + 1, &bc[..g * nc], &mut xc[..g * nc], cstart, ws);
    }
    coarse.exchange(&mut xc[..g * nc]);
    // Add the interpolated correction, fused into one pass; prescribed unknowns keep theirs.
    for k in 0..g {
        let (flags, prolong, xc_ref, wgt) = (op.flags(k), &down.prolong, block(&xc, nc, k), p.coarse_weight);
        par_update(block_mut(x, n, k), |i, xv| {
            if flags[i] & P != 0 {
                xv
            } else {
                xv + wgt * prolong.row_dot(i, xc_ref)
            }
        });
    }
    // Π_f P: the prolongated correction in the fine free subspace.
    op.project(x);
    ws.levels[l + 1].b = bc;
    ws.levels[l + 1].x = xc;
    for _ in 0..p.post {
        let work = &mut ws.levels[l];
        smooth(&op, sm, b, x, &mut work.scratch, &mut work.coefficients[comps.start], Start::Guess, false);
    }
    first
}
