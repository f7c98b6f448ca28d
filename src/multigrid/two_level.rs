//! Two-level analysis of a hierarchy (internals: the probes behind docs/perf-history.md). For a
//! level l, the cycle whose coarse level l + 1 is solved exactly — by conjugate gradients on
//! level l + 1 preconditioned by the hierarchy's own cycle from there — separates what level
//! l's smoother and its interpolation from l + 1 leave from what the levels below lose. The
//! slowest error of that two-level iteration, found by power iteration, says where the slow
//! error lives, and its reduction by the smoother alone and by the coarse correction alone says
//! which of the two fails on it.

use super::cycle::{level_cycle, CycleParams, Workspace};
use super::group::{block, block_mut, GroupOp, Scratch};
use super::hierarchy::Hierarchy;
use super::smoother::{smooth, Coefficients, Start};
use crate::bc::P;
use crate::sparse::{axpy, par_update};
use std::ops::Range;

/// What the analysis of the level pair (l, l + 1) found for one group of components.
#[derive(Clone, Debug)]
pub struct PairAnalysis {
    /// The finer level of the pair, l.
    pub level: usize,
    /// PCG iterations to the tolerance on level l's system (a fixed mode-rich right-hand side),
    /// preconditioned by the hierarchy's cycle from level l down.
    pub multilevel: usize,
    /// The same, preconditioned by the two-level cycle: level l + 1 solved exactly.
    pub two_level: usize,
    /// The same with level l + 1's operator replaced by the Galerkin product Pᵀ A P of level
    /// l's (applied matrix-free) and solved exactly: what the interpolation allows.
    pub two_level_galerkin: usize,
    /// The stationary two-level iteration's reduction of its slowest error per iteration, in
    /// the energy norm (the two-level convergence factor).
    pub rate: f64,
    /// That slowest error on level l's unknowns (one block per component of the group), scaled
    /// to unit energy.
    pub mode: Vec<f64>,
    /// ‖S e‖_A / ‖e‖_A for the slow mode e: one application of level l's smoother alone.
    pub smoother_reduction: f64,
    /// ‖(I − P A_c⁻¹ Pᵀ A) e‖_A / ‖e‖_A: the exact coarse correction alone (how much of the slow
    /// mode the interpolation's range holds, in energy).
    pub coarse_reduction: f64,
    /// The same with the Galerkin Pᵀ A P: the A-orthogonal projection on P's range, so this is
    /// the part of the slow mode's energy the interpolation cannot represent.
    pub coarse_reduction_galerkin: f64,
    /// ‖A e‖²_{D⁻¹} / ‖e‖²_A over the level's λmax of D⁻¹A: where the slow mode sits in the
    /// smoother's spectrum (near 0: smooth for the smoother, the interpolation's to take).
    pub smoother_position: f64,
    /// Per unknown of level l, the slow mode's energy there, Σ over the group's components of
    /// eᵢ (A e)ᵢ: where its energy lies (the entries sum to 1).
    pub density: Vec<f64>,
    /// The same for the slow mode after one application of the smoother (they sum to
    /// `smoother_reduction`²).
    pub smoothed_density: Vec<f64>,
    /// The same after the exact coarse correction with level l + 1's own operator (they sum to
    /// `coarse_reduction`²): where the energy the coarse level misses lies.
    pub corrected_density: Vec<f64>,
}

impl PairAnalysis {
    /// One line for the probes: the pair's unknowns on `h`, the PCG counts, the two-level
    /// factor and, on its slow mode, the smoother's and the coarse corrections' reductions.
    pub fn summary(&self, h: &Hierarchy) -> String {
        let l = self.level;
        format!(
            "pair ({l}, {}): {} -> {} unknowns; PCG iterations multilevel {} two-level {} (Galerkin coarse {}); two-level factor {:.3}; on its slow mode: smoother {:.3}, exact coarse correction {:.3} (Galerkin {:.3}), position in D^-1 A {:.2e}",
            l + 1,
            h.levels[l].n(),
            h.levels.get(l + 1).map_or(0, |c| c.n()),
            self.multilevel,
            self.two_level,
            self.two_level_galerkin,
            self.rate,
            self.smoother_reduction,
            self.coarse_reduction,
            self.coarse_reduction_galerkin,
            self.smoother_position
        )
    }
}

