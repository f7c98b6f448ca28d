//! `meshmove_solver`: the multigrid hierarchy of one mesh and boundary-condition set, and the
//! calls a flow code makes every time step.

use super::bcs::{meshmove_bcs, UserData};
use super::error::CError;
use super::handles::{self, check_out, count, get, get_mut, Handle, Slot};
use super::mesh::{meshmove_mesh, write_counts};
use super::options::meshmove_options;
use super::points::{self, Points};
use super::status::meshmove_status;
use super::types::{self, meshmove_quality, meshmove_report, meshmove_step_report, meshmove_step_seconds};
use crate::{Motion, Progress, RigidMotion, Solver};
use std::ffi::{c_char, c_void};

/// A solver: the hierarchy built once for a mesh and boundary conditions, the rigid motions
/// currently set, and the displacement of the last solve. Different solvers may be used
/// concurrently; a call on a solver that another thread is using returns
/// `MESHMOVE_STATUS_BUSY` at once and changes nothing.
pub struct meshmove_solver(Slot<SolverState>);

pub(crate) struct SolverState {
    solver: Solver,
    rigid: Vec<(i32, RigidMotion)>,
    last: Points,
}

impl Handle for meshmove_solver {
    type Payload = SolverState;
    const NAME: &'static str = "meshmove_solver";
    fn slot(&self) -> &Slot<SolverState> {
        &self.0
    }
    fn from_slot(slot: Slot<SolverState>) -> Self {
        meshmove_solver(slot)
    }
}

impl SolverState {
    fn nv(&self) -> usize {
        self.solver.mesh().num_vertices()
    }
    fn dim(&self) -> usize {
        points::dim_of(self.solver.mesh())
    }
    /// Reads a flat `dim × vertices` array of this solver's mesh.
    ///
    /// # Safety
    /// A non-NULL `p` must hold `len` doubles.
    unsafe fn read(&self, p: *const f64, len: i32, what: &str) -> Result<Points, CError> {
        // SAFETY: this function's contract.
        unsafe { points::read(p, len, self.dim(), self.nv(), what) }
    }
    /// Checks a flat `dim × vertices` output array of this solver's mesh.
    ///
    /// # Safety
    /// A non-NULL `p` must hold `len` writable doubles.
    unsafe fn check_out(&self, p: *mut f64, len: i32, what: &str) -> Result<(), CError> {
        // SAFETY: this function's contract.
        unsafe { points::check_out(p, len, self.dim(), self.nv(), what) }
    }
    fn motion(&self, d: Points) -> Motion {
        Motion { displacement: d, rigid: self.rigid.clone() }
    }
    /// Puts the reference mesh back to `before` after a failed call changed it, so that the
    /// failure leaves the solver as it was. The operators are re-evaluated there (the same
    /// values as before the call).
    fn restore(&mut self, before: Option<Points>, e: CError) -> CError {
        match before {
            Some(b) => match self.solver.set_reference(b) {
                Ok(()) => e,
                Err(r) => CError::new(e.status, format!("{}; restoring the reference failed too: {r}", e.msg)),
            },
            None => e,
        }
    }
}

fn finite_report(r: &crate::Report) -> Result<(), CError> {
    for (v, what) in
        [(r.max_correction, "max correction"), (r.rel_residual, "relative residual"), (r.seconds, "seconds")]
    {
        if !v.is_finite() {
            return Err(CError::new(
                meshmove_status::Diverged,
                format!("the report's {what} is not finite ({v}); nothing was written"),
            ));
        }
    }
    Ok(())
}

fn finite_quality(q: &crate::mesh::quality::Quality) -> Result<(), CError> {
    let fields = [
        (q.min_area_ratio, "min_area_ratio"),
        (q.max_area_ratio, "max_area_ratio"),
        (q.min_angle_deg, "min_angle_deg"),
    ];
    match fields.iter().find(|(v, _)| !v.is_finite()) {
        Some((v, what)) => Err(CError::new(
            meshmove_status::Diverged,
            format!("the quality's {what} is not finite ({v}): a cell collapsed; nothing was written"),
        )),
        None => Ok(()),
    }
}

