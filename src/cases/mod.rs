//! The paper's test cases (docs/DESIGN.md §7): deterministic mesh generators with named patches, the
//! complete set-ups (`setups`) and the measurements of a run (`report`).

pub mod boxes;
mod cdt;
mod cylinder;
mod free_surface;
pub mod hybrid;
pub mod meshes;
pub mod report;
pub mod setups;
