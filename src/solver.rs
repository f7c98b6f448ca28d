//! The solver a flow code holds for the life of its mesh: hierarchy built once, then each time
//! step a motion in and displacements out.
//!
//! What a call guarantees: a result is returned only when every component reached the tolerance
//! (`Error::NotConverged` otherwise; [`Solver::solve_report`] hands back an unconverged result for
//! callers who want to decide themselves), a conjugate-gradient breakdown is `Error::Diverged`,
//! a reference mesh with a cell of non-positive area is `Error::Tangled` before anything is
//! solved on it, and a call that fails leaves the solver exactly as it was.

use crate::bc::{resolve_links, BoundaryConditions, Kind, SlipWalls, COMPONENT, P};
use crate::mesh::quality::{inverted_cells, quality, Quality};
use crate::motion::Motion;
use crate::multigrid::cycle::{cycle, Workspace};
use crate::multigrid::group::GroupOp;
pub use crate::multigrid::hierarchy::CoarseOperator;
use crate::multigrid::hierarchy::{Carried, Hierarchy, HierarchyParams, Level};
use crate::multigrid::phases::Phases;
use crate::multigrid::policy::CycleParams;
use crate::multigrid::smoother::Start;
use crate::multigrid::solve::{solve_until, Report, SolveParams};
use crate::operator::Method;
use crate::pool::Pool;
use crate::sparse::max_abs;
use crate::{Error, Mesh, Result};
use deferred::Deferred;
use std::ops::Range;
use std::time::Instant;

/// A component's displacement at most this fraction of the largest component's is rounding.
const ROUNDING: f64 = 1e-12;

/// The largest magnitude of the components `comps` in `vals` (`dim` values per vertex).
pub(crate) fn largest_of(vals: &[f64], dim: usize, comps: Range<usize>) -> f64 {
    comps.map(|c| vals.iter().skip(c).step_by(dim).fold(0.0f64, |m, d| m.max(d.abs()))).fold(0.0, f64::max)
}

/// Whether a group of components whose prescribed displacements are at most `most` is moved by
/// rounding alone: at most `ROUNDING` of `scale`, the largest of any component (nonzero). Such a
/// group's right-hand side is rounding (a rotation about a coordinate axis moves that axis's
/// component by the rounding of cos θ + (1 − cos θ)), and a relative residual against it would
/// have the solve take that noise out to the tolerance, as many iterations as a random
/// right-hand side takes: the solvers solve it as zero.
pub(crate) fn is_rounding(most: f64, scale: f64) -> bool {
    scale > 0.0 && most <= ROUNDING * scale
}

mod deferred;
mod layer_start;
pub(crate) mod memory;
pub(crate) mod polish;
mod progress;
pub(crate) mod slip;
pub(crate) mod steps;
mod units;
mod warm_start;

pub use progress::{Cancel, Progress};
pub use steps::StepReport;

/// Most Chebyshev degree accepted (degree 6 is the biharmonic's default; the cost of a cycle
/// grows linearly with it).
pub const MAX_CHEB_DEGREE: usize = crate::limits::MAX_CHEB_DEGREE;
/// Most cycles per solve accepted.
pub const MAX_CYCLES: usize = crate::limits::MAX_CYCLES;
/// Most steps of one `move_in_steps` call accepted.
pub const MAX_STEPS: usize = crate::limits::MAX_STEPS;
/// Most sub-steps one step may be split into.
pub const MAX_SUBSTEPS: usize = crate::limits::MAX_SUBSTEPS;

/// What every step is solved from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ReferenceMode {
    /// The mesh of the previous step (docs/DESIGN.md §3's multi-step motion): each step solves for the
    /// increment on the moved mesh. Large rotations need it; the mesh depends on the path.
    #[default]
    Incremental,
    /// The original mesh: each step solves for the total displacement of the motion so far, so
    /// the mesh depends only on the boundary's position (a periodic motion comes back to its
    /// start). Valid while the total motion is small enough for one step to stay valid.
    Original,
}

/// How a [`Solver`] is built and how it solves; the default is the biharmonic, solved by CG with
/// W-cycles to a relative residual of 1e-8, one thread per core, no sub-stepping.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// The equation that moves the mesh (fixed when the solver is made).
    pub method: Method,
    /// How each solve iterates and when it stops (changeable with [`Solver::set_solve_params`]).
    pub solve: SolveParams,
    /// Worker threads of the solver's own pool (0: one per available core). All of a call's work
    /// runs there, never on rayon's global pool; results do not depend on the count.
    pub threads: usize,
    /// How the multigrid levels are built (fixed when the solver is made).
    pub hierarchy: HierarchyParams,
    /// Automatic sub-stepping: a step whose result would invert a cell, fall below
    /// `min_volume_ratio`, or not converge is split in halves, up to this many sub-steps per step.
    /// 0 or 1: no splitting.
    pub max_substeps: usize,
    /// Smallest deformed/reference cell area ratio a sub-stepped step accepts (0: any valid cell).
    pub min_volume_ratio: f64,
    /// What each step is solved from.
    pub reference: ReferenceMode,
    /// Told of every sub-step of `advance` and `move_in_steps`; can cancel the call.
    pub progress: Option<Progress>,
    /// Most memory the solver may take, in bytes (0: no limit): a solver whose estimated need is
    /// larger is refused with `Error::OutOfMemory` before anything is built.
    pub memory_budget: u64,
}

/// Displacements of every vertex and how the solve went.
#[derive(Clone, Debug)]
pub struct Solution {
    /// Displacement of every vertex, `dim` values per vertex.
    pub displacement: Vec<f64>,
    /// How the solve went.
    pub report: Report,
    /// The moved mesh against the mesh the displacement starts from.
    pub quality: Quality,
}

/// The state a failed mutating call restores.
struct Undo {
    coords: Vec<f64>,
    /// The hierarchy's weights and estimates carried from reference to reference, and its count
    /// of re-references (restored when it changed).
    carried: Carried,
    generation: u64,
    /// The hierarchy as it was before the first rebuild of the call.
    hierarchy: Option<Hierarchy>,
    /// The reference mesh's positions when its re-reference waited at the start of the call.
    waits_for: Option<Vec<f64>>,
}

