//! The biharmonic's coarse operator as the Galerkin product of the finer level's operator,
//! assembled: A_c = Pᵀ A P, with A = K_{U,F} V_F⁻¹ K_{F,U} on a level with K and V (docs/DESIGN.md
//! §3) or the finer level's own assembled A_c.
//!
//! The coarse levels otherwise apply K_c V_c⁻¹ K_c from their Galerkin K_c = PᵀKP and lumped V_c.
//! Across thin wall layers coarsened several times that product drifts from the fine operator's
//! energy on coarse functions (the lumped mass of a coarse unknown spans layers whose cells differ
//! in volume by orders of magnitude), and the cycle needs more iterations as the mesh grows; Pᵀ A P
//! is the fine operator's energy on the coarse functions whatever the layers, at the price of a
//! denser coarse operator (A couples neighbours of neighbours). The hierarchy assembles it on the
//! kept levels below wall layers only (`multigrid::hierarchy`), where the drift shows. Its
//! entries far below their diagonals are dropped onto them (`small_entries`): each level's
//! product of the level above would otherwise widen its rows level by level.

use super::small_entries::Dropped;
use super::LevelOperator;
use crate::sparse::{matmul, triple_product, triple_product_values, weighted_gram, CsrMatrix};

/// Whether the biharmonic's next coarser level takes the assembled Galerkin product A_c = Pᵀ A P
/// of a level that is `kept` (unknowns kept from a finer level, no mesh), has `lines` across wall
/// layers, or is `assembled` itself (docs/DESIGN.md §5, "Wall layers"): below the first kept
/// level of a layered hierarchy. The serial hierarchy and the distributed one decide by it.
pub(crate) fn assembled_below(kept: bool, lines: bool, assembled: bool) -> bool {
    assembled || (kept && lines)
}

/// A coarse level's assembled biharmonic and what remaking it at a new reference needs.
#[derive(Clone)]
pub(crate) struct Assembled {
    /// A_c = Pᵀ A P with its small entries dropped onto the diagonal (`small_entries`), as it is
    /// applied (coarse unknowns × coarse unknowns; the P rows of the flags are applied when it
    /// is applied, as for K). The next coarser level's product is made from it.
    pub(crate) a: CsrMatrix,
    /// When the rows are bounded: the whole product Pᵀ A P, whose values a moved mesh refills
    /// before `a` is taken again, and which of its entries `a` keeps.
    bounded: Option<(CsrMatrix, Dropped)>,
    /// Per unknown of the finer level, whether S is free there (no Z flag); used when the finer
    /// level has no assembled A of its own. Empty otherwise.
    pub(crate) s_free: Vec<bool>,
}

impl Assembled {
    /// The applied operator of the product `full`, its small entries dropped when `bound`.
    fn new(full: CsrMatrix, s_free: Vec<bool>, bound: bool) -> Assembled {
        if !bound {
            return Assembled { a: full, bounded: None, s_free };
        }
        let (dropped, a) = Dropped::new(&full);
        Assembled { a, bounded: Some((full, dropped)), s_free }
    }

    /// Pᵀ A P for a finer level `fine` without an assembled A, from its K P = `g`:
    /// K_{:,F} V_F⁻¹ K_{F,:} with F the unknowns where `s_free` is set, as Gᵀ W G with W = V⁻¹
    /// where S is free, 0 elsewhere (`weighted_gram`, bitwise the triple product with W as a
    /// diagonal matrix, which `refill` computes).
    fn from_kp(fine: &LevelOperator, s_free: Vec<bool>, g: &CsrMatrix, bound: bool) -> Assembled {
        Assembled::new(weighted_gram(&g.transpose(), &free_weights(fine, &s_free), g), s_free, bound)
    }

    /// The product's values again into the stored pattern, when P's pattern and the finer level's
    /// are those it was made with (a moved mesh changes values only), and the applied operator
    /// from them in its kept pattern: bitwise `LevelOperator::galerkin_assembled`, without its
    /// symbolic phase.
    pub(crate) fn refill(&mut self, fine: &LevelOperator, prolong: &CsrMatrix, restrict: &CsrMatrix) {
        let product = match &mut self.bounded {
            Some((full, _)) => full,
            None => &mut self.a,
        };
        match &fine.assembled {
            Some(f) => triple_product_values(restrict, &f.a, prolong, product),
            None => {
                let (g, w) = kp_and_weights(fine, &self.s_free, prolong);
                triple_product_values(&g.transpose(), &w, &g, product);
            }
        }
        if let Some((full, dropped)) = &self.bounded {
            dropped.fill(full, &mut self.a);
        }
    }
}

