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

/// An entry of K that fills no slot of the map (the diagonal, a general cell's coupling, a
/// coupling of an unknown with itself).
const NO_SLOT: u32 = u32::MAX;

/// K's pattern on the unknowns (with the diagonal, values zero: the couplings of every cell)
/// and, with `map`, the scatter map into it, from one pass over the cells' couplings: each entry
/// carries the slot of the map it fills (`2 × coupling + direction`), so its position within its
/// row is known where the row is sorted and its duplicates merged, and no row is searched. The
/// pattern is that of sorting the couplings' pairs row by row, the map that of searching the rows
/// for them (`Scatter::new`), bitwise. Past 2^31 couplings the slots do not fit: the map comes
/// from the search.
pub(crate) fn pattern_and_scatter(mesh: &Mesh, dofs: &Dofs, map: bool) -> (CsrMatrix, Scatter) {
    let n = dofs.n;
    let couplings: usize = (0..mesh.num_cells()).filter(|&c| !mesh.cell_type(c).is_general()).map(|c| mesh.cell_type(c).couplings().len()).sum();
    let slots = map && u32::try_from(2 * couplings).is_ok_and(|s| s < NO_SLOT);
    let mut general = Vec::new();
    // Calls `f(row, column, slot)` for every entry of the pattern, duplicates included.
    let mut each = |f: &mut dyn FnMut(u32, u32, u32)| {
        (0..n as u32).for_each(|i| f(i, i, NO_SLOT));
        let mut at = 0u32;
        for c in 0..mesh.num_cells() {
            let ty = mesh.cell_type(c);
            if ty.is_general() {
                general.clear();
                super::general::pattern(mesh, dofs, c, &mut general);
                general.iter().for_each(|&(a, b)| f(a, b, NO_SLOT));
                continue;
            }
            let d = dofs.cell_dofs(mesh, c);
            for &[i, j] in ty.couplings() {
                let (a, b) = (d[i as usize], d[j as usize]);
                let (ab, ba) = if slots && a != b { (2 * at, 2 * at + 1) } else { (NO_SLOT, NO_SLOT) };
                f(a, b, ab);
                f(b, a, ba);
                at = at.wrapping_add(1);
            }
        }
    };
    // The entries bucketed by row, each its column and slot in one key.
    let mut start = vec![0usize; n + 1];
    each(&mut |i, _, _| start[i as usize + 1] += 1);
    for i in 0..n {
        start[i + 1] += start[i];
    }
    offset(start[n]);
    let mut keys = vec![0u64; start[n]];
    let mut next = start.clone();
    each(&mut |i, j, slot| {
        keys[next[i as usize]] = (u64::from(j) << 32) | u64::from(slot);
        next[i as usize] += 1;
    });
    drop(next);
    let mut within_row = vec![SEARCH; if slots { 2 * couplings } else { 0 }];
    let mut row_ptr = vec![0u32; n + 1];
    let mut cols: Vec<u32> = Vec::new();
    // Per column: the row that last met it (`u32::MAX` none yet), then its position in that
    // row. A row's distinct columns are collected by the mark and sorted (a row of a hexahedral
    // mesh has 27 of its 57 entries), then each entry's slot takes its column's position.
    let mut seen = vec![u32::MAX; n];
    let mut pos = vec![0u32; n];
    for i in 0..n {
        let row = &keys[start[i]..start[i + 1]];
        let first = cols.len();
        for &key in row {
            let j = (key >> 32) as u32;
            if seen[j as usize] != i as u32 {
                seen[j as usize] = i as u32;
                cols.push(j);
            }
        }
        cols[first..].sort_unstable();
        for (p, &j) in cols[first..].iter().enumerate() {
            pos[j as usize] = offset(p);
        }
        for &key in row {
            let (j, slot) = ((key >> 32) as u32, key as u32);
            if slot != NO_SLOT {
                within_row[slot as usize] = u8::try_from(pos[j as usize]).unwrap_or(SEARCH);
            }
        }
        row_ptr[i + 1] = offset(cols.len());
    }
    drop(keys);
    cols.shrink_to_fit();
    let vals = vec![0.0; cols.len()];
    let k = CsrMatrix { nrows: n, ncols: n, row_ptr, cols, vals };
    let scatter = match (map, slots) {
        (true, false) => Scatter::new(&k, mesh, dofs),
        _ => Scatter { within_row },
    };
    (k, scatter)
}
