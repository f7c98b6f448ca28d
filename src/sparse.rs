//! Compressed sparse row matrices: the one storage for vertex graphs, operators and transfers.
//!
//! Every product is a gather over rows (each output entry owned by one row), so results are
//! bitwise identical for any thread count. Reductions use fixed-size blocks for the same reason.

mod product;

pub use product::{matmul, same_pattern, triple_product, triple_product_values, weighted_gram};
use rayon::prelude::*;

/// Rows below this count are processed serially: rayon's overhead dominates on small levels.
const PAR_ROWS: usize = 4096;
/// Matrix entries a parallel task of `par_fill_blocks` reads, about: `PAR_ROWS / 4` rows of a
/// fine level's K.
const TASK_ENTRIES: usize = 24 * 1024;
/// Block length of deterministic reductions; fixed so the summation order never depends on threads.
const REDUCE_BLOCK: usize = 4096;

/// A square or rectangular CSR matrix with sorted column indices per row.
///
/// Row offsets are u32 (half the memory of usize on every operator and transfer); constructors
/// panic, naming the limit, if a matrix would hold 2^32 entries or more.
#[derive(Clone, Debug, PartialEq)]
pub struct CsrMatrix {
    pub nrows: usize,
    pub ncols: usize,
    pub row_ptr: Vec<u32>,
    pub cols: Vec<u32>,
    pub vals: Vec<f64>,
}

impl CsrMatrix {
    /// Builds the sparsity pattern (values zero) from a list of (row, col) pairs; duplicates merge.
    /// Bucketed by row (`bucket_by_key`), then each short row sorted and deduplicated.
    pub fn from_pattern(nrows: usize, ncols: usize, pairs: Vec<(u32, u32)>) -> Self {
        offset(pairs.len());
        let (start, mut bucket) = bucket_by_key(nrows, &pairs);
        drop(pairs);
        let mut row_ptr = vec![0u32; nrows + 1];
        let mut len = 0usize;
        for i in 0..nrows {
            let (a, b) = (start[i] as usize, start[i + 1] as usize);
            bucket[a..b].sort_unstable();
            let mut last = None;
            for p in a..b {
                if last != Some(bucket[p]) {
                    last = Some(bucket[p]);
                    bucket[len] = bucket[p];
                    len += 1;
                }
            }
            row_ptr[i + 1] = len as u32;
        }
        bucket.truncate(len);
        bucket.shrink_to_fit();
        let vals = vec![0.0; len];
        CsrMatrix { nrows, ncols, row_ptr, cols: bucket, vals }
    }

    /// Builds a matrix from (row, col, value) triplets, summing duplicates in a fixed order.
    pub fn from_triplets(nrows: usize, ncols: usize, mut t: Vec<(u32, u32, f64)>) -> Self {
        // Stable sort keeps the insertion order of duplicates, so their sum is deterministic.
        t.sort_by_key(|&(r, c, _)| (r, c));
        let mut m = CsrMatrix::from_pattern(nrows, ncols, t.iter().map(|&(r, c, _)| (r, c)).collect());
        for &(r, c, v) in &t {
            let k = m.find(r as usize, c as usize).expect("entry is in the pattern built from it");
            m.vals[k] += v;
        }
        m
    }

    pub fn nnz(&self) -> usize {
        self.cols.len()
    }

    #[inline(always)]
    pub fn row(&self, i: usize) -> (&[u32], &[f64]) {
        let r = self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize;
        (&self.cols[r.clone()], &self.vals[r])
    }

    /// Row i times x: Σ_j A_ij x_j, summed as `row_dot_with` sums.
    #[inline(always)]
    pub fn row_dot(&self, i: usize, x: &[f64]) -> f64 {
        self.row_dot_with(i, |j| x[j])
    }

    /// Row i times x where x holds entries `base..` only: Σ_j A_ij x[j − base], summed as `row_dot_with` sums.
    #[inline(always)]
    pub fn row_dot_offset(&self, i: usize, x: &[f64], base: usize) -> f64 {
        self.row_dot_with(i, |j| x[j - base])
    }

