//! Assembly of K (cotangent or spring weights) and the lumped mass V on the unknowns.
//!
//! The pattern is built once per level; re-evaluating on a moved mesh only refills its values,
//! serially in cell order, so sums never depend on thread count.

use crate::bc::Dofs;
use crate::sparse::CsrMatrix;
use crate::Mesh;

/// Sparsity of K on the unknowns (with the diagonal), values zero.
pub fn stiffness_pattern(mesh: &Mesh, dofs: &Dofs) -> CsrMatrix {
    let mut pairs: Vec<(u32, u32)> = (0..dofs.n as u32).map(|i| (i, i)).collect();
    for c in 0..mesh.num_cells() {
        let d = dofs.cell_dofs(mesh, c);
        for k in 0..3 {
            let (a, b) = (d[k], d[(k + 1) % 3]);
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

/// K_ij = ∫∇φ_i·∇φ_j: per triangle, edge ij gets −½ cot of the opposite angle. Fills the values
/// of `k`, whose pattern is `stiffness_pattern(mesh, dofs)`.
pub fn stiffness(k: &mut CsrMatrix, mesh: &Mesh, dofs: &Dofs) {
    k.vals.iter_mut().for_each(|v| *v = 0.0);
    for (c, t) in mesh.cells().iter().enumerate() {
        let d = dofs.cell_dofs(mesh, c);
        let p = t.map(|v| mesh.coords()[v as usize]);
        let twice_area = (p[1] - p[0]).perp_dot(p[2] - p[0]);
        for m in 0..3 {
            // Edge (i, j) opposite vertex o: ½ cot θ_o = (e_oi · e_oj) / (2 · 2A).
            let (i, j, o) = (m, (m + 1) % 3, (m + 2) % 3);
            let w = 0.5 * (p[i] - p[o]).dot(p[j] - p[o]) / twice_area;
            let (di, dj) = (d[i] as usize, d[j] as usize);
            if di != dj {
                let a = k.find(di, dj).expect("edge in pattern");
                k.vals[a] -= w;
                let b = k.find(dj, di).expect("edge in pattern");
                k.vals[b] -= w;
            }
        }
    }
    close_diagonal(k);
}

/// The spring analogy: graph Laplacian with weight 1/L² on every mesh edge. An edge seen from
/// both its cells, or twice through a link, is one spring. Fills `k` as `stiffness` does.
pub fn spring_stiffness(k: &mut CsrMatrix, mesh: &Mesh, dofs: &Dofs) {
    k.vals.iter_mut().for_each(|v| *v = 0.0);
    let mut seen = vec![false; k.nnz()];
    let coords = mesh.coords();
    for (c, t) in mesh.cells().iter().enumerate() {
        let d = dofs.cell_dofs(mesh, c);
        for m in 0..3 {
            let (i, j) = (m, (m + 1) % 3);
            let (di, dj) = (d[i] as usize, d[j] as usize);
            let p = k.find(di, dj).expect("edge in pattern");
            if di == dj || seen[p] {
                continue;
            }
            let w = 1.0 / coords[t[i] as usize].distance_squared(coords[t[j] as usize]);
            let q = k.find(dj, di).expect("edge in pattern");
            seen[p] = true;
            seen[q] = true;
            k.vals[p] = -w;
            k.vals[q] = -w;
        }
    }
    close_diagonal(k);
}

/// V_i = ⅓ of the area of the triangles around unknown i.
pub fn lumped_mass(mesh: &Mesh, dofs: &Dofs) -> Vec<f64> {
    let mut v = vec![0.0; dofs.n];
    for (c, t) in mesh.cells().iter().enumerate() {
        let d = dofs.cell_dofs(mesh, c);
        let p = t.map(|i| mesh.coords()[i as usize]);
        let third = (p[1] - p[0]).perp_dot(p[2] - p[0]) / 6.0;
        for i in d {
            v[i as usize] += third;
        }
    }
    v
}
