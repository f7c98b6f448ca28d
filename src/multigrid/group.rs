//! What the cycle, the smoother, PCG and the coarsest solve see of one level: the operator of a
//! group of components over a block vector (one block of n values per component, in the
//! group's order). A component the methods' operators leave alone is a group of one; the
//! components coupled by slip walls are one group whose products, residuals and smoothing steps
//! are projected on the subspace the slip frames leave free (`multigrid::slip`).

use super::layout::Layout;
use super::level::Level;
use super::lanczos::upper_estimate;
use super::line_smoother::LineBlocks;
use crate::bc::{SlipFrames, P};
use crate::operator::{LevelOperator, Method};
use std::ops::Range;

/// Block `k` of a group's vector of blocks of `n` values.
pub(crate) fn block(v: &[f64], n: usize, k: usize) -> &[f64] {
    &v[k * n..(k + 1) * n]
}

/// Block `k` of a group's vector of blocks of `n` values, to write.
pub(crate) fn block_mut(v: &mut [f64], n: usize, k: usize) -> &mut [f64] {
    &mut v[k * n..(k + 1) * n]
}

/// The operator of a group of components on one level, with the Jacobi bounds its smoother
/// uses and the projection of its slip frames.
#[derive(Clone, Copy)]
pub(crate) struct GroupOp<'a> {
    level: &'a Level,
    /// The group's first component and its number of components.
    first: usize,
    len: usize,
    /// The slip frames that couple the group; None for components solved apart.
    frames: Option<&'a SlipFrames>,
    /// Smooth with λmax = 1, the l1 bound's guarantee, instead of the level's estimate.
    l1_bound: bool,
}

impl<'a> GroupOp<'a> {
    /// The group `comps` of `level`; `l1_bound` as in `CycleParams::l1_bound`.
    pub(crate) fn new(level: &'a Level, comps: Range<usize>, l1_bound: bool) -> Self {
        let frames = level.coupled_frames(&comps);
        GroupOp { level, first: comps.start, len: comps.len(), frames, l1_bound }
    }

    /// The level's unknowns (the length of one block).
    pub(crate) fn n(&self) -> usize {
        self.level.n()
    }

    /// The group's number of components (blocks).
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// The group's components.
    pub(crate) fn components(&self) -> Range<usize> {
        self.first..self.first + self.len
    }

