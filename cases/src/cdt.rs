//! Constrained Delaunay meshing of polygonal domains (spade), shared by the unstructured cases.
//!
//! Boundary loops are inserted first, in order, so their vertices keep their input indices;
//! refinement never splits a boundary segment (spade's `keep_constraint_edges`), so every input
//! segment is an edge of the output and can be tagged with its patch.

use glam::DVec2;
use spade::{AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation};
use std::collections::HashSet;

/// A face is split when larger than this many equilateral triangles of the local size: Delaunay
/// refinement leaves faces well below the largest allowed, so the bound sits above the mean.
const AREA_SLACK: f64 = 1.75;

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// A closed boundary polygon; `patches[i]` tags the segment from point `i` to point `i + 1`
/// (wrapping). Outer loops and hole loops alike; spade decides inside/outside by winding.
pub(super) struct Loop {
    pub points: Vec<DVec2>,
    pub patches: Vec<i32>,
}

/// A triangulated planar domain: the loops' points first (in loop order), then Steiner points.
pub(super) struct Planar {
    pub coords: Vec<DVec2>,
    pub tris: Vec<[u32; 3]>,
    pub tagged: Vec<([u32; 2], i32)>,
}

/// Area of an equilateral triangle of side `s`.
pub(super) fn equilateral_area(s: f64) -> f64 {
    0.25 * 3f64.sqrt() * s * s
}

fn build(loops: &[Loop], interior: &[DVec2]) -> Cdt {
    let mut cdt = Cdt::new();
    let mut next = 0usize;
    for l in loops {
        assert_eq!(l.points.len(), l.patches.len());
        let first = next;
        for p in &l.points {
            let v = cdt.insert(Point2::new(p.x, p.y)).expect("finite point");
            assert_eq!(v.index(), next, "duplicate boundary point");
            next += 1;
        }
        let n = l.points.len();
        for i in 0..n {
            let a = cdt.fixed_vertices().nth(first + i).unwrap();
            let b = cdt.fixed_vertices().nth(first + (i + 1) % n).unwrap();
            cdt.add_constraint(a, b);
        }
    }
    for p in interior {
        cdt.insert(Point2::new(p.x, p.y)).expect("finite point");
    }
    cdt
}

fn refine(cdt: &mut Cdt, angle_deg: f64, max_area: Option<f64>) -> HashSet<usize> {
    let mut params = RefinementParameters::<f64>::new()
        .exclude_outer_faces(true)
        .keep_constraint_edges()
        .with_angle_limit(AngleLimit::from_deg(angle_deg))
        .with_max_additional_vertices(2_000_000);
    if let Some(a) = max_area {
        params = params.with_max_allowed_area(a);
    }
    let r = cdt.refine(params);
    r.excluded_faces.iter().map(|f| f.index()).collect()
}

fn extract(cdt: &Cdt, excluded: &HashSet<usize>, loops: &[Loop]) -> Planar {
    let all: Vec<DVec2> = cdt
        .vertices()
        .map(|v| {
            let p = v.position();
            DVec2::new(p.x, p.y)
        })
        .collect();
    let mut tris: Vec<[u32; 3]> = cdt
        .inner_faces()
        .filter(|f| !excluded.contains(&f.fix().index()))
        .map(|f| f.vertices().map(|v| v.fix().index() as u32))
        .collect();
    // Drop vertices in no kept face (Steiner points in holes); loop points are all kept, and
    // come first, so their indices do not change.
    let n_fixed: usize = loops.iter().map(|l| l.points.len()).sum();
    let mut used = vec![false; all.len()];
    used[..n_fixed].iter_mut().for_each(|u| *u = true);
    tris.iter().flatten().for_each(|&v| used[v as usize] = true);
    let mut new_index = vec![u32::MAX; all.len()];
    let mut coords = Vec::with_capacity(all.len());
    for (i, p) in all.iter().enumerate() {
        if used[i] {
            new_index[i] = coords.len() as u32;
            coords.push(*p);
        }
    }
    tris.iter_mut().for_each(|t| *t = t.map(|v| new_index[v as usize]));
    let mut tagged = Vec::new();
    let mut first = 0u32;
    for l in loops {
        let n = l.points.len() as u32;
        for i in 0..n {
            tagged.push(([first + i, first + (i + 1) % n], l.patches[i as usize]));
        }
        first += n;
    }
    Planar { coords, tris, tagged }
}

