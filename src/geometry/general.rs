//! General cells: polygons (2D) and polyhedra (3D), each with its own corners and faces.
//!
//! The element is P1 on a decomposition into simplices through the cell's own points: in 2D a
//! fan of triangles (one per side) around the cell centre; in 3D one tetrahedron per side of
//! every face, through that face's centre and the cell centre. The centres are the averages of
//! the corners (a face's of its own corners), so they add no unknown: the shape function of a
//! centre is shared equally by the corners it averages, K = Pᵀ K_sub P and V = Pᵀ V_sub with P
//! the averaging. A linear field on the corners is linear on every sub-simplex (its centre
//! values are averages of a linear function's values, which lie on it), so the element
//! reproduces linear fields exactly, and it is symmetric and has every corner in the same role.
//! A cell is inverted when one of its sub-simplices has a non-positive volume.

use super::simplex::{tet_gradients, tet_volume, triangle_area, triangle_stiffness};
use super::{cross, dist2, dot3, sub};

/// The corners of one general cell, padded to 3 coordinates, and (3D) its faces as loops of
/// local corners whose right-hand normals point out of the cell.
#[derive(Clone, Debug)]
pub(crate) struct GeneralPoints {
    dim: usize,
    p: Vec<[f64; 3]>,
    /// Face `f`'s corners are `corners[ptr[f]..ptr[f + 1]]`; empty in 2D (the corners are the
    /// polygon's counter-clockwise loop).
    ptr: Vec<usize>,
    corners: Vec<usize>,
}

