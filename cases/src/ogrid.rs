//! Graded block-structured meshes of a body in a box: an O-grid shell around a sphere, a
//! spheroid (3D) or a circle, an ellipse (2D), and structured blocks filling the rest of the box.
//!
//! The layout, in 3D (2D is the same one dimension down):
//! - an *inner box* centred on the body, with `n_d` equal cells along axis d;
//! - a *shell* between the body and the inner box: every node of the inner box's surface is joined
//!   by a straight line to its image on the body, and each line is cut into `layers` pieces, the
//!   first the wall size, growing by `growth` up to a cap that makes them fill the line (lines
//!   too long for that grow faster, geometrically). The layer count is the smallest that ends the
//!   longest line (to an inner box corner) in a piece at most 1.25 times the inner box's spacing.
//!   The image of a surface node is the equiangular cube-sphere map: with q the node's position
//!   relative to the inner box, scaled to the unit cube, the unit vector along
//!   (tan(π q_x / 4), tan(π q_y / 4), tan(π q_z / 4)), scaled by the body's semi-axes;
//! - the rest of the box as a tensor grid (the 3×3×3 block layout with the centre block replaced
//!   by the shell): along each axis the inner box's nodes, and outside them cells growing
//!   geometrically (ratio `growth`) from the inner box's spacing to the far size.
//!
//! The hexahedral (quadrilateral) mesh is conforming by construction: the shell's outer layer is
//! the inner box's surface, node for node. The simplicial version splits every hexahedron around
//! an added centroid: each of its six faces into two triangles along the diagonal from the face's
//! smallest global vertex index, and one tetrahedron per triangle (12 per hexahedron). The split
//! of a face depends on the face's vertices alone, so both cells of a face split it alike and the
//! mesh stays conforming. Quadrilaterals split into two triangles the same way.
//!
//! # Sizes
//!
//! With wall size h_w, far size h_f and semi-axes s_d: `n_d` = max(2, ⌈π s_d / (2 h_w)⌉) (so the
//! body's surface spacing is about h_w: a quarter of the circumference over n_d cells); the inner
//! box's half-size is n_d h_f / 2 (its spacing h_f), reduced to fit the box. The shell's layer
//! count is about ln(h_f / h_w) / ln(growth) growing layers plus the layers at the cap (about
//! as many as the inner box's cells across its half-diagonal, so ∝ n). So a 3D sphere mesh has
//! 6 n² × layers hexahedra in the shell plus the tensor blocks: at a fixed h_f / h_w and a box
//! that fits the inner box, vertices grow like n³ ∝ (r / h_w)³ (the sphere channel, n = 16,
//! h_f / h_w = 3: 34,700 hexahedral vertices; h_f / h_w = 50 in [−20,20]³, n = 11: 19,944). The
//! tetrahedral mesh adds one vertex per hexahedron (about twice the vertices) and has 12
//! tetrahedra per hexahedron. In 2D vertices grow like n² ∝ (r / h_w)².
//! [`OgridPlan::num_vertices`] gives the exact count without building the mesh;
//! [`sphere_with_vertices`] and [`cylinder_with_vertices`] pick the wall size for a wanted count.

use meshmove::geometry::{CellPoints, CellType};
use meshmove::mesh::{Mesh, MeshData};
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

/// Patch of the box's walls (every side).
pub const OG_WALL: i32 = 1;
/// Patch of the body's surface.
pub const OG_BODY: i32 = 2;

/// The kind of cells of an O-grid mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellKind {
    /// Hexahedra (3D), quadrilaterals (2D).
    Tensor,
    /// Tetrahedra, 12 per hexahedron around its centroid (3D); triangles, 2 per quadrilateral
    /// (2D).
    Simplex,
}

/// An axis-aligned ellipsoid (ellipse in 2D) in an axis-aligned box, and the mesh sizes.
#[derive(Clone, Debug, PartialEq)]
pub struct OgridParams {
    /// 2 or 3.
    pub dim: usize,
    /// The body's centre (z ignored in 2D).
    pub center: [f64; 3],
    /// The body's semi-axes along x, y, z (all equal for a sphere).
    pub semi_axes: [f64; 3],
    /// The box: `[lo, hi]` along x, y, z.
    pub bounds: [[f64; 2]; 3],
    /// Cell size at the body: tangential spacing and first layer's height.
    pub wall: f64,
    /// Cell size far from the body (largest cell edge along the axes).
    pub far: f64,
    /// Largest ratio of neighbouring cell sizes along an axis of the tensor blocks, and of
    /// neighbouring layers of the shell where they are not forced to grow faster (1.2).
    pub growth: f64,
    /// Hexahedra or tetrahedra (quads or triangles).
    pub kind: CellKind,
}

