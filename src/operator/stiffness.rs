//! Assembly of K (the stiffness ∫∇φ_i·∇φ_j, or spring weights) and the lumped mass V on the
//! unknowns, from the element kernels of `geometry`.
//!
//! The pattern is built once per level; re-evaluating on a moved mesh only refills its values, at
//! the positions the scatter map (`scatter.rs`) computed with the pattern.
//! Every entry sums its cells' contributions in cell order (serially on one or two threads, row
//! by row beyond), so sums never depend on thread count.

use super::scatter::{prefetch_rows, Scatter};
use crate::bc::Dofs;
use crate::geometry::{dist2, CellPoints, Corners, Lanes, MAX_CORNERS};
use crate::sparse::CsrMatrix;
use crate::Mesh;

/// The points of cell `c`.
#[inline]
fn cell_points(mesh: &Mesh, c: usize) -> CellPoints {
    CellPoints::gather(mesh.cell_type(c), mesh.cell(c), mesh.coords(), mesh.dim())
}

/// Sparsity of K on the unknowns (with the diagonal), values zero: the couplings of every cell.
#[cfg(test)]
pub(crate) fn stiffness_pattern(mesh: &Mesh, dofs: &Dofs) -> CsrMatrix {
    super::scatter::pattern_and_scatter(mesh, dofs, false).0
}

/// Sets K_ii = −Σ_{j≠i} K_ij, so constants are exactly in the null space of every row.
pub(crate) fn close_diagonal(k: &mut CsrMatrix) {
    for i in 0..k.nrows {
        close_row(k, i);
    }
}

/// `close_diagonal` of row `i`; returns the position of its diagonal.
#[inline(always)]
fn close_row(k: &mut CsrMatrix, i: usize) -> std::ops::Range<usize> {
    let r = k.row_ptr[i] as usize..k.row_ptr[i + 1] as usize;
    let mut s = 0.0;
    let mut diag = usize::MAX;
    for p in r.clone() {
        if k.cols[p] as usize == i {
            diag = p;
        } else {
            s += k.vals[p];
        }
    }
    k.vals[diag] = -s;
    r
}

/// `close_diagonal`, returning each closed row's sum of absolute values (Σ_j |K_ij| in the row's
/// order, as `LevelOperator::inv_l1_diags` forms it): summed while the row is in cache, so the
/// l1 diagonals need no other pass over K.
pub(crate) fn close_diagonal_and_row_abs(k: &mut CsrMatrix) -> Vec<f64> {
    (0..k.nrows)
        .map(|i| {
            let r = close_row(k, i);
            k.vals[r].iter().map(|a| a.abs()).sum()
        })
        .collect()
}

#[cfg(test)]
/// K_ij = ∫∇φ_i·∇φ_j, summed cell by cell over each cell's couplings (for a triangle, edge ij
/// gets −½ cot of the opposite angle). Fills the values of `k`, whose pattern is
/// `stiffness_pattern(mesh, dofs)`.
pub(crate) fn stiffness(k: &mut CsrMatrix, mesh: &Mesh, dofs: &Dofs) {
    k.vals.iter_mut().for_each(|v| *v = 0.0);
    let mut local = [0.0; 28];
    for c in 0..mesh.num_cells() {
        if mesh.cell_type(c).is_general() {
            super::general::add(Some(k), None, mesh, dofs, c);
            continue;
        }
        let d = dofs.cell_dofs(mesh, c);
        let g = cell_points(mesh, c);
        g.stiffness(&mut local);
        for (m, &[i, j]) in g.ty.couplings().iter().enumerate() {
            let (di, dj) = (d[i as usize] as usize, d[j as usize] as usize);
            if di != dj {
                let a = k.find(di, dj).expect("coupling in pattern");
                k.vals[a] += local[m];
                let b = k.find(dj, di).expect("coupling in pattern");
                k.vals[b] += local[m];
            }
        }
    }
    close_diagonal(k);
}

/// Cells per chunk of `stiffness_and_mass`: their element matrices are evaluated in parallel,
/// then added in cell order, so the temporary stays small and sums are `stiffness`'s.
const ASSEMBLY_CHUNK: usize = 16384;
/// Most couplings of a cell (a hexahedron's 28 pairs of corners).
const MAX_COUPLINGS: usize = 28;

