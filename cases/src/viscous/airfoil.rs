//! The NACA 0012 airfoil (chord 1, closed trailing edge) with structured quad layers on its
//! surface and triangles out to a circular far field.

use super::{body_patches, Layers, ViscousMesh, FARFIELD, NO_LAYER, WALL};
use crate::cdt::{mesh_domain, Loop};
use glam::DVec2;
use meshmove::geometry::CellType;
use meshmove::mesh::{Mesh, MeshData};
use std::f64::consts::PI;

/// The airfoil mesh's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AirfoilParams {
    /// Surface vertices per side (upper and lower), cosine-clustered at both edges; it also sets
    /// the triangles' sizes (the far field's spacing is 160 / `points_per_side` chords).
    pub points_per_side: usize,
    /// The wall layers.
    pub layers: Layers,
    /// Radius of the far field circle, about the mid-chord (0.5, 0).
    pub far_radius: f64,
}

impl AirfoilParams {
    /// `points_per_side` surface vertices per side; 30 layers, the first 10⁻⁵ chords high,
    /// growth 1.2; far field of radius 20.
    pub fn new(points_per_side: usize) -> AirfoilParams {
        AirfoilParams { points_per_side, layers: Layers::new(1e-5, 30, 1.2), far_radius: 20.0 }
    }

    /// The same with the wall layers `layers`.
    pub fn with_layers(mut self, layers: Layers) -> AirfoilParams {
        self.layers = layers;
        self
    }
}

/// Half-thickness of the NACA 0012 at `x` ∈ [0, 1], with the closed trailing edge's last
/// coefficient (−0.1036): zero at both ends.
pub fn naca0012_half_thickness(x: f64) -> f64 {
    0.6 * (0.2969 * x.sqrt() - 0.1260 * x - 0.3516 * x * x + 0.2843 * x.powi(3) - 0.1036 * x.powi(4))
}

/// The airfoil's surface, counter-clockwise from the trailing edge (1, 0) over the upper side:
/// 2 `n` points, x = (1 − cos β) / 2 for β evenly spaced.
fn surface(n: usize) -> Vec<DVec2> {
    let x = |i: usize| 0.5 * (1.0 - (PI * i as f64 / n as f64).cos());
    let upper = (1..=n).rev().map(|i| DVec2::new(x(i), naca0012_half_thickness(x(i))));
    let lower = (1..n).map(|i| DVec2::new(x(i), -naca0012_half_thickness(x(i))));
    let mut pts: Vec<DVec2> = upper.chain(std::iter::once(DVec2::ZERO)).chain(lower).collect();
    // x(n) = 1 exactly, so the trailing edge's thickness is zero up to rounding; make it exact.
    pts[0] = DVec2::new(1.0, 0.0);
    pts
}

/// The unit outward directions of the layers' lines at the surface's vertices: the mean of the
/// two neighbouring segments' normals, smoothed by `sweeps` Jacobi sweeps (weights 1, 2, 1).
/// At the sharp trailing edge the bisector alone would leave a wide gap between the lines of
/// the edge and of its neighbours, which the layers' last ring and the triangles beyond cannot
/// bridge with well-shaped cells; the smoothing turns the lines gradually over the clustered
/// vertices near the edge.
fn normals(s: &[DVec2], sweeps: usize) -> Vec<DVec2> {
    let n = s.len();
    let seg = |i: usize| {
        let t = s[(i + 1) % n] - s[i];
        DVec2::new(t.y, -t.x).normalize()
    };
    let mut m: Vec<DVec2> = (0..n).map(|i| (seg((i + n - 1) % n) + seg(i)).normalize()).collect();
    for _ in 0..sweeps {
        m = (0..n).map(|i| (m[(i + n - 1) % n] + 2.0 * m[i] + m[(i + 1) % n]).normalize()).collect();
    }
    m
}

/// A planar hybrid mesh: vertices, triangles, quads with their layer, tagged edges.
pub(super) struct Hybrid2d {
    pub coords: Vec<DVec2>,
    pub tris: Vec<[u32; 3]>,
    pub quads: Vec<([u32; 4], u32)>,
    pub tagged: Vec<([u32; 2], i32)>,
}

