//! When a re-reference keeps the coarse levels of an earlier one.
//!
//! The fine level defines the discrete problem, so every re-reference evaluates it again (K, V,
//! flags, slip frames, smoother bounds). The coarse levels only precondition it: coarse levels
//! made at positions a little away from the fine level's still reduce the smooth error nearly
//! as well, and conjugate gradients absorbs what they miss. So a re-reference keeps the coarse
//! levels (unknowns, transfers, Galerkin products, bounds, the coarsest level's factors) from
//! the last full refresh, its anchor, while the fine level's Jacobi diagonal stays close to its
//! value there, and refreshes them all otherwise. Of the kept levels, the first coarse level's
//! Galerkin product and bounds follow the fine operator through the kept interpolation
//! (`Hierarchy::refill_first_coarse`): kept as well, they cost the biharmonic iterations that
//! outweigh their price (docs/perf-history.md). The Laplacian's refill, the larger part of its
//! kept re-reference, waits until some unknown's diagonal has changed by `REFILL_FROM` since the
//! last one (`refills`): its hexahedral and tetrahedral boxes keep their counts without it
//! (docs/PERFORMANCE.md, "The Laplacian's first coarse product refilled when the diagonal
//! moved").
//!
//! The measure is data only (no time, no thread count): per free unknown of the first component,
//! the relative change of its l1 Jacobi diagonal since the anchor, which follows the change of
//! the cells around it (their size and shape; rigid motions leave it alone, as they leave K and
//! V). The anchor keeps its fine positions, so a failed call can restore a state with kept
//! coarse levels bitwise (`Hierarchy::restore`).

use super::bounds::largest_drift;
use crate::operator::Method;
use crate::sparse::det_sum;
use std::sync::Arc;

/// The largest mean relative change of the fine Jacobi diagonal since the anchor with which a
/// re-reference keeps the coarse levels (docs/perf-history.md, "coarse levels kept").
pub(crate) const KEEP_COARSE_BELOW: f64 = 0.05;

/// The largest relative change of a free unknown's fine Jacobi diagonal since the first coarse
/// level's product was last refilled from which a kept re-reference of the Laplacian refills it
/// again (docs/PERFORMANCE.md, "The Laplacian's first coarse product refilled when the diagonal
/// moved").
pub(crate) const REFILL_FROM: f64 = 0.2;

/// Whether a kept re-reference of `method` refills the first coarse level's product: always,
/// but for the Laplacian, whose product waits while every free unknown's diagonal (the inverse
/// `inv_d`) stays within `REFILL_FROM` of its value at the last refill, `last`.
pub(crate) fn refills(method: Method, last: &[f64], inv_d: &[f64]) -> bool {
    !waits(method) || largest_drift(last, inv_d) >= REFILL_FROM
}

/// Whether a kept re-reference of `method` may leave the first coarse level's product as it
/// was (`refills`).
pub(crate) fn waits(method: Method) -> bool {
    method == Method::Laplacian
}

/// The state of the last full refresh the coarse levels come from.
#[derive(Clone)]
pub(crate) struct Anchor {
    /// The fine level's positions there.
    pub(crate) coords: Arc<[f64]>,
    /// The fine level's inverse l1 Jacobi diagonal of its first component there.
    pub(crate) inv_d: Arc<[f64]>,
}

impl Anchor {
    /// The anchor of a full refresh at `coords` with the fine level's inverse diagonal `inv_d`.
    pub(crate) fn new(coords: &[f64], inv_d: &[f64]) -> Anchor {
        Anchor { coords: coords.into(), inv_d: inv_d.into() }
    }

    /// The mean over the unknowns free at both of the relative change of the Jacobi diagonal
    /// from the anchor's to `inv_d`'s (inverse diagonals, as the levels keep them).
    pub(crate) fn drift(&self, inv_d: &[f64]) -> f64 {
        if inv_d.len() != self.inv_d.len() {
            return f64::INFINITY;
        }
        let both = |i: usize| self.inv_d[i] > 0.0 && inv_d[i] > 0.0;
        let free = det_sum(inv_d.len(), |i| if both(i) { 1.0 } else { 0.0 });
        if free == 0.0 {
            return 0.0;
        }
        // D_now / D_anchor = inv_d_anchor / inv_d_now.
        det_sum(inv_d.len(), |i| if both(i) { (self.inv_d[i] / inv_d[i] - 1.0).abs() } else { 0.0 }) / free
    }

    /// Whether a fine level with the inverse diagonal `inv_d` keeps the coarse levels.
    pub(crate) fn keeps(&self, inv_d: &[f64]) -> bool {
        self.drift(inv_d) < KEEP_COARSE_BELOW
    }
}

#[cfg(test)]
mod tests {
    use crate::bc::Kind;
    use crate::mesh::fixtures::rect;
    use crate::multigrid::hierarchy::{Hierarchy, HierarchyParams};
    use crate::{BoundaryConditions, Mesh, Method};

    /// Every level's K values, inverse diagonals and λmax, as bits.
    fn state(h: &Hierarchy) -> Vec<Vec<u64>> {
        h.levels
            .iter()
            .map(|l| {
                let d = l.inv_d.iter().flatten();
                l.op.k.vals.iter().chain(d).chain(&l.lambda_max).map(|x| x.to_bits()).collect()
            })
            .collect()
    }

    /// The hierarchy of `method` on `mesh` with one side fixed and the opposite one clamped.
    fn built(mesh: &Mesh, method: Method) -> Hierarchy {
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(1, Kind::Fixed).set_kinds(3, Kind::Clamped);
        // A coarsest size below 2D's default keeps three levels on this small mesh.
        let mut params = HierarchyParams::default();
        params.coarsen.coarsest_unknowns = Some(40);
        Hierarchy::build(mesh, Vec::new(), &bcs, method, &params).unwrap()
    }

