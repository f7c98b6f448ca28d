//! The distributed mesh mover: the serial methods (Laplacian, spring, biharmonic) and boundary
//! conditions (FIXED, CLAMPED with prescribed displacements or rigid motions, FREE, SLIP walls
//! flat and curved: `distributed::slip`; periodic links across ranks: `distributed::ties`) on a
//! rank's owned rows, solved by conjugate gradients preconditioned by a cycle of the distributed
//! multigrid (`distributed::mg`: on K for the Laplacian and the spring, on K V⁻¹ K assembled
//! for the biharmonic; one per component, built on the first solve from a reference and kept,
//! `distributed::kept`; projected for a group coupled by slip walls or periodic links:
//! `distributed::blocks`) or, with one level, by the Chebyshev–Jacobi smoother alone.
//!
//! Each rank's operator has the serial operator's rows for the vertices it owns: every cell
//! around an owned vertex is held (owned or ghost), so its rows of K and its lumped mass are
//! complete. The biharmonic K V⁻¹ K is applied as K, a halo exchange of S = V⁻¹ K x (only the
//! owner has S's complete row), then K again: no second ring of ghost cells is needed. The
//! flags P and Z of a vertex are its owner's; halo rows carry P, so only owned rows are
//! equations. The discrete system is thus the serial one, and the solution equals the serial
//! solver's to the solves' tolerance.

use super::agreement::agree;
use super::bcs;
use super::blocks::Blocks;
use super::dist_mesh::DistributedMesh;
use super::error::{DistError, DistErrorKind};
use super::halo::HaloLayout;
use super::interfaces;
use super::kept::{Hierarchies, Kept};
use super::level_layout::Distribution;
use super::mg::{
    any_lines, biharmonic_rows, owned_lines, Coarsening, Components, CoupledSolve, Guide, Limits, Multigrid, OwnedRows,
    Positions, Smoothers, GATHER_ROWS, ROWS_PER_RANK,
};
use super::pcg::{pcg, OneLevel, Preconditioner};
use super::reduce::{gather, sum_in_rank_order};
use super::ties::{self, Ties};
use crate::bc::{Dofs, Kind, SlipWalls, COMPONENT, P, Z};
use crate::mesh::quality::quality_of_cells;
use crate::multigrid::cell_edges::Graph;
use crate::multigrid::group::GroupOp;
use crate::multigrid::layout::Layout;
use crate::multigrid::level::{Level, LevelSlip};
use crate::multigrid::lines::Lines;
use crate::multigrid::local_level::local_level;
use crate::multigrid::policy::method_degrees;
use crate::multigrid::slip::equalise_bounds;
use crate::multigrid::smoother::Smoother;
use crate::multigrid::solve::Report;
use crate::operator::{LevelOperator, Method};
use crate::solver::polish::{self, Polish};
use crate::solver::slip::normal_parts;
use crate::solver::{is_rounding, largest_of};
use crate::sparse::CsrMatrix;
use crate::{BoundaryConditions, Mesh, Motion, Quality};
use std::sync::Arc;

mod options;
mod steps;

use options::serial_options;

pub use steps::DistStepReport;

/// How a distributed solve iterates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistSolveParams {
    /// Relative residual ‖b − A x‖₂ / ‖b‖₂ to reach, per group of components.
    pub tol: f64,
    /// Most iterations per group of components.
    pub max_iterations: usize,
    /// Degree of the fourth-kind Chebyshev–Jacobi smoother on every level; 0 (the default)
    /// picks per method: for the biharmonic the serial cycle's degrees on levels of kept
    /// unknowns (8 on every level; under wall layers, where some rank finds lines across them,
    /// 16 on every level), 4 otherwise.
    pub degree: usize,
    /// Most levels of the multigrid preconditioner; 1 preconditions by the smoother alone.
    pub max_levels: usize,
    /// Internal, for the library's tests: a coarse level with fewer unknowns than this per
    /// rank is agglomerated onto fewer ranks (small values make it happen on small meshes; 0
    /// never). Leave it at its default.
    #[doc(hidden)]
    pub agglomerate_below: u64,
    /// Internal, for the library's tests: the first level with at most this many unknowns over
    /// all ranks is the coarsest, gathered onto one rank and solved there (small values make
    /// deep hierarchies on small meshes). Leave it at its default.
    #[doc(hidden)]
    pub gather_at_most: u64,
}

impl Default for DistSolveParams {
    fn default() -> Self {
        DistSolveParams {
            tol: 1e-8,
            max_iterations: 5000,
            degree: 0,
            max_levels: 20,
            agglomerate_below: ROWS_PER_RANK,
            gather_at_most: GATHER_ROWS,
        }
    }
}

