//! Slip walls at the solver (docs/DESIGN.md §4, "Slip walls"): the prescribed normal part of the
//! displacement at every slip unknown, and after the solve the slipped vertices moved from their
//! walls' tangent planes onto the walls themselves, where the walls are (a wall moved rigidly
//! carries its shape along).

use crate::bc::{Constraint, Placements, SlipWalls, P};
use crate::motion::Motion;
use crate::multigrid::hierarchy::Level;

/// The prescribed part of the displacement at the slip unknowns, Σ (e · v) e over each one's
/// constrained directions e with v the motion's value there, as `dim` blocks of n values (zero
/// off slip unknowns); None when the level has no slip unknown.
pub(crate) fn normal_parts(lev: &Level, vals: &[f64]) -> Option<Vec<f64>> {
    let frames = &lev.slip.as_ref()?.frames;
    if frames.dofs.is_empty() {
        return None;
    }
    let (n, dim) = (lev.n(), lev.dim());
    let mut g = vec![0.0; dim * n];
    for (k, &d) in frames.dofs.iter().enumerate() {
        let v0 = lev.dofs.vertices_of(d as usize)[0] as usize;
        let mut v = [0.0; 3];
        v[..dim].copy_from_slice(&vals[v0 * dim..(v0 + 1) * dim]);
        let np = frames.normal_part(k, &v);
        (0..dim).for_each(|c| g[c * n + d as usize] = np[c]);
    }
    Some(g)
}

/// The SLIP patches `motion` deforms: a displacement with a normal part at a vertex that lies on
/// no rigidly moved patch. Their shape no longer holds; a rigidly moved wall keeps its shape and
/// is placed where the motion takes it.
pub(crate) fn deformed_patches(walls: &SlipWalls, lev: &Level, motion: &Motion, vals: &[f64]) -> Vec<i32> {
    let dim = lev.dim();
    let rigid = |p: i32| motion.rigid.iter().any(|&(q, _)| q == p);
    let mut out: Vec<i32> = Vec::new();
    if let Some(s) = lev.slip.as_ref() {
        for (d, c) in s.frames.constrained() {
            for &v in lev.dofs.vertices_of(d as usize) {
                let x = &vals[v as usize * dim..(v as usize + 1) * dim];
                if !walls.patches_of(v).any(rigid) && s.frames.has_normal_part(c, x) {
                    out.extend(walls.patches_of(v));
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Each slipped vertex of a result that is to be moved onto its walls, with the walls it lies on
/// and whether it is on an edge where walls meet: walls in `deformed` are left alone, and so are
/// unknowns with a prescribed component (moving them would change it).
fn slipped<'a>(
    walls: &'a SlipWalls,
    lev: &'a Level,
    deformed: &'a [i32],
) -> impl Iterator<Item = (usize, Vec<i32>, bool)> + 'a {
    let dim = lev.dim();
    let frames = lev.slip.as_ref().map(|s| &s.frames);
    // A component prescribed other than by the unknown's own axis walls excludes it.
    let own = |c: Constraint| if let Constraint::Axes(mask) = c { mask } else { 0 };
    frames
        .into_iter()
        .flat_map(move |f| f.constrained().map(move |(d, c)| (d, own(c), f.count(c))))
        .filter(move |&(d, mask, _)| (0..dim).all(|c| mask & 1 << c != 0 || lev.flags[c][d as usize] & P == 0))
        .flat_map(move |(d, _, count)| {
            lev.dofs.vertices_of(d as usize).iter().filter_map(move |&v| {
                let patches: Vec<i32> = walls.patches_of(v).filter(|p| deformed.binary_search(p).is_err()).collect();
                (!patches.is_empty()).then_some((v as usize, patches, count > 1))
            })
        })
}

/// The prescribed values of a second solve that puts the slipped vertices of the result
/// `displacement` on their walls (placed as `at` says): `vals` with each slipped vertex's value
/// replaced by its displacement to the closest point of its walls (the solve reads its normal
/// part). None when every slipped vertex is on its walls already (flat walls).
pub(super) fn on_wall_values(
    walls: &SlipWalls,
    at: &Placements,
    lev: &Level,
    deformed: &[i32],
    vals: &[f64],
    displacement: &[f64],
) -> Option<Vec<f64>> {
    off_walls(walls, at, lev, deformed, displacement).then(|| wall_values(walls, at, lev, deformed, vals, displacement))
}

/// The position of vertex `v` of `lev`'s mesh moved by `displacement`.
pub(crate) fn moved(lev: &Level, displacement: &[f64], v: usize) -> Vec<f64> {
    let (dim, x0) = (lev.dim(), lev.mesh().point(v));
    (0..dim).map(|c| x0[c] + displacement[v * dim + c]).collect()
}

/// Some slipped vertex of the result `displacement` is off its walls (placed as `at` says)
/// beyond rounding: the walls are curved there.
pub(crate) fn off_walls(
    walls: &SlipWalls,
    at: &Placements,
    lev: &Level,
    deformed: &[i32],
    displacement: &[f64],
) -> bool {
    slipped(walls, lev, deformed).any(|(v, patches, edge)| {
        let p = moved(lev, displacement, v);
        !on_wall(walls.distance(at, &patches, edge, &p), &p)
    })
}

/// `vals` with each slipped vertex's value replaced by its displacement to the closest point of
/// its walls (see `on_wall_values`).
pub(crate) fn wall_values(
    walls: &SlipWalls,
    at: &Placements,
    lev: &Level,
    deformed: &[i32],
    vals: &[f64],
    displacement: &[f64],
) -> Vec<f64> {
    let dim = lev.dim();
    let mut out = vals.to_vec();
    for (v, patches, edge) in slipped(walls, lev, deformed) {
        let x0 = lev.mesh().point(v);
        let mut p = moved(lev, displacement, v);
        walls.project(at, &patches, edge, &mut p);
        (0..dim).for_each(|c| out[v * dim + c] = p[c] - x0[c]);
    }
    out
}

/// Whether a slipped vertex at `p` is `off` from its wall by rounding only (1e-13 of its
/// coordinates).
fn on_wall(off: f64, p: &[f64]) -> bool {
    off <= 1e-13 * p.iter().fold(1.0f64, |m, x| m.max(x.abs()))
}

/// Moves every slipped vertex of the result onto its walls, placed as `at` says
/// (`displacement`: `dim` values per vertex, from the positions of `lev`'s mesh). Returns the
/// largest distance from the walls after and before: (`max_slip_offwall`,
/// `max_slip_correction`).
pub(crate) fn onto_walls(
    walls: &SlipWalls,
    at: &Placements,
    lev: &Level,
    deformed: &[i32],
    displacement: &mut [f64],
) -> (f64, f64) {
    let dim = lev.dim();
    let (mut after, mut before) = (0.0f64, 0.0f64);
    for (v, patches, edge) in slipped(walls, lev, deformed) {
        let x0 = lev.mesh().point(v);
        let mut p = moved(lev, displacement, v);
        let off = walls.distance(at, &patches, edge, &p);
        before = before.max(off);
        // On its wall to rounding (a flat wall): left where the solve put it, which the
        // closest-point arithmetic would move by rounding along the wall.
        if on_wall(off, &p) {
            after = after.max(off);
            continue;
        }
        walls.project(at, &patches, edge, &mut p);
        after = after.max(walls.distance(at, &patches, edge, &p));
        (0..dim).for_each(|c| displacement[v * dim + c] = p[c] - x0[c]);
    }
    (after, before)
}
