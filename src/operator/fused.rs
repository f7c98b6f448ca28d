//! The biharmonic's two passes over K, S = M⁻¹ K x (paper Eq. 5) and then K S (Eq. 6), fused
//! into one sweep over the rows of a large level.
//!
//! Row i of the second pass reads S only at its neighbours, which the locality numbering
//! (`bc/numbering.rs`) keeps within the bandwidth `bw` of i. So S can be computed `bw` rows ahead
//! of the second pass, and row i of K is read a second time while it is still in cache instead
//! of from memory. A pass over K is bound by its arithmetic about as much as by memory, so the
//! gain is modest on large meshes (docs/perf-history.md, step 13).
//!
//! In parallel the rows are cut into chunks of at least 2·`bw`. S next to a chunk's edges reads
//! the iterate of the neighbouring chunk, which a smoothing step updates in place, so those S
//! values are computed first, for every chunk, before any iterate changes (phase 1); then each
//! chunk runs its pipelined sweep alone (phase 2), reading its neighbours' edge values of S from
//! copies. Every S value and every row sum is formed by the same expression in the same order as
//! the two plain passes, so results are bitwise those of the unfused operator, whatever the
//! chunking or the thread count.

use super::LevelOperator;
use crate::bc::P;
use crate::sparse::CsrMatrix;
use rayon::prelude::*;

/// Levels below this many rows keep the plain passes: below that K stays mostly in a 32 MiB L3
/// cache between the two passes, and fusing them gains nothing (docs/perf-history.md, step 13).
const FUSE_MIN_ROWS: usize = 1 << 19;
/// Rows of the second pass per block; S runs `bw` rows ahead of the block.
const BLOCK: usize = 4096;
/// Chunks per sweep when the bandwidth allows (load balance on a few threads).
const CHUNKS: usize = 16;
/// A chunk is at least this many bandwidths long, so the edge rows (read through the copies,
/// a slower path) stay a few percent of the rows.
const MIN_CHUNK_BW: usize = 32;

/// How a level's rows are cut for the fused sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct FusePlan {
    /// max |i − j| over the entries K_ij.
    bw: usize,
    /// Chunk boundaries: 0 = b_0 < b_1 < … < b_T = n, every chunk at least 2·bw long.
    bounds: Vec<usize>,
}

impl FusePlan {
    /// The plan for K's pattern; None when the level is small or too wide for chunks.
    pub fn new(k: &CsrMatrix) -> Option<FusePlan> {
        Self::with_min_rows(k, FUSE_MIN_ROWS)
    }

    fn with_min_rows(k: &CsrMatrix, min_rows: usize) -> Option<FusePlan> {
        let n = k.nrows;
        if n < min_rows {
            return None;
        }
        let bw =
            (0..n).map(|i| k.row(i).0.iter().map(|&j| (j as usize).abs_diff(i)).max().unwrap_or(0)).max().unwrap_or(0);
        let len = (n / CHUNKS).max(MIN_CHUNK_BW * bw).max(1);
        let chunks = n / len;
        if chunks < 2 {
            return None;
        }
        // The remainder goes to the last chunk, so no chunk is short.
        let bounds = (0..chunks).map(|c| c * len).chain(std::iter::once(n)).collect();
        Some(FusePlan { bw, bounds })
    }
}

/// The iterate x of the first pass: read only (an application, a residual), or updated in
/// place by the second pass (a smoothing step, x ← x + d).
pub enum Iterate<'a> {
    Read(&'a [f64]),
    Update(&'a mut [f64]),
}

/// One chunk's view of the iterate: its rows `[base, base + len)` when it updates them, the whole
/// vector (base 0) when it only reads.
enum ChunkIterate<'a> {
    Read(&'a [f64]),
    Update(&'a mut [f64], usize),
}

impl ChunkIterate<'_> {
    fn read(&self) -> (&[f64], usize) {
        match self {
            ChunkIterate::Read(x) => (x, 0),
            ChunkIterate::Update(x, base) => (x, *base),
        }
    }
}

/// Cuts `v` at `bounds` into one mutable slice per chunk.
fn split<'a>(mut v: &'a mut [f64], bounds: &[usize]) -> Vec<&'a mut [f64]> {
    let mut out = Vec::with_capacity(bounds.len() - 1);
    for w in bounds.windows(2) {
        let (head, tail) = v.split_at_mut(w[1] - w[0]);
        out.push(head);
        v = tail;
    }
    out
}