fn not_converged(r: &crate::Report, what: &str) -> CError {
    CError::new(
        meshmove_status::NotConverged,
        format!(
            "not converged: relative residual {:e} (largest correction {:e}) after {} cycles (max_cycles); {what}",
            r.rel_residual, r.max_correction, r.cycles
        ),
    )
}

/// An optional output (NULL allowed), checked before any work so that writing it cannot fail
/// after the solver changed.
fn check_opt_out<T>(p: *mut T, what: &str) -> Result<(), CError> {
    if p.is_null() {
        Ok(())
    } else {
        handles::check_aligned(p, what)
    }
}

/// Writes the report to an optional output.
///
/// # Safety
/// `p` must be NULL or writable.
unsafe fn report_out(p: *mut meshmove_report, r: &crate::Report) -> Result<(), CError> {
    // SAFETY: this function's contract.
    unsafe { handles::write_opt(p, meshmove_report::from(r), "report") }
}

/// Creates a solver for `mesh` and `bcs` (both copied; they may be freed afterwards) with
/// `options` (NULL for the defaults; copied). Checks the boundary conditions against the mesh
/// (unknown patches, links that do not match, ill-posed components) and builds the multigrid
/// hierarchy.
///
/// # Safety
/// `mesh`, `bcs` and a non-NULL `options` must be handles from meshmove (checked); `out` writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_create(
    mesh: *const meshmove_mesh,
    bcs: *const meshmove_bcs,
    options: *const meshmove_options,
    out: *mut *mut meshmove_solver,
) -> meshmove_status {
    ffi_body!(meshmove_solver_create, {
        // SAFETY: the caller guarantees `out` is NULL (refused) or writable.
        unsafe { check_out(out, "out") }?;
        let m = get(mesh, "mesh")?;
        let b = get(bcs, "bcs")?;
        let o = if options.is_null() { crate::Options::default() } else { get(options, "options")?.clone() };
        let solver = Solver::new(&m, &b, o)?;
        let cancel = solver.canceller();
        let state = SolverState { solver, rigid: Vec::new(), last: points::zeros(m.dim(), m.num_vertices()) };
        // SAFETY: `out` passed `check_out`.
        unsafe { handles::hand_out_slot::<meshmove_solver>(Slot::cancellable(state, cancel), out) }
    })
}

/// Frees a solver; NULL is accepted.
///
/// # Safety
/// `solver` must be NULL or a pointer received from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_free(solver: *mut meshmove_solver) -> meshmove_status {
    ffi_body!(meshmove_solver_free, { handles::free(solver, "solver") })
}

/// The dimension and number of vertices of the solver's mesh, and the number of multigrid
/// levels (any pointer may be NULL).
///
/// # Safety
/// Non-NULL pointers must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_sizes(
    solver: *const meshmove_solver,
    dim: *mut i32,
    num_vertices: *mut i32,
    num_levels: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_solver_sizes, {
        let s = get(solver, "solver")?;
        // SAFETY: the caller guarantees non-NULL pointers are writable.
        unsafe {
            write_counts(&[
                (dim, s.dim(), "dim"),
                (num_vertices, s.nv(), "num_vertices"),
                (num_levels, s.solver.num_levels(), "num_levels"),
            ])
        }
    })
}

/// Makes `patch` move rigidly in the following solves: rotation by `rotation` about `center`,
/// then translation by `translation`. `translation` and `center` hold `dim` values (the mesh's
/// dimension); `rotation` holds the angle in 2D (1 value, radians, counter-clockwise) and the
/// rotation vector in 3D (3 values: the unit axis times the angle). The patch's vertices then
/// ignore the displacement array; on a CLAMPED patch the held wall spacing rotates with the body.
/// Setting a patch again replaces its motion.
///
/// # Safety
/// `solver` must be a handle from meshmove (checked); the arrays must hold the values stated.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_set_rigid_motion(
    solver: *mut meshmove_solver,
    patch: i32,
    translation: *const f64,
    rotation: *const f64,
    center: *const f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_set_rigid_motion, {
        let mut s = get_mut(solver, "solver")?;
        // SAFETY: the caller guarantees `translation` and `center` hold `dim` doubles and
        // `rotation` 1 (2D) or 3 (3D).
        let m = unsafe { points::read_rigid_motion(s.dim(), patch, translation, rotation, center) }?;
        if s.solver.mesh().patch_ids().binary_search(&patch).is_err() {
            return Err(CError::arg(format!(
                "patch {patch} is not in the mesh (patches: {:?})",
                s.solver.mesh().patch_ids()
            )));
        }
        s.rigid.retain(|(p, _)| *p != patch);
        s.rigid.push((patch, m));
        Ok(())
    })
}

