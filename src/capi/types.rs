//! Enumerations, the options struct and the report structs of the C ABI.
//!
//! Enum arguments cross the boundary as `int32_t`; the enums below give the named values (fixed,
//! never renumbered) and are converted with a check.

use super::error::CError;
use crate::limits;
use crate::{Criterion, InterfaceVariant, Kind, Method, Mode};

/// Most steps of one `meshmove_solver_move_in_steps` call.
pub const MESHMOVE_MAX_STEPS: i32 = 1_000_000;
/// Largest `meshmove_options.max_cycles`.
pub const MESHMOVE_MAX_CYCLES: i32 = 1_000_000;
/// Largest `meshmove_options.cheb_degree`.
pub const MESHMOVE_MAX_CHEB_DEGREE: i32 = 64;
/// Largest `meshmove_options.threads` (a fixed bound, the same on every machine).
pub const MESHMOVE_MAX_THREADS: i32 = 1024;
/// Largest `max_substeps` of `meshmove_solver_set_substepping`.
pub const MESHMOVE_MAX_SUBSTEPS: i32 = 1_048_576;
/// Most vertices of a mesh (2 × vertices must fit an `int32_t` length).
pub const MESHMOVE_MAX_VERTICES: i32 = 1_073_741_823;
/// Most cells of a mesh (3 × cells must fit an `int32_t` length).
pub const MESHMOVE_MAX_CELLS: i32 = 715_827_882;

// The header's numbers are the library's bounds (cbindgen needs literals to emit `#define`s).
const _: () = {
    assert!(MESHMOVE_MAX_STEPS as usize == limits::MAX_STEPS);
    assert!(MESHMOVE_MAX_CYCLES as usize == limits::MAX_CYCLES);
    assert!(MESHMOVE_MAX_CHEB_DEGREE as usize == limits::MAX_CHEB_DEGREE);
    assert!(MESHMOVE_MAX_THREADS as usize == limits::MAX_THREADS);
    assert!(MESHMOVE_MAX_SUBSTEPS as usize == limits::MAX_SUBSTEPS);
    assert!(MESHMOVE_MAX_VERTICES as usize == limits::MAX_VERTICES);
    assert!(MESHMOVE_MAX_CELLS as usize == limits::MAX_CELLS);
};

/// An `int32_t` count or option checked against `min ..= max` before anything is allocated.
pub(crate) fn bounded(v: i32, what: &str, min: usize, max: usize) -> Result<usize, CError> {
    match usize::try_from(v) {
        Ok(n) if (min..=max).contains(&n) => Ok(n),
        _ => Err(CError::arg(format!("{what} is {v}; it must be between {min} and {max}"))),
    }
}

/// Which equation moves the mesh (`meshmove_options.method`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum meshmove_method {
    /// The biharmonic (the paper's method; default): boundary spacing can be held.
    Biharmonic = 0,
    /// The Laplacian.
    Laplacian = 1,
    /// The spring analogy (graph Laplacian, edge weights 1/L²).
    Spring = 2,
}

/// How the solver iterates (`meshmove_options.mode`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum meshmove_mode {
    /// Conjugate gradients preconditioned by a W-cycle with Chebyshev smoothing (default).
    Default = 0,
    /// The paper: stationary W-cycles with one Jacobi sweep, C = 0.9.
    PaperFaithful = 1,
}

/// When a solve stops (`meshmove_options.criterion`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum meshmove_criterion {
    /// Relative residual ‖b − A x‖ / ‖b‖ ≤ tol (default).
    RelativeResidual = 0,
    /// Largest correction of the last cycle ≤ tol × largest prescribed displacement.
    MaxCorrection = 1,
}

/// The boundary condition of one displacement component on one patch.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum meshmove_kind {
    /// Position prescribed, spacing free to change.
    Fixed = 0,
    /// Position prescribed and normal spacing held (biharmonic only; as FIXED otherwise).
    Clamped = 1,
    /// The vertex moves (zero-flux conditions).
    Free = 2,
}

/// How an internal interface patch couples its two regions.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum meshmove_interface {
    /// Variant A: each side clamped separately (vertices split per region).
    Separate = 0,
    /// Variant B: one unknown per interface vertex, continuous coupling.
    Continuous = 1,
}

/// What each step of a move is solved from (`meshmove_solver_set_reference_mode`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum meshmove_reference {
    /// The mesh of the previous step (default): each step solves for the increment on the
    /// moved mesh. Large rotations need it; the mesh depends on the path.
    Incremental = 0,
    /// The original mesh: each step solves for the total displacement so far, so the mesh
    /// depends only on the boundary's position (a periodic motion comes back to its start).
    Original = 1,
}

