//! The multigrid hierarchy: a mesh per level with its unknowns, flags, operator and the
//! transfer to the next coarser level (docs/DESIGN.md §5).
//!
//! Coarse vertices are a subset of the fine ones, so when the fine mesh moves the coarse meshes
//! follow it with their topology kept; only values are re-evaluated.

use super::coarse_solve::CoarseSolve;
use super::coarsen::{coarsen, CoarsenParams};
use super::restriction::Restriction;
use super::smoother::{estimate_lambda_max, Problem};
use super::transfer::{locate, update_weights, Location};
use crate::bc::{check_well_posed, component_flags, BoundaryConditions, Dofs};
use crate::mesh::quality::signed_areas;
use crate::operator::{LevelOperator, Method};
use crate::sparse::{offset, CsrMatrix};
use crate::{Mesh, Result};
use glam::DVec2;
use std::sync::Arc;

/// Interpolation from the next coarser level and its transpose.
pub struct Transfer {
    /// The coarse cell each fine unknown interpolates from; its weights are in `prolong` (and
    /// are recomputed from these cells when the mesh moves).
    cells: Vec<u32>,
    /// Fine unknowns × coarse unknowns: barycentric weights in the coarse cell.
    pub prolong: Arc<CsrMatrix>,
    /// Its transpose, stored (pattern only, weights read from `prolong`) so restriction is a
    /// gather too.
    pub restrict: Restriction,
}

impl Transfer {
    /// Locates the unknowns of `fine` in the cells of `coarse`. Runs with every finer level
    /// alive, so its temporaries (points, locations) go as soon as they are used.
    fn new(fine: &Level, coarse: &Level) -> Transfer {
        let locs = {
            let (pts, regions) = fine.dof_points();
            locate(&coarse.mesh, &pts, &regions)
        };
        let prolong = Arc::new(prolongation(coarse, &locs));
        let cells = locs.iter().map(|l| l.cell).collect();
        drop(locs);
        let restrict = Restriction::new(Arc::clone(&prolong));
        Transfer { cells, prolong, restrict }
    }

    /// New weights in the same coarse cells, for the fine unknowns now at `pts`.
    fn update(&mut self, pts: &[DVec2], coarse: &Level) {
        let mut locs: Vec<Location> = self.cells.iter().map(|&cell| Location { cell, weights: [0.0; 3] }).collect();
        update_weights(&coarse.mesh, pts, &mut locs);
        self.prolong = Arc::new(prolongation(coarse, &locs));
        drop(locs);
        self.restrict = Restriction::new(Arc::clone(&self.prolong));
    }
}

pub struct Level {
    pub mesh: Mesh,
    pub pairs: Vec<[u32; 2]>,
    pub dofs: Dofs,
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
}

/// What a level computes from its mesh (everything but the mesh itself), so it can be built
/// while the same mesh is being coarsened.
struct LevelParts {
    dofs: Dofs,
    op: LevelOperator,
    flags: [Vec<u8>; 2],
}

impl LevelParts {
    fn build(mesh: &Mesh, pairs: &[[u32; 2]], bcs: &BoundaryConditions, method: Method) -> LevelParts {
        let dofs = Dofs::build(mesh, pairs, &bcs.split_patches());
        let flags = [0, 1].map(|c| component_flags(mesh, &dofs, bcs, c));
        let op = LevelOperator::new(method, mesh, &dofs);
        LevelParts { dofs, op, flags }
    }

    fn into_level(self, mesh: Mesh, pairs: Vec<[u32; 2]>, parent_vertex: Vec<u32>) -> Level {
        let LevelParts { dofs, op, flags } = self;
        let mut level = Level {
            mesh,
            pairs,
            dofs,
            op,
            flags,
            inv_d: [Vec::new(), Vec::new()],
            lambda_max: [1.0; 2],
            parent_vertex,
            down: None,
            coarse: None,
        };
        level.refresh_bounds();
        level
    }
}

impl Level {
    fn refresh_bounds(&mut self) {
        // The two components are independent: side by side, so small levels use both threads.
        let bounds = |c: usize| {
            let inv_d = self.op.inv_l1_diag(&self.flags[c]);
            // The l1 bound guarantees λmax(D⁻¹A) ≤ 1. For the second-order operators it is
            // nearly tight (the same CG iteration counts as the estimate on the single-step
            // cases, 2–6% more on the multi-step ones), and the estimate, redone at every
            // re-evaluated step, costs about 2/3 of a Laplacian solve (30 products per level).
            // The biharmonic's bound is looser (18 iterations instead of 16 on the
            // boundary-layer cylinder), so it keeps the estimate.
            let lambda_max = if self.op.method == Method::Biharmonic {
                estimate_lambda_max(&self.op, &self.flags[c], &inv_d)
            } else {
                1.0
            };
            (inv_d, lambda_max)
        };
        let ((d0, l0), (d1, l1)) = rayon::join(|| bounds(0), || bounds(1));
        self.inv_d = [d0, d1];
        self.lambda_max = [l0, l1];
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
            .map(|d| self.dofs.region_of(d).or(vregion[self.dofs.dof_vertex[d] as usize].flatten()))
            .collect();
        (pts, regions)
    }
}

