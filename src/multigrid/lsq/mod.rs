//! Coarse levels without meshes: a subset of the fine unknowns, interpolated by least squares
//! (the coarsener of 3D meshes, and a choice in 2D).
//!
//! No permissively licensed 3D constrained tetrahedraliser exists to rebuild coarse meshes as
//! the 2D coarsener does, and interpolation needs none: a coarse level keeps a maximal
//! independent set of the strongly coupled fine unknowns (`select`, `strong`), each fine
//! unknown interpolates from coarse unknowns of its neighbourhood with the smallest weights that reproduce linear fields exactly
//! along the feature it lies on (`weights`: the whole space inside, the tangent plane on a
//! wall, the line on a crease), and the coarse operators are Galerkin products PᵀKP and PᵀV.
//! Linear exactness is what the biharmonic needs (docs/DESIGN.md §5); aggregation without it
//! does not converge mesh-independently. Coarse unknowns are fine unknowns, so a moved fine
//! mesh moves them too: the interpolation is chosen again at the new positions.

mod along_lines;
mod features;
mod on_lines;
mod weights;

pub(crate) use features::Features;
// The distributed levels share the serial donor rule and fit.
#[cfg(feature = "mpi")]
pub(crate) use along_lines::{end_neighbour, rows_on_line};
#[cfg(feature = "mpi")]
pub(crate) use weights::{bounded, choose_donors, fit_offsets};

use super::coarse_solve::DENSE_MAX;
use super::coarsen::CoarsenParams;
use super::coarsener::{CoarseMesh, CoarseUnknowns, Coarsener};
use super::level::{Level, Transfer};
use super::restriction::Restriction;
use crate::mesh::Mesh;
use crate::operator::Method;
use crate::sparse::CsrMatrix;
use crate::Result;
use on_lines::OnLines;
use std::sync::Arc;

/// The coarsener whose coarse levels are subsets of the fine unknowns.
pub(crate) struct LeastSquares {
    pub(crate) params: CoarsenParams,
    /// Per level, what the coarsener knows of its unknowns (the pieces of boundary they lie
    /// on, their regions): built from the mesh of the last level that has one, subsets below.
    features: Vec<Features>,
    /// Whether the level the features were built on has lines across wall layers: its kept
    /// levels interpolate from the fewest donors that fit (`weights::Donors::Fewest`).
    layered: bool,
    /// Whether the unknowns on lines interpolate along them (`along_lines`): the biharmonic's
    /// hierarchies in 2D with lines. The biharmonic is fourth order, and linear interpolation
    /// leaves kinks whose energy is that of the smooth error itself. The second-order operators
    /// need no more than linear rows (the Laplacian lost iterations along the lines), and in 3D
    /// the spheroid's larger size and the wing lost iterations with them (docs/perf-history.md,
    /// "Interpolation along the lines").
    along_lines: bool,
    /// Whether the unknowns on lines are kept or dropped along them (`on_lines`): the
    /// biharmonic's hierarchies with lines across thin wall layers (`Lines::thin`), in 2D and
    /// 3D. The Laplacian keeps the general rule (it lost iterations with it, docs/perf-history.md
    /// "Coarse levels that keep their lines"), and so do the rays of a mesh graded to a wall,
    /// whose Galerkin levels kept along them converge worse as the mesh grows than the general
    /// rule's (docs/PERFORMANCE.md, "The graded cylinder's rays are not wall layers").
    on_lines: bool,
}

/// The coarsest level's largest size on the 2D biharmonic's hierarchies that interpolate along
/// lines across thin wall layers (`LeastSquares::along_lines` and `on_lines`; a graded mesh's
/// rays keep the general size). Below the lines their levels are Galerkin products
/// of isotropic cells, whose two-level pairs each leave part of the slow error; every level more
/// multiplies what a W-cycle leaves, and the largest airfoils coarsen several such levels down
/// to the general 150. Stopping at a level of a few hundred unknowns, factored densely, keeps the
/// count as the mesh grows (docs/DESIGN.md §5, "Coarse levels").
const COARSEST_ALONG_LINES: usize = 800;

impl LeastSquares {
    pub(crate) fn new(params: CoarsenParams) -> Self {
        LeastSquares { params, features: Vec::new(), layered: false, along_lines: false, on_lines: false }
    }

