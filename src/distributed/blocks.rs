//! The preconditioner of a group of components.
//!
//! With slip walls (and no periodic links) one multigrid carries every component
//! (`mg::Multigrid::build_group`: the slip frames and each component's flags on every level),
//! and a group is preconditioned by its cycle over the group's components.
//!
//! Otherwise the distributed multigrid coarsens one scalar operator per component (its free
//! rows), whose coarse levels carry no ties. A group tied by periodic links is therefore
//! preconditioned by a cycle whose finest level is the group's own: the group's smoother (the
//! Chebyshev–Jacobi steps on Π A Π, the projection Π of the slip frames and the ties in every
//! step, the Jacobi diagonal equalised at slip and tied vertices) before and after a coarse
//! correction Π P_c (each component's coarse levels) P_cᵀ Π of the residual. The smoother is
//! the same polynomial both times and the coarse correction is symmetric, so the cycle is a
//! symmetric positive preconditioner on the subspace Π leaves. The coarse levels still see the
//! components apart, with their slip unknowns free and their tied vertices apart, which the
//! serial hierarchy does not.
//!
//! Where every component's finest level would be gathered at once, the group's coupled solve
//! takes the cycle's place (`mg::CoupledSolve`): (Π A Π)⁻¹ on the subspace, as the serial
//! dense coarsest solve has it.

use super::kept::Hierarchies;
use super::level_layout::Distribution;
use super::pcg::Preconditioner;
use crate::multigrid::group::{block, block_mut, GroupOp, Scratch};
use crate::multigrid::smoother::{smooth, Coefficients, Smoother, Start};

/// The preconditioner of one group.
pub(crate) struct Blocks<'a, 'b> {
    op: &'b GroupOp<'a>,
    /// The kept multigrid of each component (the group's components' are used).
    multigrids: &'b mut Hierarchies,
    /// The group's index among the level's groups (its coupled solve's, if it has one).
    group: usize,
    sm: Smoother,
    work: Vec<Scratch>,
    coefficients: Coefficients,
    /// The residual after the first smoothing, the coarse correction, and the operator's scratch.
    r: Vec<f64>,
    e: Vec<f64>,
    s: Vec<f64>,
}

impl<'a, 'b> Blocks<'a, 'b> {
    /// The preconditioner of the group `op`, number `group` of the level's groups, smoothed by
    /// `sm`: its coupled solve if `multigrids` has one, else the cycle over the components'
    /// multigrids (`multigrids.of(c)`).
    pub(crate) fn new(op: &'b GroupOp<'a>, multigrids: &'b mut Hierarchies, group: usize, sm: Smoother) -> Self {
        // The cycle's vectors, for a group whose components are coupled (else left empty).
        let tied = matches!(op.level().layout, Distribution::Tied(..));
        let own = (op.frames().is_some() || tied) && !multigrids.whole;
        let (n, len) = if own { (op.n(), op.len()) } else { (0, 0) };
        let work = (0..len).map(|_| Scratch::new(n, op.level().op.method)).collect();
        let (r, e, s) = (vec![0.0; n * len], vec![0.0; n * len], vec![0.0; n]);
        Blocks { op, multigrids, group, sm, work, coefficients: Coefficients::default(), r, e, s }
    }
}

impl Preconditioner for Blocks<'_, '_> {
    fn apply(&mut self, r: &[f64], z: &mut [f64]) {
        let n = self.op.n();
        if let Some(coupled) = self.multigrids.coupled.get(self.group).and_then(Option::as_ref) {
            coupled.solve(r, z, n);
            self.op.project(z);
            return;
        }
        if self.multigrids.whole {
            // The multigrid of every component, its cycle over the group's.
            let comps = self.op.components();
            // Every group has the one multigrid (`Hierarchies::whole`); without it, the identity.
            match self.multigrids.of(comps.start) {
                Some(m) => m.apply_group(comps, r, z),
                None => z.copy_from_slice(r),
            }
            return;
        }
        if self.work.is_empty() {
            // Nothing couples the group's components or ties its rows: each component's own cycle.
            // A component iterated on has its multigrid (`Hierarchies::build` makes it for every
            // component with a nonzero right-hand side); without one, the identity.
            for (k, c) in self.op.components().enumerate() {
                match self.multigrids.of(c) {
                    Some(m) => m.apply(block(r, n, k), block_mut(z, n, k)),
                    None => block_mut(z, n, k).copy_from_slice(block(r, n, k)),
                }
            }
            return;
        }
        let op = self.op;
        smooth(op, self.sm, r, z, &mut self.work, &mut self.coefficients, Start::Zero, false);
        op.residual(r, z, &mut self.r, &mut self.s);
        for (k, c) in op.components().enumerate() {
            let e = block_mut(&mut self.e, n, k);
            match self.multigrids.of(c) {
                Some(m) => m.coarse_correction(block(&self.r, n, k), e),
                None => e.iter_mut().for_each(|e| *e = 0.0),
            }
        }
        op.project(&mut self.e);
        z.iter_mut().zip(&self.e).for_each(|(z, e)| *z += e);
        smooth(op, self.sm, r, z, &mut self.work, &mut self.coefficients, Start::Guess, false);
    }
}
