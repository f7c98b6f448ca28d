//! The solver a flow code holds for the life of its mesh: hierarchy built once, then each time
//! step a motion in and displacements out.
//!
//! What a call guarantees: a result is returned only when every component reached the tolerance
//! (`Error::NotConverged` otherwise; [`Solver::solve_report`] hands back an unconverged result for
//! callers who want to decide themselves), a conjugate-gradient breakdown is `Error::Diverged`,
//! a reference mesh with a cell of non-positive area is `Error::Tangled` before anything is
//! solved on it, and a call that fails leaves the solver exactly as it was.

use crate::bc::{resolve_links, BoundaryConditions, Kind, COMPONENT, P};
use crate::mesh::quality::{inverted_cells, quality, Quality};
use crate::motion::Motion;
use crate::multigrid::cycle::{cycle, Workspace};
use crate::multigrid::hierarchy::{Hierarchy, HierarchyParams, Level};
use crate::multigrid::smoother::Start;
use crate::multigrid::solve::{solve, Report, SolveParams};
use crate::operator::Method;
use crate::pool::Pool;
use crate::sparse::max_abs;
use crate::{Error, Mesh, Result};
use glam::DVec2;
use std::time::Instant;

mod steps;

pub use steps::StepReport;

/// Most Chebyshev degree accepted (degree 6 is the biharmonic's default; the cost of a cycle
/// grows linearly with it).
pub const MAX_CHEB_DEGREE: usize = 64;
/// Most cycles per solve accepted.
pub const MAX_CYCLES: usize = 1_000_000;
/// Most steps of one `move_in_steps` call accepted.
pub const MAX_STEPS: usize = 1_000_000;
/// Most sub-steps one step may be split into.
pub const MAX_SUBSTEPS: usize = 1 << 20;

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

#[derive(Clone, Debug, Default)]
pub struct Options {
    pub method: Method,
    pub solve: SolveParams,
    /// Worker threads of the solver's own pool (0: one per available core). All of a call's work
    /// runs there, never on rayon's global pool; results do not depend on the count.
    pub threads: usize,
    pub hierarchy: HierarchyParams,
    /// Automatic sub-stepping: a step whose result would invert a cell, fall below
    /// `min_volume_ratio`, or not converge is split in halves, up to this many sub-steps per step.
    /// 0 or 1: no splitting.
    pub max_substeps: usize,
    /// Smallest deformed/reference cell area ratio a sub-stepped step accepts (0: any valid cell).
    pub min_volume_ratio: f64,
    /// What each step is solved from.
    pub reference: ReferenceMode,
}

/// Displacements of every vertex and how the solve went.
#[derive(Clone, Debug)]
pub struct Solution {
    pub displacement: Vec<DVec2>,
    pub report: Report,
    /// The moved mesh against the mesh the displacement starts from.
    pub quality: Quality,
}

/// The state a failed mutating call restores.
struct Undo {
    coords: Vec<DVec2>,
    /// The hierarchy as it was before the first rebuild of the call.
    hierarchy: Option<Hierarchy>,
}

pub struct Solver {
    opts: Options,
    bcs: BoundaryConditions,
    hierarchy: Hierarchy,
    pool: Pool,
    /// `ReferenceMode::Original`: the motion done so far (the sum of the increments) and the
    /// positions it gave; the hierarchy stays on the original mesh.
    total: Option<(Motion, Vec<DVec2>)>,
    /// The sub-steps of the last `advance` or `move_in_steps` call.
    steps: Vec<StepReport>,
    /// The last valid mesh the last `advance` or `move_in_steps` call reached (empty before the
    /// first).
    last_valid: Vec<DVec2>,
}

impl Solver {
    pub fn new(mesh: &Mesh, bcs: &BoundaryConditions, opts: Options) -> Result<Solver> {
        check_options(&opts)?;
        bcs.check(mesh)?;
        check_not_tangled(mesh, mesh.coords())?;
        let pairs = resolve_links(mesh, &bcs.links)?;
        let pool = Pool::new(opts.threads)?;
        let hierarchy = pool.install(|| Hierarchy::build(mesh, pairs, bcs, opts.method, &opts.hierarchy))??;
        let (steps, last_valid) = (Vec::new(), Vec::new());
        Ok(Solver { opts, bcs: bcs.clone(), hierarchy, pool, total: None, steps, last_valid })
    }

