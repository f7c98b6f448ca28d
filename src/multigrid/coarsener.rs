//! The seam between the multigrid hierarchy and the ways of making coarse levels.
//!
//! A coarsener yields, level after level, a coarse mesh whose vertices are fine vertices and a
//! transfer (prolongation P, fine unknowns × coarse unknowns, exact for linear fields, and its
//! transpose), and re-evaluates the transfer when the meshes move. The hierarchy does the rest
//! (unknowns, flags, operators rediscretised or Galerkin PᵀKP, smoothers, coarse solve) without
//! knowing how the levels were made. The 2D implementation is vertex removal with a
//! constrained Delaunay retriangulation and barycentric interpolation (`coarsen`). A 3D one may
//! build coarse tetrahedra the same way, or interpolate from an unconstrained triangulation of
//! the kept vertices with Galerkin operators, or agglomerate with a least-squares linear-exact
//! P: it returns the kept vertices as a `CoarseMesh` and fills `Transfer` with its own P.

use super::coarsen::{CoarseMesh, CoarsenParams, Delaunay2d};
use super::hierarchy::{Level, Transfer};
use crate::{Error, Mesh, Result};

/// Makes the coarse levels of a hierarchy and their transfers.
pub(crate) trait Coarsener: Send + Sync {
    /// The next coarser mesh and links, or None when coarsening should stop here.
    fn coarsen(&self, fine: &Mesh, links: &[[u32; 2]]) -> Result<Option<CoarseMesh>>;
    /// The transfer between `fine` and the `coarse` level made from it.
    fn transfer(&self, fine: &Level, coarse: &Level) -> Transfer;
    /// `t` re-evaluated after both levels moved (same topology).
    fn update(&self, t: &mut Transfer, fine: &Level, coarse: &Level);
}

/// The coarsener for meshes of dimension `dim`: the 2D Delaunay route, and none yet in 3D (a 3D
/// hierarchy is its fine level alone, solved by the coarsest level's solve).
pub(crate) fn coarsener_for(dim: usize, params: CoarsenParams) -> Result<Box<dyn Coarsener>> {
    match dim {
        2 => Ok(Box::new(Delaunay2d { params })),
        3 => Ok(Box::new(NoCoarsening)),
        _ => Err(Error::Coarsening(format!("no coarsener for {dim}D meshes"))),
    }
}

/// Makes no coarse level: the hierarchy is the fine level alone, whose direct (up to
/// `coarse_solve::DENSE_MAX` free unknowns) or polynomial solve preconditions CG.
struct NoCoarsening;

impl Coarsener for NoCoarsening {
    fn coarsen(&self, _fine: &Mesh, _links: &[[u32; 2]]) -> Result<Option<CoarseMesh>> {
        Ok(None)
    }
    fn transfer(&self, _fine: &Level, _coarse: &Level) -> Transfer {
        unreachable!("no coarse level is ever made")
    }
    fn update(&self, _t: &mut Transfer, _fine: &Level, _coarse: &Level) {
        unreachable!("no coarse level is ever made")
    }
}
