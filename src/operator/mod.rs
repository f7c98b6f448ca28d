//! The discrete operators of docs/DESIGN.md §3: stiffness K (cotangent or spring weights), lumped mass
//! V, and per method the operator A, its right-hand side and its l1 Jacobi bound.

mod columns;
mod fused;
mod general;
mod galerkin_biharmonic;
mod level;
mod scatter;
mod small_entries;
mod stiffness;

pub(crate) use columns::Columns;
pub(crate) use galerkin_biharmonic::assembled_below;
pub use level::LevelOperator;
pub(crate) use stiffness::close_diagonal;
pub(crate) use stiffness::{lumped_mass, spring_stiffness, stiffness_and_mass};

/// Which equation moves the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Method {
    /// ∇⁴d = 0 in the mixed form −∇²d = S, −∇²S = 0 (the paper's method).
    #[default]
    Biharmonic,
    /// ∇²d = 0.
    Laplacian,
    /// Graph Laplacian with edge weights 1/L² (Batina's spring analogy).
    Spring,
}
