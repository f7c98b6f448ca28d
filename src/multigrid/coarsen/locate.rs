//! Point location in a (coarse) mesh: the cell containing each point and its barycentric weights.
//!
//! A uniform bucket grid over the cells' bounding boxes answers each query in O(1) on average.
//! Points outside every allowed cell (a coarse polygon cuts chords off a curved boundary) get the
//! nearest allowed cell and extrapolated barycentric weights, which still sum to one and reproduce
//! linear functions exactly.

use crate::mesh::Mesh;
use glam::DVec2;
use rayon::prelude::*;

/// A cell of a mesh and the barycentric weights of a point with respect to its three vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Location {
    pub cell: u32,
    pub weights: [f64; 3],
}

/// Points below this count are located serially.
const PAR_POINTS: usize = 2048;
/// A point counts as inside a cell when no barycentric weight is below this.
const INSIDE_TOL: f64 = -1e-12;

/// Barycentric weights of `p` in triangle (a, b, c); extrapolated (some negative) outside it.
/// The weights sum to one exactly up to rounding; a degenerate triangle gives its centroid weights.
pub fn barycentric(a: DVec2, b: DVec2, c: DVec2, p: DVec2) -> [f64; 3] {
    let (e1, e2, d) = (b - a, c - a, p - a);
    let det = e1.perp_dot(e2);
    if det == 0.0 || !det.is_finite() {
        return [1.0 / 3.0; 3];
    }
    let w1 = d.perp_dot(e2) / det;
    let w2 = e1.perp_dot(d) / det;
    [1.0 - w1 - w2, w1, w2]
}

/// Distance from `p` to the closed triangle (a, b, c) (zero inside), for counter-clockwise cells.
fn distance_to_triangle(a: DVec2, b: DVec2, c: DVec2, p: DVec2) -> f64 {
    let w = barycentric(a, b, c, p);
    if w.iter().all(|&x| x >= 0.0) {
        return 0.0;
    }
    seg_dist(a, b, p).min(seg_dist(b, c, p)).min(seg_dist(c, a, p))
}

