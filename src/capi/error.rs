//! The thread-local last error, read into a caller's buffer (nothing to free, Fortran-friendly),
//! the guard every entry point runs under, and the version.

use super::status::meshmove_status;
use std::cell::RefCell;
use std::ffi::{c_char, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Major version of the library this header belongs to (compare with `meshmove_version`).
pub const MESHMOVE_VERSION_MAJOR: i32 = 0;
/// Minor version of the library this header belongs to.
pub const MESHMOVE_VERSION_MINOR: i32 = 2;
/// Patch version of the library this header belongs to.
pub const MESHMOVE_VERSION_PATCH: i32 = 0;

/// A failed call inside the C layer: the status and the message (without the function name).
#[derive(Debug)]
pub struct CError {
    pub status: meshmove_status,
    pub msg: String,
}

impl CError {
    pub(crate) fn new(status: meshmove_status, msg: impl Into<String>) -> Self {
        CError { status, msg: msg.into() }
    }
    pub(crate) fn arg(msg: impl Into<String>) -> Self {
        Self::new(meshmove_status::InvalidArgument, msg)
    }
    pub(crate) fn null(what: &str) -> Self {
        Self::new(meshmove_status::NullPointer, format!("`{what}` is NULL"))
    }
    pub(crate) fn unsupported(msg: impl Into<String>) -> Self {
        Self::new(meshmove_status::Unsupported, msg)
    }
}

impl From<crate::Error> for CError {
    fn from(e: crate::Error) -> Self {
        CError { status: meshmove_status::from(&e), msg: e.to_string() }
    }
}

impl From<crate::io::IoError> for CError {
    fn from(e: crate::io::IoError) -> Self {
        crate::Error::from(e).into()
    }
}

impl From<crate::MeshError> for CError {
    fn from(e: crate::MeshError) -> Self {
        crate::Error::from(e).into()
    }
}

thread_local! {
    static LAST: RefCell<CString> = RefCell::new(CString::default());
}

fn set_last(msg: String) {
    let c = CString::new(msg.replace('\0', " ")).unwrap_or_default();
    LAST.with(|l| *l.borrow_mut() = c);
}

/// Runs an entry point's body: `Ok` clears the last error, `Err` records "function: message",
/// a panic is caught and reported as `MESHMOVE_STATUS_PANIC`.
pub(crate) fn guard(name: &str, f: impl FnOnce() -> Result<(), CError>) -> meshmove_status {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => {
            set_last(String::new());
            meshmove_status::Ok
        }
        Ok(Err(e)) => {
            set_last(format!("{name}: {}", e.msg));
            e.status
        }
        Err(p) => {
            let what = p
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            set_last(format!("{name}: internal error (Rust panic): {what}"));
            meshmove_status::Panic
        }
    }
}

/// Copies the message of the last failed call on this thread into `buf` (`buf_len` bytes,
/// always NUL-terminated, truncated if needed). The message is empty after a successful call.
/// `needed` (may be NULL) receives the full length plus one. This call does not change the last
/// error. Returns `MESHMOVE_STATUS_BUFFER_TOO_SMALL` when the message was truncated,
/// `MESHMOVE_STATUS_NULL_POINTER` when `buf` is NULL and `buf_len` is not 0.
///
/// # Safety
/// `buf` must point to `buf_len` writable bytes; `needed` must be NULL or valid.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_last_error_message(
    buf: *mut c_char,
    buf_len: usize,
    needed: *mut usize,
) -> meshmove_status {
    let r = catch_unwind(|| {
        LAST.with(|l| {
            let l = l.borrow();
            let bytes = l.as_bytes();
            if !needed.is_null() {
                if super::handles::check_aligned(needed, "needed").is_err() {
                    return meshmove_status::InvalidArgument;
                }
                // SAFETY: `needed` is not NULL and aligned; the caller guarantees it is writable.
                unsafe { *needed = bytes.len() + 1 };
            }
            if buf_len == 0 {
                return if bytes.is_empty() { meshmove_status::Ok } else { meshmove_status::BufferTooSmall };
            }
            if buf.is_null() {
                return meshmove_status::NullPointer;
            }
            let mut n = bytes.len().min(buf_len - 1);
            // Do not cut a UTF-8 sequence in half.
            while n < bytes.len() && n > 0 && (bytes[n] & 0xC0) == 0x80 {
                n -= 1;
            }
            // SAFETY: the caller guarantees `buf_len` writable bytes at `buf`, and n + 1 <= buf_len;
            // `bytes` is this thread's message, which cannot overlap the caller's buffer.
            unsafe {
                std::ptr::copy_nonoverlapping(bytes.as_ptr(), buf as *mut u8, n);
                *buf.add(n) = 0;
            }
            if n < bytes.len() {
                meshmove_status::BufferTooSmall
            } else {
                meshmove_status::Ok
            }
        })
    });
    r.unwrap_or(meshmove_status::Panic)
}

/// The message of the last failed call on this thread ("" after a success), NUL-terminated.
/// The pointer stays valid until the next meshmove call on this thread; do not free it.
#[no_mangle]
pub extern "C" fn meshmove_last_error() -> *const c_char {
    LAST.with(|l| l.borrow().as_ptr())
}

/// The name of a status value, e.g. "MESHMOVE_STATUS_INVALID_MESH"; "MESHMOVE_STATUS_UNKNOWN"
/// for a value that is not a status. Static storage; do not free.
#[no_mangle]
pub extern "C" fn meshmove_status_name(status: i32) -> *const c_char {
    match meshmove_status::ALL.iter().find(|s| **s as i32 == status) {
        Some(s) => s.name().as_ptr(),
        None => c"MESHMOVE_STATUS_UNKNOWN".as_ptr(),
    }
}

/// The library's version (the Cargo package version). Any of the pointers may be NULL.
///
/// # Safety
/// Non-NULL pointers must be valid for writing one `int32_t`.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_version(major: *mut i32, minor: *mut i32, patch: *mut i32) -> meshmove_status {
    ffi_body!(meshmove_version, {
        let parse = |s: &str| s.parse::<i32>().unwrap_or(-1);
        for (p, v) in [
            (major, env!("CARGO_PKG_VERSION_MAJOR")),
            (minor, env!("CARGO_PKG_VERSION_MINOR")),
            (patch, env!("CARGO_PKG_VERSION_PATCH")),
        ] {
            if !p.is_null() {
                // SAFETY: the caller guarantees a non-NULL pointer is valid for one `int32_t`.
                unsafe { super::handles::write_out(p, parse(v), "version") }?;
            }
        }
        Ok(())
    })
}
