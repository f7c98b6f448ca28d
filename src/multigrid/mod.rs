//! Geometric multigrid (docs/DESIGN.md §5): coarse meshes built from the user's mesh, linear transfer,
//! rediscretised operators, Jacobi/Chebyshev smoothing, W-cycles, and the solve to tolerance.

pub mod coarse_solve;
pub mod coarsen;
pub mod cycle;
pub mod hierarchy;
pub mod restriction;
pub mod smoother;
pub mod solve;
pub mod transfer;
