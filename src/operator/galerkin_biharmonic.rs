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
//! kept levels below wall layers only (`multigrid::hierarchy`), where the drift shows.

use super::LevelOperator;
use crate::sparse::{matmul, triple_product, CsrMatrix};

/// A coarse level's assembled biharmonic and what remaking it at a new reference needs.
#[derive(Clone)]
pub(crate) struct Assembled {
    /// A_c = Pᵀ A P (coarse unknowns × coarse unknowns; the P rows of the flags are applied when
    /// it is applied, as for K).
    pub(crate) a: CsrMatrix,
    /// Per unknown of the finer level, whether S is free there (no Z flag); used when the finer
    /// level has no assembled A of its own. Empty otherwise.
    pub(crate) s_free: Vec<bool>,
}

impl Assembled {
    /// Pᵀ A P for the finer level `fine`: from its own assembled A when it has one, else from
    /// K_{:,F} V_F⁻¹ K_{F,:} with F the unknowns where `s_free` is set.
    pub(crate) fn product(fine: &LevelOperator, s_free: Vec<bool>, prolong: &CsrMatrix, restrict: &CsrMatrix) -> Assembled {
        if let Some(f) = &fine.assembled {
            return Assembled { a: triple_product(restrict, &f.a, prolong), s_free: Vec::new() };
        }
        // Pᵀ K W K P = Gᵀ W G with G = K P and W = V⁻¹ on the unknowns without Z, 0 on them.
        let g = matmul(&fine.k, prolong);
        let n = fine.n();
        let w = CsrMatrix {
            nrows: n,
            ncols: n,
            row_ptr: (0..=n as u32).collect(),
            cols: (0..n as u32).collect(),
            vals: (0..n).map(|i| if s_free[i] { fine.inv_v[i] } else { 0.0 }).collect(),
        };
        Assembled { a: triple_product(&g.transpose(), &w, &g), s_free }
    }
}

impl LevelOperator {
    /// `galerkin`'s K_c and V_c, with the biharmonic's A_c = Pᵀ A P assembled and applied
    /// instead of K_c V_c⁻¹ K_c. `s_free` as in `Assembled::product`: per unknown of the finer
    /// level, S free there (the same for every component; the caller checks).
    pub fn galerkin_assembled(fine: &LevelOperator, s_free: Vec<bool>, prolong: &CsrMatrix, restrict: &CsrMatrix) -> Self {
        let mut op = LevelOperator::galerkin(fine, prolong, restrict);
        op.assembled = Some(Assembled::product(fine, s_free, prolong, restrict));
        // The fused sweep is the two-pass operator's; the assembled one is applied in one pass.
        op.fuse = None;
        op
    }

    /// Whether the level's biharmonic is the assembled Galerkin product.
    pub fn is_assembled(&self) -> bool {
        self.assembled.is_some()
    }
}