/// What building or moving a hierarchy needs besides the mesh: the solver's pool, conditions
/// and options.
struct Builder<'a> {
    pool: &'a Pool,
    bcs: &'a BoundaryConditions,
    opts: &'a Options,
    params: &'a HierarchyParams,
}

impl<'a> Builder<'a> {
    fn of(pool: &'a Pool, bcs: &'a BoundaryConditions, opts: &'a Options, params: &'a HierarchyParams) -> Self {
        Builder { pool, bcs, opts, params }
    }

    /// A hierarchy built on `mesh` with the link pairs `pairs`, beside the one the solver
    /// holds (the memory for it checked first).
    fn build(&self, mesh: &Mesh, pairs: &[[u32; 2]]) -> Result<Hierarchy> {
        let need = memory::solver_bytes(mesh, self.opts.method);
        memory::check_available(need, self.opts.memory_budget, "the rebuilt hierarchy")?;
        let (bcs, method, hp) = (self.bcs, self.opts.method, self.params);
        self.pool.install(|| Hierarchy::build(mesh, pairs.to_vec(), bcs, method, hp))?
    }

    /// Moves `h` to `mesh` (`None`), or builds a new hierarchy there when a coarse cell would
    /// invert (`Some`, `h` unchanged). On an error `h` is moved back as it was when `restoring`
    /// (else the caller's transaction restores it).
    fn settle(&self, h: &mut Hierarchy, mesh: &Mesh, restoring: bool) -> Result<Option<Hierarchy>> {
        let generation = h.generation();
        let before = restoring.then(|| (h.fine().mesh().coords().to_vec(), h.carried()));
        match self.pool.install(|| h.move_to(mesh.coords().to_vec()))? {
            Ok(true) => Ok(None),
            Ok(false) => self.build(mesh, &h.fine().pairs).map(Some),
            Err(e) => {
                if let Some((coords, carried)) = before.filter(|_| h.generation() != generation) {
                    let moved = self.pool.install(|| h.restore(coords, carried));
                    debug_assert!(matches!(moved, Ok(Ok(true))), "moving back to a previous reference failed");
                }
                Err(e)
            }
        }
    }
}

/// A mesh mover for one mesh and one set of boundary conditions: the multigrid hierarchy is built
/// once, then each call turns a prescribed [`Motion`] into the displacement of every vertex.
pub struct Solver {
    opts: Options,
    bcs: BoundaryConditions,
    /// The hierarchy at the reference mesh, or waiting to be moved there (`deferred`).
    hierarchy: Deferred,
    pool: Pool,
    /// `ReferenceMode::Original`: the motion done so far (the sum of the increments) and the
    /// positions it gave; the hierarchy stays on the original mesh.
    total: Option<(Motion, Vec<f64>)>,
    /// The sub-steps of the last `advance` or `move_in_steps` call.
    steps: Vec<StepReport>,
    /// Seconds `advance_from` spent making the caller's positions the reference, reported with
    /// the call's first sub-step.
    rebase_seconds: f64,
    /// The last accepted steps' prescribed values and displacements, from which the next
    /// step's initial guess is extrapolated (`warm_start.rs`); empty after the reference was set
    /// from outside a step.
    increments: warm_start::Increments,
    /// The last valid mesh the last `advance` or `move_in_steps` call reached (empty before the
    /// first).
    last_valid: Vec<f64>,
    /// The shapes of the SLIP walls, from the mesh the solver was made with, and where the walls
    /// moved rigidly since are (None without SLIP walls).
    walls: Option<SlipWalls>,
    /// The hierarchy parameters with the coarse-level route resolved when the solver was made:
    /// every rebuild takes the same route.
    built_with: HierarchyParams,
    /// The positions of the mesh the solver was made with: what the totals since the start
    /// ([`Solver::total_displacement`], [`Solver::total_quality`]) measure from.
    initial: Vec<f64>,
    /// Another thread's request to stop the running call ([`Solver::canceller`]).
    cancel: Cancel,
}

/// The hierarchy parameters of `opts` with the coarse-level route resolved for the dimension and
/// the mode the solver starts in.
fn hierarchy_params(opts: &Options, dim: usize) -> HierarchyParams {
    let mut hp = opts.hierarchy.clone();
    hp.coarse_levels = hp.coarse_levels.resolve(dim, opts.solve.mode);
    hp
}

impl Solver {
    /// Checks the options, the boundary conditions against `mesh` and that no cell is inverted,
    /// then builds the multigrid hierarchy on the solver's own threads. Errors: an invalid option,
    /// boundary conditions that do not fit the mesh or leave a component undetermined, a tangled
    /// mesh, or a hierarchy that cannot be built.
    pub fn new(mesh: &Mesh, bcs: &BoundaryConditions, opts: Options) -> Result<Solver> {
        check_options(&opts)?;
        bcs.check(mesh)?;
        check_not_tangled(mesh, mesh.coords())?;
        let pairs = resolve_links(mesh, &bcs.links)?;
        memory::check_available(memory::solver_bytes(mesh, opts.method), opts.memory_budget, "the solver")?;
        let pool = Pool::new(opts.threads)?;
        let built_with = hierarchy_params(&opts, mesh.dim());
        let hierarchy = pool.install(|| Hierarchy::build(mesh, pairs, bcs, opts.method, &built_with))??;
        let (steps, last_valid) = (Vec::new(), Vec::new());
        let walls = SlipWalls::new(mesh, bcs);
        let initial = mesh.coords().to_vec();
        Ok(Solver {
            opts,
            bcs: bcs.clone(),
            hierarchy: Deferred::new(hierarchy),
            pool,
            total: None,
            steps,
            rebase_seconds: 0.0,
            increments: warm_start::Increments::default(),
            last_valid,
            walls,
            built_with,
            initial,
            cancel: Cancel::default(),
        })
    }

    /// The solver's cancellation request, for another thread to stop a running call (see
    /// [`Cancel`]): the call fails with `Error::Cancelled` within one multigrid cycle and leaves
    /// the solver as it was.
    pub fn canceller(&self) -> Cancel {
        self.cancel.clone()
    }

    /// Runs `f` on the solver's threads: every part of a call's work, so the thread count set
    /// in the options bounds all of it (fails only when a forked child cannot start its pool).
    fn run<T: Send>(&self, f: impl FnOnce() -> T + Send) -> Result<T> {
        self.pool.install(f)
    }