impl OgridParams {
    /// A sphere of `radius` about `center` in the box `bounds`, tetrahedra.
    pub fn sphere(center: [f64; 3], radius: f64, bounds: [[f64; 2]; 3], wall: f64, far: f64) -> OgridParams {
        OgridParams::spheroid(center, [radius; 3], bounds, wall, far)
    }

    /// An ellipsoid of `semi_axes` about `center` in the box `bounds`, tetrahedra.
    pub fn spheroid(center: [f64; 3], semi_axes: [f64; 3], bounds: [[f64; 2]; 3], wall: f64, far: f64) -> OgridParams {
        OgridParams { dim: 3, center, semi_axes, bounds, wall, far, growth: 1.2, kind: CellKind::Simplex }
    }

    /// A circle of `radius` about `center` in the rectangle `bounds` (2D), triangles.
    pub fn cylinder(center: [f64; 2], radius: f64, bounds: [[f64; 2]; 2], wall: f64, far: f64) -> OgridParams {
        OgridParams {
            dim: 2,
            center: [center[0], center[1], 0.0],
            semi_axes: [radius, radius, 0.0],
            bounds: [bounds[0], bounds[1], [0.0, 0.0]],
            wall,
            far,
            growth: 1.2,
            kind: CellKind::Simplex,
        }
    }

    /// The same with cells of `kind`.
    pub fn with_kind(mut self, kind: CellKind) -> OgridParams {
        self.kind = kind;
        self
    }
}

/// The block structure of an O-grid mesh, computed from [`OgridParams`] without building it.
#[derive(Clone, Debug, PartialEq)]
pub struct OgridPlan {
    /// 2 or 3.
    pub dim: usize,
    /// Node coordinates of the tensor grid along each axis (a single 0 along z in 2D).
    pub axes: [Vec<f64>; 3],
    /// Index range `[first, last]` of the inner box's nodes along each axis (`[0, 0]` along z in
    /// 2D).
    pub inner: [[usize; 2]; 3],
    /// Half-sizes of the inner box.
    pub half: [f64; 3],
    /// Layers of the shell.
    pub layers: usize,
}

impl OgridPlan {
    /// Cells of the inner box along axis `d`.
    pub fn n(&self, d: usize) -> usize {
        self.inner[d][1] - self.inner[d][0]
    }

    /// Nodes of the inner box's surface.
    fn surface_nodes(&self) -> usize {
        let p = |k: usize| (0..self.dim).map(|d| self.n(d) + 1 - 2 * k).product::<usize>();
        p(0) - p(1)
    }

    /// Faces of the inner box's surface (quads in 3D, segments in 2D).
    pub(crate) fn surface_faces(&self) -> usize {
        let n: Vec<usize> = (0..self.dim).map(|d| self.n(d)).collect();
        if self.dim == 3 {
            2 * (n[0] * n[1] + n[1] * n[2] + n[0] * n[2])
        } else {
            2 * (n[0] + n[1])
        }
    }

    /// Hexahedra (quads) of the tensor mesh.
    pub fn num_tensor_cells(&self) -> usize {
        let tensor: usize = (0..self.dim).map(|d| self.axes[d].len() - 1).product();
        let inner: usize = (0..self.dim).map(|d| self.n(d)).product();
        tensor - inner + self.layers * self.surface_faces()
    }

    /// Vertices of the mesh of cells of `kind`.
    pub fn num_vertices(&self, kind: CellKind) -> usize {
        let tensor: usize = (0..self.dim).map(|d| self.axes[d].len()).product();
        let strict: usize = (0..self.dim).map(|d| self.n(d) - 1).product();
        let hex_vertices = tensor - strict + self.layers * self.surface_nodes();
        match (kind, self.dim) {
            (CellKind::Simplex, 3) => hex_vertices + self.num_tensor_cells(),
            _ => hex_vertices,
        }
    }

    /// Cells of the mesh of cells of `kind`.
    pub fn num_cells(&self, kind: CellKind) -> usize {
        let per = match (kind, self.dim) {
            (CellKind::Tensor, _) => 1,
            (CellKind::Simplex, 3) => 12,
            (CellKind::Simplex, _) => 2,
        };
        per * self.num_tensor_cells()
    }
}