    /// Σ_j A_ij x(j), for an x read through a function: the row's products in `pair_sum`'s
    /// order (every row product of the solver is summed this way).
    #[inline(always)]
    pub fn row_dot_with(&self, i: usize, x: impl Fn(usize) -> f64) -> f64 {
        let (c, v) = self.row(i);
        pair_sum(c, v, |j, a| a * x(j as usize))
    }

    /// Row i times each of the `G` vectors `xs`, every one summed exactly as `row_dot` sums it
    /// (`pair_sum`'s order), the row's entries read once for all of them: the blocks of a group
    /// of components share their level's operator.
    #[inline(always)]
    pub fn row_dots<const G: usize>(&self, i: usize, xs: &[&[f64]; G]) -> [f64; G] {
        let (c, v) = self.row(i);
        let (c2, v2) = (c.chunks_exact(2), v.chunks_exact(2));
        let last = c2.remainder().first().zip(v2.remainder().first());
        let (mut even, mut odd) = ([0.0; G], [0.0; G]);
        for (c, v) in c2.zip(v2) {
            let (j0, j1) = (c[0] as usize, c[1] as usize);
            for k in 0..G {
                even[k] += v[0] * xs[k][j0];
                odd[k] += v[1] * xs[k][j1];
            }
        }
        if let Some((&j, &a)) = last {
            for k in 0..G {
                even[k] += a * xs[k][j as usize];
            }
        }
        std::array::from_fn(|k| even[k] + odd[k])
    }

    /// Position of entry (i, j) in `cols`/`vals`, if it is in the pattern.
    pub fn find(&self, i: usize, j: usize) -> Option<usize> {
        let (c, _) = self.row(i);
        c.binary_search(&(j as u32)).ok().map(|p| self.row_ptr[i] as usize + p)
    }

    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.find(i, j).map_or(0.0, |k| self.vals[k])
    }

    /// y = A x.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.ncols, "mul_vec: x has {} entries, matrix has {} columns", x.len(), self.ncols);
        assert_eq!(y.len(), self.nrows, "mul_vec: y has {} entries, matrix has {} rows", y.len(), self.nrows);
        self.map_rows(y, |i| self.row_dot(i, x));
    }

    /// Fills `out[i] = f(i)` for every row, in parallel when the matrix is large.
    pub fn map_rows(&self, out: &mut [f64], f: impl Fn(usize) -> f64 + Sync + Send) {
        par_fill(out, f);
    }

    /// The transpose, built by a counting sort (serial, done once per hierarchy).
    pub fn transpose(&self) -> CsrMatrix {
        let (row_ptr, cols, vals) = self.transpose_map(|p, _| self.vals[p]);
        CsrMatrix { nrows: self.ncols, ncols: self.nrows, row_ptr, cols, vals }
    }

    /// The pattern of the transpose (row offsets and columns, each row's columns ascending) and,
    /// per entry, `f(p, i)` of its position `p` in this matrix's `cols`/`vals` and its row `i` here.
    pub fn transpose_map<T: Copy + Default>(&self, f: impl Fn(usize, usize) -> T) -> (Vec<u32>, Vec<u32>, Vec<T>) {
        let mut row_ptr = vec![0u32; self.ncols + 1];
        for &c in &self.cols {
            row_ptr[c as usize + 1] += 1;
        }
        for i in 0..self.ncols {
            row_ptr[i + 1] += row_ptr[i];
        }
        let mut next = row_ptr.clone();
        let mut cols = vec![0u32; self.nnz()];
        let mut out = vec![T::default(); self.nnz()];
        for i in 0..self.nrows {
            for p in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
                let j = self.cols[p] as usize;
                let q = next[j] as usize;
                cols[q] = i as u32;
                out[q] = f(p, i);
                next[j] += 1;
            }
        }
        (row_ptr, cols, out)
    }

    /// Dense copy, for direct solves of small systems and for tests.
    pub fn to_dense(&self) -> Vec<Vec<f64>> {
        let mut d = vec![vec![0.0; self.ncols]; self.nrows];
        for (i, row) in d.iter_mut().enumerate() {
            let (c, v) = self.row(i);
            for (&j, &a) in c.iter().zip(v) {
                row[j as usize] += a;
            }
        }
        d
    }
}