    /// The reference mesh (the mesh at the start of the step).
    pub fn mesh(&self) -> &Mesh {
        self.hierarchy.mesh()
    }

    /// The hierarchy at the reference mesh, moved there first when its re-reference waits
    /// (`deferred`): on an error the solver is as it was.
    fn current(&self) -> Result<&Hierarchy> {
        let b = Builder::of(&self.pool, &self.bcs, &self.opts, &self.built_with);
        self.hierarchy.get(&|h, mesh| b.settle(h, mesh, true))
    }

    /// The hierarchy once `current` (or `settle`) has moved it to the reference mesh.
    fn h(&self) -> &Hierarchy {
        self.hierarchy.ready().expect("the hierarchy is moved to the reference before it is read")
    }

    /// Inside a call's transaction: the hierarchy moved to the reference mesh when its
    /// re-reference waits (a hierarchy replaced by a new one kept in `undo`). Returns the seconds.
    fn settle(&mut self, undo: &mut Undo) -> Result<f64> {
        if self.hierarchy.ready().is_some() {
            self.hierarchy.tidy();
            return Ok(0.0);
        }
        let t = Instant::now();
        let b = Builder::of(&self.pool, &self.bcs, &self.opts, &self.built_with);
        let old = &mut undo.hierarchy;
        self.hierarchy.get_mut(&|h, mesh| b.settle(h, mesh, false), |h| {
            old.get_or_insert(h);
        })?;
        Ok(t.elapsed().as_secs_f64())
    }

    /// The positions after the last step: the reference mesh, or in `ReferenceMode::Original`
    /// the original mesh moved by the motion so far.
    pub fn current_coords(&self) -> &[f64] {
        match &self.total {
            Some((_, x)) => x,
            None => self.mesh().coords(),
        }
    }

    /// The options in force.
    pub fn options(&self) -> &Options {
        &self.opts
    }

    /// Changes how later solves iterate (mode, criterion, tolerance, Chebyshev settings) without
    /// rebuilding the hierarchy: the coarse meshes and operators do not depend on them.
    pub fn set_solve_params(&mut self, p: SolveParams) -> Result<()> {
        check_solve_params(&p)?;
        self.opts.solve = p;
        Ok(())
    }

    /// Changes the options that need no new hierarchy (iteration, sub-stepping, reference mode);
    /// method, threads and hierarchy parameters must stay as the solver was built. Switching to
    /// `ReferenceMode::Original` makes the current mesh the original one.
    pub fn set_options(&mut self, opts: Options) -> Result<()> {
        check_options(&opts)?;
        if opts.method != self.opts.method
            || opts.threads != self.opts.threads
            || opts.hierarchy != self.opts.hierarchy
            || opts.memory_budget != self.opts.memory_budget
        {
            return Err(Error::InvalidArgument(
                "method, threads, hierarchy parameters and memory budget are fixed when the solver is made: make a new \
                 solver"
                    .into(),
            ));
        }
        if opts.reference != self.opts.reference {
            // The current positions become the reference (Incremental) or the original mesh
            // with no motion done yet (Original).
            let x = self.current_coords().to_vec();
            if x.as_slice() != self.mesh().coords() {
                self.set_reference(x)?;
            }
            self.drop_total();
            self.increments.clear();
        }
        self.opts = opts;
        Ok(())
    }

    /// The number of multigrid levels, the fine one included.
    pub fn num_levels(&self) -> usize {
        match self.current() {
            Ok(h) => h.levels.len(),
            // The re-reference that waits failed: the levels of the hierarchy that waits.
            Err(_) => self.hierarchy.with_any(|h| h.levels.len()),
        }
    }

    /// A table of the multigrid levels.
    pub fn describe(&self) -> String {
        match self.current() {
            Ok(h) => h.describe(),
            Err(e) => format!("{}(not yet at the reference mesh: {e})\n", self.hierarchy.with_any(|h| h.describe())),
        }
    }

    /// The multigrid hierarchy at the reference mesh (internals: the bench and tests). Panics
    /// when the re-reference that waited fails (the solving calls report that as an error).
    #[doc(hidden)]
    pub fn hierarchy(&self) -> &Hierarchy {
        self.current().unwrap_or_else(|e| panic!("the hierarchy could not be moved to the reference mesh: {e}"))
    }

    /// The seconds per phase of the hierarchy's last build or re-reference (internals: the
    /// bench); a re-reference that waits is not done by asking.
    #[doc(hidden)]
    pub fn phases(&self) -> Phases {
        self.hierarchy.phases()
    }

    /// The sub-steps of the last [`Solver::advance`] or [`Solver::move_in_steps`] call, also when
    /// it failed.
    pub fn step_reports(&self) -> &[StepReport] {
        &self.steps
    }

    /// The last valid mesh the last [`Solver::advance`] or [`Solver::move_in_steps`] call reached
    /// (its result on success; on failure how far it got, while the solver itself is restored).
    pub fn last_valid_coords(&self) -> &[f64] {
        // Empty until the first such call (a copy of the mesh per solver is not kept for nothing).
        if self.last_valid.is_empty() {
            self.current_coords()
        } else {
            &self.last_valid
        }
    }

    /// A prescribed motion must fit the mesh and move only what it can: one rigid motion per
    /// patch, none moving a component that is FREE on its patch (it would be silently dropped).
    pub fn check_motion(&self, motion: &Motion) -> Result<()> {
        let mesh = self.mesh();
        motion.check(mesh)?;
        for &(patch, m) in &motion.rigid {
            // A SLIP patch takes the normal part of its motion.
            for (c, name) in COMPONENT.iter().enumerate() {
                if self.bcs.kind(patch, c) != Kind::Free {
                    continue;
                }
                if c >= mesh.dim() {
                    break;
                }
                let moves =
                    mesh.patch_vertices(patch).iter().any(|&v| m.displacement(mesh.point(v as usize))[c] != 0.0);
                if moves {
                    return Err(Error::InvalidArgument(format!(
                        "the rigid motion of patch {patch} moves its vertices in {name}, which is FREE on that \
                         patch: make {name} FIXED or CLAMPED there, or give that patch no motion"
                    )));
                }
            }
        }
        Ok(())
    }

