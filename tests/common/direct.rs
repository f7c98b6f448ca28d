//! The fine level's system solved by a dense direct solve, for tests that check the multigrid
//! against it: reads the solver's internals (the `internals` feature).
#![allow(dead_code)]

use meshmove::bc::{P, Z};
use meshmove::{Method, Solver};

/// Solves the fine-level system of `solver` for component `c` by a dense direct solve,
/// assembled here from K, V and the flags independently of the matrix-free operator:
/// biharmonic A = K_UF M_F⁻¹ K_FU and b = −K_UF M_F⁻¹ K_FP d_P; Laplacian/spring A = K_UU.
/// `d` holds a displacement per unknown with the prescribed values set; returns it solved.
pub fn direct_solve(solver: &Solver, c: usize, d: &[f64]) -> Vec<f64> {
    let lev = &solver.hierarchy().levels[0];
    let n = lev.n();
    let k = lev.op().k.to_dense();
    let flags = &lev.flags()[c];
    let u: Vec<usize> = (0..n).filter(|&i| flags[i] & P == 0).collect();
    let f: Vec<usize> = (0..n).filter(|&i| flags[i] & Z == 0).collect();
    let m = u.len();
    let mut a = vec![0.0; m * m];
    let mut b = vec![0.0; m];
    let biharmonic = lev.op().method == Method::Biharmonic;
    // (K_F,: d_P) / V on F, used by the right-hand side.
    for (ii, &i) in u.iter().enumerate() {
        if biharmonic {
            for &kk in &f {
                if k[i][kk] == 0.0 {
                    continue;
                }
                let w = k[i][kk] * lev.op().inv_v[kk];
                for (jj, &j) in u.iter().enumerate() {
                    a[ii * m + jj] += w * k[kk][j];
                }
                let kd: f64 = (0..n).filter(|&j| flags[j] & P != 0).map(|j| k[kk][j] * d[j]).sum();
                b[ii] -= w * kd;
            }
        } else {
            for (jj, &j) in u.iter().enumerate() {
                a[ii * m + jj] = k[i][j];
            }
            b[ii] = -(0..n).filter(|&j| flags[j] & P != 0).map(|j| k[i][j] * d[j]).sum::<f64>();
        }
    }
    for i in 0..m {
        for j in 0..i {
            let v = 0.5 * (a[i * m + j] + a[j * m + i]);
            a[i * m + j] = v;
            a[j * m + i] = v;
        }
    }
    let chol = meshmove::dense::Cholesky::new(m, &a).expect("assembled system is SPD");
    chol.solve(&mut b);
    let mut out = d.to_vec();
    for (ii, &i) in u.iter().enumerate() {
        out[i] = b[ii];
    }
    out
}

/// Per-unknown values of component `c` of a per-vertex field (`dim` values per vertex).
pub fn at_dofs(solver: &Solver, field: &[f64], c: usize) -> Vec<f64> {
    let dim = solver.mesh().dim();
    solver.hierarchy().levels[0].dofs().dof_vertex.iter().map(|&v| field[v as usize * dim + c]).collect()
}
