//! Retriangulating the kept vertices, in parts: the constrained Delaunay triangulation of the
//! kept points and segments, the inside faces by a flood fill from the exterior, the checks of
//! the coarse cells, the patch segments on them, and the regions.

use super::*;

/// One attempt's outcome: a value, or what to fix before the next attempt.
type Attempt<T> = std::result::Result<T, Failure>;

/// The coarse triangulation under construction.
type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// The value of an attempt's step, or the step's failure returned from the enclosing function.
macro_rules! attempt {
    ($e:expr) => {
        match $e {
            Ok(v) => v,
            Err(failure) => return Ok(Err(failure)),
        }
    };
}

/// The kept vertices in coarse numbering.
struct Kept {
    /// Coarse vertex i is fine vertex `fine_vertex[i]`.
    fine_vertex: Vec<u32>,
    /// The coarse number of each fine vertex (`u32::MAX` when not kept).
    coarse_of: Vec<u32>,
}

/// Triangulates the kept points with the segments as constraints and builds the coarse mesh.
pub(super) fn triangulate(
    fine: &Mesh,
    links: &[[u32; 2]],
    kept: &[bool],
    segments: &[Segment],
    f: &FeatureChains,
) -> Result<Attempt<CoarseMesh>> {
    let x = fine.xy_all();
    // Exact capacities here and for the cells: the coarse level keeps these for the solver's life.
    let mut fine_vertex: Vec<u32> = Vec::with_capacity(kept.iter().filter(|&&k| k).count());
    fine_vertex.extend((0..fine.num_vertices() as u32).filter(|&v| kept[v as usize]));
    let mut coarse_of = vec![u32::MAX; fine.num_vertices()];
    for (i, &v) in fine_vertex.iter().enumerate() {
        coarse_of[v as usize] = i as u32;
    }
    let k = Kept { fine_vertex, coarse_of };
    let (cdt, coarse_of_handle) = attempt!(constrained_delaunay(&x, &k, segments)?);
    // Segments in coarse numbering, keyed for lookup.
    let mut seg_of: HashMap<u64, usize> = HashMap::with_capacity(segments.len());
    for (i, s) in segments.iter().enumerate() {
        seg_of.insert(edge_key(k.coarse_of[s.a as usize], k.coarse_of[s.b as usize]), i);
    }
    let cells = attempt!(inside_cells(&cdt, &coarse_of_handle, &seg_of, segments));
    let cx: Vec<DVec2> = k.fine_vertex.iter().map(|&v| x[v as usize]).collect();
    let area = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|v| cx[v as usize]);
        0.5 * (b - a).perp_dot(c - a)
    };
    attempt!(check_cells(&cells, &cx, &k, f, &area));
    // Boundary of the triangulation = boundary segments; interface segments have two cells.
    let Some(edges) = EdgeCells::build(&cells) else {
        return Ok(Err(Failure::Stop));
    };
    let patch_edges = attempt!(patch_segments(&cells, &edges, segments, &k.coarse_of));
    let regions = regions(fine, &cells, &cx, &edges, &seg_of, &area);
    let coarse_links = links
        .iter()
        .filter(|l| kept[l[0] as usize] && kept[l[1] as usize])
        .map(|l| [k.coarse_of[l[0] as usize], k.coarse_of[l[1] as usize]])
        .collect();
    let mesh = Mesh::from_triangles(&cx, &cells, regions, &patch_edges);
    Ok(Ok(CoarseMesh { mesh, fine_vertex: k.fine_vertex, links: coarse_links }))
}

