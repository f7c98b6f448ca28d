//! Geometric multigrid (docs/DESIGN.md §5): coarse levels built from the user's mesh by a
//! `Coarsener`, linear transfers, rediscretised or Galerkin operators, Jacobi/Chebyshev
//! smoothing, W-cycles, and the solve to tolerance.

pub mod coarse_solve;
pub mod coarsen;
pub mod coarsener;
pub mod cycle;
pub mod group;
pub mod hierarchy;
mod layout;
mod lsq;
pub mod params;
pub mod policy;
pub mod restriction;
pub mod slip;
pub mod smoother;
pub mod solve;