/// The two-level analysis of the pair (`level`, `level` + 1) for the group `comps` (one of
/// `Hierarchy::groups`) with the cycle `cp`; None when the level is the coarsest. `tol` is
/// PCG's relative tolerance, and `power` the power iterations for the slow mode.
pub fn analyse_pair(
    h: &Hierarchy,
    cp: &CycleParams,
    comps: Range<usize>,
    level: usize,
    tol: f64,
    power: usize,
) -> Option<PairAnalysis> {
    let lev = h.levels.get(level)?;
    lev.down.as_ref()?;
    let op = GroupOp::new(lev, comps.clone(), cp.l1_bound);
    let (n, g) = (op.n(), op.len());
    let mut ws = Workspace::new(h, g);
    let scratch = (0..g).map(|_| Scratch::new(n, h.method)).collect();
    let mut tl = TwoLevel { h, cp, comps: comps.clone(), level, op, scratch, cache: Coefficients::default(), galerkin: false };
    let free = |seed: usize| free_values(&op, seed);

    let b = free(0);
    let multilevel =
        pcg(&op, None, &b, &mut vec![0.0; g * n], tol, 500, &mut |r, z| level_cycle(h, comps.clone(), cp, level, r, z, Start::Zero, &mut ws))
            .0;
    let two_level = pcg(&op, None, &b, &mut vec![0.0; g * n], tol, 500, &mut |r, z| tl.apply(r, z, &mut ws)).0;
    tl.galerkin = true;
    let two_level_galerkin = pcg(&op, None, &b, &mut vec![0.0; g * n], tol, 500, &mut |r, z| tl.apply(r, z, &mut ws)).0;
    tl.galerkin = false;

    // Power iteration on the two-level error propagation E = I − M⁻¹A from a mode-rich start.
    let mut e = free(7919);
    let (mut ae, mut s, mut z) = (vec![0.0; g * n], vec![0.0; n], vec![0.0; g * n]);
    let mut rate = 0.0;
    normalise(&op, &mut e, &mut ae, &mut s);
    for _ in 0..power {
        op.apply(&mut e, &mut ae, &mut s);
        tl.apply(&ae, &mut z, &mut ws);
        axpy(-1.0, &z, &mut e);
        rate = normalise(&op, &mut e, &mut ae, &mut s);
    }

    // The smoother alone on the slow mode: x ← S x for A x = 0.
    let zero = vec![0.0; g * n];
    let mut se = e.clone();
    smooth(&op, cp.smoother_at(level), &zero, &mut se, &mut tl.scratch, &mut tl.cache, Start::Guess, false);
    let smoother_reduction = energy(&op, &mut se, &mut ae, &mut s);
    let smoothed_density = density(&op, &se, &ae);
    // ‖A e‖²_{D⁻¹}: the smoother's preconditioner on A e.
    op.apply(&mut e, &mut ae, &mut s);
    let mode_density = density(&op, &e, &ae);
    let mut s2 = vec![0.0; g * n];
    let mut dae = ae.clone();
    for k in 0..g {
        op.precondition(k, block_mut(&mut dae, n, k), &mut Vec::new());
    }
    let lambda = (0..g).map(|k| op.lambda_max(k)).fold(0.0, f64::max);
    let smoother_position = op.dot(&ae, &dae) / op.dot(&e, &ae) / lambda;
    // The exact coarse correction alone: e − P A_c⁻¹ Pᵀ A e.
    let mut ce = e.clone();
    z.iter_mut().for_each(|v| *v = 0.0);
    tl.coarse_correction(&ae, &mut z, &mut ws);
    axpy(-1.0, &z, &mut ce);
    let coarse_reduction = energy(&op, &mut ce, &mut s2, &mut s);
    let corrected_density = density(&op, &ce, &s2);
    tl.galerkin = true;
    let mut ce = e.clone();
    z.iter_mut().for_each(|v| *v = 0.0);
    tl.coarse_correction(&ae, &mut z, &mut ws);
    axpy(-1.0, &z, &mut ce);
    let coarse_reduction_galerkin = energy(&op, &mut ce, &mut s2, &mut s);
    Some(PairAnalysis {
        level,
        multilevel,
        two_level,
        two_level_galerkin,
        rate,
        mode: e,
        smoother_reduction,
        coarse_reduction,
        coarse_reduction_galerkin,
        smoother_position,
        density: mode_density,
        smoothed_density,
        corrected_density,
    })
}

