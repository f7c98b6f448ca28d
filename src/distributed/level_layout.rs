//! The layout a multigrid level holds in a build with the `mpi` feature: one process's rows
//! (`Serial`, every level of a `Solver`) or a rank's owned rows and halo (`HaloLayout`, the
//! distributed solve). The serial variant does exactly what a build without the feature does.

use super::halo::HaloLayout;
use super::ties::Ties;
use crate::multigrid::layout::{Layout, Serial};
use std::sync::Arc;

/// How one level's vectors are spread: over one process, or over the ranks of a distributed mesh.
#[derive(Clone, Debug)]
pub(crate) enum Distribution {
    /// Every row in this process.
    Serial(Serial),
    /// A rank's owned rows, then its halo.
    Halo(Arc<HaloLayout>),
    /// A rank's owned rows and halo, with rows tied across ranks (periodic links).
    Tied(Arc<HaloLayout>, Arc<Ties>),
}

impl Distribution {
    /// The layout of a level of `n` unknowns in one process.
    pub(crate) fn new(n: usize) -> Self {
        Distribution::Serial(Serial::new(n))
    }
}

impl Layout for Distribution {
    fn owned(&self) -> usize {
        match self {
            Distribution::Serial(s) => s.owned(),
            Distribution::Halo(h) | Distribution::Tied(h, _) => h.owned(),
        }
    }

    fn exchange(&self, block: &mut [f64]) {
        match self {
            Distribution::Serial(s) => s.exchange(block),
            Distribution::Halo(h) | Distribution::Tied(h, _) => h.exchange(block),
        }
    }

    fn accumulate(&self, block: &mut [f64]) {
        match self {
            Distribution::Serial(s) => s.accumulate(block),
            Distribution::Halo(h) | Distribution::Tied(h, _) => h.accumulate(block),
        }
    }

    fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        match self {
            Distribution::Serial(s) => s.dot(a, b),
            Distribution::Halo(h) | Distribution::Tied(h, _) => h.dot(a, b),
        }
    }

    fn max_abs(&self, v: &[f64]) -> f64 {
        match self {
            Distribution::Serial(s) => s.max_abs(v),
            Distribution::Halo(h) | Distribution::Tied(h, _) => h.max_abs(v),
        }
    }

    fn tie(&self, block: &mut [f64]) {
        if let Distribution::Tied(_, t) = self {
            t.average(block);
        }
    }
}
