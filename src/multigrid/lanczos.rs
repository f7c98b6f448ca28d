//! The Lanczos estimate of λmax(D⁻¹ Π A) for the levels smoothed along lines.
//!
//! On a level with lines the top of D⁻¹A's spectrum is a few modes local to the lines, which a
//! power iteration from a spread start finds slowly (docs/perf-history.md, "The graded sphere's
//! iterations with size"). Lanczos from the same start, in D's inner product (D⁻¹A is
//! self-adjoint there, D the line or point l1 preconditioner, symmetric positive definite),
//! builds the same Krylov space with the same products and finds the top Ritz value θ far
//! sooner; its residual norm ρ = |β_k s_k| (s the Ritz vector in the Lanczos basis) bounds the
//! distance from θ to an eigenvalue, so θ + ρ is the interval's end the smoother is tuned to.

use super::group::{block_mut, fixed_start, GroupOp, POWER_ITERATIONS};

/// The Lanczos steps of an upper estimate: its products, one more than the steps, are the
/// power iteration's.
const STEPS: usize = POWER_ITERATIONS - 1;

/// θ + ρ of `STEPS` Lanczos steps on `op`'s group (`top_ritz`), capped at 1, the l1 bound's
/// guarantee; 1 where the run breaks down.
pub(crate) fn upper_estimate(op: &GroupOp) -> f64 {
    top_ritz(op, STEPS).map_or(1.0, |r| (r.theta + r.residual).min(1.0))
}

/// The top Ritz pair's value and residual norm after a Lanczos run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ritz {
    /// The largest eigenvalue of the Lanczos tridiagonal matrix.
    pub theta: f64,
    /// ‖D⁻¹A v − θ v‖_D of its Ritz vector v (‖v‖_D = 1): |β_k s_k|.
    pub residual: f64,
}

/// Runs `steps` Lanczos steps on D⁻¹ Π A from the group's fixed start (`fixed_start`), each one
/// product and one preconditioner solve as a power iteration's. None when the start has no
/// free part or D is not positive on the Krylov space (the caller falls back to the l1 bound).
pub(crate) fn top_ritz(op: &GroupOp, steps: usize) -> Option<Ritz> {
    let (n, g) = (op.n(), op.len());
    let mut x = fixed_start(op);
    let mut s = vec![0.0; n];
    let mut sol = Vec::new();
    // The D-orthonormal basis vector q, the one before it, and their products with D (kept, so
    // no product with D is formed).
    let mut r = vec![0.0; g * n];
    op.apply_blocks(&mut x, &mut r, &mut s);
    op.project(&mut r);
    let mut z = r.clone();
    let precondition = |z: &mut Vec<f64>, sol: &mut Vec<f64>| {
        for k in 0..g {
            op.precondition(k, block_mut(z, n, k), sol);
        }
        op.project(z);
    };
    precondition(&mut z, &mut sol);
    let mut beta = op.dot(&r, &z).sqrt();
    if !(beta > 0.0 && beta.is_finite()) {
        return None;
    }
    let (mut q, mut dq) = (z.clone(), r.clone());
    q.iter_mut().for_each(|v| *v /= beta);
    dq.iter_mut().for_each(|v| *v /= beta);
    let mut dq_prev = vec![0.0; g * n];
    let (mut alphas, mut betas) = (Vec::with_capacity(steps), Vec::with_capacity(steps));
    let mut w = vec![0.0; g * n];
    let mut beta_prev = 0.0;
    for _ in 0..steps {
        op.apply_blocks(&mut q, &mut w, &mut s);
        op.project(&mut w);
        let alpha = op.dot(&q, &w);
        for ((w, d), p) in w.iter_mut().zip(&dq).zip(&dq_prev) {
            *w -= alpha * d + beta_prev * p;
        }
        r.copy_from_slice(&w);
        z.copy_from_slice(&w);
        precondition(&mut z, &mut sol);
        let rz = op.dot(&r, &z);
        if !(rz >= 0.0 && rz.is_finite() && alpha.is_finite()) {
            return None;
        }
        beta = rz.sqrt();
        alphas.push(alpha);
        betas.push(beta);
        if beta == 0.0 {
            break;
        }
        std::mem::swap(&mut dq_prev, &mut dq);
        q.iter_mut().zip(&z).for_each(|(q, z)| *q = z / beta);
        dq.iter_mut().zip(&r).for_each(|(d, r)| *d = r / beta);
        beta_prev = beta;
    }
    let k = alphas.len();
    let theta = top_eigenvalue(&alphas, &betas[..k.saturating_sub(1)])?;
    let last = last_component_squared(&alphas, &betas[..k - 1], theta).sqrt();
    Some(Ritz { theta, residual: betas[k - 1] * last })
}

/// The number of eigenvalues below `x` of the symmetric tridiagonal matrix with diagonal `a`
/// and off-diagonal `b` (Sturm's count by the LDLᵀ pivots).
fn count_below(a: &[f64], b: &[f64], x: f64) -> usize {
    let mut count = 0;
    let mut d = 1.0;
    for (i, &ai) in a.iter().enumerate() {
        let off = if i > 0 { b[i - 1] * b[i - 1] / d } else { 0.0 };
        d = ai - x - off;
        if d == 0.0 {
            d = -f64::EPSILON * (ai.abs() + x.abs()).max(f64::MIN_POSITIVE);
        }
        if d < 0.0 {
            count += 1;
        }
    }
    count
}

