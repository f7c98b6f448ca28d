//! Meshes of the slip-wall tests: channels and ducts with a body, built on grids with jittered
//! interiors, their boundary faces found from the cells and tagged by where they lie.
#![allow(dead_code)]

use meshmove::{CellType, Mesh, MeshData};
use std::collections::BTreeMap;

pub const BOTTOM: i32 = 1;
pub const RIGHT: i32 = 2;
pub const TOP: i32 = 3;
pub const LEFT: i32 = 4;
pub const BODY: i32 = 6;
/// The duct's side walls z = 0 and z = 1.
pub const FRONT: i32 = 7;
pub const BACK: i32 = 8;

/// Cells and points on a grid: `keep(cell index)` says which grid cells exist; `tag(face's grid
/// vertices)` names each boundary face's patch; `place(grid vertex, interior)` gives its position.
struct Grid {
    dim: usize,
    n: [usize; 3],
}

impl Grid {
    fn id(&self, i: [usize; 3]) -> usize {
        (i[2] * (self.n[1] + 1) + i[1]) * (self.n[0] + 1) + i[0]
    }
    fn index(&self, v: usize) -> [usize; 3] {
        let nx = self.n[0] + 1;
        let ny = self.n[1] + 1;
        [v % nx, (v / nx) % ny, v / (nx * ny)]
    }
}

/// Builds the mesh: `cells` as lists of grid vertices with their type, boundary faces (used once)
/// tagged by `tag`, vertices used by no cell dropped, interior vertices moved by `place`.
fn build(
    g: &Grid,
    cells: Vec<(CellType, Vec<usize>)>,
    faces_of: impl Fn(&[usize]) -> Vec<Vec<usize>>,
    tag: impl Fn(&[[usize; 3]]) -> i32,
    place: impl Fn([usize; 3], bool) -> Vec<f64>,
) -> Mesh {
    let mut count: BTreeMap<Vec<usize>, (usize, Vec<usize>)> = BTreeMap::new();
    for (_, c) in &cells {
        for f in faces_of(c) {
            let mut key = f.clone();
            key.sort_unstable();
            count.entry(key).or_insert((0, f)).0 += 1;
        }
    }
    let boundary: Vec<Vec<usize>> = count.into_values().filter(|(k, _)| *k == 1).map(|(_, f)| f).collect();
    let mut on_boundary = BTreeMap::new();
    boundary.iter().flatten().for_each(|&v| {
        on_boundary.insert(v, ());
    });
    let mut new_id: BTreeMap<usize, u32> = BTreeMap::new();
    cells.iter().flat_map(|(_, c)| c.iter()).for_each(|&v| {
        new_id.insert(v, 0);
    });
    let mut d = MeshData::new(g.dim);
    for (k, (v, id)) in new_id.iter_mut().enumerate() {
        *id = k as u32;
        let p = place(g.index(*v), !on_boundary.contains_key(v));
        d.push_vertex(&p);
    }
    for (t, c) in &cells {
        let vs: Vec<u32> = c.iter().map(|v| new_id[v]).collect();
        d.push_cell(*t, &vs, 0);
    }
    for f in &boundary {
        let idx: Vec<[usize; 3]> = f.iter().map(|&v| g.index(v)).collect();
        let vs: Vec<u32> = f.iter().map(|v| new_id[v]).collect();
        d.push_face(&vs, tag(&idx));
    }
    Mesh::from_data(&d).unwrap()
}

/// A deterministic jitter in [−1, 1].
fn wobble(i: [usize; 3], k: f64) -> f64 {
    ((7 * i[0] + 13 * i[1] + 5 * i[2]) as f64 * k + 0.3).sin()
}

/// A channel [0, len] × [0, 1] of nx × ny squares cut into triangles, the squares of `hole` (a
/// range of columns and rows) removed (the body), interior vertices jittered by `jitter` of a
/// cell, then rotated by `angle` about the origin. Patches: BOTTOM, TOP, LEFT, RIGHT, BODY.
pub fn channel(nx: usize, ny: usize, len: f64, hole: [[usize; 2]; 2], jitter: f64, angle: f64) -> Mesh {
    let (s, c) = angle.sin_cos();
    channel_mapped(nx, ny, len, hole, jitter, |x, y| [c * x - s * y, s * x + c * y])
}