/// The displacement of a distributed solve and how it went (the same report on every rank).
#[derive(Clone, Debug, PartialEq)]
pub struct DistSolution {
    /// Displacement of every local vertex (owned and not), `dim` values each, in the host's
    /// order: the owners' values on every rank that holds a vertex.
    pub displacement: Vec<f64>,
    /// Conjugate gradient iterations of each group of components: one per component, or one for
    /// all where slip walls not normal to an axis couple them (with curved walls, the two
    /// solves' iterations added; with a polish, its stages' added).
    pub iterations: Vec<usize>,
    /// Of the iterations, those of the polish of a tangled result (the serial
    /// `Report::polish_cycles`: per stage the most of any group, summed); 0 when no polish ran.
    /// A converged result whose moved mesh inverts cells under wall layers is solved on from
    /// itself a decade tighter at a time before it is reported tangled (docs/DESIGN.md §5).
    pub polish_iterations: usize,
    /// The largest final relative residual over the components.
    pub rel_residual: f64,
    /// The moved mesh against the mesh the displacement starts from, over every rank's owned
    /// cells: inverted cells summed, ratios and angles the extremes over all ranks.
    pub quality: Quality,
    /// The rank whose owned cells hold the smallest area (volume) ratio (the lowest such rank).
    pub worst_rank: usize,
    /// Unknowns of each level of the first multigrid built over all ranks (the first
    /// component's whose system has a nonzero right-hand side: a zero one needs none), finest
    /// first (the finest level's are the vertices not prescribed); empty with one level.
    pub level_rows: Vec<u64>,
    /// Values all ranks send per halo exchange of one vector, on each level.
    pub level_halo_values: Vec<u64>,
    /// Messages all ranks send per halo exchange, on each level.
    pub level_messages: Vec<u64>,
    /// Ranks that hold each level: all ranks on the finest, fewer where a coarse level is
    /// agglomerated onto fewer ranks.
    pub level_ranks: Vec<u64>,
    /// The coarsest level is gathered onto one rank and factored there (else it is smoothed).
    pub coarsest_gathered: bool,
    /// Internal, for the library's tests: a digest of each level's prolongation over all ranks
    /// (its rows in global ids, weights to 2⁻³⁰), equal on every partition when P is.
    #[doc(hidden)]
    pub level_transfers: Vec<u64>,
    /// Internal, for the library's tests: whether each level of the biharmonic's multigrid is
    /// the assembled Galerkin product of the level above (not made from its guide's
    /// K_c V_c⁻¹ K_c), finest first (false on the finest).
    #[doc(hidden)]
    pub level_galerkin: Vec<bool>,
}

/// A mesh mover for one distributed mesh, one method and one set of boundary conditions: each
/// call turns a prescribed [`Motion`] on the rank's local vertices into the displacement of
/// every local vertex. Every call is collective over the mesh's communicator and returns the
/// same status (and the same report) on every rank.
pub struct DistributedSolver {
    mesh: DistributedMesh,
    bcs: BoundaryConditions,
    params: DistSolveParams,
    /// The rank's level on the current reference positions (layout order).
    level: Level,
    /// The multigrid of each component on the current reference, once a solve has built it.
    multigrids: Kept,
    /// The serial options of the steps, the motion done in the original-reference mode, the
    /// last call's step reports (`steps.rs`).
    steps: steps::State,
    /// The shapes of the SLIP walls of the rank's part as the solver was made, and where the
    /// walls moved rigidly since are (None without SLIP walls on this rank).
    walls: Option<SlipWalls>,
    /// The classes of vertices periodic links tie across ranks (None without links).
    ties: Option<Arc<Ties>>,
    /// The flags of each component on every local vertex from the patch faces (layout order;
    /// the owners' are complete), before links and slip walls add theirs.
    base: Vec<Vec<u8>>,
}

impl std::fmt::Debug for DistributedSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "DistributedSolver {{ rank: {}, method: {:?} }}", self.mesh.rank(), self.level.op.method)
    }
}

impl DistributedSolver {
    /// The solver of `method` on `mesh` with the conditions `bcs` (collective; every rank gives
    /// the same). FIXED, CLAMPED, FREE, SLIP, links by offset (periodic pairs, also across
    /// ranks) or by pairs of global ids, also together with SLIP walls, and interfaces of both
    /// variants are distributed (a split interface's vertices become one vertex per region,
    /// `distributed::interfaces`; [`mesh`](Self::mesh) is then the split mesh); conditions that
    /// prescribe a component nowhere are refused.
    pub fn new(
        mesh: &DistributedMesh,
        bcs: &BoundaryConditions,
        method: Method,
        params: DistSolveParams,
    ) -> Result<DistributedSolver, DistError> {
        let me = mesh.rank();
        let comm = mesh.halo().comm();
        let checked = check_params(me, &params).and_then(|_| bcs::check_supported(me, bcs, mesh.local_mesh()));
        agree(comm, checked)?;
        agree(comm, bcs::check_same_everywhere(me, mesh.halo(), bcs))?;
        let split = interfaces::split(mesh, bcs)?;
        let linked = ties::link_pairs(
            mesh.halo().shared_comm(),
            mesh.local_mesh(),
            mesh.layout_global_ids(),
            mesh.halo().owned(),
            &bcs.links,
        );
        let mut linked = agree(comm, linked)?;
        let mut base = bcs::vertex_flags(mesh.local_mesh(), bcs);
        if let Some(s) = &split {
            linked = agree(comm, linked.map(|l| s.linked(me, l)).transpose())?;
            base = s.flags(mesh, base);
        }
        let mesh = split.map_or_else(|| mesh.clone(), |s| s.mesh);
        let (local, gids, owned) = (mesh.local_mesh(), mesh.layout_global_ids(), mesh.halo().owned());
        let ties = linked.map(|l| Ties::from_pairs(mesh.halo().shared_comm(), local, gids, owned, l)).transpose();
        let ties = agree(mesh.halo().comm(), ties)?.map(Arc::new);
        let level = build_level(mesh.halo(), local.clone(), bcs, &base, method, ties.as_ref());
        agree(mesh.halo().comm(), bcs::check_prescribed(me, mesh.halo(), &level.flags))?;
        let steps = steps::State::new(method, params);
        let walls = SlipWalls::new(local, bcs);
        let multigrids = Kept::default();
        Ok(DistributedSolver { mesh, bcs: bcs.clone(), params, level, multigrids, steps, walls, ties, base })
    }