/// Counting sort of (key, value) pairs with keys below `n`: key k's values are
/// `values[start[k]..start[k + 1]]`, in input order. O(pairs + n), where a comparison sort of
/// millions of pairs would take a tenth of a setup.
pub(crate) fn bucket_by_key(n: usize, pairs: &[(u32, u32)]) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; n + 1];
    for &(k, _) in pairs {
        start[k as usize + 1] += 1;
    }
    for k in 0..n {
        start[k + 1] += start[k];
    }
    let mut values = vec![0u32; pairs.len()];
    let mut next = start.clone();
    for &(k, v) in pairs {
        values[next[k as usize] as usize] = v;
        next[k as usize] += 1;
    }
    (start, values)
}

/// Σ_k term(a_k, b_k) as two partial sums, one over the even positions k and one over the odd
/// ones, each in order, added at the end. One running sum makes every product wait for the
/// previous addition; two halve that chain, which makes whole solves 1.03–1.10× faster
/// (docs/perf-history.md, step 15). The order is fixed per row, so results do not depend on the
/// thread count.
#[inline(always)]
pub fn pair_sum<A: Copy, B: Copy>(a: &[A], b: &[B], term: impl Fn(A, B) -> f64) -> f64 {
    let (a2, b2) = (a.chunks_exact(2), b.chunks_exact(2));
    let last = a2.remainder().first().zip(b2.remainder().first());
    let (mut even, mut odd) = (0.0, 0.0);
    for (a, b) in a2.zip(b2) {
        even += term(a[0], b[0]);
        odd += term(a[1], b[1]);
    }
    if let Some((&a, &b)) = last {
        even += term(a, b);
    }
    even + odd
}

/// The entries `vals` of a matrix with rows `row_ptr` cut into blocks of `rows` rows (the last
/// one shorter): each block's row range and its own entries, disjoint, for filling a matrix's
/// rows in parallel.
pub(crate) fn row_blocks<'a, T>(row_ptr: &[u32], vals: &'a mut [T], rows: usize) -> Vec<(std::ops::Range<usize>, &'a mut [T])> {
    let n = row_ptr.len().saturating_sub(1);
    let mut blocks = Vec::with_capacity(n.div_ceil(rows.max(1)));
    let mut rest = vals;
    for first in (0..n).step_by(rows.max(1)) {
        let end = (first + rows.max(1)).min(n);
        let (b, next) = std::mem::take(&mut rest).split_at_mut((row_ptr[end] - row_ptr[first]) as usize);
        rest = next;
        blocks.push((first..end, b));
    }
    blocks
}

/// `n` as a row offset: the entry count of a matrix must stay below 2^32.
pub(crate) fn offset(n: usize) -> u32 {
    u32::try_from(n).unwrap_or_else(|_| panic!("sparse matrix with {n} entries: at most 2^32 - 1 are supported"))
}

/// `out[i] = f(i)` for all i, in parallel for long vectors. Deterministic: each entry is computed
/// by one call of `f`, whatever the thread count.
pub fn par_fill(out: &mut [f64], f: impl Fn(usize) -> f64 + Sync + Send) {
    if out.len() < PAR_ROWS {
        out.iter_mut().enumerate().for_each(|(i, o)| *o = f(i));
    } else {
        out.par_iter_mut().enumerate().with_min_len(1024).for_each(|(i, o)| *o = f(i));
    }
}

/// `y[i] = f(i, y[i])` for all i, in parallel for long vectors (elementwise, so deterministic).
pub fn par_update(y: &mut [f64], f: impl Fn(usize, f64) -> f64 + Sync + Send) {
    if y.len() < PAR_ROWS {
        y.iter_mut().enumerate().for_each(|(i, v)| *v = f(i, *v));
    } else {
        y.par_iter_mut().enumerate().with_min_len(1024).for_each(|(i, v)| *v = f(i, *v));
    }
}

