//! What a case is: a complete set-up (mesh, boundary conditions, motion, steps) and the mesh
//! sizes it comes in. The 2D (`setups`), 3D (`setups3d`) and body (`bodies3d`) cases make them.

use meshmove::bc::BoundaryConditions;
use meshmove::mesh::Mesh;
use meshmove::motion::Motion;

/// Mesh sizes: the paper's (docs/DESIGN.md §7) or coarse ones for quick smoke runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// Free-surface and interface meshes at h = 1/32, cylinder in channel at h = 1/12.
    Paper,
    /// h = 1/12 and 1/6; the boundary-layer cylinder has one size only (about 7k vertices).
    Quick,
}

/// One case: everything a solver needs, plus what the report measures.
#[derive(Clone, Debug)]
pub struct CaseSetup {
    pub name: String,
    pub mesh: Mesh,
    pub bcs: BoundaryConditions,
    /// The whole motion from the original mesh; split into `steps` equal increments.
    pub motion: Motion,
    pub steps: usize,
    /// The patch whose motion drives the case (spacing variation is measured along it).
    pub moved_patch: i32,
    /// For the interface cases: the region above the interface (for `max_y_upper`).
    pub upper_region: Option<i32>,
}