/// Solver options; fill with `meshmove_options_default` and change what you need.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct meshmove_options {
    /// A `meshmove_method` value.
    pub method: i32,
    /// A `meshmove_mode` value.
    pub mode: i32,
    /// A `meshmove_criterion` value.
    pub criterion: i32,
    /// Worker threads of this solver, 0 ≤ threads ≤ `MESHMOVE_MAX_THREADS`; 0 is one per
    /// available core. All of the solver's work runs on them (never on a shared global pool).
    /// Results do not depend on it.
    pub threads: i32,
    /// Tolerance of the criterion (default 1e-8), positive and finite.
    pub tol: f64,
    /// Most cycles per solve (default 500), 1 ≤ max_cycles ≤ `MESHMOVE_MAX_CYCLES`.
    pub max_cycles: i32,
    /// Chebyshev smoother degree of the default mode, on every level; 0 picks per method
    /// (default 0: biharmonic 6 on the finest level and 4 below, others 3 and 2), otherwise
    /// 1 ≤ cheb_degree ≤ `MESHMOVE_MAX_CHEB_DEGREE`.
    pub cheb_degree: i32,
    /// 0 (default): fourth-kind Chebyshev, which needs no interval. Above 1: first-kind
    /// Chebyshev on [λmax / cheb_lower_ratio, λmax].
    pub cheb_lower_ratio: f64,
}

/// What a solve did (AMGCL's report struct, with both stopping measures).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct meshmove_report {
    /// W-cycles (or preconditioned CG iterations, one W-cycle each), larger of the two components.
    pub cycles: i32,
    /// Largest vertex correction of the last cycle.
    pub max_correction: f64,
    /// Relative residual ‖b − A x‖ / ‖b‖ at the end (0 when nothing moved).
    pub rel_residual: f64,
    /// Wall-clock seconds of the solve.
    pub seconds: f64,
    /// 1 if both components met the criterion, else 0.
    pub converged: i32,
}

/// What one step (or automatic sub-step) of a move did.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct meshmove_step_report {
    /// The step, 1-based.
    pub step: i32,
    /// The sub-step within the step, 1-based (1 when the step was not split).
    pub substep: i32,
    /// Fraction of the whole motion done after this sub-step (1 after the last).
    pub fraction: f64,
    /// Cycles of this sub-step's solve.
    pub cycles: i32,
    /// Relative residual at the end of this sub-step's solve.
    pub rel_residual: f64,
    /// 1 if the solve met its tolerance, else 0.
    pub converged: i32,
    /// 1 if the multigrid hierarchy was rebuilt (a coarse cell would have inverted), else 0.
    pub rebuilt: i32,
    /// Inverted cells of the mesh after this sub-step.
    pub inverted: i32,
    /// Smallest moved / reference cell area ratio of this sub-step.
    pub min_volume_ratio: f64,
    /// Smallest angle of any cell after this sub-step, degrees.
    pub min_angle_deg: f64,
    /// Wall-clock seconds of this sub-step.
    pub seconds: f64,
    /// 1 if the result became the new mesh; 0 if it was rejected (and the step split), or the
    /// call failed here.
    pub accepted: i32,
}

impl From<&crate::StepReport> for meshmove_step_report {
    fn from(r: &crate::StepReport) -> Self {
        let sat = |v: usize| v.min(i32::MAX as usize) as i32;
        meshmove_step_report {
            step: sat(r.step),
            substep: sat(r.substep),
            fraction: r.fraction,
            cycles: sat(r.cycles),
            rel_residual: r.rel_residual,
            converged: i32::from(r.converged),
            rebuilt: i32::from(r.rebuilt),
            inverted: sat(r.inverted),
            min_volume_ratio: r.min_volume_ratio,
            min_angle_deg: r.min_angle_deg,
            seconds: r.seconds,
            accepted: i32::from(r.accepted),
        }
    }
}

/// Every field of an accepted step report is finite (a rejected attempt may report what went
/// wrong, e.g. a residual that blew up).
pub(crate) fn finite_step_report(r: &meshmove_step_report) -> Result<(), CError> {
    let fields = [r.fraction, r.rel_residual, r.min_volume_ratio, r.min_angle_deg, r.seconds];
    if r.accepted == 1 && !fields.iter().all(|v| v.is_finite()) {
        return Err(CError::new(
            super::status::meshmove_status::Diverged,
            format!("step {}.{}: its report is not finite; nothing was written", r.step, r.substep),
        ));
    }
    Ok(())
}

pub(crate) fn reference_mode(m: i32) -> Result<crate::ReferenceMode, CError> {
    match m {
        0 => Ok(crate::ReferenceMode::Incremental),
        1 => Ok(crate::ReferenceMode::Original),
        _ => Err(CError::arg(format!("reference mode {m} is not a meshmove_reference (0 INCREMENTAL, 1 ORIGINAL)"))),
    }
}

/// Quality of a deformed mesh against the solver's reference mesh.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct meshmove_quality {
    /// Cells whose signed area is not positive.
    pub inverted: i32,
    /// Smallest deformed / reference cell area ratio (negative when a cell inverted).
    pub min_area_ratio: f64,
    /// Largest deformed / reference cell area ratio.
    pub max_area_ratio: f64,
    /// Smallest angle of any cell, degrees.
    pub min_angle_deg: f64,
}

