//! Enumerations, bounds and the report structs of the C ABI.
//!
//! Enum arguments cross the boundary as `int32_t`; the enums below give the named values (fixed,
//! never renumbered) and are converted with a check.

use super::error::CError;
use crate::geometry::CellType;
use crate::limits;
use crate::{Criterion, InterfaceVariant, Kind, Method, Mode};

/// Most steps of one `meshmove_solver_move_in_steps` call.
pub const MESHMOVE_MAX_STEPS: i32 = 1_000_000;
/// Largest `max_cycles` of `meshmove_options_set_max_cycles`.
pub const MESHMOVE_MAX_CYCLES: i32 = 1_000_000;
/// Largest Chebyshev degree of `meshmove_options_set_cheb_degree` and `_cheb_coarse_degree`.
pub const MESHMOVE_MAX_CHEB_DEGREE: i32 = 64;
/// Largest `threads` of `meshmove_options_set_threads` (a fixed bound, the same on every machine).
pub const MESHMOVE_MAX_THREADS: i32 = 1024;
/// Largest `max_substeps` of `meshmove_solver_set_substepping`.
pub const MESHMOVE_MAX_SUBSTEPS: i32 = 1_048_576;
/// Most vertices of a mesh (dim × vertices must also fit an `int32_t` length: in 3D at most
/// `INT32_MAX / 3`).
pub const MESHMOVE_MAX_VERTICES: i32 = 1_073_741_823;
/// Most cells of a mesh (the connectivity's length must also fit an `int32_t`).
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

/// Which equation moves the mesh (`meshmove_options_set_method`).
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

/// How the solver iterates (`meshmove_options_set_mode`).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum meshmove_mode {
    /// Conjugate gradients preconditioned by a W-cycle with Chebyshev smoothing (default).
    Default = 0,
    /// The paper: stationary W-cycles with one Jacobi sweep, C = 0.9.
    PaperFaithful = 1,
}

/// When a solve stops (`meshmove_options_set_criterion`).
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
    /// The vertex slides along its wall: the displacement normal to the wall is prescribed, the
    /// tangential components are free. A kind of the whole patch: set it for every component
    /// (`meshmove_bcs_set_kinds`).
    Slip = 3,
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

/// The type of a cell in `meshmove_mesh_create`: VTK's cell type ids. Corners are in VTK's local
/// order for the type.
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum meshmove_cell_type {
    /// 3 corners (2D).
    Triangle = 5,
    /// 4 corners, counter-clockwise or clockwise like the rest of the mesh (2D).
    Quad = 9,
    /// 4 corners (3D).
    Tetra = 10,
    /// 8 corners: 0–3 the bottom face, 4–7 the top face above them (3D).
    Hexahedron = 12,
    /// 6 corners: triangle 0–1–2 and triangle 3–4–5 above it (3D).
    Wedge = 13,
    /// 5 corners: quad 0–1–2–3 and the apex 4 (3D).
    Pyramid = 14,
}

// The header's values are the library's cell types (VTK ids).
const _: () = {
    assert!(meshmove_cell_type::Triangle as u8 == CellType::Triangle as u8);
    assert!(meshmove_cell_type::Quad as u8 == CellType::Quad as u8);
    assert!(meshmove_cell_type::Tetra as u8 == CellType::Tetra as u8);
    assert!(meshmove_cell_type::Hexahedron as u8 == CellType::Hexahedron as u8);
    assert!(meshmove_cell_type::Wedge as u8 == CellType::Wedge as u8);
    assert!(meshmove_cell_type::Pyramid as u8 == CellType::Pyramid as u8);
};

/// A cell type id (`meshmove_cell_type`) of cell `cell` (numbered as the caller numbers).
pub(crate) fn cell_type(t: i32, cell: i64) -> Result<CellType, CError> {
    CellType::from_vtk(i64::from(t)).ok_or_else(|| {
        CError::arg(format!(
            "cell {cell} has type {t}, which is not a meshmove_cell_type (5 TRIANGLE, 9 QUAD, 10 TETRA, 12 \
             HEXAHEDRON, 13 WEDGE, 14 PYRAMID)"
        ))
    })
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
    /// SLIP walls: the largest distance of a slipped vertex from its wall in the result (0
    /// without slip walls).
    pub max_slip_offwall: f64,
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
    /// SLIP walls: the largest distance of a slipped vertex from its wall after this sub-step.
    pub max_slip_offwall: f64,
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
            max_slip_offwall: r.max_slip_offwall,
        }
    }
}

/// Where one step (or sub-step) of a move spent its time, in seconds (the step reports' order).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct meshmove_step_seconds {
    /// Re-evaluating the solver's reference at the accepted result (and, on the first sub-step
    /// of `meshmove_solver_move`, at positions the code moved itself); 0 for a rejected attempt.
    pub reference: f64,
    /// The solve (with a hierarchy rebuild when a reused one stalled).
    pub solve: f64,
    /// The quality check of the result.
    pub quality: f64,
}

