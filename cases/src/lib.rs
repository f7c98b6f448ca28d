//! The paper's test cases (docs/DESIGN.md §7) and their 3D versions: deterministic mesh generators
//! with named patches (`meshes`, `meshes3d`), the complete set-ups (`setups`, `setups3d`) and the
//! measurements of a run (`report`).

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
pub mod setups;
pub mod setups3d;
pub mod spheres3d;
