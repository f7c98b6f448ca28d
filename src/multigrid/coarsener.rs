//! The seam between the multigrid hierarchy and the ways of making coarse levels.
//!
//! A coarsener yields, level after level, either a coarse mesh whose vertices are fine vertices
//! (made from the fine mesh alone, beside the fine level's assembly) or a subset of the fine
//! level's unknowns (chosen from the assembled level), and a transfer (prolongation P, fine
//! unknowns × coarse unknowns, exact for linear fields, and its transpose) that it re-evaluates
//! when the meshes move. The hierarchy does the rest (unknowns, flags, operators rediscretised
//! or Galerkin PᵀKP, smoothers, coarse solve) without knowing how the levels were made. Two
//! coarseners exist: vertex removal with a constrained Delaunay retriangulation and barycentric
//! interpolation (2D, `coarsen`), and kept unknowns with least-squares interpolation (2D and
//! 3D, `lsq`).

use super::coarsen::{CoarseMesh, CoarsenParams, Delaunay2d};
use super::hierarchy::{Level, Transfer};
use super::lsq::{Features, LeastSquares};
use super::params::Mode;
use crate::{Error, Mesh, Result};

/// Makes the coarse levels of a hierarchy and their transfers.
pub(crate) trait Coarsener: Send + Sync {
    /// The next coarser mesh and links made from the fine mesh alone, or None when this
    /// coarsener makes no meshes or coarsening should stop here. It runs beside the fine
    /// level's assembly.
    fn coarsen_mesh(&self, fine: &Mesh, links: &[[u32; 2]]) -> Result<Option<CoarseMesh>>;
    /// The next coarser level as a subset of the assembled fine level's unknowns (it may
    /// record the fine level's `features`), or None when this coarsener makes meshes or
    /// coarsening should stop here.
    fn coarsen_unknowns(&self, fine: &mut Level) -> Option<CoarseUnknowns>;
    /// The transfer between `fine` and the `coarse` level made from it.
    fn transfer(&self, fine: &Level, coarse: &Level) -> Transfer;
    /// `t` re-evaluated after both levels moved (same topology).
    fn update(&self, t: &mut Transfer, fine: &Level, coarse: &Level);
}

/// A coarse level without a mesh: some of the fine level's unknowns.
pub(crate) struct CoarseUnknowns {
    /// The fine unknowns kept, ascending.
    pub kept: Vec<u32>,
    /// What the coarsener knows about them (the pieces of boundary they lie on, their regions).
    pub features: Features,
    /// The transfer from the fine level.
    pub transfer: Transfer,
}

/// How the coarse levels are made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CoarseLevels {
    /// Kept unknowns, except in 2D in the paper-faithful mode, which keeps the paper's coarse
    /// meshes. Kept unknowns carry graded meshes, re-referenced meshes and slip walls at the
    /// iteration counts of uniform meshes, where coarse meshes need several times more (docs/
    /// DESIGN.md §5 "Which route where").
    #[default]
    Auto,
    /// Coarse meshes by vertex removal and a constrained Delaunay triangulation of the kept
    /// vertices, barycentric interpolation (2D only).
    Remeshed,
    /// A maximal independent set of the unknowns on each level, least-squares interpolation
    /// exact for linear fields, Galerkin coarse operators (2D and 3D).
    LeastSquares,
}

impl CoarseLevels {
    /// The route `Auto` stands for on meshes of dimension `dim` solved in `mode`.
    pub(crate) fn resolve(self, dim: usize, mode: Mode) -> CoarseLevels {
        match (self, dim, mode) {
            (CoarseLevels::Auto, 2, Mode::PaperFaithful) => CoarseLevels::Remeshed,
            (CoarseLevels::Auto, _, _) => CoarseLevels::LeastSquares,
            (kind, _, _) => kind,
        }
    }
}

/// The coarsener for meshes of dimension `dim` (`Auto` as in the default mode).
pub(crate) fn coarsener_for(dim: usize, kind: CoarseLevels, params: CoarsenParams) -> Result<Box<dyn Coarsener>> {
    match (dim, kind) {
        (2, CoarseLevels::Remeshed) => Ok(Box::new(Delaunay2d { params })),
        (2 | 3, CoarseLevels::Auto | CoarseLevels::LeastSquares) => {
            Ok(Box::new(LeastSquares { params }))
        }
        (3, CoarseLevels::Remeshed) => {
            Err(Error::Coarsening("coarse meshes are made in 2D only; 3D meshes use kept unknowns".into()))
        }
        _ => Err(Error::Coarsening(format!("no coarsener for {dim}D meshes"))),
    }
}