/// The channel of `channel`, its points (x, y) of [0, len] × [0, 1] mapped by `map`.
pub fn channel_mapped(
    nx: usize,
    ny: usize,
    len: f64,
    hole: [[usize; 2]; 2],
    jitter: f64,
    map: impl Fn(f64, f64) -> [f64; 2],
) -> Mesh {
    let g = Grid { dim: 2, n: [nx, ny, 0] };
    let mut cells = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            if (hole[0][0]..hole[0][1]).contains(&i) && (hole[1][0]..hole[1][1]).contains(&j) {
                continue;
            }
            let q = [g.id([i, j, 0]), g.id([i + 1, j, 0]), g.id([i + 1, j + 1, 0]), g.id([i, j + 1, 0])];
            if (i + j) % 2 == 0 {
                cells.push((CellType::Triangle, vec![q[0], q[1], q[2]]));
                cells.push((CellType::Triangle, vec![q[0], q[2], q[3]]));
            } else {
                cells.push((CellType::Triangle, vec![q[0], q[1], q[3]]));
                cells.push((CellType::Triangle, vec![q[1], q[2], q[3]]));
            }
        }
    }
    let faces = |c: &[usize]| (0..3).map(|k| vec![c[k], c[(k + 1) % 3]]).collect();
    let tag = |f: &[[usize; 3]]| {
        if f.iter().all(|i| i[1] == 0) {
            BOTTOM
        } else if f.iter().all(|i| i[1] == ny) {
            TOP
        } else if f.iter().all(|i| i[0] == 0) {
            LEFT
        } else if f.iter().all(|i| i[0] == nx) {
            RIGHT
        } else {
            BODY
        }
    };
    let h = len / nx as f64;
    let place = |i: [usize; 3], inside: bool| {
        let mut x = i[0] as f64 * h;
        let mut y = i[1] as f64 / ny as f64;
        if inside {
            x += jitter * h * wobble(i, 0.71);
            y += jitter / ny as f64 * wobble(i, 1.37);
        }
        map(x, y).to_vec()
    };
    build(&g, cells, faces, tag, place)
}

/// A duct [0, len] × [0, 1] × [0, 1] of hexahedra, the cells of `hole` removed (the body),
/// interior vertices jittered. Patches: BOTTOM (y = 0), TOP (y = 1), FRONT (z = 0), BACK (z = 1),
/// LEFT (x = 0), RIGHT (x = len), BODY.
pub fn duct(n: [usize; 3], len: f64, hole: [[usize; 2]; 3], jitter: f64) -> Mesh {
    let g = Grid { dim: 3, n };
    let mut cells = Vec::new();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                if (0..3).all(|a| (hole[a][0]..hole[a][1]).contains(&[i, j, k][a])) {
                    continue;
                }
                let id = |a: usize, b: usize, c: usize| g.id([i + a, j + b, k + c]);
                let hex = vec![
                    id(0, 0, 0),
                    id(1, 0, 0),
                    id(1, 1, 0),
                    id(0, 1, 0),
                    id(0, 0, 1),
                    id(1, 0, 1),
                    id(1, 1, 1),
                    id(0, 1, 1),
                ];
                cells.push((CellType::Hexahedron, hex));
            }
        }
    }
    // Outward-ordered faces of a VTK hexahedron.
    let faces = |c: &[usize]| {
        [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [0, 4, 7, 3], [1, 2, 6, 5]]
            .iter()
            .map(|f| f.iter().map(|&k| c[k]).collect())
            .collect()
    };
    let tag = |f: &[[usize; 3]]| {
        let all = |a: usize, v: usize| f.iter().all(|i| i[a] == v);
        if all(1, 0) {
            BOTTOM
        } else if all(1, n[1]) {
            TOP
        } else if all(2, 0) {
            FRONT
        } else if all(2, n[2]) {
            BACK
        } else if all(0, 0) {
            LEFT
        } else if all(0, n[0]) {
            RIGHT
        } else {
            BODY
        }
    };
    let place = |i: [usize; 3], inside: bool| {
        let mut p = vec![i[0] as f64 * len / n[0] as f64, i[1] as f64 / n[1] as f64, i[2] as f64 / n[2] as f64];
        if inside {
            p[0] += jitter * len / n[0] as f64 * wobble(i, 0.71);
            p[1] += jitter / n[1] as f64 * wobble(i, 1.37);
            p[2] += jitter / n[2] as f64 * wobble(i, 2.11);
        }
        p
    };
    build(&g, cells, faces, tag, place)
}

/// `mesh` (3D) turned by `angle` about the x axis: a duct's walls slanted, its edges still along x.
pub fn turned_about_x(mesh: &Mesh, angle: f64) -> Mesh {
    let (s, c) = angle.sin_cos();
    let x: Vec<f64> = mesh.coords().chunks(3).flat_map(|p| [p[0], c * p[1] - s * p[2], s * p[1] + c * p[2]]).collect();
    mesh.with_coords(x)
}