/// Removes every rigid motion.
///
/// # Safety
/// `solver` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_clear_rigid_motions(solver: *mut meshmove_solver) -> meshmove_status {
    ffi_body!(meshmove_solver_clear_rigid_motions, {
        get_mut(solver, "solver")?.rigid.clear();
        Ok(())
    })
}

/// Solves for the displacement of every vertex to the options' tolerance.
///
/// `prescribed`: `len` = dim × vertices doubles, read only where a component is prescribed (FIXED
/// or CLAMPED, not on rigidly moving patches). `guess`: NULL, or an initial displacement of the
/// same length (e.g. the previous step's). `displacement` receives the result (may be the same
/// array as `prescribed` or `guess`). `report` may be NULL.
///
/// `MESHMOVE_STATUS_NOT_CONVERGED`: the solve stopped at `max_cycles` above its tolerance; the
/// unconverged displacement IS written (with its report), for the caller to use or not. On
/// every other failure nothing is written.
///
/// # Safety
/// Arrays must hold `len` doubles; `solver` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_solve(
    solver: *mut meshmove_solver,
    len: i32,
    prescribed: *const f64,
    guess: *const f64,
    displacement: *mut f64,
    report: *mut meshmove_report,
) -> meshmove_status {
    ffi_body!(meshmove_solver_solve, {
        let mut s = get_mut(solver, "solver")?;
        check_opt_out(report, "report")?;
        // SAFETY: the caller guarantees the arrays hold `len` doubles (`guess` may be NULL).
        let (d, g) = unsafe {
            s.check_out(displacement, len, "displacement")?;
            let g = if guess.is_null() { None } else { Some(s.read(guess, len, "guess")?) };
            (s.read(prescribed, len, "prescribed")?, g)
        };
        let sol = s.solver.solve_report(&s.motion(d), g.as_deref())?;
        points::finite_out(&sol.displacement, s.dim(), "displacement")?;
        finite_report(&sol.report)?;
        // SAFETY: `report` is NULL or writable (contract); `displacement` passed `check_out`.
        unsafe {
            report_out(report, &sol.report)?;
            points::write(displacement, &sol.displacement);
        }
        s.last = sol.displacement;
        if !sol.report.converged {
            return Err(not_converged(&sol.report, "the unconverged displacement was written"));
        }
        Ok(())
    })
}

/// Runs exactly one multigrid cycle of the solver's mode, from `displacement` (read and
/// overwritten, `len` = dim × vertices), for codes that run a fixed number of cycles per step.
/// `report` (may be NULL) gives the correction and residual after the cycle.
///
/// # Safety
/// Arrays must hold `len` doubles; `solver` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_cycle(
    solver: *mut meshmove_solver,
    len: i32,
    prescribed: *const f64,
    displacement: *mut f64,
    report: *mut meshmove_report,
) -> meshmove_status {
    ffi_body!(meshmove_solver_cycle, {
        let mut s = get_mut(solver, "solver")?;
        check_opt_out(report, "report")?;
        // SAFETY: the caller guarantees the arrays hold `len` doubles.
        let (d, mut x) = unsafe {
            s.check_out(displacement, len, "displacement")?;
            (s.read(prescribed, len, "prescribed")?, s.read(displacement, len, "displacement")?)
        };
        let r = s.solver.cycle(&s.motion(d), &mut x)?;
        points::finite_out(&x, s.dim(), "displacement")?;
        finite_report(&r)?;
        // SAFETY: `report` is NULL or writable (contract); `displacement` passed `check_out`.
        unsafe {
            report_out(report, &r)?;
            points::write(displacement, &x);
        }
        s.last = x;
        Ok(())
    })
}

