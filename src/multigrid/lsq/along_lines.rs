//! Interpolation along the lines of strong coupling across wall layers (`multigrid::lines`).
//!
//! Across a thin layer the coarse levels keep about every other unknown of each line, and the
//! error the line smoother leaves is smooth along the line. Linear interpolation between a
//! dropped unknown's two kept line neighbours puts a kink at every kept unknown, and the
//! biharmonic's energy (second derivatives) of such a kink is of the size of the smooth mode's
//! own: the coarse correction then removes little of that mode's energy. Cubic interpolation in
//! the distance along the line (two kept unknowns on either side, Lagrange weights) has no such
//! kinks to that order, and still reproduces linear fields where the line is straight, as the
//! lines across a layer extruded along the wall's normals are.
//!
//! A line is extended at each end by its end's nearest neighbour on the far side when that
//! neighbour is kept (the wall's unknown below the first layer, prescribed and so on no line),
//! so the first layer's unknowns interpolate from the wall too. Rows this cannot give (no kept
//! unknown on one side, a donor that may not interpolate the unknown, a line bent so much that
//! the weights miss linear fields, or weights of Σ|w| above `MAX_ABS_SUM`) are left to the
//! least-squares fit.

use super::Features;
use crate::multigrid::lines::Lines;
use crate::sparse::CsrMatrix;

/// Largest Σ|w| of a row along a line (uniform spacing gives 1.25; graded layers a little more).
const MAX_ABS_SUM: f64 = 2.0;

/// Largest residual of the linear fields, relative to the row's farthest donor, for a row along
/// a line to stand (a straight line's rows reproduce them to rounding).
const LINEAR_TOL: f64 = 1e-9;

/// Per fine unknown, its row of P along its line (coarse columns and weights), or None where
/// the least-squares fit decides. `coarse_of[u]` is u's coarse unknown (u32::MAX when dropped),
/// `points` the fine unknowns' positions (`f.dim()` values each), `k` the fine operator's graph.
/// Each row takes the two nearest kept unknowns on either side along the line (fewer where
/// the line has fewer) and their Lagrange weights in the distance along the line.
pub(super) fn rows(
    lines: &Lines,
    k: &CsrMatrix,
    f: &Features,
    points: &[f64],
    coarse_of: &[u32],
) -> Vec<Option<Vec<(u32, f64)>>> {
    let dim = f.dim();
    let at = |d: usize| &points[d * dim..(d + 1) * dim];
    let rel = |v: usize, u: usize| f.relative(v, u, at(v), at(u));
    let kept = |u: usize| coarse_of[u] != u32::MAX;
    let coarse = |u: usize| kept(u).then_some(coarse_of[u]);
    let mut out: Vec<Option<Vec<(u32, f64)>>> = vec![None; coarse_of.len()];
    let mut ext = Vec::new();
    for l in 0..lines.len() {
        let line = lines.line(l);
        let last = line.len() - 1;
        ext.clear();
        ext.extend(end_neighbour(k.row(line[0] as usize).0, line, 0, 1, &rel, kept, |u| u as u64));
        ext.extend(line.iter().map(|&v| v as usize));
        ext.extend(end_neighbour(k.row(line[last] as usize).0, line, last, last.wrapping_sub(1), &rel, kept, |u| u as u64));
        rows_on_line(&ext, &rel, coarse, |v, u| f.donor_ok(v, u), |v, row| out[v] = Some(row));
    }
    out
}

/// The rows along one line `ext` (its unknowns in order, extended at its ends as `rows` says):
/// each dropped unknown's kept unknowns around it on the line (`coarse(u)`: u's coarse column
/// when kept) with their Lagrange weights in the distance along the line, given to `put`
/// sorted by column; an unknown whose row the line cannot give (module documentation) gets
/// none. `rel(v, u)` is u's offset from v, `donor_ok(v, u)` whether u may interpolate v. The
/// serial levels pass their unknowns' indices, the distributed levels (`distributed::mg`) the
/// entries of a line joined across ranks with global ids as columns.
pub(crate) fn rows_on_line<C: Copy + Ord>(
    ext: &[usize],
    rel: &impl Fn(usize, usize) -> [f64; 3],
    coarse: impl Fn(usize) -> Option<C>,
    donor_ok: impl Fn(usize, usize) -> bool,
    mut put: impl FnMut(usize, Vec<(C, f64)>),
) {
    // Distance along the extended line.
    let mut s = vec![0.0; ext.len()];
    for i in 1..ext.len() {
        s[i] = s[i - 1] + norm(rel(ext[i - 1], ext[i]));
    }
    let kept: Vec<usize> = (0..ext.len()).filter(|&i| coarse(ext[i]).is_some()).collect();
    for (i, &v) in ext.iter().enumerate() {
        if coarse(v).is_some() {
            continue;
        }
        // The first kept unknown after i on the line.
        let after = kept.partition_point(|&j| j < i);
        if after == 0 || after == kept.len() {
            continue;
        }
        // Two on either side where the line has them (cubic), else one (quadratic, linear).
        let nodes = &kept[after.saturating_sub(2)..(after + 2).min(kept.len())];
        if !nodes.iter().all(|&j| donor_ok(v, ext[j])) {
            continue;
        }
        let w = lagrange(&nodes.iter().map(|&j| s[j]).collect::<Vec<_>>(), s[i]);
        let offsets: Vec<[f64; 3]> = nodes.iter().map(|&j| rel(v, ext[j])).collect();
        let h = offsets.iter().map(|&r| norm(r)).fold(0.0, f64::max);
        let miss = (0..3).map(|c| offsets.iter().zip(&w).map(|(r, w)| w * r[c]).sum::<f64>().abs()).fold(0.0, f64::max);
        // Written so that weights that are not finite (coincident points) fail too.
        let bounded = w.iter().map(|w| w.abs()).sum::<f64>() <= MAX_ABS_SUM;
        if !(miss <= LINEAR_TOL * h && bounded) {
            continue;
        }
        let mut row: Vec<(C, f64)> = nodes.iter().zip(w).filter_map(|(&j, w)| Some((coarse(ext[j])?, w))).collect();
        row.sort_by_key(|&(c, _)| c);
        put(v, row);
    }
}

