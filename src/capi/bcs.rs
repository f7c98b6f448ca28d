//! `meshmove_bcs`: kinds per patch and component, links, interface variants.

use super::error::CError;
use super::handles::{self, check_out, get_mut, hand_out, slice, Handle, Slot};
use super::points;
use super::status::meshmove_status;
use super::types;
use crate::bc::SlipSurface;
use crate::{BoundaryConditions, Link};
use std::ffi::c_void;

/// A boundary-condition set: a `meshmove_kind` per patch and displacement component (patches not
/// named are FIXED), links between patches, interface variants. It is checked against a mesh when a solver
/// is created, and copied into the solver (it may be freed afterwards).
pub struct meshmove_bcs(Slot<BoundaryConditions>);

impl Handle for meshmove_bcs {
    type Payload = BoundaryConditions;
    const NAME: &'static str = "meshmove_bcs";
    fn slot(&self) -> &Slot<BoundaryConditions> {
        &self.0
    }
    fn from_slot(slot: Slot<BoundaryConditions>) -> Self {
        meshmove_bcs(slot)
    }
}

/// Creates an empty boundary-condition set (every patch FIXED in every component).
///
/// # Safety
/// `out` must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_bcs_create(out: *mut *mut meshmove_bcs) -> meshmove_status {
    ffi_body!(meshmove_bcs_create, {
        // SAFETY: the caller guarantees `out` is NULL (refused) or writable.
        unsafe { check_out(out, "out") }?;
        // SAFETY: `out` passed `check_out`.
        unsafe { hand_out(BoundaryConditions::new(), out) }
    })
}

/// Frees a boundary-condition set; NULL is accepted.
///
/// # Safety
/// `bcs` must be NULL or a pointer received from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_bcs_free(bcs: *mut meshmove_bcs) -> meshmove_status {
    ffi_body!(meshmove_bcs_free, { handles::free(bcs, "bcs") })
}

/// Sets the `meshmove_kind` of one displacement component (0 = x, 1 = y, 2 = z) on `patch`. A
/// z kind is ignored on a 2D mesh.
///
/// # Safety
/// `bcs` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_bcs_set_kind(
    bcs: *mut meshmove_bcs,
    patch: i32,
    component: i32,
    kind: i32,
) -> meshmove_status {
    ffi_body!(meshmove_bcs_set_kind, {
        let mut b = get_mut(bcs, "bcs")?;
        let k = types::kind(kind)?;
        if !(0..=2).contains(&component) {
            return Err(CError::arg(format!("component {component} does not exist (0 = x, 1 = y, 2 = z)")));
        }
        b.set_kind(patch, component as usize, k)?;
        Ok(())
    })
}

/// Sets the same `meshmove_kind` for every component on `patch`.
///
/// # Safety
/// `bcs` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_bcs_set_kinds(bcs: *mut meshmove_bcs, patch: i32, kind: i32) -> meshmove_status {
    ffi_body!(meshmove_bcs_set_kinds, {
        let mut b = get_mut(bcs, "bcs")?;
        let k = types::kind(kind)?;
        b.set_kinds(patch, k);
        Ok(())
    })
}

/// Sets the kind of patches never named (every component; default FIXED).
///
/// # Safety
/// `bcs` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_bcs_set_default_kind(bcs: *mut meshmove_bcs, kind: i32) -> meshmove_status {
    ffi_body!(meshmove_bcs_set_default_kind, {
        let mut b = get_mut(bcs, "bcs")?;
        b.default_kind = [types::kind(kind)?; 3];
        Ok(())
    })
}

