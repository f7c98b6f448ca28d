//! The operator A of one level and component, applied matrix-free from K and V (docs/DESIGN.md §3):
//!
//! biharmonic:  S_k = (1/V_k) Σ_j K_kj x_j  for k without Z (else 0)      (paper Eq. 5)
//!              (A x)_i = Σ_k K_ik S_k       for i without P (else 0)      (paper Eq. 6)
//! Laplacian, spring: (A x)_i = Σ_j K_ij x_j for i without P.
//!
//! Vectors live on the unknowns; corrections are zero on P unknowns.

use super::fused::{FusePlan, Iterate};
use super::galerkin_biharmonic::Assembled;
use super::scatter::{pattern_and_scatter, Scatter};
use super::{close_diagonal, lumped_mass, spring_stiffness, stiffness_and_mass, Method};
use crate::bc::{Dofs, P, Z};
use crate::sparse::{par_fill, par_fill_blocks, par_update, par_update2, triple_product, triple_product_values, CsrMatrix};
use crate::Mesh;
use std::sync::Arc;

/// Makes a vector's halo entries their owners' values (a distributed level's exchange).
pub(crate) type HaloExchange = Arc<dyn Fn(&mut [f64]) + Send + Sync>;

#[derive(Clone)]
pub struct LevelOperator {
    pub method: Method,
    /// Values may be refilled (`reassemble`); the pattern is fixed, as the fused plan depends
    /// on its bandwidth (a new pattern means a new operator).
    pub k: CsrMatrix,
    /// 1/V: only the inverse is kept (the operator multiplies by it; `mass` gives V back).
    pub inv_v: Vec<f64>,
    /// Where the cells' element matrices add into `k` (`scatter.rs`), for `reassemble`; empty
    /// on an operator not assembled from a mesh's cells.
    pub(super) scatter: Scatter,
    /// Per row of `k`, Σ_j |K_ij| as `reassemble` left it (summed while closing the diagonal,
    /// for `inv_l1_diags`); empty where it is not known (an operator not assembled from cells).
    pub(super) row_abs: Vec<f64>,
    /// The biharmonic's two passes fused on a large level (`fused.rs`); None keeps them apart.
    pub(super) fuse: Option<FusePlan>,
    /// The biharmonic's A of a coarse level assembled as the Galerkin product of the finer
    /// level's (`galerkin_biharmonic.rs`), applied in one pass instead of K_c V_c⁻¹ K_c; None
    /// on every other level.
    pub(super) assembled: Option<Assembled>,
    /// On a rank's part of a distributed mesh: the biharmonic's S, complete only on the owned
    /// rows, takes its owners' values on the halo between the two passes. None in one process.
    pub(super) source_halo: Option<HaloExchange>,
}

impl LevelOperator {
    pub fn new(method: Method, mesh: &Mesh, dofs: &Dofs) -> Self {
        // The spring's weights are set edge by edge (`spring_stiffness`), not added by the map.
        let (k, scatter) = pattern_and_scatter(mesh, dofs, method != Method::Spring);
        let fuse = fuse_plan(method, &k);
        let mut op = LevelOperator { method, k, inv_v: Vec::new(), row_abs: Vec::new(), scatter, fuse, assembled: None, source_halo: None };
        op.reassemble(mesh, dofs);
        op
    }

    /// Re-evaluates K and V at new vertex positions, refilling K's values in place (its pattern
    /// is the topology's, so it is not rebuilt or kept twice). Only for operators from `new`.
    pub fn reassemble(&mut self, mesh: &Mesh, dofs: &Dofs) {
        let mass = match self.method {
            Method::Spring => {
                spring_stiffness(&mut self.k, mesh, dofs);
                self.row_abs = Vec::new();
                lumped_mass(mesh, dofs)
            }
            _ => {
                let mass;
                (mass, self.row_abs) = stiffness_and_mass(&mut self.k, &self.scatter, mesh, dofs);
                mass
            }
        };
        self.inv_v = mass.iter().map(|&v| 1.0 / v).collect();
    }