/// `stiffness` and `lumped_mass` in one pass, bitwise both: each chunk of cells has its element
/// matrices evaluated in parallel (a cell's stiffness and mass share its quadrature points), then
/// added into K and V in cell order, as `stiffness` and `lumped_mass` add them: serially on one
/// or two threads, at the positions `scatter` holds (`Scatter::new(k, mesh, dofs)`), row by row
/// in parallel on more (`add_by_rows`), with the same sums either way. On one thread each cell's
/// matrices are added as soon as they are evaluated, while they are in cache, the whole loop
/// compiled for the processor's lanes (`Lanes`, asked once). Returns V and the closed rows' sums
/// of absolute values (`close_diagonal_and_row_abs`).
pub(crate) fn stiffness_and_mass(k: &mut CsrMatrix, scatter: &Scatter, mesh: &Mesh, dofs: &Dofs) -> (Vec<f64>, Vec<f64>) {
    use rayon::prelude::*;
    k.vals.iter_mut().for_each(|v| *v = 0.0);
    let mut v = vec![0.0; dofs.n];
    let lanes = Lanes::detect();
    if rayon::current_num_threads() == 1 {
        let mut at = 0;
        // Inlined into `run`'s copy for the lanes, with the kernel and the adds.
        lanes.run(#[inline(always)]
        || {
            for c in 0..mesh.num_cells() {
                let next = c + 1;
                if next < mesh.num_cells() && !mesh.cell_type(next).is_general() {
                    prefetch_rows(k, &dofs.cell_dofs(mesh, next));
                }
                add_cell(c, &element(mesh, c), k, &mut v, &mut at, scatter, mesh, dofs);
            }
        });
        debug_assert_eq!(at, scatter.len(), "the map holds every coupling");
        return (v, close_diagonal_and_row_abs(k));
    }
    // A row visits every cell around it and picks its couplings out of the cell's: more index
    // work than the serial loop's, which pays back only beyond two threads (profiled).
    let by_rows = (rayon::current_num_threads() > 2).then(|| RowCells::new(mesh, dofs));
    let mut elems = Vec::new();
    // The next coupling's index in `scatter`: the cells are added in order.
    let mut at = 0;
    for start in (0..mesh.num_cells()).step_by(ASSEMBLY_CHUNK) {
        let cells = start..(start + ASSEMBLY_CHUNK).min(mesh.num_cells());
        cells.clone().into_par_iter().with_min_len(256).map(|c| lanes.run(#[inline(always)] || element(mesh, c))).collect_into_vec(&mut elems);
        if let Some(rc) = &by_rows {
            add_by_rows(rc, cells, &elems, k, &mut v, mesh, dofs);
            continue;
        }
        for (c, e) in cells.zip(&elems) {
            add_cell(c, e, k, &mut v, &mut at, scatter, mesh, dofs);
        }
    }
    debug_assert!(by_rows.is_some() || at == scatter.len(), "the map holds every coupling");
    (v, close_diagonal_and_row_abs(k))
}

/// A cell's element matrices: its stiffness per coupling and its lumped mass per corner (zero
/// for a general cell, evaluated as it is added).
type Element = ([f64; MAX_COUPLINGS], [f64; MAX_CORNERS]);

/// The element matrices of cell `c` (`Element`), inlined into the pass's `Lanes::run`.
#[inline(always)]
fn element(mesh: &Mesh, c: usize) -> Element {
    let (mut kl, mut ml) = ([0.0; MAX_COUPLINGS], [0.0; MAX_CORNERS]);
    if !mesh.cell_type(c).is_general() {
        cell_points(mesh, c).stiffness_and_mass(&mut kl, &mut ml);
    }
    (kl, ml)
}

/// Adds cell `c`'s element matrices `(kl, ml)` into K and V, its couplings at the positions
/// `scatter` holds from coupling `at` on (advanced past them); a general cell is evaluated and
/// added by `general.rs`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn add_cell(c: usize, (kl, ml): &Element, k: &mut CsrMatrix, v: &mut [f64], at: &mut usize, scatter: &Scatter, mesh: &Mesh, dofs: &Dofs) {
    if mesh.cell_type(c).is_general() {
        super::general::add(Some(k), Some(v), mesh, dofs, c);
        return;
    }
    let d = dofs.cell_dofs(mesh, c);
    let couplings = mesh.cell_type(c).couplings();
    if let Some(within) = scatter.within_rows(*at, couplings.len()) {
        // Every coupling by its map: each corner's row start read once.
        let rows = Corners::<usize>::from_fn(d.len(), |q| k.row_ptr[d[q] as usize] as usize);
        for ((&[i, j], o), &x) in couplings.iter().zip(within.chunks_exact(2)).zip(kl) {
            k.vals[rows[i as usize] + o[0] as usize] += x;
            k.vals[rows[j as usize] + o[1] as usize] += x;
        }
        *at += couplings.len();
        for (q, &i) in d.iter().enumerate() {
            v[i as usize] += ml[q];
        }
        return;
    }
    for (m, &[i, j]) in couplings.iter().enumerate() {
        let (di, dj) = (d[i as usize] as usize, d[j as usize] as usize);
        if di != dj {
            let (a, b) = scatter.positions(k, *at + m, di, dj);
            k.vals[a] += kl[m];
            k.vals[b] += kl[m];
        }
    }
    *at += couplings.len();
    for (q, &i) in d.iter().enumerate() {
        v[i as usize] += ml[q];
    }
}

/// The cells around each unknown, ascending (a cell once however many of its corners the
/// unknown holds): which element matrices a row of K sums.
struct RowCells {
    start: Vec<usize>,
    cells: Vec<u32>,
}

impl RowCells {
    fn new(mesh: &Mesh, dofs: &Dofs) -> Self {
        let mut count = vec![0usize; dofs.n + 1];
        let each = |f: &mut dyn FnMut(usize, usize)| {
            for c in 0..mesh.num_cells() {
                let d = dofs.cell_dofs(mesh, c);
                for (q, &i) in d.iter().enumerate() {
                    if !d[..q].contains(&i) {
                        f(i as usize, c);
                    }
                }
            }
        };
        each(&mut |i, _| count[i + 1] += 1);
        for i in 0..dofs.n {
            count[i + 1] += count[i];
        }
        let start = count.clone();
        let mut cells = vec![0u32; start[dofs.n]];
        each(&mut |i, c| {
            cells[count[i]] = c as u32;
            count[i] += 1;
        });
        RowCells { start, cells }
    }
}

/// Rows of K per task of `add_by_rows`.
const ROWS_PER_TASK: usize = 512;

/// Adds the element matrices `elems` of the cells `chunk` into K and V, each row of K (and entry
/// of V) by its own task: a row sums its cells in ascending order and within a cell its
/// couplings in order, which is the order the serial loop adds them to each entry, so the sums
/// are bitwise that loop's.
fn add_by_rows(
    rc: &RowCells,
    chunk: std::ops::Range<usize>,
    elems: &[Element],
    k: &mut CsrMatrix,
    v: &mut [f64],
    mesh: &Mesh,
    dofs: &Dofs,
) {
    use rayon::prelude::*;
    let row_ptr = &k.row_ptr;
    let cols = &k.cols;
    // Blocks of rows with their disjoint parts of K's values and of V.
    let mut blocks = Vec::with_capacity(dofs.n.div_ceil(ROWS_PER_TASK));
    let (mut rest, mut v_rest) = (&mut k.vals[..], v);
    for first in (0..dofs.n).step_by(ROWS_PER_TASK) {
        let end = (first + ROWS_PER_TASK).min(dofs.n);
        let (kv, next) = std::mem::take(&mut rest).split_at_mut((row_ptr[end] - row_ptr[first]) as usize);
        let (vv, v_next) = std::mem::take(&mut v_rest).split_at_mut(end - first);
        (rest, v_rest) = (next, v_next);
        blocks.push((first..end, kv, vv));
    }
    let (lo, hi) = (chunk.start as u32, chunk.end as u32);
    blocks.into_par_iter().for_each(|(rows, kv, vv)| {
        let base = row_ptr[rows.start] as usize;
        for r in rows.clone() {
            let around = &rc.cells[rc.start[r]..rc.start[r + 1]];
            let from = around.partition_point(|&c| c < lo);
            let (a, b) = (row_ptr[r] as usize, row_ptr[r + 1] as usize);
            let (row_cols, row_vals) = (&cols[a..b], &mut kv[a - base..b - base]);
            let mut add = |j: u32, x: f64| {
                let p = row_cols.binary_search(&j).expect("coupling in pattern");
                row_vals[p] += x;
            };
            for &c in around[from..].iter().take_while(|&&c| c < hi) {
                let c = c as usize;
                let d = dofs.cell_dofs(mesh, c);
                let (kl, ml) = &elems[c - chunk.start];
                let r32 = r as u32;
                for (m, &[i, j]) in mesh.cell_type(c).couplings().iter().enumerate() {
                    let (di, dj) = (d[i as usize], d[j as usize]);
                    if di == r32 && dj != r32 {
                        add(dj, kl[m]);
                    } else if dj == r32 && di != r32 {
                        add(di, kl[m]);
                    }
                }
                for (q, &i) in d.iter().enumerate() {
                    if i == r32 {
                        vv[r - rows.start] += ml[q];
                    }
                }
            }
        }
    });
}

/// The spring analogy: graph Laplacian with weight 1/L² on every edge of the cells (never a
/// face or body diagonal). An edge seen from several cells, or twice through a link, is one
/// spring. Fills `k` as `stiffness` does.
pub(crate) fn spring_stiffness(k: &mut CsrMatrix, mesh: &Mesh, dofs: &Dofs) {
    k.vals.iter_mut().for_each(|v| *v = 0.0);
    let mut seen = vec![false; k.nnz()];
    for c in 0..mesh.num_cells() {
        if mesh.cell_type(c).is_general() {
            super::general::add_springs(k, &mut seen, mesh, dofs, c);
            continue;
        }
        let d = dofs.cell_dofs(mesh, c);
        let g = cell_points(mesh, c);
        for &[i, j] in g.ty.edges() {
            let (di, dj) = (d[i as usize] as usize, d[j as usize] as usize);
            let p = k.find(di, dj).expect("edge in pattern");
            if di == dj || seen[p] {
                continue;
            }
            let w = 1.0 / dist2(&g.p[i as usize], &g.p[j as usize]);
            let q = k.find(dj, di).expect("edge in pattern");
            seen[p] = true;
            seen[q] = true;
            k.vals[p] = -w;
            k.vals[q] = -w;
        }
    }
    close_diagonal(k);
}

/// V_i = ∫φ_i, the lumped mass (a third of the area of the triangles around i).
pub(crate) fn lumped_mass(mesh: &Mesh, dofs: &Dofs) -> Vec<f64> {
    let mut v = vec![0.0; dofs.n];
    let mut local = [0.0; crate::geometry::MAX_CORNERS];
    for c in 0..mesh.num_cells() {
        if mesh.cell_type(c).is_general() {
            super::general::add(None, Some(&mut v), mesh, dofs, c);
            continue;
        }
        let d = dofs.cell_dofs(mesh, c);
        cell_points(mesh, c).lumped_mass(&mut local);
        for (k, &i) in d.iter().enumerate() {
            v[i as usize] += local[k];
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::CellType;
    use crate::mesh::MeshData;

    /// A hexahedron with a pyramid on its top, a wedge beside it and a tetrahedron on its other
    /// side, corners moved off the grid, its faces partly tagged.
    fn solids() -> Mesh {
        let mut d = MeshData::new(3);
        #[rustfmt::skip]
        let coords = [
            [0., 0., 0.], [1., 0., 0.1], [1., 1., 0.], [0., 1.05, 0.], [0., 0.1, 1.], [1., 0., 1.],
            [1.1, 1., 1.], [0., 1., 1.], [0.5, 0.4, 1.5], [2., 0., 0.], [2., 1., 0.2], [-1., 0., 0.],
        ];
        coords.iter().for_each(|p| {
            d.push_vertex(p);
        });
        d.push_cell(CellType::Hexahedron, &[0, 1, 2, 3, 4, 5, 6, 7], 1);
        d.push_cell(CellType::Pyramid, &[4, 5, 6, 7, 8], 2);
        d.push_cell(CellType::Wedge, &[1, 9, 5, 2, 10, 6], 3);
        d.push_cell(CellType::Tetra, &[0, 4, 3, 11], 4);
        d.push_face(&[0, 3, 2, 1], 1);
        Mesh::from_data(&d).unwrap()
    }

    /// Four cells in 2D: a quadrilateral, two triangles and a third cell of type `third` (a
    /// triangle or a polygon).
    fn flat(third: CellType) -> Mesh {
        let mut d = MeshData::new(2);
        for p in [[0., 0.], [1., 0.], [2., 0.1], [0., 1.], [1.1, 1.], [2., 1.], [1., 2.]] {
            d.push_vertex(&p);
        }
        d.push_cell(CellType::Quad, &[0, 1, 4, 3], 1);
        d.push_cell(CellType::Triangle, &[1, 2, 5], 1);
        d.push_cell(third, &[1, 5, 4], 1);
        d.push_cell(CellType::Triangle, &[3, 4, 6], 1);
        Mesh::from_data(&d).unwrap()
    }

    /// A box of n³ cubes, each split into six tetrahedra around its diagonal, the vertices
    /// shifted off the grid so no two cells are alike.
    fn tets(n: usize) -> Mesh {
        let mut d = MeshData::new(3);
        let m = n + 1;
        let mut x = Vec::new();
        for k in 0..m {
            for j in 0..m {
                for i in 0..m {
                    let w = (i * 7 + j * 3 + k * 5) as f64 % 11.0 / 110.0;
                    x.push([i as f64 + w, j as f64 - w, k as f64 + 0.5 * w]);
                    d.push_vertex(x.last().unwrap());
                }
            }
        }
        // Six times the signed volume of the tetrahedron.
        let volume = |t: &[u32; 4]| {
            let e = |a: usize| -> [f64; 3] { std::array::from_fn(|r| x[t[a] as usize][r] - x[t[0] as usize][r]) };
            let (a, b, c) = (e(1), e(2), e(3));
            a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])
        };
        let at = |i: usize, j: usize, k: usize| (i + m * (j + m * k)) as u32;
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let c = [at(i, j, k), at(i + 1, j, k), at(i + 1, j + 1, k), at(i, j + 1, k)];
                    let t = [at(i, j, k + 1), at(i + 1, j, k + 1), at(i + 1, j + 1, k + 1), at(i, j + 1, k + 1)];
                    for q in [[c[1], c[2], t[2]], [c[2], c[3], t[2]], [c[3], t[3], t[2]], [t[3], t[0], t[2]], [t[1], c[1], t[2]], [t[0], t[1], t[2]]] {
                        let mut tet = [c[0], q[0], q[1], q[2]];
                        if volume(&tet) < 0.0 {
                            tet.swap(1, 2);
                        }
                        d.push_cell(CellType::Tetra, &tet, 1);
                    }
                }
            }
        }
        Mesh::from_data(&d).unwrap()
    }

    /// Over several chunks of cells, the row-by-row adding of several threads is bitwise the
    /// serial loop of one thread.
    #[test]
    fn rows_added_in_parallel_are_the_serial_sums_bitwise() {
        let mesh = crate::mesh::fixtures::rect(130, 130, [0.0, 1.0, 0.0, 0.7]);
        assert!(mesh.num_cells() > 2 * ASSEMBLY_CHUNK);
        let dofs = Dofs::build(&mesh, &[], &[]);
        let run = |threads: usize| {
            let mut k = stiffness_pattern(&mesh, &dofs);
            let scatter = Scatter::new(&k, &mesh, &dofs);
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let (v, _) = pool.install(|| stiffness_and_mass(&mut k, &scatter, &mesh, &dofs));
            (k.vals, v)
        };
        let ((k1, v1), (k3, v3)) = (run(1), run(3));
        let same = |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same(&k1, &k3) && same(&v1, &v3));
        assert!(v1.iter().all(|v| *v > 0.0) && k1.iter().any(|v| *v < 0.0));
    }

    /// The one-pass parallel assembly is bitwise the separate stiffness and lumped mass, from
    /// one thread (the scatter map) and from several (row by row), on every 3D cell type.
    #[test]
    fn stiffness_and_mass_is_both_bitwise() {
        let mesh = solids();
        let dofs = Dofs::build(&mesh, &[], &[]);
        let mut k0 = stiffness_pattern(&mesh, &dofs);
        let scatter = Scatter::new(&k0, &mesh, &dofs);
        let (mut k1, mut k3) = (k0.clone(), k0.clone());
        stiffness(&mut k0, &mesh, &dofs);
        let v0 = lumped_mass(&mesh, &dofs);
        let on = |threads: usize| rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let (v1, _) = on(1).install(|| stiffness_and_mass(&mut k1, &scatter, &mesh, &dofs));
        let (v3, _) = on(3).install(|| stiffness_and_mass(&mut k3, &scatter, &mesh, &dofs));
        let same = |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same(&k0.vals, &k1.vals) && same(&v0, &v1));
        assert!(same(&k0.vals, &k3.vals) && same(&v0, &v3));
        assert!(k0.vals.iter().filter(|v| **v != 0.0).count() > 40 && v0.iter().all(|v| *v > 0.0));
    }

    /// K's pattern and the scatter map from one pass are the pattern of the sorted pairs and
    /// the map of the rows' search, on mixed cells (a polygon among them), linked vertices
    /// (a coupling of an unknown with itself) and a tetrahedral box; without the map, the same
    /// pattern.
    #[test]
    fn one_pass_gives_the_sorted_pattern_and_the_searched_map() {
        let cases = [(solids(), Vec::new()), (flat(CellType::Polygon), vec![[2, 5]]), (tets(4), Vec::new())];
        for (mesh, links) in cases {
            let dofs = Dofs::build(&mesh, &links, &[]);
            // The pairs of every coupling both ways and the diagonal, sorted row by row.
            let mut pairs: Vec<(u32, u32)> = (0..dofs.n as u32).map(|i| (i, i)).collect();
            for c in 0..mesh.num_cells() {
                if mesh.cell_type(c).is_general() {
                    super::super::general::pattern(&mesh, &dofs, c, &mut pairs);
                    continue;
                }
                let d = dofs.cell_dofs(&mesh, c);
                for &[i, j] in mesh.cell_type(c).couplings() {
                    pairs.extend([(d[i as usize], d[j as usize]), (d[j as usize], d[i as usize])]);
                }
            }
            let sorted = CsrMatrix::from_pattern(dofs.n, dofs.n, pairs);
            let (k, scatter) = super::super::scatter::pattern_and_scatter(&mesh, &dofs, true);
            assert_eq!((&k.row_ptr, &k.cols), (&sorted.row_ptr, &sorted.cols));
            assert_eq!(k.vals.len(), k.cols.len());
            let searched = Scatter::new(&sorted, &mesh, &dofs);
            assert_eq!(scatter.len(), searched.len());
            for at in 0..scatter.len() {
                assert_eq!(scatter.slots(at), searched.slots(at), "coupling {at}");
            }
            let (bare, none) = super::super::scatter::pattern_and_scatter(&mesh, &dofs, false);
            assert_eq!((&bare.row_ptr, &bare.cols, none.len()), (&k.row_ptr, &k.cols, 0));
        }
    }

    /// Adding by the scatter map's positions is bitwise adding by the rows' search, on mixed
    /// cells in 2D (triangles and quadrilaterals, two vertices linked into one unknown so a cell
    /// holds a coupling of an unknown with itself) and 3D; the map holds every coupling.
    #[test]
    fn the_scatter_map_adds_as_the_search_does() {
        let cases = [(solids(), Vec::new()), (flat(CellType::Triangle), vec![[2, 5]]), (tets(3), Vec::new())];
        for (mesh, pairs) in cases {
            let dofs = Dofs::build(&mesh, &pairs, &[]);
            let k = stiffness_pattern(&mesh, &dofs);
            let scatter = Scatter::new(&k, &mesh, &dofs);
            let couplings: usize = (0..mesh.num_cells()).map(|c| mesh.cell_type(c).couplings().len()).sum();
            assert_eq!(scatter.len(), couplings);
            let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
            let add = |s: &Scatter| {
                let mut k = k.clone();
                let (v, _) = one.install(|| stiffness_and_mass(&mut k, s, &mesh, &dofs));
                (k.vals, v)
            };
            let (mapped, searched) = (add(&scatter), add(&Scatter::searching(couplings)));
            let bits = |(k, v): &(Vec<f64>, Vec<f64>)| k.iter().chain(v).map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&mapped), bits(&searched));
            assert!(mapped.0.iter().filter(|v| **v != 0.0).count() >= 2 * mesh.num_cells());
        }
    }
}
