//! Where the element matrices add into K: computed once with K's pattern, so a re-evaluation on
//! a moved mesh adds each coupling by index instead of searching its row for the column.
//!
//! Per coupling of every fixed-type cell, in cell order and then in the cell type's coupling
//! order (`CellType::couplings`), two bytes: the positions of K_ij and K_ji within their rows.
//! One byte per entry keeps the map small (a hexahedron's 28 couplings take 56 bytes); an entry
//! at position 255 or beyond in a long row (a vertex with hundreds of neighbours) is marked and
//! found by the row's binary search, as without the map. General cells (polygons, polyhedra)
//! are added by `general.rs` with the search and take no room here.

use crate::bc::Dofs;
use crate::sparse::CsrMatrix;
use crate::Mesh;

/// A position the map leaves to the row's binary search.
const SEARCH: u8 = u8::MAX;

/// The positions of the fixed-type cells' couplings in K's rows (see the module's comment).
#[derive(Clone, Default)]
pub(crate) struct Scatter {
    /// Two per coupling: K_ij's position in row i, then K_ji's in row j.
    within_row: Vec<u8>,
}

impl Scatter {
    /// The map of `mesh`'s cells into `k`, whose pattern is `stiffness_pattern(mesh, dofs)`.
    pub(crate) fn new(k: &CsrMatrix, mesh: &Mesh, dofs: &Dofs) -> Scatter {
        let in_row = |i: u32, j: u32| -> u8 {
            let (i, j) = (i as usize, j as usize);
            match k.find(i, j) {
                Some(p) if i != j => u8::try_from(p - k.row_ptr[i] as usize).unwrap_or(SEARCH),
                _ => SEARCH,
            }
        };
        let mut within_row = Vec::new();
        for c in 0..mesh.num_cells() {
            let ty = mesh.cell_type(c);
            if ty.is_general() {
                continue;
            }
            let d = dofs.cell_dofs(mesh, c);
            for &[i, j] in ty.couplings() {
                let (a, b) = (d[i as usize], d[j as usize]);
                within_row.extend([in_row(a, b), in_row(b, a)]);
            }
        }
        within_row.shrink_to_fit();
        Scatter { within_row }
    }

    /// A map that leaves every position to the search (`len` couplings): the assembly without
    /// the map, for tests.
    #[cfg(test)]
    pub(crate) fn searching(len: usize) -> Scatter {
        Scatter { within_row: vec![SEARCH; 2 * len] }
    }

    /// The positions in `k.vals` of K_ij and K_ji for coupling `at` (counted over the cells in
    /// order) between the distinct unknowns `i` and `j`.
    #[inline]
    pub(crate) fn positions(&self, k: &CsrMatrix, at: usize, i: usize, j: usize) -> (usize, usize) {
        let slot = |o: u8, r: usize, col: usize| match o {
            SEARCH => k.find(r, col).expect("coupling in pattern"),
            o => k.row_ptr[r] as usize + o as usize,
        };
        (slot(self.within_row[2 * at], i, j), slot(self.within_row[2 * at + 1], j, i))
    }

    /// The couplings the map holds.
    pub(crate) fn len(&self) -> usize {
        self.within_row.len() / 2
    }
}
