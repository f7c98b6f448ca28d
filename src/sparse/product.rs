//! Sparse products, row by row (each row of the result from one row of the left factor), so
//! they are deterministic and parallel like every other operation on `CsrMatrix`.

use super::{offset, row_blocks, CsrMatrix};
use rayon::prelude::*;

/// Rows per task when filling a product's arrays.
const PRODUCT_BLOCK: usize = 1024;

/// Sums scaled sparse rows into one row: entries in order of first appearance, each the sum of
/// its products in the order added; `finish` emits them by ascending column.
struct RowSum {
    slot: Vec<usize>,
    cols: Vec<u32>,
    vals: Vec<f64>,
}

impl RowSum {
    fn new(ncols: usize) -> Self {
        RowSum { slot: vec![usize::MAX; ncols], cols: Vec::new(), vals: Vec::new() }
    }

    /// Adds x times the row (cols, vals).
    fn add(&mut self, x: f64, (cols, vals): (&[u32], &[f64])) {
        for (&j, &y) in cols.iter().zip(vals) {
            let s = &mut self.slot[j as usize];
            if *s == usize::MAX {
                *s = self.cols.len();
                self.cols.push(j);
                self.vals.push(0.0);
            }
            self.vals[*s] += x * y;
        }
    }

    /// Adds x times the row (cols, vals) scaled by w, each product x (w y).
    fn add_scaled(&mut self, x: f64, w: f64, (cols, vals): (&[u32], &[f64])) {
        for (&j, &y) in cols.iter().zip(vals) {
            let s = &mut self.slot[j as usize];
            if *s == usize::MAX {
                *s = self.cols.len();
                self.cols.push(j);
                self.vals.push(0.0);
            }
            self.vals[*s] += x * (w * y);
        }
    }

    /// Appends the sum to `cols` and `vals`, columns ascending, and starts a new one: the
    /// columns (each once) sorted as they are, each value then read through its column's slot.
    fn finish(&mut self, cols: &mut Vec<u32>, vals: &mut Vec<f64>) {
        let RowSum { slot, cols: c, vals: v } = self;
        let start = cols.len();
        cols.extend_from_slice(c);
        cols[start..].sort_unstable();
        vals.extend(cols[start..].iter().map(|&j| v[slot[j as usize]]));
        c.iter().for_each(|&j| slot[j as usize] = usize::MAX);
        c.clear();
        v.clear();
    }

    /// Appends row i of A B to `cols` and `vals`.
    fn product_row(&mut self, a: &CsrMatrix, b: &CsrMatrix, i: usize, cols: &mut Vec<u32>, vals: &mut Vec<f64>) {
        let (ac, av) = a.row(i);
        for (&k, &x) in ac.iter().zip(av) {
            self.add(x, b.row(k as usize));
        }
        self.finish(cols, vals);
    }
}

/// A matrix whose rows are computed independently (appended by `row(state, i, cols, vals)` to
/// its block's arrays), so it is deterministic and parallel. Each block of rows is formed once
/// into arrays of its own, which are moved into the result one after the other, each freed once
/// moved: about the result's memory at once, no per-row vectors (they took twice the result's
/// memory) and no counting pass that would form every row twice.
fn by_rows<S>(
    nrows: usize,
    ncols: usize,
    init: impl Fn() -> S + Sync + Send,
    row: impl Fn(&mut S, usize, &mut Vec<u32>, &mut Vec<f64>) + Sync + Send,
) -> CsrMatrix {
    let blocks: Vec<(Vec<u32>, Vec<u32>, Vec<f64>)> = (0..nrows.div_ceil(PRODUCT_BLOCK))
        .into_par_iter()
        .map_init(init, |s, b| {
            let rows = b * PRODUCT_BLOCK..((b + 1) * PRODUCT_BLOCK).min(nrows);
            let (mut lens, mut out_c, mut out_v) = (Vec::with_capacity(rows.len()), Vec::new(), Vec::new());
            for i in rows {
                let before = out_c.len();
                row(s, i, &mut out_c, &mut out_v);
                lens.push(offset(out_c.len() - before));
            }
            (lens, out_c, out_v)
        })
        .collect();
    let nnz = blocks.iter().map(|b| b.1.len()).sum();
    let mut row_ptr = Vec::with_capacity(nrows + 1);
    row_ptr.push(0u32);
    let (mut cols, mut vals) = (Vec::with_capacity(nnz), Vec::with_capacity(nnz));
    // The running sum in usize, each checked into a row pointer (`offset`).
    let mut at = 0usize;
    for (lens, c, v) in blocks {
        for len in lens {
            at += len as usize;
            row_ptr.push(offset(at));
        }
        cols.extend_from_slice(&c);
        vals.extend_from_slice(&v);
    }
    debug_assert_eq!(at, nnz);
    CsrMatrix { nrows, ncols, row_ptr, cols, vals }
}

