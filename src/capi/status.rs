//! The status every C function returns, derived from [`crate::Error`] (gifski's pattern: one
//! `From`, never a second hand-written mapping).

use crate::io::IoError;
use crate::Error;

/// What a meshmove call returned. The values are fixed and never renumbered; new codes are only
/// appended. `meshmove_last_error_message` gives the text of the last failure on this thread.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum meshmove_status {
    /// Success.
    Ok = 0,
    /// A required pointer argument was NULL.
    NullPointer = 1,
    /// A handle was not a live handle of the expected type (freed, never created, or another type).
    InvalidHandle = 2,
    /// An argument was out of range: a count, an index, a length, an enum value, a non-finite number.
    InvalidArgument = 3,
    /// The mesh is invalid (degenerate or repeated cells, bad indices, non-finite coordinates, ...).
    InvalidMesh = 4,
    /// The boundary conditions do not fit the mesh (unknown patch, mismatched link, ...).
    InvalidBcs = 5,
    /// A displacement component has no prescribed vertex: the problem has no unique solution.
    IllPosed = 6,
    /// The multigrid hierarchy could not be built.
    Coarsening = 7,
    /// The iteration diverged.
    Diverged = 8,
    /// A file could not be read or written, or is malformed.
    Io = 9,
    /// An output buffer was too small; the required size was reported.
    BufferTooSmall = 10,
    /// An internal error (a Rust panic) was caught; the handle involved may be inconsistent.
    Panic = 11,
    /// A solve did not reach its tolerance within `max_cycles`. `meshmove_solver_solve` still
    /// writes the unconverged displacement (the caller decides whether to use it; the report says
    /// how far it got); `_move` and `_move_in_steps` leave the coordinates and the solver as
    /// before the call.
    NotConverged = 12,
    /// The reference mesh of a step has cells of non-positive area (the message names the first).
    Tangled = 13,
    /// The solve converged but the moved mesh has inverted cells: the result IS written and the
    /// quality output gives the count. Never reported as plain OK.
    Inverted = 14,
    /// The handle is in use by a call on another thread; nothing was done (try again later, or
    /// give each thread its own handle).
    Busy = 15,
    /// The arguments are valid but this version of meshmove cannot do it (kept for what later
    /// versions add); the message says what.
    Unsupported = 16,
    /// The progress callback asked to stop (`meshmove_solver_set_progress`): the call was
    /// cancelled and the solver is as before it.
    Cancelled = 17,
    /// A callback of the caller returned failure (a slip surface's projection returning non-zero):
    /// the call stopped and the solver is as before it.
    CallbackFailed = 18,
    /// Memory could not be obtained (the system refused an allocation, or the options' memory
    /// budget is below the solver's estimate): nothing was created or changed.
    OutOfMemory = 19,
}

impl From<&Error> for meshmove_status {
    fn from(e: &Error) -> Self {
        match e {
            Error::Mesh(crate::MeshError::OutOfMemory { .. }) => meshmove_status::OutOfMemory,
            Error::Mesh(_) => meshmove_status::InvalidMesh,
            Error::Bc(_) => meshmove_status::InvalidBcs,
            Error::IllPosed { .. } => meshmove_status::IllPosed,
            Error::InvalidArgument(_) => meshmove_status::InvalidArgument,
            Error::Coarsening(_) => meshmove_status::Coarsening,
            Error::Diverged(_) => meshmove_status::Diverged,
            Error::NotConverged(_) => meshmove_status::NotConverged,
            Error::Tangled(_) => meshmove_status::Tangled,
            Error::Cancelled(_) => meshmove_status::Cancelled,
            Error::CallbackFailed(_) => meshmove_status::CallbackFailed,
            Error::OutOfMemory(_) => meshmove_status::OutOfMemory,
            Error::Io(IoError::Mesh(_)) => meshmove_status::InvalidMesh,
            Error::Io(IoError::InvalidArgument(_)) => meshmove_status::InvalidArgument,
            Error::Io(_) => meshmove_status::Io,
        }
    }
}

impl meshmove_status {
    pub(crate) fn name(self) -> &'static std::ffi::CStr {
        match self {
            meshmove_status::Ok => c"MESHMOVE_STATUS_OK",
            meshmove_status::NullPointer => c"MESHMOVE_STATUS_NULL_POINTER",
            meshmove_status::InvalidHandle => c"MESHMOVE_STATUS_INVALID_HANDLE",
            meshmove_status::InvalidArgument => c"MESHMOVE_STATUS_INVALID_ARGUMENT",
            meshmove_status::InvalidMesh => c"MESHMOVE_STATUS_INVALID_MESH",
            meshmove_status::InvalidBcs => c"MESHMOVE_STATUS_INVALID_BCS",
            meshmove_status::IllPosed => c"MESHMOVE_STATUS_ILL_POSED",
            meshmove_status::Coarsening => c"MESHMOVE_STATUS_COARSENING",
            meshmove_status::Diverged => c"MESHMOVE_STATUS_DIVERGED",
            meshmove_status::Io => c"MESHMOVE_STATUS_IO",
            meshmove_status::BufferTooSmall => c"MESHMOVE_STATUS_BUFFER_TOO_SMALL",
            meshmove_status::Panic => c"MESHMOVE_STATUS_PANIC",
            meshmove_status::NotConverged => c"MESHMOVE_STATUS_NOT_CONVERGED",
            meshmove_status::Tangled => c"MESHMOVE_STATUS_TANGLED",
            meshmove_status::Inverted => c"MESHMOVE_STATUS_INVERTED",
            meshmove_status::Busy => c"MESHMOVE_STATUS_BUSY",
            meshmove_status::Unsupported => c"MESHMOVE_STATUS_UNSUPPORTED",
            meshmove_status::Cancelled => c"MESHMOVE_STATUS_CANCELLED",
            meshmove_status::CallbackFailed => c"MESHMOVE_STATUS_CALLBACK_FAILED",
            meshmove_status::OutOfMemory => c"MESHMOVE_STATUS_OUT_OF_MEMORY",
        }
    }

    pub(crate) const ALL: [meshmove_status; 20] = [
        meshmove_status::Ok,
        meshmove_status::NullPointer,
        meshmove_status::InvalidHandle,
        meshmove_status::InvalidArgument,
        meshmove_status::InvalidMesh,
        meshmove_status::InvalidBcs,
        meshmove_status::IllPosed,
        meshmove_status::Coarsening,
        meshmove_status::Diverged,
        meshmove_status::Io,
        meshmove_status::BufferTooSmall,
        meshmove_status::Panic,
        meshmove_status::NotConverged,
        meshmove_status::Tangled,
        meshmove_status::Inverted,
        meshmove_status::Busy,
        meshmove_status::Unsupported,
        meshmove_status::Cancelled,
        meshmove_status::CallbackFailed,
        meshmove_status::OutOfMemory,
    ];
}
