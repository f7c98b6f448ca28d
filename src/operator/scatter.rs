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
use crate::sparse::{offset, CsrMatrix};
use crate::geometry::CellType;
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
    /// The map of `mesh`'s cells into `k`, whose pattern is `stiffness_pattern(mesh, dofs)`, by
    /// a search of K's rows (`pattern_and_scatter` gives it without one where its slots fit).
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

    /// The positions within their rows of the `n` couplings from `at` on (two bytes each, as
    /// `positions` reads them) when the map holds every one of them: no row is searched and no
    /// coupling is of an unknown with itself (the map marks those too). None otherwise.
    #[inline(always)]
    pub(crate) fn within_rows(&self, at: usize, n: usize) -> Option<&[u8]> {
        let b = &self.within_row[2 * at..2 * (at + n)];
        b.iter().fold(true, |all, &o| all & (o != SEARCH)).then_some(b)
    }

    /// The bytes the map holds for coupling `at` (its positions within the two rows), for tests.
    #[cfg(test)]
    pub(crate) fn slots(&self, at: usize) -> [u8; 2] {
        [self.within_row[2 * at], self.within_row[2 * at + 1]]
    }

    /// The couplings the map holds.
    pub(crate) fn len(&self) -> usize {
        self.within_row.len() / 2
    }
}