/// The drop-in call replacing a spring mover: given the boundary displacement (`len` = dim ×
/// vertices, read only where prescribed), solves and adds the displacement of every vertex to
/// `coords` in place; the moved mesh becomes the solver's reference for the next call.
///
/// `coords` on entry are the current positions; when they differ from the solver's (the code
/// moved the mesh itself), the reference is first re-evaluated there. With sub-stepping
/// (`meshmove_solver_set_substepping`) a motion that would invert a cell or not converge is
/// split; the step reports say how (`meshmove_solver_step_reports`). `report` and `quality` (of
/// the moved mesh against the positions on entry) may be NULL.
///
/// Returns OK, or `MESHMOVE_STATUS_INVERTED` when the converged result has inverted cells: then
/// `coords`, `report` and `quality` (its `inverted` count) ARE written but the solver keeps the
/// reference it had. On any other failure (`NOT_CONVERGED`, `TANGLED`, ...) nothing is written
/// and the solver is as before the call.
///
/// # Safety
/// Arrays must hold `len` doubles; `solver` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_move(
    solver: *mut meshmove_solver,
    len: i32,
    boundary_displacement: *const f64,
    coords: *mut f64,
    report: *mut meshmove_report,
    quality: *mut meshmove_quality,
) -> meshmove_status {
    ffi_body!(meshmove_solver_move, {
        let mut s = get_mut(solver, "solver")?;
        check_opt_out(report, "report")?;
        check_opt_out(quality, "quality")?;
        // SAFETY: the caller guarantees the arrays hold `len` doubles.
        let (d, x) = unsafe {
            s.check_out(coords, len, "coords")?;
            (s.read(boundary_displacement, len, "boundary_displacement")?, s.read(coords, len, "coords")?)
        };
        points::finite_in(&x, s.dim(), "coords")?;
        // Transactional: `advance_from` re-references at `coords` (when the code moved the mesh
        // itself) and solves in one transaction, restoring the solver when it fails; a result
        // with inverted cells is returned but not adopted.
        let motion = s.motion(d);
        let sol = s.solver.advance_from(&x, &motion)?;
        // The positions the solver reached (checked finite inside its transaction).
        let moved = s.solver.last_valid_coords().to_vec();
        points::finite_out(&moved, s.dim(), "moved position")?;
        finite_report(&sol.report)?;
        let q = sol.quality;
        if !quality.is_null() {
            finite_quality(&q)?;
        }
        let e = (q.inverted > 0).then(|| {
            // The method's honest answer has inverted cells: written, never plain OK; the solver
            // keeps the mesh it had (a tangled mesh is no reference for the next step).
            CError::new(
                meshmove_status::Inverted,
                format!(
                    "the moved mesh has {} inverted cell(s) (a corner Jacobian or volume <= 0; {} of non-positive {}; smallest {} ratio {:e}); coords hold it, the solver keeps the mesh it had",
                    q.inverted,
                    q.non_positive_measure,
                    if s.dim() == 2 { "area" } else { "volume" },
                    if s.dim() == 2 { "area" } else { "volume" },
                    q.min_area_ratio
                ),
            )
        });
        // SAFETY: `report` and `quality` are NULL or writable (contract); `coords` passed
        // `check_out`.
        unsafe {
            report_out(report, &sol.report)?;
            handles::write_opt(quality, meshmove_quality::from(q), "quality")?;
            points::write(coords, &moved);
        }
        // An INVERTED result is written to the caller's arrays only: the solver, its
        // displacement included, stays as before the call.
        match e {
            Some(e) => Err(e),
            None => {
                s.last = sol.displacement;
                Ok(())
            }
        }
    })
}

