//! Slip walls at the solver (docs/DESIGN.md §4, "Slip walls"): the prescribed normal part of the
//! displacement at every slip unknown, and after the solve the slipped vertices moved from their
//! walls' tangent planes onto the walls themselves.

use crate::bc::{SlipWalls, P};
use crate::motion::Motion;
use crate::multigrid::hierarchy::Level;

/// The prescribed part of the displacement at the slip unknowns, Σ (e · v) e over each one's
/// constrained directions e with v the motion's value there, as `dim` blocks of n values (zero
/// off slip unknowns); None when the level has no slip unknown.
pub(super) fn normal_parts(lev: &Level, vals: &[f64]) -> Option<Vec<f64>> {
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

/// The SLIP patches `motion` moves (a rigid motion, or a displacement with a normal part at one
/// of their vertices): their walls move with them, so their original shape no longer holds.
pub(super) fn moving_patches(walls: &SlipWalls, lev: &Level, motion: &Motion, vals: &[f64]) -> Vec<i32> {
    let dim = lev.dim();
    let mut out: Vec<i32> = motion.rigid.iter().map(|&(p, _)| p).collect();
    if let Some(s) = lev.slip.as_ref() {
        for (k, &d) in s.frames.dofs.iter().enumerate() {
            for &v in lev.dofs.vertices_of(d as usize) {
                let mut x = [0.0; 3];
                x[..dim].copy_from_slice(&vals[v as usize * dim..(v as usize + 1) * dim]);
                if s.frames.normal_part(k, &x).iter().any(|&a| a != 0.0) {
                    out.extend(walls.patches_of(v));
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Moves every slipped vertex of the result onto its walls (`displacement`: `dim` values per
/// vertex, from the positions of `lev`'s mesh). Walls in `moving` are left alone, and so are
/// unknowns with a prescribed component (the projection would change it). Returns the largest
/// distance from the walls after and before: (`max_slip_offwall`, `max_slip_correction`).
pub(super) fn onto_walls(walls: &SlipWalls, lev: &Level, moving: &[i32], displacement: &mut [f64]) -> (f64, f64) {
    let Some(s) = lev.slip.as_ref() else {
        return (0.0, 0.0);
    };
    let dim = lev.dim();
    let (mut after, mut before) = (0.0f64, 0.0f64);
    let mut patches: Vec<i32> = Vec::new();
    for (k, &d) in s.frames.dofs.iter().enumerate() {
        if (0..dim).any(|c| lev.flags[c][d as usize] & P != 0) {
            continue;
        }
        let edge = s.frames.directions(k).len() > 1;
        for &v in lev.dofs.vertices_of(d as usize) {
            patches.clear();
            patches.extend(walls.patches_of(v).filter(|p| moving.binary_search(p).is_err()));
            if patches.is_empty() {
                continue;
            }
            let v = v as usize;
            let x0 = lev.mesh.point(v);
            let mut p: Vec<f64> = (0..dim).map(|c| x0[c] + displacement[v * dim + c]).collect();
            before = before.max(walls.distance(&patches, edge, &p));
            walls.project(&patches, edge, &mut p);
            after = after.max(walls.distance(&patches, edge, &p));
            (0..dim).for_each(|c| displacement[v * dim + c] = p[c] - x0[c]);
        }
    }
    (after, before)
}