    /// Prescribed values (zero off P) and the rigid-motion flux source of component `c`.
    fn prescribed(&self, motion: &Motion, vals: &[f64], c: usize) -> Result<(Vec<f64>, Option<Vec<f64>>)> {
        let lev = self.h().fine();
        let dim = lev.dim();
        let flags = &lev.flags[c];
        let mut dp = vec![0.0; lev.n()];
        for d in 0..lev.n() {
            if flags[d] & P == 0 {
                continue;
            }
            let vs = lev.dofs.vertices_of(d);
            let v0 = vals[vs[0] as usize * dim + c];
            // Linked vertices are one unknown: they must be told the same thing. A component a
            // slip wall normal to its axis prescribes reads its first vertex, as a slip wall's
            // normal part does.
            let by_wall = lev.slip.as_ref().and_then(|s| s.frames.axes_of(d as u32)).is_some_and(|m| m & 1 << c != 0);
            for &v in vs[1..].iter().filter(|_| !by_wall) {
                let vv = vals[v as usize * dim + c];
                if (vv - v0).abs() > 1e-9 * (1.0 + v0.abs().max(vv.abs())) {
                    return Err(Error::InvalidArgument(format!(
                        "linked vertices {} and {v} are prescribed different {} displacements ({v0} and {vv})",
                        vs[0], COMPONENT[c]
                    )));
                }
            }
            dp[d] = v0;
        }
        Ok((dp, rigid_flux(self.h(), &self.bcs, motion, c)))
    }

    /// The right-hand side of component `c` (its scratch S freed before the solve starts).
    fn rhs(lev: &Level, c: usize, dp: &[f64], g: Option<&[f64]>, b: &mut [f64]) -> Result<()> {
        let mut s = vec![0.0; lev.n()];
        lev.op.rhs(&lev.flags[c], dp, g, b, &mut s);
        if let Some(i) = b.iter().position(|v| !v.is_finite()) {
            let big = dp.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            return Err(Error::InvalidArgument(format!(
                "the prescribed {} displacements (largest {big:e}) overflow the operator (right-hand side not \
                 finite at unknown {i}): displacements must be of the order of the mesh",
                COMPONENT[c]
            )));
        }
        Ok(())
    }

    fn scale(vals: &[f64]) -> f64 {
        vals.iter().fold(0.0f64, |m, d| m.max(d.abs()))
    }

    /// Writes the blocks `x` of the components `comps` (one block of n unknowns each) into the
    /// per-vertex displacement `out` (`dim` values per vertex).
    fn to_vertices(lev: &Level, comps: Range<usize>, x: &[f64], out: &mut [f64]) {
        let (n, dim) = (lev.n(), lev.dim());
        for (k, c) in comps.enumerate() {
            for (v, &d) in lev.dofs.vertex_dof.iter().enumerate() {
                out[v * dim + c] = x[k * n + d as usize];
            }
        }
    }

    /// Solves for the displacement of every vertex, to the tolerance of the options.
    pub fn solve(&self, motion: &Motion) -> Result<Solution> {
        self.solve_from(motion, None)
    }

    /// As `solve`, starting from a guess (e.g. the previous time step's displacement, `dim`
    /// values per vertex).
    pub fn solve_from(&self, motion: &Motion, guess: Option<&[f64]>) -> Result<Solution> {
        let sol = self.solve_report(motion, guess)?;
        check_converged(&sol.report, None)?;
        Ok(sol)
    }

    /// As `solve_from`, but a solve that stops above its tolerance is returned (with
    /// `report.converged == false`) for the caller to judge. Breakdowns and bad input are errors.
    pub fn solve_report(&self, motion: &Motion, guess: Option<&[f64]>) -> Result<Solution> {
        self.check_motion(motion)?;
        if let Some(g) = guess {
            check_guess(g, self.mesh())?;
        }
        self.current()?;
        Ok(self.run(|| self.solve_inner(motion, guess))??.0)
    }

    /// `solve_report` from `guess` (`dim` per vertex, checked by the caller), with the seconds
    /// of its quality check.
    fn solve_timed(&self, motion: &Motion, guess: Option<&[f64]>) -> Result<(Solution, f64)> {
        self.check_motion(motion)?;
        self.current()?;
        self.run(|| self.solve_inner(motion, guess))?
    }

    /// The right-hand side and initial iterate of the components `comps`, one block each.
    fn group_system(
        &self,
        motion: &Motion,
        vals: &[f64],
        comps: Range<usize>,
        guess: Option<&[f64]>,
    ) -> Result<(Vec<f64>, Vec<f64>)> {
        let lev = self.h().fine();
        let (n, dim) = (lev.n(), lev.dim());
        let (mut b, mut x) = (vec![0.0; comps.len() * n], vec![0.0; comps.len() * n]);
        // Slip walls: the system is for w = d − g, g the prescribed normal parts, in the free
        // subspace: b = Π (−A g − A_{U,P} d_P), w₀ = Π (guess − g).
        let normal = Self::normal_parts(lev, &comps, vals);
        for (k, c) in comps.clone().enumerate() {
            let (mut dp, g) = self.prescribed(motion, vals, c)?;
            if let Some(gn) = &normal {
                dp.iter_mut().zip(&gn[k * n..(k + 1) * n]).for_each(|(d, g)| *d += g);
            }
            Self::rhs(lev, c, &dp, g.as_deref(), &mut b[k * n..(k + 1) * n])?;
            if let Some(gv) = guess {
                let flags = &lev.flags[c];
                for (i, x) in x[k * n..(k + 1) * n].iter_mut().enumerate() {
                    if flags[i] & P == 0 {
                        *x = gv[lev.dofs.dof_vertex[i] as usize * dim + c];
                    }
                }
            }
        }
        if let (Some(gn), Some(s)) = (&normal, lev.slip.as_ref()) {
            x.iter_mut().zip(gn).for_each(|(x, g)| *x -= g);
            s.frames.project(n, &mut x);
            s.frames.project(n, &mut b);
        }
        Ok((b, x))
    }

    /// The prescribed normal parts at the slip unknowns when `comps` is the group slip walls
    /// couple (see `slip::normal_parts`).
    fn normal_parts(lev: &Level, comps: &Range<usize>, vals: &[f64]) -> Option<Vec<f64>> {
        if comps.len() != lev.dim() || comps.len() < 2 {
            return None;
        }
        slip::normal_parts(lev, vals)
    }