    /// The coarse operator of a multigrid level by Galerkin projection of the fine one's
    /// second-order parts: K_c = Pᵀ K P and V_c = Pᵀ V (the biharmonic is then K_c V_c⁻¹ K_c).
    ///
    /// Rediscretising K on the coarse mesh is consistent only where K does not depend on cell
    /// size: spring weights (1/L²) and the biharmonic's 1/V do, and across a thin wall layer a
    /// coarse cell is many fine cells thick, so rediscretised coarse operators came out far too
    /// soft there and the cycle stalled (boundary-layer cylinder). PᵀKP is the fine operator's
    /// own energy on coarse functions, whatever the cell sizes; P reproduces constants and
    /// linear fields, so K_c keeps both in its null space where K does.
    pub fn galerkin(fine: &LevelOperator, prolong: &CsrMatrix, restrict: &CsrMatrix) -> Self {
        LevelOperator::galerkin_of(fine, triple_product(restrict, &fine.k, prolong), restrict)
    }

    /// `galerkin` from its product R K P, formed by the caller.
    pub(crate) fn galerkin_of(fine: &LevelOperator, mut k: CsrMatrix, restrict: &CsrMatrix) -> Self {
        close_diagonal(&mut k);
        let inv_v = galerkin_inv_mass(fine, restrict);
        let fuse = fuse_plan(fine.method, &k);
        LevelOperator { method: fine.method, k, inv_v, row_abs: Vec::new(), scatter: Scatter::default(), fuse, assembled: None, source_halo: None }
    }

    /// A second-order operator given as its matrix K (applied in one pass, unit mass): a
    /// distributed level whose rows come assembled, such as a Galerkin coarse level across ranks.
    #[cfg(feature = "mpi")]
    pub(crate) fn from_matrix(method: Method, k: CsrMatrix) -> Self {
        debug_assert!(method != Method::Biharmonic, "a matrix is applied in one pass");
        let inv_v = vec![1.0; k.nrows];
        LevelOperator { method, k, inv_v, row_abs: Vec::new(), scatter: Scatter::default(), fuse: None, assembled: None, source_halo: None }
    }

    /// `galerkin`'s values refilled in place when K's pattern and P's are those this operator
    /// was made from (a moved mesh): only the numeric phase of PᵀKP runs. Bitwise `galerkin`.
    pub fn update_galerkin(&mut self, fine: &LevelOperator, prolong: &CsrMatrix, restrict: &CsrMatrix) {
        triple_product_values(restrict, &fine.k, prolong, &mut self.k);
        close_diagonal(&mut self.k);
        self.row_abs = Vec::new();
        self.inv_v = galerkin_inv_mass(fine, restrict);
        if let Some(a) = &mut self.assembled {
            a.refill(fine, prolong, restrict);
        }
    }

    /// The matrix A is applied from in one pass: K for the Laplacian and the spring, the
    /// assembled Galerkin A of a biharmonic coarse level; None for the biharmonic's two passes
    /// over K.
    pub(crate) fn one_pass(&self) -> Option<&CsrMatrix> {
        match (&self.assembled, self.method) {
            (Some(a), _) => Some(&a.a),
            (None, Method::Biharmonic) => None,
            (None, _) => Some(&self.k),
        }
    }

    pub fn n(&self) -> usize {
        self.inv_v.len()
    }

    /// The lumped mass V, as 1/(1/V).
    pub fn mass(&self) -> Vec<f64> {
        self.inv_v.iter().map(|&w| 1.0 / w).collect()
    }

    /// S = M⁻¹ K x on unknowns without Z (Eq. 5 with zero boundary flux), minus an optional
    /// source `g` (the rigid-motion flux of docs/DESIGN.md §4).
    fn source(&self, flags: &[u8], x: &[f64], g: Option<&[f64]>, s: &mut [f64]) {
        par_fill(s, |i| self.source_row(flags, i, x, 0, g));
        if let Some(exchange) = &self.source_halo {
            exchange(s);
        }
    }

    /// The operator of a rank's part of a distributed mesh: `exchange` makes the biharmonic's S
    /// current on the halo between its two passes (a halo row of K lacks the cells beyond the
    /// ghost layer, so only the owner forms S there). The two passes stay apart (no fused
    /// sweep), as the exchange runs between them.
    #[cfg(feature = "mpi")]
    pub(crate) fn with_source_exchange(mut self, exchange: HaloExchange) -> Self {
        self.fuse = None;
        self.source_halo = Some(exchange);
        self
    }