/// Links patch `patch_a` to `patch_b` periodically: every vertex v of `patch_a` is joined to the
/// vertex of `patch_b` at v + `offset`, within `tol` (positive). `offset` holds `dim` values, the
/// mesh's dimension (2 or 3). Both patches must be matched completely; this is checked when the
/// solver is created (`MESHMOVE_STATUS_INVALID_BCS`).
///
/// # Safety
/// `bcs` must be a handle from meshmove (checked); `offset` must hold `dim` doubles.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_bcs_link_periodic(
    bcs: *mut meshmove_bcs,
    patch_a: i32,
    patch_b: i32,
    dim: i32,
    offset: *const f64,
    tol: f64,
) -> meshmove_status {
    ffi_body!(meshmove_bcs_link_periodic, {
        let mut b = get_mut(bcs, "bcs")?;
        let dim = types::bounded(dim, "dim", 2, 3)?;
        // SAFETY: the caller guarantees `offset` holds `dim` doubles.
        let o = unsafe { slice(offset, dim, "offset") }?;
        if !o.iter().all(|v| v.is_finite()) {
            return Err(CError::arg(format!("offset {o:?} is not finite")));
        }
        if !(tol > 0.0 && tol.is_finite()) {
            return Err(CError::arg(format!("tol is {tol}; it must be positive and finite")));
        }
        if patch_a == patch_b {
            return Err(CError::arg(format!("a patch ({patch_a}) cannot be linked to itself")));
        }
        let offset = points::vector(o, "offset")?;
        b.add_link(Link::ByOffset { a: patch_a, b: patch_b, offset, tol });
        Ok(())
    })
}

/// Links explicit vertex pairs (1 ≤ `num_pairs` ≤ `MESHMOVE_MAX_VERTICES`): `pairs` holds
/// `2 num_pairs` vertex indices in `index_base`
/// (a0, b0, a1, b1, ...). Linked vertices become one unknown and must be told the same
/// displacement. Indices beyond the mesh are reported when the solver is created.
///
/// # Safety
/// `bcs` must be a handle from meshmove; `pairs` must hold `2 num_pairs` integers.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_bcs_link_pairs(
    bcs: *mut meshmove_bcs,
    num_pairs: i32,
    pairs: *const i32,
    index_base: i32,
) -> meshmove_status {
    ffi_body!(meshmove_bcs_link_pairs, {
        let mut b = get_mut(bcs, "bcs")?;
        let base = handles::index_base(index_base)?;
        let n = types::bounded(num_pairs, "num_pairs", 1, crate::limits::MAX_VERTICES)?;
        // SAFETY: the caller guarantees `pairs` holds `2 num_pairs` integers.
        let p = unsafe { slice(pairs, 2 * n, "pairs") }?;
        let mut out = Vec::with_capacity(n);
        for (i, c) in p.chunks_exact(2).enumerate() {
            let conv = |v: i32| {
                u32::try_from(i64::from(v) - i64::from(base)).map_err(|_| {
                    CError::arg(format!(
                        "pair {} has vertex index {v}, below the index base {base}",
                        i as i64 + i64::from(base)
                    ))
                })
            };
            let (a, z) = (conv(c[0])?, conv(c[1])?);
            if a == z {
                return Err(CError::arg(format!(
                    "pair {} links vertex {} to itself",
                    i as i64 + i64::from(base),
                    c[0]
                )));
            }
            out.push([a, z]);
        }
        b.add_link(Link::Pairs(out));
        Ok(())
    })
}

/// Declares how the internal interface `patch` (tagged interior edges) couples its two regions:
/// a `meshmove_interface` value.
///
/// # Safety
/// `bcs` must be a handle from meshmove (checked).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_bcs_set_interface(
    bcs: *mut meshmove_bcs,
    patch: i32,
    variant: i32,
) -> meshmove_status {
    ffi_body!(meshmove_bcs_set_interface, {
        let mut b = get_mut(bcs, "bcs")?;
        let v = types::interface(variant)?;
        b.set_interface(patch, v);
        Ok(())
    })
}

/// The closest point of a wall to a point: called with the caller's `user_data`, the dimension,
/// the point's `dim` coordinates, and `dim` doubles to write the closest point of the wall into.
/// It is called from the solver's worker threads (not the thread that made the call), one call
/// at a time, during `meshmove_solver_*` calls. It must return normally: a C++ exception,
/// `longjmp` or `pthread_exit` out of it aborts the process or leaves the solver busy for ever.
/// A callback that can fail uses `meshmove_closest_point_checked`.
pub type meshmove_closest_point =
    Option<unsafe extern "C" fn(user_data: *mut c_void, dim: i32, x: *const f64, closest: *mut f64)>;

/// As `meshmove_closest_point`, returning 0 on success and any other value on failure: the
/// meshmove call that asked then returns `MESHMOVE_STATUS_CALLBACK_FAILED` and changes nothing
/// (the way to stop from a callback: never throw or jump out of it).
pub type meshmove_closest_point_checked =
    Option<unsafe extern "C" fn(user_data: *mut c_void, dim: i32, x: *const f64, closest: *mut f64) -> i32>;

