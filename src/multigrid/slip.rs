//! Slip walls in the multigrid solve (docs/DESIGN.md §4 "Slip walls", §5): the components are one
//! group, and every vector of the group lives in the subspace the slip frames leave free.
//!
//! With Π the projection that removes each slip unknown's constrained directions (`SlipFrames`),
//! the system is Π A Π w = Π (b − A g), g the prescribed normal parts. The pieces:
//!
//! - residuals and products are projected (`Level::residual`, `Level::apply` call `project`);
//! - the smoother runs the components in lockstep with one polynomial (the largest λmax of the
//!   group) and projects its step; its Jacobi diagonal is made the same for every component at a
//!   slip unknown (`equalise_bounds`), so D⁻¹ commutes with Π and the projected step is the
//!   smoother of Π A Π, with the l1 bound's guarantee intact;
//! - restriction is Π_c Pᵀ and prolongation Π_f P: the coarse levels carry the frames of the
//!   fine unknowns their vertices are (`attach`), so they solve the constrained problem too;
//! - the coarsest level solves the coupled system densely in a basis of the free directions
//!   (`GroupCoarse`).
//!
//! The cycle stays symmetric on the subspace, so it preconditions CG as before.

use super::coarse_solve::{symmetric_cholesky, DENSE_MAX};
use super::cycle::CycleParams;
use super::hierarchy::{Hierarchy, Level};
use super::solve::{Mode, SolveParams};
use super::smoother::{first_kind, first_step, fourth_kind, next_step, Scratch, Smoother, Start};
use crate::bc::{component_flags, fine_slip_frames, inherit_slip_frames, BoundaryConditions, SlipFrames, P};
use crate::dense::Cholesky;
use crate::operator::Method;
use crate::sparse::max_abs;
use crate::{Error, Mesh, Result};
use std::ops::Range;

/// What a level keeps for its slip walls.
pub struct LevelSlip {
    /// The constrained directions of the level's slip unknowns.
    pub frames: SlipFrames,
    /// The coupled solve of the coarsest level.
    pub coarse: Option<GroupCoarse>,
    /// The conditions the fine level's frames come from, to remake them at a new reference (fine
    /// level only).
    bcs: Option<BoundaryConditions>,
    /// The components are one coupled system: the finest level has slip unknowns with frames
    /// (walls not normal to an axis). Without, the walls only prescribe components (axis walls,
    /// pinned corners) and the components are solved apart. Every level has its finest's.
    pub coupled: bool,
}

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
            .map(|frames| LevelSlip { coupled: !frames.dofs.is_empty(), frames, coarse: None, bcs: Some(bcs.clone()) }),
        Some(f) => f.slip.as_ref().and_then(|s| {
            let map = fine_dofs(level, f);
            inherit_slip_frames(&s.frames, &map, &mut level.flags).map(|frames| LevelSlip {
                frames,
                coarse: None,
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
        s.coarse = None;
    }
}

/// The frames of `level` when they apply to the components `comps` (the whole displacement of a
/// coupled hierarchy: a slip wall with frames couples every component).
pub(super) fn frames_for<'a>(level: &'a Level, comps: &Range<usize>) -> Option<&'a LevelSlip> {
    level.slip.as_ref().filter(|s| s.coupled && comps.len() == level.dim() && comps.len() > 1)
}

/// The level's components are one coupled system (see `LevelSlip::coupled`).
pub(super) fn coupled(level: &Level) -> bool {
    level.slip.as_ref().is_some_and(|s| s.coupled)
}

/// The W-cycle of a hierarchy with slip walls: the biharmonic's coarse levels smoothed with the
/// finest level's degree (6 on coarse meshes) instead of 4, unless the caller chose the degrees
/// (kept unknowns smooth every level at one degree already). Natural (tangential) conditions on
/// the walls make the rediscretised coarse operators' boundary rows a poorer match (measured on
/// the cylinder channel with its walls SLIP, 6 levels: 15 CG iterations at the default degrees
/// against 9 with FIXED walls, 10 with coarse degree 6; FREE walls: 18 and 10).
pub(crate) fn cycle_for(h: &Hierarchy, p: &SolveParams, cp: &mut CycleParams) {
    let slip = h.fine().slip.is_some();
    if slip && h.method == Method::Biharmonic && p.mode == Mode::Default && p.cheb_coarse_degree.is_none() {
        cp.coarse_smoother = cp.smoother;
    }
}

/// u ← Π u on `level` for the group `comps` (nothing without slip frames).
pub(super) fn project(level: &Level, comps: &Range<usize>, u: &mut [f64]) {
    if let Some(s) = frames_for(level, comps) {
        s.frames.project(level.n(), u);
    }
}

/// The same Jacobi diagonal for every free component of a slip unknown (the largest D of its
/// components): D⁻¹ then commutes with Π, and a larger D keeps the l1 bound's A ≤ D.
pub(super) fn equalise_bounds(level: &mut Level) {
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
        let l = coupled_lambda_max(level);
        level.lambda_max.iter_mut().for_each(|x| *x = l);
    }
}

