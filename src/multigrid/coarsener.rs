//! The seam between the multigrid hierarchy and the ways of making coarse levels.
//!
//! A coarsener yields, level after level, either a coarse mesh whose vertices are fine vertices
//! (made from the fine mesh alone, beside the fine level's assembly) or a subset of the fine
//! level's unknowns (chosen from the assembled level), and a transfer (prolongation P, fine
//! unknowns × coarse unknowns, exact for linear fields, and its transpose) that it re-evaluates
//! when the meshes move. The hierarchy does the rest (unknowns, flags, operators rediscretised
//! or Galerkin PᵀKP, smoothers, coarse solve) without knowing how the levels were made. The
//! coarseners implement this trait in their own modules; `multigrid::coarsener_for` picks one.

use super::level::{Level, Transfer};
use crate::{Mesh, Result};

/// Makes the coarse levels of a hierarchy and their transfers.
pub(crate) trait Coarsener: Send + Sync {
    /// The next coarser mesh and links made from the fine mesh alone, or None when this
    /// coarsener makes no meshes or coarsening should stop here. It runs beside the fine
    /// level's assembly.
    fn coarsen_mesh(&self, fine: &Mesh, links: &[[u32; 2]]) -> Result<Option<CoarseMesh>>;
    /// The next coarser level as a subset of the unknowns of the assembled level `l`, `fine`
    /// (what the coarsener learns of them stays in its own state), or None when this
    /// coarsener makes meshes or coarsening should stop here.
    fn coarsen_unknowns(&mut self, l: usize, fine: &Level) -> Option<CoarseUnknowns>;
    /// The transfer between level `l`, `fine`, and the `coarse` level made from it.
    fn transfer(&mut self, l: usize, fine: &Level, coarse: &Level) -> Transfer;
    /// `t`, the transfer below level `l`, re-evaluated after both levels moved (same
    /// topology).
    fn update(&self, l: usize, t: &mut Transfer, fine: &Level, coarse: &Level);
    /// `update` of the rows of P with `redo[i]` only; the other rows keep their weights (their
    /// donors moved little). By default every row is re-evaluated.
    fn update_rows(&self, l: usize, t: &mut Transfer, fine: &Level, coarse: &Level, redo: &[bool]) {
        let _ = redo;
        self.update(l, t, fine, coarse);
    }
}

/// A coarse level without a mesh: some of the fine level's unknowns.
pub(crate) struct CoarseUnknowns {
    /// The fine unknowns kept, ascending.
    pub kept: Vec<u32>,
    /// The transfer from the fine level.
    pub transfer: Transfer,
}

/// A coarse mesh made from a fine one, and how its vertices and links relate to the fine ones.
#[derive(Clone, Debug)]
pub(crate) struct CoarseMesh {
    /// The coarse mesh: valid, all cells counter-clockwise with positive area.
    pub mesh: Mesh,
    /// Coarse vertex `i` is fine vertex `fine_vertex[i]` (same position); ascending.
    pub fine_vertex: Vec<u32>,
    /// The input links whose two vertices were both kept, in coarse numbering.
    pub links: Vec<[u32; 2]>,
}
