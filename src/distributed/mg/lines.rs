//! Lines of strong coupling across thin wall layers on the distributed multigrid's levels
//! (docs/DESIGN.md §5, "Wall layers" and "Across ranks"): the serial line smoother on each rank's
//! owned rows.
//!
//! The finest level's lines are found as the serial ones are (`multigrid::lines`), from K's graph,
//! the cells' edges (`multigrid::cell_edges`) and the positions of the rank's vertices, over its
//! owned vertices only: the halo's couplings are measured (an owned vertex's strongest and weakest neighbour are those of the whole mesh),
//! but a halo vertex is on no line, so a line cut by a partition boundary becomes one segment on
//! each rank. Each segment's banded block is solved on its owner; the couplings across the cut
//! stay in the l1 diagonal bound with every other coupling off the band, so the smoother is block
//! Jacobi between ranks and keeps λmax(D⁻¹A) ≤ 1. On one rank nothing is cut.
//!
//! A coarse level keeps a line's unknowns it keeps (at least two), in order, as the serial levels
//! of kept unknowns do: a coarse unknown is the fine unknown of the same global id on the same
//! rank. A level agglomerated onto fewer ranks receives its senders' lines with their rows.

use super::donors::Positions;
use super::mover::Mover;
use super::OwnedRows;
use crate::bc::P;
use crate::distributed::reduce::max_over_ranks;
use crate::multigrid::cell_edges::Graph;
use crate::multigrid::layout::Layout;
use crate::multigrid::level::Level;
use crate::multigrid::line_smoother::LineBlocks;
use crate::multigrid::lines::Lines;
use crate::sparse::CsrMatrix;
use std::collections::HashMap;

/// The lines of a rank's part of a mesh: `k`'s graph and the cells' `edges` over its local
/// vertices (owned first, then the halo; `Graph::cell_edges` of its local mesh, whose ghost cells
/// hold every edge of an owned vertex) at `points` (`dim` values each), its first `owned`
/// vertices the candidates; the vertices prescribed in every component of `flags` are on no line, and those
/// `tied` (periodic links) are on none and their couplings are not measured, as the serial
/// linked unknowns.
pub(crate) fn owned_lines(
    k: &CsrMatrix,
    edges: &Graph,
    (points, dim): (&[f64], usize),
    owned: usize,
    flags: &[Vec<u8>],
    tied: &[bool],
) -> Lines {
    let prescribed = |i: usize| flags.iter().all(|f| f[i] & P != 0);
    let tied = |i: usize| tied.get(i).copied().unwrap_or(false);
    Lines::find(k.nrows, |i| k.row(i).0, |i| edges.neighbours(i), points, dim, |i| i >= owned || prescribed(i), tied)
}

/// The anisotropy from which a 3D hierarchy with lines interpolates along them
/// (`thin_layers`): cells of aspect ratio about 30. Wall layers of flat cells (an extruded
/// airfoil's, a cylinder's prisms) lie orders of magnitude above it, graded walls of nearly
/// isotropic cells (the sphere channel's) an order below.
const THIN_LAYERS: f64 = 1e3;

/// Whether the wall layers of the level `k` at `at` are thin enough for a 3D hierarchy with lines
/// to interpolate along them, as the 2D ones do (`along_lines`): its largest anisotropy over all
/// ranks (`largest_anisotropy`) at least `THIN_LAYERS` (collective; the same on every partition).
pub(super) fn thin_layers(k: &OwnedRows, at: &Positions) -> bool {
    largest_anisotropy(k, at) >= THIN_LAYERS
}

/// The largest anisotropy over all ranks of the unknowns of `k` (a level's operator, its rows
/// the owned unknowns') at `at`: an unknown's strongest coupling over its weakest, each measured
/// as the lines measure it (`multigrid::lines`: 1/|xᵢ − xⱼ|² over the operator's graph). An
/// owned row holds every neighbour of its unknown, so the largest does not depend on the
/// partition (collective).
fn largest_anisotropy(k: &OwnedRows, at: &Positions) -> f64 {
    let d2 = |i: usize, j: usize| (0..3).map(|c| (at.coords[i][c] - at.coords[j][c]).powi(2)).sum::<f64>();
    let mut largest = 0.0f64;
    for i in 0..k.halo.owned() {
        let (cols, _) = k.a.row(i);
        let (mut near, mut far) = (f64::INFINITY, 0.0f64);
        for &j in cols.iter().filter(|&&j| j as usize != i) {
            let d = d2(i, j as usize);
            if d > 0.0 {
                (near, far) = (near.min(d), far.max(d));
            }
        }
        if near.is_finite() {
            largest = largest.max(far / near);
        }
    }
    max_over_ranks(k.halo.comm(), largest)
}