/// Asks the processor to bring into cache the rows of K of the unknowns `d` (a cell's corners),
/// a 64-byte line at a time: issued a cell ahead, their loads overlap that cell's element kernel
/// instead of stalling its adds. The rows' bounds are all it reads (not the map's bytes per
/// coupling), so it costs a few instructions a corner. Changes no value.
#[inline(always)]
pub(crate) fn prefetch_rows(k: &CsrMatrix, d: &[u32]) {
    #[cfg(target_arch = "x86_64")]
    for &i in d {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let (Some(&a), Some(&b)) = (k.row_ptr.get(i as usize), k.row_ptr.get(i as usize + 1)) else { continue };
        let (a, b) = (a as usize, (b as usize).min(k.vals.len()));
        // Eight values a line; the row's last value's line too, where the row starts within one.
        for p in (a..b).step_by(8).chain((a < b).then(|| b - 1)) {
            // SAFETY: x86-64 always has SSE; a prefetch reads nothing (and `p` is within
            // `k.vals`).
            unsafe { _mm_prefetch::<_MM_HINT_T0>(k.vals[p..].as_ptr().cast()) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (k, d);
}

/// Per corner of a fixed cell type, the couplings that hold it: (coupling, other corner, which
/// of the coupling's two bytes is the corner's row), the type's coupling order.
type CornerCouplings = Vec<Vec<(usize, usize, usize)>>;

/// `CornerCouplings` of cell type `ty`.
fn corner_couplings(ty: CellType) -> CornerCouplings {
    let mut at = vec![Vec::new(); ty.num_corners()];
    for (m, &[q, r]) in ty.couplings().iter().enumerate() {
        at[q as usize].push((m, r as usize, 0));
        at[r as usize].push((m, q as usize, 1));
    }
    at
}

/// K's pattern on the unknowns (with the diagonal, values zero: the couplings of every cell)
/// and, with `map`, the scatter map into it, row by row from the cells around each unknown:
/// every cell couples all its corners (a fixed type's couplings are all its pairs of corners,
/// a general cell's too), so a row's columns are its cells' corners, collected by a mark and
/// sorted; then each coupling of those cells at the row's unknown takes its column's position.
/// Only the cells' corners are bucketed by unknown (one entry a corner, not the couplings' two
/// entries each). The pattern is that of sorting the couplings' pairs row by row, the map that
/// of searching the rows for them (`Scatter::new`), bitwise. Past 2^31 couplings the slots do
/// not fit: the map comes from the search.
pub(crate) fn pattern_and_scatter(mesh: &Mesh, dofs: &Dofs, map: bool) -> (CsrMatrix, Scatter) {
    let n = dofs.n;
    let cells = mesh.num_cells();
    // The fixed types, and the couplings at each corner of each (`CornerCouplings`).
    const TYPES: [CellType; 6] =
        [CellType::Triangle, CellType::Quad, CellType::Tetra, CellType::Hexahedron, CellType::Wedge, CellType::Pyramid];
    let tables: Vec<CornerCouplings> = TYPES.iter().map(|&ty| corner_couplings(ty)).collect();
    // Each cell's unknowns (CSR), its type's position in `TYPES` (`GENERAL` for a general cell)
    // and the index of its first coupling in the map.
    const GENERAL: u8 = u8::MAX;
    let (mut corner_start, mut corners) = (Vec::with_capacity(cells + 1), Vec::new());
    let (mut first_coupling, mut kind) = (Vec::with_capacity(cells), Vec::with_capacity(cells));
    corner_start.push(0usize);
    let mut couplings = 0usize;
    for c in 0..cells {
        let ty = mesh.cell_type(c);
        first_coupling.push(couplings);
        kind.push(TYPES.iter().position(|&t| t == ty).map_or(GENERAL, |t| t as u8));
        if ty.is_general() {
            corners.extend(dofs.general_cell_dofs(mesh, c));
        } else {
            corners.extend_from_slice(&dofs.cell_dofs(mesh, c));
            couplings += ty.couplings().len();
        }
        corner_start.push(corners.len());
    }
    let slots = map && u32::try_from(2 * couplings).is_ok_and(|s| s < u32::MAX);
    let corners_of = |c: usize| &corners[corner_start[c]..corner_start[c + 1]];
    // Each corner of the cells around each unknown, ascending (a cell once per corner the
    // unknown holds: linked vertices), as the cell and the corner's index in it, bucketed by a
    // count.
    let mut start = vec![0usize; n + 1];
    corners.iter().for_each(|&i| start[i as usize + 1] += 1);
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut around = vec![(0u32, 0u32); start[n]];
    let mut next = start.clone();
    for c in 0..cells {
        for (q, &i) in corners_of(c).iter().enumerate() {
            around[next[i as usize]] = (offset(c), offset(q));
            next[i as usize] += 1;
        }
    }
    drop(next);
    let mut within_row = vec![SEARCH; if slots { 2 * couplings } else { 0 }];
    let mut row_ptr = vec![0u32; n + 1];
    let mut cols: Vec<u32> = Vec::new();
    // Per column: the row that last met it (`u32::MAX` none yet), then its position in that row.
    let mut seen = vec![u32::MAX; n];
    let mut pos = vec![0u32; n];
    for i in 0..n {
        let row = i as u32;
        let here = &around[start[i]..start[i + 1]];
        let first = cols.len();
        seen[i] = row;
        cols.push(row);
        for &(c, _) in here {
            for &j in corners_of(c as usize) {
                if seen[j as usize] != row {
                    seen[j as usize] = row;
                    cols.push(j);
                }
            }
        }
        cols[first..].sort_unstable();
        for (p, &j) in cols[first..].iter().enumerate() {
            pos[j as usize] = offset(p);
        }
        row_ptr[i + 1] = offset(cols.len());
        if !slots {
            continue;
        }
        for &(c, q) in here {
            let c = c as usize;
            if kind[c] == GENERAL {
                continue;
            }
            let d = corners_of(c);
            for &(m, r, side) in &tables[kind[c] as usize][q as usize] {
                let b = d[r];
                if b != row {
                    within_row[2 * (first_coupling[c] + m) + side] = u8::try_from(pos[b as usize]).unwrap_or(SEARCH);
                }
            }
        }
    }
    drop((around, corners));
    cols.shrink_to_fit();
    let vals = vec![0.0; cols.len()];
    let k = CsrMatrix { nrows: n, ncols: n, row_ptr, cols, vals };
    let scatter = match (map, slots) {
        (true, false) => Scatter::new(&k, mesh, dofs),
        _ => Scatter { within_row },
    };
    (k, scatter)
}