    /// The distributed mesh (its reference positions are the ones it was made with): the one
    /// the solver was made with, or with split interfaces that mesh with the interfaces'
    /// vertices split per region (the same host vertices).
    pub fn mesh(&self) -> &DistributedMesh {
        &self.mesh
    }

    /// The method.
    pub fn method(&self) -> Method {
        self.level.op.method
    }

    /// The iteration parameters.
    pub fn params(&self) -> DistSolveParams {
        self.params
    }

    /// Changes the iteration parameters (collective: every rank gives the same).
    pub fn set_params(&mut self, params: DistSolveParams) -> Result<(), DistError> {
        agree(self.halo().comm(), check_params(self.mesh.rank(), &params))?;
        self.params = params;
        self.multigrids.clear();
        Ok(())
    }

    /// The positions after the last step of the local vertices, `dim` each, in the host's order:
    /// the reference, or in `ReferenceMode::Original` the original mesh moved by the motion so far.
    pub fn current_coords(&self) -> Vec<f64> {
        self.mesh.to_host_order(self.steps.current().unwrap_or(self.local().coords()), self.mesh.dim())
    }

    /// Solves for the displacement of every local vertex from the current reference
    /// (collective). `motion.displacement` has `dim` values per local vertex in the host's
    /// order, read where a component is prescribed (the owner's value counts); its rigid
    /// motions move whole patches. Nothing changes.
    pub fn solve(&self, motion: &Motion) -> Result<DistSolution, DistError> {
        let (sol, failure) = self.solve_report(motion)?;
        // The PCG scalars are global, so every rank reaches the same verdict; rank 0 speaks.
        let verdict = match failure {
            Some(msg) if self.mesh.rank() == 0 => Err(DistError::new(0, DistErrorKind::Solve, msg)),
            _ => Ok(()),
        };
        agree(self.halo().comm(), verdict)?;
        Ok(sol)
    }

    /// [`DistributedSolver::solve`] also when a group of components stops above its tolerance:
    /// the solution and, then, what went wrong (the same on every rank). A converged result
    /// with inverted cells under wall layers is polished as the serial solver's
    /// (`solver::polish`): solved on from itself to tighter tolerances, a decade at a time while
    /// it stays tangled and each stage unfolds cells, each stage kept when it still meets the
    /// caller's tolerance. The
    /// inverted count, the residuals and the lines are global, so every rank takes the same
    /// decisions.
    fn solve_report(&self, motion: &Motion) -> Result<(DistSolution, Option<String>), DistError> {
        let vals = agree(self.halo().comm(), self.layout_values(motion))?;
        let (tol, max_iterations) = (self.params.tol, self.params.max_iterations);
        let mut solved = self.solve_placed(motion, &vals, None, Budget { tol, max_iterations })?;
        let (mut quality, mut worst_rank) = self.quality(&solved.total);
        let mut report = solved.report();
        // Only under wall layers can the tolerance's error exceed a cell (as serially).
        let p = serial_options(self.method(), &self.params).solve;
        let mut polish = match quality.inverted > 0 {
            true => Polish::after(&p, &report, quality.inverted).filter(|_| self.layered()),
            false => None,
        };
        while quality.inverted > 0 {
            let Some(tight) = polish.as_mut().and_then(|s| s.next(&report, quality.inverted)) else { break };
            let budget = Budget { tol: tight.tol, max_iterations: tight.max_cycles };
            match self.solve_placed(motion, &vals, Some(&solved.total), budget) {
                Ok(stage) if stage.rel_residual <= tol => {
                    (quality, worst_rank) = self.quality(&stage.total);
                    report = polish::chain(report, stage.report());
                    solved = solved.then(stage);
                }
                // A stage that breaks down or leaves the caller's tolerance adds nothing to the
                // converged result, which stands as it is.
                _ => break,
            }
        }
        let dim = self.mesh.dim();
        let kept = self.multigrids.lock();
        let (sizes, coarsest_gathered) = kept.as_ref().map(|h| (h.sizes.clone(), h.gathers)).unwrap_or_default();
        let sol = DistSolution {
            displacement: self.mesh.to_host_order(&solved.total, dim),
            iterations: solved.iterations,
            polish_iterations: report.polish_cycles,
            rel_residual: solved.rel_residual,
            quality,
            worst_rank,
            level_rows: sizes.iter().map(|s| s.rows).collect(),
            level_halo_values: sizes.iter().map(|s| s.halo_values).collect(),
            level_messages: sizes.iter().map(|s| s.messages).collect(),
            level_ranks: sizes.iter().map(|s| s.ranks).collect(),
            coarsest_gathered,
            level_transfers: sizes.iter().map(|s| s.transfer).collect(),
            level_galerkin: sizes.iter().map(|s| s.galerkin).collect(),
        };
        Ok((sol, solved.failure))
    }