/// The nearest neighbour of the line's unknown at `end` among its neighbours `row` in K's graph
/// on the far side from its line neighbour at `inner` (`inner` out of range: a line of one),
/// when that neighbour is `kept` and not on this line; ties in distance go to the lower `key`.
pub(crate) fn end_neighbour(
    row: &[u32],
    line: &[u32],
    end: usize,
    inner: usize,
    rel: &impl Fn(usize, usize) -> [f64; 3],
    kept: impl Fn(usize) -> bool,
    key: impl Fn(usize) -> u64,
) -> Option<usize> {
    let e = line[end] as usize;
    let toward = rel(e, *line.get(inner)? as usize);
    let (d, _, u) = row
        .iter()
        .map(|&u| u as usize)
        .filter(|&u| u != e && !line.contains(&(u as u32)))
        .map(|u| (norm(rel(e, u)), key(u), u))
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))?;
    let r = rel(e, u);
    let opposite = r[0] * toward[0] + r[1] * toward[1] + r[2] * toward[2] < 0.0;
    // The neighbour continues the line: on the far side, and about as near as the line's own
    // neighbour (the layers grow by a fixed ratio).
    (opposite && d <= 2.0 * norm(toward) && kept(u)).then_some(u)
}

/// The Lagrange weights at `x` of the nodes `s` (distinct, ascending).
fn lagrange(s: &[f64], x: f64) -> Vec<f64> {
    (0..s.len())
        .map(|j| (0..s.len()).filter(|&m| m != j).map(|m| (x - s[m]) / (s[j] - s[m])).product())
        .collect()
}

fn norm(r: [f64; 3]) -> f64 {
    (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bc::Dofs;
    use crate::mesh::{fixtures, Mesh};

    #[test]
    fn cubic_weights_on_a_uniform_line() {
        let w = lagrange(&[0.0, 1.0, 2.0, 3.0], 1.5);
        let want = [-1.0 / 16.0, 9.0 / 16.0, 9.0 / 16.0, -1.0 / 16.0];
        for (a, b) in w.iter().zip(want) {
            assert!((a - b).abs() < 1e-15, "{w:?}");
        }
    }

    /// A column of quads 10 wide whose rows grow by 1.2 from the wall y = 0: its left side
    /// (inside the corners) is a line, every other vertex of it kept with the corners. The
    /// dropped ones interpolate along it from the kept ones around them (the corners through
    /// the line's ends), reproducing cubics in y between two kept unknowns on either side and
    /// quadratics next to the ends.
    #[test]
    fn rows_along_a_graded_line_reproduce_cubics() {
        let ny = 10;
        let mut d = fixtures::quads(1, ny, [0.0, 10.0, 0.0, 1.0]);
        let mut y = vec![0.0];
        for k in 0..ny {
            y.push(y[k] + 1.2f64.powi(k as i32));
        }
        for (v, p) in d.coords.chunks_mut(2).enumerate() {
            p[1] = y[v / 2];
        }
        let mesh = Mesh::from_data(&d).unwrap();
        let n = mesh.num_vertices();
        let f = Features::build(&mesh, &Dofs::identity(n), &[], vec![Some(0); n], 50.0);
        // Vertex (i, j) is 2 j + i; each couples to the vertices of its quads.
        let mut g = CsrMatrix { nrows: n, ncols: n, row_ptr: vec![0], cols: Vec::new(), vals: Vec::new() };
        for v in 0..n {
            let j = v / 2;
            for u in 2 * j.saturating_sub(1)..(2 * (j + 2)).min(n) {
                g.cols.push(u as u32);
                g.vals.push(1.0);
            }
            g.row_ptr.push(g.cols.len() as u32);
        }
        let left: Vec<u32> = (1..ny).map(|j| 2 * j as u32).collect();
        let lines = Lines { start: vec![0, left.len() as u32], unknowns: left, anisotropy: 0.0 };
        let mut coarse_of = vec![u32::MAX; n];
        for (c, j) in (0..=ny).step_by(2).enumerate() {
            coarse_of[2 * j] = c as u32;
        }
        let rows = rows(&lines, &g, &f, &d.coords, &coarse_of);
        for j in (1..ny).step_by(2) {
            let row = rows[2 * j].as_ref().unwrap_or_else(|| panic!("row {j}"));
            let inner = j > 1 && j < ny - 1;
            assert_eq!(row.len(), if inner { 4 } else { 3 }, "row {j}");
            let power = if inner { 3 } else { 2 };
            for p in 0..=power {
                let at: f64 = row.iter().map(|&(c, w)| w * y[2 * c as usize].powi(p)).sum();
                assert!((at - y[j].powi(p)).abs() <= 1e-10 * y[ny].powi(p), "row {j}, y^{p}: {at} vs {}", y[j].powi(p));
            }
        }
        // Off the line, and the kept ones, the least-squares fit decides.
        assert!((0..n).filter(|&v| v % 2 == 1 || coarse_of[v] != u32::MAX).all(|v| rows[v].is_none()));
    }
}
