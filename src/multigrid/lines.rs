//! Lines of strong coupling across thin wall layers: chains of unknowns, each the strongest
//! neighbour of the one before, along which a layer of flat cells couples its unknowns far more
//! strongly than across (docs/DESIGN.md §5, "Wall layers"). The line smoother
//! (`multigrid::line_smoother`) solves along them.
//!
//! The coupling of two neighbours is measured by the mesh, as 1/|xᵢ − xⱼ|²: the stiffness
//! couples neighbours as the inverse square of their distance, and K's own entries are no guide
//! (a trilinear hexahedron couples its face neighbours by zero, a Galerkin level's entries mix
//! several fine ones). An unknown is anisotropic when its strongest coupling is `ANISOTROPY`
//! times its weakest; a line starts at the most anisotropic unknown not yet on one (the wall's
//! first layer) whose cells' edges are stretched too (`ALONG_EDGES`), and grows at either end by
//! the strongest neighbour not yet on a line while that coupling is anisotropic and near the
//! end's strongest (`NEAR_STRONGEST`). On an isotropic mesh no unknown is anisotropic and there
//! are no lines.

/// Strongest over weakest coupling of an unknown for it to be on a line: cells of aspect ratio
/// about 4 (an isotropic hexahedron's couplings span a ratio of 3, a right triangle's 2).
const ANISOTROPY: f64 = 16.0;

/// Strongest over weakest coupling over the cells' edges alone (`multigrid::cell_edges`) of an
/// unknown for a line to start at it: edges of about 2.8:1. K's graph holds a hexahedron's body
/// diagonals, so over it a structured mesh's hexahedra of aspect ratio 2.7–2.8 at a wall (the
/// body diagonal 4× the short edge) already pass `ANISOTROPY`, where their edges reach 6.7;
/// graded hexahedra about a body reach 9 and wall layers far more. On simplices the edges are
/// K's graph and `ANISOTROPY` decides alone.
const ALONG_EDGES: f64 = 8.0;

/// A line grows by a neighbour whose coupling is at least this fraction of the end's strongest
/// (layers growing by 1.2 couple the next one by 1/1.44 of the last; a layer's side couplings
/// are weaker by its aspect ratio squared, so the line does not turn along the wall).
const NEAR_STRONGEST: f64 = 0.4;

/// Strongest over weakest coupling of the most anisotropic unknown on a mesh's lines from which
/// its lines lie across thin wall layers (`Lines::thin`): cells of aspect ratio about 100. Wall
/// layers of turbulent-flow meshes reach aspect ratios of hundreds to tens of thousands; a mesh
/// graded to a wall (cells at the wall 1/50 of the far ones) stretches its cells a few to a few
/// tens of times between its rays, and its rays are lines only for the smoother.
const THIN_LAYERS: f64 = 1e4;

/// Lines of unknowns, each in order along itself; every unknown on at most one line.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Lines {
    /// Line k holds `unknowns[start[k]..start[k + 1]]`.
    pub(crate) start: Vec<u32>,
    pub(crate) unknowns: Vec<u32>,
    /// The largest strongest-over-weakest coupling of an unknown on a line of the level the lines
    /// were found on (0 without lines); a coarser level's lines keep their finer level's.
    pub(crate) anisotropy: f64,
}

impl Lines {
    /// The number of lines.
    pub(crate) fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// Whether there are no lines.
    pub(crate) fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the lines lie across thin wall layers (`THIN_LAYERS`), whose unknowns a coarse
    /// level keeps along their lines (`multigrid::lsq::on_lines`) and whose levels below the
    /// first kept one take the assembled Galerkin product (docs/DESIGN.md §5, "Wall layers").
    pub(crate) fn thin(&self) -> bool {
        !self.is_empty() && self.anisotropy >= THIN_LAYERS
    }

    /// The unknowns of line `k`, in order.
    pub(crate) fn line(&self, k: usize) -> &[u32] {
        &self.unknowns[self.start[k] as usize..self.start[k + 1] as usize]
    }