    /// Solves every group of components for the prescribed values `vals` within `budget`, from
    /// `guess` (layout order) or zero, and with SLIP walls places the slipped vertices on them
    /// (collective). The walls are placed only from a converged solve (its failure is global,
    /// so every rank skips them alike); an unconverged result is returned as it is. Every rank
    /// takes part when the conditions have SLIP walls, also one whose part has none.
    fn solve_placed(
        &self,
        motion: &Motion,
        vals: &[f64],
        guess: Option<&[f64]>,
        budget: Budget,
    ) -> Result<Solved, DistError> {
        let mut solved = self.solve_values(motion, vals, guess, budget)?;
        if let (true, None) = (self.bcs.any_slip(), &solved.failure) {
            // Curved slip walls: a second solve from the first result, as the serial solver's.
            let mut second: Option<Solved> = None;
            let again = |on_wall: &[f64], first: &[f64]| {
                let s = self.solve_values(motion, on_wall, Some(first), budget)?;
                let total = s.total.clone();
                second = Some(s);
                Ok(total)
            };
            let total = std::mem::take(&mut solved.total);
            let gids = self.mesh.layout_global_ids();
            solved.total = super::slip::onto_walls_everywhere(
                self.walls.as_ref(),
                &self.level,
                self.halo(),
                gids,
                motion,
                vals,
                total,
                again,
            )?;
            if let Some(s) = second {
                solved.iterations.iter_mut().zip(&s.iterations).for_each(|(a, b)| *a += b);
                solved.rel_residual = s.rel_residual;
                solved.failure = s.failure;
            }
        }
        Ok(solved)
    }

    /// Whether some rank finds lines across wall layers: the kept multigrid's, else found now
    /// (collective).
    fn layered(&self) -> bool {
        let kept = self.multigrids.lock().as_ref().map(|h| h.layered);
        kept.unwrap_or_else(|| any_lines(self.halo().comm(), &self.lines()))
    }

    /// Solves every group of components for the prescribed values `vals` (layout order, `dim`
    /// per vertex) within `budget`, from `guess` (the same layout) or zero: the displacement of
    /// every local vertex (layout order) and how the solves went (collective).
    fn solve_values(
        &self,
        motion: &Motion,
        vals: &[f64],
        guess: Option<&[f64]>,
        budget: Budget,
    ) -> Result<Solved, DistError> {
        let me = self.mesh.rank();
        let rhs = agree(self.halo().comm(), self.right_hand_sides(motion, vals))?;
        let (dim, nv) = (self.mesh.dim(), self.local().num_vertices());
        let halo = self.halo();
        let method = self.level.op.method;
        let sm = Smoother::Fourth { degree: smoother_degrees(&self.params, method, dim, false).0 };
        let mut total = vec![0.0; nv * dim];
        let (mut iterations, mut worst, mut failure) = (Vec::with_capacity(dim), 0.0f64, None);
        // Each group's system, and whether conjugate gradients iterate on it: a zero
        // right-hand side is solved without (`pcg`), so its components need no multigrid.
        let mut needed = vec![false; dim];
        // Each component's largest prescribed displacement over the ranks: a group moved by
        // rounding alone is solved as zero, as serially (`solver::is_rounding`).
        let local: Vec<f64> = (0..dim).map(|c| largest_of(vals, dim, c..c + 1)).collect();
        let most = gather(halo.comm(), &local)
            .chunks_exact(dim)
            .fold(vec![0.0f64; dim], |m, r| m.iter().zip(r).map(|(a, b)| a.max(*b)).collect());
        let scale = most.iter().copied().fold(0.0, f64::max);
        let systems: Vec<_> = self
            .level
            .groups()
            .into_iter()
            .map(|comps| {
                let op = GroupOp::new(&self.level, comps.clone(), false);
                let mut system = self.group_system(&op, &rhs, guess);
                if is_rounding(most[comps.clone()].iter().copied().fold(0.0, f64::max), scale) {
                    system.0.fill(0.0);
                }
                if op.norm(&system.0) != 0.0 {
                    comps.clone().for_each(|c| needed[c] = true);
                }
                (comps, op, system)
            })
            .collect();
        let mut kept = self.multigrids.lock();
        let lacking = kept.as_ref().is_none_or(|h| (0..dim).any(|c| needed[c] && h.lacks(c)));
        if self.multigrid_pays() && lacking {
            let lines = self.lines();
            let layered = any_lines(halo.comm(), &lines);
            let (fine_degree, coarse_degree) = smoother_degrees(&self.params, method, dim, layered);
            let smoothers = Smoothers {
                fine: Smoother::Fourth { degree: fine_degree },
                coarse: Smoother::Fourth { degree: coarse_degree },
            };
            let whole = match kept.is_none() {
                true => self.slip_hierarchy(lines.clone(), smoothers)?,
                false => None,
            };
            let mut built = match whole.or_else(|| kept.take()) {
                Some(h) => h,
                None => Hierarchies::none(dim),
            };
            let fine = |c| self.fine_rows(c);
            built.build(halo, &self.level.flags, &needed, fine, &lines, self.limits(), smoothers)?;
            built.layered = layered;
            *kept = Some(built);
        }
        if let Some(h) = kept.as_mut().filter(|h| h.coupled.is_empty()) {
            h.coupled =
                self.level.groups().into_iter().map(|comps| self.coupled_solve(comps)).collect::<Result<_, _>>()?;
        }
        for (group, (comps, op, (b, dp, mut x))) in systems.into_iter().enumerate() {
            let mut one_level;
            let mut blocks;
            let pre: &mut dyn Preconditioner = match kept.as_mut() {
                Some(h) => {
                    blocks = Blocks::new(&op, h, group, sm);
                    &mut blocks
                }
                None => {
                    one_level = OneLevel::new(op, sm);
                    &mut one_level
                }
            };
            let out = pcg(&op, halo, pre, &b, &mut x, budget.tol, budget.max_iterations);
            let name: String = comps.clone().map(|c| COMPONENT[c]).collect();
            if !out.converged && failure.is_none() {
                let why = match out.breakdown {
                    Some(k) => format!("conjugate gradients broke down at iteration {k}"),
                    None => format!("relative residual {:e} after {} iterations", out.rel_residual, out.iterations),
                };
                failure = Some(format!("component {name} did not reach {:e}: {why}", budget.tol));
            }
            iterations.push(out.iterations);
            worst = worst.max(out.rel_residual);
            x.iter_mut().zip(&dp).for_each(|(x, p)| *x += p);
            for (k, c) in comps.enumerate() {
                let x = &mut x[k * nv..(k + 1) * nv];
                halo.refresh(x);
                (0..nv).for_each(|v| total[v * dim + c] = x[v]);
            }
        }
        let bad = total.iter().position(|d| !d.is_finite()).map(|i| {
            let gid = self.mesh.layout_global_ids()[i / dim];
            DistError::new(me, DistErrorKind::Solve, format!("the displacement of global id {gid} is not finite"))
        });
        agree(halo.comm(), bad.map_or(Ok(()), Err))?;
        Ok(Solved { total, iterations, rel_residual: worst, failure })
    }

