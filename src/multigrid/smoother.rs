//! Smoothers on one level: damped Jacobi with the l1 bound (paper Eq. 7) and Chebyshev
//! acceleration of the same Jacobi iteration.

use crate::bc::P;
use crate::operator::LevelOperator;
use crate::sparse::{dot, max_abs, par_fill, par_update};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Smoother {
    /// d_i ← d_i + C (b − A d)_i / D_i, paper Eq. 7 with C = `weight`.
    Jacobi { weight: f64 },
    /// Chebyshev polynomial of D⁻¹A of `degree` on [λmax / lower_ratio, λmax].
    Chebyshev { degree: usize, lower_ratio: f64 },
}

/// Scratch of one level's smoother.
pub struct Scratch {
    pub r: Vec<f64>,
    pub s: Vec<f64>,
    pub d: Vec<f64>,
}

impl Scratch {
    pub fn new(n: usize) -> Self {
        Scratch { r: vec![0.0; n], s: vec![0.0; n], d: vec![0.0; n] }
    }
}

/// The operator of one level and component, with its Jacobi bound.
#[derive(Clone, Copy)]
pub struct Problem<'a> {
    pub op: &'a LevelOperator,
    pub flags: &'a [u8],
    pub inv_d: &'a [f64],
    pub lambda_max: f64,
}

/// One application of the smoother. With `measure`, returns the largest correction it made
/// (an extra pass over the vector, so the hot path asks only where the value is reported);
/// otherwise 0.
pub fn smooth(pb: Problem, sm: Smoother, b: &[f64], x: &mut [f64], w: &mut Scratch, measure: bool) -> f64 {
    match sm {
        Smoother::Jacobi { weight } => jacobi(pb, weight, b, x, w, measure),
        Smoother::Chebyshev { degree, lower_ratio } => chebyshev(pb, degree, lower_ratio, b, x, w, measure),
    }
}

fn jacobi(pb: Problem, weight: f64, b: &[f64], x: &mut [f64], w: &mut Scratch, measure: bool) -> f64 {
    pb.op.residual(pb.flags, b, x, &mut w.r, &mut w.s);
    let r = &w.r;
    par_fill(&mut w.d, |i| weight * pb.inv_d[i] * r[i]);
    let d = &w.d;
    par_update(x, |i, x| x + d[i]);
    if measure {
        max_abs(&w.d)
    } else {
        0.0
    }
}

/// The three-term Chebyshev recurrence for D⁻¹A x = D⁻¹b (Saad, Alg. 12.1).
fn chebyshev(
    pb: Problem,
    degree: usize,
    lower_ratio: f64,
    b: &[f64],
    x: &mut [f64],
    w: &mut Scratch,
    measure: bool,
) -> f64 {
    let upper = pb.lambda_max;
    let lower = upper / lower_ratio;
    let theta = 0.5 * (upper + lower);
    let delta = 0.5 * (upper - lower);
    let sigma = theta / delta;
    let mut rho = 1.0 / sigma;
    pb.op.residual(pb.flags, b, x, &mut w.r, &mut w.s);
    let r = &w.r;
    par_fill(&mut w.d, |i| pb.inv_d[i] * r[i] / theta);
    let mut maxc = 0.0f64;
    for k in 0..degree {
        let d = &w.d;
        par_update(x, |i, x| x + d[i]);
        if measure {
            maxc = maxc.max(max_abs(&w.d));
        }
        if k + 1 == degree {
            break;
        }
        pb.op.residual(pb.flags, b, x, &mut w.r, &mut w.s);
        let rho_new = 1.0 / (2.0 * sigma - rho);
        let (c1, c2) = (rho_new * rho, 2.0 * rho_new / delta);
        let r = &w.r;
        par_update(&mut w.d, |i, d| c1 * d + c2 * pb.inv_d[i] * r[i]);
        rho = rho_new;
    }
    maxc
}

/// Largest eigenvalue of D⁻¹A by power iteration from a fixed start (deterministic), padded by
/// 10% and capped at 1, the l1 bound's guarantee.
pub fn estimate_lambda_max(op: &LevelOperator, flags: &[u8], inv_d: &[f64]) -> f64 {
    let n = op.n();
    // A fixed, mode-rich start vector: a cheap hash of the index.
    let mut x: Vec<f64> =
        (0..n)
            .map(|i| {
                if flags[i] & P != 0 {
                    0.0
                } else {
                    ((i as u64).wrapping_mul(2654435761) % 1000) as f64 / 1000.0 - 0.5
                }
            })
            .collect();
    let (mut y, mut s) = (vec![0.0; n], vec![0.0; n]);
    let mut lambda = 0.0;
    for _ in 0..15 {
        let nx = dot(&x, &x).sqrt();
        if nx == 0.0 {
            return 1.0;
        }
        x.iter_mut().for_each(|v| *v /= nx);
        op.apply(flags, &x, &mut y, &mut s);
        y.iter_mut().zip(inv_d).for_each(|(y, d)| *y *= d);
        lambda = dot(&y, &y).sqrt();
        std::mem::swap(&mut x, &mut y);
    }
    (1.1 * lambda).clamp(0.05, 1.0)
}
