//! `meshmove_solver`: the multigrid hierarchy of one mesh and boundary-condition set, and the
//! calls a flow code makes every time step.

use super::bcs::meshmove_bcs;
use super::error::CError;
use super::handles::{self, check_out, check_xy_out, count, get, get_mut, hand_out, read_xy, write_xy, Handle, Slot};
use super::mesh::meshmove_mesh;
use super::status::meshmove_status;
use super::types::{self, meshmove_options, meshmove_quality, meshmove_report, meshmove_step_report};
use crate::{Motion, RigidMotion, Solver};
use std::ffi::c_char;

/// A solver: the hierarchy built once for a mesh and boundary conditions, the rigid motions
/// currently set, and the displacement of the last solve. Different solvers may be used
/// concurrently; a call on a solver that another thread is using returns
/// `MESHMOVE_STATUS_BUSY` at once and changes nothing.
pub struct meshmove_solver(Slot<SolverState>);

pub(crate) struct SolverState {
    solver: Solver,
    rigid: Vec<(i32, RigidMotion)>,
    last: Vec<f64>,
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
    fn motion(&self, d: Vec<f64>) -> Motion {
        Motion { displacement: d, rigid: self.rigid.clone() }
    }
    /// Puts the reference mesh back to `before` after a failed call changed it, so that the
    /// failure leaves the solver as it was. The operators are re-evaluated there (the same
    /// values as before the call).
    fn restore(&mut self, before: Option<Vec<f64>>, e: CError) -> CError {
        match before {
            Some(b) => match self.solver.set_reference(b) {
                Ok(()) => e,
                Err(r) => CError::new(e.status, format!("{}; restoring the reference failed too: {r}", e.msg)),
            },
            None => e,
        }
    }
}

