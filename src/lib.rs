#![deny(missing_docs)]
//! meshmove: moves the interior of an unstructured mesh when its boundaries move.
//!
//! The biharmonic mesh deformation of Helenbrook (2001), beside the Laplacian and spring-analogy
//! movers, solved by geometric multigrid W-cycles. `docs/DESIGN.md` states the discrete equations.
//!
//! ```
//! use meshmove::{BoundaryConditions, IndexBase, Kind, Mesh, Motion, Options, Solver};
//! // Two triangles of the unit square plus a centre vertex; the right side moves up by 0.1.
//! let coords = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]];
//! let cells = [[0u32, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
//! let right = [([1u32, 2], 2)];
//! let mesh = Mesh::triangles(&coords, &cells, IndexBase::Zero, &right, None).unwrap();
//! let mut bcs = BoundaryConditions::new();
//! bcs.set_kinds(0, Kind::Fixed).set_kinds(2, Kind::Fixed);
//! let solver = Solver::new(&mesh, &bcs, Options::default()).unwrap();
//! let mut motion = Motion::zero(&mesh);
//! for v in mesh.patch_vertices(2) { motion.displacement[2 * v as usize + 1] = 0.1; }
//! // Corners 1 and 2 are also on patch 0 (FIXED, zero): the later patch id does not win, any
//! // prescription applies, and the value is read from the displacement array.
//! let sol = solver.solve(&motion).unwrap();
//! assert!(sol.report.converged);
//! assert!(sol.displacement[2 * 4 + 1] > 0.0);
//! ```

// The library's own tests name it as the integration tests do, so they can share their mesh
// generators (`tests/slabs`).
#[cfg(all(test, feature = "mpi"))]
extern crate self as meshmove;

/// A module of the solver's internals: public (and hidden from the documentation) only with
/// the `internals` feature, which the workspace's paper cases, the command line's bench and the
/// tests of the multigrid levels use. Not a stable API.
macro_rules! internal_mod {
    ($($name:ident),*) => {$(
        #[cfg(feature = "internals")]
        #[doc(hidden)]
        #[allow(missing_docs)]
        pub mod $name;
        #[cfg(not(feature = "internals"))]
        mod $name;
    )*};
}

internal_mod!(bc, dense, geometry, multigrid, operator, sparse);
#[doc(hidden)]
pub mod capi;
/// Distributed meshes over MPI (the `mpi` feature): a host's partition with ghost cells, through
/// its communicator.
#[cfg(feature = "mpi")]
pub mod distributed;
pub mod error;
pub mod io;
mod limits;
pub mod mesh;
pub mod motion;
mod pool;
pub mod solver;

pub use bc::{BoundaryConditions, InterfaceVariant, Kind, Link, SlipSurface};
pub use error::{Error, Result};
pub use geometry::CellType;
pub use mesh::{FaceMeshData, IndexBase, Mesh, MeshData, MeshError, PatchFace, Quality};
pub use motion::{Motion, RigidMotion};
pub use multigrid::coarsen::CoarsenParams;
pub use multigrid::hierarchy::{CoarseOperator, HierarchyParams};
pub use multigrid::solve::{Criterion, Mode, Report, SolveParams};
pub use multigrid::CoarseLevels;
pub use operator::Method;
pub use solver::{Cancel, Options, Progress, ReferenceMode, Solution, Solver, StepReport};

/// The README's example is compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
