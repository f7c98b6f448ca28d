//! Geometric multigrid: coarse meshes by vertex removal and the transfers between levels.

pub mod coarsen;
pub mod transfer;