    /// Adds the prescribed values to the P unknowns of the blocks `x` (the solve leaves them 0),
    /// and the prescribed normal parts to the slip unknowns.
    fn add_prescribed(lev: &Level, comps: Range<usize>, vals: &[f64], x: &mut [f64]) {
        let (n, dim) = (lev.n(), lev.dim());
        if let Some(g) = Self::normal_parts(lev, &comps, vals) {
            x.iter_mut().zip(&g).for_each(|(x, g)| *x += g);
        }
        for (k, c) in comps.enumerate() {
            let flags = &lev.flags[c];
            for (i, x) in x[k * n..(k + 1) * n].iter_mut().enumerate() {
                if flags[i] & P != 0 {
                    *x += vals[lev.dofs.vertices_of(i)[0] as usize * dim + c];
                }
            }
        }
    }

    /// The solution and the seconds of its quality checks. A converged result with inverted
    /// cells under wall layers is polished (`polish`): solved on from itself to tighter
    /// tolerances, a decade at a time while it stays tangled and each stage unfolds cells, each
    /// stage kept when it still meets the caller's criterion; only a result still tangled after
    /// that is returned tangled.
    fn solve_inner(&self, motion: &Motion, guess: Option<&[f64]>) -> Result<(Solution, f64)> {
        let lev = self.h().fine();
        let vals = motion.vertex_values(lev.mesh());
        let p = &self.opts.solve;
        // With no guess, a hierarchy with lines across a clamped body's layers starts them at the
        // body's rigid motion (`layer_start`).
        let layers = guess.is_none().then(|| layer_start::of_layers(self.h(), &self.bcs, motion)).flatten();
        let guess = guess.or(layers.as_deref());
        let (mut displacement, mut report) = self.solve_placed(motion, &vals, guess, p)?;
        let t = Instant::now();
        let mut quality = checked_quality(lev.mesh(), &displacement)?;
        let mut quality_s = t.elapsed().as_secs_f64();
        // Only under wall layers (a hierarchy with lines) can the tolerance's error exceed a
        // cell; elsewhere a tangle is the method's and is returned as the solve left it.
        let mut polish = polish::Polish::after(p, &report, quality.inverted).filter(|_| self.h().has_lines());
        while quality.inverted > 0 {
            let Some(tight) = polish.as_mut().and_then(|s| s.next(&report, quality.inverted)) else { break };
            match self.solve_placed(motion, &vals, Some(&displacement), &tight) {
                Ok((d, r)) if p.met(r.max_correction, r.rel_residual, Self::scale(&vals)) => {
                    let t = Instant::now();
                    quality = checked_quality(lev.mesh(), &d)?;
                    quality_s += t.elapsed().as_secs_f64();
                    displacement = d;
                    report = polish::chain(report, r);
                }
                Err(e @ Error::Cancelled(_)) => return Err(e),
                // A stage that breaks down or leaves the caller's tolerance adds nothing to the
                // converged result, which stands as it is.
                _ => break,
            }
        }
        Ok((Solution { displacement, report, quality }, quality_s))
    }

    /// Solves every group with `p` and, with curved slip walls, follows the walls (a second
    /// solve from the first result) and puts the slipped vertices back on them.
    fn solve_placed(
        &self,
        motion: &Motion,
        vals: &[f64],
        guess: Option<&[f64]>,
        p: &SolveParams,
    ) -> Result<(Vec<f64>, Report)> {
        let lev = self.h().fine();
        let (mut displacement, mut report) = self.solve_groups(motion, vals, guess, p)?;
        if let Some(walls) = &self.walls {
            // Curved slip walls: the solve slides vertices in the walls' tangent planes. Their
            // second-order distances from the walls are prescribed as normal displacements in a
            // second solve from the first result, so the interior follows the walls' curvature
            // (moving only the wall vertices would squeeze the cells next to a wall at every
            // step); what remains is moved onto the walls. Flat walls need no second solve.
            // A wall moved rigidly is placed where the motion takes it; a deformed one is left
            // alone (its shape is not known).
            walls.take_failure();
            let at = walls.placed_by(&motion.rigid);
            let deformed = slip::deformed_patches(walls, lev, motion, vals);
            if let Some(on_wall) = slip::on_wall_values(walls, &at, lev, &deformed, vals, &displacement) {
                let (d, r) = self.solve_groups(motion, &on_wall, Some(&displacement), p)?;
                displacement = d;
                report = Report::chain(report, r);
            }
            let (after, before) = slip::onto_walls(walls, &at, lev, &deformed, &mut displacement);
            report.max_slip_offwall = after;
            report.max_slip_correction = before;
            if walls.take_failure() {
                return Err(Error::CallbackFailed(
                    "a slip wall's closest-point function reported a failure; nothing was changed".into(),
                ));
            }
        }
        Ok((displacement, report))
    }