impl Hybrid2d {
    /// As plain arrays: the triangles first, then the quads, layer by layer from the wall.
    fn to_data(&self) -> (MeshData, Vec<u32>) {
        let mut d = MeshData::new(2);
        self.coords.iter().for_each(|p| {
            d.push_vertex(&[p.x, p.y]);
        });
        let mut layer = Vec::with_capacity(self.tris.len() + self.quads.len());
        for t in &self.tris {
            d.push_cell(CellType::Triangle, t, 0);
            layer.push(NO_LAYER);
        }
        for (q, k) in &self.quads {
            d.push_cell(CellType::Quad, q, 0);
            layer.push(*k);
        }
        self.tagged.iter().for_each(|(e, patch)| d.push_face(e, *patch));
        (d, layer)
    }
}

/// The airfoil's hybrid mesh of `p`.
pub(super) fn airfoil_parts(p: &AirfoilParams) -> Result<Hybrid2d, String> {
    p.layers.check()?;
    let n = p.points_per_side;
    if n < 8 {
        return Err(format!("airfoil: {n} points per side, fewer than 8"));
    }
    if !(p.far_radius >= 2.0 && p.far_radius.is_finite()) {
        return Err(format!("airfoil: far field radius {} below 2 chords", p.far_radius));
    }
    let s = surface(n);
    let nrm = normals(&s, n / 2);
    let ns = s.len();
    let nl = p.layers.count;
    let ring = |k: usize| -> Vec<DVec2> {
        let h = p.layers.offset(k);
        s.iter().zip(&nrm).map(|(x, m)| *x + h * *m).collect()
    };
    // The triangles: from the outermost ring (a hole) to the far circle.
    let centre = DVec2::new(0.5, 0.0);
    let scale = 64.0 / n as f64;
    let far = 2.5 * scale;
    let n_far = ((2.0 * PI * p.far_radius / far).ceil() as usize).max(16);
    let circle: Vec<DVec2> = (0..n_far)
        .map(|j| {
            let t = 2.0 * PI * j as f64 / n_far as f64;
            centre + p.far_radius * DVec2::new(t.cos(), t.sin())
        })
        .collect();
    let outer_ring = ring(nl);
    let ring_spacing = (0..ns).map(|j| (outer_ring[(j + 1) % ns] - outer_ring[j]).length()).sum::<f64>() / ns as f64;
    let size = move |q: DVec2| (ring_spacing + 0.3 * scale * ((q - centre).length() - 0.5).max(0.0)).min(far);
    let loops =
        [Loop { points: circle, patches: vec![FARFIELD; n_far] }, Loop { points: outer_ring, patches: vec![0; ns] }];
    let planar = mesh_domain(&loops, &size, 25.0, 1);
    let mut coords = planar.coords;
    let tris = planar.tris;
    let mut tagged: Vec<([u32; 2], i32)> = planar.tagged.into_iter().filter(|t| t.1 != 0).collect();
    // The rings 0 (the wall) to nl − 1, after the triangles' vertices; ring nl is the hole.
    let base = coords.len();
    for k in 0..nl {
        coords.extend(ring(k));
    }
    let id = |k: usize, j: usize| -> Result<u32, String> {
        let j = j % ns;
        let i = if k == nl { n_far + j } else { base + k * ns + j };
        u32::try_from(i).map_err(|_| "airfoil: over 2³² vertices".to_string())
    };
    let mut quads = Vec::with_capacity(nl * ns);
    for k in 0..nl {
        for j in 0..ns {
            quads.push(([id(k, j)?, id(k + 1, j)?, id(k + 1, j + 1)?, id(k, j + 1)?], k as u32));
        }
    }
    for j in 0..ns {
        tagged.push(([id(0, j)?, id(0, j + 1)?], WALL));
    }
    Ok(Hybrid2d { coords, tris, quads, tagged })
}

/// The NACA 0012 (chord 1, leading edge at the origin, closed trailing edge at (1, 0)) with
/// `p.layers` structured quad layers along the vertex normals, triangles from the last layer to
/// the far field circle of radius `p.far_radius` about (0.5, 0). Patches [`WALL`], [`FARFIELD`].
/// Vertex order: the triangles' (the far circle, the outermost ring, Steiner points), then the
/// rings from the wall outwards, each counter-clockwise from the trailing edge.
pub fn airfoil_2d(p: &AirfoilParams) -> Result<ViscousMesh, String> {
    let (d, cell_layer) = airfoil_parts(p)?.to_data();
    let mesh = Mesh::from_data(&d).map_err(|e| format!("airfoil: invalid mesh: {e}"))?;
    Ok(ViscousMesh { mesh, cell_layer, layers: p.layers, patches: body_patches(), pitch_center: [0.25, 0.0, 0.0] })
}