/// The largest eigenvalue of the symmetric tridiagonal matrix (`a`, `b`) by bisection within
/// its Gershgorin interval; None for an empty or non-finite matrix.
fn top_eigenvalue(a: &[f64], b: &[f64]) -> Option<f64> {
    if a.is_empty() || a.iter().chain(b).any(|v| !v.is_finite()) {
        return None;
    }
    let radius = |i: usize| b.get(i).map_or(0.0, |v: &f64| v.abs()) + i.checked_sub(1).map_or(0.0, |j| b[j].abs());
    let (mut lo, mut hi) = (0..a.len()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), i| {
        (lo.min(a[i] - radius(i)), hi.max(a[i] + radius(i)))
    });
    let m = a.len();
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if count_below(a, b, mid) < m {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(hi)
}

/// The squared last component of the unit eigenvector of the tridiagonal matrix (`a`, `b`) for
/// its eigenvalue `theta`: p_{k−1}(θ) / p_k′(θ), p_i the characteristic polynomials of the
/// leading i×i blocks (a ratio in [0, 1]; clamped there against rounding).
fn last_component_squared(a: &[f64], b: &[f64], theta: f64) -> f64 {
    let k = a.len();
    if k == 1 {
        return 1.0;
    }
    // p_i(θ) and p_i'(θ) by the three-term recurrence, rescaled together as they go.
    let (mut p_prev, mut p) = (1.0, theta - a[0]);
    let (mut dp_prev, mut dp) = (0.0, 1.0);
    for i in 1..k {
        let b2 = b[i - 1] * b[i - 1];
        let p_next = (theta - a[i]) * p - b2 * p_prev;
        let dp_next = p + (theta - a[i]) * dp - b2 * dp_prev;
        (p_prev, p, dp_prev, dp) = (p, p_next, dp, dp_next);
        let scale = p.abs().max(dp.abs()).max(p_prev.abs()).max(dp_prev.abs());
        if scale > 1e100 || (scale < 1e-100 && scale > 0.0) {
            (p_prev, p, dp_prev, dp) = (p_prev / scale, p / scale, dp_prev / scale, dp / scale);
        }
    }
    let ratio = p_prev / dp;
    if ratio.is_finite() {
        ratio.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bc::Kind;
    use crate::mesh::fixtures::rect;
    use crate::multigrid::group::estimate_lambda_max;
    use crate::multigrid::hierarchy::{Hierarchy, HierarchyParams};
    use crate::{BoundaryConditions, Method};

    /// On a finest level with wall layers (cells 1e-4 high at the clamped wall), smoothed along
    /// lines: the Ritz value grows with the steps, the bound of `STEPS` steps lies above the
    /// converged top eigenvalue (100 steps) by less than 5%, and the level's estimate is not
    /// below it.
    #[test]
    fn the_bound_on_lines_covers_the_converged_top() {
        let mesh = rect(20, 20, [0.0, 1.0, 0.0, 1.0]);
        let layered: Vec<f64> = mesh.coords().chunks(2).flat_map(|p| [p[0], p[1].powi(4)]).collect();
        let mesh = mesh.with_coords(layered);
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(1, Kind::Clamped).set_kinds(3, Kind::Fixed);
        let h = Hierarchy::build(&mesh, Vec::new(), &bcs, Method::Biharmonic, &HierarchyParams::default()).unwrap();
        let op = GroupOp::new(&h.levels[0], 0..1, false);
        assert!(op.lines(0).is_some(), "the layers are lines");
        let converged = top_ritz(&op, 100).unwrap().theta;
        let short = top_ritz(&op, STEPS).unwrap();
        assert!(short.theta <= converged + 1e-12 && short.theta >= 0.5 * converged, "{short:?} against {converged}");
        let bound = upper_estimate(&op);
        assert!(bound >= converged && bound <= 1.05 * converged, "{bound} against {converged}");
        assert!(estimate_lambda_max(&op) >= bound);
        assert_eq!(h.levels[0].lambda_max[0].to_bits(), estimate_lambda_max(&op).to_bits());
    }

    /// The tridiagonal matrix's top eigenpair against the closed form of the second-difference
    /// matrix (eigenvalues 2 − 2 cos(jπ/(k+1)), eigenvectors sin(ijπ/(k+1))).
    #[test]
    fn the_top_eigenpair_of_a_second_difference() {
        for k in [1usize, 2, 5, 15] {
            let a = vec![2.0; k];
            let b = vec![-1.0; k - 1];
            let h = std::f64::consts::PI / (k as f64 + 1.0);
            let want = 2.0 - 2.0 * (k as f64 * h).cos();
            let theta = top_eigenvalue(&a, &b).unwrap();
            assert!((theta - want).abs() <= 1e-12, "k {k}: {theta} against {want}");
            let v: Vec<f64> = (1..=k).map(|i| (i as f64 * k as f64 * h).sin()).collect();
            let last = v[k - 1] * v[k - 1] / v.iter().map(|x| x * x).sum::<f64>();
            let got = last_component_squared(&a, &b, theta);
            assert!((got - last).abs() <= 1e-9, "k {k}: {got} against {last}");
        }
        assert_eq!(count_below(&[1.0, 3.0], &[0.0], 2.0), 1);
        assert_eq!(top_eigenvalue(&[], &[]), None);
    }
}
