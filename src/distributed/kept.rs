//! The distributed multigrid of each component, built on the first solve from a reference that
//! needs it and kept for every later solve from it: `advance` moves the reference and drops
//! them, and the next solve builds them again, so a run pays for no hierarchy after its last
//! step. A component whose system has a zero right-hand side is solved without iterations
//! (`pcg`), so its multigrid waits for a solve that needs it.
//!
//! A solve takes the solver by shared reference (the solution depends on the reference and the
//! motion alone), so the kept hierarchies sit behind a lock: building or reusing them changes
//! no result, only the time a solve takes.

use super::error::DistError;
use super::halo::HaloLayout;
use super::mg::{Coarsening, CoupledSolve, LevelSize, Limits, Multigrid, OwnedRows, Smoothers};
use super::reduce::max_over_ranks;
use crate::multigrid::lines::Lines;
use std::sync::{Mutex, MutexGuard, PoisonError};

/// The hierarchies of one reference: components whose flags agree on every rank share one.
pub(crate) struct Hierarchies {
    multigrids: Vec<Multigrid>,
    /// The index in `multigrids` of each component's, once built.
    of_component: Vec<Option<usize>>,
    /// Unknowns and halo values per level of the first multigrid built.
    pub(crate) sizes: Vec<LevelSize>,
    /// The first multigrid built has its coarsest level gathered onto one rank.
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
    /// No multigrid yet for any of `dim` components.
    pub(crate) fn none(dim: usize) -> Hierarchies {
        let of_component = vec![None; dim];
        Hierarchies {
            multigrids: Vec::new(),
            of_component,
            sizes: Vec::new(),
            gathers: false,
            coupled: Vec::new(),
            whole: false,
            layered: false,
        }
    }

    /// Whether component `c` lacks the multigrid a solve of it needs.
    pub(crate) fn lacks(&self, c: usize) -> bool {
        !self.whole && self.of_component.get(c).is_some_and(Option::is_none)
    }

    /// Builds the multigrid of each component `needed` (the same on every rank) that has none,
    /// whose `flags` are given, from the finest level `fine(c)` makes and its `lines` across
    /// wall layers, as deep as `limits` allow, smoothed by `smoothers` (collective; every rank
    /// returns the same result). A component whose flags equal those of a component with a multigrid on every
    /// rank shares it: the build depends on the flags and the mesh alone.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn build(
        &mut self,
        halo: &HaloLayout,
        flags: &[Vec<u8>],
        needed: &[bool],
        mut fine: impl FnMut(usize) -> Result<(OwnedRows, Coarsening), DistError>,
        lines: &Lines,
        limits: Limits,
        smoothers: Smoothers,
    ) -> Result<(), DistError> {
        for c in 0..flags.len() {
            if needed.get(c) != Some(&true) || !self.lacks(c) {
                continue;
            }
            // The decision is global, as the build is collective.
            let same = |e: usize| max_over_ranks(halo.comm(), f64::from(u8::from(flags[c] != flags[e]))) == 0.0;
            let built = |e: usize| self.of_component[e].map(|k| (e, k));
            let shared = (0..flags.len()).filter_map(built).find(|&(e, _)| same(e)).map(|(_, k)| k);
            let k = match shared {
                Some(k) => k,
                None => {
                    let (rows, coarsening) = fine(c)?;
                    let mg = Multigrid::build(rows, coarsening, lines.clone(), limits, smoothers)?;
                    if self.multigrids.is_empty() {
                        (self.sizes, self.gathers) = (mg.sizes(), mg.gathers());
                    }
                    self.multigrids.push(mg);
                    self.multigrids.len() - 1
                }
            };
            self.of_component[c] = Some(k);
        }
        Ok(())
    }

    /// The hierarchies of a mesh of `dim` components with slip walls: the one `multigrid` over
    /// every component (`Multigrid::build_group`), whose cycle each group of them runs on its
    /// own components (collective).
    pub(crate) fn whole(multigrid: Multigrid, dim: usize) -> Hierarchies {
        let (sizes, gathers) = (multigrid.sizes(), multigrid.gathers());
        let of_component = vec![Some(0); dim];
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

    /// Component `c`'s multigrid, once built.
    pub(crate) fn of(&mut self, c: usize) -> Option<&mut Multigrid> {
        let k = self.of_component.get(c).copied().flatten()?;
        self.multigrids.get_mut(k)
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
