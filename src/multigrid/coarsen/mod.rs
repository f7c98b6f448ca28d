//! Vertex-removal coarsening (Mavriplis style): keep every other vertex along the feature chains
//! (boundary and interface patches), a maximal independent set of the interior vertices, and
//! retriangulate the kept points by a constrained Delaunay triangulation.
//!
//! Each coarse vertex is a fine vertex (same position), so transfers only need the location of
//! fine vertices in coarse cells (`transfer`). About half the resolution per direction survives.

#[cfg(test)]
pub(crate) mod tests;
mod locate;
mod triangulate;

use super::coarse_solve::DENSE_MAX;
use super::coarsener::{CoarseMesh, CoarseUnknowns, Coarsener};
use super::level::{Level, Transfer};
use super::restriction::Restriction;
use crate::sparse::{offset, CsrMatrix};
use locate::{Location, Locator};
use std::sync::Arc;
use crate::error::{Error, Result};
use crate::mesh::features::BoundaryFeatures;
use crate::mesh::{edge_key, EdgeCells, Mesh, VertexCells};
use glam::DVec2;
use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};
use std::collections::HashMap;
use triangulate::triangulate;

/// The 2D coarsener: vertex removal, constrained Delaunay retriangulation, barycentric
/// interpolation in the coarse triangles.
pub(crate) struct Delaunay2d {
    pub(crate) params: CoarsenParams,
    /// Per level, the coarse cell each fine unknown interpolates from (its weights are
    /// recomputed in these cells when the mesh moves).
    cells: Vec<Vec<u32>>,
}

impl Delaunay2d {
    pub(crate) fn new(params: CoarsenParams) -> Self {
        Delaunay2d { params, cells: Vec::new() }
    }
}

impl Coarsener for Delaunay2d {
    fn coarsen_mesh(&self, fine: &Mesh, links: &[[u32; 2]]) -> Result<Option<CoarseMesh>> {
        coarsen(fine, links, &self.params)
    }

    fn coarsen_unknowns(&mut self, _l: usize, _fine: &Level) -> Option<CoarseUnknowns> {
        None
    }

    /// Locates the unknowns of `fine` in the cells of `coarse`. Runs with every finer level
    /// alive, so its temporaries (points, locations) go as soon as they are used.
    fn transfer(&mut self, l: usize, fine: &Level, coarse: &Level) -> Transfer {
        let locs = locate::locate(coarse.mesh(), &dof_points(fine), &fine.dof_regions());
        let prolong = Arc::new(prolongation(coarse, &locs));
        self.cells.resize_with(self.cells.len().max(l + 1), Vec::new);
        self.cells[l] = locs.iter().map(|l| l.cell).collect();
        drop(locs);
        let restrict = Restriction::new(Arc::clone(&prolong));
        Transfer { prolong, restrict }
    }

    /// New weights in the same coarse cells, for the fine unknowns at their new positions.
    fn update(&self, l: usize, t: &mut Transfer, fine: &Level, coarse: &Level) {
        let mut locs: Vec<Location> = self.cells[l].iter().map(|&cell| Location { cell, weights: [0.0; 3] }).collect();
        locate::update_weights(coarse.mesh(), &dof_points(fine), &mut locs);
        t.prolong = Arc::new(prolongation(coarse, &locs));
        drop(locs);
        t.restrict = Restriction::new(Arc::clone(&t.prolong));
    }
}

/// Positions of a level's unknowns.
fn dof_points(l: &Level) -> Vec<DVec2> {
    l.dofs.dof_vertex.iter().map(|&v| l.mesh().xy(v as usize)).collect()
}