/// C = A B, row by row (each row of C from one row of A). Column indices come out sorted.
pub fn matmul(a: &CsrMatrix, b: &CsrMatrix) -> CsrMatrix {
    assert_eq!(a.ncols, b.nrows, "matmul: A has {} columns, B has {} rows", a.ncols, b.nrows);
    by_rows(a.nrows, b.ncols, || RowSum::new(b.ncols), |sum, i, c, v| sum.product_row(a, b, i, c, v))
}

/// R K P, bitwise `matmul(r, &matmul(k, p))` but without holding K P (the largest matrix of a
/// Galerkin hierarchy): its rows are formed where R uses them and kept until the last row of R
/// that uses them (`KpRows::drop_used`), so a row used by several rows of R in one task is
/// formed once.
pub fn triple_product(r: &CsrMatrix, k: &CsrMatrix, p: &CsrMatrix) -> CsrMatrix {
    assert_eq!(r.ncols, k.nrows, "triple_product: R has {} columns, K has {} rows", r.ncols, k.nrows);
    assert_eq!(k.ncols, p.nrows, "triple_product: K has {} columns, P has {} rows", k.ncols, p.nrows);
    let last = last_users(r);
    let init = || (KpRows::new(k.nrows, p.ncols), RowSum::new(p.ncols));
    by_rows(r.nrows, p.ncols, init, |(kp, outer), j, c, v| {
        let (rc, rv) = r.row(j);
        for (&i, &x) in rc.iter().zip(rv) {
            let e = kp.form(k, p, i as usize);
            outer.add(x, (&kp.cols[e.clone()], &kp.vals[e]));
        }
        kp.drop_used(j, &last);
        outer.finish(c, v);
    })
}

/// Per column i of R, the last row of R holding it (0 for a column no row holds).
fn last_users(r: &CsrMatrix) -> Vec<u32> {
    let mut last = vec![0u32; r.ncols];
    for j in 0..r.nrows {
        r.row(j).0.iter().for_each(|&i| last[i as usize] = offset(j));
    }
    last
}

/// Gᵀ W G for W = diag(`w`), given G and its transpose `gt`: bitwise `triple_product(gt, W, g)`
/// with W stored as a diagonal matrix, without forming the rows of W G. Each entry is the sum
/// over G's rows i, ascending, of g_ij (w_i g_im), as `triple_product` sums it: there a row of
/// W G holds 0 + w_i g_im, which differs from w_i g_im only in the sign of a zero, and a zero
/// added to a sum that starts at +0 leaves it as it is.
pub fn weighted_gram(gt: &CsrMatrix, w: &[f64], g: &CsrMatrix) -> CsrMatrix {
    assert!(gt.ncols == g.nrows && w.len() == g.nrows, "weighted_gram: Gᵀ, W and G do not fit");
    by_rows(gt.nrows, g.ncols, || RowSum::new(g.ncols), |sum, j, c, v| {
        let (gc, gv) = gt.row(j);
        for (&i, &x) in gc.iter().zip(gv) {
            sum.add_scaled(x, w[i as usize], g.row(i as usize));
        }
        sum.finish(c, v);
    })
}