/// The largest eigenvalue of D⁻¹ Π A Π on the free subspace of the coupled group, by power
/// iteration from a fixed start (as `smoother::estimate_lambda_max` for one component), padded by
/// 10% and capped at 1. The components' own estimates bound it from above, but loosely: the
/// slip unknowns' normal directions, which Π removes, carry the top of their spectra, and a
/// smoother tuned to too large a λmax damps the high modes less (measured on the channel of the
/// cylinder with SLIP walls: 15 CG iterations with the components' largest estimate, against 9
/// with FIXED walls).
fn coupled_lambda_max(level: &Level) -> f64 {
    let (n, dim) = (level.n(), level.dim());
    let frames = &level.slip.as_ref().expect("slip level").frames;
    let mut x: Vec<f64> = (0..dim * n)
        .map(|k| {
            let (c, i) = (k / n, k % n);
            if level.flags[c][i] & P != 0 {
                0.0
            } else {
                ((k as u64).wrapping_mul(2654435761) % 1000) as f64 / 1000.0 - 0.5
            }
        })
        .collect();
    frames.project(n, &mut x);
    let (mut y, mut s) = (vec![0.0; dim * n], vec![0.0; n]);
    let mut lambda = 0.0;
    for _ in 0..15 {
        let nx = crate::sparse::dot(&x, &x).sqrt();
        if nx == 0.0 {
            return 1.0;
        }
        x.iter_mut().for_each(|v| *v /= nx);
        for c in 0..dim {
            let blk = c * n..(c + 1) * n;
            level.op.apply(&level.flags[c], &x[blk.clone()], &mut y[blk.clone()], &mut s);
            y[blk.clone()].iter_mut().zip(&level.inv_d[c]).for_each(|(y, d)| *y *= d);
        }
        frames.project(n, &mut y);
        lambda = crate::sparse::dot(&y, &y).sqrt();
        std::mem::swap(&mut x, &mut y);
    }
    (1.1 * lambda).clamp(0.05, 1.0)
}

/// Moves the blocks of `x` and `d` (one per component) into the free subspace.
fn project_blocks(frames: &SlipFrames, n: usize, x: &mut [f64], w: &mut [Scratch]) {
    frames.project(n, x);
    let mut d: Vec<&mut [f64]> = w.iter_mut().map(|s| s.d.as_mut_slice()).collect();
    frames.project_blocks(&mut d);
}

/// One application of the smoother `sm` to the coupled group `comps` of `level`: every component's
/// step of the same polynomial, then the step projected (see the module's comment). Returns the
/// largest correction when `measure` is set.
#[allow(clippy::too_many_arguments)]
pub(super) fn smooth_coupled(
    level: &Level,
    comps: Range<usize>,
    sm: Smoother,
    l1_bound: bool,
    b: &[f64],
    x: &mut [f64],
    w: &mut [Scratch],
    start: Start,
    measure: bool,
) -> f64 {
    let s = frames_for(level, &comps).expect("a coupled group");
    let n = level.n();
    let lmax = if l1_bound { 1.0 } else { comps.clone().map(|c| level.lambda_max[c]).fold(0.0, f64::max) };
    let (c0, steps): (f64, Vec<(f64, f64)>) = match sm {
        Smoother::Jacobi { weight } => (weight, Vec::new()),
        Smoother::Chebyshev { degree, lower_ratio } => {
            let (c0, st) = first_kind(lmax, degree, lower_ratio);
            (c0, st.collect())
        }
        Smoother::Fourth { degree } => {
            let (c0, st) = fourth_kind(lmax, degree);
            (c0, st.collect())
        }
    };
    let pb = |c: usize| {
        let mut p = level.problem(c);
        p.lambda_max = lmax;
        p
    };
    let measured = |w: &[Scratch]| if measure { w.iter().map(|s| max_abs(&s.d)).fold(0.0, f64::max) } else { 0.0 };
    for (k, c) in comps.clone().enumerate() {
        let blk = k * n..(k + 1) * n;
        first_step(pb(c), c0, &b[blk.clone()], &mut x[blk], &mut w[k], start);
    }
    project_blocks(&s.frames, n, x, w);
    let mut maxc = measured(w);
    for (c1, c2) in steps {
        for (k, c) in comps.clone().enumerate() {
            let blk = k * n..(k + 1) * n;
            next_step(pb(c), c1, c2, &b[blk.clone()], &mut x[blk], &mut w[k]);
        }
        project_blocks(&s.frames, n, x, w);
        maxc = maxc.max(measured(w));
    }
    maxc
}