    /// Row j of `source`, with x's entry m read at `x[m − base]` (the fused sweep passes a
    /// chunk of x).
    #[inline(always)]
    pub(super) fn source_row(&self, flags: &[u8], j: usize, x: &[f64], base: usize, g: Option<&[f64]>) -> f64 {
        if flags[j] & Z != 0 {
            return 0.0;
        }
        (self.k.row_dot_offset(j, x, base) - g.map_or(0.0, |g| g[j])) * self.inv_v[j]
    }

    /// y = A x. `s` is scratch of length n.
    pub fn apply(&self, flags: &[u8], x: &[f64], y: &mut [f64], s: &mut [f64]) {
        match (self.one_pass(), &self.fuse) {
            (Some(a), _) => free_rows(a, flags, x, y),
            (None, Some(plan)) => self.fused_pass(plan, flags, Iterate::Read(x), s, y, |_, t, _| t.unwrap_or(0.0)),
            (None, None) => {
                self.source(flags, x, None, s);
                free_rows(&self.k, flags, s, y);
            }
        }
    }

    /// r = b − A x.
    pub fn residual(&self, flags: &[u8], b: &[f64], x: &[f64], r: &mut [f64], s: &mut [f64]) {
        self.update_with_residual(flags, b, x, s, r, |_, r, _| r);
    }

    /// r_k = b_k − A x_k for the blocks k of a group of components (`flags[k]` each), bitwise as
    /// `residual` forms each, with every row of A read once for all the blocks: of the assembled
    /// A, or of K in each of the biharmonic's two passes (`s` holds each block's S). A fused
    /// plan, or more blocks than three, forms them one by one.
    pub fn residuals(&self, flags: &[&[u8]], b: &[&[f64]], x: &[&[f64]], r: &mut [&mut [f64]], s: &mut [&mut [f64]]) {
        match (flags.len(), &self.fuse) {
            (1, None) => self.residuals_of::<1>(flags, b, x, r, s),
            (2, None) => self.residuals_of::<2>(flags, b, x, r, s),
            (3, None) => self.residuals_of::<3>(flags, b, x, r, s),
            _ => {
                for (k, (rk, sk)) in r.iter_mut().zip(s.iter_mut()).enumerate() {
                    self.residual(flags[k], b[k], x[k], rk, sk);
                }
            }
        }
    }

    /// `residuals` of `G` blocks.
    fn residuals_of<const G: usize>(
        &self,
        flags: &[&[u8]],
        b: &[&[f64]],
        x: &[&[f64]],
        r: &mut [&mut [f64]],
        s: &mut [&mut [f64]],
    ) {
        let (flags, b): ([&[u8]; G], [&[f64]; G]) = (std::array::from_fn(|k| flags[k]), std::array::from_fn(|k| b[k]));
        let (k, u) = self.first_pass::<G>(flags, x, s);
        par_fill_blocks(blocks::<G>(r), k.nnz(), |i| {
            let t = k.row_dots(i, &u);
            std::array::from_fn(|c| if flags[c][i] & P != 0 { b[c][i] } else { b[c][i] - t[c] })
        });
    }

    /// y_k = A x_k for the blocks k of a group of components (`flags[k]` each), bitwise as
    /// `apply` forms each, with every row of A read once for all the blocks, as in `residuals`
    /// (`s` holds each block's S). A fused plan, or more blocks than three, forms them one by one.
    pub fn applies(&self, flags: &[&[u8]], x: &[&[f64]], y: &mut [&mut [f64]], s: &mut [&mut [f64]]) {
        match (flags.len(), &self.fuse) {
            (1, None) => self.applies_of::<1>(flags, x, y, s),
            (2, None) => self.applies_of::<2>(flags, x, y, s),
            (3, None) => self.applies_of::<3>(flags, x, y, s),
            _ => {
                for (k, (yk, sk)) in y.iter_mut().zip(s.iter_mut()).enumerate() {
                    self.apply(flags[k], x[k], yk, sk);
                }
            }
        }
    }

    /// `applies` of `G` blocks.
    fn applies_of<const G: usize>(&self, flags: &[&[u8]], x: &[&[f64]], y: &mut [&mut [f64]], s: &mut [&mut [f64]]) {
        let flags: [&[u8]; G] = std::array::from_fn(|k| flags[k]);
        let (k, u) = self.first_pass::<G>(flags, x, s);
        par_fill_blocks(blocks::<G>(y), k.nnz(), |i| {
            let t = k.row_dots(i, &u);
            std::array::from_fn(|c| if flags[c][i] & P != 0 { 0.0 } else { t[c] })
        });
    }

