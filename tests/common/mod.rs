//! Small meshes for the integration tests, built directly so each test controls its geometry.
#![allow(dead_code)]

use meshmove::{IndexBase, Mesh};

pub const BOTTOM: i32 = 1;
pub const RIGHT: i32 = 2;
pub const TOP: i32 = 3;
pub const LEFT: i32 = 4;
pub const INTERFACE: i32 = 5;

/// Grid of (nx+1)(ny+1) vertices on [x0,x1]×[y0,y1]; quads split along one diagonal
/// ("right" diagonal) or alternately; interior vertices moved by a deterministic jitter of
/// `jitter` times the spacing, so the mesh is irregular but valid.
pub struct Grid {
    pub nx: usize,
    pub ny: usize,
    pub x: [f64; 2],
    pub y: [f64; 2],
    pub jitter: f64,
    pub alternate: bool,
}

impl Grid {
    pub fn new(nx: usize, ny: usize) -> Self {
        Grid { nx, ny, x: [0.0, 1.0], y: [0.0, 1.0], jitter: 0.0, alternate: false }
    }
    pub fn jitter(mut self, j: f64) -> Self {
        self.jitter = j;
        self
    }
    pub fn alternate(mut self) -> Self {
        self.alternate = true;
        self
    }
    pub fn span(mut self, x: [f64; 2], y: [f64; 2]) -> Self {
        self.x = x;
        self.y = y;
        self
    }

    fn id(&self, i: usize, j: usize) -> u32 {
        (j * (self.nx + 1) + i) as u32
    }

    pub fn coords(&self) -> Vec<[f64; 2]> {
        let (hx, hy) = ((self.x[1] - self.x[0]) / self.nx as f64, (self.y[1] - self.y[0]) / self.ny as f64);
        let mut c = Vec::new();
        for j in 0..=self.ny {
            for i in 0..=self.nx {
                let mut p = [self.x[0] + i as f64 * hx, self.y[0] + j as f64 * hy];
                if i > 0 && i < self.nx && j > 0 && j < self.ny {
                    let h = (i * 7919 + j * 104729) as f64;
                    p[0] += self.jitter * hx * ((h * 0.618).fract() - 0.5);
                    p[1] += self.jitter * hy * ((h * 0.414).fract() - 0.5);
                }
                c.push(p);
            }
        }
        c
    }

    pub fn cells(&self) -> Vec<[u32; 3]> {
        let mut t = Vec::new();
        for j in 0..self.ny {
            for i in 0..self.nx {
                let (a, b, c, d) = (self.id(i, j), self.id(i + 1, j), self.id(i + 1, j + 1), self.id(i, j + 1));
                if self.alternate && (i + j) % 2 == 1 {
                    t.push([a, b, d]);
                    t.push([b, c, d]);
                } else {
                    t.push([a, b, c]);
                    t.push([a, c, d]);
                }
            }
        }
        t
    }

    pub fn tagged(&self) -> Vec<([u32; 2], i32)> {
        let mut e = Vec::new();
        for i in 0..self.nx {
            e.push(([self.id(i, 0), self.id(i + 1, 0)], BOTTOM));
            e.push(([self.id(i, self.ny), self.id(i + 1, self.ny)], TOP));
        }
        for j in 0..self.ny {
            e.push(([self.id(0, j), self.id(0, j + 1)], LEFT));
            e.push(([self.id(self.nx, j), self.id(self.nx, j + 1)], RIGHT));
        }
        e
    }

    pub fn mesh(&self) -> Mesh {
        Mesh::triangles(&self.coords(), &self.cells(), IndexBase::Zero, &self.tagged(), None).unwrap()
    }

    /// Two regions: rows below `ny/2` region 0, above region 1; the middle row's edges tagged
    /// INTERFACE (shared vertices).
    pub fn two_regions(&self) -> Mesh {
        let mid = self.ny / 2;
        let regions: Vec<i32> = (0..self.ny).flat_map(|j| vec![i32::from(j >= mid); 2 * self.nx]).collect();
        let mut tagged = self.tagged();
        for i in 0..self.nx {
            tagged.push(([self.id(i, mid), self.id(i + 1, mid)], INTERFACE));
        }
        Mesh::triangles(&self.coords(), &self.cells(), IndexBase::Zero, &tagged, Some(&regions)).unwrap()
    }
}

pub const INNER: i32 = 1;
pub const OUTER: i32 = 2;