/// The constrained Delaunay triangulation of the kept points (in their order) with the segments
/// as constraints, and the coarse vertex of each of its vertex handles.
fn constrained_delaunay(
    x: &[DVec2],
    k: &Kept,
    segments: &[Segment],
) -> Result<Attempt<(Cdt, Vec<u32>)>> {
    let (fine_vertex, coarse_of) = (&k.fine_vertex, &k.coarse_of);
    let nc = fine_vertex.len();
    // Bulk loading keeps the vertex order (and is far faster than inserting one by one).
    let points: Vec<Point2<f64>> = fine_vertex.iter().map(|&v| Point2::new(x[v as usize].x, x[v as usize].y)).collect();
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(points, Vec::new(), |_| {}).map_err(|e| {
            let big = fine_vertex.iter().fold(0.0f64, |m, &v| m.max(x[v as usize].abs().max_element()));
            Error::Coarsening(format!(
                "the coarse triangulation cannot take these coordinates (largest |x|, |y| = {big:e}; \
                     spade: {e:?}): the mesh was moved too far or its coordinates are not finite"
            ))
        })?;
    if cdt.num_vertices() != nc {
        // Duplicate positions: spade merged vertices.
        return Ok(Err(Failure::Stop));
    }
    let handles: Vec<FixedVertexHandle> = cdt.fixed_vertices().collect();
    let mut coarse_of_handle = vec![u32::MAX; nc];
    for (i, h) in handles.iter().enumerate() {
        if h.index() >= nc {
            return Ok(Err(Failure::Stop));
        }
        coarse_of_handle[h.index()] = i as u32;
    }
    let order_kept = handles.iter().enumerate().all(|(i, h)| {
        let p = cdt.vertex(*h).position();
        let q = x[fine_vertex[i] as usize];
        p.x == q.x && p.y == q.y
    });
    if !order_kept {
        return Err(Error::Coarsening("the triangulation reordered the vertices".into()));
    }
    let mut bad_chains = Vec::new();
    for s in segments {
        let (ha, hb) = (handles[coarse_of[s.a as usize] as usize], handles[coarse_of[s.b as usize] as usize]);
        if !cdt.can_add_constraint(ha, hb) {
            bad_chains.push(s.chain);
            continue;
        }
        cdt.try_add_constraint(ha, hb);
        // A kept vertex exactly on the segment splits it: not the segment we asked for.
        if !cdt.exists_constraint(ha, hb) {
            bad_chains.push(s.chain);
        }
    }
    if !bad_chains.is_empty() {
        bad_chains.sort_unstable();
        bad_chains.dedup();
        return Ok(Err(Failure::Chains(bad_chains)));
    }
    if cdt.num_constraints() != segments.len() {
        return Ok(Err(Failure::Stop));
    }
    Ok(Ok((cdt, coarse_of_handle)))
}

/// The faces of `cdt` inside the coarse domain, as counter-clockwise triangles in coarse
/// numbering: a flood fill from the exterior in which crossing a boundary segment toggles.
fn inside_cells(
    cdt: &ConstrainedDelaunayTriangulation<Point2<f64>>,
    coarse_of_handle: &[u32],
    seg_of: &HashMap<u64, usize>,
    segments: &[Segment],
) -> Attempt<Vec<[u32; 3]>> {
    let cv = |h: FixedVertexHandle| coarse_of_handle[h.index()];
    let segment_at = |a: u32, b: u32| seg_of.get(&edge_key(a, b)).map(|&k| &segments[k]);

    let nf = cdt.num_all_faces();
    let mut inside: Vec<Option<bool>> = vec![None; nf];
    inside[0] = Some(false);
    let mut queue: Vec<usize> = Vec::new();
    let mut head = 0;
    let toggles = |constraint: bool, a: FixedVertexHandle, b: FixedVertexHandle| -> bool {
        constraint && segment_at(cv(a), cv(b)).is_none_or(|s| !s.interior)
    };
    for fh in cdt.fixed_inner_faces() {
        let face = cdt.face(fh);
        for e in face.adjacent_edges() {
            if e.rev().face().is_outer() {
                let state = toggles(e.is_constraint_edge(), e.from().fix(), e.to().fix());
                match inside[fh.index()] {
                    None => {
                        inside[fh.index()] = Some(state);
                        queue.push(fh.index());
                    }
                    Some(s) if s != state => return Err(Failure::Stop),
                    _ => {}
                }
            }
        }
    }
    let inner: Vec<_> = cdt.fixed_inner_faces().collect();
    let mut slot = vec![usize::MAX; nf];
    for (k, fh) in inner.iter().enumerate() {
        slot[fh.index()] = k;
    }
    let face_of = |i: usize| cdt.face(inner[slot[i]]);
    while head < queue.len() {
        let fi = queue[head];
        head += 1;
        let s = inside[fi].expect("queued faces are classified");
        for e in face_of(fi).adjacent_edges() {
            let g = e.rev().face();
            if g.is_outer() {
                continue;
            }
            let gi = g.fix().index();
            let state = s ^ toggles(e.is_constraint_edge(), e.from().fix(), e.to().fix());
            match inside[gi] {
                None => {
                    inside[gi] = Some(state);
                    queue.push(gi);
                }
                Some(t) if t != state => return Err(Failure::Stop),
                _ => {}
            }
        }
    }

    // Coarse cells: the inside faces, counter-clockwise (spade's orientation).
    let mut cells: Vec<[u32; 3]> = Vec::with_capacity(inner.len());
    for fh in &inner {
        match inside[fh.index()] {
            Some(true) => cells.push(cdt.face(*fh).vertices().map(|v| cv(v.fix()))),
            Some(false) => {}
            None => return Err(Failure::Stop),
        }
    }
    if cells.is_empty() {
        return Err(Failure::Stop);
    }
    Ok(cells)
}