    /// The coarsest level's largest size on this hierarchy: the caller's, else
    /// `COARSEST_ALONG_LINES` where the unknowns on lines across thin wall layers interpolate
    /// along them (the 2D biharmonic under wall layers), else
    /// `CoarsenParams::coarsest_unknowns_for`.
    fn coarsest_size(&self, dim: usize) -> usize {
        match self.params.coarsest_unknowns {
            None if self.along_lines && self.on_lines => COARSEST_ALONG_LINES,
            _ => self.params.coarsest_unknowns_for(dim),
        }
    }

    /// Whether `fine` is the coarsest level by its size: at most `coarsest_size`, where its
    /// dense solve factors every group (`DENSE_MAX` free directions; the components of a group
    /// coupled by slip walls count together).
    fn coarsest(&self, fine: &Level) -> bool {
        let n = fine.n();
        let width = if fine.slip.is_some() { fine.dim() } else { 1 };
        let size = self.coarsest_size(fine.dim());
        n <= size && (size <= self.params.coarsest_unknowns_for(fine.dim()) || n.saturating_mul(width) <= DENSE_MAX)
    }

    /// How the rows of P choose their donors on this hierarchy.
    fn donors(&self) -> weights::Donors {
        match (self.layered, self.along_lines) {
            (true, true) => weights::Donors::AlongLines,
            (true, false) => weights::Donors::Fewest,
            _ => weights::Donors::Strong,
        }
    }
}

impl Coarsener for LeastSquares {
    fn coarsen_mesh(&self, _fine: &Mesh, _links: &[[u32; 2]]) -> Result<Option<CoarseMesh>> {
        Ok(None)
    }

    fn coarsen_unknowns(&mut self, l: usize, fine: &Level) -> Option<CoarseUnknowns> {
        let n = fine.n();
        if n <= self.params.min_vertices || self.features.len() < l {
            return None;
        }
        if self.features.len() == l {
            let mesh = fine.mesh.as_ref()?;
            self.layered = !fine.lines.is_empty();
            let biharmonic = self.layered && fine.op.method == Method::Biharmonic;
            self.on_lines = biharmonic && fine.lines.lines().thin();
            self.along_lines = biharmonic && fine.dim() == 2;
            if self.coarsest(fine) {
                return None;
            }
            let regions = fine.dof_regions();
            self.features.push(Features::build(mesh, &fine.dofs, &fine.pairs, regions, self.params.corner_angle_deg));
        } else if self.coarsest(fine) {
            return None;
        }
        self.features.truncate(l + 1);
        let points = fine.unknown_points();
        // The biharmonic's hierarchies keep their lines: their unknowns are dropped along their
        // own line (`on_lines`).
        let mut on_lines = self.on_lines.then(|| OnLines::new(fine.lines.lines(), &fine.op.k, &self.features[l], &points));
        // The strong couplings, found once for the selection and the interpolation's rows.
        let mut strong = strong_couplings(&fine.op.k, &self.features[l], &points);
        let mut kept = select_on(&fine.op.k, &self.features[l], &points, &strong, on_lines.as_ref());
        let too_few_dropped = |kept: &[u32]| (n as f64) < self.params.min_ratio * kept.len() as f64;
        // A 2D level whose lines no longer couple strongly along themselves (a graded mesh's
        // rays, coarsened along them until their spacing passes the spacing across them) keeps
        // nearly every unknown on its lines; there the unknowns with no strong neighbour on
        // their own line take the general rule, as they do in 3D (`OnLines::across_lines`),
        // rather than end the hierarchy at a level too large to factor.
        if too_few_dropped(&kept) {
            if let Some(o) = on_lines.as_mut().filter(|o| !o.across()) {
                o.across_lines();
                kept = select_on(&fine.op.k, &self.features[l], &points, &strong, Some(o));
            }
        }
        // A layer one cell thick that the general rule cannot coarsen enough (a layer thinner
        // than its cells are wide: few unknowns have a strong neighbour that may interpolate
        // them) is coarsened within its planes (`Features::in_plane`); every other level keeps
        // the general rule.
        if too_few_dropped(&kept) && self.features[l].one_layer() {
            self.features[l].set_in_plane();
            strong = strong_couplings(&fine.op.k, &self.features[l], &points);
            kept = select_on(&fine.op.k, &self.features[l], &points, &strong, None);
        }
        let features = &self.features[l];
        let nc = kept.len();
        if nc < self.params.min_vertices || too_few_dropped(&kept) {
            return None;
        }
        // A level little above the coarsest size is the coarsest rather than one far below it.
        if CoarsenParams::stops_above(n, nc, fine.dim(), self.coarsest_size(fine.dim())) {
            return None;
        }
        let transfer = transfer(fine, features, &kept, self.donors(), Some(&strong));
        let coarse = features.subset(&kept);
        self.features.push(coarse);
        Some(CoarseUnknowns { kept, transfer })
    }

