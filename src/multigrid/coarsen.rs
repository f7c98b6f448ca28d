//! Vertex-removal coarsening (Mavriplis style): keep every other vertex along the feature chains
//! (boundary and interface patches), a maximal independent set of the interior vertices, and
//! retriangulate the kept points by a constrained Delaunay triangulation.
//!
//! Each coarse vertex is a fine vertex (same position), so transfers only need the location of
//! fine vertices in coarse cells (`transfer`). About half the resolution per direction survives.

use super::transfer::Locator;
use crate::error::{Error, Result};
use crate::mesh::{edge_key, EdgeCells, Mesh, PatchEdge};
use glam::DVec2;
use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};
use std::collections::HashMap;

/// When to stop coarsening and what counts as a corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoarsenParams {
    /// Stop when the coarse mesh would have fewer vertices than this.
    pub min_vertices: usize,
    /// Stop when the fine/coarse vertex ratio would be below this.
    pub min_ratio: f64,
    /// A boundary vertex where the boundary turns by more than this (degrees) is always kept.
    pub corner_angle_deg: f64,
}

impl Default for CoarsenParams {
    fn default() -> Self {
        CoarsenParams { min_vertices: 10, min_ratio: 1.6, corner_angle_deg: 50.0 }
    }
}

/// One coarse level.
#[derive(Clone, Debug)]
pub struct CoarseMesh {
    /// The coarse mesh: valid, all cells counter-clockwise with positive area.
    pub mesh: Mesh,
    /// Coarse vertex `i` is fine vertex `fine_vertex[i]` (same position); ascending.
    pub fine_vertex: Vec<u32>,
    /// The input links whose two vertices were both kept, in coarse numbering.
    pub links: Vec<[u32; 2]>,
}

/// Attempts at fixing a failed triangulation (keeping a whole chain, dropping an interior point)
/// before giving up on this level.
const MAX_ATTEMPTS: usize = 24;

/// A path of feature edges between two forced vertices, or a closed loop.
struct Chain {
    /// n + 1 vertices for n edges; `verts[0] == verts[n]` for a closed chain.
    verts: Vec<u32>,
    patch: i32,
    interior: bool,
}

impl Chain {
    fn closed(&self) -> bool {
        self.verts.first() == self.verts.last()
    }
}

/// A coarse feature segment (fine numbering until the coarse numbering exists).
#[derive(Clone, Copy, Debug)]
struct Segment {
    a: u32,
    b: u32,
    patch: i32,
    interior: bool,
    chain: usize,
}

/// Why one triangulation attempt failed.
enum Failure {
    /// Keep every vertex of these chains and retry.
    Chains(Vec<usize>),
    /// Drop these interior points (outside the coarse domain) and retry.
    Points(Vec<u32>),
    /// Nothing to fix: stop coarsening at this level.
    Stop,
}

/// Coarsens `fine`. `links` are pairs of fine vertices the solver merges (periodic sides); both
/// or neither vertex of a pair is kept.
///
/// `Ok(None)` when coarsening is not worthwhile (too few vertices, ratio too small) or the coarse
/// triangulation could not be made valid; `Err(Error::Coarsening)` only for impossible input.
pub fn coarsen(fine: &Mesh, links: &[[u32; 2]], params: &CoarsenParams) -> Result<Option<CoarseMesh>> {
    let nv = fine.num_vertices();
    if let Some(l) = links.iter().find(|l| l.iter().any(|&v| v as usize >= nv)) {
        return Err(Error::Coarsening(format!("link [{}, {}] names a vertex beyond {}", l[0], l[1], nv)));
    }
    if nv < params.min_vertices || (nv as f64) < params.min_ratio * params.min_vertices as f64 {
        return Ok(None);
    }
    let features = Features::build(fine, links, params);
    let mut keep_all = vec![false; features.chains.len()];
    let mut banned = vec![false; nv];
    for _ in 0..MAX_ATTEMPTS {
        let Some((kept, segments)) = select(fine, links, &features, &keep_all, &banned) else {
            return Ok(None);
        };
        let nc = kept.iter().filter(|&&k| k).count();
        if nc < params.min_vertices || (nv as f64) < params.min_ratio * nc as f64 {
            return Ok(None);
        }
        match triangulate(fine, links, &kept, &segments, &features)? {
            Ok(coarse) => return Ok(Some(coarse)),
            Err(Failure::Chains(cs)) if cs.iter().any(|&c| !keep_all[c]) => {
                cs.into_iter().for_each(|c| keep_all[c] = true)
            }
            Err(Failure::Points(vs)) if vs.iter().any(|&v| !banned[v as usize]) => {
                vs.into_iter().for_each(|v| banned[v as usize] = true)
            }
            Err(_) => return Ok(None),
        }
    }
    Ok(None)
}

