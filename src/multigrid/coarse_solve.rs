//! The coarsest level's solve: dense Cholesky of A on the free unknowns.

use super::smoother::{smooth, Problem, Scratch, Smoother, Start};
use crate::bc::P;
use crate::dense::Cholesky;
use crate::{Error, Result};

/// Above this many free unknowns the coarsest level is smoothed, not factored (only when
/// coarsening stopped early on an awkward mesh).
pub(super) const DENSE_MAX: usize = 1500;

/// The Cholesky factor of the dense m×m matrix `a` assembled column by column from operator
/// products, its rounding symmetrised first so Cholesky sees an exactly symmetric matrix; None
/// when it is not positive definite.
pub(super) fn symmetric_cholesky(m: usize, mut a: Vec<f64>) -> Option<Cholesky> {
    for i in 0..m {
        for j in 0..i {
            let v = 0.5 * (a[i * m + j] + a[j * m + i]);
            a[i * m + j] = v;
            a[j * m + i] = v;
        }
    }
    Cholesky::new(m, &a)
}

pub enum CoarseSolve {
    Dense {
        free: Vec<u32>,
        chol: Cholesky,
    },
    /// A fixed Chebyshev polynomial: linear in b, so still a valid preconditioner.
    Smoothed,
    /// No free unknown: the correction is zero.
    Empty,
}

impl CoarseSolve {
    /// The coarse solve of component `component` (named in the error when A is not positive
    /// definite there).
    pub fn new(pb: Problem, component: usize) -> Result<CoarseSolve> {
        let n = pb.op.n();
        let free: Vec<u32> = (0..n as u32).filter(|&i| pb.flags[i as usize] & P == 0).collect();
        let m = free.len();
        if m == 0 {
            return Ok(CoarseSolve::Empty);
        }
        if m > DENSE_MAX {
            return Ok(CoarseSolve::Smoothed);
        }
        let mut a = vec![0.0; m * m];
        let (mut e, mut y, mut s) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for (jj, &j) in free.iter().enumerate() {
            e[j as usize] = 1.0;
            pb.op.apply(pb.flags, &e, &mut y, &mut s);
            e[j as usize] = 0.0;
            for (ii, &i) in free.iter().enumerate() {
                a[ii * m + jj] = y[i as usize];
            }
        }
        // Every connected part has a prescribed vertex (checked on the fine level first), so a
        // coarsest operator that is not positive definite comes from the geometry of the levels.
        let chol = symmetric_cholesky(m, a).ok_or_else(|| {
            Error::Coarsening(format!(
                "the coarsest level's {} operator is not positive definite ({m} free unknowns): a coarse cell is \
                 degenerate or inverted",
                crate::bc::COMPONENT[component]
            ))
        })?;
        Ok(CoarseSolve::Dense { free, chol })
    }

    /// x ← x + A⁻¹(b − A x).
    /// x ← x + A⁻¹(b − A x) on the free unknowns; from `Start::Zero`, x = A⁻¹ b.
    pub fn solve(&self, pb: Problem, b: &[f64], x: &mut [f64], start: Start, w: &mut Scratch) {
        if start == Start::Zero {
            x.iter_mut().for_each(|v| *v = 0.0);
        }
        match self {
            CoarseSolve::Empty => {}
            CoarseSolve::Smoothed => {
                for _ in 0..4 {
                    smooth(pb, Smoother::Chebyshev { degree: 25, lower_ratio: 200.0 }, b, x, w, Start::Guess, false);
                }
            }
            CoarseSolve::Dense { free, chol } => {
                let r: &[f64] = match start {
                    Start::Zero => b,
                    Start::Guess => {
                        pb.op.residual(pb.flags, b, x, &mut w.r, &mut w.s);
                        &w.r
                    }
                };
                let mut rhs: Vec<f64> = free.iter().map(|&i| r[i as usize]).collect();
                chol.solve(&mut rhs);
                for (&i, v) in free.iter().zip(rhs) {
                    x[i as usize] += v;
                }
            }
        }
    }
}
