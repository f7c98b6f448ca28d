//! Distributed meshes over MPI (the `mpi` feature): each rank gives its part of the mesh — its
//! vertices with global ids, its owned cells (and any ghost cells: the library fetches the layer
//! it needs from the cells' owners), its tagged faces — through the host's communicator, which
//! the library duplicates for its own messages.
//!
//! What is distributed today: the mesh with its ownership, global numbering and halo exchange
//! lists and every check of the serial mesh (each rank's part alone, then across ranks);
//! vectors over owned and halo entries with halo exchanges by nonblocking point-to-point
//! messages and inner products reproducible for a fixed number of ranks; and the mesh mover
//! ([`DistributedSolver`](crate::distributed::DistributedSolver): the three methods with FIXED,
//! CLAMPED, FREE and SLIP patches, links (by offset or by pairs of global ids), interfaces
//! of both variants and rigid motions, made with the serial
//! `Options`; the serial solver's steps: `advance`, `advance_from`, `move_in_steps`,
//! sub-stepping, both reference modes, per-step reports) with its C ABI
//! ([`capi`](crate::distributed::capi)), solved by conjugate gradients preconditioned by the
//! distributed multigrid (`mg`: algebraic kept-unknowns levels across ranks, the biharmonic's
//! K_c V_c⁻¹ K_c assembled on them, small coarse levels agglomerated onto fewer ranks and the
//! coarsest gathered onto one; kept between solves on one reference, `kept`). Every call is collective and returns the same status on every rank.

mod agreement;
mod bcs;
mod blocks;
pub mod capi;
mod comm;
mod dist_mesh;
mod error;
mod ghosts;
mod halo;
mod interfaces;
mod kept;
mod laplacian;
mod level_layout;
mod mg;
mod ownership;
mod pcg;
mod reduce;
mod slip;
mod solver;
mod ties;

pub use comm::Comm;
pub use dist_mesh::DistributedMesh;
pub use error::{DistError, DistErrorKind};
pub(crate) use level_layout::Distribution;
/// The MPI bindings (rsmpi) the library is built with: a host in Rust names its communicators
/// with these types.
pub use mpi;
pub use solver::{DistSolution, DistSolveParams, DistStepReport, DistributedSolver};