    fn transfer(&mut self, l: usize, fine: &Level, coarse: &Level) -> Transfer {
        transfer(fine, &self.features[l], &coarse.parent_vertex, self.donors(), None)
    }

    fn update(&self, l: usize, t: &mut Transfer, fine: &Level, coarse: &Level) {
        t.prolong = Arc::new(weights::prolongation(fine, &self.features[l], &coarse.parent_vertex, self.donors(), weights::Given::NONE));
        t.restrict = Restriction::new(Arc::clone(&t.prolong));
    }

    fn update_rows(&self, l: usize, t: &mut Transfer, fine: &Level, coarse: &Level, redo: &[bool]) {
        let given = weights::Given { strong: None, keep: Some((&*t.prolong, redo)) };
        t.prolong = Arc::new(weights::prolongation(fine, &self.features[l], &coarse.parent_vertex, self.donors(), given));
        t.restrict = Restriction::new(Arc::clone(&t.prolong));
    }
}

/// The transfer from `fine`, whose unknowns have the features `f`, to its unknowns `kept`, with
/// its strong couplings (`strong_couplings`) when they are at hand.
fn transfer(fine: &Level, f: &Features, kept: &[u32], donors: weights::Donors, strong: Option<&[f64]>) -> Transfer {
    let prolong = Arc::new(weights::prolongation(fine, f, kept, donors, weights::Given { strong, keep: None }));
    let restrict = Restriction::new(Arc::clone(&prolong));
    Transfer { prolong, restrict }
}

/// The kept unknowns, ascending: a maximal independent set of the strong couplings of K's graph
/// (`strong`), greedy in the order corners, creases, walls, inside (each by index), where an
/// unknown is dropped when a strongly coupled neighbour that may interpolate it
/// (`Features::donor_ok`) is already kept. Every dropped unknown thus has a kept neighbour to
/// interpolate from, features are coarsened along themselves (every other vertex of a crease,
/// an independent set of a wall), and thin cells are coarsened across their thickness only.
/// Within the planes of a one-cell layer (`Features::in_plane`) each unknown is visited beside
/// its partner across the layer
/// (`partner`), so the two planes, coarsened apart, keep the same unknowns where their graphs
/// agree (an extruded 2D mesh): the coarse levels stay slabs of the 2D section's coarse levels.
/// With `lines` (`OnLines`) a line's unknowns are visited together from the wall outward, and
/// dropped only for the unknowns `OnLines::may_drop_for` names.
#[cfg(test)]
fn select(k: &CsrMatrix, f: &Features, points: &[f64], lines: Option<&OnLines>) -> Vec<u32> {
    select_on(k, f, points, &strong_couplings(k, f, points), lines)
}

/// `select` given the level's strong couplings (`strong_couplings`).
fn select_on(k: &CsrMatrix, f: &Features, points: &[f64], strong: &[f64], lines: Option<&OnLines>) -> Vec<u32> {
    let n = k.nrows;
    let dim = f.dim();
    let at = |d: usize| &points[d * dim..(d + 1) * dim];
    let pair = |d: usize| if f.in_plane() { partner(k, f, d, |u| f.relative(d, u, at(d), at(u))).min(d) } else { d };
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_by_cached_key(|&d| {
        let d = d as usize;
        match lines.and_then(|o| o.key(d)) {
            Some((base, place)) => (f.feature_dim(d), base as usize, place as usize),
            None => (f.feature_dim(d), pair(d), d),
        }
    });
    let mut kept = vec![false; n];
    let mut near: Vec<u32> = Vec::new();
    for &v in &order {
        let v = v as usize;
        let r = k.row_ptr[v] as usize..k.row_ptr[v + 1] as usize;
        let mut strongly = k.cols[r.clone()].iter().zip(&strong[r]).filter(|(_, d)| !d.is_nan()).map(|(&u, _)| u);
        // An unknown on a line keeps to it (`OnLines::may_drop_for`), in 3D only while it is
        // coupled strongly along it (`OnLines::keeps_to_line`).
        let along = lines.filter(|o| {
            near.clear();
            near.extend(strongly.clone());
            o.keeps_to_line(v, &near)
        });
        let may_drop_for = |u: usize| along.is_none_or(|o| o.may_drop_for(v, u));
        if !strongly.any(|u| kept[u as usize] && f.donor_ok(v, u as usize) && may_drop_for(u as usize)) {
            kept[v] = true;
        }
    }
    (0..n as u32).filter(|&d| kept[d as usize]).collect()
}