/// Every output must be finite or the call fails (and writes nothing).
fn finite_out(v: &[f64], what: &str) -> Result<(), CError> {
    match v.iter().position(|p| !p.is_finite()) {
        Some(i) => Err(CError::new(
            meshmove_status::Diverged,
            format!("the {what} of vertex {} (0-based) is not finite; nothing was written", i / 2),
        )),
        None => Ok(()),
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

unsafe fn report_out(p: *mut meshmove_report, r: &crate::Report) -> Result<(), CError> {
    if !p.is_null() {
        handles::write_out(p, meshmove_report::from(r), "report")?;
    }
    Ok(())
}

/// Creates a solver for `mesh` and `bcs` (both copied; they may be freed afterwards) with
/// `options` (NULL for the defaults). Checks the boundary conditions against the mesh (unknown
/// patches, links that do not match, ill-posed components) and builds the multigrid hierarchy.
///
/// # Safety
/// `mesh` and `bcs` must be handles from meshmove (checked); `options` NULL or valid; `out` writable.
#[no_mangle]
pub unsafe extern "C" fn meshmove_solver_create(
    mesh: *const meshmove_mesh,
    bcs: *const meshmove_bcs,
    options: *const meshmove_options,
    out: *mut *mut meshmove_solver,
) -> meshmove_status {
    ffi_body!(meshmove_solver_create, {
        check_out(out, "out")?;
        let m = get(mesh, "mesh")?;
        let b = get(bcs, "bcs")?;
        let o = if options.is_null() {
            meshmove_options::default()
        } else {
            handles::check_aligned(options, "options")?;
            *options
        };
        let solver = Solver::new(&m, &b, o.to_rust()?)?;
        let nv = m.num_vertices();
        hand_out::<meshmove_solver>(SolverState { solver, rigid: Vec::new(), last: vec![0.0; 2 * nv] }, out)
    })
}

/// Frees a solver; NULL is accepted.
///
/// # Safety
/// `solver` must be NULL or a pointer received from meshmove (checked).
#[no_mangle]
pub unsafe extern "C" fn meshmove_solver_free(solver: *mut meshmove_solver) -> meshmove_status {
    ffi_body!(meshmove_solver_free, { handles::free(solver, "solver") })
}

/// Number of vertices of the solver's mesh and of multigrid levels (either pointer may be NULL).
///
/// # Safety
/// Non-NULL pointers must be writable.
#[no_mangle]
pub unsafe extern "C" fn meshmove_solver_sizes(
    solver: *const meshmove_solver,
    num_vertices: *mut i32,
    num_levels: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_solver_sizes, {
        let s = get(solver, "solver")?;
        if !num_vertices.is_null() {
            handles::write_out(num_vertices, s.nv() as i32, "num_vertices")?;
        }
        if !num_levels.is_null() {
            handles::write_out(num_levels, s.solver.num_levels() as i32, "num_levels")?;
        }
        Ok(())
    })
}

/// Makes `patch` move rigidly in the following solves: rotation by `angle` (radians,
/// counter-clockwise) about (`cx`, `cy`), then translation by (`tx`, `ty`). Its vertices then
/// ignore the displacement array; on a CLAMPED patch the held wall spacing rotates with the body.
/// Setting a patch again replaces its motion.
///
/// # Safety
/// `solver` must be a handle from meshmove (checked).
#[no_mangle]
pub unsafe extern "C" fn meshmove_solver_set_rigid_motion(
    solver: *mut meshmove_solver,
    patch: i32,
    tx: f64,
    ty: f64,
    angle: f64,
    cx: f64,
    cy: f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_set_rigid_motion, {
        let mut s = get_mut(solver, "solver")?;
        if ![tx, ty, angle, cx, cy].iter().all(|v| v.is_finite()) {
            return Err(CError::arg(format!("rigid motion of patch {patch} is not finite")));
        }
        if s.solver.mesh().patch_ids().binary_search(&patch).is_err() {
            return Err(CError::arg(format!(
                "patch {patch} is not in the mesh (patches: {:?})",
                s.solver.mesh().patch_ids()
            )));
        }
        let m = RigidMotion::planar([tx, ty], angle, [cx, cy]);
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
pub unsafe extern "C" fn meshmove_solver_clear_rigid_motions(solver: *mut meshmove_solver) -> meshmove_status {
    ffi_body!(meshmove_solver_clear_rigid_motions, {
        get_mut(solver, "solver")?.rigid.clear();
        Ok(())
    })
}

/// Solves for the displacement of every vertex to the options' tolerance.
///
/// `prescribed`: `len` = 2 × vertices doubles, read only where a component is prescribed (FIXED
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
        let nv = s.nv();
        check_opt_out(report, "report")?;
        check_xy_out(displacement, len, nv, "displacement")?;
        let d = read_xy(prescribed, len, nv, "prescribed")?;
        let g = if guess.is_null() { None } else { Some(read_xy(guess, len, nv, "guess")?) };
        let sol = s.solver.solve_report(&s.motion(d), g.as_deref())?;
        finite_out(&sol.displacement, "displacement")?;
        finite_report(&sol.report)?;
        report_out(report, &sol.report)?;
        write_xy(displacement, &sol.displacement);
        s.last = sol.displacement;
        if !sol.report.converged {
            return Err(not_converged(&sol.report, "the unconverged displacement was written"));
        }
        Ok(())
    })
}

/// Runs exactly one multigrid cycle of the solver's mode, from `displacement` (read and
/// overwritten, `len` = 2 × vertices), for codes that run a fixed number of cycles per step.
/// `report` (may be NULL) gives the correction and residual after the cycle.
///
/// # Safety
/// Arrays must hold `len` doubles; `solver` must be a handle from meshmove (checked).
#[no_mangle]
pub unsafe extern "C" fn meshmove_solver_cycle(
    solver: *mut meshmove_solver,
    len: i32,
    prescribed: *const f64,
    displacement: *mut f64,
    report: *mut meshmove_report,
) -> meshmove_status {
    ffi_body!(meshmove_solver_cycle, {
        let mut s = get_mut(solver, "solver")?;
        let nv = s.nv();
        check_opt_out(report, "report")?;
        check_xy_out(displacement, len, nv, "displacement")?;
        let d = read_xy(prescribed, len, nv, "prescribed")?;
        let mut x = read_xy(displacement, len, nv, "displacement")?;
        let r = s.solver.cycle(&s.motion(d), &mut x)?;
        finite_out(&x, "displacement")?;
        finite_report(&r)?;
        report_out(report, &r)?;
        write_xy(displacement, &x);
        s.last = x;
        Ok(())
    })
}

