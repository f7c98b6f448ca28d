//! Handles (libimagequant's magic tag, plus a registry of live handles so that a stale or
//! foreign pointer is rejected before it is dereferenced) and argument checks.

use super::error::CError;
use super::status::meshmove_status;
use glam::DVec2;
use std::collections::HashMap;
use std::ffi::{c_char, CStr};
use std::sync::Mutex;

/// A type handed to C as an opaque pointer. Its first field is the magic tag.
pub(crate) trait Handle: 'static {
    const MAGIC: u64;
    const NAME: &'static str;
    fn tag(&self) -> u64;
    fn set_tag(&mut self, t: u64);
}

/// Written over the tag on free.
const DEAD: u64 = 0xDEAD_DEAD_DEAD_DEAD;

/// Address of every live handle and the magic of its type.
static LIVE: Mutex<Option<HashMap<usize, (u64, &'static str)>>> = Mutex::new(None);

fn live<R>(f: impl FnOnce(&mut HashMap<usize, (u64, &'static str)>) -> R) -> R {
    let mut g = LIVE.lock().unwrap_or_else(|p| p.into_inner());
    f(g.get_or_insert_with(HashMap::new))
}

/// Boxes `value`, registers it and stores it in `*out`.
pub(crate) unsafe fn hand_out<T: Handle>(value: T, out: *mut *mut T) -> Result<(), CError> {
    let p = Box::into_raw(Box::new(value));
    live(|m| m.insert(p as usize, (T::MAGIC, T::NAME)));
    *out = p;
    Ok(())
}

/// Checks `out` before any work: not NULL, aligned; `*out` is set to NULL.
pub(crate) unsafe fn check_out<T>(out: *mut *mut T, what: &str) -> Result<(), CError> {
    if out.is_null() {
        return Err(CError::null(what));
    }
    check_aligned(out, what)?;
    *out = std::ptr::null_mut();
    Ok(())
}

fn check_live<T: Handle>(p: *const T, what: &str) -> Result<(), CError> {
    if p.is_null() {
        return Err(CError::null(what));
    }
    let found = live(|m| m.get(&(p as usize)).copied());
    match found {
        Some((magic, _)) if magic == T::MAGIC => {}
        Some((_, name)) => {
            return Err(CError::new(
                meshmove_status::InvalidHandle,
                format!("`{what}` is a {name} handle, not a {}", T::NAME),
            ))
        }
        None => {
            return Err(CError::new(
                meshmove_status::InvalidHandle,
                format!("`{what}` is not a live {} handle (already freed, or not made by meshmove)", T::NAME),
            ))
        }
    }
    // Registered: safe to read the tag.
    let tag = unsafe { (*p).tag() };
    if tag != T::MAGIC {
        return Err(CError::new(meshmove_status::InvalidHandle, format!("`{what}`: {} handle is corrupted", T::NAME)));
    }
    Ok(())
}

pub(crate) unsafe fn get<'a, T: Handle>(p: *const T, what: &str) -> Result<&'a T, CError> {
    check_live(p, what)?;
    Ok(&*p)
}

pub(crate) unsafe fn get_mut<'a, T: Handle>(p: *mut T, what: &str) -> Result<&'a mut T, CError> {
    check_live(p, what)?;
    Ok(&mut *p)
}

/// Frees a handle; NULL is fine, a stale or foreign handle is an error (nothing is freed).
pub(crate) unsafe fn free<T: Handle>(p: *mut T, what: &str) -> Result<(), CError> {
    if p.is_null() {
        return Ok(());
    }
    check_live(p, what)?;
    live(|m| m.remove(&(p as usize)));
    (*p).set_tag(DEAD);
    drop(Box::from_raw(p));
    Ok(())
}

pub(crate) fn check_aligned<T>(p: *const T, what: &str) -> Result<(), CError> {
    if (p as usize) % std::mem::align_of::<T>() != 0 {
        return Err(CError::arg(format!("`{what}` is not aligned for its type")));
    }
    Ok(())
}

/// A count argument: not negative.
pub(crate) fn count(n: i32, what: &str) -> Result<usize, CError> {
    usize::try_from(n).map_err(|_| CError::arg(format!("`{what}` is {n}; it must not be negative")))
}

/// `len` elements at `p`; NULL is allowed only when `len` is 0.
pub(crate) unsafe fn slice<'a, T>(p: *const T, len: usize, what: &str) -> Result<&'a [T], CError> {
    if len == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(CError::null(what));
    }
    check_aligned(p, what)?;
    Ok(std::slice::from_raw_parts(p, len))
}

pub(crate) unsafe fn slice_mut<'a, T>(p: *mut T, len: usize, what: &str) -> Result<&'a mut [T], CError> {
    if len == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(CError::null(what));
    }
    check_aligned(p, what)?;
    Ok(std::slice::from_raw_parts_mut(p, len))
}

/// An interleaved (x0, y0, x1, y1, ...) array of exactly `2 nv` doubles, copied out.
pub(crate) unsafe fn read_xy(p: *const f64, len: i32, nv: usize, what: &str) -> Result<Vec<DVec2>, CError> {
    let n = count(len, &format!("{what} length"))?;
    if n != 2 * nv {
        return Err(CError::arg(format!(
            "`{what}` has length {n}; the mesh has {nv} vertices, so 2 × {nv} = {} values are needed",
            2 * nv
        )));
    }
    let s = slice(p, n, what)?;
    Ok(s.chunks_exact(2).map(|c| DVec2::new(c[0], c[1])).collect())
}

/// Checks an output array of exactly `2 nv` doubles (before any work is done).
pub(crate) unsafe fn check_xy_out(p: *mut f64, len: i32, nv: usize, what: &str) -> Result<(), CError> {
    let n = count(len, &format!("{what} length"))?;
    if n != 2 * nv {
        return Err(CError::arg(format!(
            "`{what}` has length {n}; the mesh has {nv} vertices, so 2 × {nv} = {} values are needed",
            2 * nv
        )));
    }
    slice_mut(p, n, what)?;
    Ok(())
}

/// Writes `v` interleaved into `p` (checked by `check_xy_out`).
pub(crate) unsafe fn write_xy(p: *mut f64, v: &[DVec2]) {
    let out = std::slice::from_raw_parts_mut(p, 2 * v.len());
    for (o, d) in out.chunks_exact_mut(2).zip(v) {
        o[0] = d.x;
        o[1] = d.y;
    }
}

pub(crate) fn finite_xy(v: &[DVec2], what: &str) -> Result<(), CError> {
    match v.iter().position(|p| !p.is_finite()) {
        Some(i) => Err(CError::arg(format!("`{what}` of vertex {i} (0-based) is not finite ({}, {})", v[i].x, v[i].y))),
        None => Ok(()),
    }
}

pub(crate) unsafe fn path<'a>(p: *const c_char, what: &str) -> Result<&'a str, CError> {
    if p.is_null() {
        return Err(CError::null(what));
    }
    CStr::from_ptr(p).to_str().map_err(|_| CError::arg(format!("`{what}` is not valid UTF-8")))
}

pub(crate) fn index_base(b: i32) -> Result<crate::IndexBase, CError> {
    match b {
        0 => Ok(crate::IndexBase::Zero),
        1 => Ok(crate::IndexBase::One),
        _ => Err(CError::arg(format!("index base is {b}; it must be 0 (C) or 1 (Fortran)"))),
    }
}

pub(crate) unsafe fn write_out<T>(p: *mut T, v: T, what: &str) -> Result<(), CError> {
    if p.is_null() {
        return Err(CError::null(what));
    }
    check_aligned(p, what)?;
    p.write(v);
    Ok(())
}