/// Row i interpolates fine unknown i from the unknowns of its coarse cell with the barycentric
/// weights: columns ascending, corners sharing an unknown summed in corner order onto zero
/// (exactly what `CsrMatrix::from_triplets` gives, built row by row without its triplet list).
fn prolongation(coarse: &Level, locs: &[Location]) -> CsrMatrix {
    let n = locs.len();
    let (mut row_ptr, mut cols, mut vals) =
        (Vec::with_capacity(n + 1), Vec::with_capacity(3 * n), Vec::with_capacity(3 * n));
    row_ptr.push(0);
    for loc in locs {
        let cd = coarse.dofs.cell_dofs(coarse.mesh(), loc.cell as usize);
        let mut corners = [0, 1, 2];
        corners.sort_by_key(|&k| cd[k]);
        let start = cols.len();
        for k in corners {
            if cols.len() == start || cols[cols.len() - 1] != cd[k] {
                cols.push(cd[k]);
                vals.push(0.0);
            }
            *vals.last_mut().expect("pushed above") += loc.weights[k];
        }
        row_ptr.push(offset(cols.len()));
    }
    CsrMatrix { nrows: n, ncols: coarse.n(), row_ptr, cols, vals }
}

/// When to stop coarsening and what counts as a corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoarsenParams {
    /// Stop when the coarse mesh would have fewer vertices than this.
    pub min_vertices: usize,
    /// Stop when the fine/coarse vertex ratio would be below this.
    pub min_ratio: f64,
    /// A boundary vertex where the boundary turns by more than this (degrees) is always kept.
    pub corner_angle_deg: f64,
    /// Coarsening by kept unknowns stops at a level of at most this many unknowns, or at a
    /// level a little above it whose coarse level would be far below it (`stops_above`): the
    /// coarsest level's dense solve is cheap there, and smaller Galerkin levels are nearly
    /// dense. None: 150 in 2D, 400 in 3D (docs/DESIGN.md §5 "Coarse levels" gives the
    /// measurements behind them).
    pub coarsest_unknowns: Option<usize>,
}

impl CoarsenParams {
    /// The coarsest level's largest size for meshes of dimension `dim` (see
    /// `coarsest_unknowns`).
    pub fn coarsest_unknowns_for(&self, dim: usize) -> usize {
        self.coarsest_unknowns.unwrap_or(if dim == 2 { 150 } else { 400 })
    }

    /// Whether a level of `n` unknowns a little above the coarsest size `size`
    /// (`coarsest_unknowns_for`, or a coarsener's own; at most a quarter above it), whose
    /// coarsening would keep `nc`,
    /// is the coarsest level instead: when its dense solve factors every group of its `dim`
    /// components (dim · n free directions at most, `DENSE_MAX`) and the coarse level would lie
    /// further below the coarsest size than this level lies above it (n · nc ≤ size², on a log
    /// scale). The coarsest level is then the one nearer the size chosen for it, not a small
    /// level below it whose Galerkin operator, nearly dense, is a poor coarse space; a level
    /// further above the size keeps its coarsening, whose smoothing costs less than a larger
    /// dense solve visited on every cycle (docs/DESIGN.md §5, "Coarse levels").
    pub(crate) fn stops_above(n: usize, nc: usize, dim: usize, size: usize) -> bool {
        n <= size.saturating_add(size / 4)
            && n.saturating_mul(dim) <= DENSE_MAX
            && n.saturating_mul(nc) <= size.saturating_mul(size)
    }
}

impl Default for CoarsenParams {
    fn default() -> Self {
        CoarsenParams { min_vertices: 10, min_ratio: 1.6, corner_angle_deg: 50.0, coarsest_unknowns: None }
    }
}

/// Attempts at fixing a failed triangulation (keeping a whole chain, dropping an interior point)
/// before giving up on this level.
const MAX_ATTEMPTS: usize = 24;

