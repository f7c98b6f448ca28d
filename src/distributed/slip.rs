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
use super::ties::Ties;
use crate::bc::{slip_frames_from_areas, BoundaryConditions, Placements, SlipFrames, SlipWalls, WallAreas};
use crate::multigrid::level::{Level, LevelSlip};
use crate::solver::slip::{deformed_patches, moved, off_walls, onto_walls, wall_values};
use crate::{Mesh, Motion};

/// The slip frames of the owned vertices of `mesh` (layout order) under `bcs`; pinned and axis
/// unknowns are made P in `flags` (per component, the halo already P; a tied vertex's flags
/// already its class's). A tied vertex (periodic links, `ties`) takes the frame one process
/// gives the merged unknown of its class: from the SLIP faces at every member of the class, on
/// whichever rank, so every member has the same frame. None without SLIP patches; collective
/// when `bcs` has some (the same on every rank).
pub(crate) fn frames(
    mesh: &Mesh,
    halo: &HaloLayout,
    bcs: &BoundaryConditions,
    flags: &mut [Vec<u8>],
    ties: Option<&Ties>,
) -> Option<LevelSlip> {
    if !bcs.any_slip() {
        return None;
    }
    let walls = WallAreas::new(mesh, bcs);
    let joined = ties.map(|t| t.joined_lists(|v| walls.at(v).collect())).unwrap_or_default();
    let areas = |v: usize, out: &mut Vec<[f64; 3]>| match ties.and_then(|t| t.class_of(v)) {
        Some(c) => out.extend(joined.get(&c).into_iter().flatten()),
        None => out.extend(walls.at(v)),
    };
    let frames = slip_frames_from_areas(mesh.dim(), mesh.num_vertices(), areas, flags);
    let framed = frames.as_ref().is_some_and(|f| !f.dofs.is_empty());
    let coupled = max_over_ranks(halo.comm(), f64::from(u8::from(framed))) > 0.0;
    let frames = frames.unwrap_or_else(|| SlipFrames::empty(mesh.dim()));
    Some(LevelSlip { frames, bcs: Some(bcs.clone()), coupled })
}

/// The SLIP patches `motion` deforms on any rank (see `solver::slip::deformed_patches`; none
/// on a rank without walls), ascending (collective).
fn deformed_everywhere(
    walls: Option<(&SlipWalls, &Placements)>,
    level: &Level,
    halo: &HaloLayout,
    motion: &Motion,
    vals: &[f64],
) -> Vec<i32> {
    let mine = walls.map(|(w, _)| deformed_patches(w, level, motion, vals)).unwrap_or_default();
    let mut all: Vec<i32> = gather_varcount(halo.comm(), &mine).into_iter().flatten().collect();
    all.sort_unstable();
    all.dedup();
    all
}

/// Puts the slipped owned vertices of the result `displacement` (layout order, `dim` per
/// vertex, halo current) on their walls, as the serial solver does: when a slipped vertex of
/// any rank is off its walls, `again` solves with their distances to the walls prescribed as
/// normal parts (its arguments: the prescribed values and the first result); then what remains
/// is moved onto the walls and the halo refreshed. `walls` are the rank's SLIP walls, None on a
/// rank whose part has no SLIP face, which takes part in the collectives all the same. A
/// closest-point function's failure on any rank fails every rank, naming the lowest such rank
/// and the global id (`gids`, layout order) of a vertex it failed at (collective).
#[allow(clippy::too_many_arguments)]
pub(crate) fn onto_walls_everywhere(
    walls: Option<&SlipWalls>,
    level: &Level,
    halo: &HaloLayout,
    gids: &[u64],
    motion: &Motion,
    vals: &[f64],
    mut displacement: Vec<f64>,
    again: impl FnOnce(&[f64], &[f64]) -> Result<Vec<f64>, DistError>,
) -> Result<Vec<f64>, DistError> {
    let placed = walls.map(|w| {
        w.take_failure();
        (w, w.placed_by(&motion.rigid))
    });
    let mine = placed.as_ref().map(|(w, at)| (*w, at));
    let deformed = deformed_everywhere(mine, level, halo, motion, vals);
    let off = mine.is_some_and(|(w, at)| off_walls(w, at, level, &deformed, &displacement));
    let checked = |d: &[f64]| callbacks_succeeded(mine, level, halo, gids, d);
    if max_over_ranks(halo.comm(), f64::from(u8::from(off))) > 0.0 {
        let on_wall = match mine {
            Some((w, at)) => wall_values(w, at, level, &deformed, vals, &displacement),
            None => vals.to_vec(),
        };
        checked(&displacement)?;
        displacement = again(&on_wall, &displacement)?;
    }
    let before = displacement.clone();
    if let Some((w, at)) = mine {
        onto_walls(w, at, level, &deformed, &mut displacement);
    }
    checked(&before)?;
    refresh_interleaved(halo, &mut displacement, level.dim());
    Ok(displacement)
}

/// No rank's closest-point function reported a failure since the last check (collective; a
/// rank without walls has none). A rank whose did names the first slipped vertex (of the
/// result `displacement`) at which it fails again.
fn callbacks_succeeded(
    walls: Option<(&SlipWalls, &Placements)>,
    level: &Level,
    halo: &HaloLayout,
    gids: &[u64],
    displacement: &[f64],
) -> Result<(), DistError> {
    let me = halo.comm().rank();
    let local = match walls.filter(|(w, _)| w.take_failure()) {
        Some((walls, at)) => {
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
        }
        None => Ok(()),
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

/// With SLIP walls and periodic links, the prescribed values `vals` (`dim` per local vertex,
/// layout order) with every owned tied vertex's taken from its class's first member (the
/// vertex of its lowest global id): one process reads a merged unknown's first vertex for the
/// normal parts of its slip walls and the components its axis walls prescribe. None without
/// either (collective).
pub(crate) fn class_first_values(level: &Level, ties: Option<&Ties>, vals: &[f64]) -> Option<Vec<f64>> {
    let (ties, _) = ties.zip(level.slip.as_ref())?;
    let (dim, n) = (level.dim(), vals.len() / level.dim());
    let mut out = vals.to_vec();
    let mut block = vec![0.0; n];
    for c in 0..dim {
        (0..n).for_each(|i| block[i] = vals[i * dim + c]);
        ties.take_firsts(&mut block);
        (0..n).for_each(|i| out[i * dim + c] = block[i]);
    }
    Some(out)
}