/// Annulus r0 ≤ r ≤ r1, `nr` rings of cells, `nt` around, radially graded by `ratio`.
pub fn annulus(nr: usize, nt: usize, r0: f64, r1: f64, ratio: f64) -> Mesh {
    let mut radii = vec![0.0];
    let mut h = 1.0;
    for _ in 0..nr {
        radii.push(radii.last().unwrap() + h);
        h *= ratio;
    }
    let total = *radii.last().unwrap();
    let mut coords = Vec::new();
    for &s in &radii {
        let r = r0 + (r1 - r0) * s / total;
        for k in 0..nt {
            let a = 2.0 * std::f64::consts::PI * k as f64 / nt as f64;
            coords.push([r * a.cos(), r * a.sin()]);
        }
    }
    let id = |i: usize, k: usize| (i * nt + k % nt) as u32;
    let mut cells = Vec::new();
    for i in 0..nr {
        for k in 0..nt {
            cells.push([id(i, k), id(i + 1, k), id(i + 1, k + 1)]);
            cells.push([id(i, k), id(i + 1, k + 1), id(i, k + 1)]);
        }
    }
    let mut tagged = Vec::new();
    for k in 0..nt {
        tagged.push(([id(0, k), id(0, k + 1)], INNER));
        tagged.push(([id(nr, k), id(nr, k + 1)], OUTER));
    }
    Mesh::triangles(&coords, &cells, IndexBase::Zero, &tagged, None).unwrap()
}

use glam::DVec2;
use meshmove::bc::{P, Z};
use meshmove::{Method, RigidMotion, Solver};

/// Flat 2D values (x0, y0, x1, y1, …: coordinates, displacements) as one vector per vertex.
pub fn to_vec2(flat: &[f64]) -> Vec<DVec2> {
    assert_eq!(flat.len() % 2, 0, "not 2D values");
    flat.chunks_exact(2).map(|p| DVec2::new(p[0], p[1])).collect()
}

/// One vector per vertex as flat 2D values (x0, y0, x1, y1, …).
pub fn to_flat(v: &[DVec2]) -> Vec<f64> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

/// The displacement of a rigid motion at a 2D point.
pub fn rigid_at(m: &RigidMotion, x: DVec2) -> DVec2 {
    let d = m.displacement(&x.to_array());
    DVec2::new(d[0], d[1])
}

/// A 2D rigid motion: rotation by `angle` about `center`, then translation by `translation`.
pub fn planar(translation: DVec2, angle: f64, center: DVec2) -> RigidMotion {
    RigidMotion::planar(translation.to_array(), angle, center.to_array())
}

/// A smooth, non-linear boundary displacement field, 1-periodic in x so it suits linked sides
/// (read only where prescribed).
pub fn wavy(x: DVec2) -> DVec2 {
    let w = std::f64::consts::TAU * x.x;
    DVec2::new(0.02 * w.sin() + 0.01 * x.y * x.y, 0.05 * w.cos() + 0.02 * x.y)
}

/// Solves the fine-level system of `solver` for component `c` by a dense direct solve,
/// assembled here from K, V and the flags independently of the matrix-free operator:
/// biharmonic A = K_UF M_F⁻¹ K_FU and b = −K_UF M_F⁻¹ K_FP d_P; Laplacian/spring A = K_UU.
/// `d` holds a displacement per unknown with the prescribed values set; returns it solved.
pub fn direct_solve(solver: &Solver, c: usize, d: &[f64]) -> Vec<f64> {
    let lev = &solver.hierarchy().levels[0];
    let n = lev.n();
    let k = lev.op().k.to_dense();
    let flags = &lev.flags()[c];
    let u: Vec<usize> = (0..n).filter(|&i| flags[i] & P == 0).collect();
    let f: Vec<usize> = (0..n).filter(|&i| flags[i] & Z == 0).collect();
    let m = u.len();
    let mut a = vec![0.0; m * m];
    let mut b = vec![0.0; m];
    let biharmonic = lev.op().method == Method::Biharmonic;
    // (K_F,: d_P) / V on F, used by the right-hand side.
    for (ii, &i) in u.iter().enumerate() {
        if biharmonic {
            for &kk in &f {
                if k[i][kk] == 0.0 {
                    continue;
                }
                let w = k[i][kk] * lev.op().inv_v[kk];
                for (jj, &j) in u.iter().enumerate() {
                    a[ii * m + jj] += w * k[kk][j];
                }
                let kd: f64 = (0..n).filter(|&j| flags[j] & P != 0).map(|j| k[kk][j] * d[j]).sum();
                b[ii] -= w * kd;
            }
        } else {
            for (jj, &j) in u.iter().enumerate() {
                a[ii * m + jj] = k[i][j];
            }
            b[ii] = -(0..n).filter(|&j| flags[j] & P != 0).map(|j| k[i][j] * d[j]).sum::<f64>();
        }
    }
    for i in 0..m {
        for j in 0..i {
            let v = 0.5 * (a[i * m + j] + a[j * m + i]);
            a[i * m + j] = v;
            a[j * m + i] = v;
        }
    }
    let chol = meshmove::dense::Cholesky::new(m, &a).expect("assembled system is SPD");
    chol.solve(&mut b);
    let mut out = d.to_vec();
    for (ii, &i) in u.iter().enumerate() {
        out[i] = b[ii];
    }
    out
}

/// Per-unknown values of component `c` of a per-vertex field (`dim` values per vertex).
pub fn at_dofs(solver: &Solver, field: &[f64], c: usize) -> Vec<f64> {
    let dim = solver.mesh().dim();
    solver.hierarchy().levels[0].dofs().dof_vertex.iter().map(|&v| field[v as usize * dim + c]).collect()
}
