//! Memory a call will need, checked before the work: an estimate from the mesh's size, compared
//! with the caller's budget and reserved once from the system (then released), so that a
//! process with a memory cap (`ulimit -v`, a batch system's limit) gets `Error::OutOfMemory`
//! instead of an abort in the middle of a build. Rust aborts when an ordinary allocation fails;
//! reserving the whole estimate up front with `try_reserve` is the one check that can fail
//! gracefully. The estimate is deliberately generous: the largest of the allocations that follow
//! must not be the first to fail.

use crate::{Error, Mesh, Method, Result};

/// Bytes of a built solver for `mesh` (the multigrid hierarchy and a solve's vectors): every
/// cell couples each pair of its corners in the fine operators (stored in compressed rows: an
/// `f64` and a `u32` per entry, K and for the biharmonic V besides), the coarse levels together
/// add at most as much again, and a solve keeps some tens of vectors of the unknowns.
pub(crate) fn solver_bytes(mesh: &Mesh, method: Method) -> u64 {
    let pairs: u64 = (0..mesh.num_cells()).map(|c| (mesh.cell(c).len() as u64).pow(2)).sum();
    let matrices: u64 = if method == Method::Biharmonic { 3 } else { 2 };
    let unknowns = mesh.num_vertices() as u64 * mesh.dim() as u64;
    let fine = pairs * 12 * matrices + unknowns * 8 * 40;
    fine.saturating_mul(2)
}

/// Bytes a mesh of these sizes needs once built (its arrays, the copies made while checking
/// them, and its topology: faces of every cell sorted, patch faces, vertex neighbours).
pub(crate) fn mesh_bytes(dim: usize, vertices: usize, cells: usize, cell_vertices: usize, faces: usize) -> u64 {
    let input = vertices as u64 * dim as u64 * 8 + cell_vertices as u64 * 4 + cells as u64 * 9 + faces as u64 * 16;
    input.saturating_mul(6)
}

/// Fails with `Error::OutOfMemory` when `bytes` exceed the `budget` (0: none) or cannot be
/// reserved from the system now; `what` names the work in the message.
pub(crate) fn check_available(bytes: u64, budget: u64, what: &str) -> Result<()> {
    if budget > 0 && bytes > budget {
        return Err(Error::OutOfMemory(format!(
            "{what} needs about {bytes} bytes (an estimate), more than the memory budget of {budget} bytes"
        )));
    }
    let mut probe: Vec<u8> = Vec::new();
    let reserved = usize::try_from(bytes).ok().is_some_and(|n| probe.try_reserve_exact(n).is_ok());
    if !reserved {
        return Err(Error::OutOfMemory(format!(
            "{what} needs about {bytes} bytes (an estimate), which the system refused to reserve"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_budget_below_the_estimate_or_an_impossible_size_is_refused() {
        assert!(check_available(1 << 20, 0, "x").is_ok());
        assert!(check_available(1 << 20, 2 << 20, "x").is_ok());
        let e = check_available(3 << 20, 2 << 20, "the solver").unwrap_err();
        assert!(matches!(e, Error::OutOfMemory(_)) && e.to_string().contains("memory budget of 2097152"), "{e}");
        let e = check_available(u64::MAX / 2, 0, "the solver").unwrap_err();
        assert!(e.to_string().contains("refused to reserve"), "{e}");
    }
}
