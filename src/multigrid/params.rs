//! What a caller chooses of a solve: the iteration, the stopping test and the smoother's
//! degrees (the cycle's policy from them is `policy::CycleParams::resolve`).

/// How the solver iterates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Mode {
    /// Conjugate gradients preconditioned by a W-cycle with Chebyshev smoothing.
    #[default]
    Default,
    /// The paper: stationary W-cycles, one Jacobi sweep with C = 0.9 (coarse correction halved
    /// for the biharmonic, see `CycleParams::paper`).
    PaperFaithful,
}

/// When to stop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Criterion {
    /// ‖b − A x‖₂ / ‖b‖₂ ≤ tol.
    #[default]
    RelativeResidual,
    /// Largest vertex correction of the last cycle ≤ tol × largest prescribed displacement
    /// (the paper's Fig. 8 measure).
    MaxCorrection,
}

/// How a solve iterates and when it stops; the default is CG preconditioned by W-cycles, to a
/// relative residual of 1e-8, in at most 500 iterations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveParams {
    /// The iteration: preconditioned CG (the default) or the paper's stationary W-cycles.
    pub mode: Mode,
    /// The stopping test `tol` applies to.
    pub criterion: Criterion,
    /// The tolerance: of the relative residual, or of the largest correction as a fraction of the
    /// largest prescribed displacement (see [`Criterion`]).
    pub tol: f64,
    /// The most W-cycles (paper-faithful mode) or CG iterations (default mode) a solve runs,
    /// restarts included; a solve that reaches it unconverged reports `converged: false`.
    pub max_cycles: usize,
    /// Chebyshev degree of the default mode's smoother on the finest level; None picks per method.
    pub cheb_degree: Option<usize>,
    /// Its degree on the coarse levels; None uses `cheb_degree` when that is set, else the
    /// per-method default (see `CycleParams::resolve`).
    pub cheb_coarse_degree: Option<usize>,
    /// None (the default): the fourth-kind polynomial, which needs no lower bound. Some(r): the
    /// classical first-kind polynomial on [λmax / r, λmax], r > 1.
    pub cheb_lower_ratio: Option<f64>,
}

impl SolveParams {
    /// True when a cycle's largest correction `max_corr` and relative residual `rel` meet the
    /// criterion (`scale`: the largest prescribed displacement).
    pub(crate) fn met(&self, max_corr: f64, rel: f64, scale: f64) -> bool {
        match self.criterion {
            Criterion::RelativeResidual => rel <= self.tol,
            Criterion::MaxCorrection => max_corr <= self.tol * scale,
        }
    }
}

impl Default for SolveParams {
    fn default() -> Self {
        SolveParams {
            mode: Mode::Default,
            criterion: Criterion::RelativeResidual,
            tol: 1e-8,
            max_cycles: 500,
            cheb_degree: None,
            cheb_coarse_degree: None,
            cheb_lower_ratio: None,
        }
    }
}