impl From<&crate::StepReport> for meshmove_step_seconds {
    fn from(r: &crate::StepReport) -> Self {
        meshmove_step_seconds { reference: r.reference_seconds, solve: r.solve_seconds, quality: r.quality_seconds }
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
    /// Inverted cells: cells with a corner whose Jacobian is not positive or with a non-positive
    /// volume (the solver's test). A hexahedron folded at one corner is inverted with a positive
    /// volume, so this can exceed `negative_volume_cells`, never fall below it.
    pub inverted: i32,
    /// Smallest deformed / reference cell volume (area in 2D) ratio (negative when a cell inverted).
    pub min_volume_ratio: f64,
    /// Largest deformed / reference cell volume (area in 2D) ratio.
    pub max_volume_ratio: f64,
    /// Smallest angle of any cell, degrees.
    pub min_angle_deg: f64,
    /// Cells whose signed volume (area in 2D) is not positive: what VTK's cell volume finds.
    pub negative_volume_cells: i32,
    /// Smallest deformed / reference ratio of a cell's smallest corner Jacobian (negative when a
    /// corner inverted); for triangles and tetrahedra the volume ratio.
    pub min_corner_jacobian_ratio: f64,
}

impl From<&crate::Report> for meshmove_report {
    fn from(r: &crate::Report) -> Self {
        meshmove_report {
            cycles: r.cycles.min(i32::MAX as usize) as i32,
            max_correction: r.max_correction,
            rel_residual: r.rel_residual,
            seconds: r.seconds,
            converged: i32::from(r.converged),
            max_slip_offwall: r.max_slip_offwall,
        }
    }
}

impl From<crate::mesh::quality::Quality> for meshmove_quality {
    fn from(q: crate::mesh::quality::Quality) -> Self {
        meshmove_quality {
            inverted: q.inverted.min(i32::MAX as usize) as i32,
            min_volume_ratio: q.min_area_ratio,
            max_volume_ratio: q.max_area_ratio,
            min_angle_deg: q.min_angle_deg,
            negative_volume_cells: q.non_positive_measure.min(i32::MAX as usize) as i32,
            min_corner_jacobian_ratio: q.min_corner_jacobian_ratio,
        }
    }
}

pub(crate) fn kind(k: i32) -> Result<Kind, CError> {
    match k {
        0 => Ok(Kind::Fixed),
        1 => Ok(Kind::Clamped),
        2 => Ok(Kind::Free),
        3 => Ok(Kind::Slip),
        _ => Err(CError::arg(format!("kind {k} is not a meshmove_kind (0 FIXED, 1 CLAMPED, 2 FREE, 3 SLIP)"))),
    }
}

pub(crate) fn interface(v: i32) -> Result<InterfaceVariant, CError> {
    match v {
        0 => Ok(InterfaceVariant::Separate),
        1 => Ok(InterfaceVariant::Continuous),
        _ => Err(CError::arg(format!("interface variant {v} is not a meshmove_interface (0 SEPARATE, 1 CONTINUOUS)"))),
    }
}

pub(crate) fn method(m: i32) -> Result<Method, CError> {
    match m {
        0 => Ok(Method::Biharmonic),
        1 => Ok(Method::Laplacian),
        2 => Ok(Method::Spring),
        _ => Err(CError::arg(format!("method {m} is not a meshmove_method (0 BIHARMONIC, 1 LAPLACIAN, 2 SPRING)"))),
    }
}

pub(crate) fn mode(m: i32) -> Result<Mode, CError> {
    match m {
        0 => Ok(Mode::Default),
        1 => Ok(Mode::PaperFaithful),
        _ => Err(CError::arg(format!("mode {m} is not a meshmove_mode (0 DEFAULT, 1 PAPER_FAITHFUL)"))),
    }
}

pub(crate) fn criterion(c: i32) -> Result<Criterion, CError> {
    match c {
        0 => Ok(Criterion::RelativeResidual),
        1 => Ok(Criterion::MaxCorrection),
        _ => Err(CError::arg(format!(
            "criterion {c} is not a meshmove_criterion (0 RELATIVE_RESIDUAL, 1 MAX_CORRECTION)"
        ))),
    }
}

/// The sub-stepping limits: 0 ≤ `max_substeps` ≤ `MESHMOVE_MAX_SUBSTEPS`, 0 ≤ `min_volume_ratio` < 1.
pub(crate) fn substepping(max_substeps: i32, min_volume_ratio: f64) -> Result<(usize, f64), CError> {
    let n = bounded(max_substeps, "max_substeps", 0, limits::MAX_SUBSTEPS)?;
    if !(0.0..1.0).contains(&min_volume_ratio) {
        return Err(CError::arg(format!("min_volume_ratio is {min_volume_ratio}; it must be at least 0 and below 1")));
    }
    Ok((n, min_volume_ratio))
}