/// Rows of K P formed for neighbouring rows of R K P, each once however many of them use it (a
/// fine row is used by every coarse unknown it interpolates from) until they are forgotten:
/// `at[i]` is the position of K P's row i in `ptr` (`NOT_FORMED` for rows not formed).
struct KpRows {
    at: Vec<u32>,
    formed: Vec<u32>,
    ptr: Vec<usize>,
    cols: Vec<u32>,
    vals: Vec<f64>,
    /// Per column of P: its position in the row of K P being formed (`NOT_FORMED` when absent).
    slot: Vec<u32>,
    /// Per column of P: its position in the row of the result being filled.
    pos: Vec<u32>,
    /// The entries past which `drop_used` forgets the rows no longer used.
    limit: usize,
}

const NOT_FORMED: u32 = u32::MAX;

/// Most entries of K P a task keeps formed (a few megabytes); past them `triple_product` forgets
/// the rows no later row of R uses, and keeps at least twice what stays.
const KP_KEPT: usize = 1 << 18;

impl KpRows {
    fn new(k_rows: usize, p_cols: usize) -> Self {
        KpRows {
            at: vec![NOT_FORMED; k_rows],
            formed: Vec::new(),
            ptr: vec![0],
            cols: Vec::new(),
            vals: Vec::new(),
            slot: vec![NOT_FORMED; p_cols],
            pos: vec![0; p_cols],
            limit: KP_KEPT,
        }
    }

    /// Forms row i of K P unless the block has: its columns in order of first appearance,
    /// each the sum of its products in the order of K's and P's rows from zero, as `RowSum`
    /// sums them. Returns its range in `cols` and `vals`.
    fn form(&mut self, k: &CsrMatrix, p: &CsrMatrix, i: usize) -> std::ops::Range<usize> {
        if self.at[i] == NOT_FORMED {
            self.at[i] = offset(self.formed.len());
            self.formed.push(offset(i));
            let start = self.cols.len();
            let (kc, kv) = k.row(i);
            // Room for every product, so the loop writes into fixed slices (no growth, the
            // slices' starts kept in registers); cut to the row's columns after it.
            let most: usize = kc.iter().map(|&l| (p.row_ptr[l as usize + 1] - p.row_ptr[l as usize]) as usize).sum();
            self.cols.resize(start + most, 0);
            self.vals.resize(start + most, 0.0);
            let (cols, vals, slot) = (&mut self.cols[start..], &mut self.vals[start..], &mut self.slot);
            let mut len = 0;
            for (&l, &y) in kc.iter().zip(kv) {
                let (pc, pv) = p.row(l as usize);
                for (&m, &z) in pc.iter().zip(pv) {
                    let s = &mut slot[m as usize];
                    if *s == NOT_FORMED {
                        *s = offset(len);
                        cols[len] = m;
                        len += 1;
                    }
                    vals[*s as usize] += y * z;
                }
            }
            cols[..len].iter().for_each(|&m| slot[m as usize] = NOT_FORMED);
            self.cols.truncate(start + len);
            self.vals.truncate(start + len);
            self.ptr.push(self.cols.len());
        }
        let f = self.at[i] as usize;
        self.ptr[f]..self.ptr[f + 1]
    }

    /// Forgets the rows formed when they hold more than `KP_KEPT` entries (the rows are formed
    /// the same whenever they are, so when they are forgotten changes no value).
    fn bound(&mut self) {
        if self.cols.len() > KP_KEPT {
            self.clear();
        }
    }