impl GeneralPoints {
    /// Gathers the corners `verts` of a general cell from interleaved `coords` of `dim` values
    /// per vertex; in 3D `faces` are its faces as loops of (global) vertices, each of them one
    /// of `verts` (the mesh's validation sees to it).
    pub(crate) fn gather<'a>(
        verts: &[u32],
        faces: impl Iterator<Item = &'a [u32]>,
        coords: &[f64],
        dim: usize,
    ) -> GeneralPoints {
        let p = verts
            .iter()
            .map(|&v| {
                let mut x = [0.0; 3];
                x[..dim].copy_from_slice(&coords[v as usize * dim..v as usize * dim + dim]);
                x
            })
            .collect();
        let (mut ptr, mut corners) = (vec![0], Vec::new());
        if dim == 3 {
            for f in faces {
                corners.extend(f.iter().map(|v| verts.iter().position(|w| w == v).unwrap_or(0)));
                ptr.push(corners.len());
            }
        }
        GeneralPoints { dim, p, ptr, corners }
    }

    /// The number of corners.
    pub(crate) fn num_corners(&self) -> usize {
        self.p.len()
    }

    /// The faces' loops of local corners (3D).
    fn faces(&self) -> impl Iterator<Item = &[usize]> + '_ {
        self.ptr.windows(2).map(|w| &self.corners[w[0]..w[1]])
    }

    /// The cell's edges as pairs of local corners, each once: the polygon's sides, or each face
    /// side seen from the face that runs along it from the lower corner to the higher (the
    /// other face runs along it the other way).
    pub(crate) fn edges(&self) -> Vec<[usize; 2]> {
        let n = self.p.len();
        if self.dim == 2 {
            return (0..n).map(|k| [k, (k + 1) % n]).collect();
        }
        let mut out = Vec::new();
        for f in self.faces() {
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                if a < b {
                    out.push([a, b]);
                }
            }
        }
        out
    }

    /// The average of the given corners.
    fn centre(&self, corners: impl ExactSizeIterator<Item = usize>) -> [f64; 3] {
        let w = 1.0 / corners.len() as f64;
        let mut c = [0.0; 3];
        for k in corners {
            (0..3).for_each(|i| c[i] += self.p[k][i]);
        }
        c.map(|x| x * w)
    }

    /// The sub-simplices as nodes of the augmented cell: corners 0..n, then (3D) the face
    /// centres n..n + faces, then the cell centre. Each is positively oriented in a valid cell.
    fn simplices(&self, mut f: impl FnMut(&[usize])) {
        let n = self.p.len();
        if self.dim == 2 {
            (0..n).for_each(|k| f(&[k, (k + 1) % n, n]));
            return;
        }
        let centre = n + self.ptr.len() - 1;
        for (i, face) in self.faces().enumerate() {
            for k in 0..face.len() {
                // The face's side a → b runs round its outward normal: (b, a, face centre) has
                // the cell centre on its positive side.
                f(&[face[(k + 1) % face.len()], face[k], n + i, centre]);
            }
        }
    }

    /// The positions of the augmented cell's nodes (corners, face centres, centre) and, for
    /// each node past the corners, the corners it averages.
    fn augmented(&self) -> (Vec<[f64; 3]>, Vec<Vec<usize>>) {
        let n = self.p.len();
        let mut x = self.p.clone();
        let mut averages: Vec<Vec<usize>> = self.faces().map(|f| f.to_vec()).collect();
        averages.push((0..n).collect());
        x.extend(averages.iter().map(|a| self.centre(a.iter().copied())));
        (x, averages)
    }

    /// Calls `f` with the positions of every sub-simplex.
    fn each_simplex(&self, mut f: impl FnMut(&[usize], &[[f64; 3]])) {
        let (x, _) = self.augmented();
        self.simplices(|s| {
            let q: Vec<[f64; 3]> = s.iter().map(|&k| x[k]).collect();
            f(s, &q);
        });
    }

    /// The measure of one sub-simplex.
    fn simplex_measure(&self, q: &[[f64; 3]]) -> f64 {
        if self.dim == 2 {
            triangle_area(q)
        } else {
            tet_volume(q)
        }
    }

    /// Signed area (2D) or volume (3D): the sum of the sub-simplices'.
    pub(crate) fn signed_measure(&self) -> f64 {
        let mut sum = 0.0;
        self.each_simplex(|_, q| sum += self.simplex_measure(q));
        sum
    }

    /// The smallest sub-simplex Jacobian (twice the area, six times the volume): the cell is
    /// inverted when it is ≤ 0.
    pub(crate) fn min_corner_jacobian(&self) -> f64 {
        let scale = if self.dim == 2 { 2.0 } else { 6.0 };
        let mut min = f64::INFINITY;
        self.each_simplex(|_, q| min = min.min(scale * self.simplex_measure(q)));
        min
    }

    /// True when a sub-simplex is not positive, or the measure is NaN.
    pub(crate) fn is_inverted(&self) -> bool {
        super::not_positive(self.min_corner_jacobian()) || super::not_positive(self.signed_measure())
    }

    /// The squared length of the longest edge.
    pub(crate) fn longest_edge_squared(&self) -> f64 {
        self.edges().iter().map(|e| dist2(&self.p[e[0]], &self.p[e[1]])).fold(0.0, f64::max)
    }

    /// The smallest angle, degrees: in 2D the smallest interior angle at a corner (0 where the
    /// cell folds), in 3D the smallest dihedral angle between two faces at an edge.
    pub(crate) fn min_angle_deg(&self) -> f64 {
        let n = self.p.len();
        let mut min = 180.0f64;
        if self.dim == 2 {
            if self.is_inverted() {
                return 0.0;
            }
            for k in 0..n {
                let a = sub(&self.p[(k + 1) % n], &self.p[k]);
                let b = sub(&self.p[(k + n - 1) % n], &self.p[k]);
                // From the side to the next corner round to the side to the previous one: a
                // reflex corner of a star-shaped polygon has an angle past 180°.
                let angle = (a[0] * b[1] - a[1] * b[0]).atan2(a[0] * b[0] + a[1] * b[1]).to_degrees();
                min = min.min(if angle < 0.0 { 360.0 + angle } else { angle });
            }
            return min;
        }
        // At each edge a → b of a face, the direction from the edge into that face and into the
        // face that runs along it b → a, orthogonal to the edge.
        let faces: Vec<&[usize]> = self.faces().collect();
        let into = |f: &[usize], k: usize| {
            let (pa, pb) = (&self.p[f[k]], &self.p[f[(k + 1) % f.len()]]);
            let e = sub(pb, pa);
            let w = sub(&self.p[f[(k + 2) % f.len()]], pa);
            let t = dot3(&w, &e) / dot3(&e, &e);
            [w[0] - t * e[0], w[1] - t * e[1], w[2] - t * e[2]]
        };
        for f in &faces {
            for k in 0..f.len() {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                if a > b {
                    continue;
                }
                let other = faces.iter().find_map(|g| {
                    (0..g.len()).find(|&j| g[j] == b && g[(j + 1) % g.len()] == a).map(|j| into(g, j))
                });
                let Some(v) = other else { continue };
                let u = into(f, k);
                let s = cross(&u, &v);
                min = min.min(dot3(&s, &s).sqrt().atan2(dot3(&u, &v)).to_degrees());
            }
        }
        min
    }

    /// The element: `k` (n × n, row-major) = ∫∇φ_i·∇φ_j and `m` (n) = ∫φ_i, each when asked.
    pub(crate) fn element(&self, k: Option<&mut [f64]>, m: Option<&mut [f64]>) {
        let n = self.p.len();
        let (x, averages) = self.augmented();
        let na = x.len();
        let mut ka = vec![0.0; na * na];
        let mut ma = vec![0.0; na];
        self.simplices(|s| {
            let q: Vec<[f64; 3]> = s.iter().map(|&k| x[k]).collect();
            let mut local = [[0.0; 4]; 4];
            let v = if self.dim == 2 {
                let mut e = [0.0; 3];
                triangle_stiffness(&q, &mut e);
                for (m, &val) in e.iter().enumerate() {
                    let (i, j) = (m, (m + 1) % 3);
                    local[i][j] = val;
                    local[j][i] = val;
                }
                triangle_area(&q)
            } else {
                let (g, v) = tet_gradients(&q);
                for i in 0..4 {
                    for j in 0..4 {
                        if i != j {
                            local[i][j] = v * dot3(&g[i], &g[j]);
                        }
                    }
                }
                v
            };
            // Rows sum to zero: constants are in the null space of every sub-simplex.
            for (i, row) in local.iter_mut().enumerate().take(s.len()) {
                row[i] = -(0..s.len()).filter(|&j| j != i).map(|j| row[j]).sum::<f64>();
            }
            let share = v / s.len() as f64;
            for (i, &a) in s.iter().enumerate() {
                ma[a] += share;
                for (j, &b) in s.iter().enumerate() {
                    ka[a * na + b] += local[i][j];
                }
            }
        });
        // Distribute each centre to the corners it averages: P has row `a` = e_a for a corner,
        // 1/|average| on each averaged corner for a centre.
        let spread = |row: &[f64], out: &mut [f64]| {
            out[..n].copy_from_slice(&row[..n]);
            for (c, avg) in averages.iter().enumerate() {
                let w = row[n + c] / avg.len() as f64;
                avg.iter().for_each(|&i| out[i] += w);
            }
        };
        if let Some(m) = m {
            spread(&ma, m);
        }
        if let Some(k) = k {
            // K P: each row of K_aug spread over the corners; then Pᵀ (K P): its columns likewise.
            let mut kp = vec![0.0; na * n];
            for a in 0..na {
                spread(&ka[a * na..(a + 1) * na], &mut kp[a * n..(a + 1) * n]);
            }
            let mut col = vec![0.0; na];
            let mut out = vec![0.0; n];
            for j in 0..n {
                (0..na).for_each(|a| col[a] = kp[a * n + j]);
                spread(&col, &mut out);
                (0..n).for_each(|i| k[i * n + j] = out[i]);
            }
            // The upper triangle mirrored: K is symmetric bitwise, whatever the order of the sums.
            for i in 0..n {
                for j in i + 1..n {
                    k[j * n + i] = k[i * n + j];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube as a polyhedron: corners in VTK's hexahedron order, faces outward.
    fn cube(x: impl Fn([f64; 3]) -> [f64; 3]) -> GeneralPoints {
        let c = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.], [0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]];
        let coords: Vec<f64> = c.iter().flat_map(|&p| x(p)).collect();
        let faces: [&[u32]; 6] = [&[0, 3, 2, 1], &[4, 5, 6, 7], &[0, 1, 5, 4], &[1, 2, 6, 5], &[2, 3, 7, 6], &[3, 0, 4, 7]];
        GeneralPoints::gather(&[0, 1, 2, 3, 4, 5, 6, 7], faces.into_iter(), &coords, 3)
    }

    /// The cube's volume, masses summing to it, a constant in K's null space, K symmetric, a
    /// linear field's energy exact (|∇u|² times the volume), and a dihedral angle of 90°.
    #[test]
    fn cube_element() {
        let g = cube(|p| [2.0 * p[0], p[1], p[2]]);
        assert!((g.signed_measure() - 2.0).abs() < 1e-14);
        assert!(!g.is_inverted());
        let (mut k, mut m) = (vec![0.0; 64], vec![0.0; 8]);
        g.element(Some(&mut k), Some(&mut m));
        assert!((m.iter().sum::<f64>() - 2.0).abs() < 1e-14 && m.iter().all(|&x| (x - 0.25).abs() < 1e-14));
        let u: Vec<f64> = [[0., 0., 0.], [2., 0., 0.], [2., 1., 0.], [0., 1., 0.], [0., 0., 1.], [2., 0., 1.], [2., 1., 1.], [0., 1., 1.]]
            .iter()
            .map(|p| 0.5 * p[0] - 3.0 * p[1] + p[2])
            .collect();
        let mut energy = 0.0;
        for i in 0..8 {
            assert!(k[i * 8..(i + 1) * 8].iter().sum::<f64>().abs() < 1e-13);
            for j in 0..8 {
                assert_eq!(k[i * 8 + j], k[j * 8 + i]);
                energy += u[i] * k[i * 8 + j] * u[j];
            }
        }
        assert!((energy - (0.25 + 9.0 + 1.0) * 2.0).abs() < 1e-12, "{energy}");
        assert!((g.min_angle_deg() - 90.0).abs() < 1e-12);
        assert!((g.longest_edge_squared() - 4.0).abs() < 1e-15);
        assert_eq!(g.edges().len(), 12);
    }

    /// On a tetrahedron the element is P1's: the centres' values are the linear interpolant's,
    /// so the piecewise linear function on the sub-tetrahedra is the tetrahedron's own.
    #[test]
    fn a_tetrahedron_gets_p1() {
        let p = [[0.1, 0.0, 0.0], [1.0, 0.2, 0.1], [0.3, 1.1, 0.0], [0.2, 0.3, 0.9]];
        let coords: Vec<f64> = p.iter().flatten().copied().collect();
        let faces: Vec<Vec<u32>> =
            super::super::CellType::Tetra.faces().iter().map(|f| f.iter().map(|&k| k as u32).collect()).collect();
        let g = GeneralPoints::gather(&[0, 1, 2, 3], faces.iter().map(|f| f.as_slice()), &coords, 3);
        let mut k = vec![0.0; 16];
        g.element(Some(&mut k), None);
        let mut p1 = [0.0; 6];
        super::super::simplex::tet_stiffness(&p, &mut p1);
        for (m, &[i, j]) in super::super::CellType::Tetra.edges().iter().enumerate() {
            let (i, j) = (i as usize, j as usize);
            assert!((k[i * 4 + j] - p1[m]).abs() < 1e-14, "{i}-{j}: {} {}", k[i * 4 + j], p1[m]);
        }
        assert!((g.signed_measure() - super::super::simplex::tet_volume(&p)).abs() < 1e-15);
    }

    /// A corner pushed through the opposite face inverts a sub-tetrahedron while the volume
    /// stays positive; a mirrored cube has a negative volume.
    #[test]
    fn inversion() {
        let g = cube(|p| if p == [1., 1., 1.] { [0.2, 0.2, 0.2] } else { p });
        assert!(g.signed_measure() > 0.0 && g.is_inverted());
        let g = cube(|p| [-p[0], p[1], p[2]]);
        assert!((g.signed_measure() + 1.0).abs() < 1e-14 && g.is_inverted());
    }

    /// An irregular hexagon: area (shoelace), masses, a linear field's energy, its smallest
    /// angle (at corner 1, between the sides to (3, 1) and to (0, 0)).
    #[test]
    fn polygon_element() {
        let c = [[0., 0.], [2., 0.], [3., 1.], [2., 2.5], [0.5, 2.], [-0.5, 1.]];
        let area = 0.5 * (0..6).map(|k| c[k][0] * c[(k + 1) % 6][1] - c[(k + 1) % 6][0] * c[k][1]).sum::<f64>();
        let coords: Vec<f64> = c.iter().flatten().copied().collect();
        let g = GeneralPoints::gather(&[0, 1, 2, 3, 4, 5], std::iter::empty(), &coords, 2);
        assert!((g.signed_measure() - area).abs() < 1e-14 && !g.is_inverted());
        let (mut k, mut m) = (vec![0.0; 36], vec![0.0; 6]);
        g.element(Some(&mut k), Some(&mut m));
        assert!((m.iter().sum::<f64>() - area).abs() < 1e-14);
        let u: Vec<f64> = c.iter().map(|p| 2.0 * p[0] + p[1]).collect();
        let energy: f64 = (0..36).map(|ij| u[ij / 6] * k[ij] * u[ij % 6]).sum();
        assert!((energy - 5.0 * area).abs() < 1e-12, "{energy}");
        let at = |k: usize| {
            let (a, b) = (sub(&g.p[(k + 1) % 6], &g.p[k]), sub(&g.p[(k + 5) % 6], &g.p[k]));
            (a[0] * b[1] - a[1] * b[0]).atan2(a[0] * b[0] + a[1] * b[1]).to_degrees()
        };
        assert_eq!(g.min_angle_deg(), (0..6).map(at).fold(180.0, f64::min));
        assert!((g.min_angle_deg() - 90.0).abs() < 30.0);
        // Its mirror image is inverted: every sub-triangle turns over, and no angle is kept.
        let mirrored: Vec<f64> = c.iter().flat_map(|p| [-p[0], p[1]]).collect();
        let g = GeneralPoints::gather(&[0, 1, 2, 3, 4, 5], std::iter::empty(), &mirrored, 2);
        assert!(g.is_inverted() && g.min_angle_deg() == 0.0 && g.signed_measure() < 0.0);
    }
}
