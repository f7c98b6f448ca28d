//! Structured meshes of the unit cube: n³ hexahedra, or the same grid cut into 6 n³ tetrahedra
//! (Freudenthal), with one patch per side. The 3D free-surface analogue of `meshmove bench`
//! moves the top of these boxes.

use super::meshes::lerp_step;
use crate::geometry::CellType;
use crate::mesh::{Mesh, MeshData};

/// [`structured_box`]: the bottom, z = 0.
pub const BOX_BOTTOM: i32 = 1;
/// [`structured_box`]: the top, z = 1.
pub const BOX_TOP: i32 = 2;
/// [`structured_box`]: the side x = 0.
pub const BOX_X0: i32 = 3;
/// [`structured_box`]: the side x = 1.
pub const BOX_X1: i32 = 4;
/// [`structured_box`]: the side y = 0.
pub const BOX_Y0: i32 = 5;
/// [`structured_box`]: the side y = 1.
pub const BOX_Y1: i32 = 6;

/// The four sides of [`structured_box`] and the axis each is normal to.
pub const BOX_SIDES: [(i32, usize); 4] = [(BOX_X0, 0), (BOX_X1, 0), (BOX_Y0, 1), (BOX_Y1, 1)];

/// The cells of a [`structured_box`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoxCells {
    /// One hexahedron per grid cube.
    Hexes,
    /// Six tetrahedra per grid cube around its main diagonal (Freudenthal), the same in every
    /// cube, so the face diagonals of neighbouring cubes match.
    Tets,
}

impl BoxCells {
    /// A short name: "hex" or "tet".
    pub fn name(self) -> &'static str {
        match self {
            BoxCells::Hexes => "hex",
            BoxCells::Tets => "tet",
        }
    }
}

/// Patch of the cube side `axis` = `at` (0 or 1).
fn side_patch(axis: usize, at: usize) -> i32 {
    [[BOX_X0, BOX_X1], [BOX_Y0, BOX_Y1], [BOX_BOTTOM, BOX_TOP]][axis][at]
}

/// The unit cube as an `n`×`n`×`n` grid, (n + 1)³ vertices, vertex (i, j, k) at index
/// (k (n + 1) + j)(n + 1) + i and position (i, j, k)/n exactly; its cells by `cells`. Every
/// boundary face is tagged: [`BOX_BOTTOM`], [`BOX_TOP`], [`BOX_X0`], [`BOX_X1`], [`BOX_Y0`],
/// [`BOX_Y1`].
pub fn structured_box(n: usize, cells: BoxCells) -> Mesh {
    assert!(n >= 1, "structured_box: n >= 1");
    let n1 = n + 1;
    let id = |i: usize, j: usize, k: usize| ((k * n1 + j) * n1 + i) as u32;
    let mut d = MeshData::new(3);
    d.coords.reserve(3 * n1 * n1 * n1);
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                d.push_vertex(&[lerp_step(0.0, 1.0, i, n), lerp_step(0.0, 1.0, j, n), lerp_step(0.0, 1.0, k, n)]);
            }
        }
    }
    // Grid index of a vertex along `axis`.
    let grid = |v: u32, axis: usize| (v as usize / n1.pow(axis as u32)) % n1;
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                // The 8 corners in VTK hexahedron order.
                let c = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                let boundary = [i, j, k].iter().any(|&a| a == 0 || a == n - 1);
                match cells {
                    BoxCells::Hexes => d.push_cell(CellType::Hexahedron, &c, 0),
                    BoxCells::Tets => {
                        for path in [[1, 2], [2, 3], [3, 7], [7, 4], [4, 5], [5, 1]] {
                            let t = [c[0], c[path[0]], c[path[1]], c[6]];
                            d.push_cell(CellType::Tetra, &t, 0);
                            if !boundary {
                                continue;
                            }
                            // A face of the tetrahedron on a side of the cube is a boundary face.
                            for skip in 0..4 {
                                let f: Vec<u32> = (0..4).filter(|&q| q != skip).map(|q| t[q]).collect();
                                for axis in 0..3 {
                                    for at in [0, n] {
                                        if f.iter().all(|&v| grid(v, axis) == at) {
                                            d.push_face(&f, side_patch(axis, (at == n) as usize));
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    if cells == BoxCells::Hexes {
        // Each side's quads: the grid square (a, b) of the side `axis` = `at`.
        for axis in 0..3 {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            for at in [0, n] {
                for b in 0..n {
                    for a in 0..n {
                        let v = |da: usize, db: usize| {
                            let mut g = [0; 3];
                            g[axis] = at;
                            g[u] = a + da;
                            g[w] = b + db;
                            id(g[0], g[1], g[2])
                        };
                        d.push_face(&[v(0, 0), v(1, 0), v(1, 1), v(0, 1)], side_patch(axis, (at == n) as usize));
                    }
                }
            }
        }
    }
    Mesh::from_data(&d).unwrap_or_else(|e| panic!("structured_box({n}, {cells:?}): {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::quality::signed_measures;

    #[test]
    fn boxes_fill_the_unit_cube_and_tag_every_side() {
        let n = 4;
        for cells in [BoxCells::Hexes, BoxCells::Tets] {
            let m = structured_box(n, cells);
            assert_eq!(m.num_vertices(), 125);
            assert_eq!(m.num_cells(), if cells == BoxCells::Hexes { 64 } else { 384 });
            let vols = signed_measures(&m, m.coords());
            assert!(vols.iter().all(|&v| v > 0.0), "{cells:?}");
            assert!((vols.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{cells:?}");
            // 6 sides of n² squares (two triangles each for tets); none left on patch 0.
            let per_square = if cells == BoxCells::Hexes { 1 } else { 2 };
            assert_eq!(m.num_patch_faces(), 6 * n * n * per_square, "{cells:?}");
            assert!(m.patch_faces().all(|f| f.patch != 0), "{cells:?}");
            for (patch, axis, at) in [(BOX_BOTTOM, 2, 0.0), (BOX_TOP, 2, 1.0), (BOX_X1, 0, 1.0), (BOX_Y0, 1, 0.0)] {
                let vs = m.patch_vertices(patch);
                assert_eq!(vs.len(), 25, "{cells:?} patch {patch}");
                assert!(vs.iter().all(|&v| m.point(v as usize)[axis] == at), "{cells:?} patch {patch}");
            }
        }
    }
}
