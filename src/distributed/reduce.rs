//! Reductions whose result is the same on every rank and, for a fixed number of ranks, the same
//! on every run: each rank's partial values are gathered (`MPI_Allgather`) and combined in rank
//! order on every rank, rather than left to the order an `MPI_Allreduce` algorithm picks.

use super::comm::Comm;
use mpi::datatype::Partition;
use mpi::traits::*;

/// Σ over ranks of each entry of `partials`, added in rank order (the same vector length on
/// every rank). One collective for any number of sums, so a solver's inner products of one
/// iteration go together.
pub(crate) fn sum_in_rank_order(comm: &Comm, partials: &[f64]) -> Vec<f64> {
    let all = gather(comm, partials);
    let m = partials.len();
    let mut out = vec![0.0; m];
    for rank in all.chunks_exact(m.max(1)) {
        out.iter_mut().zip(rank).for_each(|(o, p)| *o += p);
    }
    out
}

/// The largest of every rank's `value`; NaN when any rank's is NaN.
pub(crate) fn max_over_ranks(comm: &Comm, value: f64) -> f64 {
    gather(comm, &[value]).into_iter().fold(0.0, |m, v| if v.is_nan() || m.is_nan() { f64::NAN } else { m.max(v) })
}

/// Every rank's `values` (the same length on every rank), in rank order.
pub(crate) fn gather<T: Equivalence + Copy + Default>(comm: &Comm, values: &[T]) -> Vec<T> {
    let mut all = vec![T::default(); values.len() * comm.size()];
    comm.mpi().all_gather_into(values, &mut all[..]);
    all
}

/// Every rank's `values` (any length per rank), by rank: one exchange of counts, then one of
/// the values.
pub(crate) fn gather_varcount<T: Equivalence + Copy + Default>(comm: &Comm, values: &[T]) -> Vec<Vec<T>> {
    let counts: Vec<i32> = gather(comm, &[values.len() as i32]);
    let displs: Vec<i32> = counts.iter().scan(0i32, |acc, &x| Some(std::mem::replace(acc, *acc + x))).collect();
    let mut all = vec![T::default(); counts.iter().map(|&c| c as usize).sum()];
    {
        let mut rp = mpi::datatype::PartitionMut::new(&mut all[..], &counts[..], &displs[..]);
        comm.mpi().all_gather_varcount_into(values, &mut rp);
    }
    let mut out = Vec::with_capacity(counts.len());
    let mut start = 0;
    for &c in &counts {
        out.push(all[start..start + c as usize].to_vec());
        start += c as usize;
    }
    out
}

/// Personalised all-to-all: `send[r]` goes to rank r; returns what each rank sent here, by
/// source rank. One exchange of counts, then one of the values.
pub(crate) fn all_to_all<T: Equivalence + Copy + Default>(comm: &Comm, send: &[Vec<T>]) -> Vec<Vec<T>> {
    let size = comm.size();
    let counts: Vec<i32> = send.iter().map(|s| s.len() as i32).collect();
    let mut recv_counts = vec![0i32; size];
    comm.mpi().all_to_all_into(&counts[..], &mut recv_counts[..]);
    let displs =
        |c: &[i32]| c.iter().scan(0i32, |acc, &x| Some(std::mem::replace(acc, *acc + x))).collect::<Vec<i32>>();
    let flat: Vec<T> = send.iter().flatten().copied().collect();
    let total = recv_counts.iter().map(|&c| c as usize).sum();
    let mut recv = vec![T::default(); total];
    {
        let sp = Partition::new(&flat[..], &counts[..], displs(&counts));
        let mut rp = mpi::datatype::PartitionMut::new(&mut recv[..], &recv_counts[..], displs(&recv_counts));
        comm.mpi().all_to_all_varcount_into(&sp, &mut rp);
    }
    let mut out = Vec::with_capacity(size);
    let mut start = 0;
    for &c in &recv_counts {
        out.push(recv[start..start + c as usize].to_vec());
        start += c as usize;
    }
    out
}