/// The caller's context pointer, handed back to its callback (the caller keeps it valid, and
/// safe to use from the solver's threads, for as long as a solver made with these conditions
/// lives).
pub(crate) struct UserData(pub(crate) *mut c_void);
// SAFETY: the pointer is only passed back to the caller's callback, which the caller makes safe
// to call from the solver's threads (documented on `meshmove_bcs_set_slip_surface`).
unsafe impl Send for UserData {}
// SAFETY: as above; the solver calls the callback one call at a time.
unsafe impl Sync for UserData {}

/// Gives the SLIP patch `patch` an analytic shape: after each solve its slipped vertices are moved
/// to `closest(user_data, dim, x, out)` instead of onto the patch's original faces (a circle, a
/// cylinder, a CAD surface), described where the wall is in the mesh a solver is made with: a
/// wall the motion moves rigidly carries the shape along (the callback is asked in the wall's
/// original frame). `closest` NULL removes the shape. The callback must be safe to call
/// from the solver's threads, and `user_data` valid while a solver made with these conditions
/// lives. A callback that writes a non-finite point leaves the vertex where the solve put it.
///
/// # Safety
/// `bcs` must be a handle from meshmove (checked); `closest` a function of the declared type.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_bcs_set_slip_surface(
    bcs: *mut meshmove_bcs,
    patch: i32,
    closest: meshmove_closest_point,
    user_data: *mut c_void,
) -> meshmove_status {
    ffi_body!(meshmove_bcs_set_slip_surface, {
        let surface = closest.map(|f| {
            let user = UserData(user_data);
            SlipSurface::new(move |x: &[f64]| {
                let user = &user;
                let mut out = [0.0f64; 3];
                // SAFETY: the caller guarantees the callback and its context (documented above);
                // x holds `dim` values and out has room for 3.
                unsafe { f(user.0, x.len() as i32, x.as_ptr(), out.as_mut_ptr()) };
                finite_or_same(out, x)
            })
        });
        set_surface(bcs, patch, surface)
    })
}

/// As `meshmove_bcs_set_slip_surface`, with a callback that returns 0 on success and any other
/// value on failure (`meshmove_closest_point_checked`): a failure makes the solver call that
/// asked return `MESHMOVE_STATUS_CALLBACK_FAILED` with the solver as before it.
///
/// # Safety
/// `bcs` must be a handle from meshmove (checked); `closest` a function of the declared type.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_bcs_set_slip_surface_checked(
    bcs: *mut meshmove_bcs,
    patch: i32,
    closest: meshmove_closest_point_checked,
    user_data: *mut c_void,
) -> meshmove_status {
    ffi_body!(meshmove_bcs_set_slip_surface_checked, {
        let surface = closest.map(|f| {
            let user = UserData(user_data);
            SlipSurface::fallible(move |x: &[f64]| {
                let user = &user;
                let mut out = [0.0f64; 3];
                // SAFETY: as in `meshmove_bcs_set_slip_surface`.
                let failed = unsafe { f(user.0, x.len() as i32, x.as_ptr(), out.as_mut_ptr()) } != 0;
                (!failed).then(|| finite_or_same(out, x))
            })
        });
        set_surface(bcs, patch, surface)
    })
}

/// The callback's point when finite, else `x` itself (the vertex stays where the solve put it).
fn finite_or_same(out: [f64; 3], x: &[f64]) -> [f64; 3] {
    if out[..x.len()].iter().all(|v| v.is_finite()) {
        out
    } else {
        let mut same = [0.0; 3];
        same[..x.len()].copy_from_slice(x);
        same
    }
}

/// Gives SLIP patch `patch` the analytic shape `surface`, or removes its shape (None).
fn set_surface(bcs: *mut meshmove_bcs, patch: i32, surface: Option<SlipSurface>) -> Result<(), CError> {
    let mut b = get_mut(bcs, "bcs")?;
    match surface {
        Some(s) => b.set_slip_surface(patch, s),
        None => b.remove_slip_surface(patch),
    };
    Ok(())
}
