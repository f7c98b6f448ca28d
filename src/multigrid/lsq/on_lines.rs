//! Where each unknown lies on the lines across wall layers (`multigrid::lines`), for the
//! selection of kept unknowns (`lsq::select`) on the biharmonic's hierarchies with lines.
//!
//! The general rule drops an unknown when any strong neighbour that may interpolate it is kept.
//! On a geometrically graded layer the wall lies within the strong reach of every unknown of a
//! line once the Galerkin graph reaches it (the distance to the wall is a geometric sum, less than
//! twice the last spacing), so a level that keeps the wall's unknowns drops whole lines and the
//! levels below are smoothed pointwise across what is left of the layers. Here a line's unknown
//! is dropped only for a kept unknown on its own line, and at the line's ends also for one off
//! every line (the wall below the first layer, the cells beyond the last): the layers are
//! semi-coarsened along their lines, and the lines shorten level by level from their ends
//! (Mavriplis's agglomeration along implicit lines). The lines are visited from the wall
//! outward, so the first layer's unknown goes for the wall's and each kept unknown drops the
//! next ones out along its line that it couples strongly (one on the finest level, one or two on
//! a Galerkin level, whose graph reaches further).
//!
//! The rule is the same in 3D. There the general rule also drops a line's unknowns for the
//! kept unknowns of the lines beside it (a wing's layers, whose cells are long along the span
//! and shorter along the chord, couple their lines more strongly along the chord than the
//! reach counts for the span): coarsened along their lines only, the layers keep every line on
//! every level, as in 2D.

use super::along_lines::end_neighbour;
use super::Features;
use crate::multigrid::lines::Lines;
use crate::sparse::CsrMatrix;

/// Marks an unknown on no line.
const NONE: u32 = u32::MAX;

/// Each unknown's line and place on it.
pub(super) struct OnLines {
    /// The line of each unknown (`NONE` off every line).
    line_of: Vec<u32>,
    /// The visiting key of each unknown on a line: its line's lowest-indexed end, then its place
    /// counted from the wall's end.
    key: Vec<(u32, u32)>,
    /// Whether the unknown ends its line.
    end: Vec<bool>,
    /// Whether a line's unknowns coupled strongly only off their line take the general rule
    /// (3D, `keeps_to_line`).
    across: bool,
}

impl OnLines {
    /// The places of the unknowns on `lines` (K's graph `k`, features `f`, positions `points`).
    pub(super) fn new(lines: &Lines, k: &CsrMatrix, f: &Features, points: &[f64]) -> OnLines {
        let n = k.nrows;
        let dim = f.dim();
        let at = |d: usize| &points[d * dim..(d + 1) * dim];
        let rel = |v: usize, u: usize| f.relative(v, u, at(v), at(u));
        let on_boundary = |u: usize| f.feature_dim(u) < dim;
        let mut out = OnLines { line_of: vec![NONE; n], key: vec![(0, 0); n], end: vec![false; n], across: dim == 3 };
        for l in 0..lines.len() {
            let line = lines.line(l);
            let last = line.len() - 1;
            // The line continues into the boundary (the wall) at its last unknown and not at its
            // first: it is counted from its last.
            let wall_at = |end: usize, inner: usize| {
                end_neighbour(k.row(line[end] as usize).0, line, end, inner, &rel, on_boundary, |u| u as u64).is_some()
            };
            let reversed = wall_at(last, last.wrapping_sub(1)) && !wall_at(0, 1);
            let base = line[0].min(line[last]);
            for (p, &v) in line.iter().enumerate() {
                let place = if reversed { last - p } else { p };
                out.line_of[v as usize] = l as u32;
                out.key[v as usize] = (base, place as u32);
            }
            out.end[line[0] as usize] = true;
            out.end[line[last] as usize] = true;
        }
        out
    }

    /// The visiting key of unknown `d` when it is on a line (`key`).
    pub(super) fn key(&self, d: usize) -> Option<(u32, u32)> {
        (self.line_of[d] != NONE).then_some(self.key[d])
    }

    /// Whether a line's unknowns coupled strongly only off their line take the general rule.
    pub(super) fn across(&self) -> bool {
        self.across
    }