/// Feature chains and per-vertex feature data of the fine mesh.
struct Features {
    chains: Vec<Chain>,
    /// Vertex lies on a feature edge.
    on_feature: Vec<bool>,
}

impl Features {
    fn build(fine: &Mesh, links: &[[u32; 2]], params: &CoarsenParams) -> Features {
        let nv = fine.num_vertices();
        let pe = fine.patch_edges();
        let x = fine.coords();
        // Incident feature edges per vertex (CSR, ascending edge index).
        let mut ptr = vec![0usize; nv + 1];
        for e in pe {
            for &v in &e.vertices {
                ptr[v as usize + 1] += 1;
            }
        }
        for i in 0..nv {
            ptr[i + 1] += ptr[i];
        }
        let mut next = ptr.clone();
        let mut inc = vec![0usize; ptr[nv]];
        for (k, e) in pe.iter().enumerate() {
            for &v in &e.vertices {
                inc[next[v as usize]] = k;
                next[v as usize] += 1;
            }
        }
        let incident = |v: usize| &inc[ptr[v]..ptr[v + 1]];
        let other = |k: usize, v: u32| {
            let [a, b] = pe[k].vertices;
            if a == v {
                b
            } else {
                a
            }
        };
        let cos_corner = params.corner_angle_deg.to_radians().cos();
        let mut forced = vec![false; nv];
        let mut on_feature = vec![false; nv];
        for v in 0..nv {
            let es = incident(v);
            if es.is_empty() {
                continue;
            }
            on_feature[v] = true;
            if es.len() != 2 {
                forced[v] = true;
                continue;
            }
            let (e1, e2) = (&pe[es[0]], &pe[es[1]]);
            if e1.patch != e2.patch || e1.interior != e2.interior {
                forced[v] = true;
                continue;
            }
            let (u, w) = (other(es[0], v as u32), other(es[1], v as u32));
            let d1 = x[v] - x[u as usize];
            let d2 = x[w as usize] - x[v];
            let (l1, l2) = (d1.length(), d2.length());
            if l1 == 0.0 || l2 == 0.0 || d1.dot(d2) < cos_corner * l1 * l2 {
                forced[v] = true;
            }
        }
        // A vertex linked to a forced vertex is forced (to a fixed point: links may chain).
        loop {
            let mut changed = false;
            for &[a, b] in links {
                let f = forced[a as usize] || forced[b as usize];
                for v in [a, b] {
                    if f && !forced[v as usize] {
                        forced[v as usize] = true;
                        changed = true;
                    }
                }
            }
            if !changed {
                break;
            }
        }
        // Walk the chains: paths from forced vertices first, then closed loops.
        let mut visited = vec![false; pe.len()];
        let mut chains = Vec::new();
        let walk = |start: u32, first: usize, visited: &mut Vec<bool>| -> Chain {
            let mut verts = vec![start];
            let (mut cur, mut e) = (start, first);
            loop {
                visited[e] = true;
                let nxt = other(e, cur);
                verts.push(nxt);
                if forced[nxt as usize] || nxt == start {
                    break;
                }
                match incident(nxt as usize).iter().find(|&&k| !visited[k]) {
                    Some(&k) => {
                        cur = nxt;
                        e = k;
                    }
                    None => break,
                }
            }
            Chain { verts, patch: pe[first].patch, interior: pe[first].interior }
        };
        for v in (0..nv).filter(|&v| forced[v]) {
            for &k in incident(v) {
                if !visited[k] {
                    chains.push(walk(v as u32, k, &mut visited));
                }
            }
        }
        for v in 0..nv {
            // The lowest-index vertex of each remaining loop is met first.
            if let Some(&k) = incident(v).iter().find(|&&k| !visited[k]) {
                chains.push(walk(v as u32, k, &mut visited));
            }
        }
        Features { chains, on_feature }
    }
}

