//! A rank's vectors over its local vertices: its owned entries first, then the halo (copies of
//! the vertices other ranks own), grouped by owner rank and by global id within a group. The
//! exchange lists say, for each neighbour rank, which owned entries go there and which halo
//! entries come from there; both sides list a neighbour's entries in global id order, so
//! nothing else needs agreeing. Exchanges are nonblocking point-to-point messages, all posted
//! before any is waited for.

use super::comm::Comm;
use super::reduce::{max_over_ranks, sum_in_rank_order};
use crate::multigrid::layout::Layout;
use crate::sparse;
use mpi::traits::*;
use std::ops::Range;
use std::sync::Arc;

/// The tag of the library's halo messages (its communicator is its own, so any tag is free).
const HALO_TAG: i32 = 28;

/// The exchange lists of one layout of vectors over a rank's local vertices.
#[derive(Debug)]
pub(crate) struct HaloLayout {
    comm: Arc<Comm>,
    /// Owned entries (the first ones of a vector).
    owned: usize,
    /// Owned plus halo entries.
    len: usize,
    /// Per neighbour rank (ascending): the owned entries it receives from us, in global id order.
    sends: Vec<(usize, Vec<u32>)>,
    /// Per owner rank (ascending): the halo entries it sends us (a contiguous range).
    recvs: Vec<(usize, Range<usize>)>,
}

impl HaloLayout {
    /// The layout of `len` entries of which the first `owned` are this rank's, with its lists.
    pub(crate) fn new(
        comm: Arc<Comm>,
        owned: usize,
        len: usize,
        sends: Vec<(usize, Vec<u32>)>,
        recvs: Vec<(usize, Range<usize>)>,
    ) -> HaloLayout {
        HaloLayout { comm, owned, len, sends, recvs }
    }

    /// The library's communicator.
    pub(crate) fn comm(&self) -> &Comm {
        &self.comm
    }

    /// The library's communicator, shared (for the layouts built from this one).
    pub(crate) fn shared_comm(&self) -> &Arc<Comm> {
        &self.comm
    }

    /// The neighbour ranks this rank sends to and receives from.
    pub(crate) fn neighbours(&self) -> Vec<usize> {
        let mut n: Vec<usize> = self.sends.iter().map(|s| s.0).chain(self.recvs.iter().map(|r| r.0)).collect();
        n.sort_unstable();
        n.dedup();
        n
    }

    /// Per neighbour rank: the owned entries it receives from us, in global id order.
    pub(crate) fn send_lists(&self) -> &[(usize, Vec<u32>)] {
        &self.sends
    }

    /// Per owner rank: the range of halo entries it sends us.
    pub(crate) fn recv_ranges(&self) -> &[(usize, Range<usize>)] {
        &self.recvs
    }

    /// The owner rank of every entry (this rank for the owned ones).
    pub(crate) fn owner_ranks(&self) -> Vec<usize> {
        let mut owners = vec![self.comm.rank(); self.len];
        for (rank, range) in &self.recvs {
            owners[range.clone()].iter_mut().for_each(|o| *o = *rank);
        }
        owners
    }

    /// Owned plus halo entries.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// Values sent per exchange of one vector (owned entries copied to neighbours).
    pub(crate) fn sent_per_exchange(&self) -> usize {
        self.sends.iter().map(|s| s.1.len()).sum()
    }

    /// Makes the halo entries of `v` (one vector of `len` entries) equal to their owners' values.
    pub(crate) fn refresh<T: Equivalence + Copy>(&self, v: &mut [T]) {
        let bufs: Vec<Vec<T>> =
            self.sends.iter().map(|(_, idx)| idx.iter().map(|&i| v[i as usize]).collect()).collect();
        let world = self.comm.mpi();
        let (_, mut halo) = v.split_at_mut(self.owned);
        mpi::request::scope(|scope| {
            let mut recvs = Vec::with_capacity(self.recvs.len());
            for (rank, range) in &self.recvs {
                let (head, tail) = std::mem::take(&mut halo).split_at_mut(range.len());
                halo = tail;
                recvs.push(world.process_at_rank(*rank as i32).immediate_receive_into_with_tag(scope, head, HALO_TAG));
            }
            let sends: Vec<_> = self
                .sends
                .iter()
                .zip(&bufs)
                .map(|((rank, _), b)| {
                    world.process_at_rank(*rank as i32).immediate_send_with_tag(scope, &b[..], HALO_TAG)
                })
                .collect();
            recvs.into_iter().for_each(|r| {
                r.wait();
            });
            sends.into_iter().for_each(|s| {
                s.wait();
            });
        });
    }

    /// Adds the halo entries of `v` into their owners' entries: the reverse of `refresh`. Each
    /// owner adds its neighbours' contributions in rank order.
    pub(crate) fn add_to_owners(&self, v: &mut [f64]) {
        let world = self.comm.mpi();
        let mut bufs: Vec<Vec<f64>> = self.sends.iter().map(|(_, idx)| vec![0.0; idx.len()]).collect();
        mpi::request::scope(|scope| {
            let recvs: Vec<_> = self
                .sends
                .iter()
                .zip(bufs.iter_mut())
                .map(|((rank, _), b)| {
                    world.process_at_rank(*rank as i32).immediate_receive_into_with_tag(scope, &mut b[..], HALO_TAG)
                })
                .collect();
            let sends: Vec<_> = self
                .recvs
                .iter()
                .map(|(rank, range)| {
                    world.process_at_rank(*rank as i32).immediate_send_with_tag(scope, &v[range.clone()], HALO_TAG)
                })
                .collect();
            recvs.into_iter().for_each(|r| {
                r.wait();
            });
            sends.into_iter().for_each(|s| {
                s.wait();
            });
        });
        for ((_, idx), b) in self.sends.iter().zip(&bufs) {
            idx.iter().zip(b).for_each(|(&i, x)| v[i as usize] += x);
        }
    }

    /// Σ over every rank's owned entries of each pair's aᵢ bᵢ, in one collective: each rank's
    /// partial sums in today's fixed-order blocks, the ranks' partials added in rank order.
    /// Vectors hold whole blocks of `len` entries (a group's components).
    pub(crate) fn dots(&self, pairs: &[(&[f64], &[f64])]) -> Vec<f64> {
        let partial: Vec<f64> = pairs.iter().map(|(a, b)| self.owned_dot(a, b)).collect();
        sum_in_rank_order(&self.comm, &partial)
    }

    /// This rank's Σ aᵢ bᵢ over the owned entries of every block.
    fn owned_dot(&self, a: &[f64], b: &[f64]) -> f64 {
        let (n, m) = (self.len.max(1), self.owned);
        a.chunks(n).zip(b.chunks(n)).map(|(a, b)| sparse::dot(&a[..m], &b[..m])).sum()
    }
}

impl Layout for HaloLayout {
    fn owned(&self) -> usize {
        self.owned
    }

    fn exchange(&self, block: &mut [f64]) {
        self.refresh(block);
    }

    fn accumulate(&self, block: &mut [f64]) {
        self.add_to_owners(block);
    }

    fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        self.dots(&[(a, b)])[0]
    }

    fn max_abs(&self, v: &[f64]) -> f64 {
        let (n, m) = (self.len.max(1), self.owned);
        let local = v.chunks(n).map(|b| sparse::max_abs(&b[..m])).fold(0.0, |x: f64, y| {
            if x.is_nan() || y.is_nan() {
                f64::NAN
            } else {
                x.max(y)
            }
        });
        max_over_ranks(&self.comm, local)
    }
}
