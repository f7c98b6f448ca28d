//! Smoothers on one level: damped Jacobi with the l1 bound (paper Eq. 7) and Chebyshev
//! acceleration of the same Jacobi iteration.

use crate::bc::P;
use crate::operator::{LevelOperator, Method};
use crate::sparse::{dot, max_abs, par_fill, par_update};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Smoother {
    /// d_i ← d_i + C (b − A d)_i / D_i, paper Eq. 7 with C = `weight`.
    Jacobi { weight: f64 },
    /// Chebyshev polynomial of D⁻¹A of `degree` on [λmax / lower_ratio, λmax].
    Chebyshev { degree: usize, lower_ratio: f64 },
}

/// Scratch of one level's smoother: the residual (restriction and coarse solves), the
/// biharmonic's S (empty for the second-order methods, which have none) and the direction.
pub struct Scratch {
    pub r: Vec<f64>,
    pub s: Vec<f64>,
    pub d: Vec<f64>,
}

impl Scratch {
    pub fn new(n: usize, method: Method) -> Self {
        let ns = if method == Method::Biharmonic { n } else { 0 };
        Scratch { r: vec![0.0; n], s: vec![0.0; ns], d: vec![0.0; n] }
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

/// One application of the smoother. With `measure`, returns the largest correction it made
/// (an extra pass over the vector, so the hot path asks only where the value is reported);
/// otherwise 0.
pub fn smooth(
    pb: Problem,
    sm: Smoother,
    b: &[f64],
    x: &mut [f64],
    w: &mut Scratch,
    start: Start,
    measure: bool,
) -> f64 {
    match sm {
        Smoother::Jacobi { weight } => jacobi(pb, weight, b, x, w, start, measure),
        Smoother::Chebyshev { degree, lower_ratio } => chebyshev(pb, degree, lower_ratio, b, x, w, start, measure),
    }
}

/// d = c · D⁻¹ (b − A x), with the residual fused into the pass (see `update_with_residual`).
fn first_direction(pb: Problem, c: f64, b: &[f64], x: &[f64], w: &mut Scratch, start: Start) {
    let inv_d = pb.inv_d;
    match start {
        Start::Zero => par_fill(&mut w.d, |i| c * inv_d[i] * b[i]),
        Start::Guess => pb.op.update_with_residual(pb.flags, b, x, &mut w.s, &mut w.d, |i, r, _| c * inv_d[i] * r),
    }
}

/// x ← x + d (x = d from a zero start).
fn step(x: &mut [f64], d: &[f64], start: Start) {
    match start {
        Start::Zero => par_fill(x, |i| d[i]),
        Start::Guess => par_update(x, |i, x| x + d[i]),
    }
}

fn jacobi(pb: Problem, weight: f64, b: &[f64], x: &mut [f64], w: &mut Scratch, start: Start, measure: bool) -> f64 {
    first_direction(pb, weight, b, x, w, start);
    step(x, &w.d, start);
    if measure {
        max_abs(&w.d)
    } else {
        0.0
    }
}

/// The three-term Chebyshev recurrence for D⁻¹A x = D⁻¹b (Saad, Alg. 12.1).
#[allow(clippy::too_many_arguments)]
fn chebyshev(
    pb: Problem,
    degree: usize,
    lower_ratio: f64,
    b: &[f64],
    x: &mut [f64],
    w: &mut Scratch,
    start: Start,
    measure: bool,
) -> f64 {
    let upper = pb.lambda_max;
    let lower = upper / lower_ratio;
    let theta = 0.5 * (upper + lower);
    let delta = 0.5 * (upper - lower);
    let sigma = theta / delta;
    let mut rho = 1.0 / sigma;
    first_direction(pb, 1.0 / theta, b, x, w, start);
    let mut start = start;
    let mut maxc = 0.0f64;
    let inv_d = pb.inv_d;
    for k in 0..degree {
        step(x, &w.d, start);
        start = Start::Guess;
        if measure {
            maxc = maxc.max(max_abs(&w.d));
        }
        if k + 1 == degree {
            break;
        }
        let rho_new = 1.0 / (2.0 * sigma - rho);
        let (c1, c2) = (rho_new * rho, 2.0 * rho_new / delta);
        pb.op.update_with_residual(pb.flags, b, x, &mut w.s, &mut w.d, |i, r, d| c1 * d + c2 * inv_d[i] * r);
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
