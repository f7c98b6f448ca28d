//! The one macro every exported function body goes through.
//!
//! hyper's `ffi_fn!` wraps the whole item; cbindgen does not expand macros on a stable
//! toolchain, so here the `#[no_mangle] pub unsafe extern "C" fn` stays visible to it and the
//! macro wraps the body: it runs the body under `catch_unwind`, turns `Err` and panics into a
//! status and records the message as the thread's last error (cleared on success).

/// `ffi_body!(name, { ...; Ok(()) })` evaluates the block (a `Result<(), CError>`) guarded and
/// returns the `meshmove_status`.
macro_rules! ffi_body {
    ($name:ident, $body:block) => {
        $crate::capi::error::guard(
            stringify!($name),
            move || -> ::std::result::Result<(), $crate::capi::error::CError> { $body },
        )
    };
}
