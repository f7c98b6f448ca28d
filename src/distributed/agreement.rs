//! Collective failure: every rank joins the agreement whether or not it found an error, so a
//! rank with bad input never leaves the others waiting in a collective. The status is reduced
//! (the largest error kind, then the lowest rank reporting it), that rank's error is broadcast,
//! and every rank returns it.

use super::comm::Comm;
use super::error::{DistError, DistErrorKind};
use super::reduce::gather;
use mpi::traits::*;

/// Agrees on the outcome of one phase of a collective call: `Ok` on every rank when every rank
/// succeeded, else the same error on every rank.
pub(crate) fn agree<T>(comm: &Comm, local: Result<T, DistError>) -> Result<T, DistError> {
    let (code, blamed) = match &local {
        Ok(_) => (0i32, 0i64),
        Err(e) => (e.kind.code(), e.rank as i64),
    };
    let all = gather(comm, &[code as i64, blamed]);
    let worst = all.chunks_exact(2).map(|s| s[0]).max().unwrap_or(0);
    if worst == 0 {
        return local;
    }
    // The lowest rank reporting the worst kind speaks for all.
    let speaker = all.chunks_exact(2).position(|s| s[0] == worst).unwrap_or(0);
    let rank = usize::try_from(all[2 * speaker + 1]).unwrap_or(0);
    let mine = match &local {
        Err(e) if comm.rank() == speaker => e.message.clone().into_bytes(),
        _ => Vec::new(),
    };
    let message = broadcast_bytes(comm, speaker, mine);
    let kind = DistErrorKind::from_code(worst as i32);
    Err(DistError::new(rank, kind, String::from_utf8_lossy(&message).into_owned()))
}

/// `bytes` of rank `root`, on every rank (length first, then the bytes).
fn broadcast_bytes(comm: &Comm, root: usize, bytes: Vec<u8>) -> Vec<u8> {
    let root = comm.mpi().process_at_rank(root as i32);
    let mut len = bytes.len() as u64;
    root.broadcast_into(&mut len);
    let mut buf = bytes;
    buf.resize(usize::try_from(len).unwrap_or(0), 0);
    root.broadcast_into(&mut buf[..]);
    buf
}