/// The coarsest level's solve of the coupled group: Π A Π on a basis of the free directions
/// (unit vectors of free components; a slip unknown's tangents), dense Cholesky.
pub enum GroupCoarse {
    /// The basis vectors (unknown, coefficient per component) and the factor.
    Dense { basis: Vec<(u32, [f64; 3])>, chol: Cholesky },
    /// Too many free directions: a fixed Chebyshev polynomial of the coupled smoother.
    Smoothed,
    /// Nothing free: the correction is zero.
    Empty,
}

/// Builds the coupled coarse solve of `level` when it has slip frames.
pub(super) fn attach_coarse_solve(level: &mut Level) -> Result<()> {
    if !coupled(level) {
        return Ok(());
    }
    let gc = GroupCoarse::new(level)?;
    level.slip.as_mut().expect("checked").coarse = Some(gc);
    Ok(())
}

impl GroupCoarse {
    fn new(level: &Level) -> Result<GroupCoarse> {
        let (n, dim) = (level.n(), level.dim());
        let frames = &level.slip.as_ref().expect("slip level").frames;
        let mut basis: Vec<(u32, [f64; 3])> = Vec::new();
        let mut k = 0;
        for d in 0..n {
            let prescribed: Vec<bool> = (0..dim).map(|c| level.flags[c][d] & P != 0).collect();
            if frames.dofs.get(k) == Some(&(d as u32)) {
                basis.extend(frames.tangents(k, &prescribed).into_iter().map(|t| (d as u32, t)));
                k += 1;
            } else {
                for c in (0..dim).filter(|&c| !prescribed[c]) {
                    let mut e = [0.0; 3];
                    e[c] = 1.0;
                    basis.push((d as u32, e));
                }
            }
        }
        let m = basis.len();
        if m == 0 {
            return Ok(GroupCoarse::Empty);
        }
        if m > DENSE_MAX {
            return Ok(GroupCoarse::Smoothed);
        }
        // Column by column: A_c e_j for each unknown j and component c, then the basis vectors
        // at j combine them; basis vectors are grouped by unknown.
        let mut a = vec![0.0; m * m];
        let (mut e, mut s) = (vec![0.0; n], vec![0.0; n]);
        let mut y: Vec<Vec<f64>> = vec![vec![0.0; n]; dim];
        let mut first = 0;
        while first < m {
            let j = basis[first].0;
            let last = first + basis[first..].iter().take_while(|b| b.0 == j).count();
            for (c, yc) in y.iter_mut().enumerate() {
                if basis[first..last].iter().all(|b| b.1[c] == 0.0) {
                    yc.iter_mut().for_each(|v| *v = 0.0);
                    continue;
                }
                e[j as usize] = 1.0;
                level.op.apply(&level.flags[c], &e, yc, &mut s);
                e[j as usize] = 0.0;
            }
            for beta in first..last {
                let cb = basis[beta].1;
                for (alpha, &(i, ca)) in basis.iter().enumerate() {
                    a[alpha * m + beta] = (0..dim).map(|c| ca[c] * cb[c] * y[c][i as usize]).sum();
                }
            }
            first = last;
        }
        let chol = symmetric_cholesky(m, a).ok_or_else(|| {
            Error::Coarsening(format!(
                "the coarsest level's coupled slip operator is not positive definite ({m} free directions): a coarse \
                 cell is degenerate or inverted, or the slip walls leave a direction free"
            ))
        })?;
        Ok(GroupCoarse::Dense { basis, chol })
    }

    /// x ← x + (Π A Π)⁻¹ Π (b − A x) on the coupled group `comps` of `level`; from `Start::Zero`,
    /// x = (Π A Π)⁻¹ b. `r` is scratch of the group's length.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn solve(
        &self,
        level: &Level,
        comps: Range<usize>,
        l1_bound: bool,
        b: &[f64],
        x: &mut [f64],
        start: Start,
        r: &mut [f64],
        w: &mut [Scratch],
    ) {
        if start == Start::Zero {
            x.iter_mut().for_each(|v| *v = 0.0);
        }
        let n = level.n();
        match self {
            GroupCoarse::Empty => {}
            GroupCoarse::Smoothed => {
                let sm = Smoother::Chebyshev { degree: 25, lower_ratio: 200.0 };
                for _ in 0..4 {
                    smooth_coupled(level, comps.clone(), sm, l1_bound, b, x, w, Start::Guess, false);
                }
            }
            GroupCoarse::Dense { basis, chol } => {
                let r: &[f64] = match start {
                    Start::Zero => b,
                    Start::Guess => {
                        level.residual(comps.clone(), b, x, r, &mut w[0].s);
                        r
                    }
                };
                let dim = comps.len();
                let mut rhs: Vec<f64> =
                    basis.iter().map(|&(i, t)| (0..dim).map(|c| t[c] * r[c * n + i as usize]).sum()).collect();
                chol.solve(&mut rhs);
                for (&(i, t), v) in basis.iter().zip(rhs) {
                    for c in 0..dim {
                        x[c * n + i as usize] += t[c] * v;
                    }
                }
            }
        }
    }
}
