//! The cycle's policy, decided in one place: per level the smoother (kind, degree, interval)
//! and the cycle's shape, from the hierarchy and the caller's `SolveParams`; and how a stalled
//! solve strengthens it. docs/DESIGN.md §5 "The cycle's policy" has the table; the measurements
//! behind each choice are in docs/perf-history.md.

use super::hierarchy::Hierarchy;
use super::params::{Mode, SolveParams};
use super::smoother::Smoother;
use crate::operator::Method;

/// Shape of one cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CycleParams {
    /// Coarse visits per level: 1 = V-cycle, 2 = W-cycle.
    pub gamma: usize,
    /// The first level that visits its coarse level once whatever `gamma` is (a V-cycle from
    /// there down); `usize::MAX` keeps `gamma` on every level.
    pub once_from: usize,
    /// The smoother of the finest level.
    pub smoother: Smoother,
    /// The smoother of every coarser level.
    pub coarse_smoother: Smoother,
    /// Smoothing applications before the coarse correction.
    pub pre: usize,
    /// Smoothing applications after it.
    pub post: usize,
    /// Scale of the prolongated coarse correction.
    pub coarse_weight: f64,
    /// Smooth with λmax = 1, the l1 bound's guarantee, instead of each level's power-iteration
    /// estimate (a stalled solve's first remedy, see `stronger`).
    pub l1_bound: bool,
}

impl CycleParams {
    /// The cycle of a solve with `p` on `h`: the paper's Jacobi W-cycle in the paper-faithful
    /// mode, else the Chebyshev W-cycle of `chebyshev` with the degrees of `degrees`.
    pub fn resolve(h: &Hierarchy, p: &SolveParams) -> Self {
        match p.mode {
            Mode::PaperFaithful => CycleParams::paper(h.method),
            Mode::Default => {
                let (fine, coarse) = degrees(h, p);
                CycleParams { once_from: once_from(h), ..CycleParams::chebyshev(fine, coarse, p.cheb_lower_ratio) }
            }
        }
    }

    /// The smoother of level `l`.
    pub fn smoother_at(&self, l: usize) -> Smoother {
        if l == 0 {
            self.smoother
        } else {
            self.coarse_smoother
        }
    }

    /// The coarse visits of level `l` (`gamma`, or 1 from `once_from` on).
    pub fn gamma_at(&self, l: usize) -> usize {
        if l >= self.once_from {
            1
        } else {
            self.gamma
        }
    }

    /// The paper's W-cycle: one Jacobi sweep with C = 0.9 before coarsening, none after.
    ///
    /// For the biharmonic the rediscretised coarse operator K_c M_c⁻¹ K_c is about half the
    /// Galerkin PᵀAP, so a full coarse correction overshoots about twice and the cycle diverges.
    /// The coarse correction is weighted by ½ instead of adding a post-sweep (docs/DESIGN.md §5
    /// allows either): it keeps the paper's sweep pattern and converges at every size. The
    /// Laplacian's coarse operators do not overshoot; it keeps the full correction.
    pub fn paper(method: Method) -> Self {
        let coarse_weight = if method == Method::Biharmonic { 0.5 } else { 1.0 };
        let smoother = Smoother::Jacobi { weight: 0.9 };
        CycleParams {
            gamma: 2,
            once_from: usize::MAX,
            smoother,
            coarse_smoother: smoother,
            pre: 1,
            post: 0,
            coarse_weight,
            l1_bound: false,
        }
    }

    /// The preconditioner of the default mode: W-cycle with Chebyshev pre- and post-smoothing,
    /// of the fourth kind, or of the first kind on [λmax / r, λmax] given `lower_ratio` r.
    pub fn chebyshev(degree: usize, coarse_degree: usize, lower_ratio: Option<f64>) -> Self {
        let smoother = |degree| match lower_ratio {
            None => Smoother::Fourth { degree },
            Some(lower_ratio) => Smoother::Chebyshev { degree, lower_ratio },
        };
        CycleParams {
            gamma: 2,
            once_from: usize::MAX,
            smoother: smoother(degree),
            coarse_smoother: smoother(coarse_degree),
            pre: 1,
            post: 1,
            coarse_weight: 1.0,
            l1_bound: false,
        }
    }