/// `out[k][i] = f(i)[k]` for all i and each of the `G` vectors `out` (of one length), where
/// the rows read `entries` matrix entries in all: one call of `f` per row fills that row of
/// every vector, so a kernel that reads a row once serves a group's blocks. In parallel by the
/// work, not the rows: tasks of about `TASK_ENTRIES` entries, so the few dense rows of a deep
/// Galerkin level are spread as a fine level's many sparse ones. Deterministic as `par_fill`.
pub fn par_fill_blocks<const G: usize>(out: [&mut [f64]; G], entries: usize, f: impl Fn(usize) -> [f64; G] + Sync + Send) {
    let n = out.first().map_or(0, |o| o.len());
    assert!(out.iter().all(|o| o.len() == n), "par_fill_blocks: vectors of different lengths");
    let rows = (TASK_ENTRIES * n).div_ceil(entries.max(1)).clamp(16, 1024);
    let fill = |first: usize, pieces: &mut [&mut [f64]; G]| {
        for r in 0..pieces.first().map_or(0, |p| p.len()) {
            let v = f(first + r);
            for (p, v) in pieces.iter_mut().zip(v) {
                p[r] = v;
            }
        }
    };
    if n < 2 * rows {
        let mut out = out;
        fill(0, &mut out);
        return;
    }
    let mut chunks: Vec<Vec<&mut [f64]>> = (0..n.div_ceil(rows)).map(|_| Vec::with_capacity(G)).collect();
    for o in out {
        for (c, piece) in o.chunks_mut(rows).enumerate() {
            chunks[c].push(piece);
        }
    }
    chunks.into_par_iter().enumerate().for_each(|(c, pieces)| {
        if let Ok(mut pieces) = <[&mut [f64]; G]>::try_from(pieces) {
            fill(c * rows, &mut pieces);
        }
    });
}

/// `(a[i], b[i]) = f(i, a[i], b[i])` for all i: two vectors updated in one pass, in parallel for
/// long vectors (elementwise, so deterministic).
pub fn par_update2(a: &mut [f64], b: &mut [f64], f: impl Fn(usize, f64, f64) -> (f64, f64) + Sync + Send) {
    assert_eq!(a.len(), b.len(), "par_update2: vectors of {} and {} entries", a.len(), b.len());
    let g = |i: usize, a: &mut f64, b: &mut f64| (*a, *b) = f(i, *a, *b);
    if a.len() < PAR_ROWS {
        a.iter_mut().zip(b).enumerate().for_each(|(i, (a, b))| g(i, a, b));
    } else {
        a.par_iter_mut().zip(b).enumerate().with_min_len(1024).for_each(|(i, (a, b))| g(i, a, b));
    }
}

/// Sum of `f(i)` for i in 0..n, in blocks of fixed length summed in order: bitwise the same for
/// any thread count (a plain parallel sum is not).
pub fn det_sum(n: usize, f: impl Fn(usize) -> f64 + Sync + Send) -> f64 {
    if n <= REDUCE_BLOCK {
        return (0..n).map(&f).sum();
    }
    let nblocks = n.div_ceil(REDUCE_BLOCK);
    let partial: Vec<f64> = (0..nblocks)
        .into_par_iter()
        .map(|b| (b * REDUCE_BLOCK..((b + 1) * REDUCE_BLOCK).min(n)).map(&f).sum())
        .collect();
    partial.iter().sum()
}

/// Deterministic dot product.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    det_sum(a.len(), |i| a[i] * b[i])
}

/// Largest absolute entry (max is order-independent, so a plain parallel reduction is exact).
pub fn max_abs(a: &[f64]) -> f64 {
    // NaN wins (`f64::max` would drop it): a non-finite vector must not look small.
    let max = |m: f64, x: f64| if m.is_nan() || x.is_nan() { f64::NAN } else { m.max(x) };
    if a.len() < PAR_ROWS {
        a.iter().fold(0.0, |m, &x| max(m, x.abs()))
    } else {
        a.par_iter().map(|x| x.abs()).reduce(|| 0.0, max)
    }
}

