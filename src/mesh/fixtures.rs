//! Small structured meshes for the crate's unit tests (the paper's cases live in their own
//! crate, out of the library's reach).

use super::{IndexBase, Mesh, MeshData};
use crate::geometry::CellType;

/// The vertices of an nx × ny grid on `bounds` = [x0, x1, y0, y1], vertex (i, j) at index
/// j (nx + 1) + i, the last ones exactly on x1 and y1.
fn grid_points(nx: usize, ny: usize, bounds: [f64; 4]) -> Vec<[f64; 2]> {
    let [x0, x1, y0, y1] = bounds;
    let at = |a: f64, b: f64, i: usize, n: usize| if i == n { b } else { a + (b - a) * (i as f64 / n as f64) };
    (0..=ny).flat_map(|j| (0..=nx).map(move |i| [at(x0, x1, i, nx), at(y0, y1, j, ny)])).collect()
}

/// The index of grid vertex (i, j) of an nx × ny grid.
fn id(nx: usize, i: usize, j: usize) -> u32 {
    (j * (nx + 1) + i) as u32
}

/// The boundary sides of an nx × ny grid, counter-clockwise with the domain on their left:
/// bottom 1, right 2, top 3, left 4.
fn rect_sides(nx: usize, ny: usize) -> Vec<([u32; 2], i32)> {
    let id = |i, j| id(nx, i, j);
    let mut s: Vec<([u32; 2], i32)> = (0..nx).map(|i| ([id(i, 0), id(i + 1, 0)], 1)).collect();
    s.extend((0..ny).map(|j| ([id(nx, j), id(nx, j + 1)], 2)));
    s.extend((0..nx).rev().map(|i| ([id(i + 1, ny), id(i, ny)], 3)));
    s.extend((0..ny).rev().map(|j| ([id(0, j + 1), id(0, j)], 4)));
    s
}

/// The triangles of an nx × ny grid, each square cut by its rising diagonal, row by row.
fn grid_triangles(nx: usize, ny: usize) -> Vec<[u32; 3]> {
    let id = |i, j| id(nx, i, j);
    (0..ny)
        .flat_map(|j| (0..nx).map(move |i| (i, j)))
        .flat_map(|(i, j)| [[id(i, j), id(i + 1, j), id(i + 1, j + 1)], [id(i, j), id(i + 1, j + 1), id(i, j + 1)]])
        .collect()
}

/// Triangles on the rectangle `bounds` (see [`grid_triangles`]), its sides tagged as in
/// [`rect_sides`].
pub(crate) fn rect(nx: usize, ny: usize, bounds: [f64; 4]) -> Mesh {
    let tags = rect_sides(nx, ny);
    Mesh::triangles(&grid_points(nx, ny, bounds), &grid_triangles(nx, ny), IndexBase::Zero, &tags, None).unwrap()
}

/// The unit square in n × n squares (n even) cut into triangles: regions 1 (y < 1/2) and 2, the
/// interface y = 1/2 tagged as patch 9, the outer sides untagged.
pub(crate) fn two_regions(n: usize) -> Mesh {
    let regions: Vec<i32> = (0..n).flat_map(|j| [if 2 * j < n { 1 } else { 2 }; 2].repeat(n)).collect();
    let tags: Vec<([u32; 2], i32)> = (0..n).map(|i| ([id(n, i, n / 2), id(n, i + 1, n / 2)], 9)).collect();
    let (coords, cells) = (grid_points(n, n, [0.0, 1.0, 0.0, 1.0]), grid_triangles(n, n));
    Mesh::triangles(&coords, &cells, IndexBase::Zero, &tags, Some(&regions)).unwrap()
}

/// nx × ny quads on `bounds`, region 0, the sides tagged as in [`rect_sides`].
pub(crate) fn quads(nx: usize, ny: usize, bounds: [f64; 4]) -> MeshData {
    let id = |i, j| id(nx, i, j);
    let mut d = MeshData::new(2);
    grid_points(nx, ny, bounds).iter().for_each(|p| {
        d.push_vertex(p);
    });
    for j in 0..ny {
        for i in 0..nx {
            d.push_cell(CellType::Quad, &[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)], 0);
        }
    }
    rect_sides(nx, ny).iter().for_each(|(f, p)| d.push_face(f, *p));
    d
}