/// Makes both vertices of every link kept when either is (to a fixed point).
fn sync_links(links: &[[u32; 2]], kept: &mut [bool]) {
    loop {
        let mut changed = false;
        for &[a, b] in links {
            if kept[a as usize] != kept[b as usize] {
                kept[a as usize] = true;
                kept[b as usize] = true;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
}

/// Chooses the kept vertices and the coarse feature segments; None when no valid choice exists.
fn select(
    fine: &Mesh,
    links: &[[u32; 2]],
    f: &Features,
    keep_all: &[bool],
    banned: &[bool],
) -> Option<(Vec<bool>, Vec<Segment>)> {
    let nv = fine.num_vertices();
    let mut kept = vec![false; nv];
    let mut keep_all = keep_all.to_vec();
    let segments = loop {
        kept.iter_mut().for_each(|k| *k = false);
        for (c, ch) in f.chains.iter().enumerate() {
            let n = ch.verts.len() - 1;
            let all = keep_all[c] || (ch.closed() && n < 6);
            for (p, &v) in ch.verts.iter().enumerate() {
                if all || p == 0 || p == n || (p % 2 == 0 && p + 2 <= n) {
                    kept[v as usize] = true;
                }
            }
        }
        sync_links(links, &mut kept);
        let mut segments = Vec::new();
        for (c, ch) in f.chains.iter().enumerate() {
            let mut last = ch.verts[0];
            for &v in &ch.verts[1..] {
                if kept[v as usize] {
                    segments.push(Segment { a: last, b: v, patch: ch.patch, interior: ch.interior, chain: c });
                    last = v;
                }
            }
        }
        // Two chains collapsing onto the same segment (or a degenerate one): keep their vertices.
        let mut keys: Vec<(u64, usize)> = segments.iter().map(|s| (edge_key(s.a, s.b), s.chain)).collect();
        keys.sort_unstable();
        let mut bad: Vec<usize> = segments.iter().filter(|s| s.a == s.b).map(|s| s.chain).collect();
        for w in keys.windows(2) {
            if w[0].0 == w[1].0 {
                bad.extend([w[0].1, w[1].1]);
            }
        }
        bad.retain(|&c| !keep_all[c]);
        if bad.is_empty() {
            if segments.iter().any(|s| s.a == s.b) || keys.windows(2).any(|w| w[0].0 == w[1].0) {
                return None;
            }
            break segments;
        }
        for c in bad {
            keep_all[c] = true;
        }
    };
    // Interior points: greedy maximal independent set in index order, kept feature vertices
    // already selected.
    let g = fine.graph();
    let mut blocked = vec![false; nv];
    for v in (0..nv).filter(|&v| kept[v]) {
        for &j in g.row(v).0 {
            blocked[j as usize] = true;
        }
    }
    for v in 0..nv {
        if kept[v] || f.on_feature[v] || blocked[v] || banned[v] {
            continue;
        }
        kept[v] = true;
        for &j in g.row(v).0 {
            blocked[j as usize] = true;
        }
    }
    sync_links(links, &mut kept);
    for v in 0..nv {
        if banned[v] && !f.on_feature[v] {
            kept[v] = false;
        }
    }
    Some((kept, segments))
}

/// Triangulates the kept points with the segments as constraints and builds the coarse mesh.
fn triangulate(
    fine: &Mesh,
    links: &[[u32; 2]],
    kept: &[bool],
    segments: &[Segment],
    f: &Features,
) -> Result<std::result::Result<CoarseMesh, Failure>> {
    let x = fine.coords();
    let fine_vertex: Vec<u32> = (0..fine.num_vertices() as u32).filter(|&v| kept[v as usize]).collect();
    let mut coarse_of = vec![u32::MAX; fine.num_vertices()];
    for (i, &v) in fine_vertex.iter().enumerate() {
        coarse_of[v as usize] = i as u32;
    }
    let nc = fine_vertex.len();
    // Bulk loading keeps the vertex order (and is far faster than inserting one by one).
    let points: Vec<Point2<f64>> = fine_vertex.iter().map(|&v| Point2::new(x[v as usize].x, x[v as usize].y)).collect();
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(points, Vec::new(), |_| {})
            .map_err(|e| Error::Coarsening(format!("triangulating the kept vertices: {e:?}")))?;
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
    // Segments in coarse numbering, keyed for lookup.
    let mut seg_of: HashMap<u64, usize> = HashMap::with_capacity(segments.len());
    for (k, s) in segments.iter().enumerate() {
        let (a, b) = (coarse_of[s.a as usize], coarse_of[s.b as usize]);
        seg_of.insert(edge_key(a, b), k);
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
    let cv = |h: FixedVertexHandle| coarse_of_handle[h.index()];
    let segment_at = |a: u32, b: u32| seg_of.get(&edge_key(a, b)).map(|&k| &segments[k]);

    // Inside/outside by flood fill from the exterior: crossing a boundary segment toggles.
    let nf = cdt.num_all_faces();
    let mut inside: Vec<Option<bool>> = vec![None; nf];
    inside[0] = Some(false);
    let mut queue: Vec<usize> = Vec::new();
    let mut head = 0;
    let toggles = |constraint: bool, a: FixedVertexHandle, b: FixedVertexHandle| -> bool {
        constraint && segment_at(cv(a), cv(b)).map_or(true, |s| !s.interior)
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
                    Some(s) if s != state => return Ok(Err(Failure::Stop)),
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
                Some(t) if t != state => return Ok(Err(Failure::Stop)),
                _ => {}
            }
        }
    }

    // Coarse cells: the inside faces, counter-clockwise (spade's orientation).
    let mut cells: Vec<[u32; 3]> = Vec::new();
    for fh in &inner {
        match inside[fh.index()] {
            Some(true) => cells.push(cdt.face(*fh).vertices().map(|v| cv(v.fix()))),
            Some(false) => {}
            None => return Ok(Err(Failure::Stop)),
        }
    }
    if cells.is_empty() {
        return Ok(Err(Failure::Stop));
    }
    let cx: Vec<DVec2> = fine_vertex.iter().map(|&v| x[v as usize]).collect();
    // Every kept vertex must be in an inside cell; an interior point outside is dropped.
    let mut used = vec![false; nc];
    for t in &cells {
        for &v in t {
            used[v as usize] = true;
        }
    }
    let unused: Vec<u32> = (0..nc).filter(|&i| !used[i]).map(|i| fine_vertex[i]).collect();
    if unused.iter().any(|&v| f.on_feature[v as usize]) {
        return Ok(Err(Failure::Stop));
    }
    if !unused.is_empty() {
        return Ok(Err(Failure::Points(unused)));
    }
    // Positive areas.
    let (mut lo, mut hi) = (cx[0], cx[0]);
    for &p in &cx {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let min_area = 1e-14 * (hi - lo).length_squared();
    let area = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|v| cx[v as usize]);
        0.5 * (b - a).perp_dot(c - a)
    };
    if cells.iter().any(|t| area(t).is_nan() || area(t) <= min_area) {
        return Ok(Err(Failure::Stop));
    }
    // Boundary of the triangulation = boundary segments; interface segments have two cells.
    let Ok(edges) = EdgeCells::build(&cells) else {
        return Ok(Err(Failure::Stop));
    };
    let mut patch_edges = Vec::with_capacity(segments.len());
    let mut boundary_segments = 0;
    for s in segments {
        let (a, b) = (coarse_of[s.a as usize], coarse_of[s.b as usize]);
        let Some([c0, c1]) = edges.get(a, b) else {
            return Ok(Err(Failure::Stop));
        };
        if s.interior {
            if c1 == u32::MAX {
                return Ok(Err(Failure::Stop));
            }
            patch_edges.push(PatchEdge { vertices: [a, b], patch: s.patch, interior: true });
        } else {
            if c1 != u32::MAX {
                return Ok(Err(Failure::Stop));
            }
            boundary_segments += 1;
            let t = cells[c0 as usize];
            let forward = (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b);
            patch_edges.push(PatchEdge {
                vertices: if forward { [a, b] } else { [b, a] },
                patch: s.patch,
                interior: false,
            });
        }
    }
    let boundary_edges = edges.edges.iter().filter(|e| e.1[1] == u32::MAX).count();
    if boundary_edges != boundary_segments {
        return Ok(Err(Failure::Stop));
    }
    // Regions: components of inside faces not separated by segments, each given the region of
    // the fine cell under the centroid of its largest face.
    let ncell = cells.len();
    let mut comp = vec![u32::MAX; ncell];
    let mut regions = vec![0i32; ncell];
    let locator = Locator::new(fine);
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
        let fine_cell = locator.locate((a + b + d) / 3.0, None).cell;
        let r = fine.regions()[fine_cell as usize];
        for &c in &members {
            regions[c] = r;
        }
    }
    let coarse_links = links
        .iter()
        .filter(|l| kept[l[0] as usize] && kept[l[1] as usize])
        .map(|l| [coarse_of[l[0] as usize], coarse_of[l[1] as usize]])
        .collect();
    Ok(Ok(CoarseMesh { mesh: Mesh::from_parts(cx, cells, regions, patch_edges), fine_vertex, links: coarse_links }))
}

