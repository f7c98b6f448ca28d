//! Seconds per phase of the hierarchy's last build or re-reference: where a setup and a
//! re-reference spend their time (docs/PERFORMANCE.md), read by the bench and the step reports.

use std::time::Instant;

/// Seconds per phase of the last `Hierarchy::build` or `Hierarchy::move_to`. Phases that run
/// side by side (a level's unknowns and its coarsening at build) are each counted in full.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Phases {
    /// Numbering the unknowns, their flags and the slip frames (build); checking the coarse
    /// levels for inverted cells at the new positions and remaking the slip frames (re-reference).
    pub unknowns: f64,
    /// K and V of the levels with a mesh from their element matrices.
    pub assemble: f64,
    /// Choosing coarse meshes or kept unknowns, with their first interpolation weights (build).
    pub coarsen: f64,
    /// Interpolation weights re-chosen at the new positions (re-reference).
    pub transfer: f64,
    /// Galerkin products PᵀKP and PᵀV.
    pub galerkin: f64,
    /// Jacobi diagonals and the λmax power iterations.
    pub bounds: f64,
    /// The coarsest level's dense factorisation.
    pub coarse_solve: f64,
    /// A re-reference kept the coarse levels of an earlier one (`multigrid::lag`): only the
    /// fine level was evaluated again.
    pub coarse_kept: bool,
}

impl Phases {
    /// The sum of the phases.
    pub fn total(&self) -> f64 {
        self.unknowns + self.assemble + self.coarsen + self.transfer + self.galerkin + self.bounds + self.coarse_solve
    }

    /// The phases as (name, seconds), in the order they run.
    pub fn named(&self) -> [(&'static str, f64); 7] {
        [
            ("unknowns", self.unknowns),
            ("assemble", self.assemble),
            ("coarsen", self.coarsen),
            ("transfer", self.transfer),
            ("galerkin", self.galerkin),
            ("bounds", self.bounds),
            ("coarse_solve", self.coarse_solve),
        ]
    }
}

/// Runs `f`, adding its wall time to `slot`.
pub(crate) fn timed<T>(slot: &mut f64, f: impl FnOnce() -> T) -> T {
    let t = Instant::now();
    let r = f();
    *slot += t.elapsed().as_secs_f64();
    r
}