/// Moves the boundary to `prescribed` (and the rigid motions) in `steps` equal steps
/// (1 ≤ `steps` ≤ `MESHMOVE_MAX_STEPS`), the reference re-evaluated after each (the paper's 10-
/// and 15-interval runs); the solver's reference becomes the moved mesh. `reports`: NULL (with
/// `num_reports` 0), or room for `num_reports` step reports: the first min(count, num_reports)
/// are copied (all of them: `meshmove_solver_step_reports`). On failure the solver is as before
/// the call (its step reports say how far the motion got); so it is when the last step's result
/// has inverted cells (`MESHMOVE_STATUS_INVERTED`: the method's answer, reported, not adopted).
///
/// # Safety
/// `prescribed` must hold `len` doubles, `reports` `num_reports` structs.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_move_in_steps(
    solver: *mut meshmove_solver,
    len: i32,
    prescribed: *const f64,
    steps: i32,
    num_reports: i32,
    reports: *mut meshmove_step_report,
) -> meshmove_status {
    ffi_body!(meshmove_solver_move_in_steps, {
        let mut s = get_mut(solver, "solver")?;
        let n = types::bounded(steps, "steps", 1, crate::limits::MAX_STEPS)?;
        let cap = count(num_reports, "num_reports")?;
        // SAFETY: the caller guarantees `reports` holds `num_reports` structs and `prescribed`
        // `len` doubles.
        let (out, d) =
            unsafe { (handles::slice_mut(reports, cap, "reports")?, s.read(prescribed, len, "prescribed")?) };
        let before = s.solver.current_coords().to_vec();
        let motion = s.motion(d);
        // `move_in_steps` restores the solver itself when it fails; its step reports stay.
        let r = s.solver.move_in_steps(&motion, n);
        r?;
        let steps: Vec<meshmove_step_report> = s.solver.step_reports().iter().map(meshmove_step_report::from).collect();
        let checked = points::finite_out(s.solver.current_coords(), s.dim(), "moved position")
            .and_then(|()| steps.iter().try_for_each(types::finite_step_report));
        if let Err(e) = checked {
            return Err(s.restore(Some(before), e));
        }
        for (o, r) in out.iter_mut().zip(&steps) {
            *o = *r;
        }
        // The last step's result inverted cells (the method's honest answer without
        // sub-stepping): reported, never plain OK; the solver, its displacement included, stays
        // as before the call.
        match s.solver.step_reports().last() {
            Some(r) if r.inverted > 0 => Err(CError::new(
                meshmove_status::Inverted,
                format!(
                    "the last step's mesh has {} inverted cell(s) (smallest {} ratio {:e}); the solver keeps the mesh it \
                     had before the call (the step reports say how the motion went)",
                    r.inverted,
                    if s.dim() == 2 { "area" } else { "volume" },
                    r.min_volume_ratio
                ),
            )),
            _ => {
                s.last = points::difference(s.solver.current_coords(), &before);
                Ok(())
            }
        }
    })
}

/// The step reports of the last `_move` or `_move_in_steps` call on this solver (one per step
/// or sub-step attempt, rejected attempts with `accepted` 0; kept after a failure too). `*count` receives how many there are; if `capacity` is
/// smaller (e.g. 0 with `reports` NULL, to ask the size), nothing is copied and
/// `MESHMOVE_STATUS_BUFFER_TOO_SMALL` is returned.
///
/// # Safety
/// `reports` must hold `capacity` structs; `count` must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_step_reports(
    solver: *const meshmove_solver,
    capacity: i32,
    reports: *mut meshmove_step_report,
    count: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_solver_step_reports, {
        // SAFETY: the caller's contract is `copy_steps`'.
        unsafe { copy_steps(solver, capacity, reports, count, "reports") }
    })
}

/// Where each step of the last `_move` or `_move_in_steps` call spent its time (seconds of
/// re-reference, solve and quality check), one struct per step report in the same order; sized
/// and copied as `meshmove_solver_step_reports`.
///
/// # Safety
/// `seconds` must hold `capacity` structs; `count` must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_step_seconds(
    solver: *const meshmove_solver,
    capacity: i32,
    seconds: *mut meshmove_step_seconds,
    count: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_solver_step_seconds, {
        // SAFETY: the caller's contract is `copy_steps`'.
        unsafe { copy_steps(solver, capacity, seconds, count, "seconds") }
    })
}