/// The drop-in call replacing a spring mover: given the boundary displacement (`len` = 2 ×
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
        let nv = s.nv();
        check_opt_out(report, "report")?;
        check_opt_out(quality, "quality")?;
        check_xy_out(coords, len, nv, "coords")?;
        let d = read_xy(boundary_displacement, len, nv, "boundary_displacement")?;
        let x = read_xy(coords, len, nv, "coords")?;
        handles::finite_xy(&x, "coords")?;
        // Transactional: `advance_from` re-references at `coords` (when the code moved the mesh
        // itself) and solves in one transaction, restoring the solver when it fails; a result
        // with inverted cells is returned but not adopted.
        let motion = s.motion(d);
        let sol = s.solver.advance_from(&x, &motion)?;
        // The positions the solver reached (checked finite inside its transaction).
        let moved = s.solver.last_valid_coords().to_vec();
        finite_out(&moved, "moved position")?;
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
                    "the moved mesh has {} inverted cell(s) (smallest area ratio {:e}); coords hold it, the solver keeps the mesh it had",
                    q.inverted, q.min_area_ratio
                ),
            )
        });
        report_out(report, &sol.report)?;
        if !quality.is_null() {
            handles::write_out(quality, meshmove_quality::from(q), "quality")?;
        }
        write_xy(coords, &moved);
        s.last = sol.displacement;
        e.map_or(Ok(()), Err)
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
        let nv = s.nv();
        let n = types::bounded(steps, "steps", 1, crate::limits::MAX_STEPS)?;
        let cap = count(num_reports, "num_reports")?;
        let out = handles::slice_mut(reports, cap, "reports")?;
        let d = read_xy(prescribed, len, nv, "prescribed")?;
        let before = s.solver.current_coords().to_vec();
        let motion = s.motion(d);
        // `move_in_steps` restores the solver itself when it fails; its step reports stay.
        let r = s.solver.move_in_steps(&motion, n);
        r?;
        let steps: Vec<meshmove_step_report> = s.solver.step_reports().iter().map(meshmove_step_report::from).collect();
        let checked = finite_out(s.solver.current_coords(), "moved position")
            .and_then(|()| steps.iter().try_for_each(types::finite_step_report));
        if let Err(e) = checked {
            return Err(s.restore(Some(before), e));
        }
        for (o, r) in out.iter_mut().zip(&steps) {
            *o = *r;
        }
        s.last = s.solver.current_coords().iter().zip(&before).map(|(a, b)| a - b).collect();
        // The last step's result inverted cells (the method's honest answer without
        // sub-stepping): reported, never plain OK; the solver stays as before the call.
        match s.solver.step_reports().last() {
            Some(r) if r.accepted && r.inverted > 0 => Err(CError::new(
                meshmove_status::Inverted,
                format!(
                    "the last step's mesh has {} inverted cell(s) (smallest area ratio {:e}); the solver keeps the mesh it \
                     had before the call (the step reports say how the motion went)",
                    r.inverted, r.min_volume_ratio
                ),
            )),
            _ => Ok(()),
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
pub unsafe extern "C" fn meshmove_solver_step_reports(
    solver: *const meshmove_solver,
    capacity: i32,
    reports: *mut meshmove_step_report,
    count: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_solver_step_reports, {
        let s = get(solver, "solver")?;
        let cap = handles::count(capacity, "capacity")?;
        if count.is_null() {
            return Err(CError::null("count"));
        }
        let steps = s.solver.step_reports();
        let n = steps.len();
        handles::write_out(count, n.min(i32::MAX as usize) as i32, "count")?;
        if cap < n {
            return Err(CError::new(
                meshmove_status::BufferTooSmall,
                format!("there are {n} step reports; capacity is {cap}"),
            ));
        }
        for (o, r) in handles::slice_mut(reports, n, "reports")?.iter_mut().zip(steps) {
            *o = meshmove_step_report::from(r);
        }
        Ok(())
    })
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
pub unsafe extern "C" fn meshmove_solver_set_substepping(
    solver: *mut meshmove_solver,
    max_substeps: i32,
    min_volume_ratio: f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_set_substepping, {
        let mut s = get_mut(solver, "solver")?;
        let n = types::bounded(max_substeps, "max_substeps", 0, crate::limits::MAX_SUBSTEPS)?;
        if !(0.0..1.0).contains(&min_volume_ratio) {
            return Err(CError::arg(format!(
                "min_volume_ratio is {min_volume_ratio}; it must be at least 0 and below 1"
            )));
        }
        let mut o = s.solver.options().clone();
        o.max_substeps = n;
        o.min_volume_ratio = min_volume_ratio;
        s.solver.set_options(o)?;
        Ok(())
    })
}