    /// The slip frames coupling the group, if any.
    pub(crate) fn frames(&self) -> Option<&'a SlipFrames> {
        self.frames
    }

    /// The level the group lives on.
    pub(crate) fn level(&self) -> &'a Level {
        self.level
    }

    /// The flags of the group's block `k`.
    pub(crate) fn flags(&self, k: usize) -> &'a [u8] {
        &self.level.flags[self.first + k]
    }

    /// The inverse Jacobi (l1) diagonal of block `k`.
    pub(crate) fn inv_d(&self, k: usize) -> &'a [f64] {
        &self.level.inv_d[self.first + k]
    }

    /// The level's line blocks when block `k` is solved along lines (`multigrid::line_smoother`);
    /// None where it is smoothed pointwise.
    pub(crate) fn lines(&self, k: usize) -> Option<&'a LineBlocks> {
        let lines = &self.level.lines;
        lines.active(self.first + k).then_some(lines)
    }

    /// z ← D⁻¹ z for block `k`: along its lines when it has them, else pointwise by the
    /// Jacobi diagonal. `sol` is the line solves' scratch.
    pub(crate) fn precondition(&self, k: usize, z: &mut [f64], sol: &mut Vec<f64>) {
        match self.lines(k) {
            Some(lines) => lines.precondition(self.first + k, self.inv_d(k), z, sol),
            None => z.iter_mut().zip(self.inv_d(k)).for_each(|(z, d)| *z *= d),
        }
    }

    /// The λmax of D⁻¹A the smoother of block `k` is tuned to: 1 with the l1 bound, the group's
    /// largest estimate for a coupled group (one polynomial for all its blocks), else the
    /// component's own.
    pub(crate) fn lambda_max(&self, k: usize) -> f64 {
        if self.l1_bound {
            1.0
        } else if self.frames.is_some() {
            self.components().map(|c| self.level.lambda_max[c]).fold(0.0, f64::max)
        } else {
            self.level.lambda_max[self.first + k]
        }
    }

    /// Block `k`'s operator and bounds, as the smoother's steps take them.
    pub(crate) fn problem(&self, k: usize) -> Problem<'a> {
        Problem { op: &self.level.op, flags: self.flags(k), inv_d: self.inv_d(k) }
    }

    /// Makes the halo of every block of `x` current (`Layout::exchange`) before an operator
    /// reads it.
    pub(crate) fn exchange(&self, x: &mut [f64]) {
        let n = self.n();
        debug_assert!(self.level.layout.owned() <= n, "a block holds its owned rows first");
        for k in 0..self.len {
            self.level.layout.exchange(block_mut(x, n, k));
        }
    }

    /// Adds the halo rows of every block of `x` into their owners (`Layout::accumulate`), after
    /// a transposed product wrote them.
    pub(crate) fn accumulate(&self, x: &mut [f64]) {
        let n = self.n();
        for k in 0..self.len {
            self.level.layout.accumulate(block_mut(x, n, k));
        }
    }

    /// Σ aᵢ bᵢ over the group's vectors (every process's owned rows).
    pub(crate) fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        self.level.layout.dot(a, b)
    }

    /// ‖a‖₂ over the group's vector.
    pub(crate) fn norm(&self, a: &[f64]) -> f64 {
        self.dot(a, a).sqrt()
    }

    /// The largest |aᵢ| over the group's vector (NaN when any is NaN).
    pub(crate) fn max_abs(&self, a: &[f64]) -> f64 {
        self.level.layout.max_abs(a)
    }

    /// y = A x block by block, without the projection (the power iteration's product). `s` is
    /// scratch of length n.
    pub(crate) fn apply_blocks(&self, x: &mut [f64], y: &mut [f64], s: &mut [f64]) {
        self.exchange(x);
        let n = self.n();
        for k in 0..self.len {
            self.level.op.apply(self.flags(k), block(x, n, k), block_mut(y, n, k), s);
        }
    }

    /// y = Π A x. `s` is scratch of length n.
    pub(crate) fn apply(&self, x: &mut [f64], y: &mut [f64], s: &mut [f64]) {
        self.apply_blocks(x, y, s);
        self.project(y);
    }

    /// r = Π (b − A x). `s` is scratch of length n.
    pub(crate) fn residual(&self, b: &[f64], x: &mut [f64], r: &mut [f64], s: &mut [f64]) {
        self.exchange(x);
        let n = self.n();
        if self.level.op.one_pass().is_some() && n > 0 {
            // One pass over A's rows for every block; it needs no S.
            let mut r: Vec<&mut [f64]> = r.chunks_mut(n).collect();
            self.residuals(b, x, &mut r, &mut []);
        } else {
            for k in 0..self.len {
                self.level.op.residual(self.flags(k), block(b, n, k), block(x, n, k), block_mut(r, n, k), s);
            }
        }
        self.project(r);
    }

    /// r_k = b_k − A x_k into each block's `r[k]` (no projection, no exchange), the rows of the
    /// level's operator read once for all blocks (`LevelOperator::residuals`); `s` holds each
    /// block's S, and may be empty for an operator applied in one pass (`one_pass`), which
    /// needs none.
    pub(crate) fn residuals(&self, b: &[f64], x: &[f64], r: &mut [&mut [f64]], s: &mut [&mut [f64]]) {
        let (n, g) = (self.n(), self.len);
        let flags: Vec<&[u8]> = (0..g).map(|k| self.flags(k)).collect();
        let (b, x): (Vec<&[f64]>, Vec<&[f64]>) = (0..g).map(|k| (block(b, n, k), block(x, n, k))).unzip();
        if s.is_empty() {
            let mut none: Vec<&mut [f64]> = (0..g).map(|_| &mut [][..]).collect();
            self.level.op.residuals(&flags, &b, &x, r, &mut none);
        } else {
            self.level.op.residuals(&flags, &b, &x, r, s);
        }
    }

    /// u ← Π u (nothing for a group without slip frames and tied rows): the slip frames'
    /// projection, and the layout's ties (`Layout::tie`).
    pub(crate) fn project(&self, u: &mut [f64]) {
        if let Some(f) = self.frames {
            f.project(self.n(), u);
        }
        self.tie(u);
    }

    /// Ties every block of `u` (`Layout::tie`).
    fn tie(&self, u: &mut [f64]) {
        let n = self.n();
        for k in 0..self.len {
            self.level.layout.tie(block_mut(u, n, k));
        }
    }

    /// Moves a smoothing step into the free subspace: the iterate `x` and the blocks' steps `d`
    /// in `w` (nothing for a group without slip frames and tied rows).
    pub(crate) fn project_step(&self, x: &mut [f64], w: &mut [Scratch]) {
        if let Some(f) = self.frames {
            f.project(self.n(), x);
            let mut d: Vec<&mut [f64]> = w.iter_mut().map(|s| s.d.as_mut_slice()).collect();
            f.project_blocks(&mut d);
        }
        self.tie(x);
        w.iter_mut().for_each(|s| self.level.layout.tie(&mut s.d));
    }
}