/// Meshes the domain bounded by `loops`: Delaunay refinement to `angle_deg`, triangles no larger
/// than an equilateral one of side `size(centroid)`, then `smooth` sweeps of Laplacian smoothing
/// of the Steiner points, each followed by a fresh constrained Delaunay triangulation.
pub(super) fn mesh_domain(loops: &[Loop], size: &dyn Fn(DVec2) -> f64, angle_deg: f64, smooth: usize) -> Planar {
    let n_fixed: usize = loops.iter().map(|l| l.points.len()).sum();
    let mut cdt = build(loops, &[]);
    // Grade by a size field: Ruppert refinement, then split faces larger than the local target at
    // their centroids, and repeat until every face is small enough.
    let mut excluded;
    for _ in 0..64 {
        excluded = refine(&mut cdt, angle_deg, None);
        let big: Vec<Point2<f64>> = cdt
            .inner_faces()
            .filter(|f| !excluded.contains(&f.fix().index()))
            .filter_map(|f| {
                let c = f.center();
                let s = size(DVec2::new(c.x, c.y));
                (f.area() > AREA_SLACK * equilateral_area(s)).then_some(c)
            })
            .collect();
        if big.is_empty() {
            break;
        }
        for c in big {
            cdt.insert(c).expect("finite point");
        }
    }
    excluded = refine(&mut cdt, angle_deg, None);
    smooth_sweeps(extract(&cdt, &excluded, loops), loops, n_fixed, smooth, angle_deg)
}

/// `smooth` sweeps of Laplacian smoothing, each followed by a fresh constrained triangulation;
/// the last sweep repairs any face smoothing left below the angle limit.
fn smooth_sweeps(mut planar: Planar, loops: &[Loop], n_fixed: usize, smooth: usize, angle_deg: f64) -> Planar {
    for sweep in 0..smooth {
        let pts = smoothed(&planar, n_fixed);
        let mut cdt = build(loops, &pts[n_fixed..]);
        let angle = if sweep + 1 == smooth { angle_deg } else { 0.0 };
        let excluded = refine(&mut cdt, angle, None);
        planar = extract(&cdt, &excluded, loops);
    }
    planar
}

/// One Jacobi sweep of Laplacian smoothing of the vertices after the first `n_fixed`.
fn smoothed(p: &Planar, n_fixed: usize) -> Vec<DVec2> {
    let n = p.coords.len();
    let mut sum = vec![DVec2::ZERO; n];
    let mut cnt = vec![0u32; n];
    let mut edges: Vec<(u32, u32)> = p
        .tris
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])].map(|(a, b)| (a.min(b), a.max(b))))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    for (a, b) in edges {
        let (a, b) = (a as usize, b as usize);
        sum[a] += p.coords[b];
        cnt[a] += 1;
        sum[b] += p.coords[a];
        cnt[b] += 1;
    }
    (0..n).map(|i| if i < n_fixed || cnt[i] == 0 { p.coords[i] } else { sum[i] / cnt[i] as f64 }).collect()
}

/// Deterministic pseudo-random number in [−1/2, 1/2) from two integers (splitmix64).
fn jitter(i: i64, k: i64, salt: u64) -> f64 {
    let mut z = (i as u64)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add((k as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F))
        .wrapping_add(salt);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let t = ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0);
    (p - (a + t * d)).length()
}

/// Meshes the domain bounded by `loops` with uniform edge length about `s`: a hexagonal lattice
/// of spacing `s` (rows fitted to the bounding box, each point jittered deterministically by up
/// to `jitter_frac`·s), less the points within `0.6 s` of a boundary segment, triangulated,
/// then Delaunay-refined to `angle_deg` without splitting boundary segments and smoothed by
/// `smooth` Laplacian sweeps. Points outside the domain fall in excluded faces and are dropped.
pub(super) fn mesh_lattice(loops: &[Loop], s: f64, jitter_frac: f64, angle_deg: f64, smooth: usize) -> Planar {
    let pts = loops.iter().flat_map(|l| l.points.iter().copied());
    let (lo, hi) =
        pts.fold((DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)), |(lo, hi), p| (lo.min(p), hi.max(p)));
    let rows = (((hi.y - lo.y) / (0.5 * 3f64.sqrt() * s)).round() as i64).max(1);
    let dy = (hi.y - lo.y) / rows as f64;
    let cols = ((hi.x - lo.x) / s).ceil() as i64;
    let segs: Vec<(DVec2, DVec2)> = loops
        .iter()
        .flat_map(|l| {
            let n = l.points.len();
            (0..n).map(move |i| (l.points[i], l.points[(i + 1) % n]))
        })
        .collect();
    let mut interior = Vec::new();
    for k in 1..rows {
        for i in 0..=cols {
            let x = lo.x + (i as f64 + 0.5 * (k % 2) as f64) * s;
            let y = lo.y + k as f64 * dy;
            let p = DVec2::new(x + jitter_frac * s * jitter(i, k, 1), y + jitter_frac * s * jitter(i, k, 2));
            if p.x <= lo.x || p.x >= hi.x || p.y <= lo.y || p.y >= hi.y {
                continue;
            }
            if segs.iter().all(|&(a, b)| segment_distance(p, a, b) >= 0.6 * s) {
                interior.push(p);
            }
        }
    }
    let n_fixed: usize = loops.iter().map(|l| l.points.len()).sum();
    let mut cdt = build(loops, &interior);
    let excluded = refine(&mut cdt, angle_deg, None);
    smooth_sweeps(extract(&cdt, &excluded, loops), loops, n_fixed, smooth, angle_deg)
}
