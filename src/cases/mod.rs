//! The paper's test cases (DESIGN §7): deterministic mesh generators with named patches.

mod cdt;
mod cylinder;
mod free_surface;
pub mod meshes;