    /// The system of the group `op` from the components' right-hand sides and prescribed values
    /// `rhs` (one block each, in the group's order): b projected, the prescribed values, and the
    /// first iterate, `guess` less the prescribed values on the free unknowns (projected; zero
    /// without a guess). With slip walls the unknowns are w = d − g, g the normal parts.
    fn group_system(&self, op: &GroupOp, rhs: &[System], guess: Option<&[f64]>) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let (dim, nv) = (self.mesh.dim(), op.n());
        let comps = op.components();
        let b: Vec<f64> = comps.clone().flat_map(|c| rhs[c].0.iter().copied()).collect();
        let dp: Vec<f64> = comps.clone().flat_map(|c| rhs[c].1.iter().copied()).collect();
        let mut x = vec![0.0; b.len()];
        if let Some(g) = guess {
            for (k, c) in comps.enumerate() {
                let flags = &self.level.flags[c];
                for v in (0..nv).filter(|&v| flags[v] & P == 0) {
                    x[k * nv + v] = g[v * dim + c] - dp[k * nv + v];
                }
            }
        }
        let mut b = b;
        op.project(&mut b);
        op.project(&mut x);
        (b, dp, x)
    }

    /// The drop-in call of a time step, as [`crate::Solver::advance`] (collective): moves the
    /// mesh by `increment` (the boundary motion since the last call, host order) from the
    /// current positions, with the sub-stepping and reference mode of the options, and makes the
    /// result the current mesh. Returns the displacement from the positions before the call and
    /// its quality against them. A result that inverts a cell of any rank is refused
    /// (`DistErrorKind::Inverted`, naming the rank of the worst cell); on any error nothing
    /// changes and [`DistributedSolver::step_reports`] say how far the call got.
    pub fn advance(&mut self, increment: &Motion) -> Result<DistSolution, DistError> {
        steps::advance(self, None, increment)
    }

    /// The multigrid preconditions this solve: more than one level is allowed.
    ///
    /// With periodic links every method's hierarchy is built on the rows without ties, and its
    /// cycle is projected onto the tied vectors (`Blocks`, Π M Π: symmetric and positive there,
    /// so a preconditioner of the tied system). For the biharmonic those rows are K V⁻¹ K with
    /// S per vertex (`biharmonic_rows` exchanges S over the halo alone) where the tied operator
    /// has one S per class: another operator at the linked sides, close enough to precondition.
    fn multigrid_pays(&self) -> bool {
        self.params.max_levels > 1
    }

    /// How deep the multigrid goes and where its levels are held, from the parameters.
    fn limits(&self) -> Limits {
        let p = &self.params;
        Limits { levels: p.max_levels, per_rank: p.agglomerate_below, gather: p.gather_at_most }
    }

    /// The coupled solve gathered on one rank of the group `comps` (`mg::CoupledSolve`): for a
    /// group whose slip walls or periodic links couple what its components' multigrids solve
    /// apart, when it is small enough to gather (collective; None otherwise).
    fn coupled_solve(&self, comps: std::ops::Range<usize>) -> Result<Option<CoupledSolve>, DistError> {
        let op = GroupOp::new(&self.level, comps, false);
        if op.frames().is_none() && self.ties.is_none() {
            return Ok(None);
        }
        CoupledSolve::new(&op, self.mesh.layout_global_ids(), self.halo(), self.ties.as_deref())
    }

    /// The owned rows of component `c`'s operator, the multigrid's finest level, and what its
    /// coarse levels are made from (collective): K's free rows for the Laplacian and the spring,
    /// coarsened by Galerkin products at the local vertices' positions; the biharmonic's
    /// K V⁻¹ K assembled, with its guide (K's rows of the vertices with S: the free ones and
    /// the prescribed ones without Z; the flags, V and the positions).
    pub(crate) fn fine_rows(&self, c: usize) -> Result<(OwnedRows, Coarsening), DistError> {
        self.rows_of(&self.level.flags[c])
    }

    /// With slip walls (and no periodic links): the one multigrid of every component
    /// (`Multigrid::build_group`), whose finest level has the rows free in any component, each
    /// component's flags and the slip frames; None otherwise (collective).
    fn slip_hierarchy(&self, lines: Lines, smoothers: Smoothers) -> Result<Option<Hierarchies>, DistError> {
        let Some(slip) = self.level.slip.as_ref().filter(|_| self.ties.is_none()) else {
            return Ok(None);
        };
        let flags = &self.level.flags;
        let any_free: Vec<u8> = (0..flags[0].len()).map(|v| flags.iter().fold(P | Z, |a, f| a & f[v])).collect();
        let (rows, coarsening) = self.rows_of(&any_free)?;
        let (n, owned) = (rows.halo.len(), rows.halo.owned());
        let flags = flags.iter().map(|f| (0..n).map(|i| if i < owned { f[i] } else { P | Z }).collect()).collect();
        let frames = LevelSlip { frames: slip.frames.clone(), bcs: None, coupled: slip.coupled };
        let components = Components { flags, slip: Some(frames) };
        let mg = Multigrid::build_group(rows, coarsening, components, lines, self.limits(), smoothers)?;
        Ok(Some(Hierarchies::whole(mg, self.mesh.dim())))
    }

    /// The owned rows of the operator over the unknowns `flags` leaves free (see `fine_rows`).
    fn rows_of(&self, flags: &[u8]) -> Result<(OwnedRows, Coarsening), DistError> {
        let (op, halo) = (&self.level.op, self.halo());
        let gids = self.mesh.layout_global_ids();
        let local = self.local();
        let at = Positions::from_interleaved(local.coords(), local.dim(), local.num_vertices());
        if op.method == Method::Biharmonic {
            let a = biharmonic_rows(&op.k, &op.inv_v, flags, gids, halo, &[])?;
            // The guide carries every vertex with S, CLAMPED ones too (docs/DESIGN.md §5).
            let with_s: Vec<u8> = flags.iter().map(|&f| if f & Z != 0 { P } else { 0 }).collect();
            let k = OwnedRows { a: free_rows(&op.k, &with_s, halo), gids: gids.to_vec(), halo: halo.clone() };
            let mut flags = flags.to_vec();
            halo.refresh(&mut flags);
            return Ok((a, Coarsening::Guide(Guide { k, flags, mass: op.mass(), at })));
        }
        let k = OwnedRows { a: free_rows(&op.k, flags, halo), gids: gids.to_vec(), halo: halo.clone() };
        Ok((k, Coarsening::Galerkin(at)))
    }

    /// The lines across wall layers of the rank's owned vertices at the current reference
    /// (`distributed::mg::owned_lines`), the multigrid's finest level's; the tied vertices
    /// (periodic links) are on none.
    fn lines(&self) -> Lines {
        let mut tied = vec![0u8; self.local().num_vertices()];
        if let Some(t) = &self.ties {
            t.members().for_each(|v| tied[v] = 1);
        }
        self.halo().refresh(&mut tied);
        let tied: Vec<bool> = tied.iter().map(|&t| t != 0).collect();
        let (local, owned) = (self.local(), self.halo().owned());
        let edges = Graph::cell_edges(local, &self.level.dofs, &self.level.op.k);
        owned_lines(&self.level.op.k, &edges, (local.coords(), local.dim()), owned, &self.level.flags, &tied)
    }

    fn halo(&self) -> &Arc<HaloLayout> {
        self.mesh.halo()
    }

    /// The rank's part at the current reference, layout order.
    fn local(&self) -> &Mesh {
        self.level.mesh()
    }

    /// The motion's values on the local vertices in layout order, rigid motions applied;
    /// checked (sizes, finite values, one rigid motion per patch).
    fn layout_values(&self, motion: &Motion) -> Result<Vec<f64>, DistError> {
        let (me, dim) = (self.mesh.rank(), self.mesh.dim());
        let n = self.mesh.num_local_vertices();
        let input = |msg: String| Err(DistError::new(me, DistErrorKind::Input, msg));
        if motion.displacement.len() != n * dim {
            let given = motion.displacement.len();
            return input(format!("{given} displacement values given for {n} vertices of dimension {dim}"));
        }
        if let Some(i) = motion.displacement.iter().position(|d| !d.is_finite()) {
            let gid = self.mesh.global_ids()[i / dim];
            return input(format!("local vertex {} (global id {gid}) has a non-finite displacement", i / dim));
        }
        for (k, (p, m)) in motion.rigid.iter().enumerate() {
            if motion.rigid[..k].iter().any(|(q, _)| q == p) {
                return input(format!("patch {p} is given two rigid motions: give one (compose them first)"));
            }
            if !m.translation.iter().chain(&m.rotation).chain(&m.center).all(|x| x.is_finite()) {
                return input(format!("the rigid motion of patch {p} is not finite"));
            }
        }
        // The fetched vertices are never owned: their values are not read.
        let d = self.mesh.to_layout_order(&motion.displacement, dim);
        let m = Motion { displacement: d, rigid: motion.rigid.clone() };
        Ok(m.vertex_values(self.local()).into_owned())
    }

    /// Per component the right-hand side and the prescribed values (the owners' values on the
    /// halo); an error where tied vertices are prescribed different values or the right-hand
    /// side overflows. Every component's exchanges run on every rank, whatever it finds (the
    /// first error is returned after them).
    fn right_hand_sides(&self, motion: &Motion, vals: &[f64]) -> Result<Vec<System>, DistError> {
        let (dim, nv, owned) = (self.mesh.dim(), self.local().num_vertices(), self.halo().owned());
        let (me, gids) = (self.mesh.rank(), self.mesh.layout_global_ids());
        let mut out = Vec::with_capacity(dim);
        let mut error = None;
        // What the slip walls prescribe a tied vertex is read at its class's first member.
        let firsts = super::slip::class_first_values(&self.level, self.ties.as_deref(), vals);
        let walls_read = firsts.as_deref().unwrap_or(vals);
        // Slip walls prescribe the normal parts at the owned slip unknowns (free in the flags).
        let normal = normal_parts(&self.level, walls_read);
        let axes = self.level.slip.as_ref().map(|s| &s.frames);
        for c in 0..dim {
            let flags = &self.level.flags[c];
            let by_wall = |v: usize| axes.and_then(|f| f.axes_of(v as u32)).is_some_and(|m| m & 1 << c != 0);
            let value = |v: usize| if by_wall(v) { walls_read[v * dim + c] } else { vals[v * dim + c] };
            let mut dp: Vec<f64> =
                (0..nv).map(|v| if v < owned && flags[v] & P != 0 { value(v) } else { 0.0 }).collect();
            if let Some(g) = &normal {
                dp.iter_mut().zip(&g[c * nv..(c + 1) * nv]).for_each(|(d, g)| *d += g);
            }
            if let Some(Err(msg)) = self.ties.as_ref().map(|t| t.agreed_values(&mut dp, gids)) {
                let msg = format!(
                    "tied vertices (periodic links) are prescribed different {} displacements: {msg}",
                    COMPONENT[c]
                );
                error.get_or_insert(DistError::new(me, DistErrorKind::Input, msg));
            }
            self.halo().refresh(&mut dp);
            let g = self.rigid_flux(motion, c);
            let (mut b, mut s) = (vec![0.0; nv], vec![0.0; nv]);
            self.level.op.rhs(flags, &dp, g.as_deref(), &mut b, &mut s);
            if let Some(i) = b[..owned].iter().position(|v| !v.is_finite()) {
                let msg = format!(
                    "the prescribed {} displacements overflow the operator at global id {}: displacements must be of \
                     the order of the mesh",
                    COMPONENT[c], gids[i]
                );
                error.get_or_insert(DistError::new(me, DistErrorKind::Input, msg));
            }
            out.push((b, dp));
        }
        error.map_or(Ok(out), Err)
    }

    /// The biharmonic's source from the CLAMPED patches moving rigidly (docs/DESIGN.md §4, as
    /// the serial solver's): (K L) on the patch vertices, L the rigid displacement. Only the
    /// owned rows are read, and they are complete.
    fn rigid_flux(&self, motion: &Motion, c: usize) -> Option<Vec<f64>> {
        if self.level.op.method != Method::Biharmonic {
            return None;
        }
        let mesh = self.local();
        let mut g: Option<Vec<f64>> = None;
        for &(patch, m) in motion.rigid.iter().filter(|(p, _)| self.bcs.kind(*p, c) == Kind::Clamped) {
            let l: Vec<f64> = (0..mesh.num_vertices()).map(|v| m.displacement(mesh.point(v))[c]).collect();
            let g = g.get_or_insert_with(|| vec![0.0; mesh.num_vertices()]);
            for v in mesh.patch_vertices(patch) {
                g[v as usize] = self.level.op.k.row_dot(v as usize, &l);
            }
        }
        g
    }

    /// The quality of the moved owned cells over every rank, and the rank of the smallest area
    /// ratio (collective).
    fn quality(&self, displacement: &[f64]) -> (Quality, usize) {
        let mesh = self.local();
        let moved: Vec<f64> = mesh.coords().iter().zip(displacement).map(|(x, d)| x + d).collect();
        self.quality_between(mesh, &moved)
    }

    /// The quality of the positions `moved` (layout order) against `mesh` over every rank's
    /// owned cells, and the rank of the smallest area ratio (collective).
    fn quality_between(&self, mesh: &Mesh, moved: &[f64]) -> (Quality, usize) {
        let owned = self.mesh.owned_cells();
        let q = quality_of_cells(mesh, moved, (0..mesh.num_cells()).filter(|&c| owned[c]));
        let comm = self.halo().comm();
        let counts = sum_in_rank_order(comm, &[q.inverted as f64, q.non_positive_measure as f64]);
        let extremes =
            gather(comm, &[q.min_corner_jacobian_ratio, q.min_area_ratio, -q.max_area_ratio, q.min_angle_deg]);
        let min_at = |k: usize| extremes.chunks_exact(4).map(|e| e[k]).fold(f64::INFINITY, f64::min);
        let worst = min_at(1);
        let worst_rank = extremes.chunks_exact(4).position(|e| e[1] == worst).unwrap_or(0);
        let quality = Quality {
            inverted: counts[0] as usize,
            non_positive_measure: counts[1] as usize,
            min_corner_jacobian_ratio: min_at(0),
            min_area_ratio: worst,
            max_area_ratio: -min_at(2),
            min_angle_deg: min_at(3),
        };
        (quality, worst_rank)
    }
}

