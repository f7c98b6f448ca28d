//! Coarse levels without meshes: a subset of the fine unknowns, interpolated by least squares
//! (the coarsener of 3D meshes, and a choice in 2D).
//!
//! No permissively licensed 3D constrained tetrahedraliser exists to rebuild coarse meshes as
//! the 2D coarsener does, and interpolation needs none: a coarse level keeps a maximal
//! independent set of the fine unknowns (`select`), each fine unknown interpolates from coarse
//! unknowns of its neighbourhood with the smallest weights that reproduce linear fields exactly
//! along the feature it lies on (`weights`: the whole space inside, the tangent plane on a
//! wall, the line on a crease), and the coarse operators are Galerkin products PᵀKP and PᵀV.
//! Linear exactness is what the biharmonic needs (docs/DESIGN.md §5); aggregation without it
//! does not converge mesh-independently. Coarse unknowns are fine unknowns, so a moved fine
//! mesh moves them too: the weights are re-evaluated with the same neighbours.

mod features;
mod weights;

pub(crate) use features::Features;

use super::coarsen::{CoarseMesh, CoarsenParams};
use super::coarsener::{CoarseUnknowns, Coarsener};
use super::hierarchy::{Level, Transfer};
use super::restriction::Restriction;
use crate::mesh::Mesh;
use crate::Result;
use std::sync::Arc;

/// The coarsener whose coarse levels are subsets of the fine unknowns.
pub(crate) struct LeastSquares {
    pub(crate) params: CoarsenParams,
}

impl Coarsener for LeastSquares {
    fn coarsen_mesh(&self, _fine: &Mesh, _links: &[[u32; 2]]) -> Result<Option<CoarseMesh>> {
        Ok(None)
    }

    fn coarsen_unknowns(&self, fine: &mut Level) -> Option<CoarseUnknowns> {
        let n = fine.n();
        if n <= self.params.coarsest_unknowns.max(self.params.min_vertices) {
            return None;
        }
        if fine.features.is_none() {
            let mesh = fine.mesh.as_ref().expect("the finest level has a mesh");
            let regions = fine.dof_regions();
            fine.features =
                Some(Features::build(mesh, &fine.dofs, &fine.pairs, regions, self.params.corner_angle_deg));
        }
        let features = fine.features.as_ref().expect("just built");
        let kept = select(&fine.op.k, features);
        let nc = kept.len();
        if nc < self.params.min_vertices || (n as f64) < self.params.min_ratio * nc as f64 {
            return None;
        }
        let features = features.subset(&kept);
        let transfer = transfer(fine, &kept);
        Some(CoarseUnknowns { kept, features, transfer })
    }

    fn transfer(&self, fine: &Level, coarse: &Level) -> Transfer {
        transfer(fine, &coarse.parent_vertex)
    }

    fn update(&self, t: &mut Transfer, fine: &Level, coarse: &Level) {
        t.prolong = Arc::new(weights::prolongation(fine, &coarse.parent_vertex, Some(&t.prolong)));
        t.restrict = Restriction::new(Arc::clone(&t.prolong));
    }
}

/// The transfer from `fine` to its unknowns `kept`.
fn transfer(fine: &Level, kept: &[u32]) -> Transfer {
    let prolong = Arc::new(weights::prolongation(fine, kept, None));
    let restrict = Restriction::new(Arc::clone(&prolong));
    Transfer { cells: Vec::new(), prolong, restrict }
}

/// The kept unknowns, ascending: a maximal independent set of K's graph, greedy in the order
/// corners, creases, walls, inside (each by index), where an unknown is dropped when a
/// neighbour that may interpolate it (`Features::donor_ok`) is already kept. Every dropped
/// unknown thus has a kept neighbour to interpolate from, and features are coarsened along
/// themselves: every other vertex of a crease, an independent set of a wall.
fn select(k: &crate::sparse::CsrMatrix, f: &Features) -> Vec<u32> {
    let n = k.nrows;
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_by_key(|&d| (f.feature_dim(d as usize), d));
    let mut kept = vec![false; n];
    for &v in &order {
        let v = v as usize;
        let (cols, _) = k.row(v);
        if !cols.iter().any(|&u| u as usize != v && kept[u as usize] && f.donor_ok(v, u as usize)) {
            kept[v] = true;
        }
    }
    (0..n as u32).filter(|&d| kept[d as usize]).collect()
}
