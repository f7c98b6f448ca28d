//! The one place where the C layer meets the Rust types of points, displacements and vectors.
//!
//! Coordinates and displacements cross the ABI as flat `dim × n` interleaved arrays (x0, y0,
//! (z0,) x1, ...), `dim` being the mesh's, the same layout the Rust API holds them in; rigid
//! motions and offsets as `dim`-vectors (the rotation as an angle in 2D, a rotation vector in
//! 3D). Nothing else in `src/capi` converts points or assumes a dimension.

use super::error::CError;
use super::handles::{count, slice, slice_mut};
use super::status::meshmove_status;
use crate::geometry::rotation;
use crate::{Mesh, RigidMotion};

/// The points (or displacements) of a mesh's vertices, as the Rust API takes them: `dim`
/// values per vertex, interleaved.
pub(crate) type Points = Vec<f64>;

/// The dimension of a mesh's points.
pub(crate) fn dim_of(mesh: &Mesh) -> usize {
    mesh.dim()
}

/// Zero displacements of `nv` vertices in `dim` dimensions.
pub(crate) fn zeros(dim: usize, nv: usize) -> Points {
    vec![0.0; dim * nv]
}

/// `a − b`, value by value (the total displacement between two positions of a mesh).
pub(crate) fn difference(a: &[f64], b: &[f64]) -> Points {
    a.iter().zip(b).map(|(a, b)| a - b).collect()
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
    Ok(flat.to_vec())
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

/// Writes `v` (already interleaved) into `p`.
///
/// # Safety
/// `p` must have passed [`check_out`] for `v.len()` values.
pub(crate) unsafe fn write(p: *mut f64, v: &[f64]) {
    // SAFETY: `check_out` found `p` not NULL, aligned and of `v.len()` doubles (contract).
    let out = unsafe { std::slice::from_raw_parts_mut(p, v.len()) };
    out.copy_from_slice(v);
}

/// The first vertex with a non-finite component (`dim` values per vertex): its index and its
/// components as text.
fn first_non_finite(v: &[f64], dim: usize) -> Option<(usize, String)> {
    let i = v.iter().position(|p| !p.is_finite())? / dim;
    let parts: Vec<String> = v[i * dim..(i + 1) * dim].iter().map(f64::to_string).collect();
    Some((i, parts.join(", ")))
}

/// An input of `dim` values per vertex must be finite (`MESHMOVE_STATUS_INVALID_ARGUMENT`
/// otherwise).
pub(crate) fn finite_in(v: &[f64], dim: usize, what: &str) -> Result<(), CError> {
    match first_non_finite(v, dim) {
        Some((i, p)) => Err(CError::arg(format!("`{what}` of vertex {i} (0-based) is not finite ({p})"))),
        None => Ok(()),
    }
}

/// Every output must be finite or the call fails (`MESHMOVE_STATUS_DIVERGED`) and writes nothing.
pub(crate) fn finite_out(v: &[f64], dim: usize, what: &str) -> Result<(), CError> {
    match first_non_finite(v, dim) {
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
    rotation::value_count(dim)
}

/// A rigid motion from its C arrays: `translation` and `center` of `dim` values, `rotation` of
/// [`rotation_len`] values (all checked finite by the caller).
fn rigid_motion(dim: usize, translation: &[f64], rotation: &[f64], center: &[f64]) -> Result<RigidMotion, CError> {
    let mut m = RigidMotion { translation: [0.0; 3], rotation: [0.0; 3], center: [0.0; 3] };
    m.translation[..dim].copy_from_slice(&translation[..dim]);
    m.center[..dim].copy_from_slice(&center[..dim]);
    m.rotation = rotation::from_values(rotation, dim);
    Ok(m)
}

/// The rigid motion of `patch` from the caller's arrays: `translation` and `center` of `dim`
/// values, `rotation` of [`rotation_len`] values, all finite.
///
/// # Safety
/// Each non-NULL array must hold the values stated.
pub(crate) unsafe fn read_rigid_motion(
    dim: usize,
    patch: i32,
    translation: *const f64,
    rotation: *const f64,
    center: *const f64,
) -> Result<RigidMotion, CError> {
    // SAFETY: this function's contract.
    let (t, r, c) = unsafe {
        (
            slice(translation, dim, "translation")?,
            slice(rotation, rotation_len(dim), "rotation")?,
            slice(center, dim, "center")?,
        )
    };
    if !t.iter().chain(r).chain(c).all(|v| v.is_finite()) {
        return Err(CError::arg(format!(
            "rigid motion of patch {patch} is not finite (translation {t:?}, rotation {r:?}, center {c:?})"
        )));
    }
    rigid_motion(dim, t, r, c)
}

/// A vector of 2 or 3 components (a periodic link's offset), z = 0 for a 2D one.
pub(crate) fn vector(v: &[f64], what: &str) -> Result<[f64; 3], CError> {
    match v.len() {
        2 => Ok([v[0], v[1], 0.0]),
        3 => Ok([v[0], v[1], v[2]]),
        n => Err(CError::arg(format!("`{what}` has {n} components; it must have 2 (2D) or 3 (3D)"))),
    }
}
