//! The C ABI (docs/DESIGN.md §6): four opaque handles (`meshmove_mesh`, `meshmove_bcs`,
//! `meshmove_options`, `meshmove_solver`), a status from every call, a thread-local last-error
//! message.
//!
//! This module only checks arguments, converts them, calls the Rust API and maps errors; the
//! mathematics stays in the other modules. `include/meshmove.h` is generated from it by cbindgen
//! (`tests/header_fresh.rs` fails when the committed header is stale; `MESHMOVE_BLESS=1 cargo
//! test --test header_fresh` rewrites it) and `include/meshmove.f90` binds it for Fortran.
//!
//! Rules every entry point follows: the body runs inside `ffi_body!` (catch_unwind → status,
//! last error set); every handle is checked against the registry of slots ever handed out and
//! acquired through its atomic state word (`handles.rs`: BUSY instead of a race, freed slots kept
//! as tombstones so a stale handle is always refused); every array pointer is checked for NULL
//! and alignment and comes with an explicit `int32_t` length that must match (coordinates and
//! displacements: `dim × vertices`, `dim` the mesh's); every count and
//! option is checked against its bound (`MESHMOVE_MAX_*`) before anything is allocated; enum
//! arguments are `int32_t` values checked before conversion (a Rust enum receiving an unknown
//! discriminant would be undefined behaviour); outputs are written only after every check passed
//! and only when finite, and a failing call puts back anything it changed; every function that
//! returns a status is `#[must_use]` (the header marks it `warn_unused_result`).
//!
//! Points and displacements meet the Rust types in one file, `points.rs`; every other file
//! works with flat `dim × n` arrays and `points::Points`.
#![allow(non_camel_case_types)]
#![allow(clippy::missing_safety_doc)]
#![deny(unsafe_op_in_unsafe_fn)]
#![deny(clippy::undocumented_unsafe_blocks)]

#[macro_use]
mod macros;
pub mod bcs;
pub mod error;
mod fork;
pub(crate) mod handles;
pub mod mesh;
pub mod options;
pub(crate) mod points;
pub mod polyhedra;
pub mod solver;
pub mod status;
pub mod types;

pub use bcs::*;
pub use error::*;
pub use mesh::*;
pub use options::*;
pub use polyhedra::*;
pub use solver::*;
pub use status::*;
pub use types::*;
