//! The biharmonic's first iterate under wall layers (docs/DESIGN.md §5, "The first
//! iterate"). A zero start leaves the whole motion of a CLAMPED body as error between the wall and
//! its first layer, a cell 10⁻⁵–10⁻⁴ of the body thick: the iterations that take it out meet the
//! relative residual long before the first layer follows the wall (the stop test under wall
//! layers then holds the solve on). The clamped layers move with the body (the rigid flux holds
//! their spacing), so each line of strong coupling that hangs off a CLAMPED patch moved rigidly
//! starts at that rigid motion. Beyond the lines' outer ends the start falls off to the fixed
//! boundary's zero by the distances to both (`reach`): a start of zero there would leave the
//! whole motion as a jump across the cells at each line's outer end, whose stretch grows as
//! those cells shrink with the mesh's size, and the stop test on every edge's stretch would
//! hold the solve on the more iterations the finer the mesh.

mod reach;

use super::ROUNDING;
use crate::bc::{BoundaryConditions, Kind, P};
use crate::motion::Motion;
use crate::multigrid::hierarchy::Hierarchy;
use crate::operator::Method;

/// The first iterate of a biharmonic solve with no guess (`dim` values per vertex) when its
/// finest level has lines hanging off a CLAMPED patch that `motion` moves rigidly: each such
/// line's vertices (and the patch's) at the patch's rigid displacement; every other vertex at
/// the rigid displacement of the patch nearest it, weighted by (d_fixed / (d_body + d_fixed))², its
/// distances through K's graph to those lines and to the unknowns prescribed in every component
/// (at zero where no such unknown exists). None when no line hangs off such a patch (the solve
/// starts from zero).
pub(crate) fn of_layers(h: &Hierarchy, bcs: &BoundaryConditions, motion: &Motion) -> Option<Vec<f64>> {
    let lev = h.fine();
    if lev.op.method != Method::Biharmonic || lev.lines.is_empty() || motion.rigid.is_empty() {
        return None;
    }
    let (mesh, dim, k) = (lev.mesh(), lev.dim(), &lev.op.k);
    let lines = lev.lines.lines();
    // Per unknown, the rigid motion (its index in `motion.rigid`) that starts it: a line's
    // unknowns and the patch's own.
    let mut moved: Vec<Option<usize>> = vec![None; lev.n()];
    for (r, &(patch, _)) in motion.rigid.iter().enumerate() {
        if (0..dim).any(|c| bcs.kind(patch, c) != Kind::Clamped) {
            continue;
        }
        let mut on_patch = vec![false; mesh.num_vertices()];
        mesh.patch_vertices(patch).iter().for_each(|&v| on_patch[v as usize] = true);
        let held = |d: usize| lev.dofs.vertices_of(d).iter().any(|&v| on_patch[v as usize]);
        // An end of a line is on the patch, or a neighbour of it in K's graph.
        let at_patch = |d: usize| {
            held(d) || k.cols[k.row_ptr[d] as usize..k.row_ptr[d + 1] as usize].iter().any(|&j| held(j as usize))
        };
        let mut any = false;
        for l in 0..lines.len() {
            let line = lines.line(l);
            let (Some(&first), Some(&last)) = (line.first(), line.last()) else { continue };
            if !at_patch(first as usize) && !at_patch(last as usize) {
                continue;
            }
            any = true;
            line.iter().for_each(|&d| moved[d as usize] = Some(r));
        }
        if any {
            (0..lev.n()).filter(|&d| held(d)).for_each(|d| moved[d] = Some(r));
        }
    }
    if moved.iter().all(Option::is_none) {
        return None;
    }
    let points = lev.unknown_points();
    let n = lev.n();
    let mut start = vec![0.0; mesh.coords().len()];
    // The components the blend below carries: `put` sets only those it is given.
    let put = |start: &mut [f64], d: usize, r: usize, w: f64, comps: &[bool]| {
        let m = &motion.rigid[r].1;
        for &v in lev.dofs.vertices_of(d) {
            let v = v as usize;
            let l = m.displacement(mesh.point(v));
            for c in (0..dim).filter(|&c| comps[c]) {
                start[v * dim + c] = w * l[c];
            }
        }
    };
    let every = vec![true; dim];
    (0..n).for_each(|d| {
        if let Some(r) = moved[d] {
            put(&mut start, d, r, 1.0, &every)
        }
    });
    // Beyond the lines' outer ends the start falls off from the rigid motion to the fixed
    // boundary's zero as the square of the distances' blend, (d_fixed / (d_body + d_fixed))²:
    // the start's error is then smooth there, not a jump of the whole motion across one cell at
    // each line's end (a jump whose stretch grows as the cells there shrink with the mesh's
    // size). The square falls off faster than the blend itself away from the body, as the
    // biharmonic's solution does, and leaves less error far from it (docs/PERFORMANCE.md).
    // A component the body moves by rounding alone (a rotation about a coordinate axis leaves
    // that axis's component at the rounding of cos θ + (1 − cos θ)) has a right-hand side of
    // rounding, against which the blend's values would be a residual to take out: it starts at
    // zero beyond the lines.
    let most: Vec<f64> =
        (0..dim).map(|c| start.iter().skip(c).step_by(dim).fold(0.0f64, |a, s| a.max(s.abs()))).collect();
    let largest = most.iter().copied().fold(0.0f64, f64::max);
    let blended: Vec<bool> = most.iter().map(|&m| m > ROUNDING * largest).collect();
    let fixed: Vec<bool> = (0..n).map(|d| moved[d].is_none() && lev.flags.iter().all(|f| f[d] & P != 0)).collect();
    if fixed.iter().any(|&f| f) {
        let source: Vec<bool> = moved.iter().map(Option::is_some).collect();
        let (to_body, from) = reach::nearest(k, &points, dim, &source);
        let to_fixed = reach::distances(k, &points, dim, &fixed);
        for d in 0..n {
            if moved[d].is_some() || fixed[d] || !to_body[d].is_finite() {
                continue;
            }
            let w = if to_fixed[d].is_finite() { (to_fixed[d] / (to_body[d] + to_fixed[d])).powi(2) } else { 1.0 };
            if let Some(r) = from[d].and_then(|f| moved[f]) {
                put(&mut start, d, r, w, &blended);
            }
        }
    }
    Some(start)
}
