//! Values of a group of ranks moved onto one rank of the group and back: rank r sends its values
//! to rank r >> s, which lays its senders' values end to end in rank order. It is how a coarse
//! level's vectors reach the fewer ranks it is agglomerated onto (`agglomerate`) and how the
//! coarsest level's right-hand side reaches the one rank that solves it (`gathered`): one
//! point-to-point message per rank each way, where an allgather would send every rank's values
//! to every rank.

use crate::distributed::comm::Comm;
use mpi::traits::*;
use std::ops::Range;
use std::sync::Arc;

/// The tag of the mover's messages (the library's communicators are its own).
const MOVE_TAG: i32 = 29;

/// One rank's part in moving values onto ranks r >> s of a communicator and back.
pub(super) struct Mover {
    comm: Arc<Comm>,
    /// The rank this one's values go to.
    target: usize,
    /// How many values this rank sends.
    count: usize,
    /// The ranks whose values come here (ascending) and where they go in the moved vector.
    sources: Vec<(usize, Range<usize>)>,
}

impl Mover {
    /// The mover of `count` values per rank onto ranks r >> `shift` of `comm` (collective: the
    /// counts are exchanged once).
    pub(super) fn new(comm: &Arc<Comm>, shift: u32, count: usize) -> Mover {
        let (me, size) = (comm.rank(), comm.size());
        let target = me >> shift;
        let first = me.checked_shl(shift).unwrap_or(usize::MAX).min(size);
        let last = (me + 1).checked_shl(shift).unwrap_or(usize::MAX).min(size);
        let mut counts = vec![0u64; last - first];
        let mine = [count as u64];
        let recvs: Vec<(usize, &mut [u64])> = (first..last).zip(counts.chunks_mut(1)).collect();
        swap(comm, &[(target, &mine[..])], recvs);
        let mut at = 0;
        let sources = (first..last)
            .zip(&counts)
            .map(|(rank, &c)| {
                let range = at..at + c as usize;
                at = range.end;
                (rank, range)
            })
            .collect();
        Mover { comm: comm.clone(), target, count, sources }
    }

    /// How many values arrive here (none on a rank no value moves to).
    pub(super) fn len(&self) -> usize {
        self.sources.last().map_or(0, |s| s.1.end)
    }

    /// How many values this rank sends.
    pub(super) fn count(&self) -> usize {
        self.count
    }

    /// Every sender's `mine` (`count` values) into `moved` (its first `len` entries), on the
    /// target ranks (collective over the senders and their targets).
    pub(super) fn gather(&self, mine: &[f64], moved: &mut [f64]) {
        let mut rest = &mut moved[..self.len()];
        let recvs = self
            .sources
            .iter()
            .map(|(rank, range)| {
                let (head, tail) = std::mem::take(&mut rest).split_at_mut(range.len());
                rest = tail;
                (*rank, head)
            })
            .collect();
        swap(&self.comm, &[(self.target, &mine[..self.count])], recvs);
    }

    /// The reverse of `gather`: each sender's values of `moved` back into its `mine`.
    pub(super) fn scatter(&self, moved: &[f64], mine: &mut [f64]) {
        let sends: Vec<(usize, &[f64])> =
            self.sources.iter().map(|(rank, range)| (*rank, &moved[range.clone()])).collect();
        swap(&self.comm, &sends, vec![(self.target, &mut mine[..self.count])]);
    }
}

/// Posts every receive and send (nonblocking, a rank may send to itself) and waits for all.
fn swap<T: Equivalence>(comm: &Comm, sends: &[(usize, &[T])], recvs: Vec<(usize, &mut [T])>) {
    let world = comm.mpi();
    mpi::request::scope(|scope| {
        let recvs: Vec<_> = recvs
            .into_iter()
            .map(|(rank, buf)| world.process_at_rank(rank as i32).immediate_receive_into_with_tag(scope, buf, MOVE_TAG))
            .collect();
        let sends: Vec<_> = sends
            .iter()
            .map(|(rank, buf)| world.process_at_rank(*rank as i32).immediate_send_with_tag(scope, *buf, MOVE_TAG))
            .collect();
        recvs.into_iter().for_each(|r| {
            r.wait();
        });
        sends.into_iter().for_each(|s| {
            s.wait();
        });
    });
}
