//! SLIP walls on a rank's part (docs/DESIGN.md §4 "Slip walls", §5 "Across ranks"): the slip
//! frames of the vertices the rank owns, from the wall faces its part holds at them (all of
//! them: every cell around an owned vertex is owned or a ghost), and the curved walls' second
//! solve decided over every rank.
//!
//! Halo vertices carry P in every component, so they get no frame: Π acts on owned entries
//! only, and the halo of a vector is its owners' values, projected by them. Whether the walls
//! couple the components (some rank has a slip unknown whose walls are not normal to an axis)
//! is decided over every rank, so every rank solves the same groups with the same smoother.

use super::error::{DistError, DistErrorKind};
use super::halo::HaloLayout;
use super::reduce::{gather_varcount, max_over_ranks};
use crate::bc::{fine_slip_frames, BoundaryConditions, Dofs, Placements, SlipFrames, SlipWalls};
use crate::multigrid::level::{Level, LevelSlip};
use crate::solver::slip::{deformed_patches, moved, off_walls, onto_walls, wall_values};
use crate::{Mesh, Motion};

/// The slip frames of the owned vertices of `mesh` (layout order) under `bcs`; pinned and axis
/// unknowns are made P in `flags` (per component, the halo already P). None without SLIP
/// patches; collective when `bcs` has some (the same on every rank).
pub(crate) fn frames(
    mesh: &Mesh,
    halo: &HaloLayout,
    bcs: &BoundaryConditions,
    flags: &mut [Vec<u8>],
) -> Option<LevelSlip> {
    if !bcs.any_slip() {
        return None;
    }
    let frames = fine_slip_frames(mesh, &Dofs::identity(mesh.num_vertices()), bcs, flags);
    let framed = frames.as_ref().is_some_and(|f| !f.dofs.is_empty());
    let coupled = max_over_ranks(halo.comm(), f64::from(u8::from(framed))) > 0.0;
    let frames = frames.unwrap_or_else(|| SlipFrames::empty(mesh.dim()));
    Some(LevelSlip { frames, bcs: Some(bcs.clone()), coupled })
}

/// The SLIP patches `motion` deforms on any rank (see `solver::slip::deformed_patches`),
/// ascending (collective).
fn deformed_everywhere(walls: &SlipWalls, level: &Level, halo: &HaloLayout, motion: &Motion, vals: &[f64]) -> Vec<i32> {
    let mine = deformed_patches(walls, level, motion, vals);
    let mut all: Vec<i32> = gather_varcount(halo.comm(), &mine).into_iter().flatten().collect();
    all.sort_unstable();
    all.dedup();
    all
}

/// Puts the slipped owned vertices of the result `displacement` (layout order, `dim` per
/// vertex, halo current) on their walls, as the serial solver does: when a slipped vertex of
/// any rank is off its walls, `again` solves with their distances to the walls prescribed as
/// normal parts (its arguments: the prescribed values and the first result); then what remains
/// is moved onto the walls and the halo refreshed. A closest-point function's failure on any
/// rank fails every rank, naming the lowest such rank and the global id (`gids`, layout order)
/// of a vertex it failed at (collective).
#[allow(clippy::too_many_arguments)]
pub(crate) fn onto_walls_everywhere(
    walls: &SlipWalls,
    level: &Level,
    halo: &HaloLayout,
    gids: &[u64],
    motion: &Motion,
    vals: &[f64],
    mut displacement: Vec<f64>,
    again: impl FnOnce(&[f64], &[f64]) -> Result<Vec<f64>, DistError>,
) -> Result<Vec<f64>, DistError> {
    walls.take_failure();
    let at = walls.placed_by(&motion.rigid);
    let deformed = deformed_everywhere(walls, level, halo, motion, vals);
    let off = off_walls(walls, &at, level, &deformed, &displacement);
    let checked = |d: &[f64]| callbacks_succeeded(walls, &at, level, halo, gids, d);
    if max_over_ranks(halo.comm(), f64::from(u8::from(off))) > 0.0 {
        let on_wall = wall_values(walls, &at, level, &deformed, vals, &displacement);
        checked(&displacement)?;
        displacement = again(&on_wall, &displacement)?;
    }
    let before = displacement.clone();
    onto_walls(walls, &at, level, &deformed, &mut displacement);
    checked(&before)?;
    refresh_interleaved(halo, &mut displacement, level.dim());
    Ok(displacement)
}

/// No rank's closest-point function reported a failure since the last check (collective). A
/// rank whose did names the first slipped vertex (of the result `displacement`) at which it
/// fails again.
fn callbacks_succeeded(
    walls: &SlipWalls,
    at: &Placements,
    level: &Level,
    halo: &HaloLayout,
    gids: &[u64],
    displacement: &[f64],
) -> Result<(), DistError> {
    let me = halo.comm().rank();
    let local = if walls.take_failure() {
        let frames = level.slip.as_ref().map(|s| &s.frames);
        let failing = frames.into_iter().flat_map(|f| f.constrained()).map(|(d, _)| d as usize).find(|&v| {
            let x = moved(level, displacement, v);
            walls.patches_of(v as u32).for_each(|p| {
                walls.closest(at, p, &x);
            });
            walls.take_failure()
        });
        let whose = failing.map_or(String::new(), |v| format!(" (at global id {})", gids[v]));
        Err(DistError::new(
            me,
            DistErrorKind::Input,
            format!("a slip wall's closest-point function reported a failure{whose}; nothing was changed"),
        ))
    } else {
        Ok(())
    };
    super::agreement::agree(halo.comm(), local)
}

/// Makes the halo of a field of `dim` values per local vertex its owners'.
fn refresh_interleaved(halo: &HaloLayout, v: &mut [f64], dim: usize) {
    let n = v.len() / dim;
    let mut block = vec![0.0; n];
    for c in 0..dim {
        (0..n).for_each(|i| block[i] = v[i * dim + c]);
        halo.refresh(&mut block);
        (0..n).for_each(|i| v[i * dim + c] = block[i]);
    }
}
