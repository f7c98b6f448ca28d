//! The one place where the C layer meets the Rust types of points, displacements and vectors.
//!
//! Coordinates and displacements cross the ABI as flat `dim × n` interleaved arrays (x0, y0,
//! (z0,) x1, ...), `dim` being the mesh's. The Rust API holds them as `Vec<DVec2>` today (the
//! core is 2D); when it becomes dimension-generic only this file changes: [`Points`],
//! [`dim_of`], the conversions between flat arrays and points, and the rigid-motion and offset
//! conversions. Nothing else in `src/capi` names a glam type or assumes a dimension.

use super::error::CError;
use super::handles::{count, slice, slice_mut};
use super::status::meshmove_status;
use crate::{Mesh, RigidMotion};
use glam::DVec2;

/// The points (or displacements) of a mesh's vertices, as the Rust API takes them.
pub(crate) type Points = Vec<DVec2>;

/// The dimension of a mesh's points. The Rust `Mesh` is 2D today; becomes `mesh.dim()`.
pub(crate) fn dim_of(_mesh: &Mesh) -> usize {
    2
}

/// `nv` zero displacements.
pub(crate) fn zeros(nv: usize) -> Points {
    vec![DVec2::ZERO; nv]
}

/// `a − b`, point by point (the total displacement between two positions of a mesh).
pub(crate) fn difference(a: &[DVec2], b: &[DVec2]) -> Points {
    a.iter().zip(b).map(|(a, b)| *a - *b).collect()
}

/// The error for a dimension the Rust types cannot hold yet.
fn not_in(dim: usize, what: &str) -> CError {
    CError::unsupported(format!("{what} in {dim}D: this version of meshmove handles 2D only"))
}

/// Checks a flat array length: exactly `dim × nv` values.
fn flat_len(len: i32, dim: usize, nv: usize, what: &str) -> Result<usize, CError> {
    let n = count(len, &format!("{what} length"))?;
    if n != dim * nv {
        return Err(CError::arg(format!(
            "`{what}` has length {n}; the mesh has {nv} vertices in {dim}D, so {dim} × {nv} = {} values are needed",
            dim * nv
        )));
    }
    Ok(n)
}

/// Reads a flat `dim × nv` array (`len` must be exactly that) into points, copied.
///
/// # Safety
/// A non-NULL `p` must point to `len` doubles.
pub(crate) unsafe fn read(p: *const f64, len: i32, dim: usize, nv: usize, what: &str) -> Result<Points, CError> {
    let n = flat_len(len, dim, nv, what)?;
    // SAFETY: `p` holds `len` = `n` doubles (this function's contract).
    let flat = unsafe { slice(p, n, what) }?;
    match dim {
        2 => Ok(flat.chunks_exact(2).map(|c| DVec2::new(c[0], c[1])).collect()),
        _ => Err(not_in(dim, what)),
    }
}

/// Checks an output array of exactly `dim × nv` doubles, before any work is done.
///
/// # Safety
/// A non-NULL `p` must point to `len` writable doubles.
pub(crate) unsafe fn check_out(p: *mut f64, len: i32, dim: usize, nv: usize, what: &str) -> Result<(), CError> {
    let n = flat_len(len, dim, nv, what)?;
    // SAFETY: `p` holds `len` = `n` writable doubles (this function's contract).
    unsafe { slice_mut(p, n, what) }?;
    Ok(())
}

/// Writes `v` flat (interleaved) into `p`.
///
/// # Safety
/// `p` must have passed [`check_out`] for `v.len()` vertices of `v`'s dimension.
pub(crate) unsafe fn write(p: *mut f64, v: &[DVec2]) {
    // SAFETY: `check_out` found `p` not NULL, aligned and of `2 × v.len()` doubles (contract).
    let out = unsafe { std::slice::from_raw_parts_mut(p, 2 * v.len()) };
    for (o, d) in out.chunks_exact_mut(2).zip(v) {
        o.copy_from_slice(&d.to_array());
    }
}

/// The first point with a non-finite component: its index and its components as text.
fn first_non_finite(v: &[DVec2]) -> Option<(usize, String)> {
    let i = v.iter().position(|p| !p.is_finite())?;
    let parts: Vec<String> = v[i].to_array().iter().map(f64::to_string).collect();
    Some((i, parts.join(", ")))
}

/// An input must be finite (`MESHMOVE_STATUS_INVALID_ARGUMENT` otherwise).
pub(crate) fn finite_in(v: &[DVec2], what: &str) -> Result<(), CError> {
    match first_non_finite(v) {
        Some((i, p)) => Err(CError::arg(format!("`{what}` of vertex {i} (0-based) is not finite ({p})"))),
        None => Ok(()),
    }
}

/// Every output must be finite or the call fails (`MESHMOVE_STATUS_DIVERGED`) and writes nothing.
pub(crate) fn finite_out(v: &[DVec2], what: &str) -> Result<(), CError> {
    match first_non_finite(v) {
        Some((i, p)) => Err(CError::new(
            meshmove_status::Diverged,
            format!("the {what} of vertex {i} (0-based) is not finite ({p}); nothing was written"),
        )),
        None => Ok(()),
    }
}

/// Number of rotation values of a rigid motion in `dim` dimensions: the angle in 2D, the
/// rotation vector (axis × angle) in 3D.
pub(crate) fn rotation_len(dim: usize) -> usize {
    if dim == 2 {
        1
    } else {
        3
    }
}

/// A rigid motion from its C arrays: `translation` and `center` of `dim` values, `rotation` of
/// [`rotation_len`] values (all checked finite by the caller).
pub(crate) fn rigid_motion(
    dim: usize,
    translation: &[f64],
    rotation: &[f64],
    center: &[f64],
) -> Result<RigidMotion, CError> {
    match dim {
        2 => Ok(RigidMotion {
            translation: DVec2::new(translation[0], translation[1]),
            angle: rotation[0],
            center: DVec2::new(center[0], center[1]),
        }),
        _ => Err(not_in(dim, "a rigid motion")),
    }
}

/// A vector of 2 or 3 components (a periodic link's offset).
pub(crate) fn vector(v: &[f64], what: &str) -> Result<DVec2, CError> {
    match v.len() {
        2 => Ok(DVec2::new(v[0], v[1])),
        3 => Err(not_in(3, what)),
        n => Err(CError::arg(format!("`{what}` has {n} components; it must have 2 (2D) or 3 (3D)"))),
    }
}
