//! The paper's test cases (docs/DESIGN.md §7) and their 3D versions, for meshmove's command line,
//! tests and diagnostic probes (`examples/`): deterministic mesh generators with named patches
//! (`meshes`, `meshes3d`), the complete set-ups (`setups`, `setups3d`) and the measurements of a
//! run (`report`). Not part of the library: fixtures, free to change with the cases.

pub mod amplitude;
pub mod bodies3d;
pub mod boxes;
mod cdt;
pub mod cut;
mod cylinder;
mod free_surface;
pub mod hybrid;
pub mod meshes;
pub mod meshes3d;
pub mod ogrid;
pub mod report;
mod setup;
pub mod setups;
pub mod setups3d;
pub mod spheres3d;
pub mod viscous;