    /// The cycle for a stalled solve after `boosts` earlier strengthenings: Chebyshev degrees
    /// ×1.6 (6 → 10 → 16 → 26), and at the second strengthening the same degree on [0, 1], the l1
    /// bound's interval, instead of the estimated λmax. An estimate below the true λmax makes the
    /// polynomial amplify the top of the spectrum and CG stagnates whatever the degree; distorted
    /// cells that only need more smoothing are served by the first, larger degree.
    pub fn stronger(&self, boosts: usize) -> Self {
        if boosts == 1 && !self.l1_bound {
            return CycleParams { l1_bound: true, ..*self };
        }
        let up = |sm: Smoother| match sm {
            Smoother::Chebyshev { degree, lower_ratio } => {
                Smoother::Chebyshev { degree: (degree * 8).div_ceil(5), lower_ratio }
            }
            Smoother::Fourth { degree } => Smoother::Fourth { degree: (degree * 8).div_ceil(5) },
            other => other,
        };
        CycleParams { smoother: up(self.smoother), coarse_smoother: up(self.coarse_smoother), ..*self }
    }
}

/// The Chebyshev degrees (finest level, coarse levels) of `method` in `dim` dimensions on a
/// hierarchy with levels of kept unknowns (`kept`) and lines across wall layers (`lines`) when
/// the caller sets none: the rule of `degrees` below, which the distributed biharmonic's levels
/// of kept unknowns share.
pub(crate) fn method_degrees(method: Method, dim: usize, kept: bool, lines: bool) -> (usize, usize) {
    match (method, kept) {
        (Method::Biharmonic, false) => (6, 4),
        (Method::Biharmonic, true) if lines => (16, 16),
        (Method::Biharmonic, true) => (8, 8),
        _ if dim >= 3 => (4, 3),
        _ => (3, 2),
    }
}

/// The first level of `h` that visits its coarse level once in the default mode: below thin 3D
/// wall layers (the biharmonic's 3D hierarchies of kept unknowns with lines) the fifth
/// (`ONCE_FROM_UNDER_LAYERS`), elsewhere none (the W-cycle on every level).
///
/// Under 3D wall layers the kept levels shrink by about 2 a level while their assembled
/// Galerkin rows grow to 100–200 entries, so a W-cycle's 2ˡ visits make each deep level cost as
/// much as the finest one or more, and the coarsest (factored, or smoothed where coarsening
/// stopped above the factor's size) is visited 2ᴸ times. Visited once from the fifth level on,
/// the deepest levels cost a fraction of that and the counts stay; from a higher level on the
/// largest wings lose iterations, and so do the 2D hierarchies, which keep their lines on the
/// coarse levels, without any deep level's second visit (docs/DESIGN.md §5, "Wall layers").
pub(crate) fn once_from(h: &Hierarchy) -> usize {
    if h.method == Method::Biharmonic && h.fine().dim() >= 3 && h.has_kept_levels() && h.has_lines() {
        ONCE_FROM_UNDER_LAYERS
    } else {
        usize::MAX
    }
}

/// Under 3D wall layers, the first level a cycle visits once: levels 0–3 keep the W-cycle's two
/// visits of their coarse level.
const ONCE_FROM_UNDER_LAYERS: usize = 4;

/// The default mode's Chebyshev degrees (finest level, coarse levels) on `h`: the caller's when
/// set (`cheb_degree`, `cheb_coarse_degree`), else per method:
///
/// - the biharmonic: 6 and 4 on coarse meshes, 8 on every level with levels of kept unknowns
///   (their Galerkin coarse operator is further from the biharmonic's K_c V_c⁻¹ K_c, so more
///   smoothing pays), and with slip walls the coarse levels at the finest level's degree (the
///   natural tangential condition makes the rediscretised coarse operators' boundary rows a
///   poorer match) unless the caller chose the coarse degree;
///   and below thin wall layers (levels with lines, `multigrid::lines`) 16 on every level, in
///   2D and 3D: the coarse levels' Galerkin operators, many layers thick, need the stronger
///   smoothing, and the finest level's smoothing is what keeps the count as the mesh grows and
///   on re-referenced meshes, whose interpolation rows are fitted again (a 1e-8 result that
///   this leaves tangled in the thinnest cells is polished by the solver, `solver::polish`;
///   docs/perf-history.md);
/// - the Laplacian and the spring: 3 and 2 in 2D, 4 and 3 in 3D, where a 3D vertex has more
///   neighbours and the higher degrees take an iteration or two fewer on the boxes and the graded
///   sphere for about the same solve time (docs/perf-history.md, "The graded sphere's iterations
///   with size").
pub(crate) fn degrees(h: &Hierarchy, p: &SolveParams) -> (usize, usize) {
    let (fine, coarse) = method_degrees(h.method, h.fine().dim(), h.has_kept_levels(), h.has_lines());
    let (fine, coarse) = match p.cheb_degree {
        Some(d) => (d, p.cheb_coarse_degree.unwrap_or(d)),
        None => (fine, p.cheb_coarse_degree.unwrap_or(coarse)),
    };
    let slip = h.fine().slip.is_some();
    if slip && h.method == Method::Biharmonic && p.cheb_coarse_degree.is_none() {
        return (fine, coarse.max(fine));
    }
    (fine, coarse)
}
