//! meshmove: moves the interior of an unstructured mesh when its boundaries move.
//!
//! The biharmonic mesh deformation of Helenbrook (2001), beside the Laplacian and spring-analogy
//! movers, solved by geometric multigrid. See `DESIGN.md` for the discrete equations.

pub mod error;
pub mod mesh;
pub mod multigrid;
pub mod sparse;

pub use error::{Error, Result};
pub use mesh::{IndexBase, Mesh, MeshError, PatchEdge};
