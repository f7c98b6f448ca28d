use super::*;
use crate::mesh::IndexBase;
use spade::DelaunayTriangulation;

/// Deterministic pseudo-random numbers in [0, 1).
pub(crate) struct Lcg(pub(crate) u64);
impl Lcg {
    pub(crate) fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Tags the boundary edges of a rectangle [0, w] x [0, h]: bottom 1, right 2, top 3, left 4.
fn rect_tags(coords: &[[f64; 2]], cells: &[[u32; 3]], w: f64, h: f64) -> Vec<([u32; 2], i32)> {
    let edges = EdgeCells::build(cells).unwrap();
    let mut tags = Vec::new();
    for &(key, [_, c1]) in &edges.edges {
        if c1 != u32::MAX {
            continue;
        }
        let (a, b) = ((key >> 32) as u32, (key & 0xffff_ffff) as u32);
        let (p, q) = (coords[a as usize], coords[b as usize]);
        let on = |k: usize, v: f64| (p[k] - v).abs() < 1e-12 && (q[k] - v).abs() < 1e-12;
        let patch = if on(1, 0.0) {
            1
        } else if on(0, w) {
            2
        } else if on(1, h) {
            3
        } else if on(0, 0.0) {
            4
        } else {
            continue;
        };
        tags.push(([a, b], patch));
    }
    tags
}

/// Structured (n+1) x (m+1) vertices on [0, w] x [0, h], each square cut by its right
/// diagonal; vertex (i, j) is j * (n + 1) + i.
pub(crate) fn structured(n: usize, m: usize, w: f64, h: f64) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut coords = Vec::new();
    for j in 0..=m {
        for i in 0..=n {
            coords.push([w * i as f64 / n as f64, h * j as f64 / m as f64]);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut cells = Vec::new();
    for j in 0..m {
        for i in 0..n {
            cells.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            cells.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (coords, cells)
}

pub(crate) fn rect(n: usize) -> Mesh {
    let (coords, cells) = structured(n, n, 1.0, 1.0);
    let tags = rect_tags(&coords, &cells, 1.0, 1.0);
    Mesh::triangles(&coords, &cells, IndexBase::Zero, &tags, None).unwrap()
}

/// Unit square, regions 1 (y < 1/2) and 2, interface y = 1/2 tagged as patch 9.
pub(crate) fn two_regions(n: usize) -> Mesh {
    let (coords, cells) = structured(n, n, 1.0, 1.0);
    let mut tags = rect_tags(&coords, &cells, 1.0, 1.0);
    let regions: Vec<i32> = cells
        .iter()
        .map(|t| {
            let y = t.iter().map(|&v| coords[v as usize][1]).sum::<f64>() / 3.0;
            if y < 0.5 {
                1
            } else {
                2
            }
        })
        .collect();
    for j in 0..n {
        let (a, b) = ((n / 2) * (n + 1) + j, (n / 2) * (n + 1) + j + 1);
        tags.push(([a as u32, b as u32], 9));
    }
    Mesh::triangles(&coords, &cells, IndexBase::Zero, &tags, Some(&regions)).unwrap()
}

/// Delaunay mesh of the unit square: boundary points at spacing 1/n, jittered interior.
pub(crate) fn unstructured_rect(n: usize, seed: u64) -> Mesh {
    let mut rng = Lcg(seed);
    let h = 1.0 / n as f64;
    let mut pts = Vec::new();
    for k in 0..n {
        let t = k as f64 * h;
        pts.extend([[t, 0.0], [1.0, t], [1.0 - t, 1.0], [0.0, 1.0 - t]]);
    }
    for j in 1..n {
        for i in 1..n {
            let x = (i as f64 + 0.6 * (rng.next() - 0.5)) * h;
            let y = (j as f64 + 0.6 * (rng.next() - 0.5)) * h;
            pts.push([x, y]);
        }
    }
    let mut dt: DelaunayTriangulation<Point2<f64>> = DelaunayTriangulation::new();
    for p in &pts {
        dt.insert(Point2::new(p[0], p[1])).unwrap();
    }
    let coords: Vec<[f64; 2]> = dt.vertices().map(|v| [v.position().x, v.position().y]).collect();
    let cells: Vec<[u32; 3]> = dt.inner_faces().map(|f| f.vertices().map(|v| v.fix().index() as u32)).collect();
    let tags = rect_tags(&coords, &cells, 1.0, 1.0);
    Mesh::triangles(&coords, &cells, IndexBase::Zero, &tags, None).unwrap()
}

/// Channel [0, 4] x [0, 2] around a cylinder of radius 0.3 at (1, 1) (patch 5).
pub(crate) fn cylinder(n: usize, seed: u64) -> Mesh {
    let mut rng = Lcg(seed);
    let h = 2.0 / n as f64;
    let (c, r) = (DVec2::new(1.0, 1.0), 0.3);
    let mut pts: Vec<DVec2> = Vec::new();
    let mut segs: Vec<[usize; 2]> = Vec::new();
    let nx = 2 * n;
    let mut ring = |pts: &mut Vec<DVec2>, p: Vec<DVec2>| {
        let s = pts.len();
        for k in 0..p.len() {
            segs.push([s + k, s + (k + 1) % p.len()]);
        }
        pts.extend(p);
    };
    let mut outer = Vec::new();
    for k in 0..nx {
        outer.push(DVec2::new(k as f64 * h, 0.0));
    }
    for k in 0..n {
        outer.push(DVec2::new(4.0, k as f64 * h));
    }
    for k in 0..nx {
        outer.push(DVec2::new(4.0 - k as f64 * h, 2.0));
    }
    for k in 0..n {
        outer.push(DVec2::new(0.0, 2.0 - k as f64 * h));
    }
    ring(&mut pts, outer);
    let nc = ((2.0 * std::f64::consts::PI * r / (0.5 * h)).round() as usize).max(8);
    ring(
        &mut pts,
        (0..nc)
            .map(|k| {
                let t = 2.0 * std::f64::consts::PI * k as f64 / nc as f64;
                c + r * DVec2::new(t.cos(), t.sin())
            })
            .collect(),
    );
    for j in 1..n {
        for i in 1..nx {
            let p = DVec2::new((i as f64 + 0.5 * (rng.next() - 0.5)) * h, (j as f64 + 0.5 * (rng.next() - 0.5)) * h);
            if (p - c).length() > r + 0.6 * h {
                pts.push(p);
            }
        }
    }
    let vs: Vec<Point2<f64>> = pts.iter().map(|p| Point2::new(p.x, p.y)).collect();
    let cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::bulk_load_cdt(vs, segs).unwrap();
    let coords: Vec<[f64; 2]> = cdt.vertices().map(|v| [v.position().x, v.position().y]).collect();
    let cells: Vec<[u32; 3]> = cdt
        .inner_faces()
        .filter(|f| {
            let m = f.vertices().iter().fold(DVec2::ZERO, |s, v| s + DVec2::new(v.position().x, v.position().y)) / 3.0;
            (m - c).length() > r
        })
        .map(|f| f.vertices().map(|v| v.fix().index() as u32))
        .collect();
    let mut tags = rect_tags(&coords, &cells, 4.0, 2.0);
    let edges = EdgeCells::build(&cells).unwrap();
    for &(key, [_, c1]) in &edges.edges {
        let (a, b) = ((key >> 32) as usize, (key & 0xffff_ffff) as usize);
        let on = |v: usize| ((DVec2::from(coords[v]) - c).length() - r).abs() < 1e-9;
        if c1 == u32::MAX && on(a) && on(b) {
            tags.push(([a as u32, b as u32], 5));
        }
    }
    Mesh::triangles(&coords, &cells, IndexBase::Zero, &tags, None).unwrap()
}

/// Polar-structured annulus 0.5 < r < 1: outer circle patch 1, inner circle patch 2.
pub(crate) fn annulus(nr: usize, nt: usize) -> Mesh {
    annulus_r(0.5, nr, nt)
}

/// Polar-structured annulus r0 < r < 1.
fn annulus_r(r0: f64, nr: usize, nt: usize) -> Mesh {
    let mut coords = Vec::new();
    for j in 0..=nr {
        let r = r0 + (1.0 - r0) * j as f64 / nr as f64;
        for i in 0..nt {
            let t = 2.0 * std::f64::consts::PI * i as f64 / nt as f64;
            coords.push([r * t.cos(), r * t.sin()]);
        }
    }
    let id = |i: usize, j: usize| (j * nt + i % nt) as u32;
    let mut cells = Vec::new();
    let mut tags = Vec::new();
    for j in 0..nr {
        for i in 0..nt {
            cells.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            cells.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    for i in 0..nt {
        tags.push(([id(i, 0), id(i + 1, 0)], 2));
        tags.push(([id(i, nr), id(i + 1, nr)], 1));
    }
    Mesh::triangles(&coords, &cells, IndexBase::Zero, &tags, None).unwrap()
}

/// Checks everything a coarse level promises and returns its area.
pub(crate) fn check(fine: &Mesh, c: &CoarseMesh) -> f64 {
    let m = &c.mesh;
    // Round trip through the validating constructor.
    let tags: Vec<([u32; 2], i32)> = m.patch_edges().iter().map(|e| (e.vertices, e.patch)).collect();
    let again =
        Mesh::triangles(&m.coords_xy(), &m.tris(), IndexBase::Zero, &tags, Some(m.regions())).expect("coarse mesh validates");
    assert_eq!(again.patch_edges().len(), m.patch_edges().len());
    let areas = crate::mesh::quality::signed_measures(m, m.coords());
    assert!(areas.iter().all(|&a| a > 0.0), "non-positive coarse cell");
    assert_eq!(c.fine_vertex.len(), m.num_vertices());
    assert!(c.fine_vertex.windows(2).all(|w| w[0] < w[1]));
    for (i, &v) in c.fine_vertex.iter().enumerate() {
        assert_eq!(m.points_2d()[i], fine.points_2d()[v as usize]);
    }
    let mut used = vec![false; m.num_vertices()];
    m.tris().iter().flatten().for_each(|&v| used[v as usize] = true);
    assert!(used.iter().all(|&u| u), "unused coarse vertex");
    // Boundary edges oriented with the domain on the left; every boundary edge is a patch edge.
    let edges = EdgeCells::build(&m.tris()).unwrap();
    let nb = edges.edges.iter().filter(|e| e.1[1] == u32::MAX).count();
    let mut nbp = 0;
    for e in m.patch_edges() {
        let [a, b] = e.vertices;
        let [c0, c1] = edges.get(a, b).unwrap();
        if e.interior {
            assert_ne!(c1, u32::MAX);
        } else {
            nbp += 1;
            assert_eq!(c1, u32::MAX);
            let t = m.tris()[c0 as usize];
            assert!((0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b));
        }
    }
    assert_eq!(nb, nbp);
    areas.iter().sum()
}

fn fine_area(m: &Mesh) -> f64 {
    crate::mesh::quality::signed_measures(m, m.coords()).iter().sum()
}

fn hierarchy(fine: &Mesh, links: &[[u32; 2]]) -> Vec<usize> {
    let mut counts = vec![fine.num_vertices()];
    let (mut m, mut l) = (fine.clone(), links.to_vec());
    while let Some(c) = coarsen(&m, &l, &CoarsenParams::default()).unwrap() {
        check(&m, &c);
        counts.push(c.mesh.num_vertices());
        m = c.mesh;
        l = c.links;
        assert!(counts.len() < 20);
    }
    counts
}

#[test]
fn structured_square_halves_resolution() {
    let fine = rect(32);
    let c = coarsen(&fine, &[], &CoarsenParams::default()).unwrap().unwrap();
    let area = check(&fine, &c);
    assert!((area - 1.0).abs() < 1e-12, "area {area}");
    let ratio = fine.num_vertices() as f64 / c.mesh.num_vertices() as f64;
    assert!((2.5..=5.0).contains(&ratio), "ratio {ratio}");
    // Corners kept.
    for v in [0u32, 32, 33 * 32, 33 * 33 - 1] {
        assert!(c.fine_vertex.binary_search(&v).is_ok(), "corner {v} dropped");
    }
    // Every other boundary vertex: 17 per side.
    for p in 1..=4 {
        assert_eq!(c.mesh.patch_vertices(p).len(), 17, "patch {p}");
    }
    // Patch ids of coarse edges match the side they lie on.
    let x = c.mesh.points_2d();
    for e in c.mesh.patch_edges() {
        let [a, b] = e.vertices.map(|v| x[v as usize]);
        let ok = match e.patch {
            1 => a.y == 0.0 && b.y == 0.0 && b.x > a.x,
            2 => a.x == 1.0 && b.x == 1.0 && b.y > a.y,
            3 => a.y == 1.0 && b.y == 1.0 && b.x < a.x,
            4 => a.x == 0.0 && b.x == 0.0 && b.y < a.y,
            _ => false,
        };
        assert!(ok, "edge {e:?}");
        assert!(!e.interior);
    }
    assert!(c.links.is_empty());
}

#[test]
fn repeated_coarsening_terminates_with_levels() {
    let counts = hierarchy(&rect(64), &[]);
    eprintln!("structured 65x65 levels: {counts:?}");
    assert!(counts.len() >= 4, "{counts:?}");
    let min = CoarsenParams::default().min_vertices;
    assert!(*counts.last().unwrap() >= min && *counts.last().unwrap() < 200, "{counts:?}");
    for w in counts.windows(2) {
        assert!(w[0] as f64 >= 1.6 * w[1] as f64);
    }
}

#[test]
fn unstructured_square() {
    let fine = unstructured_rect(40, 7);
    let counts = hierarchy(&fine, &[]);
    eprintln!("unstructured square levels: {counts:?}");
    assert!(counts.len() >= 4, "{counts:?}");
    let c = coarsen(&fine, &[], &CoarsenParams::default()).unwrap().unwrap();
    let area = check(&fine, &c);
    assert!((area - 1.0).abs() < 1e-12);
    let ratio = fine.num_vertices() as f64 / c.mesh.num_vertices() as f64;
    assert!((2.5..=5.0).contains(&ratio), "ratio {ratio}");
}

#[test]
fn cylinder_in_channel() {
    let fine = cylinder(24, 3);
    let counts = hierarchy(&fine, &[]);
    eprintln!("cylinder levels: {counts:?}");
    assert!(counts.len() >= 3, "{counts:?}");
    let c = coarsen(&fine, &[], &CoarsenParams::default()).unwrap().unwrap();
    let area = check(&fine, &c);
    // The coarse hole is an inscribed polygon with half the vertices: a slightly larger domain.
    let fa = fine_area(&fine);
    assert!(area > fa && area < fa + 0.02, "{area} vs {fa}");
    let hole = c.mesh.patch_vertices(5);
    // A closed loop of n = 45 edges keeps positions 0, 2, ..., n - 3.
    assert_eq!(fine.patch_vertices(5).len(), 45);
    assert_eq!(hole.len(), 22);
    for &v in &hole {
        let p = c.mesh.points_2d()[v as usize];
        assert!(((p - DVec2::new(1.0, 1.0)).length() - 0.3).abs() < 1e-12);
    }
    for e in c.mesh.patch_edges() {
        assert!(!e.interior);
        assert!((1..=5).contains(&e.patch));
    }
}

#[test]
fn interface_between_regions_is_preserved() {
    let fine = two_regions(32);
    let counts = hierarchy(&fine, &[]);
    eprintln!("two-region levels: {counts:?}");
    let c = coarsen(&fine, &[], &CoarsenParams::default()).unwrap().unwrap();
    let area = check(&fine, &c);
    assert!((area - 1.0).abs() < 1e-12);
    let m = &c.mesh;
    let x = m.points_2d();
    let iface: Vec<_> = m.patch_edges().into_iter().filter(|e| e.patch == 9).collect();
    assert_eq!(iface.len(), 16);
    let mut len = 0.0;
    for e in &iface {
        assert!(e.interior);
        let [a, b] = e.vertices.map(|v| x[v as usize]);
        assert!(a.y == 0.5 && b.y == 0.5);
        len += (a - b).length();
    }
    assert!((len - 1.0).abs() < 1e-14);
    let areas = crate::mesh::quality::signed_measures(m, m.coords());
    let (mut a1, mut a2) = (0.0, 0.0);
    for (k, t) in m.tris().iter().enumerate() {
        let y = t.iter().map(|&v| x[v as usize].y).sum::<f64>() / 3.0;
        match m.regions()[k] {
            1 => {
                assert!(y < 0.5);
                a1 += areas[k];
            }
            2 => {
                assert!(y > 0.5);
                a2 += areas[k];
            }
            r => panic!("region {r}"),
        }
    }
    assert!((a1 - 0.5).abs() < 1e-12 && (a2 - 0.5).abs() < 1e-12);
}

#[test]
fn periodic_links_stay_paired() {
    // 33 x 17 vertices; left side (0, j) linked with right side (32, j).
    let (coords, cells) = structured(32, 16, 2.0, 1.0);
    let tags = rect_tags(&coords, &cells, 2.0, 1.0);
    let fine = Mesh::triangles(&coords, &cells, IndexBase::Zero, &tags, None).unwrap();
    let links: Vec<[u32; 2]> = (0..=16u32).map(|j| [j * 33, j * 33 + 32]).collect();
    let check_links = |m: &Mesh, l: &[[u32; 2]]| {
        let x = m.points_2d();
        let left = m.points_2d().iter().filter(|p| p.x == 0.0).count();
        assert_eq!(l.len(), left);
        for &[a, b] in l {
            let (p, q) = (x[a as usize], x[b as usize]);
            assert!(p.x == 0.0 && q.x == 2.0 && p.y == q.y);
        }
    };
    let (mut m, mut l) = (fine.clone(), links.clone());
    let mut counts = vec![m.num_vertices()];
    while let Some(c) = coarsen(&m, &l, &CoarsenParams::default()).unwrap() {
        check(&m, &c);
        check_links(&c.mesh, &c.links);
        counts.push(c.mesh.num_vertices());
        m = c.mesh;
        l = c.links;
    }
    eprintln!("periodic levels: {counts:?}");
    assert!(counts.len() >= 3);
    // Odd-length chains with opposite walking directions still pair up through the links.
    let links2: Vec<[u32; 2]> = (0..=16u32).map(|j| [j * 33, (16 - j) * 33 + 32]).collect();
    let c = coarsen(&fine, &links2, &CoarsenParams::default()).unwrap().unwrap();
    for &[a, b] in &c.links {
        let (p, q) = (c.mesh.points_2d()[a as usize], c.mesh.points_2d()[b as usize]);
        assert!(p.x == 0.0 && q.x == 2.0 && (p.y + q.y - 1.0).abs() < 1e-15);
    }
    assert_eq!(c.links.len(), c.mesh.points_2d().iter().filter(|p| p.x == 0.0).count());
}

#[test]
fn hierarchies_reach_a_few_dozen_vertices() {
    let meshes = [
        ("annulus 9x96", annulus(8, 96)),
        ("annulus 17x160", annulus(16, 160)),
        // Thin layers at a coarsely resolved curved wall: interior points outside the chords.
        ("annulus 65x24", annulus(64, 24)),
        ("cylinder 48", cylinder(48, 1)),
        ("cylinder 20 refined", cylinder(20, 2).refine_uniform()),
        ("unstructured 60", unstructured_rect(60, 3)),
        ("unstructured 25 refined twice", unstructured_rect(25, 4).refine_uniform().refine_uniform()),
        ("two regions 64", two_regions(64)),
    ];
    for (name, fine) in &meshes {
        let counts = hierarchy(fine, &[]);
        eprintln!("{name}: {counts:?}");
        assert!(counts.len() >= 3, "{name}: {counts:?}");
        assert!(*counts.last().unwrap() < 150, "{name}: {counts:?}");
    }
}

#[test]
fn crossing_chords_keep_their_chain() {
    // Gap 0.02 between circles of 24 vertices, the outer one numbered from a vertex half a
    // coarse step away: its chords (0.034 deep) would cut through the kept inner vertices, so
    // the outer circle keeps all of its vertices.
    let (nr, nt) = (2, 24);
    let base = annulus_r(0.98, nr, nt);
    let relabel = |v: u32| {
        let (j, i) = (v as usize / nt, v as usize % nt);
        if j == nr {
            (j * nt + (i + 1) % nt) as u32
        } else {
            v
        }
    };
    let mut coords = base.coords_xy();
    for (v, p) in base.coords_xy().into_iter().enumerate() {
        coords[relabel(v as u32) as usize] = p;
    }
    let cells: Vec<[u32; 3]> = base.tris().iter().map(|t| t.map(relabel)).collect();
    let tags: Vec<([u32; 2], i32)> = base.patch_edges().iter().map(|e| (e.vertices.map(relabel), e.patch)).collect();
    let fine = Mesh::triangles(&coords, &cells, IndexBase::Zero, &tags, None).unwrap();
    let params = CoarsenParams { min_vertices: 10, ..Default::default() };
    let c = coarsen(&fine, &[], &params).unwrap().unwrap();
    check(&fine, &c);
    assert_eq!(c.mesh.patch_vertices(1).len(), 24);
    assert_eq!(c.mesh.patch_vertices(2).len(), 12);
    assert_eq!(c.mesh.num_vertices(), 36);
    // Without the shift the two coarse polygons nest and both halve.
    let c = coarsen(&base, &[], &params).unwrap().unwrap();
    check(&base, &c);
    assert_eq!(c.mesh.patch_vertices(1).len(), 12);
    assert_eq!(c.mesh.patch_vertices(2).len(), 12);
}

#[test]
fn deterministic() {
    for fine in [cylinder(16, 11), two_regions(24), unstructured_rect(30, 5)] {
        let a = coarsen(&fine, &[], &CoarsenParams::default()).unwrap().unwrap();
        let b = coarsen(&fine, &[], &CoarsenParams::default()).unwrap().unwrap();
        assert_eq!(a.fine_vertex, b.fine_vertex);
        assert_eq!(a.mesh.points_2d(), b.mesh.points_2d());
        assert_eq!(a.mesh.tris(), b.mesh.tris());
        assert_eq!(a.mesh.regions(), b.mesh.regions());
        assert_eq!(a.mesh.patch_edges(), b.mesh.patch_edges());
    }
}

#[test]
fn too_small_meshes_are_not_coarsened() {
    assert!(coarsen(&rect(4), &[], &CoarsenParams::default()).unwrap().is_none());
    let strict = CoarsenParams { min_ratio: 10.0, ..Default::default() };
    assert!(coarsen(&rect(32), &[], &strict).unwrap().is_none());
    assert!(matches!(coarsen(&rect(8), &[[0, 1000]], &CoarsenParams::default()), Err(Error::Coarsening(_))));
}