#[cfg(test)]
pub(crate) mod tests {
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
        Mesh::new(&coords, &cells, IndexBase::Zero, &tags, None).unwrap()
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
        Mesh::new(&coords, &cells, IndexBase::Zero, &tags, Some(&regions)).unwrap()
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
        Mesh::new(&coords, &cells, IndexBase::Zero, &tags, None).unwrap()
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
                let p =
                    DVec2::new((i as f64 + 0.5 * (rng.next() - 0.5)) * h, (j as f64 + 0.5 * (rng.next() - 0.5)) * h);
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
                let m =
                    f.vertices().iter().fold(DVec2::ZERO, |s, v| s + DVec2::new(v.position().x, v.position().y)) / 3.0;
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
        Mesh::new(&coords, &cells, IndexBase::Zero, &tags, None).unwrap()
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
        Mesh::new(&coords, &cells, IndexBase::Zero, &tags, None).unwrap()
    }

    /// Checks everything a coarse level promises and returns its area.
    pub(crate) fn check(fine: &Mesh, c: &CoarseMesh) -> f64 {
        let m = &c.mesh;
        // Round trip through the validating constructor.
        let tags: Vec<([u32; 2], i32)> = m.patch_edges().iter().map(|e| (e.vertices, e.patch)).collect();
        let again = Mesh::new(&m.coords_xy(), m.cells(), IndexBase::Zero, &tags, Some(m.regions()))
            .expect("coarse mesh validates");
        assert_eq!(again.patch_edges().len(), m.patch_edges().len());
        let areas = crate::mesh::quality::signed_areas(m, m.coords());
        assert!(areas.iter().all(|&a| a > 0.0), "non-positive coarse cell");
        assert_eq!(c.fine_vertex.len(), m.num_vertices());
        assert!(c.fine_vertex.windows(2).all(|w| w[0] < w[1]));
        for (i, &v) in c.fine_vertex.iter().enumerate() {
            assert_eq!(m.coords()[i], fine.coords()[v as usize]);
        }
        let mut used = vec![false; m.num_vertices()];
        m.cells().iter().flatten().for_each(|&v| used[v as usize] = true);
        assert!(used.iter().all(|&u| u), "unused coarse vertex");
        // Boundary edges oriented with the domain on the left; every boundary edge is a patch edge.
        let edges = EdgeCells::build(m.cells()).unwrap();
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
                let t = m.cells()[c0 as usize];
                assert!((0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b));
            }
        }
        assert_eq!(nb, nbp);
        areas.iter().sum()
    }

    fn fine_area(m: &Mesh) -> f64 {
        crate::mesh::quality::signed_areas(m, m.coords()).iter().sum()
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
        let x = c.mesh.coords();
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
            let p = c.mesh.coords()[v as usize];
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
        let x = m.coords();
        let iface: Vec<_> = m.patch_edges().iter().filter(|e| e.patch == 9).collect();
        assert_eq!(iface.len(), 16);
        let mut len = 0.0;
        for e in &iface {
            assert!(e.interior);
            let [a, b] = e.vertices.map(|v| x[v as usize]);
            assert!(a.y == 0.5 && b.y == 0.5);
            len += (a - b).length();
        }
        assert!((len - 1.0).abs() < 1e-14);
        let areas = crate::mesh::quality::signed_areas(m, x);
        let (mut a1, mut a2) = (0.0, 0.0);
        for (k, t) in m.cells().iter().enumerate() {
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
        let fine = Mesh::new(&coords, &cells, IndexBase::Zero, &tags, None).unwrap();
        let links: Vec<[u32; 2]> = (0..=16u32).map(|j| [j * 33, j * 33 + 32]).collect();
        let check_links = |m: &Mesh, l: &[[u32; 2]]| {
            let x = m.coords();
            let left = m.coords().iter().filter(|p| p.x == 0.0).count();
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
            let (p, q) = (c.mesh.coords()[a as usize], c.mesh.coords()[b as usize]);
            assert!(p.x == 0.0 && q.x == 2.0 && (p.y + q.y - 1.0).abs() < 1e-15);
        }
        assert_eq!(c.links.len(), c.mesh.coords().iter().filter(|p| p.x == 0.0).count());
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
        let cells: Vec<[u32; 3]> = base.cells().iter().map(|t| t.map(relabel)).collect();
        let tags: Vec<([u32; 2], i32)> =
            base.patch_edges().iter().map(|e| (e.vertices.map(relabel), e.patch)).collect();
        let fine = Mesh::new(&coords, &cells, IndexBase::Zero, &tags, None).unwrap();
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
            assert_eq!(a.mesh.coords(), b.mesh.coords());
            assert_eq!(a.mesh.cells(), b.mesh.cells());
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
}