/// A component's right-hand side and its prescribed values (the owners' on the halo).
type System = (Vec<f64>, Vec<f64>);

/// What one solve may take: the relative residual to reach and the most iterations per group.
#[derive(Clone, Copy)]
struct Budget {
    tol: f64,
    max_iterations: usize,
}

/// The displacements of one pass of solves and how they went.
struct Solved {
    /// `dim` values per local vertex, layout order, halo current.
    total: Vec<f64>,
    /// Iterations of each group of components.
    iterations: Vec<usize>,
    /// The largest final relative residual.
    rel_residual: f64,
    /// What went wrong when a group stopped above its tolerance (the same on every rank).
    failure: Option<String>,
}

impl Solved {
    /// The serial report of these solves, as the polish reads it: the most iterations of a
    /// group, the largest residual, converged when no group stopped above its tolerance.
    fn report(&self) -> Report {
        let cycles = self.iterations.iter().copied().max().unwrap_or(0);
        Report { cycles, rel_residual: self.rel_residual, converged: self.failure.is_none(), ..Default::default() }
    }

    /// These solves followed by a stage of their polish, `stage`, which met the caller's
    /// tolerance: its displacement and residual, the iterations added, converged.
    fn then(self, stage: Solved) -> Solved {
        let iterations = self.iterations.iter().zip(&stage.iterations).map(|(a, b)| a + b).collect();
        Solved { total: stage.total, iterations, rel_residual: stage.rel_residual, failure: None }
    }
}