/// The unknown across a one-cell layer from `v` (`v` itself when there is none): its nearest
/// neighbour in K's graph on a feature of the same dimension that neither may interpolate the
/// other (the other plane's copy of `v`'s wall, edge or corner).
fn partner(k: &CsrMatrix, f: &Features, v: usize, rel: impl Fn(usize) -> [f64; 3]) -> usize {
    let fd = f.feature_dim(v);
    k.row(v)
        .0
        .iter()
        .map(|&u| u as usize)
        .filter(|&u| u != v && f.feature_dim(u) == fd && !f.donor_ok(v, u) && !f.donor_ok(u, v))
        .map(|u| (norm2(rel(u)), u))
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        .map_or(v, |(_, u)| u)
}

/// How much farther than the nearest neighbour in its direction a neighbour may be and still
/// count as strongly coupled. Within a cell of moderate aspect ratio every neighbour does (a
/// cube's diagonal is √3 of its edge); across a thin layer only the neighbours through its
/// thickness do.
const STRONG_REACH: f64 = 2.0;

/// How much farther than the nearest neighbour of all the nearest neighbour in a direction may
/// be for that direction to count as strongly coupled (`directional`): across cells stretched
/// more than this, the unknown is coarsened along their short sides only.
const SHORT_DIRECTION: f64 = 1.3;

/// The squared cosine of the half-angle of a direction's cone in `directional` (30°).
const CONE_COS2: f64 = 0.75;

/// The smallest spread of the short directions' unit vectors along an axis, relative to the
/// largest, for `directional` to count that axis as spanned by them.
const SPAN: f64 = 0.1;

/// Buffers of `strong`, reused from row to row: the row's offsets and its short neighbours.
#[derive(Default)]
pub(super) struct Shorts {
    /// The offset of each entry of the row from its unknown (zero at the unknown itself).
    rel: Vec<[f64; 3]>,
    /// `directional`'s short neighbours, each its offset and squared distance.
    short: Vec<([f64; 3], f64)>,
}

/// The neighbours of `v` in K's graph (not `v`) that are strongly coupled to it
/// (`directional`), `rel(u)` giving u's offset from `v`: `out`, one value per entry of K's row
/// `v`, takes the squared distance of each such neighbour and NaN at every other entry. The
/// stiffness couples neighbours as the inverse square of their distance, so the near ones are
/// the strong ones; K's own entries are no guide, as a trilinear hexahedron couples face
/// neighbours by zero.
///
/// On a layer one cell thick coarsened within its planes (`Features::in_plane`), an unknown
/// whose strong neighbours all lie across the thickness, on the other plane, could never be
/// dropped: none of them may interpolate it (`Features::donor_ok`). For such an unknown only the
/// neighbours that may interpolate it (on its own plane, or its edge) count, the nearest among
/// them setting the reach, so each plane is coarsened as its 2D section would be; every other
/// unknown keeps the rule above. `buf` holds the row's offsets (each found once) and
/// `directional`'s short neighbours.
pub(super) fn strong(
    k: &CsrMatrix,
    f: &Features,
    v: usize,
    rel: impl Fn(usize) -> [f64; 3],
    out: &mut [f64],
    buf: &mut Shorts,
) {
    let row = k.row(v).0;
    buf.rel.clear();
    buf.rel.extend(row.iter().map(|&u| if u as usize != v { rel(u as usize) } else { [0.0; 3] }));
    for ((d, &u), r) in out.iter_mut().zip(row).zip(&buf.rel) {
        *d = if u as usize != v { norm2(*r) } else { f64::INFINITY };
    }
    let near = STRONG_REACH * STRONG_REACH * nearest_of(out);
    let eligible = |u: u32| u as usize != v && f.donor_ok(v, u as usize);
    if f.in_plane() && !row.iter().zip(out.iter()).any(|(&u, &d)| d <= near && eligible(u)) {
        // Only the eligible neighbours, at the distances found above (u ≠ v for each).
        for (d, &u) in out.iter_mut().zip(row) {
            *d = if eligible(u) { *d } else { f64::INFINITY };
        }
        let near = STRONG_REACH * STRONG_REACH * nearest_of(out);
        out.iter_mut().for_each(|d| *d = if *d <= near && *d < f64::INFINITY { *d } else { f64::NAN });
        return;
    }
    if f.dim() == 3 {
        directional(row, v, &buf.rel, out, &mut buf.short);
    } else {
        // 2D keeps one reach from the nearest neighbour: its slip-wall channel's kept levels
        // took more iterations with the directions' rule.
        out.iter_mut().for_each(|d| *d = if *d <= near { *d } else { f64::NAN });
    }
}