    /// Once the rows formed hold more than `limit` entries, forgets those no row of R after
    /// row `j` uses (`last`: per row of K P, the last row of R that uses it), keeping the others
    /// in the order they were formed; `limit` grows to twice what stays, so the rows still in
    /// use are moved a bounded number of times. A task takes the rows of R in ascending order,
    /// so a row is formed once while its users are in one task (the rows are formed the same
    /// whenever they are, so which are kept changes no value).
    fn drop_used(&mut self, j: usize, last: &[u32]) {
        if self.cols.len() <= self.limit {
            return;
        }
        let (mut kept, mut to) = (0, 0);
        for f in 0..self.formed.len() {
            let i = self.formed[f] as usize;
            let (a, b) = (self.ptr[f], self.ptr[f + 1]);
            if last[i] as usize > j {
                self.cols.copy_within(a..b, to);
                self.vals.copy_within(a..b, to);
                self.formed[kept] = offset(i);
                self.at[i] = offset(kept);
                kept += 1;
                to += b - a;
                self.ptr[kept] = to;
            } else {
                self.at[i] = NOT_FORMED;
            }
        }
        self.formed.truncate(kept);
        self.ptr.truncate(kept + 1);
        self.cols.truncate(to);
        self.vals.truncate(to);
        self.limit = KP_KEPT.max(2 * to);
    }

    /// Forgets the rows formed.
    fn clear(&mut self) {
        self.formed.iter().for_each(|&i| self.at[i as usize] = NOT_FORMED);
        self.formed.clear();
        self.ptr.truncate(1);
        self.cols.clear();
        self.vals.clear();
    }
}

/// The values of R K P into `c`, whose pattern is `triple_product(r, k, p)`'s (the numeric phase
/// on a stored symbolic one: a moved mesh changes the values of K and P, not their patterns).
/// Bitwise `triple_product(r, k, p)`: each entry of a row of K P and of C is the sum of the same
/// products in the same order, from the same zero. Each block of C's rows forms the rows of
/// K P it uses once (`KpRows`), so only the rows shared with a neighbouring block are formed twice.
pub fn triple_product_values(r: &CsrMatrix, k: &CsrMatrix, p: &CsrMatrix, c: &mut CsrMatrix) {
    assert_eq!((c.nrows, c.ncols), (r.nrows, p.ncols), "triple_product_values: C is not R K P's shape");
    let row_ptr = &c.row_ptr;
    let cols = &c.cols;
    // Blocks of rows with their disjoint parts of vals.
    let blocks = row_blocks(row_ptr, &mut c.vals, PRODUCT_BLOCK);
    let init = || KpRows::new(k.nrows, p.ncols);
    blocks.into_par_iter().for_each_init(init, |kp, (rows, out)| {
        let base = row_ptr[rows.start] as usize;
        for j in rows {
            let (a, b) = (row_ptr[j] as usize, row_ptr[j + 1] as usize);
            for (q, &m) in cols[a..b].iter().enumerate() {
                kp.pos[m as usize] = q as u32;
            }
            let row = &mut out[a - base..b - base];
            row.iter_mut().for_each(|v| *v = 0.0);
            let (rc, rv) = r.row(j);
            for (&i, &x) in rc.iter().zip(rv) {
                // Row i of K P, then x times it into row j (every column of it is in row j's
                // pattern).
                let e = kp.form(k, p, i as usize);
                for (&m, &y) in kp.cols[e.clone()].iter().zip(&kp.vals[e]) {
                    row[kp.pos[m as usize] as usize] += x * y;
                }
            }
            kp.bound();
        }
        kp.clear();
    });
}