/// Sizes growing geometrically by `g` from `h0` (the first is `h0 g`, capped at `max(hmax, h0)`),
/// as many as fill `len` best, scaled to fill it exactly; returned as offsets from the start,
/// the last exactly `len`.
fn graded_offsets(len: f64, h0: f64, hmax: f64, g: f64) -> Vec<f64> {
    let cap = hmax.max(h0);
    let mut sizes = Vec::new();
    let (mut sum, mut h) = (0.0, h0);
    while sum < len {
        h = (h * g).min(cap);
        sizes.push(h);
        sum += h;
    }
    // Drop the last size when the sum without it is nearer `len`.
    if sizes.len() > 1 && len - (sum - h) < sum - len {
        sizes.pop();
        sum -= h;
    }
    let scale = len / sum;
    let mut offsets = Vec::with_capacity(sizes.len());
    let mut acc = 0.0;
    for s in &sizes {
        acc += s * scale;
        offsets.push(acc);
    }
    *offsets.last_mut().expect("one size at least") = len;
    offsets
}

/// The smallest x in [lo, hi] with `f(x) >= target`, for `f` increasing (bisection).
fn bisect(f: impl Fn(f64) -> f64, target: f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// `m` sizes summing to `len`, the first `h`: h q^k capped at the size that makes them fill
/// `len` when growth by `q` overfills it; else geometric with the ratio (≥ `q`, or < 1 when
/// `m h` > `len`) that fills it.
fn layer_sizes(len: f64, h: f64, m: usize, q: f64) -> Vec<f64> {
    let geometric = |r: f64| (0..m).map(|k| h * r.powi(k as i32)).collect::<Vec<f64>>();
    let sum = |v: Vec<f64>| v.iter().sum::<f64>();
    if m == 1 {
        return vec![len];
    }
    if m as f64 * h >= len || sum(geometric(q)) <= len {
        let r = bisect(|r| sum(geometric(r)), len, 1e-3, (len / h).max(2.0));
        return geometric(r);
    }
    let capped = |cap: f64| geometric(q).into_iter().map(|s| s.min(cap)).collect::<Vec<f64>>();
    let cap = bisect(|c| sum(capped(c)), len, h, len);
    capped(cap)
}

/// Position of node `i` of `n` equal steps from `a` to `b`, both ends exact.
fn lerp(a: f64, b: f64, i: usize, n: usize) -> f64 {
    super::meshes::lerp_step(a, b, i, n)
}

/// The body's point for the inner box's surface point `b` (the equiangular cube-sphere map).
fn body_point(p: &OgridParams, half: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    let dim = p.dim;
    let mut u = [0.0; 3];
    for d in 0..dim {
        let q = ((b[d] - p.center[d]) / half[d]).clamp(-1.0, 1.0);
        u[d] = (FRAC_PI_4 * q).tan();
    }
    let norm = u.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut s = [0.0; 3];
    for d in 0..dim {
        s[d] = p.center[d] + p.semi_axes[d] * u[d] / norm;
    }
    s
}

/// The block structure of the mesh of `p`, or why `p` cannot be meshed.
pub fn plan(p: &OgridParams) -> Result<OgridPlan, String> {
    plan_with_cells(p, None)
}

/// [`plan`] with the inner box's cells along each axis given (`cells`, at least 2 each along
/// the mesh's axes) instead of derived from the wall size: the body's tangential spacing then
/// no longer follows the first layer's height, as in a wall-layered (viscous) mesh.
pub fn plan_with_cells(p: &OgridParams, cells: Option<[usize; 3]>) -> Result<OgridPlan, String> {
    let dim = p.dim;
    if dim != 2 && dim != 3 {
        return Err(format!("ogrid: dimension {dim}, not 2 or 3"));
    }
    if !(p.wall > 0.0 && p.far >= p.wall && p.far.is_finite()) {
        return Err(format!("ogrid: need 0 < wall ({}) <= far ({})", p.wall, p.far));
    }
    if !(p.growth > 1.0 && p.growth <= 2.0) {
        return Err(format!("ogrid: growth {} not in (1, 2]", p.growth));
    }
    let mut n = [0usize; 3];
    let mut half = [0.0; 3];
    for d in 0..dim {
        let (s, c, [lo, hi]) = (p.semi_axes[d], p.center[d], p.bounds[d]);
        if s.is_nan() || s <= 0.0 {
            return Err(format!("ogrid: semi-axis {d} is {s}"));
        }
        let room = (c - lo).min(hi - c);
        n[d] = match cells {
            Some(c) if c[d] >= 2 => c[d],
            Some(c) => return Err(format!("ogrid: {} cells along axis {d}, fewer than 2", c[d])),
            None => ((FRAC_PI_2 * s / p.wall).ceil() as usize).max(2),
        };
        let min_half = s + 2.0 * p.wall;
        let max_half = room - 0.5 * p.far.min(room - s);
        if min_half > max_half {
            return Err(format!("ogrid: the body does not fit the box along axis {d} with room for the wall cells"));
        }
        half[d] = (n[d] as f64 * p.far / 2.0).clamp(min_half, max_half);
    }
    // Layers: as few as let the longest line (body to inner box) end in a layer at most 1.25
    // times the inner box's (geometric mean) spacing.
    let spacing: Vec<f64> = (0..dim).map(|d| 2.0 * half[d] / n[d] as f64).collect();
    let h_end = (spacing.iter().map(|h| h.ln()).sum::<f64>() / dim as f64).exp();
    let longest = shell_thickness(p, &n, &half).into_iter().fold(0.0, f64::max);
    let target = 1.25 * h_end.max(p.wall);
    let mut layers = 1;
    while layer_sizes(longest, p.wall, layers, p.growth).last().copied().unwrap_or(0.0) > target {
        layers += 1;
    }
    let mut axes: [Vec<f64>; 3] = [vec![0.0], vec![0.0], vec![0.0]];
    let mut inner = [[0usize; 2]; 3];
    for d in 0..dim {
        let (c, [lo, hi]) = (p.center[d], p.bounds[d]);
        let (a, b) = (c - half[d], c + half[d]);
        let below = graded_offsets(a - lo, spacing[d], p.far, p.growth);
        let above = graded_offsets(hi - b, spacing[d], p.far, p.growth);
        let mut x = Vec::with_capacity(below.len() + n[d] + above.len() + 1);
        x.push(lo);
        x.extend(below.iter().rev().skip(1).map(|o| a - o));
        inner[d][0] = x.len();
        x.extend((0..=n[d]).map(|i| lerp(a, b, i, n[d])));
        inner[d][1] = x.len() - 1;
        x.extend(above[..above.len() - 1].iter().map(|o| b + o));
        x.push(hi);
        axes[d] = x;
    }
    Ok(OgridPlan { dim, axes, inner, half, layers })
}

/// The distances from the inner box's surface nodes to their body points.
fn shell_thickness(p: &OgridParams, n: &[usize; 3], half: &[f64; 3]) -> Vec<f64> {
    let mut out = Vec::new();
    let nz = if p.dim == 3 { n[2] } else { 0 };
    for k in 0..=nz {
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                let idx = [i, j, k];
                let on_surface = (0..p.dim).any(|d| idx[d] == 0 || idx[d] == n[d]);
                if !on_surface {
                    continue;
                }
                let mut b = [0.0; 3];
                for d in 0..p.dim {
                    b[d] = lerp(p.center[d] - half[d], p.center[d] + half[d], idx[d], n[d]);
                }
                let s = body_point(p, half, &b);
                out.push((0..p.dim).map(|d| (b[d] - s[d]).powi(2)).sum::<f64>().sqrt());
            }
        }
    }
    out
}

