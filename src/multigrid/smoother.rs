//! Smoothers on one level: damped Jacobi with the l1 bound (paper Eq. 7) and Chebyshev
//! acceleration of the same Jacobi iteration.

use super::group::{block, block_mut, GroupOp, Problem, Scratch};

use crate::sparse::par_update2;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Smoother {
    /// d_i ← d_i + C (b − A d)_i / D_i, paper Eq. 7 with C = `weight`.
    Jacobi { weight: f64 },
    /// Chebyshev polynomial of D⁻¹A of `degree` on [λmax / lower_ratio, λmax] (first kind).
    Chebyshev { degree: usize, lower_ratio: f64 },
    /// Fourth-kind Chebyshev polynomial of D⁻¹A of `degree` (Lottes 2023, "Optimal polynomial
    /// smoothers for multigrid V-cycles"): it damps all of (0, λmax] with weight on the high end,
    /// so it needs no lower bound: on the boundary-layer cylinder's wall layer it converges where
    /// the first kind stalls (docs/perf-history.md).
    Fourth { degree: usize },
}

/// What `x` holds when a smoother starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    /// An iterate: the first residual is b − A x.
    Guess,
    /// Nothing (its content is ignored and overwritten): x = 0, so the first residual is b and
    /// costs no operator application. Every coarse-level visit and every preconditioner
    /// application in CG starts so; skipping that application saves one of the 13 per visit.
    Zero,
}

/// The first step's coefficient and the (c1, c2) of the others of `sm` for a given λmax.
fn coefficients(sm: Smoother, lambda_max: f64) -> (f64, Vec<(f64, f64)>) {
    match sm {
        Smoother::Jacobi { weight } => (weight, Vec::new()),
        Smoother::Chebyshev { degree, lower_ratio } => {
            let (c0, steps) = first_kind(lambda_max, degree, lower_ratio);
            (c0, steps.collect())
        }
        Smoother::Fourth { degree } => {
            let (c0, steps) = fourth_kind(lambda_max, degree);
            (c0, steps.collect())
        }
    }
}

/// A smoother's coefficients for each block of a group, kept for the smoother and the λmax
/// they were computed for: the cycle calls `smooth` on a level many times between two refreshes
/// of its bounds, and each call finds them here instead of running the recurrence again.
#[derive(Default)]
pub(crate) struct Coefficients {
    /// The smoother and each block's λmax (as bits) the coefficients are for.
    smoother: Option<Smoother>,
    lambda_bits: Vec<u64>,
    /// Per block: the first step's coefficient and the (c1, c2) of the others.
    blocks: Vec<(f64, Vec<(f64, f64)>)>,
}

impl Coefficients {
    /// The coefficients of `sm` for each block of `op`, computed again only when the smoother
    /// or a block's λmax differs from the last call's.
    fn for_group(&mut self, op: &GroupOp, sm: Smoother) -> &[(f64, Vec<(f64, f64)>)] {
        let g = op.len();
        let same = self.smoother == Some(sm)
            && self.lambda_bits.len() == g
            && (0..g).all(|k| self.lambda_bits[k] == op.lambda_max(k).to_bits());
        if !same {
            self.smoother = Some(sm);
            self.lambda_bits = (0..g).map(|k| op.lambda_max(k).to_bits()).collect();
            self.blocks = (0..g).map(|k| coefficients(sm, op.lambda_max(k))).collect();
        }
        &self.blocks
    }
}