/// Marks the strong couplings of `v` among its neighbours `row`, at offsets `rel` and squared
/// distances `d2` (∞ at `v` itself): a neighbour is strong when its direction is a short one (some
/// neighbour within `CONE_COS2`'s cone of it, either way along it, lies within
/// `SHORT_DIRECTION` of the nearest neighbour of all) and it lies within `STRONG_REACH` of the
/// nearest neighbour in that cone; a neighbour with no short one in its cone is strong when it
/// lies within 30° of the short directions' span (a cube's diagonals) and within `STRONG_REACH`
/// of the nearest neighbour of all. Every other entry becomes NaN. Across cells longer one way
/// than the other (a graded shell whose cells are longer across it than along it) the long
/// direction is weak, whatever the ratio beyond `SHORT_DIRECTION`, so the shell is coarsened
/// along itself; within cells of moderate aspect ratio every direction is short and the reach
/// is the nearest neighbour's. `shorts` is a buffer the caller reuses from row to row.
fn directional(row: &[u32], v: usize, rel: &[[f64; 3]], d2: &mut [f64], shorts: &mut Vec<([f64; 3], f64)>) {
    let nearest = nearest_of(d2);
    let short = SHORT_DIRECTION * SHORT_DIRECTION * nearest;
    let reach = STRONG_REACH * STRONG_REACH * short;
    let within_nearest = STRONG_REACH * STRONG_REACH * nearest;
    // The short neighbours (offset, squared distance): only they can set a direction's spacing.
    shorts.clear();
    shorts.extend(row.iter().zip(d2.iter()).zip(rel).filter(|&((&u, &d), _)| u as usize != v && d <= short).map(|((_, &d), &r)| (r, d)));
    let shorts = &shorts[..];
    // The axes the short directions span (those of their unit vectors' spread above a tenth
    // of the largest): a neighbour within 30° of their span is along the cells' short sides.
    // Where the moments' determinant shows every spread above `SPAN` of the largest (cells of
    // moderate aspect ratio), no axis is across the span and the eigenproblem is not solved.
    let moments = weights::moments(shorts.iter().map(|&(s, ds)| s.map(|x| x / ds.sqrt())));
    let mut across = [[0.0; 3]; 3];
    let mut n_across = 0;
    if !weights::spans_every_axis(&moments, SPAN) {
        let (axes, spread) = weights::principal_axes_of_moments(moments);
        for i in (0..3).filter(|&i| spread[i] < SPAN * spread[0]) {
            across[n_across] = axes[i];
            n_across += 1;
        }
    }
    let across = &across[..n_across];
    let in_span = |r: [f64; 3], d: f64| {
        let off: f64 = across.iter().map(|a| (r[0] * a[0] + r[1] * a[1] + r[2] * a[2]).powi(2)).sum();
        off <= (1.0 - CONE_COS2) * d
    };
    for ((d, &u), &r) in d2.iter_mut().zip(row).zip(rel) {
        if u as usize == v || *d > reach {
            *d = f64::NAN;
            continue;
        }
        let in_cone = |&&(s, ds): &&([f64; 3], f64)| {
            let dot = r[0] * s[0] + r[1] * s[1] + r[2] * s[2];
            dot * dot >= CONE_COS2 * *d * ds
        };
        // Within the reach of the nearest neighbour of all a neighbour is within that of its
        // cone's nearest too (no short neighbour is nearer than the nearest), so there it is
        // strong when its direction lies in the short directions' span (every direction, when
        // they span all three axes) or any short neighbour lies in its cone. Beyond it, it is strong within the
        // reach of its cone's nearest short neighbour, and weak with none in its cone (a
        // stretched shell's long side).
        let strong = if *d <= within_nearest {
            in_span(r, *d) || shorts.iter().any(|s| in_cone(&s))
        } else {
            let spacing = shorts.iter().filter(in_cone).map(|&(_, ds)| ds).fold(f64::INFINITY, f64::min);
            spacing < f64::INFINITY && *d <= STRONG_REACH * STRONG_REACH * spacing
        };
        if !strong {
            *d = f64::NAN;
        }
    }
}

