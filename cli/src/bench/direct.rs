//! The direct alternative: the assembled operator on the free unknowns, factored by faer's
//! sparse Cholesky (A is SPD on them: biharmonic A = K_UF M_F⁻¹ K_FU, Laplacian/spring K_UU).

use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::Side;
use meshmove::bc::{P, Z};
use meshmove::multigrid::hierarchy::Level;
use meshmove::operator::Method;

pub struct Direct {
    /// Assembly, ordering and numeric factorisation.
    pub factor_s: f64,
    /// Forward and back substitution.
    pub solve_s: f64,
}

/// Lower triangle of A restricted to the free unknowns, as CSC columns (= rows of the upper
/// triangle, A being symmetric), in the free numbering.
fn assemble_lower(lev: &Level, c: usize, free_of: &[u32], nfree: usize) -> SparseColMat<usize, f64> {
    let flags = &lev.flags()[c];
    let k = &lev.op().k;
    let n = lev.n();
    let mut col_ptr = vec![0usize];
    let mut rows: Vec<usize> = Vec::new();
    let mut vals: Vec<f64> = Vec::new();
    let mut acc = vec![0.0; n];
    let mut mark = vec![false; n];
    let mut touched: Vec<u32> = Vec::new();
    for i in 0..n {
        if flags[i] & P != 0 {
            continue;
        }
        let (ci, vi) = k.row(i);
        let mut add = |j: u32, a: f64| {
            let ju = j as usize;
            if flags[ju] & P != 0 || free_of[ju] < free_of[i] {
                return;
            }
            if !mark[ju] {
                mark[ju] = true;
                touched.push(j);
            }
            acc[ju] += a;
        };
        match lev.op().method {
            Method::Biharmonic => {
                for (&kk, &a) in ci.iter().zip(vi) {
                    let ku = kk as usize;
                    if flags[ku] & Z != 0 {
                        continue;
                    }
                    let w = a * lev.op().inv_v[ku];
                    let (ck, vk) = k.row(ku);
                    for (&j, &b) in ck.iter().zip(vk) {
                        add(j, w * b);
                    }
                }
            }
            _ => {
                for (&j, &a) in ci.iter().zip(vi) {
                    add(j, a);
                }
            }
        }
        touched.sort_unstable();
        for &j in &touched {
            rows.push(free_of[j as usize] as usize);
            vals.push(acc[j as usize]);
            acc[j as usize] = 0.0;
            mark[j as usize] = false;
        }
        touched.clear();
        col_ptr.push(rows.len());
    }
    let sym = SymbolicSparseColMat::new_checked(nfree, nfree, col_ptr, None, rows);
    SparseColMat::new(sym, vals)
}

/// Solves A x = b for component `c` directly; `x` gets the solution (zero on P unknowns).
pub fn solve(lev: &Level, c: usize, b: &[f64], x: &mut [f64]) -> Result<Direct, String> {
    use faer::prelude::SpSolver;
    let t0 = std::time::Instant::now();
    let flags = &lev.flags()[c];
    let mut free_of = vec![u32::MAX; lev.n()];
    let mut nfree = 0u32;
    for (i, f) in free_of.iter_mut().enumerate() {
        if flags[i] & P == 0 {
            *f = nfree;
            nfree += 1;
        }
    }
    let a = assemble_lower(lev, c, &free_of, nfree as usize);
    let chol = a.as_ref().sp_cholesky(Side::Lower).map_err(|e| format!("sparse Cholesky failed: {e:?}"))?;
    drop(a);
    let factor_s = t0.elapsed().as_secs_f64();
    let t1 = std::time::Instant::now();
    let mut rhs = faer::Col::<f64>::zeros(nfree as usize);
    for i in 0..lev.n() {
        if free_of[i] != u32::MAX {
            rhs[free_of[i] as usize] = b[i];
        }
    }
    chol.solve_in_place(rhs.as_mut());
    for i in 0..lev.n() {
        x[i] = if free_of[i] != u32::MAX { rhs[free_of[i] as usize] } else { 0.0 };
    }
    Ok(Direct { factor_s, solve_s: t1.elapsed().as_secs_f64() })
}
