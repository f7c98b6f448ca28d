//! The library's own communicator: a duplicate of the host's, made once when a distributed mesh
//! is made and freed when the last thing holding it is dropped, so the library's messages never
//! match the host's (as PETSc duplicates the communicator it is given).

use mpi::topology::{Color, Communicator, SimpleCommunicator};

/// A duplicate (`MPI_Comm_dup`) of the host's communicator; freed (`MPI_Comm_free`) on drop.
/// Collective to make and to drop: every rank makes and drops its copy together.
pub struct Comm {
    comm: SimpleCommunicator,
    rank: usize,
    size: usize,
}

// SAFETY: the handle is an opaque MPI handle that is only ever used from the thread that called
// the library (the solve's own thread); the worker threads of the solver's pool never touch it.
// A host that initialised MPI with MPI_THREAD_FUNNELED or higher and calls from one thread at a
// time meets MPI's requirement.
unsafe impl Send for Comm {}
// SAFETY: as for Send: shared references reach MPI only from the calling thread.
unsafe impl Sync for Comm {}

impl Comm {
    /// Duplicates `host` (collective over `host`).
    pub fn duplicate<C: Communicator>(host: &C) -> Comm {
        let comm = host.duplicate();
        let rank = usize::try_from(comm.rank()).unwrap_or(0);
        let size = usize::try_from(comm.size()).unwrap_or(1);
        Comm { comm, rank, size }
    }

    /// The first `active` ranks of this communicator as one of their own (`MPI_Comm_split`, each
    /// keeping its rank; collective over this one), freed when dropped; None on the other ranks.
    pub(crate) fn split_first(&self, active: usize) -> Option<Comm> {
        let color = if self.rank < active { Color::with_value(0) } else { Color::undefined() };
        let key = i32::try_from(self.rank).unwrap_or(i32::MAX);
        let comm = self.comm.split_by_color_with_key(color, key)?;
        let rank = usize::try_from(comm.rank()).unwrap_or(0);
        let size = usize::try_from(comm.size()).unwrap_or(1);
        Some(Comm { comm, rank, size })
    }

    /// This process's rank.
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// The number of ranks.
    pub fn size(&self) -> usize {
        self.size
    }

    /// The MPI communicator, for the library's own messages.
    pub(crate) fn mpi(&self) -> &SimpleCommunicator {
        &self.comm
    }
}

impl std::fmt::Debug for Comm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Comm {{ rank: {}, size: {} }}", self.rank, self.size)
    }
}
