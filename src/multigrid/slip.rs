//! Slip walls in the multigrid solve (docs/DESIGN.md §4 "Slip walls", §5): the components are one
//! group, and every vector of the group lives in the subspace the slip frames leave free.
//!
//! With Π the projection that removes each slip unknown's constrained directions (`SlipFrames`),
//! the system is Π A Π w = Π (b − A g), g the prescribed normal parts. The pieces:
//!
//! - residuals and products are projected (`GroupOp::residual`, `GroupOp::apply`);
//! - the smoother runs the components in lockstep with one polynomial (the largest λmax of the
//!   group) and projects its step (`smoother::smooth` on the group); its Jacobi diagonal is made the same for every component at a
//!   slip unknown (`equalise_bounds`), so D⁻¹ commutes with Π and the projected step is the
//!   smoother of Π A Π, with the l1 bound's guarantee intact;
//! - restriction is Π_c Pᵀ and prolongation Π_f P: the coarse levels carry the frames of the
//!   fine unknowns their vertices are (`attach`), so they solve the constrained problem too;
//! - the coarsest level solves the coupled system densely in a basis of the free directions
//!   (`CoarseSolve` of the group).
//!
//! The cycle stays symmetric on the subspace, so it preconditions CG as before.

use super::group::{estimate_lambda_max, GroupOp};
use super::level::{Level, LevelSlip};
use crate::bc::{component_flags, fine_slip_frames, inherit_slip_frames, BoundaryConditions, SlipFrames, P};
use crate::operator::Method;
use crate::Mesh;

/// The finer level's unknown of each unknown of `level` (its vertex is a finer vertex, or on a
/// level without a mesh it is a finer unknown).
fn fine_dofs(level: &Level, fine: &Level) -> Vec<u32> {
    if level.mesh.is_none() {
        return level.parent_vertex.clone();
    }
    level
        .dofs
        .dof_vertex
        .iter()
        .map(|&v| fine.dofs.vertex_dof[level.parent_vertex[v as usize] as usize])
        .collect()
}

/// Gives `level` its slip frames: from its own mesh on the finest level (`fine` None), inherited
/// from `fine` below. Pinned unknowns are made P in every component of `level.flags`.
pub(super) fn attach(level: &mut Level, fine: Option<&Level>, bcs: &BoundaryConditions) {
    level.slip = match fine {
        None => fine_slip_frames(level.mesh.as_ref().expect("the finest level has a mesh"), &level.dofs, bcs, &mut level.flags)
            .map(|frames| LevelSlip { coupled: !frames.dofs.is_empty(), frames, bcs: Some(bcs.clone()) }),
        Some(f) => f.slip.as_ref().and_then(|s| {
            let map = fine_dofs(level, f);
            inherit_slip_frames(&s.frames, &map, &mut level.flags).map(|frames| LevelSlip {
                frames,
                bcs: None,
                coupled: s.coupled,
            })
        }),
    };
}

/// A level's slip frames and flags at new positions.
pub(super) type MovedFrames = (Option<SlipFrames>, Vec<Vec<u8>>);

/// The frames and flags of every level at new positions (`meshes`, one per level, None for a
/// level without a mesh, whose flags are its finer level's), or None when
/// the walls' structure changed (an unknown became pinned or stopped being pinned): the caller
/// then rebuilds the hierarchy. Some(empty) when the hierarchy has no slip wall.
pub(super) fn moved_frames(levels: &[Level], meshes: &[Option<&Mesh>]) -> Option<Vec<MovedFrames>> {
    let bcs = match levels[0].slip.as_ref() {
        None => return Some(Vec::new()),
        Some(s) => s.bcs.as_ref().expect("the finest level keeps its conditions"),
    };
    let mut out: Vec<MovedFrames> = Vec::new();
    for (l, (level, mesh)) in levels.iter().zip(meshes).enumerate() {
        let mut flags: Vec<Vec<u8>> = match mesh {
            Some(mesh) => (0..level.dim()).map(|c| component_flags(mesh, &level.dofs, bcs, c)).collect(),
            None => {
                let map = fine_dofs(level, &levels[l - 1]);
                out[l - 1].1.iter().map(|f| map.iter().map(|&d| f[d as usize]).collect()).collect()
            }
        };
        let frames = if l == 0 {
            fine_slip_frames(mesh.expect("the finest level has a mesh"), &level.dofs, bcs, &mut flags)
        } else {
            let fine = out[l - 1].0.as_ref();
            fine.and_then(|f| inherit_slip_frames(f, &fine_dofs(level, &levels[l - 1]), &mut flags))
        };
        let old = level.slip.as_ref().map(|s| &s.frames);
        let same = match (old, &frames) {
            (None, None) => true,
            (Some(a), Some(b)) => a.dofs == b.dofs && a.pinned == b.pinned && a.axes == b.axes,
            _ => false,
        };
        if !same || flags != level.flags {
            return None;
        }
        out.push((frames, flags));
    }
    Some(out)
}

/// Replaces the frames of `level` (after `moved_frames`), keeping what else it has.
pub(super) fn set_frames(level: &mut Level, frames: Option<SlipFrames>) {
    if let (Some(s), Some(f)) = (level.slip.as_mut(), frames) {
        s.frames = f;
    }
}

/// The same Jacobi diagonal for every free component of a slip unknown (the largest D of its
/// components): D⁻¹ then commutes with Π, and a larger D keeps the l1 bound's A ≤ D.
pub(crate) fn equalise_bounds(level: &mut Level) {
    let Some(s) = level.slip.as_ref().filter(|s| s.coupled) else {
        return;
    };
    for &d in &s.frames.dofs {
        let d = d as usize;
        let free = |c: &usize| level.flags[*c][d] & P == 0;
        let m = (0..level.dim()).filter(free).map(|c| level.inv_d[c][d]).fold(f64::INFINITY, f64::min);
        for c in (0..level.dim()).filter(free) {
            level.inv_d[c][d] = m;
        }
    }
    if level.op.method == Method::Biharmonic {
        // The components' own estimates bound it from above, but loosely: the slip unknowns'
        // normal directions, which Π removes, carry the top of their spectra, and a smoother
        // tuned to too large a λmax damps the high modes less.
        let l = estimate_lambda_max(&GroupOp::new(level, 0..level.dim(), false));
        level.lambda_max.iter_mut().for_each(|x| *x = l);
    }
}