/// Writes the number of step reports to `count` and, when `capacity` is large enough, one `T`
/// per report to `out` (`what` names it in errors).
///
/// # Safety
/// `out` must hold `capacity` values of `T`; `count` must be writable.
unsafe fn copy_steps<T: for<'a> From<&'a crate::StepReport>>(
    solver: *const meshmove_solver,
    capacity: i32,
    out: *mut T,
    count: *mut i32,
    what: &str,
) -> Result<(), CError> {
    let s = get(solver, "solver")?;
    // SAFETY: the caller's contract is `copy_reports`'.
    unsafe { copy_reports(s.solver.step_reports(), capacity, out, count, what) }
}

/// Writes the number of `reports` to `count` and, when `capacity` is large enough, one `T` per
/// report to `out` (`what` names it in errors); else `MESHMOVE_STATUS_BUFFER_TOO_SMALL`.
///
/// # Safety
/// `out` must hold `capacity` values of `T`; `count` must be writable.
pub(crate) unsafe fn copy_reports<R, T: for<'a> From<&'a R>>(
    reports: &[R],
    capacity: i32,
    out: *mut T,
    count: *mut i32,
    what: &str,
) -> Result<(), CError> {
    let cap = handles::count(capacity, "capacity")?;
    if count.is_null() {
        return Err(CError::null("count"));
    }
    let n = reports.len();
    // SAFETY: `count` is not NULL; the caller guarantees it is writable.
    unsafe { handles::write_out(count, n.min(i32::MAX as usize) as i32, "count") }?;
    if cap < n {
        return Err(CError::new(
            meshmove_status::BufferTooSmall,
            format!("there are {n} step reports; capacity is {cap}"),
        ));
    }
    // SAFETY: the caller guarantees `out` holds `capacity` >= `n` values.
    let out = unsafe { handles::slice_mut(out, n, what) }?;
    for (o, r) in out.iter_mut().zip(reports) {
        *o = T::from(r);
    }
    Ok(())
}

/// Automatic sub-stepping of `_move` and `_move_in_steps`: a step whose result would invert a
/// cell, fall below `min_volume_ratio` (moved / reference cell area), or not converge is split in
/// halves, down to 1/`max_substeps` of the step (0 ≤ `max_substeps` ≤ `MESHMOVE_MAX_SUBSTEPS`;
/// 0 or 1: no splitting, the default; 0 ≤ `min_volume_ratio` < 1, default 0). The motion still
/// ends exactly at the prescribed position, or the call fails at the last valid state (the
/// solver as before the call, the step reports saying how far it got).
///
/// # Safety
/// `solver` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_set_substepping(
    solver: *mut meshmove_solver,
    max_substeps: i32,
    min_volume_ratio: f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_set_substepping, {
        let mut s = get_mut(solver, "solver")?;
        let (n, min_volume_ratio) = types::substepping(max_substeps, min_volume_ratio)?;
        let mut o = s.solver.options().clone();
        o.max_substeps = n;
        o.min_volume_ratio = min_volume_ratio;
        s.solver.set_options(o)?;
        Ok(())
    })
}

/// The caller's progress callback: called with the caller's `user_data`, the report of the
/// sub-step just done (valid during the call only) and the call's number of steps. It returns 0
/// to go on; any other value cancels the call, which returns `MESHMOVE_STATUS_CANCELLED` with the
/// solver, its coordinates and its displacement as before the call.
///
/// It runs on the thread that called `meshmove_solver_move` or `_move_in_steps`, between solves,
/// while that call holds the solver (a meshmove call on the same solver from the callback
/// returns `MESHMOVE_STATUS_BUSY`). It must return normally: it must not throw a C++
/// exception, call `longjmp` or `pthread_exit` out of meshmove (that aborts the process or leaves
/// the solver busy for ever); to stop, return non-zero.
pub type meshmove_progress =
    Option<unsafe extern "C" fn(user_data: *mut c_void, report: *const meshmove_step_report, steps: i32) -> i32>;

/// Sets the progress callback of `solver`'s `_move` and `_move_in_steps` calls (see
/// `meshmove_progress`): called after every sub-step, accepted or rejected, its return value
/// going on or cancelling. `progress` NULL removes it. `user_data` must stay valid while the
/// callback is set.
///
/// # Safety
/// `solver` must be a handle from meshmove (checked); `progress` a function of the declared type.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_set_progress(
    solver: *mut meshmove_solver,
    progress: meshmove_progress,
    user_data: *mut c_void,
) -> meshmove_status {
    ffi_body!(meshmove_solver_set_progress, {
        let mut s = get_mut(solver, "solver")?;
        let mut o = s.solver.options().clone();
        o.progress = progress_hook(progress, user_data);
        s.solver.set_options(o)?;
        Ok(())
    })
}