/// Appends a cell of type `ty` with corners `c`, reordered to positive orientation if needed.
pub(crate) fn push_oriented(d: &mut MeshData, ty: CellType, c: &[u32]) {
    let m = CellPoints::gather(ty, c, &d.coords, d.dim).signed_measure();
    if m < 0.0 {
        let f: Vec<u32> = ty.flipped().iter().map(|&k| c[k as usize]).collect();
        d.push_cell(ty, &f, 0);
    } else {
        d.push_cell(ty, c, 0);
    }
}

/// The two triangles of the quad `q` (cyclic) split along the diagonal from its smallest vertex.
pub(crate) fn split_quad(q: [u32; 4]) -> [[u32; 3]; 2] {
    let m = (0..4).min_by_key(|&k| q[k]).expect("four corners");
    if m % 2 == 0 {
        [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    } else {
        [[q[0], q[1], q[3]], [q[1], q[2], q[3]]]
    }
}

/// The tensor (hexahedral or quadrilateral) mesh of `plan` for `p`, as plain arrays. Cells: the
/// tensor blocks first, then the shell, face by face of the inner box's surface, each face's
/// `plan.layers` cells from the body outwards. A shell vertex of layer l (below the inner box)
/// has the index of its line's body vertex plus l, so the order of a face's corners by index is
/// the same in every layer of the shell.
pub(crate) fn tensor_mesh(p: &OgridParams, plan: &OgridPlan) -> MeshData {
    let dim = p.dim;
    let len = [plan.axes[0].len(), plan.axes[1].len(), plan.axes[2].len()];
    let t = |i: usize, j: usize, k: usize| (k * len[1] + j) * len[0] + i;
    let inn = &plan.inner;
    let strictly_inside = |idx: [usize; 3]| (0..dim).all(|d| idx[d] > inn[d][0] && idx[d] < inn[d][1]);
    let mut d = MeshData::new(dim);
    let point = |idx: [usize; 3]| -> [f64; 3] { [0, 1, 2].map(|a| plan.axes[a][idx[a]]) };

    let mut ids = vec![u32::MAX; len[0] * len[1] * len[2]];
    for k in 0..len[2] {
        for j in 0..len[1] {
            for i in 0..len[0] {
                if !strictly_inside([i, j, k]) {
                    ids[t(i, j, k)] = d.push_vertex(&point([i, j, k])[..dim]);
                }
            }
        }
    }
    // Shell nodes: layers 0 (the body) to layers − 1 of every surface node of the inner box.
    let m = plan.layers;
    let mut shell: HashMap<usize, u32> = HashMap::new();
    for k in inn[2][0]..=inn[2][1] {
        for j in inn[1][0]..=inn[1][1] {
            for i in inn[0][0]..=inn[0][1] {
                if strictly_inside([i, j, k]) {
                    continue;
                }
                let b = point([i, j, k]);
                let s = body_point(p, &plan.half, &b);
                let dist = (0..dim).map(|a| (b[a] - s[a]).powi(2)).sum::<f64>().sqrt();
                let sizes = layer_sizes(dist, p.wall, m, p.growth);
                let base = d.num_vertices() as u32;
                let mut acc = 0.0;
                for size in sizes {
                    let f = acc / dist;
                    let x: Vec<f64> = (0..dim).map(|a| s[a] + (b[a] - s[a]) * f).collect();
                    d.push_vertex(&x);
                    acc += size;
                }
                shell.insert(t(i, j, k), base);
            }
        }
    }
    let layer_id = |node: usize, l: usize| if l == m { ids[node] } else { shell[&node] + l as u32 };

    // Tensor blocks.
    let cells = [len[0] - 1, len[1] - 1, if dim == 3 { len[2] - 1 } else { 1 }];
    for k in 0..cells[2] {
        for j in 0..cells[1] {
            for i in 0..cells[0] {
                let inside = (0..dim).all(|a| [i, j, k][a] >= inn[a][0] && [i, j, k][a] < inn[a][1]);
                if inside {
                    continue;
                }
                if dim == 3 {
                    let c = [
                        t(i, j, k),
                        t(i + 1, j, k),
                        t(i + 1, j + 1, k),
                        t(i, j + 1, k),
                        t(i, j, k + 1),
                        t(i + 1, j, k + 1),
                        t(i + 1, j + 1, k + 1),
                        t(i, j + 1, k + 1),
                    ]
                    .map(|x| ids[x]);
                    push_oriented(&mut d, CellType::Hexahedron, &c);
                } else {
                    let c = [t(i, j, 0), t(i + 1, j, 0), t(i + 1, j + 1, 0), t(i, j + 1, 0)].map(|x| ids[x]);
                    push_oriented(&mut d, CellType::Quad, &c);
                }
            }
        }
    }
    // The faces of the inner box's surface (tensor node indices), each with its axis.
    let mut surface_faces: Vec<Vec<usize>> = Vec::new();
    for a in 0..dim {
        for side in 0..2 {
            let fixed = inn[a][side];
            let others: Vec<usize> = (0..dim).filter(|&b| b != a).collect();
            let node = |u: usize, v: usize| {
                let mut idx = [0usize; 3];
                idx[a] = fixed;
                idx[others[0]] = u;
                if dim == 3 {
                    idx[others[1]] = v;
                }
                t(idx[0], idx[1], idx[2])
            };
            let (b0, b1) = (others[0], *others.get(1).unwrap_or(&2));
            let vrange = if dim == 3 { inn[b1][0]..inn[b1][1] } else { 0..1 };
            for v in vrange {
                for u in inn[b0][0]..inn[b0][1] {
                    if dim == 3 {
                        surface_faces.push(vec![node(u, v), node(u + 1, v), node(u + 1, v + 1), node(u, v + 1)]);
                    } else {
                        surface_faces.push(vec![node(u, 0), node(u + 1, 0)]);
                    }
                }
            }
        }
    }
    for f in &surface_faces {
        for l in 0..m {
            if dim == 3 {
                let c: Vec<u32> = (0..8).map(|q| layer_id(f[q % 4], l + q / 4)).collect();
                push_oriented(&mut d, CellType::Hexahedron, &c);
            } else {
                let c = [layer_id(f[0], l), layer_id(f[1], l), layer_id(f[1], l + 1), layer_id(f[0], l + 1)];
                push_oriented(&mut d, CellType::Quad, &c);
            }
        }
        let body: Vec<u32> = f.iter().map(|&x| layer_id(x, 0)).collect();
        d.push_face(&body, OG_BODY);
    }
    // The box's walls.
    for a in 0..dim {
        for side in [0, len[a] - 1] {
            let others: Vec<usize> = (0..dim).filter(|&b| b != a).collect();
            let node = |u: usize, v: usize| {
                let mut idx = [0usize; 3];
                idx[a] = side;
                idx[others[0]] = u;
                if dim == 3 {
                    idx[others[1]] = v;
                }
                ids[t(idx[0], idx[1], idx[2])]
            };
            let (b0, b1) = (others[0], *others.get(1).unwrap_or(&2));
            let nv = if dim == 3 { len[b1] - 1 } else { 1 };
            for v in 0..nv {
                for u in 0..len[b0] - 1 {
                    if dim == 3 {
                        d.push_face(&[node(u, v), node(u + 1, v), node(u + 1, v + 1), node(u, v + 1)], OG_WALL);
                    } else {
                        d.push_face(&[node(u, 0), node(u + 1, 0)], OG_WALL);
                    }
                }
            }
        }
    }
    d
}

/// Appends the hexahedron of corners `v` (vertices of `s`) as 12 tetrahedra around its added
/// centroid, each face split by [`split_quad`]; returns how many cells it appended (12).
pub(crate) fn push_hex_as_tets(s: &mut MeshData, v: &[u32]) -> usize {
    let centre: Vec<f64> = (0..3).map(|a| v.iter().map(|&x| s.coords[3 * x as usize + a]).sum::<f64>() / 8.0).collect();
    let o = s.push_vertex(&centre);
    for f in CellType::Hexahedron.faces() {
        for tri in split_quad([0, 1, 2, 3].map(|k| v[f[k] as usize])) {
            push_oriented(s, CellType::Tetra, &[tri[0], tri[1], tri[2], o]);
        }
    }
    12
}

/// `d` (hexahedra or quads) split into tetrahedra (12 per hexahedron around an added centroid)
/// or triangles (2 per quad); quad faces split as their cells split them.
fn simplex_mesh(d: &MeshData) -> MeshData {
    let mut s = MeshData::new(d.dim);
    s.coords = d.coords.clone();
    for c in 0..d.num_cells() {
        let v = d.cell(c);
        if d.dim == 3 {
            push_hex_as_tets(&mut s, v);
        } else {
            for tri in split_quad([v[0], v[1], v[2], v[3]]) {
                push_oriented(&mut s, CellType::Triangle, &tri);
            }
        }
    }
    for f in 0..d.num_faces() {
        let v = d.face(f);
        if v.len() == 4 {
            for tri in split_quad([v[0], v[1], v[2], v[3]]) {
                s.push_face(&tri, d.face_patch[f]);
            }
        } else {
            s.push_face(v, d.face_patch[f]);
        }
    }
    s
}

/// The O-grid mesh of `p` as plain arrays, or why `p` cannot be meshed. Patches [`OG_WALL`]
/// (every side of the box) and [`OG_BODY`].
pub fn ogrid_data(p: &OgridParams) -> Result<MeshData, String> {
    let plan = plan(p)?;
    let d = tensor_mesh(p, &plan);
    Ok(match p.kind {
        CellKind::Tensor => d,
        CellKind::Simplex => simplex_mesh(&d),
    })
}

/// The validated O-grid mesh of `p`, or why `p` cannot be meshed.
pub fn ogrid(p: &OgridParams) -> Result<Mesh, String> {
    let d = ogrid_data(p)?;
    Mesh::from_data(&d).map_err(|e| format!("ogrid: invalid mesh: {e}"))
}

/// The mesh of a sphere (or ellipsoid) in a box, [`OgridParams::sphere`]; panics on parameters
/// that cannot be meshed.
pub fn sphere_in_box(p: &OgridParams) -> Mesh {
    assert_eq!(p.dim, 3, "sphere_in_box: a 3D body");
    ogrid(p).unwrap_or_else(|e| panic!("{e}"))
}

/// The mesh of a circle (or ellipse) in a rectangle, [`OgridParams::cylinder`]; panics on
/// parameters that cannot be meshed.
pub fn cylinder_in_box(p: &OgridParams) -> Mesh {
    assert_eq!(p.dim, 2, "cylinder_in_box: a 2D body");
    ogrid(p).unwrap_or_else(|e| panic!("{e}"))
}

/// `base` with the wall size (and the far size, kept at `far / wall` = `ratio`) chosen so the
/// mesh has about `vertices` vertices (the largest mesh not above it, by bisection on the wall
/// size over [`OgridPlan::num_vertices`]; no mesh is built).
fn with_vertices(base: &OgridParams, ratio: f64, vertices: usize) -> Result<OgridParams, String> {
    let at = |wall: f64| OgridParams { wall, far: ratio * wall, ..base.clone() };
    let count = |wall: f64| plan(&at(wall)).map(|pl| pl.num_vertices(base.kind));
    // From the coarsest wall size (a quarter of the smallest semi-axis) down by halves until the
    // mesh has too many vertices, then bisection (geometric) between the last two.
    let smax = (0..base.dim).map(|d| base.semi_axes[d]).fold(f64::INFINITY, f64::min);
    let mut hi = 0.25 * smax;
    if count(hi)? > vertices {
        return Err(format!("ogrid: {vertices} vertices are fewer than the coarsest mesh's"));
    }
    let mut lo = hi;
    while count(lo)? <= vertices {
        hi = lo;
        lo *= 0.5;
    }
    for _ in 0..40 {
        let mid = (lo * hi).sqrt();
        match count(mid) {
            Ok(n) if n > vertices => lo = mid,
            _ => hi = mid,
        }
    }
    plan(&at(hi))?;
    Ok(at(hi))
}

/// A sphere of radius 1/2 at the origin in the cube [−20, 20]³, wall size 1/50 of the far size,
/// cells of `kind`, with about `vertices` vertices (at most that many): the graded 3D mesh of
/// the bench.
pub fn sphere_with_vertices(vertices: usize, kind: CellKind) -> Result<Mesh, String> {
    let base = OgridParams::sphere([0.0; 3], 0.5, [[-20.0, 20.0]; 3], 0.05, 2.5).with_kind(kind);
    ogrid(&with_vertices(&base, 50.0, vertices)?)
}

/// A circle of radius 1/2 at the origin in the square [−20, 20]², wall size 1/50 of the far
/// size, cells of `kind`, with about `vertices` vertices (at most that many): the graded 2D
/// mesh of the bench.
pub fn cylinder_with_vertices(vertices: usize, kind: CellKind) -> Result<Mesh, String> {
    let base = OgridParams::cylinder([0.0; 2], 0.5, [[-20.0, 20.0]; 2], 0.05, 2.5).with_kind(kind);
    ogrid(&with_vertices(&base, 50.0, vertices)?)
}

/// Size and shape measures of a mesh around a body (see [`measure`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OgridStats {
    /// Smallest cell angle, degrees: the dihedral angle in 3D, the corner angle in 2D.
    pub min_angle_deg: f64,
    /// Largest ratio of a cell's longest to its shortest edge.
    pub max_edge_ratio: f64,
    /// Mean length of the body's face edges (the wall's tangential spacing).
    pub body_edge: f64,
    /// Mean length of the edges from a body vertex to a vertex off the body: in a tensor mesh the
    /// first layer's height (a simplicial mesh adds the diagonals and the centroids' edges).
    pub wall_normal_edge: f64,
    /// Longest edge of the mesh.
    pub max_edge: f64,
    /// Sum of the cells' signed measures.
    pub total_measure: f64,
}