/// One application of the smoother `sm` to the group `op`: a polynomial of D⁻¹A as a two-term
/// recurrence (damped Jacobi is its one-step case), every block's step in lockstep and each
/// step moved into the group's free subspace (for a coupled group, one polynomial of the
/// group's λmax; D⁻¹ commutes with the projection there, see `multigrid::slip`). `w` holds one
/// scratch per block, `cache` the coefficients of the level's last call. With `measure`, returns
/// the largest correction it made (an extra pass over the vector, so the hot path asks only
/// where the value is reported); otherwise 0.
#[allow(clippy::too_many_arguments)]
pub(crate) fn smooth(
    op: &GroupOp,
    sm: Smoother,
    b: &[f64],
    x: &mut [f64],
    w: &mut [Scratch],
    cache: &mut Coefficients,
    start: Start,
    measure: bool,
) -> f64 {
    let (n, g) = (op.n(), op.len());
    let w = &mut w[..g];
    let coeffs = cache.for_group(op, sm);
    if start == Start::Guess {
        op.exchange(x);
    }
    // A group smoothed along lines in every block forms its blocks' residuals in one pass.
    let lined = g > 1 && (0..g).all(|k| op.lines(k).is_some());
    if lined {
        line_residuals(op, b, x, w, start);
    }
    for (k, wk) in w.iter_mut().enumerate() {
        let (bk, xk) = (block(b, n, k), block_mut(x, n, k));
        match op.lines(k) {
            None => first_step(op.problem(k), coeffs[k].0, bk, xk, wk, start),
            Some(_) if lined => line_update(op, k, (0.0, coeffs[k].0), xk, wk, start),
            Some(_) => line_step(op, k, (0.0, coeffs[k].0), bk, xk, wk, start),
        }
    }
    op.project_step(x, w);
    let mut maxc = measured(op, measure, w);
    for j in 0..coeffs[0].1.len() {
        op.exchange(x);
        if lined {
            line_residuals(op, b, x, w, Start::Guess);
        }
        for (k, wk) in w.iter_mut().enumerate() {
            let (c1, c2) = coeffs[k].1[j];
            let (bk, xk) = (block(b, n, k), block_mut(x, n, k));
            match op.lines(k) {
                None => next_step(op.problem(k), c1, c2, bk, xk, wk),
                Some(_) if lined => line_update(op, k, (c1, c2), xk, wk, Start::Guess),
                Some(_) => line_step(op, k, (c1, c2), bk, xk, wk, Start::Guess),
            }
        }
        op.project_step(x, w);
        maxc = maxc.max(measured(op, measure, w));
    }
    maxc
}

/// d = c · D⁻¹ (b − A x), then x ← x + d (x = d from a zero start): the first step of every
/// smoother, with the residual fused into the pass (see `LevelOperator::step_with_residual`).
fn first_step(pb: Problem, c: f64, b: &[f64], x: &mut [f64], w: &mut Scratch, start: Start) {
    let inv_d = pb.inv_d;
    match start {
        Start::Zero => par_update2(x, &mut w.d, |i, _, _| {
            let d = c * inv_d[i] * b[i];
            (d, d)
        }),
        Start::Guess => pb.op.step_with_residual(pb.flags, b, x, &mut w.s, &mut w.d, |i, r, _| c * inv_d[i] * r),
    }
}

/// d ← c1 d + c2 D⁻¹ (b − A x), then x ← x + d: one step of a polynomial smoother's recurrence.
fn next_step(pb: Problem, c1: f64, c2: f64, b: &[f64], x: &mut [f64], w: &mut Scratch) {
    let inv_d = pb.inv_d;
    pb.op.step_with_residual(pb.flags, b, x, &mut w.s, &mut w.d, |i, r, d| c1 * d + c2 * inv_d[i] * r);
}

/// d ← c1 d + c2 D⁻¹ (b − A x), then x ← x + d, with D the line blocks of block `k`
/// (`GroupOp::precondition`): the residual is formed first, as the line solves need all of it.
/// From `Start::Zero`, x = 0, d = c2 D⁻¹ b and x = d (c1 and x's content ignored).
fn line_step(op: &GroupOp, k: usize, c: (f64, f64), b: &[f64], x: &mut [f64], w: &mut Scratch, start: Start) {
    let pb = op.problem(k);
    w.r.resize(b.len(), 0.0);
    match start {
        Start::Zero => w.r.copy_from_slice(b),
        Start::Guess => pb.op.residual(pb.flags, b, x, &mut w.r, &mut w.s),
    }
    line_update(op, k, c, x, w, start);
}

/// `line_step`'s residual for every block of the group into its scratch's `r`, each row of the
/// operator read once for all the blocks (`GroupOp::residuals`); bitwise the blocks' own.
fn line_residuals(op: &GroupOp, b: &[f64], x: &[f64], w: &mut [Scratch], start: Start) {
    let n = op.n();
    w.iter_mut().for_each(|wk| wk.r.resize(n, 0.0));
    match start {
        Start::Zero => w.iter_mut().enumerate().for_each(|(k, wk)| wk.r.copy_from_slice(block(b, n, k))),
        Start::Guess => {
            let (mut r, mut s): (Vec<&mut [f64]>, Vec<&mut [f64]>) =
                w.iter_mut().map(|wk| (&mut wk.r[..], &mut wk.s[..])).unzip();
            op.residuals(b, x, &mut r, &mut s);
        }
    }
}

/// The rest of `line_step` from the residual in `w.r`: the line solves and the update of the
/// step and the iterate.
fn line_update(op: &GroupOp, k: usize, (c1, c2): (f64, f64), x: &mut [f64], w: &mut Scratch, start: Start) {
    op.precondition(k, &mut w.r, &mut w.sol);
    let z = &w.r;
    match start {
        Start::Zero => par_update2(x, &mut w.d, |i, _, _| {
            let d = c2 * z[i];
            (d, d)
        }),
        // The first step (c1 = 0) ignores the d of an earlier application.
        Start::Guess => par_update2(x, &mut w.d, |i, x, d| {
            let d = if c1 == 0.0 { c2 * z[i] } else { c1 * d + c2 * z[i] };
            (x + d, d)
        }),
    }
}

