//! The one error type of the crate; the C status codes are derived from it in `capi`.

use crate::mesh::MeshError;
use thiserror::Error;

/// Everything that can go wrong in meshmove; each variant's message names the offending item.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum Error {
    /// The mesh is invalid.
    #[error("invalid mesh: {0}")]
    Mesh(#[from] MeshError),
    /// The boundary conditions do not fit the mesh (an unknown patch, a link without partners, …); the
    /// message says which.
    #[error("invalid boundary conditions: {0}")]
    Bc(String),
    /// A displacement component is undetermined: a connected part of the mesh has no vertex where it
    /// is prescribed.
    #[error("ill-posed problem: component {component} has no prescribed vertex{detail}")]
    IllPosed {
        /// The undetermined component: `"x"`, `"y"` or `"z"`.
        component: &'static str,
        /// The rest of the message: the part of the mesh (when there are several) and the remedy.
        detail: String,
    },
    /// An argument or option is out of its range; the message says which.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// The multigrid hierarchy could not be built (the coarsener refused its input).
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
    /// The caller's progress hook asked to stop: the call was cancelled and changed nothing.
    #[error("cancelled: {0}")]
    Cancelled(String),
    /// A callback of the caller (a slip surface's projection) reported a failure; nothing was
    /// changed.
    #[error("callback failed: {0}")]
    CallbackFailed(String),
    /// Memory for the call could not be reserved (the system refused it, or the solver's memory
    /// budget is smaller than what it would need); nothing was changed.
    #[error("out of memory: {0}")]
    OutOfMemory(String),
    /// A mesh file could not be read or written.
    #[error("mesh file: {0}")]
    Io(#[from] crate::io::IoError),
}

/// The crate's result type, with [`enum@Error`] as the default error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::{read_msh, IoError};

    #[test]
    fn io_error_converts_into_crate_error() {
        let e: Error = read_msh(std::path::Path::new("tests/data/no_such_file.msh")).unwrap_err().into();
        assert!(matches!(e, Error::Io(IoError::Io { .. })));
        assert_eq!(e.clone(), e);
    }
}
