//! The coarsest level's solve of a group: Π A Π on a basis of the group's free directions (unit
//! vectors of free components; a slip unknown's tangents), dense Cholesky.

use super::group::{GroupOp, Scratch};
use super::smoother::{smooth, Coefficients, Smoother, Start};
use crate::bc::P;
use crate::dense::Cholesky;
use crate::operator::Method;
use crate::{Error, Result};

/// Above this many free directions the coarsest level is smoothed, not factored (only when
/// coarsening stopped early on an awkward mesh).
pub(crate) const DENSE_MAX: usize = 1500;

/// The coarsest level's solve where it is smoothed: Chebyshev polynomials of the smoother.
const SMOOTHED: Smoother = Smoother::Chebyshev { degree: 25, lower_ratio: 200.0 };

/// How many `SMOOTHED` polynomials a smoothed coarsest level of `method` applies. Such a level
/// is a deep Galerkin level of dense rows (where a wing's wall layers stop the coarsening), each
/// application a sizeable part of a fine-level sweep. The second-order operators take one: more
/// leave the conjugate gradients' counts as they are on the viscous meshes and multiply the
/// cycle's cost (docs/PERFORMANCE.md, "The wing's Laplacian and spring a vertex"). The
/// biharmonic's coarsest operator has the square of their condition number and keeps four.
fn polynomials(method: Method) -> usize {
    match method {
        Method::Biharmonic => 4,
        Method::Laplacian | Method::Spring => 1,
    }
}

/// The Cholesky factor of the dense m×m matrix `a` assembled column by column from operator
/// products, its rounding symmetrised first so Cholesky sees an exactly symmetric matrix; None
/// when it is not positive definite.
pub(crate) fn symmetric_cholesky(m: usize, mut a: Vec<f64>) -> Option<Cholesky> {
    for i in 0..m {
        for j in 0..i {
            let v = 0.5 * (a[i * m + j] + a[j * m + i]);
            a[i * m + j] = v;
            a[j * m + i] = v;
        }
    }
    Cholesky::new(m, &a)
}

/// The coarsest level's solve of one group.
pub enum CoarseSolve {
    /// The basis vectors (unknown, coefficient per block of the group) and the factor.
    Dense { basis: Vec<(u32, [f64; 3])>, chol: Cholesky },
    /// Too many free directions: fixed Chebyshev polynomials of the smoother (`SMOOTHED`, this
    /// many), linear in b, so still a valid preconditioner.
    Smoothed(usize),
    /// Nothing free: the correction is zero.
    Empty,
}

/// The free directions of the group `op`, grouped by unknown in ascending order.
fn free_basis(op: &GroupOp) -> Vec<(u32, [f64; 3])> {
    let (n, g) = (op.n(), op.len());
    let mut basis: Vec<(u32, [f64; 3])> = Vec::new();
    let mut k = 0;
    for d in 0..n {
        let prescribed: Vec<bool> = (0..g).map(|c| op.flags(c)[d] & P != 0).collect();
        match op.frames() {
            Some(frames) if frames.dofs.get(k) == Some(&(d as u32)) => {
                basis.extend(frames.tangents(k, &prescribed).into_iter().map(|t| (d as u32, t)));
                k += 1;
            }
            _ => {
                for c in (0..g).filter(|&c| !prescribed[c]) {
                    let mut e = [0.0; 3];
                    e[c] = 1.0;
                    basis.push((d as u32, e));
                }
            }
        }
    }
    basis
}

impl CoarseSolve {
    /// The coarse solve of the group `op` (named in the error when Π A Π is not positive
    /// definite there).
    pub(crate) fn new(op: &GroupOp) -> Result<CoarseSolve> {
        let (n, g) = (op.n(), op.len());
        let basis = free_basis(op);
        let m = basis.len();
        if m == 0 {
            return Ok(CoarseSolve::Empty);
        }
        if m > DENSE_MAX {
            return Ok(CoarseSolve::Smoothed(polynomials(op.level().op.method)));
        }
        // Column by column: A_c e_j for each unknown j and block c, then the basis vectors at j
        // combine them; basis vectors are grouped by unknown.
        let mut a = vec![0.0; m * m];
        let (mut e, mut s) = (vec![0.0; n], vec![0.0; n]);
        let mut y: Vec<Vec<f64>> = vec![vec![0.0; n]; g];
        let mut first = 0;
        while first < m {
            let j = basis[first].0;
            let last = first + basis[first..].iter().take_while(|b| b.0 == j).count();
            for (c, yc) in y.iter_mut().enumerate() {
                if basis[first..last].iter().all(|b| b.1[c] == 0.0) {
                    yc.iter_mut().for_each(|v| *v = 0.0);
                    continue;
                }
                e[j as usize] = 1.0;
                op.level().op.apply(op.flags(c), &e, yc, &mut s);
                e[j as usize] = 0.0;
            }
            for beta in first..last {
                let cb = basis[beta].1;
                for (alpha, &(i, ca)) in basis.iter().enumerate() {
                    a[alpha * m + beta] = (0..g).map(|c| ca[c] * cb[c] * y[c][i as usize]).sum();
                }
            }
            first = last;
        }
        // Every connected part has a prescribed vertex (checked on the fine level first), so a
        // coarsest operator that is not positive definite comes from the geometry of the levels.
        let chol = symmetric_cholesky(m, a).ok_or_else(|| {
            Error::Coarsening(match op.frames() {
                Some(_) => format!(
                    "the coarsest level's coupled slip operator is not positive definite ({m} free directions): a \
                     coarse cell is degenerate or inverted, or the slip walls leave a direction free"
                ),
                None => format!(
                    "the coarsest level's {} operator is not positive definite ({m} free unknowns): a coarse cell is \
                     degenerate or inverted",
                    crate::bc::COMPONENT[op.components().start]
                ),
            })
        })?;
        Ok(CoarseSolve::Dense { basis, chol })
    }

    /// x ← x + (Π A Π)⁻¹ Π (b − A x) on the group `op`; from `Start::Zero`, x = (Π A Π)⁻¹ b.
    /// `r` is scratch of the group's length, `w` one smoother scratch per block.
    pub(crate) fn solve(&self, op: &GroupOp, b: &[f64], x: &mut [f64], start: Start, r: &mut [f64], w: &mut [Scratch]) {
        if start == Start::Zero {
            x.iter_mut().for_each(|v| *v = 0.0);
        }
        let (n, g) = (op.n(), op.len());
        match self {
            CoarseSolve::Empty => {}
            CoarseSolve::Smoothed(polynomials) => {
                let mut cache = Coefficients::default();
                for _ in 0..*polynomials {
                    smooth(op, SMOOTHED, b, x, w, &mut cache, Start::Guess, false);
                }
            }
            CoarseSolve::Dense { basis, chol } => {
                let r: &[f64] = match start {
                    Start::Zero => b,
                    Start::Guess => {
                        op.residual(b, x, r, &mut w[0].s);
                        r
                    }
                };
                let mut rhs: Vec<f64> =
                    basis.iter().map(|&(i, t)| (0..g).map(|c| t[c] * r[c * n + i as usize]).sum()).collect();
                chol.solve(&mut rhs);
                for (&(i, t), v) in basis.iter().zip(rhs) {
                    for c in 0..g {
                        x[c * n + i as usize] += t[c] * v;
                    }
                }
            }
        }
    }
}