/// The operator of one level and component, with its Jacobi scaling.
#[derive(Clone, Copy)]
pub struct Problem<'a> {
    pub op: &'a LevelOperator,
    pub flags: &'a [u8],
    pub inv_d: &'a [f64],
}

/// Scratch of one block of a level's smoother: the biharmonic's S (empty for the second-order
/// methods, which have none) and the step; on a level with lines also the residual and the
/// line solves' values (allocated at their first use).
pub struct Scratch {
    pub s: Vec<f64>,
    pub d: Vec<f64>,
    pub(crate) r: Vec<f64>,
    pub(crate) sol: Vec<f64>,
}

impl Scratch {
    pub fn new(n: usize, method: Method) -> Self {
        let ns = if method == Method::Biharmonic { n } else { 0 };
        Scratch { s: vec![0.0; ns], d: vec![0.0; n], r: Vec::new(), sol: Vec::new() }
    }
}

/// The power iterations of a λmax estimate from the fixed start: the count the Chebyshev
/// smoother's interval is tuned to.
pub(crate) const POWER_ITERATIONS: usize = 15;

/// Largest eigenvalue of D⁻¹ Π A on the group's free subspace by power iteration from a fixed
/// start (deterministic), padded by 10% and capped at 1, the l1 bound's guarantee (D the point
/// or line l1 preconditioner, `GroupOp::precondition`); on a group with lines not below the
/// Lanczos bound (`raised_on_lines`).
pub(crate) fn estimate_lambda_max(op: &GroupOp) -> f64 {
    let mut power = PowerIteration::new(op);
    power.run(op, POWER_ITERATIONS);
    raised_on_lines(op, padded(power.after(POWER_ITERATIONS)))
}

/// The padded power-iteration estimate `estimate` of `op`'s group, raised where a block is
/// smoothed along lines to the Lanczos bound (`lanczos::upper_estimate`) when that lies above
/// it: the power iteration from a spread start finds the lines' local top modes slowly, and
/// the smoother's high-degree polynomial amplifies a mode above its interval.
///
/// The decision is every process's (the layout's maximum): across ranks the lines may sit on
/// some ranks only, and the Lanczos run is collective.
pub(crate) fn raised_on_lines(op: &GroupOp, estimate: f64) -> f64 {
    let here = f64::from(u8::from((0..op.len()).any(|k| op.lines(k).is_some())));
    if op.max_abs(&vec![here; op.n()]) > 0.0 {
        estimate.max(upper_estimate(op))
    } else {
        estimate
    }
}

/// The padded, capped estimate of an unpadded `lambda`; None (the power iteration met a
/// vanishing iterate) gives the l1 bound 1.
pub(crate) fn padded(lambda: Option<f64>) -> f64 {
    lambda.map_or(1.0, |l| (1.1 * l).clamp(0.05, 1.0))
}

/// The fixed, mode-rich start of the λmax estimates of `op`'s group: a cheap hash of the index
/// (zero at prescribed unknowns), projected.
pub(crate) fn fixed_start(op: &GroupOp) -> Vec<f64> {
    let n = op.n();
    let mut x: Vec<f64> = (0..op.len() * n)
        .map(|k| {
            let (b, i) = (k / n, k % n);
            if op.flags(b)[i] & P != 0 {
                0.0
            } else {
                ((k as u64).wrapping_mul(2654435761) % 1000) as f64 / 1000.0 - 0.5
            }
        })
        .collect();
    op.project(&mut x);
    x
}

/// The power iteration of D⁻¹ Π A from the fixed start, run in stages (`run`): a run to k
/// iterations continues the one before it, so its estimates are those of one run to k.
pub(crate) struct PowerIteration {
    x: Vec<f64>,
    y: Vec<f64>,
    s: Vec<f64>,
    sol: Vec<f64>,
    /// ‖B x‖ of each iteration's unit x, B = D⁻¹ Π A (unpadded).
    estimates: Vec<f64>,
    /// An iterate vanished: no further estimate.
    vanished: bool,
}