/// G = K P and W = V⁻¹ as a diagonal matrix, zero where S is not free: Pᵀ K W K P = Gᵀ W G.
fn kp_and_weights(fine: &LevelOperator, s_free: &[bool], prolong: &CsrMatrix) -> (CsrMatrix, CsrMatrix) {
    let g = matmul(&fine.k, prolong);
    let n = fine.n();
    let w = CsrMatrix {
        nrows: n,
        ncols: n,
        row_ptr: (0..=n as u32).collect(),
        cols: (0..n as u32).collect(),
        vals: free_weights(fine, s_free),
    };
    (g, w)
}

/// W's diagonal: V⁻¹ where S is free, 0 elsewhere.
fn free_weights(fine: &LevelOperator, s_free: &[bool]) -> Vec<f64> {
    (0..fine.n()).map(|i| if s_free[i] { fine.inv_v[i] } else { 0.0 }).collect()
}

impl LevelOperator {
    /// `galerkin`'s K_c and V_c, with the biharmonic's A_c = Pᵀ A P assembled and applied
    /// instead of K_c V_c⁻¹ K_c. `s_free`: per unknown of the finer
    /// level, S free there (the same for every component; the caller checks). With `bound`
    /// the product's small entries are dropped onto its diagonal (`small_entries`).
    pub fn galerkin_assembled(
        fine: &LevelOperator,
        s_free: Vec<bool>,
        prolong: &CsrMatrix,
        restrict: &CsrMatrix,
        bound: bool,
    ) -> Self {
        let (mut op, assembled) = match &fine.assembled {
            Some(f) => {
                let a = triple_product(restrict, &f.a, prolong);
                (LevelOperator::galerkin(fine, prolong, restrict), Assembled::new(a, Vec::new(), bound))
            }
            None => {
                // K P serves both products: K_c = R (K P), bitwise `galerkin`'s R K P.
                let g = matmul(&fine.k, prolong);
                let op = LevelOperator::galerkin_of(fine, matmul(restrict, &g), restrict);
                (op, Assembled::from_kp(fine, s_free, &g, bound))
            }
        };
        op.assembled = Some(assembled);
        // The fused sweep is the two-pass operator's; the assembled one is applied in one pass.
        op.fuse = None;
        op
    }

    /// This coarse operator made again from `fine` with a new interpolation (new patterns):
    /// `galerkin`, or `galerkin_assembled` with the same S flags and bound when it is assembled.
    pub fn galerkin_again(&self, fine: &LevelOperator, prolong: &CsrMatrix, restrict: &CsrMatrix) -> Self {
        match &self.assembled {
            Some(a) => {
                LevelOperator::galerkin_assembled(fine, a.s_free.clone(), prolong, restrict, a.bounded.is_some())
            }
            None => LevelOperator::galerkin(fine, prolong, restrict),
        }
    }

    /// The nonzeros of the assembled Galerkin biharmonic, when the level has one.
    pub fn assembled_nnz(&self) -> Option<usize> {
        self.assembled.as_ref().map(|a| a.a.nnz())
    }

