//! `meshmove_options`: the solver options as an opaque handle with one checked setter per
//! option, so that options can be added without changing the ABI.

use super::error::CError;
use super::handles::{self, check_out, get_mut, hand_out, Handle, Slot};
use super::status::meshmove_status;
use super::types::{self, bounded};
use crate::{limits, Options};

/// Solver options: create with `meshmove_options_create` (the defaults: biharmonic, default
/// mode, relative residual 1e-8, 500 cycles, one thread per core), change what you need with the
/// `meshmove_options_set_*` calls, pass to `meshmove_solver_create` (which copies them: the
/// options may be freed or changed afterwards) and free with `meshmove_options_free`. A setter
/// given a value out of range returns `MESHMOVE_STATUS_INVALID_ARGUMENT` naming it and leaves the
/// options as they were.
pub struct meshmove_options(Slot<Options>);

impl Handle for meshmove_options {
    type Payload = Options;
    const NAME: &'static str = "meshmove_options";
    fn slot(&self) -> &Slot<Options> {
        &self.0
    }
    fn from_slot(slot: Slot<Options>) -> Self {
        meshmove_options(slot)
    }
}

/// Changes one option of `options` with `f` (which checks its value first).
fn set(options: *mut meshmove_options, f: impl FnOnce(&mut Options)) -> Result<(), CError> {
    f(&mut *get_mut(options, "options")?);
    Ok(())
}

/// A Chebyshev degree: 0 picks the per-method default, otherwise 1 ..= `MESHMOVE_MAX_CHEB_DEGREE`.
fn cheb_degree(d: i32, what: &str) -> Result<Option<usize>, CError> {
    Ok(Some(bounded(d, what, 0, limits::MAX_CHEB_DEGREE)?).filter(|&d| d > 0))
}

/// Creates options holding the defaults.
///
/// # Safety
/// `out` must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_create(out: *mut *mut meshmove_options) -> meshmove_status {
    ffi_body!(meshmove_options_create, {
        // SAFETY: the caller guarantees `out` is NULL (refused) or writable.
        unsafe { check_out(out, "out") }?;
        // SAFETY: `out` passed `check_out`.
        unsafe { hand_out::<meshmove_options>(Options::default(), out) }
    })
}

/// Frees options; NULL is accepted.
///
/// # Safety
/// `options` must be NULL or a pointer received from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_free(options: *mut meshmove_options) -> meshmove_status {
    ffi_body!(meshmove_options_free, { handles::free(options, "options") })
}

/// Which equation moves the mesh: a `meshmove_method` value (default BIHARMONIC).
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_method(options: *mut meshmove_options, method: i32) -> meshmove_status {
    ffi_body!(meshmove_options_set_method, {
        let m = types::method(method)?;
        set(options, |o| o.method = m)
    })
}

/// How the solver iterates: a `meshmove_mode` value (default DEFAULT).
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_mode(options: *mut meshmove_options, mode: i32) -> meshmove_status {
    ffi_body!(meshmove_options_set_mode, {
        let m = types::mode(mode)?;
        set(options, |o| o.solve.mode = m)
    })
}

/// When a solve stops: a `meshmove_criterion` value (default RELATIVE_RESIDUAL).
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_criterion(
    options: *mut meshmove_options,
    criterion: i32,
) -> meshmove_status {
    ffi_body!(meshmove_options_set_criterion, {
        let c = types::criterion(criterion)?;
        set(options, |o| o.solve.criterion = c)
    })
}

/// Worker threads of the solver, 0 ≤ `threads` ≤ `MESHMOVE_MAX_THREADS`; 0 (default) is one per
/// available core. All of the solver's work runs on them (never on a shared global pool).
/// Results do not depend on it.
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_threads(options: *mut meshmove_options, threads: i32) -> meshmove_status {
    ffi_body!(meshmove_options_set_threads, {
        let n = bounded(threads, "threads", 0, limits::MAX_THREADS)?;
        set(options, |o| o.threads = n)
    })
}

/// Most memory a solver made with these options may take, in bytes (0, the default: no limit;
/// negative is refused). `meshmove_solver_create` estimates what the solver will need from the
/// mesh's size and returns `MESHMOVE_STATUS_OUT_OF_MEMORY` before building anything when the
/// estimate is larger.
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_memory_budget(
    options: *mut meshmove_options,
    bytes: i64,
) -> meshmove_status {
    ffi_body!(meshmove_options_set_memory_budget, {
        let b = u64::try_from(bytes)
            .map_err(|_| CError::arg(format!("memory budget is {bytes}; it must be 0 (no limit) or positive")))?;
        set(options, |o| o.memory_budget = b)
    })
}

