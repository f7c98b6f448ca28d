//! The seam between the multigrid and the distribution of its vectors: everything that reaches
//! beyond a process's own rows goes through a level's `Layout`. The group operator
//! (`GroupOp`) makes a vector's halo current before an operator reads it, sums restricted
//! contributions into their owners, and takes its dot products and largest entries through it;
//! PCG, the smoother and the cycle use nothing else. One process needs no exchange and its
//! reductions are the serial ones (`Serial`); a distributed build replaces this layer
//! (`Distribution`), not the cycle.

use crate::sparse;

/// How one level's vectors are spread over processes. A group's vector is one block of n
/// values per component; each block holds the process's owned rows and, after them in a
/// distributed layout, copies of its neighbours' rows (the halo).
pub(crate) trait Layout: Send + Sync {
    /// The rows of a block this process owns.
    fn owned(&self) -> usize;
    /// Makes the halo of `block` equal to its owners' values (before an operator reads it).
    fn exchange(&self, block: &mut [f64]);
    /// Adds the halo rows of `block` into their owners' rows (after a transposed product such
    /// as restriction wrote contributions there).
    fn accumulate(&self, block: &mut [f64]);
    /// Σ aᵢ bᵢ over the owned rows of every process, in an order fixed by the layout (the
    /// result does not depend on the thread count).
    fn dot(&self, a: &[f64], b: &[f64]) -> f64;
    /// The largest |vᵢ| over the owned rows of every process (NaN when any is NaN).
    fn max_abs(&self, v: &[f64]) -> f64;
    /// Projects `block` on the vectors whose tied rows (copies of one unknown on different
    /// processes, such as periodic pairs) are equal: each tied owned row takes the mean of its
    /// copies. Nothing where no rows are tied (one process, whose tied vertices are one
    /// unknown already).
    fn tie(&self, _block: &mut [f64]) {}
}

/// One process owns every row: no halo, and the serial deterministic reductions.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Serial {
    n: usize,
}

impl Serial {
    /// The layout of a level of `n` unknowns.
    pub(crate) fn new(n: usize) -> Self {
        Serial { n }
    }
}

impl Layout for Serial {
    fn owned(&self) -> usize {
        self.n
    }

    fn exchange(&self, _block: &mut [f64]) {}

    fn accumulate(&self, _block: &mut [f64]) {}

    fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        sparse::dot(a, b)
    }

    fn max_abs(&self, v: &[f64]) -> f64 {
        sparse::max_abs(v)
    }
}

/// The layout every level has in a build without the `mpi` feature.
#[cfg(not(feature = "mpi"))]
pub(crate) type Distribution = Serial;
/// With the `mpi` feature a level holds one process's rows or a rank's part of a distributed mesh.
#[cfg(feature = "mpi")]
pub(crate) use crate::distributed::Distribution;