/// Every kept vertex must be in an inside cell (an interior point outside is dropped and the
/// attempt repeated), and every cell must have a positive area.
fn check_cells(
    cells: &[[u32; 3]],
    cx: &[DVec2],
    k: &Kept,
    f: &FeatureChains,
    area: &impl Fn(&[u32; 3]) -> f64,
) -> Attempt<()> {
    let nc = cx.len();
    let mut used = vec![false; nc];
    for t in cells {
        for &v in t {
            used[v as usize] = true;
        }
    }
    let unused: Vec<u32> = (0..nc).filter(|&i| !used[i]).map(|i| k.fine_vertex[i]).collect();
    if unused.iter().any(|&v| f.on_feature[v as usize]) {
        return Err(Failure::Stop);
    }
    if !unused.is_empty() {
        return Err(Failure::Points(unused));
    }
    // Positive areas.
    let (mut lo, mut hi) = (cx[0], cx[0]);
    for &p in cx {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let min_area = 1e-14 * (hi - lo).length_squared();
    if cells.iter().any(|t| area(t).is_nan() || area(t) <= min_area) {
        return Err(Failure::Stop);
    }
    Ok(())
}

/// The coarse patch faces: each segment an edge of the coarse cells, a boundary segment on the
/// triangulation's boundary (oriented with the domain on its left) and an interface segment
/// between two cells; the triangulation's boundary must be made of boundary segments only.
fn patch_segments(
    cells: &[[u32; 3]],
    edges: &EdgeCells,
    segments: &[Segment],
    coarse_of: &[u32],
) -> Attempt<Vec<([u32; 2], i32, bool)>> {
    let mut patch_edges: Vec<([u32; 2], i32, bool)> = Vec::with_capacity(segments.len());
    let mut boundary_segments = 0;
    for s in segments {
        let (a, b) = (coarse_of[s.a as usize], coarse_of[s.b as usize]);
        let Some([c0, c1]) = edges.get(a, b) else {
            return Err(Failure::Stop);
        };
        if s.interior {
            if c1 == u32::MAX {
                return Err(Failure::Stop);
            }
            patch_edges.push(([a, b], s.patch, true));
        } else {
            if c1 != u32::MAX {
                return Err(Failure::Stop);
            }
            boundary_segments += 1;
            let t = cells[c0 as usize];
            let forward = (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b);
            patch_edges.push((if forward { [a, b] } else { [b, a] }, s.patch, false));
        }
    }
    let boundary_edges = edges.edges.iter().filter(|e| e.1[1] == u32::MAX).count();
    if boundary_edges != boundary_segments {
        return Err(Failure::Stop);
    }
    Ok(patch_edges)
}

/// Regions: components of inside faces not separated by segments, each given the region of the
/// fine cell under the centroid of its largest face.
fn regions(
    fine: &Mesh,
    cells: &[[u32; 3]],
    cx: &[DVec2],
    edges: &EdgeCells,
    seg_of: &HashMap<u64, usize>,
    area: &impl Fn(&[u32; 3]) -> f64,
) -> Vec<i32> {
    let ncell = cells.len();
    let mut comp = vec![u32::MAX; ncell];
    let mut regions = vec![0i32; ncell];
    let fine_regions = fine.regions();
    // With one region there is nothing to look up: skip the point locator over the fine mesh.
    // The locator works on triangles: a fine mesh with other cells is located in their halves.
    let split = fine_regions.iter().any(|&r| r != fine_regions[0]).then(|| fine.split_into_triangles());
    let locator = split.as_ref().map(Locator::new);
    let fine_regions = split.as_ref().map_or(fine_regions, |m| m.regions());
    let mut stack = Vec::new();
    for start in 0..ncell {
        if comp[start] != u32::MAX {
            continue;
        }
        comp[start] = start as u32;
        stack.push(start);
        let mut members = Vec::new();
        while let Some(c) = stack.pop() {
            members.push(c);
            let [a, b, d] = cells[c];
            for (p, q) in [(a, b), (b, d), (d, a)] {
                if seg_of.contains_key(&edge_key(p, q)) {
                    continue;
                }
                let [c0, c1] = edges.get(p, q).expect("cell edge");
                let o = if c0 as usize == c { c1 } else { c0 };
                if o != u32::MAX && comp[o as usize] == u32::MAX {
                    comp[o as usize] = start as u32;
                    stack.push(o as usize);
                }
            }
        }
        members.sort_unstable();
        let mut big = members[0];
        for &c in &members {
            if area(&cells[c]) > area(&cells[big]) {
                big = c;
            }
        }
        let [a, b, d] = cells[big].map(|v| cx[v as usize]);
        let r =
            locator.as_ref().map_or(fine_regions[0], |l| fine_regions[l.locate((a + b + d) / 3.0, None).cell as usize]);
        for &c in &members {
            regions[c] = r;
        }
    }
    regions
}