impl From<&crate::Report> for meshmove_report {
    fn from(r: &crate::Report) -> Self {
        meshmove_report {
            cycles: r.cycles.min(i32::MAX as usize) as i32,
            max_correction: r.max_correction,
            rel_residual: r.rel_residual,
            seconds: r.seconds,
            converged: i32::from(r.converged),
        }
    }
}

impl From<crate::mesh::quality::Quality> for meshmove_quality {
    fn from(q: crate::mesh::quality::Quality) -> Self {
        meshmove_quality {
            inverted: q.inverted.min(i32::MAX as usize) as i32,
            min_area_ratio: q.min_area_ratio,
            max_area_ratio: q.max_area_ratio,
            min_angle_deg: q.min_angle_deg,
        }
    }
}

impl Default for meshmove_options {
    fn default() -> Self {
        let o = crate::Options::default();
        meshmove_options {
            method: meshmove_method::Biharmonic as i32,
            mode: meshmove_mode::Default as i32,
            criterion: meshmove_criterion::RelativeResidual as i32,
            threads: 0,
            tol: o.solve.tol,
            max_cycles: o.solve.max_cycles as i32,
            cheb_degree: o.solve.cheb_degree.map_or(0, |d| d as i32),
            cheb_lower_ratio: 0.0,
        }
    }
}

pub(crate) fn kind(k: i32) -> Result<Kind, CError> {
    match k {
        0 => Ok(Kind::Fixed),
        1 => Ok(Kind::Clamped),
        2 => Ok(Kind::Free),
        _ => Err(CError::arg(format!("kind {k} is not a meshmove_kind (0 FIXED, 1 CLAMPED, 2 FREE)"))),
    }
}

pub(crate) fn interface(v: i32) -> Result<InterfaceVariant, CError> {
    match v {
        0 => Ok(InterfaceVariant::Separate),
        1 => Ok(InterfaceVariant::Continuous),
        _ => Err(CError::arg(format!("interface variant {v} is not a meshmove_interface (0 SEPARATE, 1 CONTINUOUS)"))),
    }
}

impl meshmove_options {
    /// Checked conversion to the Rust options.
    pub(crate) fn to_rust(self) -> Result<crate::Options, CError> {
        let method = match self.method {
            0 => Method::Biharmonic,
            1 => Method::Laplacian,
            2 => Method::Spring,
            m => {
                return Err(CError::arg(format!(
                    "options.method {m} is not a meshmove_method (0 BIHARMONIC, 1 LAPLACIAN, 2 SPRING)"
                )))
            }
        };
        let mode = match self.mode {
            0 => Mode::Default,
            1 => Mode::PaperFaithful,
            m => {
                return Err(CError::arg(format!(
                    "options.mode {m} is not a meshmove_mode (0 DEFAULT, 1 PAPER_FAITHFUL)"
                )))
            }
        };
        let criterion = match self.criterion {
            0 => Criterion::RelativeResidual,
            1 => Criterion::MaxCorrection,
            c => {
                return Err(CError::arg(format!(
                    "options.criterion {c} is not a meshmove_criterion (0 RELATIVE_RESIDUAL, 1 MAX_CORRECTION)"
                )))
            }
        };
        let threads = bounded(self.threads, "options.threads", 0, limits::MAX_THREADS)?;
        let max_cycles = bounded(self.max_cycles, "options.max_cycles", 1, limits::MAX_CYCLES)?;
        // 0 picks the per-method default, like cheb_lower_ratio.
        let cheb_degree =
            Some(bounded(self.cheb_degree, "options.cheb_degree", 0, limits::MAX_CHEB_DEGREE)?).filter(|&d| d > 0);
        if !(self.tol > 0.0 && self.tol.is_finite()) {
            return Err(CError::arg(format!("options.tol is {}; it must be positive and finite", self.tol)));
        }
        let ratio = self.cheb_lower_ratio;
        let cheb_lower_ratio = if ratio == 0.0 {
            None
        } else if ratio > 1.0 && ratio.is_finite() {
            Some(ratio)
        } else {
            return Err(CError::arg(format!(
                "options.cheb_lower_ratio is {ratio}; it must be 0 (fourth kind) or above 1"
            )));
        };
        let mut o = crate::Options { method, threads, ..Default::default() };
        o.solve.mode = mode;
        o.solve.criterion = criterion;
        o.solve.tol = self.tol;
        o.solve.max_cycles = max_cycles;
        o.solve.cheb_degree = cheb_degree;
        o.solve.cheb_lower_ratio = cheb_lower_ratio;
        Ok(o)
    }
}

/// Fills `*options` with the defaults (biharmonic, default mode, relative residual 1e-8, 500
/// cycles, all cores).
///
/// # Safety
/// `options` must be NULL (an error) or point to a writable `meshmove_options`.
#[no_mangle]
pub unsafe extern "C" fn meshmove_options_default(options: *mut meshmove_options) -> super::status::meshmove_status {
    ffi_body!(meshmove_options_default, { super::handles::write_out(options, meshmove_options::default(), "options") })
}
