//! Conjugate gradients over a distributed level, preconditioned by any fixed symmetric positive
//! operator (`Preconditioner`): the distributed multigrid's V-cycle (`distributed::mg`), or the
//! level's polynomial (Chebyshev–Jacobi) smoother from a zero start (`OneLevel`). The iteration
//! is Chronopoulos and Gear's (1989): it carries s = A p beside p and forms the step from rᵀu
//! and (Au)ᵀu of the preconditioned residual u, so all of an iteration's inner products (with
//! rᵀr for the stopping test) go in one collective.

use super::halo::HaloLayout;
use crate::multigrid::group::{GroupOp, Scratch};
use crate::multigrid::smoother::{smooth, Coefficients, Smoother, Start};
use crate::sparse::{axpy, par_update};

/// What a distributed PCG solve did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Outcome {
    /// Iterations taken.
    pub(crate) iterations: usize,
    /// ‖b − A x‖₂ / ‖b‖₂ at the end, from the true residual.
    pub(crate) rel_residual: f64,
    /// The true residual met the tolerance.
    pub(crate) converged: bool,
    /// pᵀAp was not positive and finite at this iteration.
    pub(crate) breakdown: Option<usize>,
}

/// z = M r for a fixed symmetric positive M over a level's vectors (owned entries then halo;
/// z's halo need not be current). Collective.
pub(crate) trait Preconditioner {
    /// z = M r.
    fn apply(&mut self, r: &[f64], z: &mut [f64]);
}

/// One level's Chebyshev–Jacobi smoother from a zero start, with its scratch.
pub(crate) struct OneLevel<'a> {
    op: GroupOp<'a>,
    sm: Smoother,
    work: Vec<Scratch>,
    coefficients: Coefficients,
}

impl<'a> OneLevel<'a> {
    /// The smoother `sm` of the group `op`.
    pub(crate) fn new(op: GroupOp<'a>, sm: Smoother) -> Self {
        let work = (0..op.len()).map(|_| Scratch::new(op.n(), op.level().op.method)).collect();
        OneLevel { op, sm, work, coefficients: Coefficients::default() }
    }
}

impl Preconditioner for OneLevel<'_> {
    fn apply(&mut self, r: &[f64], z: &mut [f64]) {
        smooth(&self.op, self.sm, r, z, &mut self.work, &mut self.coefficients, Start::Zero, false);
    }
}

/// Restarts from the true residual when the updated one claimed convergence it does not have.
const RESTARTS: usize = 2;

/// Solves A x = b for the group `op` (over `halo`) from x to a relative residual `tol`, in at
/// most `max_iterations` iterations, preconditioned by `pre` (collective).
pub(crate) fn pcg(
    op: &GroupOp,
    halo: &HaloLayout,
    pre: &mut dyn Preconditioner,
    b: &[f64],
    x: &mut [f64],
    tol: f64,
    max_iterations: usize,
) -> Outcome {
    let n = b.len();
    let mut out = Outcome::default();
    let bnorm = op.norm(b);
    if bnorm == 0.0 {
        x.iter_mut().for_each(|v| *v = 0.0);
        out.converged = true;
        return out;
    }
    let [mut r, mut u, mut w, mut p, mut s] = std::array::from_fn(|_| vec![0.0; n]);
    let mut scratch = vec![0.0; op.n()];
    for _ in 0..=RESTARTS {
        op.residual(b, x, &mut r, &mut scratch);
        pre.apply(&r, &mut u);
        op.apply(&mut u, &mut w, &mut scratch);
        let [mut gamma, mut delta, mut rr] = reduced(halo, &r, &u, &w);
        // (γ, α) of the previous iteration; none at a start.
        let mut previous: Option<(f64, f64)> = None;
        while rr.sqrt() > tol * bnorm && out.iterations < max_iterations {
            let (beta, denom) = match previous {
                None => (0.0, delta),
                Some((gamma_prev, alpha_prev)) => {
                    let beta = gamma / gamma_prev;
                    (beta, delta - beta * gamma / alpha_prev)
                }
            };
            // pᵀAp = δ − β γ / α_prev: not positive and finite means A (or the
            // preconditioner) is not positive definite.
            if denom <= 0.0 || !denom.is_finite() {
                out.breakdown = Some(out.iterations + 1);
                break;
            }
            let alpha = gamma / denom;
            let (ur, wr) = (&u, &w);
            par_update(&mut p, |i, v| ur[i] + beta * v);
            par_update(&mut s, |i, v| wr[i] + beta * v);
            axpy(alpha, &p, x);
            axpy(-alpha, &s, &mut r);
            out.iterations += 1;
            pre.apply(&r, &mut u);
            op.apply(&mut u, &mut w, &mut scratch);
            previous = Some((gamma, alpha));
            [gamma, delta, rr] = reduced(halo, &r, &u, &w);
        }
        op.residual(b, x, &mut r, &mut scratch);
        out.rel_residual = op.norm(&r) / bnorm;
        out.converged = out.rel_residual <= tol;
        if out.converged || out.breakdown.is_some() || out.iterations >= max_iterations {
            break;
        }
    }
    out
}

/// (rᵀu, wᵀu, rᵀr) over every rank, in one collective.
fn reduced(halo: &HaloLayout, r: &[f64], u: &[f64], w: &[f64]) -> [f64; 3] {
    let d = halo.dots(&[(r, u), (w, u), (r, r)]);
    [d[0], d[1], d[2]]
}