/// The largest correction of a step over the blocks' `d`, when asked (an extra pass, so only
/// where reported).
fn measured(op: &GroupOp, measure: bool, w: &[Scratch]) -> f64 {
    match w {
        _ if !measure => 0.0,
        [one] => op.max_abs(&one.d),
        _ => w.iter().map(|s| op.max_abs(&s.d)).fold(0.0, f64::max),
    }
}

/// Coefficients of the three-term Chebyshev recurrence for D⁻¹A x = D⁻¹b on [λmax / ratio,
/// λmax] (Saad, Alg. 12.1): the first step's, then (c1, c2) of the others.
pub(super) fn first_kind(lambda_max: f64, degree: usize, lower_ratio: f64) -> (f64, impl Iterator<Item = (f64, f64)>) {
    let lower = lambda_max / lower_ratio;
    let theta = 0.5 * (lambda_max + lower);
    let delta = 0.5 * (lambda_max - lower);
    let sigma = theta / delta;
    let steps = (1..degree).scan(1.0 / sigma, move |rho, _| {
        let rho_new = 1.0 / (2.0 * sigma - *rho);
        let c = (rho_new * *rho, 2.0 * rho_new / delta);
        *rho = rho_new;
        Some(c)
    });
    (1.0 / theta, steps)
}

/// Coefficients of the fourth-kind recurrence with ρ = λmax (Lottes 2023, Alg. 3 with all
/// β = 1; the "optimised" β of that paper took more CG iterations here, docs/perf-history.md):
/// d₀ = 4/(3ρ) D⁻¹r₀, d_k = (2k−1)/(2k+3) d_{k−1} + (8k+4)/((2k+3)ρ) D⁻¹r_k.
pub(super) fn fourth_kind(rho: f64, degree: usize) -> (f64, impl Iterator<Item = (f64, f64)>) {
    let steps = (1..degree).map(move |k| {
        let k = k as f64;
        ((2.0 * k - 1.0) / (2.0 * k + 3.0), (8.0 * k + 4.0) / ((2.0 * k + 3.0) * rho))
    });
    (4.0 / (3.0 * rho), steps)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The error polynomial p(λ) of a smoother's coefficients, run on the scalar problem
    /// λ x = λ from x = 0 (D = 1), exactly as `smooth` runs them.
    fn error_polynomial(c0: f64, steps: impl Iterator<Item = (f64, f64)>, lambda: f64) -> f64 {
        let mut d = c0 * lambda;
        let mut x = d;
        for (c1, c2) in steps {
            d = c1 * d + c2 * (lambda - lambda * x);
            x += d;
        }
        1.0 - x
    }

    #[test]
    fn fourth_kind_meets_its_optimal_bound() {
        // Lottes 2023: max over (0, ρ] of √(λ/ρ) |p(λ)| is 1/(2k+1) for the fourth kind.
        let rho = 0.8;
        for k in [1, 2, 4, 6, 10] {
            let worst = (1..=4000)
                .map(|i| rho * i as f64 / 4000.0)
                .map(|l| {
                    let (c0, steps) = fourth_kind(rho, k);
                    (l / rho).sqrt() * error_polynomial(c0, steps, l).abs()
                })
                .fold(0.0, f64::max);
            let bound = 1.0 / (2 * k + 1) as f64;
            assert!((worst - bound).abs() < 1e-3 * bound, "degree {k}: {worst} vs {bound}");
        }
    }

    #[test]
    fn first_kind_is_the_chebyshev_minimax_on_its_interval() {
        // On [λmax/r, λmax] the first kind's |p| is at most 1/T_k(σ) with σ = (λmax+λmin)/(λmax−λmin).
        let (lmax, r, k) = (1.0, 20.0, 6);
        let sigma: f64 = (lmax + lmax / r) / (lmax - lmax / r);
        let bound = 1.0 / (k as f64 * sigma.acosh()).cosh();
        let worst = (0..=4000)
            .map(|i| lmax / r + (lmax - lmax / r) * i as f64 / 4000.0)
            .map(|l| {
                let (c0, steps) = first_kind(lmax, k, r);
                error_polynomial(c0, steps, l).abs()
            })
            .fold(0.0, f64::max);
        assert!((worst - bound).abs() < 1e-9 + 1e-6 * bound, "{worst} vs {bound}");
    }
}
