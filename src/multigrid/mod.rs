//! Geometric multigrid (docs/DESIGN.md §5): coarse levels built from the user's mesh by a
//! `Coarsener`, linear transfers, rediscretised or Galerkin operators, Jacobi/Chebyshev
//! smoothing, W-cycles, and the solve to tolerance.

mod bounds;
pub(crate) mod cell_edges;
pub mod coarse_solve;
pub mod coarsen;
pub mod coarsener;
pub mod cycle;
pub mod group;
pub mod hierarchy;
mod lag;
mod lanczos;
pub(crate) mod layout;
pub mod level;
#[cfg(feature = "mpi")]
pub(crate) mod local_level;
pub(crate) mod line_smoother;
pub(crate) mod lines;
pub(crate) mod lsq;
pub mod params;
pub mod phases;
mod refit;
pub mod policy;
pub mod restriction;
pub mod slip;
pub mod smoother;
pub mod solve;
pub(crate) mod strain;
#[cfg(feature = "internals")]
pub mod two_level;

use coarsen::{CoarsenParams, Delaunay2d};
use coarsener::Coarsener;
use lsq::LeastSquares;
use params::Mode;
use crate::{Error, Result};

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
        (2, CoarseLevels::Remeshed) => Ok(Box::new(Delaunay2d::new(params))),
        (2 | 3, CoarseLevels::Auto | CoarseLevels::LeastSquares) => Ok(Box::new(LeastSquares::new(params))),
        (3, CoarseLevels::Remeshed) => {
            Err(Error::Coarsening("coarse meshes are made in 2D only; 3D meshes use kept unknowns".into()))
        }
        _ => Err(Error::Coarsening(format!("no coarsener for {dim}D meshes"))),
    }
}