impl LevelOperator {
    /// For every unknown i, `out_i ← f(i, t_i, out_i)` with t_i = (K S)_i, S = M⁻¹ K x, or None
    /// on P unknowns; with `Iterate::Update` then x_i ← x_i + out_i. `s` (length n) holds S on
    /// return (edge rows from phase 1, the rest from phase 2).
    pub(super) fn fused_pass(
        &self,
        plan: &FusePlan,
        flags: &[u8],
        x: Iterate,
        s: &mut [f64],
        out: &mut [f64],
        f: impl Fn(usize, Option<f64>, f64) -> f64 + Sync + Send,
    ) {
        let (bw, bounds) = (plan.bw, &plan.bounds);
        let n = self.n();
        assert_eq!(bounds.last(), Some(&n), "the fused plan was made for another K");
        let chunks = bounds.len() - 1;
        // Phase 1: S on the first and last bw rows of every chunk, from x as it is now.
        {
            let xr: &[f64] = match &x {
                Iterate::Read(x) => x,
                Iterate::Update(x) => x,
            };
            split(s, bounds).into_par_iter().enumerate().for_each(|(c, sc)| {
                let (a, e) = (bounds[c], bounds[c + 1]);
                for j in (a..a + bw).chain(e - bw..e) {
                    sc[j - a] = self.source_row(flags, j, xr, 0, None);
                }
            });
        }
        // Each chunk's neighbours' edge values of S, copied before the chunks write S again.
        let halos: Vec<(Vec<f64>, Vec<f64>)> = (0..chunks)
            .map(|c| {
                let (a, e) = (bounds[c], bounds[c + 1]);
                (s[a.saturating_sub(bw)..a].to_vec(), s[e..(e + bw).min(n)].to_vec())
            })
            .collect();
        let xs: Vec<ChunkIterate> = match x {
            Iterate::Read(x) => (0..chunks).map(|_| ChunkIterate::Read(x)).collect(),
            Iterate::Update(x) => {
                split(x, bounds).into_iter().zip(bounds).map(|(xc, &a)| ChunkIterate::Update(xc, a)).collect()
            }
        };
        // Phase 2: each chunk alone, S running bw rows ahead of the second pass.
        split(s, bounds).into_par_iter().zip(split(out, bounds)).zip(xs).zip(&halos).enumerate().for_each(
            |(c, (((sc, oc), mut xc), (left, right)))| {
                let (a, e) = (bounds[c], bounds[c + 1]);
                let lo = a.saturating_sub(bw);
                // S at any row this chunk's second pass can reach: a copy outside the chunk.
                let s_at = |sc: &[f64], j: usize| {
                    if j < a {
                        left[j - lo]
                    } else if j >= e {
                        right[j - e]
                    } else {
                        sc[j - a]
                    }
                };
                let mut done = a + bw;
                let mut i0 = a;
                while i0 < e {
                    let i1 = (i0 + BLOCK).min(e);
                    let need = (i1 + bw).min(e - bw);
                    if need > done {
                        let (xr, base) = xc.read();
                        for j in done..need {
                            sc[j - a] = self.source_row(flags, j, xr, base, None);
                        }
                        done = need;
                    }
                    for i in i0..i1 {
                        let t = if flags[i] & P != 0 {
                            None
                        } else if i >= a + bw && i + bw < e {
                            Some(self.k.row_dot_offset(i, sc, a))
                        } else {
                            Some(self.k.row_dot_with(i, |j| s_at(sc, j)))
                        };
                        oc[i - a] = f(i, t, oc[i - a]);
                    }
                    if let ChunkIterate::Update(xv, _) = &mut xc {
                        for i in i0..i1 {
                            xv[i - a] += oc[i - a];
                        }
                    }
                    i0 = i1;
                }
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bc::Z;
    use crate::mesh::fixtures::rect;
    use crate::{BoundaryConditions, Kind, Link, Method, Options, Solver};

    /// The fused sweep, forced onto a small level cut into several chunks of several blocks,
    /// gives bitwise the plain passes' application, residual and smoothing step, on rows with
    /// every flag (P, Z, linked periodic sides), from 3 threads.
    #[test]
    fn fused_sweep_is_bitwise_the_two_passes() {
        // A free surface [0,1]×[−2,0], tall enough for several chunks of its bandwidth: bottom
        // FIXED, top CLAMPED, sides linked (x CLAMPED, y FREE).
        let mesh = rect(96, 256, [0.0, 1.0, -2.0, 0.0]);
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(1, Kind::Fixed).set_kinds(3, Kind::Clamped);
        for p in [2, 4] {
            bcs.set_kind(p, 0, Kind::Clamped).unwrap().set_kind(p, 1, Kind::Free).unwrap();
        }
        bcs.add_link(Link::ByOffset { a: 4, b: 2, offset: [1.0, 0.0, 0.0], tol: 1e-9 });
        let opts = Options { method: Method::Biharmonic, threads: 3, ..Default::default() };
        let solver = Solver::new(&mesh, &bcs, opts).unwrap();
        let lev = solver.hierarchy().fine();
        let plain = &lev.op;
        assert!(plain.fuse.is_none(), "a {}-row level is below the fusing size", plain.n());
        let mut fused = plain.clone();
        fused.fuse = FusePlan::with_min_rows(&fused.k, 0);
        let plan = fused.fuse.as_ref().expect("the level can be cut into chunks");
        let n = plain.n();
        assert!(plan.bounds.len() >= 4, "{} chunks of {n} rows, bandwidth {}", plan.bounds.len() - 1, plan.bw);
        assert!(plan.bounds.windows(2).all(|w| w[1] - w[0] >= 2 * plan.bw && w[1] - w[0] > BLOCK));
        let flags = &lev.flags[1];
        assert!(flags.iter().any(|f| f & P != 0) && flags.iter().any(|f| f & Z != 0));
        let x: Vec<f64> = (0..n).map(|i| ((i * 7919) % 1009) as f64 / 1009.0 - 0.5).collect();
        let b: Vec<f64> = (0..n).map(|i| ((i * 104_729) % 997) as f64 / 997.0 - 0.5).collect();
        let same = |a: &[f64], c: &[f64]| a.iter().zip(c).all(|(a, c)| a.to_bits() == c.to_bits());
        let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        pool.install(|| {
            let (mut y0, mut y1, mut s) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            plain.apply(flags, &x, &mut y0, &mut s);
            fused.apply(flags, &x, &mut y1, &mut s);
            assert!(same(&y0, &y1), "application differs");
            assert!(y0.iter().any(|v| *v != 0.0));
            plain.residual(flags, &b, &x, &mut y0, &mut s);
            fused.residual(flags, &b, &x, &mut y1, &mut s);
            assert!(same(&y0, &y1), "residual differs");
            // Two Jacobi-like steps with a direction that depends on the old one, x in place.
            let (mut x0, mut x1) = (x.clone(), x.clone());
            let (mut d0, mut d1) = (b.clone(), b.clone());
            for _ in 0..2 {
                let f = |i: usize, r: f64, d: f64| 0.3 * d + 1e-3 * r * (1 + i % 3) as f64;
                plain.step_with_residual(flags, &b, &mut x0, &mut s, &mut d0, f);
                fused.step_with_residual(flags, &b, &mut x1, &mut s, &mut d1, f);
            }
            assert!(same(&d0, &d1) && same(&x0, &x1), "smoothing step differs");
            assert!(!same(&x0, &x), "the steps moved x");
        });
    }
}