/// The rank's level of `method` on `mesh` (layout order) with the flags of `bcs` (collective).
/// With `ties` (periodic links) the tied vertices' flags are their class's, the biharmonic's S
/// is merged over each class and the solve runs on the tied vectors (`distributed::ties`).
fn build_level(
    halo: &Arc<HaloLayout>,
    mesh: Mesh,
    bcs: &BoundaryConditions,
    base: &[Vec<u8>],
    method: Method,
    ties: Option<&Arc<Ties>>,
) -> Level {
    let (flags, slip) = bcs::flags_and_frames(&mesh, halo, bcs, base, ties.map(|t| &**t));
    let mut op = LevelOperator::new(method, &mesh, &Dofs::identity(mesh.num_vertices()));
    if let (Some(t), Method::Spring) = (ties, method) {
        t.share_seam_springs(&mut op.k);
    }
    // The owners' lumped masses on the halo, so the Jacobi bounds read the complete ones.
    let mut mass = op.mass();
    halo.refresh(&mut mass);
    if method == Method::Biharmonic {
        let h = halo.clone();
        op = match ties {
            None => op.with_source_exchange(Arc::new(move |s: &mut [f64]| h.refresh(s))),
            Some(t) => {
                let (t, w) = (t.clone(), t.weights(&mass));
                op.with_source_exchange(Arc::new(move |s: &mut [f64]| {
                    t.merge_sources(s, &w);
                    h.refresh(s);
                }))
            }
        };
    }
    op.inv_v = mass.iter().map(|&v| 1.0 / v).collect();
    let layout = match ties {
        None => Distribution::Halo(halo.clone()),
        Some(t) => Distribution::Tied(halo.clone(), t.clone()),
    };
    let mut level = local_level(mesh, op, flags, layout);
    if let Some(t) = ties {
        t.equalise_bounds(&mut level);
    }
    if slip.is_some() {
        level.slip = slip;
        equalise_bounds(&mut level);
    }
    level
}

