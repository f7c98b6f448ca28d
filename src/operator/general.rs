//! The element matrices of general cells (polygons and polyhedra) added into K and V: their
//! corners are more than a fixed cell's and their stiffness couples every pair of them
//! (`geometry::GeneralPoints::element`), so they are evaluated and added one cell at a time.

use crate::bc::Dofs;
use crate::geometry::dist2;
use crate::sparse::CsrMatrix;
use crate::Mesh;

/// The couplings of general cell `c`, both ways: every pair of its corners (the pattern of
/// `scatter::pattern_and_scatter` takes a general cell's corners as its rows' columns; the tests
/// compare it with these pairs).
#[cfg(test)]
pub(super) fn pattern(mesh: &Mesh, dofs: &Dofs, c: usize, pairs: &mut Vec<(u32, u32)>) {
    let d = dofs.general_cell_dofs(mesh, c);
    for (i, &a) in d.iter().enumerate() {
        for &b in &d[i + 1..] {
            pairs.push((a, b));
            pairs.push((b, a));
        }
    }
}

/// Adds general cell `c`'s stiffness into `k` (its pattern from `pattern`) when given, its
/// lumped mass into `v` when given; the diagonal of `k` is left to `close_diagonal`.
pub(super) fn add(k: Option<&mut CsrMatrix>, v: Option<&mut [f64]>, mesh: &Mesh, dofs: &Dofs, c: usize) {
    let g = mesh.general_points(mesh.coords(), c);
    let n = g.num_corners();
    let d = dofs.general_cell_dofs(mesh, c);
    let mut kl = k.is_some().then(|| vec![0.0; n * n]);
    let mut ml = v.is_some().then(|| vec![0.0; n]);
    g.element(kl.as_deref_mut(), ml.as_deref_mut());
    if let (Some(k), Some(kl)) = (k, kl) {
        for i in 0..n {
            for j in i + 1..n {
                let (di, dj) = (d[i] as usize, d[j] as usize);
                if di != dj {
                    let a = k.find(di, dj).expect("coupling in pattern");
                    k.vals[a] += kl[i * n + j];
                    let b = k.find(dj, di).expect("coupling in pattern");
                    k.vals[b] += kl[i * n + j];
                }
            }
        }
    }
    if let (Some(v), Some(ml)) = (v, ml) {
        for (q, &i) in d.iter().enumerate() {
            v[i as usize] += ml[q];
        }
    }
}

/// The springs (weight 1/L²) of general cell `c`'s edges, each set once (`seen`), as
/// `spring_stiffness` sets those of the fixed cells.
pub(super) fn add_springs(k: &mut CsrMatrix, seen: &mut [bool], mesh: &Mesh, dofs: &Dofs, c: usize) {
    let g = mesh.general_points(mesh.coords(), c);
    let d = dofs.general_cell_dofs(mesh, c);
    let x = |k: usize| {
        let v = mesh.cell(c)[k] as usize;
        crate::geometry::padded(mesh.point(v))
    };
    for [i, j] in g.edges() {
        let (di, dj) = (d[i] as usize, d[j] as usize);
        let p = k.find(di, dj).expect("edge in pattern");
        if di == dj || seen[p] {
            continue;
        }
        let w = 1.0 / dist2(&x(i), &x(j));
        let q = k.find(dj, di).expect("edge in pattern");
        seen[p] = true;
        seen[q] = true;
        k.vals[p] = -w;
        k.vals[q] = -w;
    }
}