/// PCG's iterations and relative residual on level `level`'s system for the group `comps`,
/// preconditioned by the cycle `cp` from that level, from zero on a fixed pseudo-random
/// right-hand side, to the relative residual `tol` within `max` iterations: the multilevel count
/// of [`analyse_pair`] without its two-level solves, to compare cycles on one hierarchy and a
/// level's count across sizes. None for a level the hierarchy does not have.
pub fn multilevel_iterations(
    h: &Hierarchy,
    cp: &CycleParams,
    comps: Range<usize>,
    level: usize,
    tol: f64,
    max: usize,
) -> Option<(usize, f64)> {
    let lev = h.levels.get(level)?;
    let op = GroupOp::new(lev, comps.clone(), cp.l1_bound);
    let mut ws = Workspace::new(h, op.len());
    let b = free_values(&op, 0);
    let mut x = vec![0.0; b.len()];
    Some(pcg(&op, None, &b, &mut x, tol, max, &mut |r, z| level_cycle(h, comps.clone(), cp, level, r, z, Start::Zero, &mut ws)))
}

/// Fixed pseudo-random values (seeded by `seed`) on `op`'s free unknowns, zero on the
/// prescribed ones, projected onto the slip walls' constraints.
fn free_values(op: &GroupOp, seed: usize) -> Vec<f64> {
    let n = op.n();
    let mut x: Vec<f64> =
        (0..op.len() * n).map(|k| if op.flags(k / n)[k % n] & P != 0 { 0.0 } else { hashed(k + seed) }).collect();
    op.project(&mut x);
    x
}

/// Per unknown, Σ over the blocks of xᵢ (A x)ᵢ, given `ax` = A x.
fn density(op: &GroupOp, x: &[f64], ax: &[f64]) -> Vec<f64> {
    let (n, g) = (op.n(), op.len());
    (0..n).map(|i| (0..g).map(|k| x[k * n + i] * ax[k * n + i]).sum()).collect()
}

/// A fixed pseudo-random value in [−0.5, 0.5) for index `i`.
fn hashed(i: usize) -> f64 {
    ((i as u64).wrapping_mul(2654435761) % 1000) as f64 / 1000.0 - 0.5
}

/// ‖x‖_A (`ax` and `s` scratch).
fn energy(op: &GroupOp, x: &mut [f64], ax: &mut [f64], s: &mut [f64]) -> f64 {
    op.apply(x, ax, s);
    op.dot(x, ax).max(0.0).sqrt()
}

/// Scales `x` to unit energy; returns the energy it had.
fn normalise(op: &GroupOp, x: &mut [f64], ax: &mut [f64], s: &mut [f64]) -> f64 {
    let e = energy(op, x, ax, s);
    if e > 0.0 {
        x.iter_mut().for_each(|v| *v /= e);
    }
    e
}

/// The operator of a PCG solve: y = A x.
type Apply<'f> = &'f mut dyn FnMut(&mut [f64], &mut [f64]);