/// y += alpha * x.
pub fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    if y.len() < PAR_ROWS {
        y.iter_mut().zip(x).for_each(|(y, &x)| *y += alpha * x);
    } else {
        y.par_iter_mut().zip(x).with_min_len(1024).for_each(|(y, &x)| *y += alpha * x);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pair_sum_adds_even_and_odd_positions_apart() {
        let one = |a: f64, b: f64| a * b;
        // A running sum loses the 1 beside 1e16; the two partial sums keep both.
        let (a, b) = ([1e16, 1.0, -1e16, 1.0], [1.0; 4]);
        assert_eq!(pair_sum(&a, &b, one), 2.0);
        assert_eq!(a.iter().sum::<f64>(), 1.0);
        // An odd length: the last term joins the even sum before the two are added.
        assert_eq!(pair_sum(&[1e16, 1.0, -1e16, 1.0, 1.0], &[1.0; 5], one), 3.0);
        assert_eq!(pair_sum(&[3.0], &[2.0], one), 6.0);
        assert_eq!(pair_sum::<f64, f64>(&[], &[], one), 0.0);
        // Rows go through it: row_dot is the same sum.
        let m = CsrMatrix::from_triplets(1, 4, vec![(0, 0, 1e16), (0, 1, 1.0), (0, 2, -1e16), (0, 3, 1.0)]);
        assert_eq!(m.row_dot(0, &[1.0; 4]), 2.0);
    }

    #[test]
    fn triplets_sum_duplicates_and_transpose_roundtrips() {
        let m = CsrMatrix::from_triplets(2, 3, vec![(1, 2, 1.0), (0, 0, 2.0), (1, 2, 0.5), (0, 1, -1.0)]);
        assert_eq!(m.row_ptr, vec![0, 2, 3]);
        assert_eq!(m.get(1, 2), 1.5);
        assert_eq!(m.get(0, 1), -1.0);
        assert_eq!(m.transpose().transpose(), m);
        let mut y = vec![0.0; 2];
        m.mul_vec(&[1.0, 2.0, 3.0], &mut y);
        assert_eq!(y, vec![0.0, 4.5]);
    }

    #[test]
    fn row_dots_are_each_vector_s_row_dot_bitwise() {
        // Rows of odd and even lengths, values spread over magnitudes so the order shows.
        let n = PAR_ROWS + 37;
        let t: Vec<(u32, u32, f64)> = (0..n)
            .flat_map(|i| {
                (0..(i % 7) + 1).map(move |k| {
                    let j = (i * 13 + k * 101) % n;
                    (i as u32, j as u32, ((i * 31 + k * 17) % 19) as f64 * 10f64.powi((k % 5) as i32 * 4) - 9.0)
                })
            })
            .collect();
        let m = CsrMatrix::from_triplets(n, n, t);
        let xs: Vec<Vec<f64>> = (0..3).map(|c| (0..n).map(|j| ((j * 7 + c) % 11) as f64 / 3.0 - 1.5).collect()).collect();
        let x3 = [&xs[0][..], &xs[1][..], &xs[2][..]];
        let (mut a, mut b, mut c) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        par_fill_blocks([&mut a, &mut b, &mut c], m.nnz(), |i| m.row_dots(i, &x3));
        for (k, got) in [a, b, c].iter().enumerate() {
            for (i, g) in got.iter().enumerate() {
                assert_eq!(g.to_bits(), m.row_dot(i, &xs[k]).to_bits(), "vector {k}, row {i}");
            }
        }
        let mut one = vec![0.0; 5];
        par_fill_blocks([&mut one], m.nnz(), |i| m.row_dots(i, &[&xs[0][..]]));
        assert_eq!(one, (0..5).map(|i| m.row_dot(i, &xs[0])).collect::<Vec<_>>());
    }

    #[test]
    fn det_sum_matches_serial_blocks() {
        let n = 3 * REDUCE_BLOCK + 17;
        let s = det_sum(n, |i| 1.0 / (i as f64 + 1.0));
        let serial: f64 = (0..n.div_ceil(REDUCE_BLOCK))
            .map(|b| (b * REDUCE_BLOCK..((b + 1) * REDUCE_BLOCK).min(n)).map(|i| 1.0 / (i as f64 + 1.0)).sum::<f64>())
            .sum();
        assert_eq!(s.to_bits(), serial.to_bits());
    }
}