    /// Runs `f` on the solver's threads: every part of a call's work, so the thread count set
    /// in the options bounds all of it (fails only when a forked child cannot start its pool).
    fn run<T: Send>(&self, f: impl FnOnce() -> T + Send) -> Result<T> {
        self.pool.install(f)
    }

    /// The reference mesh (the mesh at the start of the step).
    pub fn mesh(&self) -> &Mesh {
        &self.hierarchy.fine().mesh
    }

    /// The positions after the last step: the reference mesh, or in `ReferenceMode::Original`
    /// the original mesh moved by the motion so far.
    pub fn current_coords(&self) -> &[DVec2] {
        match &self.total {
            Some((_, x)) => x,
            None => self.mesh().coords(),
        }
    }

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
        if opts.method != self.opts.method || opts.threads != self.opts.threads || opts.hierarchy != self.opts.hierarchy
        {
            return Err(Error::InvalidArgument(
                "method, threads and hierarchy parameters are fixed when the solver is made: make a new solver".into(),
            ));
        }
        if opts.reference != self.opts.reference {
            // The current positions become the reference (Incremental) or the original mesh
            // with no motion done yet (Original).
            let x = self.current_coords().to_vec();
            if x.as_slice() != self.mesh().coords() {
                self.set_reference(x)?;
            }
            self.total = None;
        }
        self.opts = opts;
        Ok(())
    }

    pub fn num_levels(&self) -> usize {
        self.hierarchy.levels.len()
    }

    /// A table of the multigrid levels.
    pub fn describe(&self) -> String {
        self.hierarchy.describe()
    }

    pub fn hierarchy(&self) -> &Hierarchy {
        &self.hierarchy
    }

    /// The sub-steps of the last [`Solver::advance`] or [`Solver::move_in_steps`] call, also when
    /// it failed.
    pub fn step_reports(&self) -> &[StepReport] {
        &self.steps
    }

    /// The last valid mesh the last [`Solver::advance`] or [`Solver::move_in_steps`] call reached
    /// (its result on success; on failure how far it got, while the solver itself is restored).
    pub fn last_valid_coords(&self) -> &[DVec2] {
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
            for (c, name) in COMPONENT.iter().enumerate() {
                if self.bcs.kind(patch, c) != Kind::Free {
                    continue;
                }
                let moves =
                    mesh.patch_vertices(patch).iter().any(|&v| m.displacement(mesh.coords()[v as usize])[c] != 0.0);
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
    fn prescribed(&self, motion: &Motion, vals: &[DVec2], c: usize) -> Result<(Vec<f64>, Option<Vec<f64>>)> {
        let lev = self.hierarchy.fine();
        let flags = &lev.flags[c];
        let mut dp = vec![0.0; lev.n()];
        for d in 0..lev.n() {
            if flags[d] & P == 0 {
                continue;
            }
            let vs = lev.dofs.vertices_of(d);
            let v0 = vals[vs[0] as usize][c];
            // Linked vertices are one unknown: they must be told the same thing.
            for &v in &vs[1..] {
                let vv = vals[v as usize][c];
                if (vv - v0).abs() > 1e-9 * (1.0 + v0.abs().max(vv.abs())) {
                    return Err(Error::InvalidArgument(format!(
                        "linked vertices {} and {v} are prescribed different {} displacements ({v0} and {vv})",
                        vs[0], COMPONENT[c]
                    )));
                }
            }
            dp[d] = v0;
        }
        Ok((dp, rigid_flux(&self.hierarchy, &self.bcs, motion, c)))
    }

    /// The right-hand side of component `c` (its scratch S freed before the solve starts).
    fn rhs(lev: &Level, c: usize, dp: &[f64], g: Option<&[f64]>) -> Result<Vec<f64>> {
        let (mut b, mut s) = (vec![0.0; lev.n()], vec![0.0; lev.n()]);
        lev.op.rhs(&lev.flags[c], dp, g, &mut b, &mut s);
        if let Some(i) = b.iter().position(|v| !v.is_finite()) {
            let big = dp.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            return Err(Error::InvalidArgument(format!(
                "the prescribed {} displacements (largest {big:e}) overflow the operator (right-hand side not \
                 finite at unknown {i}): displacements must be of the order of the mesh",
                COMPONENT[c]
            )));
        }
        Ok(b)
    }

    fn scale(vals: &[DVec2]) -> f64 {
        vals.iter().fold(0.0f64, |m, d| m.max(d.x.abs()).max(d.y.abs()))
    }

    fn to_vertices(lev: &Level, d: &[Vec<f64>; 2]) -> Vec<DVec2> {
        lev.dofs.vertex_dof.iter().map(|&k| DVec2::new(d[0][k as usize], d[1][k as usize])).collect()
    }

    /// Solves for the displacement of every vertex, to the tolerance of the options.
    pub fn solve(&self, motion: &Motion) -> Result<Solution> {
        self.solve_from(motion, None)
    }

    /// As `solve`, starting from a guess (e.g. the previous time step's displacement).
    pub fn solve_from(&self, motion: &Motion, guess: Option<&[DVec2]>) -> Result<Solution> {
        let sol = self.solve_report(motion, guess)?;
        check_converged(&sol.report, None)?;
        Ok(sol)
    }

    /// As `solve_from`, but a solve that stops above its tolerance is returned (with
    /// `report.converged == false`) for the caller to judge. Breakdowns and bad input are errors.
    pub fn solve_report(&self, motion: &Motion, guess: Option<&[DVec2]>) -> Result<Solution> {
        self.check_motion(motion)?;
        let lev = self.hierarchy.fine();
        if let Some(g) = guess {
            check_guess(g, lev.mesh.num_vertices())?;
        }
        self.run(|| self.solve_inner(motion, guess))?
    }

    fn solve_inner(&self, motion: &Motion, guess: Option<&[DVec2]>) -> Result<Solution> {
        let lev = self.hierarchy.fine();
        let vals = motion.vertex_values(&lev.mesh);
        let scale = Self::scale(&vals);
        let mut d: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
        let mut reps = Vec::new();
        for c in 0..2 {
            let (dp, g) = self.prescribed(motion, &vals, c)?;
            let flags = &lev.flags[c];
            let b = Self::rhs(lev, c, &dp, g.as_deref())?;
            // Not kept through the solve (memory): the prescribed values are re-read from `vals`.
            drop((dp, g));
            let mut x: Vec<f64> = match guess {
                Some(gv) => (0..lev.n())
                    .map(|k| if flags[k] & P != 0 { 0.0 } else { gv[lev.dofs.dof_vertex[k] as usize][c] })
                    .collect(),
                None => vec![0.0; lev.n()],
            };
            let rep = solve(&self.hierarchy, c, &self.opts.solve, &b, &mut x, scale);
            if let Some(k) = rep.breakdown {
                return Err(Error::Diverged(format!(
                    "component {}: conjugate gradients broke down at iteration {k} (pᵀAp not positive): the \
                     operator is not positive definite on this reference mesh",
                    COMPONENT[c]
                )));
            }
            if !rep.rel_residual.is_finite() || rep.rel_residual > 1.0 {
                return Err(Error::Diverged(format!(
                    "component {} residual {:e} after {} cycles",
                    COMPONENT[c], rep.rel_residual, rep.cycles
                )));
            }
            // The solve leaves P unknowns at zero; they take their prescribed values.
            for (k, x) in x.iter_mut().enumerate() {
                if flags[k] & P != 0 {
                    *x += vals[lev.dofs.vertices_of(k)[0] as usize][c];
                }
            }
            d[c] = x;
            reps.push(rep);
        }
        let ry = reps.pop().expect("two reports");
        let rx = reps.pop().expect("two reports");
        let displacement = Self::to_vertices(lev, &d);
        if let Some(v) = displacement.iter().position(|d| !d.is_finite()) {
            return Err(Error::Diverged(format!("the displacement of vertex {v} is not finite")));
        }
        let quality = moved_quality(&lev.mesh, &displacement);
        Ok(Solution { displacement, report: Report::merge(rx, ry), quality })
    }

    /// One multigrid cycle of the solver's mode from `displacement` (read and overwritten): for
    /// codes that run a fixed number of cycles per time step.
    pub fn cycle(&self, motion: &Motion, displacement: &mut [DVec2]) -> Result<Report> {
        self.check_motion(motion)?;
        check_guess(displacement, self.mesh().num_vertices())?;
        let (out, rep) = self.run(|| self.cycle_inner(motion, displacement))??;
        if let Some(v) = out.iter().position(|d| !d.is_finite()) {
            return Err(Error::Diverged(format!("the cycle's displacement of vertex {v} is not finite")));
        }
        displacement.copy_from_slice(&out);
        Ok(rep)
    }

    fn cycle_inner(&self, motion: &Motion, displacement: &[DVec2]) -> Result<(Vec<DVec2>, Report)> {
        let lev = self.hierarchy.fine();
        let vals = motion.vertex_values(&lev.mesh);
        let cp = self.opts.solve.cycle_params(self.opts.method);
        let mut d: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
        let mut reps = Vec::new();
        for c in 0..2 {
            let t0 = Instant::now();
            let (dp, g) = self.prescribed(motion, &vals, c)?;
            let flags = &lev.flags[c];
            let n = lev.n();
            let b = Self::rhs(lev, c, &dp, g.as_deref())?;
            let (mut s, mut r) = (vec![0.0; n], vec![0.0; n]);
            let mut x: Vec<f64> = (0..n)
                .map(|k| if flags[k] & P != 0 { 0.0 } else { displacement[lev.dofs.dof_vertex[k] as usize][c] })
                .collect();
            let before = x.clone();
            let mut ws = Workspace::new(&self.hierarchy);
            cycle(&self.hierarchy, c, &cp, &b, &mut x, Start::Guess, &mut ws);
            lev.op.residual(flags, &b, &x, &mut r, &mut s);
            let bn = crate::sparse::dot(&b, &b).sqrt();
            let rn = crate::sparse::dot(&r, &r).sqrt();
            // A zero right-hand side has nothing to reduce: its relative residual is its norm.
            let rel = if bn > 0.0 { rn / bn } else { rn };
            let change: Vec<f64> = x.iter().zip(&before).map(|(a, b)| a - b).collect();
            let mc = max_abs(&change);
            if !rel.is_finite() || !mc.is_finite() {
                return Err(Error::Diverged(format!(
                    "component {}: the cycle gave a non-finite residual or correction",
                    COMPONENT[c]
                )));
            }
            x.iter_mut().zip(&dp).for_each(|(x, p)| *x += p);
            d[c] = x;
            let secs = t0.elapsed().as_secs_f64();
            reps.push(Report {
                cycles: 1,
                max_correction: mc,
                rel_residual: rel,
                converged: false,
                breakdown: None,
                seconds: secs,
                history: vec![(mc, rel)],
            });
        }
        let ry = reps.pop().expect("two reports");
        let rx = reps.pop().expect("two reports");
        Ok((Self::to_vertices(lev, &d), Report::merge(rx, ry)))
    }

    /// Makes `coords` the new reference mesh: K and V re-evaluated on every level, the coarse
    /// topology kept (rebuilt only if a coarse cell would invert). Positions with a cell of
    /// non-positive area are `Error::Tangled`; on any error the solver is unchanged.
    pub fn set_reference(&mut self, coords: Vec<DVec2>) -> Result<()> {
        self.check_reference(&coords)?;
        let mut undo = self.undo();
        let r = self.set_reference_inner(coords, &mut undo);
        match r {
            // In `ReferenceMode::Original` the new reference is the new original mesh.
            Ok(()) => self.total = None,
            Err(_) => self.restore(undo),
        }
        r
    }

    /// Finite positions, one per vertex, no cell of non-positive area.
    pub(crate) fn check_reference(&self, coords: &[DVec2]) -> Result<()> {
        let nv = self.hierarchy.fine().mesh.num_vertices();
        if coords.len() != nv {
            return Err(Error::InvalidArgument(format!("new reference needs {nv} positions, got {}", coords.len())));
        }
        if let Some(v) = coords.iter().position(|p| !p.is_finite()) {
            return Err(Error::InvalidArgument(format!("new reference: vertex {v} is not finite")));
        }
        check_not_tangled(&self.hierarchy.fine().mesh, coords)
    }

    fn undo(&self) -> Undo {
        Undo { coords: self.hierarchy.fine().mesh.coords().to_vec(), hierarchy: None }
    }

    /// Puts the solver back to the state `undo` recorded: the hierarchy it had (moved back to
    /// its positions, which recomputes every value bitwise as it was).
    fn restore(&mut self, undo: Undo) {
        if let Some(h) = undo.hierarchy {
            self.hierarchy = h;
        }
        if self.hierarchy.fine().mesh.coords() != undo.coords.as_slice() {
            let hierarchy = &mut self.hierarchy;
            let moved = self.pool.install(|| hierarchy.move_to(undo.coords));
            // The same topology at positions it had before: every coarse cell was valid there.
            debug_assert!(matches!(moved, Ok(Ok(true))), "moving back to a previous reference failed");
        }
    }

    fn set_reference_inner(&mut self, coords: Vec<DVec2>, undo: &mut Undo) -> Result<()> {
        let hierarchy = &mut self.hierarchy;
        let kept = self.pool.install(|| hierarchy.move_to(coords.clone()))??;
        if !kept {
            self.rebuild(coords, undo)?;
        }
        Ok(())
    }

    /// A new hierarchy built from `coords`, the old one kept in `undo` (the first time).
    fn rebuild(&mut self, coords: Vec<DVec2>, undo: &mut Undo) -> Result<()> {
        let mesh = self.hierarchy.fine().mesh.with_coords(coords);
        let pairs = self.hierarchy.fine().pairs.clone();
        let (bcs, method, hp) = (&self.bcs, self.opts.method, &self.opts.hierarchy);
        let built = self.pool.install(|| Hierarchy::build(&mesh, pairs, bcs, method, hp))??;
        let old = std::mem::replace(&mut self.hierarchy, built);
        if undo.hierarchy.is_none() {
            undo.hierarchy = Some(old);
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
    pub fn advance_from(&mut self, coords: &[DVec2], increment: &Motion) -> Result<Solution> {
        self.check_motion(increment)?;
        let from = (coords != self.current_coords()).then_some(coords);
        steps::advance(self, from, increment)
    }

    /// Quality of the reference mesh moved by `displacement`.
    pub fn quality(&self, displacement: &[DVec2]) -> Quality {
        moved_quality(self.mesh(), displacement)
    }
}

/// `Error::Tangled` naming the first cells of non-positive area of `mesh`'s topology at `coords`.
fn check_not_tangled(mesh: &Mesh, coords: &[DVec2]) -> Result<()> {
    let bad = inverted_cells(mesh, coords);
    if bad.is_empty() {
        return Ok(());
    }
    let first: Vec<String> = bad.iter().take(5).map(|c| c.to_string()).collect();
    Err(Error::Tangled(format!(
        "{} cell(s) of non-positive area (first: {}); nothing is solved on a tangled mesh",
        bad.len(),
        first.join(", ")
    )))
}

/// Quality of `mesh` moved by `displacement` against `mesh`.
fn moved_quality(mesh: &Mesh, displacement: &[DVec2]) -> Quality {
    let moved: Vec<DVec2> = mesh.coords().iter().zip(displacement).map(|(x, d)| *x + *d).collect();
    quality(mesh, &moved)
}

/// docs/DESIGN.md §4: on a CLAMPED patch moving rigidly, S_b = (1/V_b) Σ_j K_bj (d_j − L_j); the K L part
/// is returned as a source, so the held spacing rotates with the body. Every unknown of a patch
/// vertex gets it (a vertex split per region has one per side).
pub(crate) fn rigid_flux(h: &Hierarchy, bcs: &BoundaryConditions, motion: &Motion, c: usize) -> Option<Vec<f64>> {
    let lev = h.fine();
    if lev.op.method != Method::Biharmonic {
        return None;
    }
    let mut g: Option<Vec<f64>> = None;
    let x = lev.mesh.coords();
    for &(patch, m) in &motion.rigid {
        if bcs.kind(patch, c) != Kind::Clamped {
            continue;
        }
        let l: Vec<f64> = lev.dofs.dof_vertex.iter().map(|&v| m.displacement(x[v as usize])[c]).collect();
        let mut on_patch = vec![false; lev.mesh.num_vertices()];
        lev.mesh.patch_vertices(patch).iter().for_each(|&v| on_patch[v as usize] = true);
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

fn check_options(o: &Options) -> Result<()> {
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

fn check_guess(g: &[DVec2], nv: usize) -> Result<()> {
    if g.len() != nv {
        return Err(Error::InvalidArgument(format!(
            "displacement has {} entries, the mesh has {nv} vertices",
            g.len()
        )));
    }
    if let Some(v) = g.iter().position(|d| !d.is_finite()) {
        return Err(Error::InvalidArgument(format!("initial displacement of vertex {v} is not finite")));
    }
    Ok(())
}