/// A patch face of the 2D fine mesh: a segment.
struct PatchSegment {
    vertices: [u32; 2],
    patch: i32,
    interior: bool,
}

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
pub(crate) fn coarsen(fine: &Mesh, links: &[[u32; 2]], params: &CoarsenParams) -> Result<Option<CoarseMesh>> {
    let nv = fine.num_vertices();
    if let Some(l) = links.iter().find(|l| l.iter().any(|&v| v as usize >= nv)) {
        return Err(Error::Coarsening(format!("link [{}, {}] names a vertex beyond {}", l[0], l[1], nv)));
    }
    if fine.has_general_cells() {
        return Err(Error::Coarsening(
            "coarse meshes are made from triangles and quads; a mesh with polygons uses kept unknowns (coarse levels \
             `auto` or least squares)"
                .into(),
        ));
    }
    if nv < params.min_vertices || (nv as f64) < params.min_ratio * params.min_vertices as f64 {
        return Ok(None);
    }
    let features = FeatureChains::build(fine, links, params);
    let around = fine.vertex_cells();
    let mut keep_all = vec![false; features.chains.len()];
    let mut banned = vec![false; nv];
    for _ in 0..MAX_ATTEMPTS {
        let Some((kept, segments)) = select(fine, &around, links, &features, &keep_all, &banned) else {
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

/// Feature chains and per-vertex feature data of the fine mesh (its corners from
/// `BoundaryFeatures::is_chain_corner`).
struct FeatureChains {
    chains: Vec<Chain>,
    /// Vertex lies on a feature edge.
    on_feature: Vec<bool>,
}

impl FeatureChains {
    fn build(fine: &Mesh, links: &[[u32; 2]], params: &CoarsenParams) -> FeatureChains {
        let nv = fine.num_vertices();
        let boundary = BoundaryFeatures::new(fine);
        let pe: Vec<PatchSegment> = (0..boundary.len())
            .map(|k| {
                let f = boundary.face(k);
                PatchSegment { vertices: [f.vertices[0], f.vertices[1]], patch: f.patch, interior: f.interior }
            })
            .collect();
        let pe = &pe[..];
        let x = fine.xy_all();
        let incident = |v: usize| boundary.faces_at(v);
        let other = |k: usize, v: u32| {
            let [a, b] = pe[k].vertices;
            if a == v {
                b
            } else {
                a
            }
        };
        let on_feature: Vec<bool> = (0..nv).map(|v| !incident(v).is_empty()).collect();
        let mut forced: Vec<bool> =
            (0..nv).map(|v| boundary.is_chain_corner(v, params.corner_angle_deg, &x)).collect();
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
                match incident(nxt as usize).iter().find(|&&k| !visited[k as usize]) {
                    Some(&k) => {
                        cur = nxt;
                        e = k as usize;
                    }
                    None => break,
                }
            }
            Chain { verts, patch: pe[first].patch, interior: pe[first].interior }
        };
        for v in (0..nv).filter(|&v| forced[v]) {
            for &k in incident(v) {
                if !visited[k as usize] {
                    chains.push(walk(v as u32, k as usize, &mut visited));
                }
            }
        }
        for v in 0..nv {
            // The lowest-index vertex of each remaining loop is met first.
            if let Some(&k) = incident(v).iter().find(|&&k| !visited[k as usize]) {
                chains.push(walk(v as u32, k as usize, &mut visited));
            }
        }
        FeatureChains { chains, on_feature }
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
    around: &VertexCells,
    links: &[[u32; 2]],
    f: &FeatureChains,
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
    // already selected. A vertex's neighbours are the corners of its cells.
    let mut blocked = vec![false; nv];
    let block_around = |v: usize, blocked: &mut [bool]| {
        for &c in around.of(v) {
            fine.cell(c as usize).iter().for_each(|&j| blocked[j as usize] = true);
        }
    };
    for v in (0..nv).filter(|&v| kept[v]) {
        block_around(v, &mut blocked);
    }
    for v in 0..nv {
        if kept[v] || f.on_feature[v] || blocked[v] || banned[v] {
            continue;
        }
        kept[v] = true;
        block_around(v, &mut blocked);
    }
    sync_links(links, &mut kept);
    for v in 0..nv {
        if banned[v] && !f.on_feature[v] {
            kept[v] = false;
        }
    }
    Some((kept, segments))
}