/// Whether two matrices have the same shape and pattern (their values aside).
pub fn same_pattern(a: &CsrMatrix, b: &CsrMatrix) -> bool {
    a.nrows == b.nrows && a.ncols == b.ncols && a.row_ptr == b.row_ptr && a.cols == b.cols
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triple_product_is_two_products_bitwise() {
        let m = |nrows: usize, ncols: usize, seed: u32| {
            let t = (0..nrows as u32)
                .flat_map(|i| {
                    (0..3).map(move |k| (i, (i * 7 + k * 5 + seed) % ncols as u32, 1.0 / (i + k + seed) as f64))
                })
                .collect();
            CsrMatrix::from_triplets(nrows, ncols, t)
        };
        let (r, k, p) = (m(4, 9, 1), m(9, 9, 2), m(9, 4, 3));
        let want = matmul(&r, &matmul(&k, &p));
        assert_eq!(triple_product(&r, &k, &p), want);
        assert!(want.nnz() > 4);
    }

    /// Rows of K P forgotten once no later row of R uses them, and kept while one does, give
    /// the two products bitwise where the rows formed exceed `KP_KEPT` (R's rows reach fine
    /// rows far apart, so rows are kept across many rows of R and some are dropped early).
    #[test]
    fn triple_product_past_the_kept_rows_is_two_products_bitwise() {
        let m = |nrows: usize, ncols: usize, per: u32, stride: u32, seed: u32| {
            let t = (0..nrows as u32)
                .flat_map(|i| {
                    (0..per).map(move |k| (i, (i * stride + k * 977 + seed) % ncols as u32, 1.0 / (i + k + seed) as f64 - 0.01))
                })
                .collect();
            CsrMatrix::from_triplets(nrows, ncols, t)
        };
        let (r, k, p) = (m(4000, 30000, 6, 7, 1), m(30000, 30000, 8, 1, 2), m(30000, 4000, 5, 1, 3));
        let kp = matmul(&k, &p);
        assert!(kp.nnz() > KP_KEPT, "K P has {} entries", kp.nnz());
        let want = matmul(&r, &kp);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let got = pool.install(|| triple_product(&r, &k, &p));
        assert!(same_pattern(&got, &want) && want.nnz() > 4000);
        assert!(want.vals.iter().zip(&got.vals).all(|(a, b)| a.to_bits() == b.to_bits()));
    }

    /// Gᵀ W G without the rows of W G is the triple product with W diagonal, bitwise, with
    /// zero and negative weights and entries among them.
    #[test]
    fn weighted_gram_is_the_triple_product_bitwise() {
        let t = (0..40u32)
            .flat_map(|i| (0..4).map(move |k| (i, (i * 3 + k * 7) % 25, if k == 2 { 0.0 } else { 1.0 / (i + k + 1) as f64 - 0.2 })))
            .collect();
        let g = CsrMatrix::from_triplets(40, 25, t);
        let w: Vec<f64> = (0..40).map(|i| if i % 5 == 0 { 0.0 } else { (i as f64 - 13.0) / 7.0 }).collect();
        let d = CsrMatrix::from_triplets(40, 40, (0..40u32).map(|i| (i, i, w[i as usize])).collect());
        let want = triple_product(&g.transpose(), &d, &g);
        let got = weighted_gram(&g.transpose(), &w, &g);
        assert!(same_pattern(&got, &want) && want.nnz() > 100);
        assert!(want.vals.iter().zip(&got.vals).all(|(a, b)| a.to_bits() == b.to_bits()));
    }

    /// The numeric phase into a stored pattern gives the whole product's values bitwise, from
    /// any previous values and on several threads.
    #[test]
    fn values_into_a_stored_pattern_are_the_product_bitwise() {
        let m = |nrows: usize, ncols: usize, seed: u32| {
            let t = (0..nrows as u32)
                .flat_map(|i| {
                    (0..4).map(move |k| (i, (i * 7 + k * 5 + seed) % ncols as u32, 1.0 / (i + k + seed) as f64 - 0.1))
                })
                .collect();
            CsrMatrix::from_triplets(nrows, ncols, t)
        };
        let (r, k, p) = (m(3000, 5000, 1), m(5000, 5000, 2), m(5000, 3000, 3));
        let want = triple_product(&r, &k, &p);
        let mut c = want.clone();
        c.vals.iter_mut().for_each(|v| *v = 7.0);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        pool.install(|| triple_product_values(&r, &k, &p, &mut c));
        assert!(want.vals.iter().zip(&c.vals).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert!(same_pattern(&c, &want) && want.nnz() > 3000 && want.vals.iter().any(|v| *v != 0.0));
    }
}