    /// Lets a line's unknowns coupled strongly only off their line take the general rule (the
    /// 3D rule, `keeps_to_line`), for a 2D level whose lines no longer couple along themselves.
    pub(super) fn across_lines(&mut self) {
        self.across = true;
    }

    /// Whether unknown `v`, whose strong neighbours are `near`, keeps to its line
    /// (`may_drop_for`): in 2D every unknown on a line; in 3D one with a strong neighbour on its
    /// own line, and the others take the general rule.
    pub(super) fn keeps_to_line(&self, v: usize, near: &[u32]) -> bool {
        let lv = self.line_of[v];
        lv != NONE && (!self.across || near.iter().any(|&u| self.line_of[u as usize] == lv))
    }

    /// Whether unknown `v` may be dropped for the kept unknown `u` (a strong neighbour that may
    /// interpolate it): off every line always, on a line for its own line's unknowns, and at
    /// its line's ends for unknowns off every line.
    pub(super) fn may_drop_for(&self, v: usize, u: usize) -> bool {
        let (lv, lu) = (self.line_of[v], self.line_of[u]);
        lv == NONE || lu == lv || (self.end[v] && lu == NONE)
    }
}

#[cfg(test)]
mod tests {
    use super::super::select;
    use super::*;
    use crate::bc::Dofs;
    use crate::mesh::{fixtures, Mesh};

    /// Columns of quads graded by 2.2 away from a wall at the top (y = its height), far wider
    /// than high, in the graph of a deep Galerkin level: each unknown coupled to its column's
    /// neighbours, its row's neighbours and its column's wall unknown. The wall lies within the
    /// strong reach of every unknown (its distance is a geometric sum, below twice the last
    /// spacing), so the general rule drops every line for the wall; kept along their lines
    /// (counted from the wall, which has the highest indices), every second unknown stays.
    #[test]
    fn lines_are_kept_along_themselves_not_dropped_for_the_wall() {
        let (nx, ny) = (4, 8);
        let mut d = fixtures::quads(nx, ny, [0.0, 4.0e4, 0.0, 1.0]);
        // Depth of row `ny - j` below the wall.
        let depth: Vec<f64> = (0..=ny).map(|j| (0..j).map(|i| 2.2f64.powi(i as i32)).sum()).collect();
        for (v, p) in d.coords.chunks_mut(2).enumerate() {
            p[1] = depth[ny] - depth[ny - v / (nx + 1)];
        }
        let mesh = Mesh::from_data(&d).unwrap();
        let n = mesh.num_vertices();
        let f = Features::build(&mesh, &Dofs::identity(n), &[], vec![Some(0); n], 50.0);
        let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
        let mut t = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                let mut couple = |a: u32, b: u32| t.extend([(a, b, 1.0), (b, a, 1.0)]);
                couple(id(i, j), id(i, j));
                if j < ny {
                    couple(id(i, j), id(i, j + 1));
                    if j + 1 < ny {
                        couple(id(i, j), id(i, ny));
                    }
                }
                if i < nx {
                    couple(id(i, j), id(i + 1, j));
                }
            }
        }
        let k = CsrMatrix::from_triplets(n, n, t);
        // The interior columns' unknowns between the bottom and the wall, bottom first.
        let columns: Vec<Vec<u32>> = (1..nx).map(|i| (1..ny).map(|j| id(i, j)).collect()).collect();
        let lines = Lines {
            start: (0..=columns.len()).map(|c| (c * (ny - 1)) as u32).collect(),
            unknowns: columns.concat(),
            anisotropy: 0.0,
        };
        let general = select(&k, &f, &d.coords, None);
        assert!(lines.unknowns.iter().all(|u| !general.contains(u)), "{general:?}");
        let on_lines = OnLines::new(&lines, &k, &f, &d.coords);
        let kept = select(&k, &f, &d.coords, Some(&on_lines));
        for column in &columns {
            // Places counted from the wall: row ny - 1 is the first.
            let places: Vec<usize> = column.iter().rev().enumerate().filter(|(_, u)| kept.contains(u)).map(|(p, _)| p + 1).collect();
            assert_eq!(places, [2, 4, 6], "{kept:?}");
        }
    }
}
