//! Assembly of K (the stiffness ∫∇φ_i·∇φ_j, or spring weights) and the lumped mass V on the
//! unknowns, from the element kernels of `geometry`.
//!
//! The pattern is built once per level; re-evaluating on a moved mesh only refills its values,
//! serially in cell order, so sums never depend on thread count.

use crate::bc::Dofs;
use crate::geometry::{dist2, CellPoints};
use crate::sparse::CsrMatrix;
use crate::Mesh;

/// The points of cell `c`.
#[inline]
fn cell_points(mesh: &Mesh, c: usize) -> CellPoints {
    CellPoints::gather(mesh.cell_type(c), mesh.cell(c), mesh.coords(), mesh.dim())
}

/// Sparsity of K on the unknowns (with the diagonal), values zero: the couplings of every cell.
pub(crate) fn stiffness_pattern(mesh: &Mesh, dofs: &Dofs) -> CsrMatrix {
    let mut pairs: Vec<(u32, u32)> = (0..dofs.n as u32).map(|i| (i, i)).collect();
    for c in 0..mesh.num_cells() {
        let d = dofs.cell_dofs(mesh, c);
        for &[i, j] in mesh.cell_type(c).couplings() {
            let (a, b) = (d[i as usize], d[j as usize]);
            pairs.push((a, b));
            pairs.push((b, a));
        }
    }
    CsrMatrix::from_pattern(dofs.n, dofs.n, pairs)
}

/// Sets K_ii = −Σ_{j≠i} K_ij, so constants are exactly in the null space of every row.
pub(crate) fn close_diagonal(k: &mut CsrMatrix) {
    for i in 0..k.nrows {
        let r = k.row_ptr[i] as usize..k.row_ptr[i + 1] as usize;
        let mut s = 0.0;
        let mut diag = usize::MAX;
        for p in r {
            if k.cols[p] as usize == i {
                diag = p;
            } else {
                s += k.vals[p];
            }
        }
        k.vals[diag] = -s;
    }
}

/// K_ij = ∫∇φ_i·∇φ_j, summed cell by cell over each cell's couplings (for a triangle, edge ij
/// gets −½ cot of the opposite angle). Fills the values of `k`, whose pattern is
/// `stiffness_pattern(mesh, dofs)`.
pub(crate) fn stiffness(k: &mut CsrMatrix, mesh: &Mesh, dofs: &Dofs) {
    k.vals.iter_mut().for_each(|v| *v = 0.0);
    let mut local = [0.0; 28];
    for c in 0..mesh.num_cells() {
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

/// The spring analogy: graph Laplacian with weight 1/L² on every edge of the cells (never a
/// face or body diagonal). An edge seen from several cells, or twice through a link, is one
/// spring. Fills `k` as `stiffness` does.
pub(crate) fn spring_stiffness(k: &mut CsrMatrix, mesh: &Mesh, dofs: &Dofs) {
    k.vals.iter_mut().for_each(|v| *v = 0.0);
    let mut seen = vec![false; k.nnz()];
    for c in 0..mesh.num_cells() {
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
        let d = dofs.cell_dofs(mesh, c);
        cell_points(mesh, c).lumped_mass(&mut local);
        for (k, &i) in d.iter().enumerate() {
            v[i as usize] += local[k];
        }
    }
    v
}
