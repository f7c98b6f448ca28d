//! A single level over one rank's part of a distributed mesh: its local vertices are its
//! unknowns (owned first, then the halo), its operator is assembled from its owned and ghost
//! cells, and its layout exchanges the halo. The group operator, the smoothers and their bounds
//! run on it as on any level; only the layout differs.

use super::group::{estimate_lambda_max, GroupOp};
use super::layout::Distribution;
use super::level::Level;
use super::line_smoother::LineBlocks;
use crate::bc::Dofs;
use crate::operator::LevelOperator;
use crate::Mesh;

/// The level of the operator `op` on `mesh` (the rank's local vertices in layout order; a
/// biharmonic's operator carries its halo exchange between the passes), with the per-component
/// `flags` and the Jacobi bounds of the smoother (collective: λmax is estimated over every
/// rank's rows).
pub(crate) fn local_level(mesh: Mesh, op: LevelOperator, flags: Vec<Vec<u8>>, layout: Distribution) -> Level {
    let dofs = Dofs::identity(mesh.num_vertices());
    let inv_d = flags.iter().map(|f| op.inv_l1_diag(f)).collect();
    let comps = flags.len();
    let mut level = Level {
        mesh: Some(mesh),
        points: Vec::new(),
        pairs: Vec::new(),
        dofs,
        op,
        flags,
        inv_d,
        lambda_max: vec![1.0; comps],
        lines: LineBlocks::default(),
        parent_vertex: Vec::new(),
        down: None,
        slip: None,
        layout,
    };
    level.lambda_max = (0..comps).map(|c| estimate_lambda_max(&GroupOp::new(&level, c..c + 1, false))).collect();
    level
}
