//! 3D hexahedral meshes of the slip-wall cases: a spherical shell and a sphere in a square duct,
//! both with cubed-sphere layers around the sphere.

use meshmove::geometry::CellType;
use meshmove::mesh::{Mesh, MeshData};
use std::collections::{BTreeMap, HashMap};

/// Patch ids of the shell: the inner and outer spheres.
pub const SH_INNER: i32 = 1;
pub const SH_OUTER: i32 = 2;
/// Patch ids of the duct: its four side walls and two ends, and the sphere.
pub const SC_WALL: i32 = 1;
pub const SC_SPHERE: i32 = 2;

/// The six faces of the cube as (outward normal, t1, t2) with t1 × t2 = normal.
const FACES: [[[f64; 3]; 3]; 6] = [
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    [[-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]],
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
    [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    [[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
];

/// Vertices merged by position, hexahedra, and boundary faces found as the faces used once.
#[derive(Default)]
struct Builder {
    points: Vec<[f64; 3]>,
    index: HashMap<[i64; 3], u32>,
    hexes: Vec<[u32; 8]>,
}

impl Builder {
    fn vertex(&mut self, p: [f64; 3]) -> u32 {
        let key = p.map(|x| (x * 1e7).round() as i64);
        let n = self.points.len() as u32;
        *self.index.entry(key).or_insert_with(|| {
            self.points.push(p);
            n
        })
    }

    fn hex(&mut self, corners: [[f64; 3]; 8]) {
        let h = corners.map(|p| self.vertex(p));
        self.hexes.push(h);
    }

    /// The mesh, each boundary face tagged by `tag(its corner points)`.
    fn mesh(self, tag: impl Fn(&[[f64; 3]]) -> i32) -> Mesh {
        const QUADS: [[usize; 4]; 6] =
            [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [0, 4, 7, 3], [1, 2, 6, 5]];
        let mut count: BTreeMap<[u32; 4], (usize, [u32; 4])> = BTreeMap::new();
        for h in &self.hexes {
            for q in QUADS {
                let f = q.map(|k| h[k]);
                let mut key = f;
                key.sort_unstable();
                count.entry(key).or_insert((0, f)).0 += 1;
            }
        }
        let mut d = MeshData::new(3);
        for p in &self.points {
            d.push_vertex(p);
        }
        for h in &self.hexes {
            d.push_cell(CellType::Hexahedron, h, 0);
        }
        for (n, f) in count.into_values() {
            if n == 1 {
                let pts: Vec<[f64; 3]> = f.iter().map(|&v| self.points[v as usize]).collect();
                d.push_face(&f, tag(&pts));
            }
        }
        Mesh::from_data(&d).expect("a valid hexahedral mesh")
    }
}

fn norm(p: [f64; 3]) -> [f64; 3] {
    let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    p.map(|x| x / l)
}

/// A point of cube face `f` at parameters (a, b) ∈ [−1, 1]²: n + a t1 + b t2.
fn on_cube(f: usize, a: f64, b: f64) -> [f64; 3] {
    let [n, t1, t2] = FACES[f];
    [0, 1, 2].map(|c| n[c] + a * t1[c] + b * t2[c])
}

/// Hexahedra between two surfaces over the six faces of a cube: `k` × `k` cells per face, `layers`
/// layers; `at(face, a, b, layer)` places a point (layer 0 inside, `layers` outside).
fn cubed_layers(b: &mut Builder, k: usize, layers: usize, at: impl Fn(usize, f64, f64, usize) -> [f64; 3]) {
    let s = |i: usize| -1.0 + 2.0 * i as f64 / k as f64;
    for f in 0..6 {
        for i in 0..k {
            for j in 0..k {
                for l in 0..layers {
                    let p = |di: usize, dj: usize, dl: usize| at(f, s(i + di), s(j + dj), l + dl);
                    b.hex([
                        p(0, 0, 0),
                        p(1, 0, 0),
                        p(1, 1, 0),
                        p(0, 1, 0),
                        p(0, 0, 1),
                        p(1, 0, 1),
                        p(1, 1, 1),
                        p(0, 1, 1),
                    ]);
                }
            }
        }
    }
}

/// The spherical shell r0 ≤ r ≤ r1 about the origin: `k` × `k` equiangular cells per cube face,
/// `layers` layers graded by `ratio`. Patches `SH_INNER`, `SH_OUTER`.
pub fn sphere_shell(k: usize, layers: usize, r0: f64, r1: f64, ratio: f64) -> Mesh {
    let mut radii = vec![0.0];
    let mut h = 1.0;
    for _ in 0..layers {
        radii.push(radii.last().expect("one") + h);
        h *= ratio;
    }
    let total = *radii.last().expect("one");
    let mut b = Builder::default();
    let eq = |a: f64| (a * std::f64::consts::FRAC_PI_4).tan();
    cubed_layers(&mut b, k, layers, |f, u, v, l| {
        let r = r0 + (r1 - r0) * radii[l] / total;
        norm(on_cube(f, eq(u), eq(v))).map(|x| r * x)
    });
    let mid = 0.5 * (r0 + r1);
    b.mesh(|pts| {
        let r = pts.iter().map(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()).sum::<f64>() / pts.len() as f64;
        if r < mid {
            SH_INNER
        } else {
            SH_OUTER
        }
    })
}

/// A sphere of diameter `d` at (`cx`, 0, 0) in the duct [0, `len`] × [−1, 1] × [−1, 1]: a
/// structured grid of spacing 2/`n` outside the cube of half-side 2`q`/`n` about the sphere's
/// centre, and `layers` cubed-sphere layers from the cube to the sphere (2`q` cells per cube face
/// side, matching the grid). `cx` and `len` should lie on grid lines. Patches `SC_WALL` (the
/// four side walls and both ends), `SC_SPHERE`.
pub fn sphere_channel(n: usize, len: f64, cx: f64, d: f64, q: usize, layers: usize) -> Mesh {
    let h = 2.0 / n as f64;
    let nx = (len / h).round() as usize;
    let a = q as f64 * h;
    let c = [cx, 0.0, 0.0];
    let mut b = Builder::default();
    let inside = |p: [f64; 3]| (0..3).all(|k| (p[k] - c[k]).abs() < a - 1e-9);
    for i in 0..nx {
        for j in 0..n {
            for l in 0..n {
                let p = |di: usize, dj: usize, dl: usize| {
                    [(i + di) as f64 * h, -1.0 + (j + dj) as f64 * h, -1.0 + (l + dl) as f64 * h]
                };
                let centre = [(i as f64 + 0.5) * h, -1.0 + (j as f64 + 0.5) * h, -1.0 + (l as f64 + 0.5) * h];
                if inside(centre) {
                    continue;
                }
                b.hex([p(0, 0, 0), p(1, 0, 0), p(1, 1, 0), p(0, 1, 0), p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1)]);
            }
        }
    }
    let r0 = 0.5 * d;
    cubed_layers(&mut b, 2 * q, layers, |f, u, v, l| {
        let cube = on_cube(f, u, v);
        let sphere = norm(cube).map(|x| r0 * x);
        let t = l as f64 / layers as f64;
        [0, 1, 2].map(|k| c[k] + (1.0 - t) * sphere[k] + t * a * cube[k])
    });
    b.mesh(|pts| {
        let on = |k: usize, v: f64| pts.iter().all(|p| (p[k] - v).abs() < 1e-9);
        if on(0, 0.0) || on(0, len) || on(1, -1.0) || on(1, 1.0) || on(2, -1.0) || on(2, 1.0) {
            SC_WALL
        } else {
            SC_SPHERE
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shell_and_channel_are_valid_and_closed() {
        let m = sphere_shell(3, 4, 1.0, 3.0, 1.2);
        // 6 k² + 2 vertices per sphere, layers + 1 spheres.
        assert_eq!(m.num_vertices(), 5 * 56);
        assert_eq!(m.num_cells(), 6 * 9 * 4);
        assert_eq!(m.patch_vertices(SH_OUTER).len(), 56);
        let c = sphere_channel(8, 4.0, 1.5, 0.4, 2, 3);
        assert_eq!(c.patch_vertices(SC_SPHERE).len(), 6 * 16 + 2);
        assert!(meshmove::mesh::inverted_cells(&c, c.coords()).is_empty());
    }
}
