//! The coarsest level's solve of a group: Π A Π on a basis of the group's free directions (unit
//! vectors of free components; a slip unknown's tangents), dense Cholesky.

use super::group::{GroupOp, Scratch};
use super::smoother::{smooth, Coefficients, Smoother, Start};
use crate::bc::P;
use crate::dense::Cholesky;
use crate::operator::Columns;
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

/// Π A Π on `basis` (grouped by unknown), dense m×m, column by column: A_c e_j for each
/// unknown j and block c, formed at its nonzero rows by `columns` where the operator is applied
/// in one pass (bitwise the product's) and by a product of the whole level otherwise, then the
/// basis vectors at j combine them.
fn assemble(op: &GroupOp, basis: &[(u32, [f64; 3])], mut columns: Option<Columns>) -> Vec<f64> {
    let (n, g, m) = (op.n(), op.len(), basis.len());
    let mut a = vec![0.0; m * m];
    let (mut e, mut s) = (vec![0.0; n], vec![0.0; n]);
    let mut y: Vec<Vec<f64>> = vec![vec![0.0; n]; g];
    let mut written: Vec<Vec<u32>> = vec![Vec::new(); g];
    let mut first = 0;
    while first < m {
        let j = basis[first].0;
        let last = first + basis[first..].iter().take_while(|b| b.0 == j).count();
        for (c, yc) in y.iter_mut().enumerate() {
            if basis[first..last].iter().all(|b| b.1[c] == 0.0) {
                yc.iter_mut().for_each(|v| *v = 0.0);
                continue;
            }
            match &mut columns {
                Some(t) => t.column(j as usize, op.flags(c), yc, &mut written[c]),
                None => {
                    e[j as usize] = 1.0;
                    op.level().op.apply(op.flags(c), &e, yc, &mut s);
                    e[j as usize] = 0.0;
                }
            }
        }
        for beta in first..last {
            let cb = basis[beta].1;
            for (alpha, &(i, ca)) in basis.iter().enumerate() {
                a[alpha * m + beta] = (0..g).map(|c| ca[c] * cb[c] * y[c][i as usize]).sum();
            }
        }
        first = last;
    }
    a
}

impl CoarseSolve {
    /// The coarse solve of the group `op` (named in the error when Π A Π is not positive
    /// definite there).
    pub(crate) fn new(op: &GroupOp) -> Result<CoarseSolve> {
        let basis = free_basis(op);
        let m = basis.len();
        if m == 0 {
            return Ok(CoarseSolve::Empty);
        }
        if m > DENSE_MAX {
            return Ok(CoarseSolve::Smoothed(polynomials(op.level().op.method)));
        }
        let a = assemble(op, &basis, Columns::new(&op.level().op));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bc::Kind;
    use crate::mesh::fixtures::rect;
    use crate::multigrid::hierarchy::{Hierarchy, HierarchyParams};
    use crate::{BoundaryConditions, Method};

    /// The columns formed at their nonzero rows give the products' dense matrix bitwise, on
    /// every level of a Laplacian's hierarchy (the finest one's K, the Galerkin levels'
    /// products), for scalar groups with prescribed rows and a group coupled by slip walls; the
    /// biharmonic's two passes keep the products.
    #[test]
    fn columns_at_their_rows_are_the_products_bitwise() {
        let mesh = rect(12, 10, [0.0, 1.3, 0.0, 1.0]);
        for (method, sides) in [Method::Laplacian, Method::Biharmonic].into_iter().flat_map(|m| [(m, Kind::Slip), (m, Kind::Free)]) {
            let mut bcs = BoundaryConditions::new();
            bcs.set_kinds(1, Kind::Fixed).set_kinds(3, Kind::Clamped);
            for p in [2, 4] {
                match sides {
                    Kind::Slip => {
                        bcs.set_kinds(p, Kind::Slip);
                    }
                    _ => {
                        bcs.set_kind(p, 0, Kind::Clamped).unwrap().set_kind(p, 1, Kind::Free).unwrap();
                    }
                }
            }
            let mut params = HierarchyParams::default();
            params.coarsen.coarsest_unknowns = Some(30);
            let h = Hierarchy::build(&mesh, Vec::new(), &bcs, method, &params).unwrap();
            assert!(h.levels.len() >= 2, "{} levels", h.levels.len());
            if method == Method::Biharmonic {
                assert!(h.levels.iter().all(|l| Columns::new(&l.op).is_none()));
                continue;
            }
            let mut nonzero = 0;
            for level in &h.levels {
                for g in h.groups() {
                    let op = GroupOp::new(level, g, false);
                    let basis = free_basis(&op);
                    let columns = Columns::new(&level.op).expect("applied in one pass");
                    let (read, formed) = (assemble(&op, &basis, Some(columns)), assemble(&op, &basis, None));
                    assert!(basis.len() < op.n() * op.len(), "some direction is prescribed");
                    assert!(read.iter().zip(&formed).all(|(a, b)| a.to_bits() == b.to_bits()), "{method:?} {sides:?}");
                    nonzero += read.iter().filter(|v| **v != 0.0).count();
                }
            }
            assert!(nonzero > 500, "{nonzero} entries");
        }
    }
}