/// What each later step is solved from: a `meshmove_reference` value. Switching to
/// `MESHMOVE_REFERENCE_ORIGINAL` makes the current mesh the original one.
///
/// # Safety
/// `solver` must be a handle from meshmove (checked).
#[no_mangle]
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

/// Makes `coords` (`len` = 2 × vertices, finite) the solver's reference mesh: the operators are
/// re-evaluated there, the coarse topology is kept when it can be.
///
/// # Safety
/// `coords` must hold `len` doubles.
#[no_mangle]
pub unsafe extern "C" fn meshmove_solver_set_reference(
    solver: *mut meshmove_solver,
    len: i32,
    coords: *const f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_set_reference, {
        let mut s = get_mut(solver, "solver")?;
        let x = read_xy(coords, len, s.nv(), "coords")?;
        handles::finite_xy(&x, "coords")?;
        s.solver.set_reference(x)?;
        Ok(())
    })
}

/// Copies the current positions (after `meshmove_solver_move` or `_move_in_steps`: the moved
/// mesh) into `coords`, `len` = 2 × vertices.
///
/// # Safety
/// `coords` must hold `len` doubles.
#[no_mangle]
pub unsafe extern "C" fn meshmove_solver_get_coords(
    solver: *const meshmove_solver,
    len: i32,
    coords: *mut f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_get_coords, {
        let s = get(solver, "solver")?;
        check_xy_out(coords, len, s.nv(), "coords")?;
        write_xy(coords, s.solver.current_coords());
        Ok(())
    })
}

/// Copies the displacement of the last solve, cycle or move (for `_move_in_steps`, the total)
/// into `displacement`, `len` = 2 × vertices; zero before any.
///
/// # Safety
/// `displacement` must hold `len` doubles.
#[no_mangle]
pub unsafe extern "C" fn meshmove_solver_get_displacement(
    solver: *const meshmove_solver,
    len: i32,
    displacement: *mut f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_get_displacement, {
        let s = get(solver, "solver")?;
        check_xy_out(displacement, len, s.nv(), "displacement")?;
        write_xy(displacement, &s.last);
        Ok(())
    })
}

/// Quality of the reference mesh moved by `displacement` (`len` = 2 × vertices): inverted cells,
/// area ratios, smallest angle.
///
/// # Safety
/// `displacement` must hold `len` doubles; `quality` must be writable.
#[no_mangle]
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
        let d = read_xy(displacement, len, s.nv(), "displacement")?;
        handles::finite_xy(&d, "displacement")?;
        let q = s.solver.quality(&d);
        finite_quality(&q)?;
        handles::write_out(quality, meshmove_quality::from(q), "quality")
    })
}

/// Writes the reference mesh moved by `displacement` (`len` = 2 × vertices; NULL with `len` 0
/// for the reference itself) as a `.vtu` file (see `meshmove_mesh_write_vtu`).
///
/// # Safety
/// `path` must be a NUL-terminated string; `displacement` must hold `len` doubles.
#[no_mangle]
pub unsafe extern "C" fn meshmove_solver_write_vtu(
    solver: *const meshmove_solver,
    path: *const c_char,
    len: i32,
    displacement: *const f64,
) -> meshmove_status {
    ffi_body!(meshmove_solver_write_vtu, {
        let s = get(solver, "solver")?;
        let p = handles::path(path, "path")?;
        super::mesh::write_vtu(s.solver.mesh(), p, len, displacement)
    })
}