    /// Solves every group of components for the prescribed values `vals` (`dim` per vertex),
    /// from `guess`: the displacement of every vertex and the combined report.
    fn solve_groups(
        &self,
        motion: &Motion,
        vals: &[f64],
        guess: Option<&[f64]>,
        p: &SolveParams,
    ) -> Result<(Vec<f64>, Report)> {
        let lev = self.h().fine();
        let scale = Self::scale(vals);
        // Displacements far from 1 are solved scaled by a power of two (exact), see `units`.
        let f = units::factor(scale);
        // Each group's solution on the unknowns; the per-vertex field is made after the last
        // solve, so it does not add to the memory of the solves.
        let mut solved: Vec<(Range<usize>, Vec<f64>)> = Vec::new();
        let mut report: Option<Report> = None;
        let stop = || self.cancel.is_requested();
        for comps in self.h().groups() {
            let name = group_name(comps.clone());
            // One group at a time: only its right-hand side and iterate are alive (memory).
            let (mut b, mut x) = self.group_system(motion, vals, comps.clone(), guess)?;
            if is_rounding(largest_of(vals, lev.dim(), comps.clone()), scale) {
                // Moved by rounding alone: its interior is zero, its prescribed values stay as
                // given (`is_rounding`).
                b.fill(0.0);
            }
            if f != 1.0 {
                units::scale(&mut b, f);
                units::scale(&mut x, f);
            }
            let mut rep = solve_until(self.h(), comps.clone(), p, &b, &mut x, scale * f, f, &stop);
            drop(b);
            if self.cancel.take() {
                return Err(Error::Cancelled(format!(
                    "the call was cancelled in the solve of component {name}, after {} of its cycles; nothing was \
                     changed",
                    rep.cycles
                )));
            }
            if f != 1.0 {
                units::scale(&mut x, 1.0 / f);
                rep.max_correction /= f;
                rep.history.iter_mut().for_each(|h| h.0 /= f);
            }
            if let Some(k) = rep.breakdown {
                return Err(Error::Diverged(format!(
                    "component {name}: conjugate gradients broke down at iteration {k} (pᵀAp not positive): the \
                     operator is not positive definite on this reference mesh"
                )));
            }
            if !rep.rel_residual.is_finite() || rep.rel_residual > 1.0 {
                return Err(Error::Diverged(format!(
                    "component {name} residual {:e} after {} cycles",
                    rep.rel_residual, rep.cycles
                )));
            }
            Self::add_prescribed(lev, comps.clone(), vals, &mut x);
            solved.push((comps, x));
            report = Some(match report {
                None => rep,
                Some(r) => Report::merge(r, rep),
            });
        }
        let mut displacement = vec![0.0; lev.mesh().coords().len()];
        for (comps, x) in solved {
            Self::to_vertices(lev, comps, &x, &mut displacement);
        }
        if let Some(i) = displacement.iter().position(|d| !d.is_finite()) {
            return Err(Error::Diverged(format!("the displacement of vertex {} is not finite", i / lev.dim())));
        }
        Ok((displacement, report.expect("at least one component")))
    }

    /// One multigrid cycle of the solver's mode from `displacement` (read and overwritten, `dim`
    /// values per vertex): for codes that run a fixed number of cycles per time step.
    pub fn cycle(&self, motion: &Motion, displacement: &mut [f64]) -> Result<Report> {
        self.check_motion(motion)?;
        check_guess(displacement, self.mesh())?;
        self.current()?;
        let (out, rep) = self.run(|| self.cycle_inner(motion, displacement))??;
        if let Some(i) = out.iter().position(|d| !d.is_finite()) {
            return Err(Error::Diverged(format!(
                "the cycle's displacement of vertex {} is not finite",
                i / self.mesh().dim()
            )));
        }
        displacement.copy_from_slice(&out);
        Ok(rep)
    }

    fn cycle_inner(&self, motion: &Motion, displacement: &[f64]) -> Result<(Vec<f64>, Report)> {
        let lev = self.h().fine();
        let vals = motion.vertex_values(lev.mesh());
        let mut out = vec![0.0; displacement.len()];
        let mut report: Option<Report> = None;
        for comps in self.h().groups() {
            let t0 = Instant::now();
            let (b, mut x) = self.group_system(motion, &vals, comps.clone(), Some(displacement))?;
            let mut s = vec![0.0; lev.n()];
            let mut r = vec![0.0; b.len()];
            let before = x.clone();
            let mut ws = Workspace::new(self.h(), comps.len());
            let cp = CycleParams::resolve(self.h(), &self.opts.solve);
            cycle(self.h(), comps.clone(), &cp, &b, &mut x, Start::Guess, &mut ws);
            GroupOp::new(lev, comps.clone(), false).residual(&b, &mut x, &mut r, &mut s);
            let bn = crate::sparse::dot(&b, &b).sqrt();
            let rn = crate::sparse::dot(&r, &r).sqrt();
            // A zero right-hand side has nothing to reduce: its relative residual is its norm.
            let rel = if bn > 0.0 { rn / bn } else { rn };
            let change: Vec<f64> = x.iter().zip(&before).map(|(a, b)| a - b).collect();
            let mc = max_abs(&change);
            if !rel.is_finite() || !mc.is_finite() {
                return Err(Error::Diverged(format!(
                    "component {}: the cycle gave a non-finite residual or correction",
                    group_name(comps)
                )));
            }
            Self::add_prescribed(lev, comps.clone(), &vals, &mut x);
            Self::to_vertices(lev, comps, &x, &mut out);
            let secs = t0.elapsed().as_secs_f64();
            let rep = Report {
                cycles: 1,
                max_correction: mc,
                rel_residual: rel,
                converged: false,
                breakdown: None,
                seconds: secs,
                history: vec![(mc, rel)],
                ..Default::default()
            };
            report = Some(match report {
                None => rep,
                Some(r) => Report::merge(r, rep),
            });
        }
        Ok((out, report.expect("at least one component")))
    }

    /// Makes `coords` the new reference mesh. The hierarchy follows when a later call needs it:
    /// K and V re-evaluated on every level, the coarse topology kept (rebuilt only if a coarse
    /// cell would invert); that call reports a failure to move it and leaves the solver as it
    /// was. Positions with a cell of non-positive area are `Error::Tangled`; on any error the
    /// solver is unchanged.
    pub fn set_reference(&mut self, coords: Vec<f64>) -> Result<()> {
        self.check_reference(&coords)?;
        self.set_reference_inner(coords);
        self.increments.clear();
        // In `ReferenceMode::Original` the new reference is the new original mesh.
        self.drop_total();
        Ok(())
    }

    /// Finite positions, one per vertex, no cell of non-positive area.
    pub(crate) fn check_reference(&self, coords: &[f64]) -> Result<()> {
        let mesh = self.mesh();
        if coords.len() != mesh.coords().len() {
            return Err(Error::InvalidArgument(format!(
                "new reference needs {} values ({} vertices × {}), got {}",
                mesh.coords().len(),
                mesh.num_vertices(),
                mesh.dim(),
                coords.len()
            )));
        }
        if let Some(i) = coords.iter().position(|p| !p.is_finite()) {
            return Err(Error::InvalidArgument(format!("new reference: vertex {} is not finite", i / mesh.dim())));
        }
        check_not_tangled(mesh, coords)
    }

    /// Forgets the total motion of `ReferenceMode::Original` (the current mesh becomes the
    /// original one); the slip walls it moved rigidly stay where it took them.
    fn drop_total(&mut self) {
        if let (Some((m, _)), Some(w)) = (self.total.take(), self.walls.as_mut()) {
            w.move_walls(&m.rigid);
        }
    }

