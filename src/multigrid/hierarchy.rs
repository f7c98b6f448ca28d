//! The multigrid hierarchy: a mesh per level with its unknowns, flags, operator and the
//! transfer to the next coarser level (DESIGN §5).
//!
//! Coarse vertices are a subset of the fine ones, so when the fine mesh moves the coarse meshes
//! follow it with their topology kept; only values are re-evaluated.

use super::coarse_solve::CoarseSolve;
use super::coarsen::{coarsen, CoarsenParams};
use super::smoother::{estimate_lambda_max, Problem};
use super::transfer::{locate, update_weights, Location};
use crate::bc::{check_well_posed, component_flags, BoundaryConditions, Dofs};
use crate::mesh::quality::signed_areas;
use crate::operator::{Assembly, LevelOperator, Method};
use crate::sparse::CsrMatrix;
use crate::{Mesh, Result};
use glam::DVec2;

/// Interpolation from the next coarser level and its transpose.
pub struct Transfer {
    locs: Vec<Location>,
    /// Fine unknowns × coarse unknowns: barycentric weights in the coarse cell.
    pub prolong: CsrMatrix,
    /// Its transpose, stored so restriction is a gather too.
    pub restrict: CsrMatrix,
}

pub struct Level {
    pub mesh: Mesh,
    pub pairs: Vec<[u32; 2]>,
    pub dofs: Dofs,
    asm: Assembly,
    pub op: LevelOperator,
    pub flags: [Vec<u8>; 2],
    pub inv_d: [Vec<f64>; 2],
    pub lambda_max: [f64; 2],
    /// Vertex i of this level is vertex `parent_vertex[i]` of the next finer level.
    pub parent_vertex: Vec<u32>,
    /// Transfer to the next coarser level; None on the coarsest.
    pub down: Option<Transfer>,
    /// Direct solve per component, on the coarsest level only.
    pub coarse: Option<[CoarseSolve; 2]>,
    /// Factor applied to K on this level (see `spring_scale`).
    k_scale: f64,
}

/// The spring stiffness (weights 1/L²) is not scale-free like the cotangent Laplacian: its
/// energy for a smooth field grows with the number of edges, so a rediscretised coarse spring
/// operator is about n_c/n_f of the Galerkin PᵀAP and every coarse correction overshoots ≈ 4×
/// (measured: spring-mg stalled at a 6e-3 residual after 500 CG iterations on 16k vertices).
/// Scaling level l's K by n_0/n_l (its vertex-count ratio to the finest) restores the balance.
fn spring_scale(method: Method, n_fine: usize, n_level: usize) -> f64 {
    if method == Method::Spring {
        n_fine as f64 / n_level as f64
    } else {
        1.0
    }
}

impl Level {
    fn new(
        mesh: Mesh,
        pairs: Vec<[u32; 2]>,
        parent_vertex: Vec<u32>,
        bcs: &BoundaryConditions,
        method: Method,
    ) -> Level {
        let dofs = Dofs::build(&mesh, &pairs, &bcs.split_patches());
        let asm = Assembly::new(&dofs);
        let flags = [0, 1].map(|c| component_flags(&mesh, &dofs, bcs, c));
        let op = LevelOperator::new(method, &asm, mesh.coords(), mesh.cells(), &dofs);
        let mut level = Level {
            mesh,
            pairs,
            dofs,
            asm,
            op,
            flags,
            inv_d: [Vec::new(), Vec::new()],
            lambda_max: [1.0; 2],
            parent_vertex,
            down: None,
            coarse: None,
            k_scale: 1.0,
        };
        level.refresh_bounds();
        level
    }

    /// Scales K by `f` (coarse spring levels, see `spring_scale`) and refreshes the bounds.
    fn set_k_scale(&mut self, f: f64) {
        self.k_scale = f;
        if f != 1.0 {
            self.op.k.vals.iter_mut().for_each(|a| *a *= f);
            self.refresh_bounds();
        }
    }

    fn refresh_bounds(&mut self) {
        for c in 0..2 {
            self.inv_d[c] = self.op.inv_l1_diag(&self.flags[c]);
            self.lambda_max[c] = estimate_lambda_max(&self.op, &self.flags[c], &self.inv_d[c]);
        }
    }

    pub fn problem(&self, c: usize) -> Problem<'_> {
        Problem { op: &self.op, flags: &self.flags[c], inv_d: &self.inv_d[c], lambda_max: self.lambda_max[c] }
    }

    pub fn n(&self) -> usize {
        self.dofs.n
    }

    /// Positions of the unknowns and the region each should be interpolated from.
    fn dof_points(&self) -> (Vec<DVec2>, Vec<Option<i32>>) {
        let x = self.mesh.coords();
        let pts = self.dofs.dof_vertex.iter().map(|&v| x[v as usize]).collect();
        // A vertex inside one region interpolates from that region's coarse cells only.
        let mut vregion: Vec<Option<Option<i32>>> = vec![None; self.mesh.num_vertices()];
        for (t, &r) in self.mesh.cells().iter().zip(self.mesh.regions()) {
            for &v in t {
                let e = &mut vregion[v as usize];
                *e = match *e {
                    None => Some(Some(r)),
                    Some(Some(q)) if q == r => Some(Some(r)),
                    _ => Some(None),
                };
            }
        }
        let regions = (0..self.dofs.n)
            .map(|d| self.dofs.dof_region[d].or(vregion[self.dofs.dof_vertex[d] as usize].flatten()))
            .collect();
        (pts, regions)
    }
}