/// Conjugate gradients from `x` on the operator `a`, or `op`'s own when None, with `op`'s inner
/// products, preconditioned by `m` (z = M⁻¹ r); returns the iterations and the relative
/// residual reached.
fn pcg(
    op: &GroupOp,
    a: Option<Apply>,
    b: &[f64],
    x: &mut [f64],
    tol: f64,
    max: usize,
    m: &mut dyn FnMut(&[f64], &mut [f64]) -> f64,
) -> (usize, f64) {
    let mut s = vec![0.0; op.n()];
    let mut own = |x: &mut [f64], y: &mut [f64]| op.apply(x, y, &mut s);
    let a: Apply = match a {
        Some(a) => a,
        None => &mut own,
    };
    let n = b.len();
    let (mut r, mut z, mut q) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    a(x, &mut r);
    r.iter_mut().zip(b).for_each(|(r, b)| *r = b - *r);
    let bn = op.norm(b);
    if bn == 0.0 {
        return (0, 0.0);
    }
    m(&r, &mut z);
    let mut dir = z.clone();
    let mut rz = op.dot(&r, &z);
    let mut rel = op.norm(&r) / bn;
    for k in 1..=max {
        a(&mut dir, &mut q);
        let pq = op.dot(&dir, &q);
        if pq <= 0.0 || !pq.is_finite() {
            return (k, rel);
        }
        let alpha = rz / pq;
        axpy(alpha, &dir, x);
        axpy(-alpha, &q, &mut r);
        rel = op.norm(&r) / bn;
        if rel <= tol {
            return (k, rel);
        }
        m(&r, &mut z);
        let rz_new = op.dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        let zr = &z;
        par_update(&mut dir, |i, d| zr[i] + beta * d);
    }
    (max, rel)
}

/// The two-level cycle on level `level` for one component: the level's own smoothing, and the
/// level below solved exactly.
struct TwoLevel<'a> {
    h: &'a Hierarchy,
    cp: &'a CycleParams,
    comps: Range<usize>,
    level: usize,
    op: GroupOp<'a>,
    scratch: Vec<Scratch>,
    cache: Coefficients,
    /// Solve Pᵀ A P on the coarse level instead of its own operator.
    galerkin: bool,
}