fn seg_dist(a: DVec2, b: DVec2, p: DVec2) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 { ((p - a).dot(ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    (a + t * ab - p).length()
}

/// A uniform bucket grid over the cells of one mesh, for repeated point location.
pub struct Locator<'a> {
    mesh: &'a Mesh,
    origin: DVec2,
    inv_h: f64,
    h: f64,
    nx: usize,
    ny: usize,
    /// CSR: cells whose bounding box overlaps each bucket, ascending.
    bucket_ptr: Vec<u32>,
    bucket_cells: Vec<u32>,
    /// Sorted region ids present in the mesh.
    regions: Vec<i32>,
}

impl<'a> Locator<'a> {
    /// Builds the bucket grid (about two cells per bucket).
    pub fn new(mesh: &'a Mesh) -> Locator<'a> {
        debug_assert!(mesh.cell_types().iter().all(|&t| t == crate::geometry::CellType::Triangle));
        let nc = mesh.num_cells();
        let cells = || (0..nc).map(|c| mesh.tri(c));
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for t in cells() {
            for v in t {
                lo = lo.min(mesh.xy(v as usize));
                hi = hi.max(mesh.xy(v as usize));
            }
        }
        if !lo.is_finite() {
            lo = DVec2::ZERO;
            hi = DVec2::ONE;
        }
        let ext = (hi - lo).max(DVec2::splat(1e-300));
        let nb = (nc / 2).max(1) as f64;
        let mut h = (ext.x * ext.y / nb).sqrt();
        if h.is_nan() || h <= 0.0 || !h.is_finite() {
            h = ext.x.max(ext.y);
        }
        // Cap the bucket count per direction (thin domains) to keep the grid O(cells).
        let cap = (nc + 1) as f64;
        h = h.max(ext.x / cap).max(ext.y / cap);
        let nx = ((ext.x / h).ceil() as usize).max(1);
        let ny = ((ext.y / h).ceil() as usize).max(1);
        let inv_h = 1.0 / h;
        let mut loc = Locator {
            mesh,
            origin: lo,
            inv_h,
            h,
            nx,
            ny,
            bucket_ptr: Vec::new(),
            bucket_cells: Vec::new(),
            regions: Vec::new(),
        };
        // The buckets a cell's bounding box overlaps; computed in both passes rather than stored
        // (a list of them would be the largest allocation of a whole coarsening).
        let range = |t: [u32; 3]| {
            let p = t.map(|v| mesh.xy(v as usize));
            let (a, b) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
            let (i0, j0) = loc.bucket_of(a);
            let (i1, j1) = loc.bucket_of(b);
            [i0, j0, i1, j1]
        };
        let mut count = vec![0u32; nx * ny + 1];
        for r in cells().map(range) {
            for j in r[1]..=r[3] {
                for i in r[0]..=r[2] {
                    count[j * nx + i + 1] += 1;
                }
            }
        }
        for k in 0..nx * ny {
            count[k + 1] += count[k];
        }
        let mut next = count.clone();
        let mut bucket_cells = vec![0u32; count[nx * ny] as usize];
        for (c, r) in cells().map(range).enumerate() {
            for j in r[1]..=r[3] {
                for i in r[0]..=r[2] {
                    let k = j * nx + i;
                    bucket_cells[next[k] as usize] = c as u32;
                    next[k] += 1;
                }
            }
        }
        loc.bucket_ptr = count;
        loc.bucket_cells = bucket_cells;
        let mut regions = mesh.regions().to_vec();
        regions.sort_unstable();
        regions.dedup();
        loc.regions = regions;
        loc
    }

    /// The bucket containing `p`, clamped to the grid.
    fn bucket_of(&self, p: DVec2) -> (usize, usize) {
        let q = (p - self.origin) * self.inv_h;
        let i = q.x.floor().clamp(0.0, (self.nx - 1) as f64) as usize;
        let j = q.y.floor().clamp(0.0, (self.ny - 1) as f64) as usize;
        (i, j)
    }

    fn bucket(&self, i: usize, j: usize) -> &[u32] {
        let k = j * self.nx + i;
        &self.bucket_cells[self.bucket_ptr[k] as usize..self.bucket_ptr[k + 1] as usize]
    }

    fn weights(&self, c: u32, p: DVec2) -> [f64; 3] {
        let t = self.mesh.tri(c as usize);
        let x = |v: u32| self.mesh.xy(v as usize);
        barycentric(x(t[0]), x(t[1]), x(t[2]), p)
    }

    /// Distance from `p` to bucket (i, j)'s rectangle.
    fn bucket_distance(&self, i: usize, j: usize, p: DVec2) -> f64 {
        let lo = self.origin + DVec2::new(i as f64, j as f64) * self.h;
        let hi = lo + DVec2::splat(self.h);
        let d = (lo - p).max(p - hi).max(DVec2::ZERO);
        d.length()
    }

    /// The cell containing `p` (restricted to cells of `region` when given and present in the
    /// mesh), else the nearest such cell, with (possibly extrapolated) barycentric weights.
    pub fn locate(&self, p: DVec2, region: Option<i32>) -> Location {
        let region = region.filter(|r| self.regions.binary_search(r).is_ok());
        let regions = self.mesh.regions();
        let allowed = |c: u32| region.is_none_or(|r| regions[c as usize] == r);
        let (ci, cj) = self.bucket_of(p);
        // Containing cell in the point's own bucket: the one with the largest smallest weight.
        let mut best: Option<(f64, u32, [f64; 3])> = None;
        for &c in self.bucket(ci, cj) {
            if !allowed(c) {
                continue;
            }
            let w = self.weights(c, p);
            let m = w[0].min(w[1]).min(w[2]);
            if m >= INSIDE_TOL && best.is_none_or(|b| m > b.0) {
                best = Some((m, c, w));
            }
        }
        if let Some((_, cell, weights)) = best {
            return Location { cell, weights };
        }
        // Nearest allowed cell: rings of buckets around the point's bucket.
        let x = |v: u32| self.mesh.xy(v as usize);
        let mut nearest: Option<(f64, u32)> = None;
        let max_r = self.nx.max(self.ny);
        for r in 0..=max_r {
            let (i0, i1) = (ci.saturating_sub(r), (ci + r).min(self.nx - 1));
            let (j0, j1) = (cj.saturating_sub(r), (cj + r).min(self.ny - 1));
            for j in j0..=j1 {
                for i in i0..=i1 {
                    if i.abs_diff(ci).max(j.abs_diff(cj)) != r {
                        continue;
                    }
                    if nearest.is_some_and(|n| self.bucket_distance(i, j, p) > n.0) {
                        continue;
                    }
                    for &c in self.bucket(i, j) {
                        if !allowed(c) {
                            continue;
                        }
                        let t = self.mesh.tri(c as usize);
                        let d = distance_to_triangle(x(t[0]), x(t[1]), x(t[2]), p);
                        if nearest.is_none_or(|n| d < n.0 || (d == n.0 && c < n.1)) {
                            nearest = Some((d, c));
                        }
                    }
                }
            }
            // Lower bound on the distance to any bucket outside the rings searched so far.
            let mut bound = f64::INFINITY;
            let o = self.origin;
            if ci + r + 1 < self.nx {
                bound = bound.min((o.x + (ci + r + 1) as f64 * self.h - p.x).max(0.0));
            }
            if ci > r {
                bound = bound.min((p.x - (o.x + (ci - r) as f64 * self.h)).max(0.0));
            }
            if cj + r + 1 < self.ny {
                bound = bound.min((o.y + (cj + r + 1) as f64 * self.h - p.y).max(0.0));
            }
            if cj > r {
                bound = bound.min((p.y - (o.y + (cj - r) as f64 * self.h)).max(0.0));
            }
            if bound == f64::INFINITY || nearest.is_some_and(|n| n.0 < bound) {
                break;
            }
        }
        let cell = nearest.expect("a mesh has at least one cell").1;
        Location { cell, weights: self.weights(cell, p) }
    }
}

/// For each point, the cell of `coarse` containing it (restricted to cells of region `regions[i]`
/// when that is `Some` and the region exists) and its barycentric weights. A point outside every
/// allowed cell gets the nearest allowed cell and extrapolated weights (not clamped).
///
/// `regions` has one entry per point, or is empty (no restriction).
pub fn locate(coarse: &Mesh, points: &[DVec2], regions: &[Option<i32>]) -> Vec<Location> {
    assert!(
        regions.is_empty() || regions.len() == points.len(),
        "locate: {} regions for {} points",
        regions.len(),
        points.len()
    );
    let loc = Locator::new(coarse);
    let region = |i: usize| regions.get(i).copied().flatten();
    if points.len() < PAR_POINTS {
        points.iter().enumerate().map(|(i, &p)| loc.locate(p, region(i))).collect()
    } else {
        points.par_iter().enumerate().with_min_len(256).map(|(i, &p)| loc.locate(p, region(i))).collect()
    }
}

/// Recomputes the weights of existing locations at new coordinates (same cells), after the mesh
/// moved. `points` are the new positions of the located points, one per location.
pub fn update_weights(coarse: &Mesh, points: &[DVec2], locs: &mut [Location]) {
    assert_eq!(points.len(), locs.len(), "update_weights: length mismatch");
    let x = |v: u32| coarse.xy(v as usize);
    let f = |(l, &p): (&mut Location, &DVec2)| {
        let t = coarse.tri(l.cell as usize);
        l.weights = barycentric(x(t[0]), x(t[1]), x(t[2]), p);
    };
    if points.len() < PAR_POINTS {
        locs.iter_mut().zip(points).for_each(f);
    } else {
        locs.par_iter_mut().zip(points).with_min_len(256).for_each(f);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::multigrid::coarsen::tests::{annulus, cylinder, rect, two_regions, unstructured_rect, Lcg};
    use crate::multigrid::coarsen::{coarsen, CoarsenParams};

    fn linear(p: DVec2) -> f64 {
        2.0 + 3.0 * p.x - 5.0 * p.y
    }

    /// Largest error of interpolating a linear function from `coarse` at `points`; also the most
    /// negative weight seen.
    fn linear_error(coarse: &Mesh, points: &[DVec2], locs: &[Location]) -> (f64, f64) {
        let (mut err, mut wmin) = (0.0f64, f64::INFINITY);
        for (p, l) in points.iter().zip(locs) {
            let t = coarse.tris()[l.cell as usize];
            let v: f64 = (0..3).map(|k| l.weights[k] * linear(coarse.points_2d()[t[k] as usize])).sum();
            assert!((l.weights.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            err = err.max((v - linear(*p)).abs());
            wmin = wmin.min(l.weights[0].min(l.weights[1]).min(l.weights[2]));
        }
        (err, wmin)
    }

    #[test]
    fn linear_functions_reproduced_including_outside_points() {
        // Curved outer boundary: fine vertices on it lie outside the coarse chords.
        let fine = annulus(8, 96);
        let c = coarsen(&fine, &[], &CoarsenParams::default()).unwrap().unwrap();
        let locs = locate(&c.mesh, &fine.points_2d(), &[]);
        let (err, wmin) = linear_error(&c.mesh, &fine.points_2d(), &locs);
        assert!(err < 1e-12, "error {err}");
        assert!(wmin < -1e-3, "no fine vertex outside the coarse domain ({wmin})");
        // The outside ones got the nearest cell: extrapolation stays mild.
        assert!(wmin > -0.5, "{wmin}");
        let outside = locs.iter().filter(|l| l.weights.iter().any(|&w| w < -1e-12)).count();
        assert_eq!(outside, 48, "fine outer vertices between kept ones");
        // Kept vertices are located at themselves (weight one on that vertex).
        for (i, &v) in c.fine_vertex.iter().enumerate() {
            let l = locs[v as usize];
            let t = c.mesh.tris()[l.cell as usize];
            let k = t.iter().position(|&u| u as usize == i).expect("own cell");
            assert!((l.weights[k] - 1.0).abs() < 1e-12);
        }

        // Cylinder in a channel, every level of the hierarchy.
        let mut m = cylinder(24, 3);
        while let Some(c) = coarsen(&m, &[], &CoarsenParams::default()).unwrap() {
            let locs = locate(&c.mesh, &m.points_2d(), &[]);
            let (err, _) = linear_error(&c.mesh, &m.points_2d(), &locs);
            assert!(err < 1e-12, "error {err}");
            m = c.mesh;
        }
    }

    #[test]
    fn region_restriction_picks_the_side_of_an_interface() {
        let fine = two_regions(32);
        let c = coarsen(&fine, &[], &CoarsenParams::default()).unwrap().unwrap();
        let pts: Vec<DVec2> = (0..=32).map(|i| DVec2::new(i as f64 / 32.0, 0.5)).collect();
        for r in [1, 2] {
            let locs = locate(&c.mesh, &pts, &vec![Some(r); pts.len()]);
            for l in &locs {
                assert_eq!(c.mesh.regions()[l.cell as usize], r);
            }
            let (err, wmin) = linear_error(&c.mesh, &pts, &locs);
            assert!(err < 1e-12 && wmin > -1e-12);
        }
        // A region absent from the mesh does not restrict.
        let l = locate(&c.mesh, &pts[..1], &[Some(77)]);
        assert!(l[0].weights.iter().all(|&w| w > -1e-12));
    }

    #[test]
    fn far_points_get_the_nearest_cell() {
        let m = rect(8);
        let locs = locate(&m, &[DVec2::new(3.0, 3.0), DVec2::new(-1.0, 0.5), DVec2::new(0.5, -1e-9)], &[]);
        let has = |l: &Location, p: DVec2| m.tris()[l.cell as usize].iter().any(|&v| m.points_2d()[v as usize] == p);
        assert!(has(&locs[0], DVec2::new(1.0, 1.0)));
        assert!(has(&locs[1], DVec2::new(0.0, 0.5)));
        // Just below the bottom edge: a cell on that edge.
        let t = m.tris()[locs[2].cell as usize];
        assert_eq!(t.iter().filter(|&&v| m.point(v as usize)[1] == 0.0).count(), 2);
        let pts = [DVec2::new(3.0, 3.0), DVec2::new(-1.0, 0.5), DVec2::new(0.5, -1e-9)];
        let (err, _) = linear_error(&m, &pts, &locs);
        assert!(err < 1e-12);
    }

    #[test]
    fn update_weights_follows_moved_mesh() {
        let fine = unstructured_rect(40, 9);
        let c = coarsen(&fine, &[], &CoarsenParams::default()).unwrap().unwrap();
        let mut locs = locate(&c.mesh, &fine.points_2d(), &[]);
        let mut rng = Lcg(1);
        let moved: Vec<DVec2> =
            c.mesh.points_2d().iter().map(|p| *p + 0.002 * DVec2::new(rng.next() - 0.5, rng.next() - 0.5)).collect();
        let moved_mesh = c.mesh.with_coords(moved.iter().flat_map(|p| [p.x, p.y]).collect());
        let fine_moved: Vec<DVec2> = fine.points_2d().iter().map(|p| *p * 1.01).collect();
        let cells_before: Vec<u32> = locs.iter().map(|l| l.cell).collect();
        update_weights(&moved_mesh, &fine_moved, &mut locs);
        assert_eq!(cells_before, locs.iter().map(|l| l.cell).collect::<Vec<_>>());
        let (err, _) = linear_error(&moved_mesh, &fine_moved, &locs);
        assert!(err < 1e-12);
    }

    #[test]
    fn parallel_matches_serial() {
        let m = unstructured_rect(30, 2);
        let mut rng = Lcg(5);
        let pts: Vec<DVec2> =
            (0..3 * PAR_POINTS).map(|_| DVec2::new(1.4 * rng.next() - 0.2, 1.4 * rng.next() - 0.2)).collect();
        let par = locate(&m, &pts, &[]);
        let loc = Locator::new(&m);
        for (p, l) in pts.iter().zip(&par) {
            assert_eq!(*l, loc.locate(*p, None));
        }
        let (err, _) = linear_error(&m, &pts, &par);
        assert!(err < 1e-12);
    }

    /// `cargo test --release --lib locate_million -- --ignored --nocapture`
    #[test]
    #[ignore]
    fn locate_million_points_timing() {
        let fine = rect(1000);
        let t0 = std::time::Instant::now();
        let c = coarsen(&fine, &[], &CoarsenParams::default()).unwrap().unwrap();
        let t1 = std::time::Instant::now();
        let locs = locate(&c.mesh, &fine.points_2d(), &[]);
        let t2 = std::time::Instant::now();
        eprintln!("{} fine vertices: coarsen {:.2?}, locate {:.2?}", fine.num_vertices(), t1 - t0, t2 - t1);
        let (err, _) = linear_error(&c.mesh, &fine.points_2d(), &locs);
        assert!(err < 1e-11);
    }
}