    /// The state to restore when the call that begins fails.
    fn undo(&mut self) -> Undo {
        self.hierarchy.tidy();
        let waits_for = self.hierarchy.waits_for().map(<[f64]>::to_vec);
        let (coords, carried, generation) =
            self.hierarchy.with_any(|h| (h.fine().mesh().coords().to_vec(), h.carried(), h.generation()));
        Undo { coords, carried, generation, hierarchy: None, waits_for }
    }

    /// Puts the solver back to the state `undo` recorded: the hierarchy it had (moved back to
    /// its positions with the weights and estimates it had there, which recomputes every value
    /// bitwise as it was), and the re-reference that waited then.
    fn restore(&mut self, undo: Undo) {
        self.hierarchy.cancel();
        if let Some(h) = undo.hierarchy {
            self.hierarchy.replace(h);
        }
        let hierarchy = self.hierarchy.ready_mut();
        if hierarchy.generation() != undo.generation {
            let moved = self.pool.install(|| hierarchy.restore(undo.coords, undo.carried));
            // The same topology at positions it had before: every coarse cell was valid there.
            debug_assert!(matches!(moved, Ok(Ok(true))), "moving back to a previous reference failed");
        }
        if let Some(x) = undo.waits_for {
            self.set_reference_inner(x);
        }
    }

    /// Makes `coords` the reference; the hierarchy is moved there when a call needs it.
    fn set_reference_inner(&mut self, coords: Vec<f64>) {
        let mesh = self.mesh().with_coords(coords);
        self.hierarchy.defer(mesh);
    }

    /// A new hierarchy built at the reference mesh, the old one kept in `undo` (the first time).
    fn rebuild(&mut self, undo: &mut Undo) -> Result<()> {
        let b = Builder::of(&self.pool, &self.bcs, &self.opts, &self.built_with);
        let built = b.build(self.mesh(), &self.h().fine().pairs)?;
        if let Some(old) = self.hierarchy.replace(built) {
            undo.hierarchy.get_or_insert(old);
        }
        Ok(())
    }

    /// Moves the boundary to `motion` in `steps` equal steps, the reference re-evaluated after
    /// each (the paper's 10- and 15-interval runs), with the sub-stepping of the options. The
    /// solver's reference becomes the moved mesh. Returns one report per sub-step (also kept in
    /// [`Solver::step_reports`]); on failure the solver is as before the call.
    pub fn move_in_steps(&mut self, motion: &Motion, steps: usize) -> Result<Vec<StepReport>> {
        if steps == 0 || steps > MAX_STEPS {
            return Err(Error::InvalidArgument(format!("step count is {steps}; it must be 1 to {MAX_STEPS}")));
        }
        self.check_motion(motion)?;
        steps::move_in_steps(self, motion, steps)?;
        Ok(self.steps.clone())
    }

    /// The drop-in call of a time step: moves the mesh by `increment` (the boundary motion since
    /// the last call) from the current positions, with the sub-stepping of the options, and makes
    /// the result the current mesh. Returns the displacement from the positions before the call;
    /// a result with inverted cells is returned (its `quality` says so) and not adopted: the
    /// solver stays as before the call, since no step can start from a tangled mesh.
    pub fn advance(&mut self, increment: &Motion) -> Result<Solution> {
        self.check_motion(increment)?;
        steps::advance(self, None, increment)
    }

    /// [`Solver::advance`] from the positions `coords`, when the caller moved the mesh itself
    /// since the last call: they become the current mesh (the reference, or in
    /// `ReferenceMode::Original` the new original mesh) in the same transaction, so a failure
    /// leaves the solver as it was. A result with inverted cells is returned and not adopted.
    pub fn advance_from(&mut self, coords: &[f64], increment: &Motion) -> Result<Solution> {
        self.check_motion(increment)?;
        let from = (coords != self.current_coords()).then_some(coords);
        steps::advance(self, from, increment)
    }

    /// Quality of the reference mesh moved by `displacement`.
    pub fn quality(&self, displacement: &[f64]) -> Quality {
        moved_quality(self.mesh(), displacement)
    }

    /// The positions of the mesh the solver was made with (whatever steps, moves and new
    /// references came since).
    pub fn initial_coords(&self) -> &[f64] {
        &self.initial
    }

    /// The mesh the solver was made with: its cells and faces at [`Solver::initial_coords`].
    pub fn initial_mesh(&self) -> Mesh {
        self.mesh().with_coords(self.initial.clone())
    }

    /// The displacement of every vertex since the mesh the solver was made with: the current
    /// positions minus the initial ones, the sum of every call's displacement (a step's
    /// [`Solution::displacement`] is its increment from the mesh before it).
    pub fn total_displacement(&self) -> Vec<f64> {
        self.current_coords().iter().zip(&self.initial).map(|(x, x0)| x - x0).collect()
    }

    /// Quality of the current positions against the mesh the solver was made with (a step's
    /// [`Solution::quality`] compares with the mesh before that step).
    pub fn total_quality(&self) -> Quality {
        quality(&self.initial_mesh(), self.current_coords())
    }
}

/// `Error::Tangled` naming the first cells of non-positive area of `mesh`'s topology at `coords`.
fn check_not_tangled(mesh: &Mesh, coords: &[f64]) -> Result<()> {
    let bad = inverted_cells(mesh, coords);
    if bad.is_empty() {
        return Ok(());
    }
    let first: Vec<String> = bad.iter().take(5).map(|c| c.to_string()).collect();
    Err(Error::Tangled(format!(
        "{} inverted cell(s) (a corner Jacobian or volume ≤ 0; first: {}); nothing is solved on a tangled mesh",
        bad.len(),
        first.join(", ")
    )))
}

/// True when a cell of `mesh` moved by `displacement` has a measure that is not finite (products
/// of coordinates overflow); computed only when the sizes make that possible.
fn measures_overflow(mesh: &Mesh, displacement: &[f64]) -> bool {
    let size = Solver::scale(displacement) + extent(mesh.coords(), mesh.dim());
    if (8.0 * size.powi(mesh.dim() as i32)).is_finite() {
        return false;
    }
    let x = moved(mesh.coords(), displacement);
    crate::mesh::quality::signed_measures(mesh, &x).iter().any(|m| !m.is_finite())
}

