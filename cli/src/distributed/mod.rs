//! The command line under `mpirun` (the `mpi` feature): what `deform` and `bench` share there —
//! METIS's partition of the cells (`partition`), each rank's part with its ghost layer
//! (`parts`), the case's conditions and motions sent to the ranks (`case`), per-vertex arrays
//! between the whole mesh on rank 0 and the parts (`vertex_values`), and the command line's own
//! messages (`wire`).

pub mod case;
pub mod partition;
pub mod parts;
pub mod vertex_values;
pub mod wire;

/// Whether this process was started by `mpirun` (Open MPI's or MPICH's launcher): then `deform`
/// runs distributed over the launched ranks.
pub fn launched() -> bool {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"].iter().any(|v| std::env::var_os(v).is_some())
}