fn prolongation(n_fine: usize, coarse: &Level, locs: &[Location]) -> CsrMatrix {
    let mut t = Vec::with_capacity(3 * locs.len());
    for (i, loc) in locs.iter().enumerate() {
        let cd = coarse.dofs.cell_dofs[loc.cell as usize];
        for k in 0..3 {
            t.push((i as u32, cd[k], loc.weights[k]));
        }
    }
    CsrMatrix::from_triplets(n_fine, coarse.n(), t)
}

/// Hierarchy parameters.
#[derive(Clone, Debug)]
pub struct HierarchyParams {
    pub coarsen: CoarsenParams,
    /// Stop after this many levels (the paper used six).
    pub max_levels: usize,
}

impl Default for HierarchyParams {
    fn default() -> Self {
        HierarchyParams { coarsen: CoarsenParams::default(), max_levels: 20 }
    }
}

pub struct Hierarchy {
    pub levels: Vec<Level>,
    pub method: Method,
}

impl Hierarchy {
    /// Builds every level from the fine mesh and its resolved link pairs.
    pub fn build(
        mesh: &Mesh,
        pairs: Vec<[u32; 2]>,
        bcs: &BoundaryConditions,
        method: Method,
        params: &HierarchyParams,
    ) -> Result<Hierarchy> {
        let fine = Level::new(mesh.clone(), pairs, Vec::new(), bcs, method);
        check_well_posed(&fine.op.k, &fine.flags, &fine.dofs)?;
        let mut levels = vec![fine];
        while levels.len() < params.max_levels {
            let fine = levels.last().expect("one level at least");
            let Some(cm) = coarsen(&fine.mesh, &fine.pairs, &params.coarsen)? else {
                break;
            };
            let mut coarse = Level::new(cm.mesh, cm.links, cm.fine_vertex, bcs, method);
            coarse.set_k_scale(spring_scale(method, mesh.num_vertices(), coarse.mesh.num_vertices()));
            let (pts, regions) = fine.dof_points();
            let locs = locate(&coarse.mesh, &pts, &regions);
            let prolong = prolongation(fine.n(), &coarse, &locs);
            let restrict = prolong.transpose();
            levels.last_mut().expect("fine level").down = Some(Transfer { locs, prolong, restrict });
            levels.push(coarse);
        }
        let mut h = Hierarchy { levels, method };
        h.build_coarse_solve()?;
        Ok(h)
    }

    fn build_coarse_solve(&mut self) -> Result<()> {
        let last = self.levels.last_mut().expect("one level at least");
        let solves = [CoarseSolve::new(last.problem(0))?, CoarseSolve::new(last.problem(1))?];
        last.coarse = Some(solves);
        Ok(())
    }

    pub fn fine(&self) -> &Level {
        &self.levels[0]
    }

    /// Re-evaluates every level at new fine-vertex positions, keeping the coarse topology.
    /// Returns false (and changes nothing) when a coarse cell would invert: the caller rebuilds.
    pub fn move_to(&mut self, fine_coords: Vec<DVec2>) -> Result<bool> {
        let mut coords = vec![fine_coords];
        for l in 1..self.levels.len() {
            let prev = &coords[l - 1];
            let c: Vec<DVec2> = self.levels[l].parent_vertex.iter().map(|&v| prev[v as usize]).collect();
            if signed_areas(&self.levels[l].mesh, &c).iter().any(|&a| a <= 0.0) {
                return Ok(false);
            }
            coords.push(c);
        }
        let method = self.method;
        for (level, c) in self.levels.iter_mut().zip(coords) {
            level.mesh = level.mesh.with_coords(c);
            level.op = LevelOperator::new(method, &level.asm, level.mesh.coords(), level.mesh.cells(), &level.dofs);
            level.refresh_bounds();
            level.set_k_scale(level.k_scale);
        }
        for l in 0..self.levels.len() - 1 {
            let (pts, _) = self.levels[l].dof_points();
            let (fine, rest) = self.levels.split_at_mut(l + 1);
            let (fine, coarse) = (&mut fine[l], &rest[0]);
            let n_fine = fine.n();
            let down = fine.down.as_mut().expect("not the coarsest level");
            update_weights(&coarse.mesh, &pts, &mut down.locs);
            let prolong = prolongation(n_fine, coarse, &down.locs);
            down.restrict = prolong.transpose();
            down.prolong = prolong;
        }
        self.build_coarse_solve()?;
        Ok(true)
    }

    /// A table of the levels (PyAMG style): unknowns, cells, nonzeros, and complexities.
    pub fn describe(&self) -> String {
        let mut s = String::from("level  unknowns     cells       nnz(K)\n");
        let (mut nsum, mut zsum) = (0usize, 0usize);
        for (l, lev) in self.levels.iter().enumerate() {
            s += &format!("{l:>5} {:>9} {:>9} {:>12}\n", lev.n(), lev.mesh.num_cells(), lev.op.k.nnz());
            nsum += lev.n();
            zsum += lev.op.k.nnz();
        }
        let f = &self.levels[0];
        s += &format!(
            "grid complexity {:.3}, operator complexity {:.3}\n",
            nsum as f64 / f.n() as f64,
            zsum as f64 / f.op.k.nnz() as f64
        );
        s
    }
}