    /// The matrix the last pass of `G` blocks reads and the vectors it multiplies: the one-pass
    /// matrix and `x`, or for the biharmonic K and each block's S = M⁻¹ K x (`source`, zero on
    /// unknowns with Z), formed into `s` with every row of K read once for all the blocks.
    fn first_pass<'a, const G: usize>(
        &'a self,
        flags: [&[u8]; G],
        x: &[&'a [f64]],
        s: &'a mut [&mut [f64]],
    ) -> (&'a CsrMatrix, [&'a [f64]; G]) {
        match self.one_pass() {
            Some(a) => (a, std::array::from_fn(|k| x[k])),
            None => {
                let x: [&[f64]; G] = std::array::from_fn(|k| x[k]);
                let inv_v = &self.inv_v;
                par_fill_blocks(blocks::<G>(s), self.k.nnz(), |j| {
                    let t = self.k.row_dots(j, &x);
                    std::array::from_fn(|c| if flags[c][j] & Z != 0 { 0.0 } else { t[c] * inv_v[j] })
                });
                if let Some(exchange) = &self.source_halo {
                    s.iter_mut().for_each(|s| exchange(s));
                }
                (&self.k, std::array::from_fn(|k| &*s[k]))
            }
        }
    }

    /// `out_i ← f(i, r_i, out_i)` for every unknown, with r = b − A x formed row by row and never
    /// stored: one pass over K for the Laplacian and spring, two for the biharmonic (S first).
    /// The smoothers update their direction this way, which saves the residual vector's
    /// write and re-read on every sweep (the operator is memory-bound). `out` must not be `x`.
    pub fn update_with_residual(
        &self,
        flags: &[u8],
        b: &[f64],
        x: &[f64],
        s: &mut [f64],
        out: &mut [f64],
        f: impl Fn(usize, f64, f64) -> f64 + Sync + Send,
    ) {
        let (k, u): (&CsrMatrix, &[f64]) = match (self.one_pass(), &self.fuse) {
            (Some(a), _) => (a, x),
            (None, Some(plan)) => return self.fused_pass(plan, flags, Iterate::Read(x), s, out, with_residual(b, f)),
            (None, None) => {
                self.source(flags, x, None, s);
                (&self.k, s)
            }
        };
        par_update(out, |i, o| {
            let r = if flags[i] & P != 0 { b[i] } else { b[i] - k.row_dot(i, u) };
            f(i, r, o)
        });
    }

    /// `d_i ← f(i, r_i, d_i)` with r = b − A x as in `update_with_residual`, then x ← x + d: one
    /// step of a smoother. The biharmonic's second pass reads only S, so it updates x in place
    /// in the same pass; the second-order operators read x's neighbours there, so they add d in a
    /// pass of their own.
    pub fn step_with_residual(
        &self,
        flags: &[u8],
        b: &[f64],
        x: &mut [f64],
        s: &mut [f64],
        d: &mut [f64],
        f: impl Fn(usize, f64, f64) -> f64 + Sync + Send,
    ) {
        if self.one_pass().is_some() {
            self.update_with_residual(flags, b, x, s, d, f);
            par_update(x, |i, x| x + d[i]);
            return;
        }
        if let Some(plan) = &self.fuse {
            return self.fused_pass(plan, flags, Iterate::Update(x), s, d, with_residual(b, f));
        }
        self.source(flags, x, None, s);
        let (k, s) = (&self.k, &*s);
        par_update2(x, d, |i, x, d| {
            let r = if flags[i] & P != 0 { b[i] } else { b[i] - k.row_dot(i, s) };
            let d = f(i, r, d);
            (x + d, d)
        });
    }

    /// Right-hand side for the unknowns without P, given prescribed values `dp` (zero off P)
    /// and the optional rigid-motion flux source `g`: b = −A_{U,P} dp (+ the source's share).
    pub fn rhs(&self, flags: &[u8], dp: &[f64], g: Option<&[f64]>, b: &mut [f64], s: &mut [f64]) {
        match self.one_pass() {
            Some(a) => free_rows(a, flags, dp, b),
            None => {
                self.source(flags, dp, g, s);
                free_rows(&self.k, flags, s, b);
            }
        }
        b.iter_mut().for_each(|b| *b = -*b);
    }

    /// 1/D with D the l1 (Gershgorin) row bound of docs/DESIGN.md §3, zero on P unknowns:
    /// biharmonic D_i = Σ_{k without Z} |K_ik| (Σ_j |K_kj|) / V_k  (bounds Σ_j |A_ij|, paper Eq. 8),
    /// Laplacian and spring D_i = Σ_j |K_ij|, an assembled Galerkin biharmonic D_i = Σ_j |A_ij|.
    pub fn inv_l1_diag(&self, flags: &[u8]) -> Vec<f64> {
        self.inv_l1_diags(&[flags]).pop().unwrap_or_default()
    }

    /// `inv_l1_diag` of each of the components `flags`, bitwise: the rows' absolute sums, which
    /// do not depend on the flags, formed once for all of them, the components side by side.
    pub fn inv_l1_diags(&self, flags: &[&[u8]]) -> Vec<Vec<f64>> {
        use rayon::prelude::*;
        let k = self.one_pass().unwrap_or(&self.k);
        // K's row sums from its assembly where A's rows are K's (the same sums).
        let known = self.assembled.is_none() && self.row_abs.len() == self.n();
        let mut formed = Vec::new();
        if !known {
            formed = vec![0.0; self.n()];
            par_fill(&mut formed, |i| k.row(i).1.iter().map(|a| a.abs()).sum());
        }
        let rowabs = if known { &self.row_abs } else { &formed };
        flags
            .par_iter()
            .map(|flags| {
                let mut inv = vec![0.0; self.n()];
                par_fill(&mut inv, |i| {
                    if flags[i] & P != 0 {
                        return 0.0;
                    }
                    let d = match self.one_pass() {
                        None => {
                            let (c, v) = k.row(i);
                            c.iter()
                                .zip(v)
                                .filter(|(&j, _)| flags[j as usize] & Z == 0)
                                .map(|(&j, &a)| a.abs() * rowabs[j as usize] * self.inv_v[j as usize])
                                .sum()
                        }
                        _ => rowabs[i],
                    };
                    if d > 0.0 {
                        1.0 / d
                    } else {
                        0.0
                    }
                });
                inv
            })
            .collect()
    }
}