/// The caller's progress callback and its `user_data` as a `Progress` (None for NULL).
pub(crate) fn progress_hook(progress: meshmove_progress, user_data: *mut c_void) -> Option<Progress> {
    progress.map(|f| {
        let user = UserData(user_data);
        Progress::new(move |r, steps| {
            let user = &user;
            let report = meshmove_step_report::from(r);
            let steps = steps.min(i32::MAX as usize) as i32;
            // SAFETY: the caller guarantees the callback and its context (`meshmove_progress`);
            // `report` lives until the callback returns.
            unsafe { f(user.0, &report, steps) == 0 }
        })
    })
}

/// Asks the call running on `solver` to stop; callable from any thread, also (and this is what
/// it is for) while another thread's call holds `solver`: it is the one function that never
/// returns `MESHMOVE_STATUS_BUSY`. The running call checks the request after every multigrid
/// cycle, so it stops within one cycle of a solve (and a long `_move_in_steps` within one step's
/// cycle), and returns `MESHMOVE_STATUS_CANCELLED` with the solver, its coordinates and its
/// displacement as before the call. When no call is running, the next call that solves stops at
/// its first check. The call that stops consumes the request.
///
/// # Safety
/// `solver` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_cancel(solver: *const meshmove_solver) -> meshmove_status {
    ffi_body!(meshmove_solver_cancel, {
        handles::cancel_of(solver, "solver")?.cancel();
        Ok(())
    })
}

/// What each later step is solved from: a `meshmove_reference` value. Switching to
/// `MESHMOVE_REFERENCE_ORIGINAL` makes the current mesh the original one.
///
/// # Safety
/// `solver` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_set_reference_mode(
    solver: *mut meshmove_solver,
    mode: i32,
) -> meshmove_status {
    ffi_body!(meshmove_solver_set_reference_mode, {
        let mut s = get_mut(solver, "solver")?;
        let mut o = s.solver.options().clone();
        o.reference = types::reference_mode(mode)?;
        s.solver.set_options(o)?;
        Ok(())
    })
}

/// Makes `coords` (`len` = dim × vertices, finite) the solver's reference mesh: the operators are
/// re-evaluated there (by the next call that solves), the coarse topology is kept when it can be.
///
/// # Safety
/// `coords` must hold `len` doubles.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_set_reference(
    solver: *mut meshmove_solver,
    len: i32,
    coords: *const f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_set_reference, {
        let mut s = get_mut(solver, "solver")?;
        // SAFETY: the caller guarantees `coords` holds `len` doubles.
        let x = unsafe { s.read(coords, len, "coords") }?;
        points::finite_in(&x, s.dim(), "coords")?;
        s.solver.set_reference(x)?;
        Ok(())
    })
}

/// Copies the current positions (after `meshmove_solver_move` or `_move_in_steps`: the moved
/// mesh) into `coords`, `len` = dim × vertices.
///
/// # Safety
/// `coords` must hold `len` doubles.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_get_coords(
    solver: *const meshmove_solver,
    len: i32,
    coords: *mut f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_get_coords, {
        let s = get(solver, "solver")?;
        // SAFETY: the caller guarantees `coords` holds `len` doubles; `write` after `check_out`.
        unsafe {
            s.check_out(coords, len, "coords")?;
            points::write(coords, s.solver.current_coords());
        }
        Ok(())
    })
}

/// Copies the displacement of the last solve, cycle or move (for `_move_in_steps`, the total)
/// into `displacement`, `len` = dim × vertices; zero before any. A call that fails leaves it as
/// it was (also one returning `MESHMOVE_STATUS_INVERTED`); an unconverged solve's written
/// displacement is the one exception.
///
/// # Safety
/// `displacement` must hold `len` doubles.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_get_displacement(
    solver: *const meshmove_solver,
    len: i32,
    displacement: *mut f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_get_displacement, {
        let s = get(solver, "solver")?;
        // SAFETY: the caller guarantees `displacement` holds `len` doubles; `write` after
        // `check_out`.
        unsafe {
            s.check_out(displacement, len, "displacement")?;
            points::write(displacement, &s.last);
        }
        Ok(())
    })
}

