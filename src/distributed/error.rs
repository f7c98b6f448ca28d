//! What a distributed call returns when any rank fails: the same error on every rank, naming
//! the rank whose input is at fault.

use thiserror::Error;

/// What went wrong, in the order the agreement ranks them: when ranks fail differently, the
/// largest kind wins (then the lowest rank reporting it), so every rank returns the same error.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum DistErrorKind {
    /// A rank's arrays have wrong sizes or an index out of range.
    Input,
    /// A rank's own part fails the serial mesh checks (a non-finite coordinate, a tangled or
    /// degenerate cell, a face tagged twice, …).
    LocalMesh,
    /// The ranks disagree: a global id at different positions on two ranks, a global id twice
    /// on one rank, a vertex in no rank's owned cells, orientations that differ between ranks.
    Inconsistent,
    /// A rank owns a vertex but lacks a cell around it. The library completes each rank's ghost
    /// layer from the cells' owners, so a mesh it builds never lacks one.
    MissingGhostCell,
    /// A distributed solve did not reach its tolerance or broke down.
    Solve,
    /// The solved motion inverts cells (of the rank named, the one with the smallest ratio).
    Inverted,
    /// A mesh a step would start from has inverted cells: positions given as the reference, or
    /// a step's result that later steps would start from.
    Tangled,
    /// The progress callback (rank 0's) or a cancellation request stopped the call.
    Cancelled,
}

/// The error every rank returns from a failed collective call.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
#[error("rank {rank}: {message}")]
pub struct DistError {
    /// The rank whose input (or whose part of the solve) is at fault.
    pub rank: usize,
    /// What kind of failure.
    pub kind: DistErrorKind,
    /// What is wrong, naming the global ids involved.
    pub message: String,
}

impl DistError {
    /// An error blamed on `rank`.
    pub(crate) fn new(rank: usize, kind: DistErrorKind, message: impl Into<String>) -> DistError {
        DistError { rank, kind, message: message.into() }
    }
}

impl DistErrorKind {
    /// The code the agreement reduces (0 is success).
    pub(crate) fn code(self) -> i32 {
        self as i32 + 1
    }

    /// The kind of a code from `code`.
    pub(crate) fn from_code(code: i32) -> DistErrorKind {
        use DistErrorKind::*;
        [Input, LocalMesh, Inconsistent, MissingGhostCell, Solve, Inverted, Tangled, Cancelled]
            .into_iter()
            .find(|k| k.code() == code)
            .unwrap_or(Solve)
    }
}
