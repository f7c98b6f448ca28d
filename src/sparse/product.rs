//! Sparse products, row by row (each row of the result from one row of the left factor), so
//! they are deterministic and parallel like every other operation on `CsrMatrix`.

use super::{offset, CsrMatrix};
use rayon::prelude::*;

/// Rows per task when filling a product's arrays.
const PRODUCT_BLOCK: usize = 1024;

/// Sums scaled sparse rows into one row: entries in order of first appearance, each the sum of
/// its products in the order added; `finish` emits them by ascending column.
struct RowSum {
    slot: Vec<usize>,
    cols: Vec<u32>,
    vals: Vec<f64>,
    order: Vec<usize>,
}

impl RowSum {
    fn new(ncols: usize) -> Self {
        RowSum { slot: vec![usize::MAX; ncols], cols: Vec::new(), vals: Vec::new(), order: Vec::new() }
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

    /// Adds the columns of a row, for counting only (values are left unset).
    fn add_pattern(&mut self, cols: &[u32]) {
        for &j in cols {
            if self.slot[j as usize] == usize::MAX {
                self.slot[j as usize] = self.cols.len();
                self.cols.push(j);
            }
        }
    }

    /// The number of distinct columns added, and starts a new row.
    fn take_count(&mut self) -> usize {
        let n = self.cols.len();
        self.cols.iter().for_each(|&j| self.slot[j as usize] = usize::MAX);
        self.cols.clear();
        self.vals.clear();
        n
    }

    /// Writes the sum, columns ascending, and starts a new one.
    fn finish(&mut self, cols: &mut Vec<u32>, vals: &mut Vec<f64>) {
        let RowSum { slot, cols: c, vals: v, order } = self;
        order.clear();
        order.extend(0..c.len());
        order.sort_unstable_by_key(|&p| c[p]);
        cols.clear();
        vals.clear();
        cols.extend(order.iter().map(|&p| c[p]));
        vals.extend(order.iter().map(|&p| v[p]));
        c.iter().for_each(|&j| slot[j as usize] = usize::MAX);
        c.clear();
        v.clear();
    }

    /// Row i of A B.
    fn product_row(&mut self, a: &CsrMatrix, b: &CsrMatrix, i: usize, cols: &mut Vec<u32>, vals: &mut Vec<f64>) {
        let (ac, av) = a.row(i);
        for (&k, &x) in ac.iter().zip(av) {
            self.add(x, b.row(k as usize));
        }
        self.finish(cols, vals);
    }
}

/// A matrix whose rows are computed independently (`count(state, i)` entries, written by
/// `row(state, i, cols, vals)`), so it is deterministic and parallel. Counting first lets the rows
/// be written in place: no per-row vectors held at once (they took twice the result's memory).
fn by_rows<S>(
    nrows: usize,
    ncols: usize,
    init: impl Fn() -> S + Sync + Send,
    count: impl Fn(&mut S, usize) -> usize + Sync + Send,
    row: impl Fn(&mut S, usize, &mut Vec<u32>, &mut Vec<f64>) + Sync + Send,
) -> CsrMatrix {
    // Row lengths, then their running sums.
    let mut row_ptr = vec![0u32; nrows + 1];
    row_ptr[1..].par_iter_mut().enumerate().with_min_len(256).for_each_init(&init, |s, (i, len)| {
        *len = offset(count(s, i));
    });
    let mut nnz = 0;
    for p in &mut row_ptr[1..] {
        nnz += *p as usize;
        *p = offset(nnz);
    }
    let (mut cols, mut vals) = (vec![0u32; nnz], vec![0.0; nnz]);
    // Blocks of rows with their disjoint parts of cols and vals.
    let mut blocks = Vec::with_capacity(nrows.div_ceil(PRODUCT_BLOCK));
    let (mut c_rest, mut v_rest) = (&mut cols[..], &mut vals[..]);
    for start in (0..nrows).step_by(PRODUCT_BLOCK) {
        let end = (start + PRODUCT_BLOCK).min(nrows);
        let len = (row_ptr[end] - row_ptr[start]) as usize;
        let (c, c_next) = std::mem::take(&mut c_rest).split_at_mut(len);
        let (v, v_next) = std::mem::take(&mut v_rest).split_at_mut(len);
        (c_rest, v_rest) = (c_next, v_next);
        blocks.push((start..end, c, v));
    }
    let init = || (init(), Vec::new(), Vec::new());
    blocks.into_par_iter().for_each_init(init, |(s, c, v), (rows, out_c, out_v)| {
        let mut at = 0;
        for i in rows {
            row(s, i, c, v);
            out_c[at..at + c.len()].copy_from_slice(c);
            out_v[at..at + v.len()].copy_from_slice(v);
            at += c.len();
        }
    });
    CsrMatrix { nrows, ncols, row_ptr, cols, vals }
}

/// C = A B, row by row (each row of C from one row of A). Column indices come out sorted.
pub fn matmul(a: &CsrMatrix, b: &CsrMatrix) -> CsrMatrix {
    assert_eq!(a.ncols, b.nrows, "matmul: A has {} columns, B has {} rows", a.ncols, b.nrows);
    let count = |sum: &mut RowSum, i: usize| {
        a.row(i).0.iter().for_each(|&k| sum.add_pattern(b.row(k as usize).0));
        sum.take_count()
    };
    by_rows(a.nrows, b.ncols, || RowSum::new(b.ncols), count, |sum, i, c, v| sum.product_row(a, b, i, c, v))
}

/// R K P, bitwise `matmul(r, &matmul(k, p))` but without holding K P (the largest matrix of a
/// Galerkin hierarchy): its rows are formed where R uses them and kept a while (`KpRows`), so a
/// row used by several neighbouring rows of R is mostly formed once.
pub fn triple_product(r: &CsrMatrix, k: &CsrMatrix, p: &CsrMatrix) -> CsrMatrix {
    assert_eq!(r.ncols, k.nrows, "triple_product: R has {} columns, K has {} rows", r.ncols, k.nrows);
    assert_eq!(k.ncols, p.nrows, "triple_product: K has {} columns, P has {} rows", k.ncols, p.nrows);
    let init = || (KpRows::new(k.nrows, p.ncols), RowSum::new(p.ncols));
    let count = |(kp, outer): &mut (KpRows, RowSum), j: usize| {
        for &i in r.row(j).0 {
            let e = kp.form(k, p, i as usize);
            outer.add_pattern(&kp.cols[e]);
        }
        kp.bound();
        outer.take_count()
    };
    by_rows(r.nrows, p.ncols, init, count, |(kp, outer), j, c, v| {
        let (rc, rv) = r.row(j);
        for (&i, &x) in rc.iter().zip(rv) {
            let e = kp.form(k, p, i as usize);
            outer.add(x, (&kp.cols[e.clone()], &kp.vals[e]));
        }
        kp.bound();
        outer.finish(c, v);
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
}

const NOT_FORMED: u32 = u32::MAX;

/// Most entries of K P a task keeps formed (a few megabytes).
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
            for (&l, &y) in kc.iter().zip(kv) {
                let (pc, pv) = p.row(l as usize);
                for (&m, &z) in pc.iter().zip(pv) {
                    let s = &mut self.slot[m as usize];
                    if *s == NOT_FORMED {
                        *s = offset(self.cols.len() - start);
                        self.cols.push(m);
                        self.vals.push(0.0);
                    }
                    self.vals[start + *s as usize] += y * z;
                }
            }
            self.cols[start..].iter().for_each(|&m| self.slot[m as usize] = NOT_FORMED);
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
    let mut blocks = Vec::with_capacity(c.nrows.div_ceil(PRODUCT_BLOCK));
    let mut rest = &mut c.vals[..];
    for start in (0..c.nrows).step_by(PRODUCT_BLOCK) {
        let end = (start + PRODUCT_BLOCK).min(c.nrows);
        let (v, next) = std::mem::take(&mut rest).split_at_mut((row_ptr[end] - row_ptr[start]) as usize);
        rest = next;
        blocks.push((start..end, v));
    }
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