    /// The lines of a coarser level: each line's unknowns that `coarse_of` maps to the coarser
    /// level's unknowns, in order, where at least two are. A coarse level of kept unknowns has no
    /// mesh to look for lines in, and its Galerkin operator couples unknowns several spacings
    /// apart, which would look anisotropic on an isotropic mesh; its lines are its finer level's.
    pub(crate) fn restricted(&self, coarse_of: impl Fn(u32) -> Option<u32>) -> Lines {
        let mut out = Lines { start: vec![0], unknowns: Vec::new(), anisotropy: self.anisotropy };
        for k in 0..self.len() {
            let before = out.unknowns.len();
            out.unknowns.extend(self.line(k).iter().filter_map(|&v| coarse_of(v)));
            if out.unknowns.len() - before >= 2 {
                out.start.push(out.unknowns.len() as u32);
            } else {
                out.unknowns.truncate(before);
            }
        }
        out
    }

    /// The lines of the graph whose neighbours of unknown i are `neighbours(i)` (i itself may
    /// be among them) at `points` (`dim` values per unknown), started only where the unknown's
    /// neighbours along the cells' edges, `edges(i)` (a part of `neighbours(i)`), are
    /// `ALONG_EDGES` apart; unknowns with `skip` set are on no line (prescribed in every
    /// component), and those with `unmeasured` set are on none and their couplings are not
    /// measured (linked unknowns, whose position is one of several). Deterministic: ties go to
    /// the lower index.
    pub(crate) fn find<'a, 'b>(
        n: usize,
        neighbours: impl Fn(usize) -> &'a [u32] + Sync,
        edges: impl Fn(usize) -> &'b [u32],
        points: &[f64],
        dim: usize,
        skip: impl Fn(usize) -> bool,
        unmeasured: impl Fn(usize) -> bool,
    ) -> Lines {
        let skip = |i: usize| skip(i) || unmeasured(i);
        let dist2 = |i: usize, j: usize| -> f64 { (0..dim).map(|c| (points[i * dim + c] - points[j * dim + c]).powi(2)).sum() };
        let weight = |i: usize, j: usize| {
            let d2 = dist2(i, j);
            if d2 > 0.0 {
                1.0 / d2
            } else {
                0.0
            }
        };
        // The strongest and weakest coupling of unknown i among `of` (`weight`'s largest and
        // smallest, 0 and ∞ when there is none): from the nearest and farthest of the
        // neighbours at a positive distance, a reciprocal each. A correctly rounded reciprocal
        // is monotone, so the reciprocal of the smallest squared distance is the largest of
        // the neighbours' reciprocals, bitwise; a neighbour at distance 0 weighs 0.
        let span = |i: usize, of: &[u32]| {
            if unmeasured(i) {
                return (0.0, f64::INFINITY);
            }
            let (mut near, mut far, mut coincident) = (f64::INFINITY, 0.0f64, false);
            for &j in of.iter().filter(|&&j| j as usize != i && !unmeasured(j as usize)) {
                let d2 = dist2(i, j as usize);
                if d2 > 0.0 {
                    (near, far) = (near.min(d2), far.max(d2));
                } else {
                    coincident = true;
                }
            }
            let lo = if coincident {
                0.0
            } else if far > 0.0 {
                1.0 / far
            } else {
                f64::INFINITY
            };
            (1.0 / near, lo)
        };
        let bounds: Vec<(f64, f64)> = (0..n).map(|i| span(i, neighbours(i))).collect();
        let anisotropic = |i: usize| bounds[i].0 >= ANISOTROPY * bounds[i].1 && bounds[i].1 > 0.0;
        let stretched = |i: usize| {
            let (hi, lo) = span(i, edges(i));
            hi >= ALONG_EDGES * lo && lo > 0.0
        };
        let mut seeds: Vec<(f64, u32)> = (0..n)
            .filter(|&i| !skip(i) && anisotropic(i) && stretched(i))
            .map(|i| (bounds[i].0 / bounds[i].1, i as u32))
            .collect();
        seeds.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        let mut claimed = vec![false; n];
        let mut lines = Lines { start: vec![0], unknowns: Vec::new(), anisotropy: 0.0 };
        // The next unknown after `e`: its strongest unclaimed neighbour, if that coupling is
        // anisotropic at `e` and near `e`'s strongest.
        let next = |e: usize, claimed: &[bool]| -> Option<usize> {
            let (mut best, mut bw) = (None, 0.0);
            for &j in neighbours(e) {
                let j = j as usize;
                if j == e || claimed[j] || skip(j) {
                    continue;
                }
                let w = weight(e, j);
                if w > bw {
                    (best, bw) = (Some(j), w);
                }
            }
            let (hi, lo) = bounds[e];
            best.filter(|_| bw >= NEAR_STRONGEST * hi && bw >= ANISOTROPY * lo)
        };
        let mut line = Vec::new();
        for &(_, s) in &seeds {
            let s = s as usize;
            if claimed[s] {
                continue;
            }
            line.clear();
            line.push(s);
            claimed[s] = true;
            // Grow at the far end, then turn the line round and grow at the other.
            for _ in 0..2 {
                while let Some(j) = next(*line.last().expect("a line has its seed"), &claimed) {
                    claimed[j] = true;
                    line.push(j);
                }
                line.reverse();
            }
            if line.len() < 2 {
                // A lone unknown is its own block: point Jacobi serves it, and it stays free.
                claimed[s] = false;
                continue;
            }
            // The line runs from its lower-indexed end (a fixed orientation).
            if line[0] > line[line.len() - 1] {
                line.reverse();
            }
            lines.unknowns.extend(line.iter().map(|&v| v as u32));
            lines.anisotropy = line.iter().map(|&v| bounds[v].0 / bounds[v].1).fold(lines.anisotropy, f64::max);
            lines.start.push(lines.unknowns.len() as u32);
        }
        lines
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The neighbours of every vertex of an nx × ny grid of quads (its 8 around and itself).
    fn grid_graph(nx: usize, ny: usize) -> Vec<Vec<u32>> {
        let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
        let mut g = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                let mut row = Vec::new();
                for b in j.saturating_sub(1)..=(j + 1).min(ny) {
                    for a in i.saturating_sub(1)..=(i + 1).min(nx) {
                        row.push(id(a, b));
                    }
                }
                g.push(row);
            }
        }
        g
    }

    fn grid_points(xs: &[f64], ys: &[f64]) -> Vec<f64> {
        ys.iter().flat_map(|&y| xs.iter().flat_map(move |&x| [x, y])).collect()
    }

    /// Rows from the wall y = 0: `layers` rows of first height `first`, each `growth` times the last.
    fn graded_rows(first: f64, growth: f64, layers: usize) -> Vec<f64> {
        let mut ys = vec![0.0];
        for k in 0..layers {
            ys.push(ys[k] + first * growth.powi(k as i32));
        }
        ys
    }

    #[test]
    fn a_graded_layer_gives_lines_normal_to_the_wall() {
        // 8 columns of width 0.1; rows from the wall y = 0: 10 layers of first height 1e-5
        // growing by 1.2, then rows of height 0.1.
        let nx = 8;
        let xs: Vec<f64> = (0..=nx).map(|i| 0.1 * i as f64).collect();
        let mut ys = graded_rows(1e-5, 1.2, 10);
        for _ in 0..4 {
            ys.push(ys.last().unwrap() + 0.1);
        }
        let ny = ys.len() - 1;
        let g = grid_graph(nx, ny);
        let points = grid_points(&xs, &ys);
        // The wall's vertices are prescribed.
        let lines = Lines::find(g.len(), |i| &g[i], |i| &g[i], &points, 2, |i| i <= nx, |_| false);
        assert_eq!(lines.len(), nx + 1, "one line per column");
        for k in 0..lines.len() {
            let line = lines.line(k);
            let column = line[0] as usize % (nx + 1);
            // Rows 1 to 10: the layers' vertices up to the layer's top (row 11 couples to row
            // 10 by 0.1 over its height, far weaker).
            let rows: Vec<usize> = line.iter().map(|&v| v as usize / (nx + 1)).collect();
            assert!(line.iter().all(|&v| v as usize % (nx + 1) == column), "line {k} leaves its column");
            assert_eq!(rows, (1..=10).collect::<Vec<_>>(), "line {k}");
        }
        // The first layer's cells are 1e4 times as wide as high: thin layers.
        assert!(lines.anisotropy > 1e8, "{}", lines.anisotropy);
        assert!(lines.thin());
        assert!(lines.restricted(Some).thin(), "a coarse level's lines keep their anisotropy");
    }

    #[test]
    fn a_graded_mesh_s_rays_are_lines_but_not_thin_layers() {
        // Columns of width 0.1, rows from 0.01 growing by 1.3 to above 0.1: cells of aspect
        // ratio up to 10 at the wall, 100 in 1/d².
        let nx = 8;
        let xs: Vec<f64> = (0..=nx).map(|i| 0.1 * i as f64).collect();
        let ys = graded_rows(0.01, 1.3, 10);
        let g = grid_graph(nx, ys.len() - 1);
        let lines = Lines::find(g.len(), |i| &g[i], |i| &g[i], &grid_points(&xs, &ys), 2, |i| i <= nx, |_| false);
        assert_eq!(lines.len(), nx + 1, "one line per column");
        assert!(lines.anisotropy > 16.0 && lines.anisotropy < 1e4, "{}", lines.anisotropy);
        assert!(!lines.thin());
        assert!(!Lines::default().thin());
    }

    #[test]
    fn an_isotropic_mesh_has_no_lines() {
        let xs: Vec<f64> = (0..=10).map(|i| 0.1 * i as f64).collect();
        // Mildly graded rows (ratio 1.3) stay isotropic.
        let mut ys = vec![0.0];
        for k in 0..8 {
            ys.push(ys[k] + 0.05 * 1.3f64.powi(k as i32));
        }
        let g = grid_graph(10, ys.len() - 1);
        let lines = Lines::find(g.len(), |i| &g[i], |i| &g[i], &grid_points(&xs, &ys), 2, |_| false, |_| false);
        assert!(lines.is_empty());
    }

    /// Two boxes of `a` × `b` × `b` stacked along x (corners 0–11, the x = 0, a, 2a planes'
    /// rectangles): K's graph (every pair of a box's corners) and the boxes' edges.
    fn two_boxes(a: f64, b: f64) -> (Vec<f64>, Vec<Vec<u32>>, Vec<Vec<u32>>) {
        let mut points = Vec::new();
        for x in 0..3 {
            for [y, z] in [[0.0, 0.0], [b, 0.0], [b, b], [0.0, b]] {
                points.extend([a * x as f64, y, z]);
            }
        }
        let (mut k, mut edges) = (vec![Vec::new(); 12], vec![Vec::new(); 12]);
        for first in [0u32, 4] {
            let box_: Vec<u32> = (first..first + 8).collect();
            for &i in &box_ {
                for &j in &box_ {
                    if i == j {
                        continue;
                    }
                    k[i as usize].push(j);
                    // An edge: along x in the same corner of the square, or a side of a square.
                    let (ci, cj) = (i % 4, j % 4);
                    if (ci == cj && i.abs_diff(j) == 4) || (i / 4 == j / 4 && (ci + 2) % 4 != cj) {
                        edges[i as usize].push(j);
                    }
                }
            }
        }
        for row in k.iter_mut().chain(edges.iter_mut()) {
            row.sort_unstable();
            row.dedup();
        }
        (points, k, edges)
    }

    #[test]
    fn a_hexahedron_s_body_diagonal_starts_no_line() {
        // 1 × 2.75 × 2.75: the body diagonal is 16.1 times the short edge in d², the long
        // edges 7.6; over K's graph the middle square's corners are anisotropic, over the
        // edges not.
        let (points, k, edges) = two_boxes(1.0, 2.75);
        assert_eq!(edges[4], vec![0, 5, 7, 8]);
        let lines = Lines::find(12, |i| &k[i], |i| &edges[i], &points, 3, |_| false, |_| false);
        assert!(lines.is_empty(), "{lines:?}");
        let over_k = Lines::find(12, |i| &k[i], |i| &k[i], &points, 3, |_| false, |_| false);
        assert_eq!(over_k.len(), 4, "one line along x through each corner of the squares");
        // 1 × 3 × 3: the edges 9 apart, a layer.
        let (points, k, edges) = two_boxes(1.0, 3.0);
        let lines = Lines::find(12, |i| &k[i], |i| &edges[i], &points, 3, |_| false, |_| false);
        assert_eq!((&lines.start, &lines.unknowns), (&over_k.start, &over_k.unknowns));
        assert_eq!(lines.line(0), &[0, 4, 8]);
        // The body diagonal over the short edge, 1 + 2 · 3² in d².
        assert_eq!(lines.anisotropy, 19.0);
    }
}
