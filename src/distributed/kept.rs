//! The distributed multigrid of each component, built on the first solve from a reference and
//! kept for every later solve from it: `advance` moves the reference and drops them, and the
//! next solve builds them again, so a run pays for no hierarchy after its last step.
//!
//! A solve takes the solver by shared reference (the solution depends on the reference and the
//! motion alone), so the kept hierarchies sit behind a lock: building or reusing them changes
//! no result, only the time a solve takes.

use super::error::DistError;
use super::halo::HaloLayout;
use super::mg::{Coarsening, CoupledSolve, LevelSize, Multigrid, OwnedRows, Smoothers};
use super::reduce::max_over_ranks;
use crate::multigrid::lines::Lines;
use std::sync::{Mutex, MutexGuard, PoisonError};

/// The hierarchies of one reference: components whose flags agree on every rank share one.
pub(crate) struct Hierarchies {
    multigrids: Vec<Multigrid>,
    /// The index in `multigrids` of each component's.
    of_component: Vec<usize>,
    /// Unknowns and halo values per level of the first component's.
    pub(crate) sizes: Vec<LevelSize>,
    /// The first component's coarsest level is gathered onto one rank.
    pub(crate) gathers: bool,
    /// Per group of components coupled by slip walls or periodic links and small enough to be
    /// gathered: its coupled solve on one rank (`mg::CoupledSolve`), which preconditions it in
    /// place of the components' multigrids; filled by the solver after the build.
    pub(crate) coupled: Vec<Option<CoupledSolve>>,
    /// One multigrid carries every component (`Multigrid::build_group`, slip walls): each group
    /// of components is preconditioned by its cycle over that group.
    pub(crate) whole: bool,
    /// Some rank found lines across wall layers; set by the solver after the build (it decides
    /// the smoothing degrees and whether a tangled result is polished).
    pub(crate) layered: bool,
}

impl Hierarchies {
    /// Builds the multigrid of each of the components whose `flags` are given, from the finest
    /// level `fine(c)` makes and its `lines` across wall layers, with at most `max_levels` levels smoothed by `smoothers`, coarse
    /// levels agglomerated below `per_rank` unknowns per rank (collective; every rank returns
    /// the same result).
    pub(crate) fn build(
        halo: &HaloLayout,
        flags: &[Vec<u8>],
        mut fine: impl FnMut(usize) -> Result<(OwnedRows, Coarsening), DistError>,
        lines: &Lines,
        max_levels: usize,
        smoothers: Smoothers,
        per_rank: u64,
    ) -> Result<Hierarchies, DistError> {
        let (mut multigrids, mut of_component) = (Vec::new(), Vec::with_capacity(flags.len()));
        for c in 0..flags.len() {
            // A component whose flags equal the previous one's on every rank shares its
            // hierarchy; the decision is global, as the build is collective.
            let share = c > 0 && max_over_ranks(halo.comm(), f64::from(u8::from(flags[c] != flags[c - 1]))) == 0.0;
            if !share {
                let (rows, coarsening) = fine(c)?;
                multigrids.push(Multigrid::build(rows, coarsening, lines.clone(), max_levels, smoothers, per_rank)?);
            }
            of_component.push(multigrids.len() - 1);
        }
        let (sizes, gathers) = multigrids.first().map(|m| (m.sizes(), m.gathers())).unwrap_or_default();
        Ok(Hierarchies { multigrids, of_component, sizes, gathers, coupled: Vec::new(), whole: false, layered: false })
    }

    /// The hierarchies of a mesh of `dim` components with slip walls: the one `multigrid` over
    /// every component (`Multigrid::build_group`), whose cycle each group of them runs on its
    /// own components (collective).
    pub(crate) fn whole(multigrid: Multigrid, dim: usize) -> Hierarchies {
        let (sizes, gathers) = (multigrid.sizes(), multigrid.gathers());
        let of_component = vec![0; dim];
        Hierarchies {
            multigrids: vec![multigrid],
            of_component,
            sizes,
            gathers,
            coupled: Vec::new(),
            whole: true,
            layered: false,
        }
    }

    /// Component `c`'s multigrid.
    pub(crate) fn of(&mut self, c: usize) -> &mut Multigrid {
        &mut self.multigrids[self.of_component[c]]
    }
}

/// The hierarchies kept for the current reference, if built.
#[derive(Default)]
pub(crate) struct Kept(Mutex<Option<Hierarchies>>);

impl Kept {
    /// The kept hierarchies, for a solve to build or use (a panic in an earlier solve leaves
    /// them whole: a cycle's scratch is rewritten before it is read).
    pub(crate) fn lock(&self) -> MutexGuard<'_, Option<Hierarchies>> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Drops them: the reference or the parameters they were built for changed.
    pub(crate) fn clear(&mut self) {
        *self.0.get_mut().unwrap_or_else(PoisonError::into_inner) = None;
    }
}