    /// A small stretch keeps the coarse levels below the first (bitwise those of the build) and
    /// re-evaluates the fine one and the first coarse one's product; a rigid turn of it keeps
    /// them too; a large squash refreshes them all; a failed
    /// call's restore of a state with kept coarse levels is bitwise that state.
    #[test]
    fn small_changes_keep_the_coarse_levels_and_large_ones_refresh_them() {
        let mesh = rect(24, 24, [0.0, 1.0, 0.0, 1.0]);
        for method in [Method::Biharmonic, Method::Laplacian] {
            let mut h = built(&mesh, method);
            assert!(h.levels.len() >= 3, "{} levels", h.levels.len());
            let built = state(&h);

            let stretched: Vec<f64> = mesh.coords().chunks(2).flat_map(|p| [p[0] * (1.0 + 0.01 * p[0]), p[1]]).collect();
            assert!(h.move_to(stretched.clone()).unwrap());
            assert!(h.phases().coarse_kept, "{method:?}: a small stretch keeps the coarse levels");
            let kept = state(&h);
            assert_ne!(kept[0], built[0], "{method:?}: the fine level is re-evaluated");
            // The biharmonic refills the first coarse product; the Laplacian's waits for a
            // larger change (`refills`).
            match method {
                Method::Laplacian => assert_eq!(kept[1], built[1], "the Laplacian's first coarse product waits"),
                _ => assert_ne!(kept[1], built[1], "{method:?}: the first coarse product is refilled"),
            }
            assert_eq!(kept[2..], built[2..], "{method:?}: the levels below it are the build's");

            let (c, s) = (0.3f64.cos(), 0.3f64.sin());
            let turned: Vec<f64> = stretched.chunks(2).flat_map(|p| [c * p[0] - s * p[1] + 2.0, s * p[0] + c * p[1]]).collect();
            let carried = h.carried();
            assert!(h.move_to(turned).unwrap());
            assert!(h.phases().coarse_kept, "{method:?}: a rigid turn keeps the coarse levels");

            let squashed: Vec<f64> = mesh.coords().chunks(2).flat_map(|p| [p[0], p[1] * (0.3 + 0.7 * p[1])]).collect();
            assert!(h.move_to(squashed).unwrap());
            assert!(!h.phases().coarse_kept, "{method:?}: a large squash refreshes the coarse levels");
            assert_ne!(state(&h)[2], built[2], "{method:?}: refreshed");

            assert!(h.restore(stretched, carried).unwrap());
            assert_eq!(state(&h), kept, "{method:?}: a restore gives the kept state bitwise");
            assert!(h.phases().coarse_kept);
        }
    }

    /// The Laplacian's first coarse product waits while every unknown's diagonal stays within
    /// `REFILL_FROM` of its value at the last refill and is refilled past it; a failed call's
    /// restore of a state whose product was refilled on an earlier kept re-reference, and then
    /// left, is bitwise that state.
    #[test]
    fn the_laplacians_first_coarse_product_waits_for_a_large_local_change() {
        let mesh = rect(24, 24, [0.0, 1.0, 0.0, 1.0]);
        let mut h = built(&mesh, Method::Laplacian);
        let built = state(&h);
        // The last column of cells squeezed to 0.3 of its width: a large change of a few rows'
        // diagonals, a small mean change.
        let squeezed: Vec<f64> =
            mesh.coords().chunks(2).flat_map(|p| [if p[0] > 0.99 { p[0] - 0.7 / 24.0 } else { p[0] }, p[1]]).collect();
        assert!(h.move_to(squeezed.clone()).unwrap());
        assert!(h.phases().coarse_kept, "a local squeeze keeps the coarse levels");
        let refilled = state(&h);
        assert_ne!(refilled[1], built[1], "a large local change refills the first coarse product");
        assert_eq!(refilled[2..], built[2..]);

        let nudged: Vec<f64> = squeezed.chunks(2).flat_map(|p| [p[0] * (1.0 + 0.002 * p[0]), p[1]]).collect();
        assert!(h.move_to(nudged.clone()).unwrap());
        assert!(h.phases().coarse_kept);
        let waited = state(&h);
        assert_ne!(waited[0], refilled[0], "the fine level is re-evaluated");
        assert_eq!(waited[1..], refilled[1..], "a small change leaves the first coarse product");

        let carried = h.carried();
        let squashed: Vec<f64> = mesh.coords().chunks(2).flat_map(|p| [p[0], p[1] * (0.3 + 0.7 * p[1])]).collect();
        assert!(h.move_to(squashed).unwrap());
        assert!(!h.phases().coarse_kept);
        assert!(h.restore(nudged, carried).unwrap());
        assert_eq!(state(&h), waited, "a restore gives the state bitwise");
    }

    /// The drift is the mean relative change of the diagonal over the unknowns free at both.
    #[test]
    fn the_drift_is_the_mean_relative_change_of_the_free_diagonal() {
        let a = super::Anchor::new(&[], &[1.0, 0.5, 0.0, 0.25]);
        // D: 1, 2, –, 4 at the anchor; 1.1, 2, –, 3 now (a prescribed row stays out).
        let d = a.drift(&[1.0 / 1.1, 0.5, 0.0, 1.0 / 3.0]);
        assert!((d - (0.1 + 0.0 + 0.25) / 3.0).abs() < 1e-12, "{d}");
        assert_eq!(a.drift(&[1.0; 3]), f64::INFINITY);
    }
}
