//! The few messages of the command line's own over MPI (the library has its own communicator for
//! its messages): arrays from rank 0 to one rank and back, and a result broadcast from rank 0.
//! Messages between two ranks arrive in the order they were sent, so each side sends and
//! receives its arrays in one fixed order.

use meshmove::distributed::mpi::datatype::Equivalence;
use meshmove::distributed::mpi::topology::SimpleCommunicator;
use meshmove::distributed::mpi::traits::*;

/// Sends `values` to rank `to` (a blocking send, matched by [`receive`] there).
pub fn send<T: Equivalence>(world: &SimpleCommunicator, to: usize, values: &[T]) {
    world.process_at_rank(to as i32).send(values);
}

/// The next array rank 0 sent to this rank ([`send`]).
pub fn receive<T: Equivalence>(world: &SimpleCommunicator) -> Vec<T> {
    receive_from(world, 0)
}

/// The next array rank `from` sent to this rank.
pub fn receive_from<T: Equivalence>(world: &SimpleCommunicator, from: usize) -> Vec<T> {
    world.process_at_rank(from as i32).receive_vec().0
}

/// Rank 0's `result` on every rank (collective; the other ranks pass anything): Ok, or the same
/// error message everywhere.
pub fn broadcast_result(world: &SimpleCommunicator, result: Result<(), String>) -> Result<(), String> {
    let root = world.process_at_rank(0);
    let mut bytes = result.err().map(String::into_bytes).unwrap_or_default();
    let mut len = bytes.len() as u64;
    root.broadcast_into(&mut len);
    bytes.resize(len as usize, 0);
    if len > 0 {
        root.broadcast_into(&mut bytes[..]);
    }
    match len {
        0 => Ok(()),
        _ => Err(String::from_utf8_lossy(&bytes).into_owned()),
    }
}

/// Rank 0's `values` on every rank (collective; the other ranks pass anything).
pub fn broadcast<T: Equivalence + Default + Clone>(world: &SimpleCommunicator, values: &mut Vec<T>) {
    let root = world.process_at_rank(0);
    let mut len = values.len() as u64;
    root.broadcast_into(&mut len);
    values.resize(len as usize, T::default());
    if len > 0 {
        root.broadcast_into(&mut values[..]);
    }
}