/// The smoother's degrees (finest level, coarse levels) of a solve of `method` in `dim` dimensions with `p`
/// (`DistSolveParams::degree`), `layered` when some rank finds lines across wall layers: the
/// caller's degree on every level; else the biharmonic's of the serial levels of kept unknowns
/// (`policy::method_degrees`), whose rule the distributed levels share, and 4 on every level for
/// the Laplacian and the spring: their V-cycle at degree 4 takes no more iterations than the
/// serial degrees 3 and 2 in a W-cycle on the same levels (docs/perf-history.md), at less work.
fn smoother_degrees(p: &DistSolveParams, method: Method, dim: usize, layered: bool) -> (usize, usize) {
    match (p.degree, method) {
        (0, Method::Biharmonic) => method_degrees(method, dim, true, layered),
        (0, _) => (4, 4),
        (d, _) => (d, d),
    }
}

/// The parameters are usable.
fn check_params(me: usize, p: &DistSolveParams) -> Result<(), DistError> {
    if p.tol.is_finite() && p.tol > 0.0 && p.degree <= 64 && p.max_levels >= 1 {
        Ok(())
    } else {
        Err(DistError::new(me, DistErrorKind::Input, format!("unusable solve parameters {p:?}")))
    }
}

/// The rows of `k` (a level's local matrix) the solve has: the owned rows without P in `flags`,
/// over the columns without P, a halo column's P being its owner's (collective).
fn free_rows(k: &CsrMatrix, flags: &[u8], halo: &HaloLayout) -> CsrMatrix {
    let owned = halo.owned();
    let mut out: Vec<u8> = flags.iter().enumerate().map(|(v, f)| u8::from(v >= owned || f & P != 0)).collect();
    halo.refresh(&mut out);
    let mut t = Vec::new();
    for i in (0..owned).filter(|&i| out[i] == 0) {
        let (cols, vals) = k.row(i);
        t.extend(cols.iter().zip(vals).filter(|(&j, _)| out[j as usize] == 0).map(|(&j, &v)| (i as u32, j, v)));
    }
    CsrMatrix::from_triplets(k.nrows, k.ncols, t)
}
