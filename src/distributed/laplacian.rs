//! The Laplacian mover with every patch FIXED: the first distributed solve, kept as the
//! shortest call (a thin case of [`DistributedSolver`]).

use super::dist_mesh::DistributedMesh;
use super::error::DistError;
use super::solver::{DistSolution, DistSolveParams, DistributedSolver};
use crate::{BoundaryConditions, Method, Motion};

impl DistributedMesh {
    /// Moves the interior by the Laplacian (∇²d = 0) so that every vertex on a patch face (every
    /// boundary face is on a patch, untagged ones on patch 0) takes its value of `boundary` (`dim`
    /// values per local vertex in the host's order, all finite; only the prescribed vertices'
    /// values are read, and each owner's are the ones used). Collective; every rank returns the
    /// same error when any fails.
    pub fn solve_laplacian(&self, boundary: &[f64], params: &DistSolveParams) -> Result<DistSolution, DistError> {
        let solver = DistributedSolver::new(self, &BoundaryConditions::new(), Method::Laplacian, *params)?;
        solver.solve(&Motion::from_displacement(boundary.to_vec()))
    }
}