/// The largest extent of the points `x` (`dim` values each) along an axis.
fn extent(x: &[f64], dim: usize) -> f64 {
    (0..dim)
        .map(|c| {
            let axis = x.iter().skip(c).step_by(dim);
            axis.clone().fold(f64::NEG_INFINITY, |a, &v| a.max(v)) - axis.fold(f64::INFINITY, |a, &v| a.min(v))
        })
        .fold(0.0, f64::max)
}

/// Quality of `mesh` moved by `displacement` against `mesh`; displacements so large that the
/// moved cells' measures overflow are an error.
fn checked_quality(mesh: &Mesh, displacement: &[f64]) -> Result<Quality> {
    let quality = moved_quality(mesh, displacement);
    if !(quality.min_area_ratio.is_finite() && quality.max_area_ratio.is_finite())
        || measures_overflow(mesh, displacement)
    {
        // Finite displacements so large that the moved cells' measures overflow (a prescribed
        // motion or a slip surface's point far beyond the mesh): no mesh can hold the result.
        return Err(Error::InvalidArgument(format!(
            "the moved mesh's cell areas (volumes) overflow double precision (largest displacement {:e}, on a mesh \
             about {:e} across): displacements must be of the order of the mesh",
            Solver::scale(displacement),
            extent(mesh.coords(), mesh.dim())
        )));
    }
    Ok(quality)
}

/// Quality of `mesh` moved by `displacement` against `mesh`.
fn moved_quality(mesh: &Mesh, displacement: &[f64]) -> Quality {
    quality(mesh, &moved(mesh.coords(), displacement))
}

/// Positions `x` moved by `d` (both `dim` values per vertex).
pub(crate) fn moved(x: &[f64], d: &[f64]) -> Vec<f64> {
    x.iter().zip(d).map(|(x, d)| x + d).collect()
}

/// "x", "y", "z", or e.g. "x–y" for a group of components solved together.
fn group_name(comps: Range<usize>) -> String {
    match comps.len() {
        1 => COMPONENT[comps.start].to_string(),
        _ => format!("{}–{}", COMPONENT[comps.start], COMPONENT[comps.end - 1]),
    }
}

/// docs/DESIGN.md §4: on a CLAMPED patch moving rigidly, S_b = (1/V_b) Σ_j K_bj (d_j − L_j); the K L part
/// is returned as a source, so the held spacing rotates with the body. Every unknown of a patch
/// vertex gets it (a vertex split per region has one per side).
#[doc(hidden)]
pub fn rigid_flux(h: &Hierarchy, bcs: &BoundaryConditions, motion: &Motion, c: usize) -> Option<Vec<f64>> {
    let lev = h.fine();
    if lev.op.method != Method::Biharmonic {
        return None;
    }
    let mut g: Option<Vec<f64>> = None;
    for &(patch, m) in &motion.rigid {
        if bcs.kind(patch, c) != Kind::Clamped {
            continue;
        }
        let l: Vec<f64> =
            lev.dofs.dof_vertex.iter().map(|&v| m.displacement(lev.mesh().point(v as usize))[c]).collect();
        let mut on_patch = vec![false; lev.mesh().num_vertices()];
        lev.mesh().patch_vertices(patch).iter().for_each(|&v| on_patch[v as usize] = true);
        let g = g.get_or_insert_with(|| vec![0.0; lev.n()]);
        for (d, g) in g.iter_mut().enumerate() {
            if lev.dofs.vertices_of(d).iter().any(|&v| on_patch[v as usize]) {
                *g = lev.op.k.row_dot(d, &l);
            }
        }
    }
    g
}

/// `Error::NotConverged` for a report that did not reach its tolerance (`step` names the step).
fn check_converged(rep: &Report, step: Option<(usize, usize)>) -> Result<()> {
    if rep.converged {
        return Ok(());
    }
    let at = step.map(|(s, sub)| format!("step {s}.{sub}: ")).unwrap_or_default();
    Err(Error::NotConverged(format!(
        "{at}relative residual {:.3e} after {} cycles (the limit), largest correction {:.3e}",
        rep.rel_residual, rep.cycles, rep.max_correction
    )))
}

fn check_solve_params(p: &SolveParams) -> Result<()> {
    let degree_ok = |d: Option<usize>| d.is_none_or(|d| (1..=MAX_CHEB_DEGREE).contains(&d));
    let ok = p.tol > 0.0
        && p.tol.is_finite()
        && (1..=MAX_CYCLES).contains(&p.max_cycles)
        && degree_ok(p.cheb_degree)
        && degree_ok(p.cheb_coarse_degree)
        && p.cheb_lower_ratio.is_none_or(|r| r > 1.0 && r.is_finite());
    if !ok {
        return Err(Error::InvalidArgument(format!(
            "tolerance must be positive and finite, max cycles 1 to {MAX_CYCLES}, Chebyshev degree 1 to \
             {MAX_CHEB_DEGREE}, lower ratio finite and above 1"
        )));
    }
    Ok(())
}

pub(crate) fn check_options(o: &Options) -> Result<()> {
    check_solve_params(&o.solve)?;
    if o.max_substeps > MAX_SUBSTEPS {
        return Err(Error::InvalidArgument(format!("max_substeps is {}; at most {MAX_SUBSTEPS}", o.max_substeps)));
    }
    if !(0.0..1.0).contains(&o.min_volume_ratio) {
        return Err(Error::InvalidArgument(format!(
            "min_volume_ratio is {}; it must be at least 0 and below 1",
            o.min_volume_ratio
        )));
    }
    Ok(())
}

fn check_guess(g: &[f64], mesh: &Mesh) -> Result<()> {
    if g.len() != mesh.coords().len() {
        return Err(Error::InvalidArgument(format!(
            "displacement has {} values, the mesh has {} vertices × {} components",
            g.len(),
            mesh.num_vertices(),
            mesh.dim()
        )));
    }
    if let Some(i) = g.iter().position(|d| !d.is_finite()) {
        return Err(Error::InvalidArgument(format!("initial displacement of vertex {} is not finite", i / mesh.dim())));
    }
    Ok(())
}
