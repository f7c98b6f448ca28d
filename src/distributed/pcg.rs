//! Conjugate gradients over a distributed level, preconditioned by the level's polynomial
//! (Chebyshev–Jacobi) smoother from a zero start: a fixed symmetric positive operator, so a valid
//! preconditioner. Each iteration reduces twice: pᵀAp alone, then rᵀz with rᵀr fused into one
//! collective.

use super::halo::HaloLayout;
use crate::multigrid::group::{GroupOp, Scratch};
use crate::multigrid::smoother::{smooth, Smoother, Start};
use crate::operator::Method;
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

/// Restarts from the true residual when the updated one claimed convergence it does not have.
const RESTARTS: usize = 2;

/// Solves A x = b for the group `op` (over `halo`) from x to a relative residual `tol`, in at
/// most `max_iterations` iterations, preconditioned by `sm` (collective).
pub(crate) fn pcg(
    op: &GroupOp,
    halo: &HaloLayout,
    sm: Smoother,
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
    let mut w: Vec<Scratch> = (0..op.len()).map(|_| Scratch::new(op.n(), Method::Laplacian)).collect();
    let (mut r, mut z, mut p, mut q) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut s = vec![0.0; op.n()];
    for _ in 0..=RESTARTS {
        op.residual(b, x, &mut r, &mut s);
        smooth(op, sm, &r, &mut z, &mut w, Start::Zero, false);
        let [mut rz, mut rr] = fused(halo, &r, &z);
        p.copy_from_slice(&z);
        while rr.sqrt() > tol * bnorm && out.iterations < max_iterations {
            out.iterations += 1;
            op.apply(&mut p, &mut q, &mut s);
            let pq = op.dot(&p, &q);
            if pq <= 0.0 || !pq.is_finite() {
                out.breakdown = Some(out.iterations);
                break;
            }
            let alpha = rz / pq;
            axpy(alpha, &p, x);
            axpy(-alpha, &q, &mut r);
            smooth(op, sm, &r, &mut z, &mut w, Start::Zero, false);
            let [rz_new, rr_new] = fused(halo, &r, &z);
            let beta = rz_new / rz;
            (rz, rr) = (rz_new, rr_new);
            let zr = &z;
            par_update(&mut p, |i, d| zr[i] + beta * d);
        }
        op.residual(b, x, &mut r, &mut s);
        out.rel_residual = op.norm(&r) / bnorm;
        out.converged = out.rel_residual <= tol;
        if out.converged || out.breakdown.is_some() || out.iterations >= max_iterations {
            break;
        }
    }
    out
}

/// (rᵀz, rᵀr) over every rank, in one collective.
fn fused(halo: &HaloLayout, r: &[f64], z: &[f64]) -> [f64; 2] {
    let d = halo.dots(&[(r, z), (r, r)]);
    [d[0], d[1]]
}