impl PowerIteration {
    /// The power iteration of `op` from its group's fixed start (`fixed_start`).
    pub(crate) fn new(op: &GroupOp) -> Self {
        let x = fixed_start(op);
        let (n, g) = (op.n(), op.len());
        PowerIteration { x, y: vec![0.0; g * n], s: vec![0.0; n], sol: Vec::new(), estimates: Vec::new(), vanished: false }
    }

    /// The power iteration of `op` from the start `x` (a kept iterate of the group's length),
    /// projected onto the group's free subspace.
    pub(crate) fn from_start(op: &GroupOp, mut x: Vec<f64>) -> Self {
        op.project(&mut x);
        let (n, g) = (op.n(), op.len());
        PowerIteration { x, y: vec![0.0; g * n], s: vec![0.0; n], sol: Vec::new(), estimates: Vec::new(), vanished: false }
    }

    /// The unit iterate the last iteration started from (its product's norm is the last
    /// estimate); None before the first iteration or after an iterate vanished.
    pub(crate) fn last_start(&self) -> Option<&[f64]> {
        (!self.estimates.is_empty() && !self.vanished).then_some(self.y.as_slice())
    }

    /// Continues to `iterations` iterations in all (fewer when an iterate vanishes).
    pub(crate) fn run(&mut self, op: &GroupOp, iterations: usize) {
        while self.begin(op, iterations) {
            op.apply_blocks(&mut self.x, &mut self.y, &mut self.s);
            self.finish(op);
        }
    }

    /// Starts the next iteration of a run to `iterations`: normalises the iterate x. False when
    /// the run is done or x vanished (then no iteration follows).
    fn begin(&mut self, op: &GroupOp, iterations: usize) -> bool {
        if self.estimates.len() >= iterations || self.vanished {
            return false;
        }
        let nx = op.norm(&self.x);
        if nx == 0.0 {
            self.vanished = true;
            return false;
        }
        self.x.iter_mut().for_each(|v| *v /= nx);
        true
    }

    /// Ends an iteration whose product A x is in y: y ← Π D⁻¹ y block by block, its norm the
    /// iteration's estimate, and y the next iterate.
    fn finish(&mut self, op: &GroupOp) {
        let n = op.n();
        for k in 0..op.len() {
            op.precondition(k, block_mut(&mut self.y, n, k), &mut self.sol);
        }
        op.project(&mut self.y);
        self.estimates.push(op.norm(&self.y));
        std::mem::swap(&mut self.x, &mut self.y);
    }

    /// The unpadded estimate after `k` ≥ 1 iterations; None when the iteration stopped before.
    pub(crate) fn after(&self, k: usize) -> Option<f64> {
        k.checked_sub(1).and_then(|i| self.estimates.get(i)).copied()
    }
}

/// Continues each power iteration of `runs` (one component's group on `level` each) to
/// `iterations` iterations in all, side by side: each round's products read the rows of the
/// level's operator once for all the runs still going (`LevelOperator::applies`), where a run
/// of its own reads them once per component. Every vector operation is the run's own, so the
/// estimates and iterates are bitwise those of `PowerIteration::run` on each, whatever the
/// thread count.
pub(crate) fn run_side_by_side(level: &Level, runs: &mut [(GroupOp, &mut PowerIteration)], iterations: usize) {
    debug_assert!(runs.iter().all(|(op, _)| op.len() == 1 && std::ptr::eq(op.level(), level)), "groups of one component on the level");
    loop {
        let mut going: Vec<(GroupOp, &mut PowerIteration)> = Vec::with_capacity(runs.len());
        for (op, power) in runs.iter_mut() {
            if !power.begin(op, iterations) {
                continue;
            }
            op.exchange(&mut power.x);
            going.push((*op, &mut **power));
        }
        if going.is_empty() {
            return;
        }
        {
            let flags: Vec<&[u8]> = going.iter().map(|(op, _)| op.flags(0)).collect();
            let mut xs: Vec<&[f64]> = Vec::with_capacity(going.len());
            let mut ys: Vec<&mut [f64]> = Vec::with_capacity(going.len());
            let mut ss: Vec<&mut [f64]> = Vec::with_capacity(going.len());
            for (_, power) in going.iter_mut() {
                let PowerIteration { x, y, s, .. } = &mut **power;
                xs.push(x);
                ys.push(y);
                ss.push(s);
            }
            level.op.applies(&flags, &xs, &mut ys, &mut ss);
        }
        for (op, power) in going {
            power.finish(&op);
        }
    }
}