/// The first `G` of a group's blocks, as the array `par_fill_blocks` fills.
fn blocks<'a, const G: usize>(v: &'a mut [&mut [f64]]) -> [&'a mut [f64]; G] {
    let mut it = v.iter_mut().map(|v| &mut **v);
    std::array::from_fn(|_| it.next().expect("a block per component"))
}

/// 1/V_c with V_c = P₊ᵀ V: the positive weights only, so a coarse mass stays positive where a
/// least-squares P has negative weights (PᵀV could vanish or turn negative there, and
/// K_c V_c⁻¹ K_c with it); with P ≥ 0, as barycentric weights are, it is PᵀV.
fn galerkin_inv_mass(fine: &LevelOperator, restrict: &CsrMatrix) -> Vec<f64> {
    let mass = fine.mass();
    let mut v = vec![0.0; restrict.nrows];
    restrict.map_rows(&mut v, |c| {
        let (rows, w) = restrict.row(c);
        rows.iter().zip(w).map(|(&i, &w)| w.max(0.0) * mass[i as usize]).sum()
    });
    v.iter().map(|&v| 1.0 / v).collect()
}

/// y = M u on unknowns without P, zero on P.
fn free_rows(m: &CsrMatrix, flags: &[u8], u: &[f64], y: &mut [f64]) {
    par_fill(y, |i| if flags[i] & P != 0 { 0.0 } else { m.row_dot(i, u) });
}

/// The fused sweep's plan for a biharmonic level large enough to gain from it.
fn fuse_plan(method: Method, k: &CsrMatrix) -> Option<FusePlan> {
    if method == Method::Biharmonic {
        FusePlan::new(k)
    } else {
        None
    }
}

/// The fused sweep's row callback from a residual one: r_i = b_i − (K S)_i, or b_i on P rows.
fn with_residual<'a>(
    b: &'a [f64],
    f: impl Fn(usize, f64, f64) -> f64 + Sync + Send + 'a,
) -> impl Fn(usize, Option<f64>, f64) -> f64 + Sync + Send + 'a {
    move |i, t, o| f(i, t.map_or(b[i], |t| b[i] - t), o)
}