/// Tolerance of the stopping criterion (default 1e-8), positive and finite.
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_tol(options: *mut meshmove_options, tol: f64) -> meshmove_status {
    ffi_body!(meshmove_options_set_tol, {
        if !(tol > 0.0 && tol.is_finite()) {
            return Err(CError::arg(format!("tol is {tol}; it must be positive and finite")));
        }
        set(options, |o| o.solve.tol = tol)
    })
}

/// Most cycles (or CG iterations) per solve (default 500), 1 ≤ `max_cycles` ≤
/// `MESHMOVE_MAX_CYCLES`.
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_max_cycles(
    options: *mut meshmove_options,
    max_cycles: i32,
) -> meshmove_status {
    ffi_body!(meshmove_options_set_max_cycles, {
        let n = bounded(max_cycles, "max_cycles", 1, limits::MAX_CYCLES)?;
        set(options, |o| o.solve.max_cycles = n)
    })
}

/// Chebyshev smoother degree of the default mode on the finest level, and on the coarse levels
/// unless `meshmove_options_set_cheb_coarse_degree` says otherwise; 0 (default) picks per method
/// (biharmonic 6 on the finest level and 4 below, the others 3 and 2 in 2D, 4 and 3 in 3D),
/// otherwise 1 ≤ `degree` ≤ `MESHMOVE_MAX_CHEB_DEGREE`.
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_cheb_degree(
    options: *mut meshmove_options,
    degree: i32,
) -> meshmove_status {
    ffi_body!(meshmove_options_set_cheb_degree, {
        let d = cheb_degree(degree, "cheb_degree")?;
        set(options, |o| o.solve.cheb_degree = d)
    })
}

/// Chebyshev smoother degree on the coarse levels; 0 (default) follows
/// `meshmove_options_set_cheb_degree` (or the per-method default), otherwise
/// 1 ≤ `degree` ≤ `MESHMOVE_MAX_CHEB_DEGREE`.
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_cheb_coarse_degree(
    options: *mut meshmove_options,
    degree: i32,
) -> meshmove_status {
    ffi_body!(meshmove_options_set_cheb_coarse_degree, {
        let d = cheb_degree(degree, "cheb_coarse_degree")?;
        set(options, |o| o.solve.cheb_coarse_degree = d)
    })
}

/// 0 (default): fourth-kind Chebyshev, which needs no interval. Above 1 (finite): first-kind
/// Chebyshev on [λmax / `ratio`, λmax].
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_cheb_lower_ratio(
    options: *mut meshmove_options,
    ratio: f64,
) -> meshmove_status {
    ffi_body!(meshmove_options_set_cheb_lower_ratio, {
        let r = if ratio == 0.0 {
            None
        } else if ratio > 1.0 && ratio.is_finite() {
            Some(ratio)
        } else {
            return Err(CError::arg(format!("cheb_lower_ratio is {ratio}; it must be 0 (fourth kind) or above 1")));
        };
        set(options, |o| o.solve.cheb_lower_ratio = r)
    })
}

/// Automatic sub-stepping of the solver's moves, as `meshmove_solver_set_substepping` (which
/// changes it on a solver later): 0 ≤ `max_substeps` ≤ `MESHMOVE_MAX_SUBSTEPS` (0 or 1, the
/// default: no splitting), 0 ≤ `min_volume_ratio` < 1 (default 0).
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_substepping(
    options: *mut meshmove_options,
    max_substeps: i32,
    min_volume_ratio: f64,
) -> meshmove_status {
    ffi_body!(meshmove_options_set_substepping, {
        let (n, r) = types::substepping(max_substeps, min_volume_ratio)?;
        set(options, |o| {
            o.max_substeps = n;
            o.min_volume_ratio = r;
        })
    })
}

/// What each step is solved from: a `meshmove_reference` value (default INCREMENTAL), as
/// `meshmove_solver_set_reference_mode` (which changes it on a solver later).
///
/// # Safety
/// `options` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_options_set_reference_mode(
    options: *mut meshmove_options,
    mode: i32,
) -> meshmove_status {
    ffi_body!(meshmove_options_set_reference_mode, {
        let m = types::reference_mode(mode)?;
        set(options, |o| o.reference = m)
    })
}