/// [`OgridStats`] of `mesh` with its body on patch `body`.
pub fn measure(mesh: &Mesh, body: i32) -> OgridStats {
    let dim = mesh.dim();
    let x = mesh.coords();
    let len = |a: u32, b: u32| {
        (0..dim).map(|k| (x[a as usize * dim + k] - x[b as usize * dim + k]).powi(2)).sum::<f64>().sqrt()
    };
    let mut on_body = vec![false; mesh.num_vertices()];
    mesh.patch_vertices(body).iter().for_each(|&v| on_body[v as usize] = true);
    let (mut min_angle, mut max_ratio, mut max_edge, mut total) = (180.0f64, 0.0f64, 0.0f64, 0.0);
    let mut edges: Vec<(u32, u32)> = Vec::new();
    for c in 0..mesh.num_cells() {
        let (ty, v) = (mesh.cell_type(c), mesh.cell(c));
        let cp = CellPoints::gather(ty, v, x, dim);
        min_angle = min_angle.min(cp.min_angle_deg());
        total += cp.signed_measure();
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for e in ty.edges() {
            let (a, b) = (v[e[0] as usize], v[e[1] as usize]);
            let l = len(a, b);
            lo = lo.min(l);
            hi = hi.max(l);
            if on_body[a as usize] != on_body[b as usize] {
                edges.push((a.min(b), a.max(b)));
            }
        }
        max_ratio = max_ratio.max(hi / lo);
        max_edge = max_edge.max(hi);
    }
    edges.sort_unstable();
    edges.dedup();
    let wall_normal_edge = edges.iter().map(|&(a, b)| len(a, b)).sum::<f64>() / edges.len().max(1) as f64;
    let mut body_edges: Vec<(u32, u32)> = Vec::new();
    for f in mesh.patch_faces().filter(|f| f.patch == body) {
        let v = f.vertices;
        for k in 0..v.len() {
            let (a, b) = (v[k], v[(k + 1) % v.len()]);
            if v.len() > 2 || k == 0 {
                body_edges.push((a.min(b), a.max(b)));
            }
        }
    }
    body_edges.sort_unstable();
    body_edges.dedup();
    let body_edge = body_edges.iter().map(|&(a, b)| len(a, b)).sum::<f64>() / body_edges.len().max(1) as f64;
    OgridStats {
        min_angle_deg: min_angle,
        max_edge_ratio: max_ratio,
        body_edge,
        wall_normal_edge,
        max_edge,
        total_measure: total,
    }
}