impl TwoLevel<'_> {
    /// z = M⁻¹ r: pre-smoothing from zero, the exact coarse correction, post-smoothing.
    fn apply(&mut self, r: &[f64], z: &mut [f64], ws: &mut Workspace) -> f64 {
        let sm = self.cp.smoother_at(self.level);
        let op = self.op;
        smooth(&op, sm, r, z, &mut self.scratch, &mut self.cache, Start::Zero, false);
        let mut res = vec![0.0; r.len()];
        op.residual(r, z, &mut res, &mut self.scratch[0].s);
        self.coarse_correction(&res, z, ws);
        smooth(&op, sm, r, z, &mut self.scratch, &mut self.cache, Start::Guess, false);
        0.0
    }

    /// z ← z + P A_c⁻¹ Pᵀ res, A_c⁻¹ by PCG on the coarse level to 1e-12 with the hierarchy's
    /// cycle from there (exact where that level is the factored coarsest).
    fn coarse_correction(&mut self, res: &[f64], z: &mut [f64], ws: &mut Workspace) {
        let (h, l) = (self.h, self.level);
        let down = h.levels[l].down.as_ref().expect("not the coarsest level");
        let coarse = GroupOp::new(&h.levels[l + 1], self.comps.clone(), self.cp.l1_bound);
        let (n, nc, g) = (self.op.n(), coarse.n(), coarse.len());
        let mut bc = vec![0.0; g * nc];
        for k in 0..g {
            down.restrict.mul_vec(block(res, n, k), block_mut(&mut bc, nc, k));
        }
        coarse.accumulate(&mut bc);
        coarse.project(&mut bc);
        let mut xc = vec![0.0; g * nc];
        let (cp, comps) = (self.cp, self.comps.clone());
        let m = &mut |r: &[f64], y: &mut [f64]| level_cycle(h, comps.clone(), cp, l + 1, r, y, Start::Zero, ws);
        if self.galerkin {
            let op = self.op;
            let (mut fx, mut fy, mut s) = (vec![0.0; g * n], vec![0.0; g * n], vec![0.0; n]);
            let mut ptap = |x: &mut [f64], y: &mut [f64]| {
                for k in 0..g {
                    let (flags, xk) = (op.flags(k), block(x, nc, k));
                    par_update(block_mut(&mut fx, n, k), |i, _| if flags[i] & P != 0 { 0.0 } else { down.prolong.row_dot(i, xk) });
                }
                op.project(&mut fx);
                op.apply(&mut fx, &mut fy, &mut s);
                for k in 0..g {
                    down.restrict.mul_vec(block(&fy, n, k), block_mut(y, nc, k));
                }
                coarse.accumulate(y);
                coarse.project(y);
            };
            pcg(&coarse, Some(&mut ptap), &bc, &mut xc, 1e-11, 300, m);
        } else {
            pcg(&coarse, None, &bc, &mut xc, 1e-11, 300, m);
        }
        coarse.exchange(&mut xc);
        for k in 0..g {
            let (flags, xr) = (self.op.flags(k), block(&xc, nc, k));
            par_update(block_mut(z, n, k), |i, v| if flags[i] & P != 0 { v } else { v + down.prolong.row_dot(i, xr) });
        }
        self.op.project(z);
    }
}

/// Per unknown of `level`, the finest level's unknown it is (kept unknowns are fine unknowns);
/// None for a level of coarse meshes, whose vertices are not the finest level's unknowns.
pub fn finest_unknowns(h: &Hierarchy, level: usize) -> Option<Vec<u32>> {
    let mut map: Vec<u32> = (0..h.levels.get(level)?.n() as u32).collect();
    for l in (1..=level).rev() {
        if h.levels[l].mesh.is_some() {
            return None;
        }
        let parent = &h.levels[l].parent_vertex;
        map.iter_mut().for_each(|u| *u = parent[*u as usize]);
    }
    Some(map)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bc::Kind;
    use crate::mesh::fixtures::rect;
    use crate::multigrid::hierarchy::HierarchyParams;
    use crate::{BoundaryConditions, Method, SolveParams};

    /// The cycle from the finest level converges its system in a few iterations, the factored
    /// coarsest level's exact solve in one; a level the hierarchy lacks has no count.
    #[test]
    fn multilevel_iterations_per_level() {
        let mesh = rect(24, 24, [0.0, 1.0, 0.0, 1.0]);
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(1, Kind::Fixed).set_kinds(3, Kind::Clamped);
        let mut params = HierarchyParams::default();
        params.coarsen.coarsest_unknowns = Some(40);
        let h = Hierarchy::build(&mesh, Vec::new(), &bcs, Method::Biharmonic, &params).unwrap();
        let levels = h.levels.len();
        assert!(levels >= 3, "{levels} levels");
        let cp = CycleParams::resolve(&h, &SolveParams::default());
        let (its, rel) = multilevel_iterations(&h, &cp, 0..1, 0, 1e-8, 100).unwrap();
        assert!((2..=15).contains(&its) && rel <= 1e-8, "finest level: {its} iterations, residual {rel:e}");
        let (its, rel) = multilevel_iterations(&h, &cp, 0..1, levels - 1, 1e-8, 100).unwrap();
        assert!(its == 1 && rel <= 1e-8, "coarsest level: {its} iterations, residual {rel:e}");
        assert!(multilevel_iterations(&h, &cp, 0..1, levels, 1e-8, 100).is_none());
    }
}