/// The segments of `coarse`, the level kept from one whose entries have the global ids `gids` and
/// whose segments are `segments`: each segment's unknowns that `coarse` owns, in order, where at
/// least one is kept. A line's one kept unknown on this rank stays a segment of one, so that a
/// line the partition cuts joins across ranks for the rows along the lines (`along_lines`) as it
/// does on one rank; the smoother's lines are the segments of two or more (`smoothed`).
pub(super) fn kept_segments(segments: &Lines, gids: &[u64], coarse: &OwnedRows) -> Lines {
    if segments.is_empty() {
        return Lines::default();
    }
    let owned = &coarse.gids[..coarse.halo.owned()];
    let index: HashMap<u64, u32> = owned.iter().zip(0u32..).map(|(&g, i)| (g, i)).collect();
    let mut out = Lines { start: vec![0], unknowns: Vec::new(), anisotropy: segments.anisotropy };
    for k in 0..segments.len() {
        let before = out.unknowns.len();
        out.unknowns.extend(segments.line(k).iter().filter_map(|&v| index.get(&gids[v as usize]).copied()));
        if out.unknowns.len() > before {
            out.start.push(out.unknowns.len() as u32);
        }
    }
    out
}

/// The lines the smoother solves along: the segments of two or more unknowns, in order (a line
/// keeps on a coarse level the unknowns it keeps, at least two, as the serial levels do).
pub(super) fn smoothed(segments: &Lines) -> Lines {
    let mut out = Lines { start: vec![0], unknowns: Vec::new(), anisotropy: segments.anisotropy };
    for k in (0..segments.len()).filter(|&k| segments.line(k).len() >= 2) {
        out.unknowns.extend_from_slice(segments.line(k));
        out.start.push(out.unknowns.len() as u32);
    }
    out
}

/// The lines of a level moved onto fewer ranks by `mover` (collective over its senders and
/// targets): `lines` are this rank's over the entries it sends, `rank` its rank. A receiving rank
/// gets its senders' lines over its moved entries (which are its senders' end to end, the
/// mover's order), each line kept whole and in order; the others get none.
pub(super) fn moved_lines(lines: &Lines, mover: &Mover, rank: usize) -> Lines {
    // Each entry's line, as this rank and the line's index (exact in a double: both are below
    // 2³²), and its place along the line; −1 off the lines.
    let mut key = vec![-1.0; mover.count()];
    let mut place = vec![0.0; mover.count()];
    for k in 0..lines.len() {
        for (p, &v) in lines.line(k).iter().enumerate() {
            key[v as usize] = rank as f64 * 4_294_967_296.0 + k as f64;
            place[v as usize] = p as f64;
        }
    }
    let n = mover.len();
    let (mut moved_key, mut moved_place) = (vec![0.0; n], vec![0.0; n]);
    mover.gather(&key, &mut moved_key);
    mover.gather(&place, &mut moved_place);
    let mut on: Vec<(f64, f64, u32)> =
        (0..n).filter(|&i| moved_key[i] >= 0.0).map(|i| (moved_key[i], moved_place[i], i as u32)).collect();
    on.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut out = Lines { start: vec![0], unknowns: Vec::with_capacity(on.len()), anisotropy: lines.anisotropy };
    for (e, &(k, _, i)) in on.iter().enumerate() {
        if e > 0 && on[e - 1].0 != k {
            out.start.push(out.unknowns.len() as u32);
        }
        out.unknowns.push(i);
    }
    if !out.unknowns.is_empty() {
        out.start.push(out.unknowns.len() as u32);
    }
    out
}

/// Gives `level` (one of the distributed multigrid's, its operator a matrix) the line blocks of
/// `lines` with blocks of `band` (2 for the biharmonic's rows, 1 otherwise); a level without
/// lines keeps its point smoother.
pub(super) fn attach(level: &mut Level, lines: Lines, band: usize) {
    if lines.is_empty() {
        return;
    }
    let apart = vec![false; level.n()];
    level.lines = LineBlocks::banded(lines, &level.op, &level.flags, &apart, band);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owned_lines_stop_at_the_halo() {
        // A column of 6 vertices, heights growing by 1.2 from 1e-4, beside a column 1 away;
        // the first column's vertices 0..4 owned, 4 and 5 (and the second column) the halo.
        let ys: Vec<f64> = (0..6).map(|k| 1e-4 * (1.2f64.powi(k) - 1.0) / 0.2 + 1e-4).collect();
        let mut points: Vec<f64> = ys.iter().flat_map(|&y| [0.0, y]).collect();
        points.extend(ys.iter().flat_map(|&y| [1.0, y]));
        let mut t = Vec::new();
        for c in 0..2u32 {
            for k in 0..6u32 {
                let v = c * 6 + k;
                t.push((v, v, 1.0));
                if k + 1 < 6 {
                    t.extend([(v, v + 1, -1.0), (v + 1, v, -1.0)]);
                }
                if c == 0 {
                    t.extend([(v, v + 6, -1.0), (v + 6, v, -1.0)]);
                }
            }
        }
        let k = CsrMatrix::from_triplets(12, 12, t);
        let edges = Graph::of_entries(&k, |_| true);
        let flags = vec![vec![0u8; 12]];
        let lines = owned_lines(&k, &edges, (&points, 2), 4, &flags, &[]);
        assert_eq!(lines.len(), 1);
        assert_eq!(lines.line(0), &[0, 1, 2, 3]);
        // All owned: the whole column.
        let lines = owned_lines(&k, &edges, (&points, 2), 12, &flags, &[]);
        assert_eq!(lines.line(0), &[0, 1, 2, 3, 4, 5]);
    }
}