/// Quality of the reference mesh moved by `displacement` (`len` = dim × vertices): inverted cells,
/// area ratios, smallest angle.
///
/// # Safety
/// `displacement` must hold `len` doubles; `quality` must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_quality(
    solver: *const meshmove_solver,
    len: i32,
    displacement: *const f64,
    quality: *mut meshmove_quality,
) -> meshmove_status {
    ffi_body!(meshmove_solver_quality, {
        let s = get(solver, "solver")?;
        if quality.is_null() {
            return Err(CError::null("quality"));
        }
        // SAFETY: the caller guarantees `displacement` holds `len` doubles.
        let d = unsafe { s.read(displacement, len, "displacement") }?;
        points::finite_in(&d, s.dim(), "displacement")?;
        let q = s.solver.quality(&d);
        finite_quality(&q)?;
        // SAFETY: `quality` is not NULL; the caller guarantees it is writable.
        unsafe { handles::write_out(quality, meshmove_quality::from(q), "quality") }
    })
}

/// Writes a `.vtu` file (see `meshmove_mesh_write_vtu`). With `displacement` NULL and `len` 0:
/// the mesh the solver was made with, moved by the total displacement since then (the current
/// positions), so its `displacement` and ratios measure every move and step so far. Otherwise
/// the current reference mesh moved by `displacement` (`len` = dim × vertices).
///
/// # Safety
/// `path` must be a NUL-terminated string; `displacement` must hold `len` doubles.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_write_vtu(
    solver: *const meshmove_solver,
    path: *const c_char,
    len: i32,
    displacement: *const f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_write_vtu, {
        let s = get(solver, "solver")?;
        if len == 0 && displacement.is_null() {
            let total = s.solver.total_displacement();
            // SAFETY: the caller guarantees `path` is a NUL-terminated string; `total` holds
            // dim × vertices doubles.
            return unsafe {
                super::mesh::write_vtu(&s.solver.initial_mesh(), path, total.len() as i32, total.as_ptr())
            };
        }
        // SAFETY: the caller guarantees `path` is a NUL-terminated string and `displacement`
        // holds `len` doubles.
        unsafe { super::mesh::write_vtu(s.solver.mesh(), path, len, displacement) }
    })
}

/// Copies the total displacement since the mesh the solver was made with (the current positions
/// minus the initial ones: the sum of every `meshmove_solver_move` increment and
/// `_move_in_steps` total so far) into `displacement`, `len` = dim × vertices.
/// `meshmove_solver_get_displacement` gives only the last call's.
///
/// # Safety
/// `displacement` must hold `len` doubles.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_get_total_displacement(
    solver: *const meshmove_solver,
    len: i32,
    displacement: *mut f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_get_total_displacement, {
        let s = get(solver, "solver")?;
        // SAFETY: the caller guarantees `displacement` holds `len` doubles; `write` after
        // `check_out`.
        unsafe {
            s.check_out(displacement, len, "displacement")?;
            points::write(displacement, &s.solver.total_displacement());
        }
        Ok(())
    })
}

/// Quality of the current positions against the mesh the solver was made with: inverted cells,
/// volume (area) ratios, smallest angle, over every move and step so far (the quality a move
/// returns compares with the mesh before that move).
///
/// # Safety
/// `quality` must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_solver_total_quality(
    solver: *const meshmove_solver,
    quality: *mut meshmove_quality,
) -> meshmove_status {
    ffi_body!(meshmove_solver_total_quality, {
        let s = get(solver, "solver")?;
        if quality.is_null() {
            return Err(CError::null("quality"));
        }
        let q = s.solver.total_quality();
        finite_quality(&q)?;
        // SAFETY: `quality` is not NULL; the caller guarantees it is writable.
        unsafe { handles::write_out(quality, meshmove_quality::from(q), "quality") }
    })
}
