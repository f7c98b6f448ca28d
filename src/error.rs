//! The one error type of the crate; the C status codes are derived from it in `capi`.

use crate::mesh::MeshError;
use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum Error {
    #[error("invalid mesh: {0}")]
    Mesh(#[from] MeshError),
    #[error("invalid boundary conditions: {0}")]
    Bc(String),
    #[error("ill-posed problem: component {component} has no prescribed vertex{detail}")]
    IllPosed { component: &'static str, detail: String },
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    #[error("multigrid hierarchy could not be built: {0}")]
    Coarsening(String),
    /// The iteration diverged, or conjugate gradients broke down (pᵀAp ≤ 0 or not finite).
    #[error("solver diverged: {0}")]
    Diverged(String),
    /// A solve stopped at its cycle limit above its tolerance.
    #[error("not converged: {0}")]
    NotConverged(String),
    /// The reference mesh of a step has cells of non-positive area: nothing was solved on it.
    #[error("tangled reference mesh: {0}")]
    Tangled(String),
    #[error("mesh file: {0}")]
    Io(#[from] crate::io::IoError),
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