    /// Whether the level's biharmonic is the assembled Galerkin product.
    pub fn is_assembled(&self) -> bool {
        self.assembled.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bc::{Dofs, Z};
    use crate::mesh::fixtures::rect;
    use crate::operator::Method;

    /// An interpolation from every other unknown: kept unknowns take themselves, the others
    /// the mean of two kept ones (any weights serve the identity checked below).
    fn prolong(n: usize) -> CsrMatrix {
        let nc = n.div_ceil(2);
        let t = (0..n as u32)
            .flat_map(|i| match i % 2 {
                0 => vec![(i, i / 2, 1.0)],
                _ => vec![(i, i / 2, 0.5), (i, ((i / 2 + 1) as usize).min(nc - 1) as u32, 0.5)],
            })
            .collect();
        CsrMatrix::from_triplets(n, nc, t)
    }

    /// xᵀ A y for the operator `op` with `flags` (no P unknowns here).
    fn energy(op: &LevelOperator, flags: &[u8], x: &[f64], y: &[f64]) -> f64 {
        let (mut ay, mut s) = (vec![0.0; y.len()], vec![0.0; y.len()]);
        op.apply(flags, y, &mut ay, &mut s);
        x.iter().zip(&ay).map(|(a, b)| a * b).sum()
    }

    /// Two levels down, the assembled operator is the fine biharmonic's energy on the
    /// interpolated vectors: x_cᵀ A_c y_c = (P x_c)ᵀ A (P y_c), the Z unknowns' S held at zero.
    #[test]
    fn assembled_levels_are_the_fine_energy_of_interpolated_vectors() {
        let mesh = rect(6, 5, [0.0, 1.0, 0.0, 0.02]);
        let dofs = Dofs::build(&mesh, &[], &[]);
        let fine = LevelOperator::new(Method::Biharmonic, &mesh, &dofs);
        let n = fine.n();
        let flags: Vec<u8> = (0..n).map(|i| if i % 7 == 3 { Z } else { 0 }).collect();
        let p1 = prolong(n);
        let l1 = LevelOperator::galerkin_assembled(
            &fine,
            flags.iter().map(|&f| f & Z == 0).collect(),
            &p1,
            &p1.transpose(),
            false,
        );
        let p2 = prolong(l1.n());
        let l2 = LevelOperator::galerkin_assembled(&l1, Vec::new(), &p2, &p2.transpose(), false);
        assert!(l1.is_assembled() && l2.is_assembled() && l2.n() < l1.n());
        let xc: Vec<f64> = (0..l2.n()).map(|i| ((i * 37 % 11) as f64 - 5.0) / 3.0).collect();
        let yc: Vec<f64> = (0..l2.n()).map(|i| ((i * 13 % 7) as f64 - 3.0) / 2.0).collect();
        let up = |v: &[f64]| {
            let (mut a, mut b) = (vec![0.0; l1.n()], vec![0.0; n]);
            p2.mul_vec(v, &mut a);
            p1.mul_vec(&a, &mut b);
            b
        };
        let coarse = energy(&l2, &vec![0; l2.n()], &xc, &yc);
        let fine_e = energy(&fine, &flags, &up(&xc), &up(&yc));
        assert!(fine_e.abs() > 1.0, "{fine_e}");
        assert!((coarse - fine_e).abs() <= 1e-10 * fine_e.abs(), "{coarse} vs {fine_e}");
    }

    /// On a moved mesh (same patterns, new values) the refilled assembled operators of two
    /// levels equal the ones made afresh, bitwise.
    #[test]
    fn refilled_levels_are_the_fresh_products_bitwise() {
        let mesh = rect(6, 5, [0.0, 1.0, 0.0, 0.02]);
        let dofs = Dofs::build(&mesh, &[], &[]);
        let mut fine = LevelOperator::new(Method::Biharmonic, &mesh, &dofs);
        let n = fine.n();
        let s_free: Vec<bool> = (0..n).map(|i| i % 7 != 3).collect();
        let (p1, p2) = (prolong(n), prolong(n.div_ceil(2)));
        let (r1, r2) = (p1.transpose(), p2.transpose());
        let mut l1 = LevelOperator::galerkin_assembled(&fine, s_free.clone(), &p1, &r1, true);
        let mut l2 = LevelOperator::galerkin_assembled(&l1, Vec::new(), &p2, &r2, true);
        // The mesh moves: K and V take new values in the same pattern.
        fine.k.vals.iter_mut().enumerate().for_each(|(j, v)| *v *= 1.0 + 0.01 * (j % 5) as f64);
        fine.inv_v.iter_mut().enumerate().for_each(|(i, v)| *v *= 1.0 - 0.02 * (i % 3) as f64);
        l1.update_galerkin(&fine, &p1, &r1);
        l2.update_galerkin(&l1, &p2, &r2);
        let f1 = LevelOperator::galerkin_assembled(&fine, s_free, &p1, &r1, true);
        let f2 = LevelOperator::galerkin_assembled(&f1, Vec::new(), &p2, &r2, true);
        let bits = |op: &LevelOperator| {
            op.assembled.as_ref().map(|a| a.a.vals.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
        };
        assert!(bits(&l1).is_some_and(|b| b.iter().any(|&v| v != 0)));
        assert_eq!(bits(&l1), bits(&f1));
        assert_eq!(bits(&l2), bits(&f2));
    }
}