/// The smallest of `d2` (∞ when empty; NaNs ignored), in four running minima: the smallest of
/// a set is the same whatever order it is taken in.
fn nearest_of(d2: &[f64]) -> f64 {
    let mut m = [f64::INFINITY; 4];
    let chunks = d2.chunks_exact(4);
    let rest = chunks.remainder().iter().fold(f64::INFINITY, |a, &d| a.min(d));
    for c in chunks {
        for i in 0..4 {
            m[i] = m[i].min(c[i]);
        }
    }
    m[0].min(m[1]).min(m[2].min(m[3])).min(rest)
}

/// Rows of K per task of `strong_couplings`.
const STRONG_ROWS: usize = 1024;

/// Every unknown's strong neighbours (`strong`): one value per entry of K, the squared distance
/// of a strong coupling and NaN elsewhere.
pub(super) fn strong_couplings(k: &CsrMatrix, f: &Features, points: &[f64]) -> Vec<f64> {
    use rayon::prelude::*;
    let dim = f.dim();
    let at = |d: usize| &points[d * dim..(d + 1) * dim];
    let mut out = vec![0.0; k.nnz()];
    crate::sparse::row_blocks(&k.row_ptr, &mut out, STRONG_ROWS).into_par_iter().for_each(|(rows, b)| {
        let base = k.row_ptr[rows.start] as usize;
        let mut shorts = Shorts::default();
        for v in rows {
            let r = k.row_ptr[v] as usize - base..k.row_ptr[v + 1] as usize - base;
            strong(k, f, v, |u| f.relative(v, u, at(v), at(u)), &mut b[r], &mut shorts);
        }
    });
    out
}

fn norm2(r: [f64; 3]) -> f64 {
    r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
}

#[cfg(test)]
mod tests {
    use super::{directional, nearest_of};

    /// The strong couplings of unknown 0 among neighbours 1.. at `offsets`: true where strong.
    fn strong_of(offsets: &[[f64; 3]]) -> Vec<bool> {
        let row: Vec<u32> = (0..=offsets.len() as u32).collect();
        let rel: Vec<[f64; 3]> = std::iter::once([0.0; 3]).chain(offsets.iter().copied()).collect();
        let mut d2: Vec<f64> = std::iter::once(f64::INFINITY).chain(offsets.iter().map(|r| r.iter().map(|x| x * x).sum())).collect();
        directional(&row, 0, &rel, &mut d2, &mut Vec::new());
        d2[1..].iter().map(|d| !d.is_nan()).collect()
    }

    /// In a shell whose cells are 1.8 times longer across it (x) than along it (y, z), the
    /// neighbours across it are weak, though within twice the nearest one's distance, and the
    /// shell's own neighbours strong; in cells of moderate aspect ratio every neighbour is strong.
    #[test]
    fn a_stretched_direction_is_weak() {
        let shell = [[1.8, 0.0, 0.0], [-1.8, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.1], [0.0, 1.0, 1.0]];
        assert_eq!(strong_of(&shell), [false, false, true, true, true, true, true]);
        let moderate = [[1.2, 0.0, 0.0], [-1.25, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.1], [1.0, 1.0, 1.0]];
        assert_eq!(strong_of(&moderate), [true; 6]);
        // Beyond the reach of its direction's nearest neighbour a neighbour is weak.
        let far = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 2.1, 0.0]];
        assert_eq!(strong_of(&far), [true, true, true, false]);
        // Beyond the nearest neighbour's reach, with no short neighbour in its cone, a
        // neighbour is weak, whether or not it lies in the short directions' span.
        let off_cone = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.5, 1.5, 1.0], [0.9, 0.9, 0.9]];
        assert_eq!(strong_of(&off_cone), [true, true, true, false, true]);
    }

    /// The four running minima give the sequential fold's minimum bitwise, with NaNs, infinities
    /// and ties among the values, for every slice of them (lengths 0 to 11).
    #[test]
    fn nearest_is_the_sequential_minimum_bitwise() {
        let values = [3.5, f64::NAN, 0.25, f64::INFINITY, 7.0, 0.25, 1e-300, f64::NAN, 2.0, 0.0, 5.0];
        for len in 0..=values.len() {
            for start in 0..=values.len() - len {
                let d = &values[start..start + len];
                let want = d.iter().fold(f64::INFINITY, |a, &b| a.min(b));
                assert_eq!(nearest_of(d).to_bits(), want.to_bits(), "{d:?}");
            }
        }
        assert_eq!(nearest_of(&values), 0.0);
    }
}