/// Smallest angle of cell `c` (dihedral in 3D), degrees.
pub fn cell_min_angle(mesh: &Mesh, c: usize) -> f64 {
    CellPoints::gather(mesh.cell_type(c), mesh.cell(c), mesh.coords(), mesh.dim()).min_angle_deg()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layer_sizes_fill_the_line() {
        // Capped growth: 0.05, 0.06, … up to the cap, summing to the length.
        let s = layer_sizes(1.0, 0.05, 12, 1.2);
        assert_eq!(s.len(), 12);
        assert_eq!(s[0], 0.05);
        assert!((s.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        assert!(s.windows(2).all(|w| w[1] >= w[0] - 1e-15 && w[1] <= 1.2 * w[0] + 1e-12));
        // Too long for growth by 1.2: geometric, faster.
        let s = layer_sizes(10.0, 0.05, 12, 1.2);
        assert!((s.iter().sum::<f64>() - 10.0).abs() < 1e-9);
        assert!(s[1] / s[0] > 1.2);
        // Too short for m wall sizes: shrinking.
        let s = layer_sizes(0.3, 0.05, 12, 1.2);
        assert!((s.iter().sum::<f64>() - 0.3).abs() < 1e-12 && s[11] < s[0]);
        assert_eq!(layer_sizes(0.7, 0.05, 1, 1.2), vec![0.7]);
    }

    #[test]
    fn graded_offsets_end_exactly() {
        let o = graded_offsets(2.0, 0.1, 0.3, 1.2);
        assert_eq!(*o.last().unwrap(), 2.0);
        let sizes: Vec<f64> = o.iter().scan(0.0, |prev, &x| Some(x - std::mem::replace(prev, x))).collect();
        assert!(sizes.iter().all(|&s| s > 0.0 && s <= 0.3 * 1.1), "{sizes:?}");
        assert!(sizes.windows(2).all(|w| w[1] <= 1.2 * w[0] + 1e-12));
    }

    #[test]
    fn split_quads_conform() {
        // The split depends on the vertex set alone: any rotation or reversal of a quad's
        // vertex list gives the same two triangles.
        let q = [7, 3, 9, 5];
        let key = |t: [[u32; 3]; 2]| {
            let mut v: Vec<Vec<u32>> = t
                .iter()
                .map(|x| {
                    let mut x = x.to_vec();
                    x.sort();
                    x
                })
                .collect();
            v.sort();
            v
        };
        let want = key(split_quad(q));
        for r in 0..4 {
            let rot = [q[r], q[(r + 1) % 4], q[(r + 2) % 4], q[(r + 3) % 4]];
            assert_eq!(key(split_quad(rot)), want);
            let rev = [rot[3], rot[2], rot[1], rot[0]];
            assert_eq!(key(split_quad(rev)), want);
        }
    }
}