/// Row i interpolates fine unknown i from the unknowns of its coarse cell with the barycentric
/// weights: columns ascending, corners sharing an unknown summed in corner order onto zero
/// (exactly what `CsrMatrix::from_triplets` gives, built row by row without its triplet list).
fn prolongation(coarse: &Level, locs: &[Location]) -> CsrMatrix {
    let n = locs.len();
    let (mut row_ptr, mut cols, mut vals) =
        (Vec::with_capacity(n + 1), Vec::with_capacity(3 * n), Vec::with_capacity(3 * n));
    row_ptr.push(0);
    for loc in locs {
        let cd = coarse.dofs.cell_dofs(&coarse.mesh, loc.cell as usize);
        let mut corners = [0, 1, 2];
        corners.sort_by_key(|&k| cd[k]);
        let start = cols.len();
        for k in corners {
            if cols.len() == start || cols[cols.len() - 1] != cd[k] {
                cols.push(cd[k]);
                vals.push(0.0);
            }
            *vals.last_mut().expect("pushed above") += loc.weights[k];
        }
        row_ptr.push(offset(cols.len()));
    }
    CsrMatrix { nrows: n, ncols: coarse.n(), row_ptr, cols, vals }
}

/// How a coarse level's K and V are made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CoarseOperator {
    /// Galerkin for the spring analogy, rediscretised otherwise.
    ///
    /// Rediscretised spring operators are far too soft on coarse levels (their 1/L² weights
    /// shrink 4× per level): CG diverges on the free surface and takes 123 iterations on the
    /// wall layer of the boundary-layer cylinder, where Galerkin takes 5 (free surface 66k /
    /// 266k vertices: 4 / 5). The biharmonic and Laplacian converge
    /// as fast rediscretised (12 / 8 / 9 and 5 / 5 / 5) and their solves are 1.4–1.6× cheaper
    /// that way (sparser coarse operators), so they keep docs/DESIGN.md §5's rediscretisation.
    #[default]
    Auto,
    /// K and V rediscretised on the coarse mesh (docs/DESIGN.md §5).
    Rediscretised,
    /// K_c = PᵀKP, V_c = PᵀV; see `LevelOperator::galerkin`.
    Galerkin,
}

impl CoarseOperator {
    fn galerkin(self, method: Method) -> bool {
        match self {
            CoarseOperator::Auto => method == Method::Spring,
            CoarseOperator::Rediscretised => false,
            CoarseOperator::Galerkin => true,
        }
    }
}

/// Hierarchy parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct HierarchyParams {
    pub coarsen: CoarsenParams,
    /// How coarse levels get their operator.
    pub coarse_operator: CoarseOperator,
    /// Stop after this many levels (the paper used six).
    pub max_levels: usize,
}

impl Default for HierarchyParams {
    fn default() -> Self {
        HierarchyParams { coarsen: CoarsenParams::default(), coarse_operator: CoarseOperator::Auto, max_levels: 20 }
    }
}

pub struct Hierarchy {
    pub levels: Vec<Level>,
    pub method: Method,
    galerkin: bool,
    /// Built from the current fine mesh (true) or moved there from the mesh it was built on.
    pub fresh: bool,
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
        let mut levels: Vec<Level> = Vec::new();
        let (mut mesh, mut pairs, mut parent_vertex) = (mesh.clone(), pairs, Vec::new());
        loop {
            // A level's unknowns and operator do not depend on its coarsening, and both are
            // mostly serial work: on two threads they run side by side.
            let last = levels.len() + 1 >= params.max_levels;
            let (parts, cm) = rayon::join(
                || LevelParts::build(&mesh, &pairs, bcs, method),
                || if last { Ok(None) } else { coarsen(&mesh, &pairs, &params.coarsen) },
            );
            let mut level = parts.into_level(mesh, pairs, parent_vertex);
            match levels.last_mut() {
                None => check_well_posed(&level.op.k, &level.flags, &level.dofs)?,
                Some(fine) => {
                    let down = Transfer::new(fine, &level);
                    if params.coarse_operator.galerkin(method) {
                        level.op = LevelOperator::galerkin(&fine.op, &down.prolong, &down.prolong.transpose());
                        level.refresh_bounds();
                    }
                    fine.down = Some(down);
                }
            }
            levels.push(level);
            let Some(cm) = cm? else {
                break;
            };
            (mesh, pairs, parent_vertex) = (cm.mesh, cm.links, cm.fine_vertex);
        }
        let mut h = Hierarchy { levels, method, galerkin: params.coarse_operator.galerkin(method), fresh: true };
        h.build_coarse_solve()?;
        Ok(h)
    }

    fn build_coarse_solve(&mut self) -> Result<()> {
        let last = self.levels.last_mut().expect("one level at least");
        let solves = [CoarseSolve::new(last.problem(0), 0)?, CoarseSolve::new(last.problem(1), 1)?];
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
        for (l, c) in coords.into_iter().enumerate() {
            let level = &mut self.levels[l];
            level.mesh = level.mesh.with_coords(c);
            if l == 0 || !self.galerkin {
                level.op.reassemble(&level.mesh, &level.dofs);
            }
            if l > 0 {
                // The transfer from the level above, then (Galerkin) this level's operator.
                let (upper, rest) = self.levels.split_at_mut(l);
                let (fine, coarse) = (&mut upper[l - 1], &mut rest[0]);
                let pts = fine.dof_points().0;
                let down = fine.down.as_mut().expect("not the coarsest level");
                down.update(&pts, coarse);
                if self.galerkin {
                    coarse.op = LevelOperator::galerkin(&fine.op, &down.prolong, &down.prolong.transpose());
                }
            }
            self.levels[l].refresh_bounds();
        }
        self.build_coarse_solve()?;
        self.fresh = false;
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
