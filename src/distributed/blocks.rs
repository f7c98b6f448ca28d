//! The preconditioner of a group of components from their scalar multigrids: each block of the
//! residual through its component's V-cycle, then the group's slip projection Π.
//!
//! The distributed multigrid coarsens one scalar operator (a component's free rows), and its
//! coarse levels carry no slip frames. A group coupled by slip walls is therefore
//! preconditioned by M = Π diag(M₀, M₁, …) Π, Mc the V-cycle of component c with its slip
//! unknowns free: symmetric, and positive on the subspace Π leaves (xᵀMx = (Πx)ᵀ diag(Mc) (Πx)),
//! so it preconditions conjugate gradients on Π A Π. It drops the coupling of the components
//! at the walls, which the serial hierarchy keeps on every level, and takes more iterations.

use super::kept::Hierarchies;
use super::pcg::Preconditioner;
use crate::multigrid::group::{block, block_mut, GroupOp};

/// The block preconditioner of one group.
pub(crate) struct Blocks<'a, 'b> {
    op: &'b GroupOp<'a>,
    /// The kept multigrid of each component (the group's components' are used).
    multigrids: &'b mut Hierarchies,
}

impl<'a, 'b> Blocks<'a, 'b> {
    /// The preconditioner of the group `op`, the block of component c through
    /// `multigrids.of(c)`.
    pub(crate) fn new(op: &'b GroupOp<'a>, multigrids: &'b mut Hierarchies) -> Self {
        Blocks { op, multigrids }
    }
}

impl Preconditioner for Blocks<'_, '_> {
    fn apply(&mut self, r: &[f64], z: &mut [f64]) {
        let n = self.op.n();
        for (k, c) in self.op.components().enumerate() {
            self.multigrids.of(c).apply(block(r, n, k), block_mut(z, n, k));
        }
        self.op.project(z);
    }
}
