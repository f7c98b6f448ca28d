//! The l1 line-Jacobi preconditioner of a level with lines of strong coupling
//! (`multigrid::lines`): D⁻¹ r solved along each line, D⁻¹ r = r / D pointwise elsewhere.
//!
//! On a line, D is the line's banded part of A (tridiagonal for the Laplacian and spring, whose
//! A is K; pentadiagonal for the biharmonic's K V⁻¹ K, whose couplings reach two neighbours along
//! a line) plus, on its diagonal, a bound of the row's couplings left out: Σ |A_ij| over the
//! unknowns j off the band. Off the lines D is the l1 diagonal of docs/DESIGN.md §3, the same
//! bound for a line of one. So D − A is a sum of the symmetric off-band parts E, each bounded by
//! diag(Σ_j |E_ij|): A ≤ D, and λmax(D⁻¹A) ≤ 1 as for point Jacobi (the l1 smoothers of Baker,
//! Falgout, Kolev and Yang 2011). The smoothers' polynomials and their λmax stay as they are;
//! across a thin layer the line solve removes the strong couplings point Jacobi cannot smooth.
//!
//! Each component has its own factors (its prescribed unknowns leave the line blocks: their
//! correction is zero); components with the same flags share them. In a group coupled by slip
//! walls the slip unknowns leave the blocks too and keep their equalised point diagonal, so D
//! commutes with the projection Π as the point diagonal does (`multigrid::slip`).

use super::lines::Lines;
use crate::bc::{P, Z};
use crate::operator::{LevelOperator, Method};
use crate::sparse::par_update;
use std::ops::Range;
use rayon::prelude::*;
use std::sync::Arc;

/// The banded LDLᵀ factors of one component's line blocks.
#[derive(Debug, PartialEq)]
struct Factor {
    /// Per unknown on a line (in `Lines::unknowns` order) `band + 1` values: the pivot D_i,
    /// then L_{i,i−1} … L_{i,i−band}.
    ldl: Vec<f64>,
    /// Per unknown on a line: it is in its line's block (free, not a slip unknown of a coupled
    /// group); the others are solved pointwise.
    inside: Vec<bool>,
}

/// The line blocks of one level: its lines and each component's factors.
#[derive(Debug, Default)]
pub(crate) struct LineBlocks {
    /// The level's lines were looked for (they are kept while the mesh moves).
    searched: bool,
    lines: Lines,
    /// Position of each unknown in `lines.unknowns`, u32::MAX off the lines.
    at: Vec<u32>,
    /// The lines cut into runs of about `CHUNK` unknowns, the parallel tasks: run t holds the
    /// lines `runs[t]..runs[t + 1]`.
    runs: Vec<u32>,
    /// The band of the blocks: the couplings of A along a line reach this far.
    band: usize,
    /// Per component; None where a line's block could not be factored (then all are pointwise).
    factors: Vec<Option<Arc<Factor>>>,
}

impl LineBlocks {
    /// The line blocks of `lines` for `op` and the components' `flags`; `apart` marks the
    /// unknowns solved pointwise in every component (the slip unknowns of a coupled group).
    pub(crate) fn new(lines: Lines, op: &LevelOperator, flags: &[Vec<u8>], apart: &[bool]) -> LineBlocks {
        LineBlocks::banded(lines, op, flags, apart, band_of(op.method))
    }

    /// As `new`, with the blocks' `band` given: an operator held as a matrix (`one_pass`) whose
    /// entries are a biharmonic's (a level of the distributed multigrid) couples two neighbours
    /// along a line whatever its `method` says.
    pub(crate) fn banded(lines: Lines, op: &LevelOperator, flags: &[Vec<u8>], apart: &[bool], band: usize) -> LineBlocks {
        let mut blocks = LineBlocks::unfactored(lines, op.n(), band);
        blocks.refactor(op, flags, apart);
        blocks
    }

    /// The lines of a level of `n` unknowns with blocks of `band`, to be factored (`refactor`).
    fn unfactored(lines: Lines, n: usize, band: usize) -> LineBlocks {
        let mut at = vec![u32::MAX; n];
        for (p, &v) in lines.unknowns.iter().enumerate() {
            at[v as usize] = p as u32;
        }
        let mut runs = vec![0u32];
        for k in 0..lines.len() {
            if lines.start[k + 1] - lines.start[*runs.last().expect("starts at 0") as usize] >= CHUNK as u32 {
                runs.push(k as u32 + 1);
            }
        }
        if *runs.last().expect("starts at 0") as usize != lines.len() {
            runs.push(lines.len() as u32);
        }
        LineBlocks { searched: true, lines, at, runs, band, factors: Vec::new() }
    }

    /// The lines of a level of kept unknowns `kept` (unknowns of this level, ascending) with
    /// `method` (`Lines::restricted`), factored when the level's bounds are made (`refresh`).
    pub(crate) fn kept(&self, kept: &[u32], method: Method) -> LineBlocks {
        let mut coarse_of = vec![u32::MAX; self.at.len()];
        for (c, &d) in kept.iter().enumerate() {
            coarse_of[d as usize] = c as u32;
        }
        let lines = self.lines.restricted(|v| Some(coarse_of[v as usize]).filter(|&c| c != u32::MAX));
        LineBlocks::unfactored(lines, kept.len(), band_of(method))
    }

    /// Whether the level has lines.
    pub(crate) fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// The level's lines.
    pub(crate) fn lines(&self) -> &Lines {
        &self.lines
    }

    /// Whether the lines were looked for.
    pub(crate) fn searched(&self) -> bool {
        self.searched
    }

    /// Finds the lines once (they follow the level's topology, which a moved mesh keeps), from
    /// the unknowns' `points` (`dim` values each), K's graph and the neighbours along the cells'
    /// edges of each unknown, `edges(i)` (`multigrid::cell_edges`, where a line may start; both
    /// read only on the first call, `edges` only at unknowns anisotropic over K's graph), and
    /// factors their blocks for `op`'s current values and the components' `flags`;
    /// `apart` as in `new`.
    /// `linked` marks the unknowns that stand for several vertices (on no line, their couplings
    /// not measured).
    pub(crate) fn refresh<'e>(
        &mut self,
        op: &LevelOperator,
        flags: &[Vec<u8>],
        apart: &[bool],
        (points, dim, edges): (&[f64], usize, impl Fn(usize) -> &'e [u32]),
        linked: impl Fn(usize) -> bool,
    ) {
        if self.searched {
            self.refactor(op, flags, apart);
            return;
        }
        let prescribed = |i: usize| flags.iter().all(|f| f[i] & P != 0);
        let lines = Lines::find(op.n(), |i| op.k.row(i).0, edges, points, dim, prescribed, linked);
        *self = LineBlocks::new(lines, op, flags, apart);
    }

    /// Factors the blocks again for the operator's current values (after the mesh moved).
    pub(crate) fn refactor(&mut self, op: &LevelOperator, flags: &[Vec<u8>], apart: &[bool]) {
        if self.lines.is_empty() {
            self.factors = vec![None; flags.len()];
            return;
        }
        let mut factors: Vec<Option<Arc<Factor>>> = Vec::with_capacity(flags.len());
        for (c, f) in flags.iter().enumerate() {
            let same = (0..c).find(|&e| flags[e] == *f);
            let factor = match same {
                Some(e) => factors[e].clone(),
                None => self.factor(op, f, apart).map(Arc::new),
            };
            factors.push(factor);
        }
        self.factors = factors;
    }

    /// Whether component `c` is solved along the lines.
    pub(crate) fn active(&self, c: usize) -> bool {
        !self.lines.is_empty() && self.factors.get(c).is_some_and(|f| f.is_some())
    }

    /// One component's factors; None when a block is not positive definite in floating point
    /// (a tangled mesh), so the component keeps point Jacobi.
    fn factor(&self, op: &LevelOperator, flags: &[u8], apart: &[bool]) -> Option<Factor> {
        let lines = &self.lines;
        let b = self.band;
        let inside: Vec<bool> =
            lines.unknowns.iter().map(|&v| flags[v as usize] & P == 0 && !apart[v as usize]).collect();
        let mut ldl = vec![0.0; lines.unknowns.len() * (b + 1)];
        let ok = self
            .runs(&mut ldl, b + 1)
            .into_par_iter()
            .map(|(run, out)| {
                let first = lines.start[run.start] as usize;
                run.into_iter().fold(true, |ok, k| {
                    let (s, e) = (lines.start[k] as usize - first, lines.start[k + 1] as usize - first);
                    ok & self.factor_line(op, flags, &inside, k, &mut out[s * (b + 1)..e * (b + 1)])
                })
            })
            .reduce(|| true, |a, b| a && b);
        ok.then_some(Factor { ldl, inside })
    }

    /// `buf` (`width` values per unknown on a line) cut into the runs of lines: each run's
    /// lines and its part of `buf`.
    fn runs<'a>(&self, buf: &'a mut [f64], width: usize) -> Vec<(Range<usize>, &'a mut [f64])> {
        let mut out = Vec::with_capacity(self.runs.len());
        let mut rest = buf;
        for t in self.runs.windows(2) {
            let (a, b) = (t[0] as usize, t[1] as usize);
            let len = (self.lines.start[b] - self.lines.start[a]) as usize * width;
            let (head, tail) = std::mem::take(&mut rest).split_at_mut(len);
            out.push((a..b, head));
            rest = tail;
        }
        out
    }

    /// Assembles line `k`'s banded block with its l1 diagonal and factors it into `out`
    /// (`band + 1` values per unknown of the line). False when a pivot is not positive.
    fn factor_line(&self, op: &LevelOperator, flags: &[u8], inside: &[bool], k: usize, out: &mut [f64]) -> bool {
        let b = self.band;
        let s = self.lines.start[k] as usize;
        let line = self.lines.line(k);
        let m = line.len();
        // out[p (b+1) + q] = A(p, p − q) for q ≤ b, then the factors in place.
        out.iter_mut().for_each(|v| *v = 0.0);
        let pos = |j: u32| -> Option<usize> {
            let a = self.at[j as usize];
            (a != u32::MAX && (a as usize) >= s && (a as usize) < s + m && inside[a as usize]).then(|| a as usize - s)
        };
        let k_mat = &op.k;
        for (p, &v) in line.iter().enumerate() {
            if !inside[s + p] {
                out[p * (b + 1)] = 1.0;
                continue;
            }
            let row = &mut out[p * (b + 1)..(p + 1) * (b + 1)];
            let mut off = 0.0;
            // Adds a coupling a to column j of row p: into the band (lower half, the upper
            // half is the same by symmetry) or, off the band, its size to the diagonal bound.
            let mut add = |j: u32, a: f64, row: &mut [f64]| match pos(j) {
                Some(q) if q <= p && p - q <= b => row[p - q] += a,
                Some(q) if q > p && q - p <= b => {}
                _ => off += a.abs(),
            };
            match op.one_pass() {
                None => {
                    let (cols, vals) = k_mat.row(v as usize);
                    for (&kk, &kik) in cols.iter().zip(vals) {
                        if flags[kk as usize] & Z != 0 {
                            continue;
                        }
                        let c = kik * op.inv_v[kk as usize];
                        let (cols2, vals2) = k_mat.row(kk as usize);
                        for (&j, &kkj) in cols2.iter().zip(vals2) {
                            add(j, c * kkj, row);
                        }
                    }
                }
                Some(a) => {
                    let (cols, vals) = a.row(v as usize);
                    for (&j, &a) in cols.iter().zip(vals) {
                        add(j, a, row);
                    }
                }
            }
            row[0] += off;
        }
        ldl_band(out, m, b)
    }

    /// z = D⁻¹ r for component `c` in place: along the lines, and r / D (`inv_d`) elsewhere.
    /// `sol` is scratch of the lines' length.
    pub(crate) fn precondition(&self, c: usize, inv_d: &[f64], z: &mut [f64], sol: &mut Vec<f64>) {
        let f = self.factors[c].as_ref().expect("an active component");
        let b = self.band;
        let lines = &self.lines;
        sol.resize(lines.unknowns.len(), 0.0);
        let r = &*z;
        self.runs(sol, 1).into_par_iter().for_each(|(run, out)| {
            let first = lines.start[run.start] as usize;
            for k in run {
                let (s, e) = (lines.start[k] as usize, lines.start[k + 1] as usize);
                let y = &mut out[s - first..e - first];
                for (p, &v) in lines.line(k).iter().enumerate() {
                    y[p] = if f.inside[s + p] { r[v as usize] } else { 0.0 };
                }
                solve_band(&f.ldl[s * (b + 1)..e * (b + 1)], y, b);
            }
        });
        let (at, sol) = (&self.at, &*sol);
        par_update(z, |i, r| {
            let a = at[i];
            if a != u32::MAX && f.inside[a as usize] {
                sol[a as usize]
            } else {
                inv_d[i] * r
            }
        });
    }
}

/// The band of the line blocks of `method`'s operator: the biharmonic's K V⁻¹ K couples two
/// neighbours along a line, K one.
pub(crate) fn band_of(method: Method) -> usize {
    if method == Method::Biharmonic {
        2
    } else {
        1
    }
}

/// Unknowns on lines per parallel task (whole lines, so a task may hold a few more).
const CHUNK: usize = 4096;

/// In place: the banded symmetric matrix given by its lower band (`a[p (b+1) + q]` = A(p, p−q))
/// into its LDLᵀ factors (D_p at q = 0, L(p, p−q) at q ≥ 1). False when a pivot is not positive
/// and finite.
fn ldl_band(a: &mut [f64], m: usize, b: usize) -> bool {
    let w = b + 1;
    for p in 0..m {
        // L(p, j) for j = p−b … p−1, ascending j.
        for j in p.saturating_sub(b)..p {
            let mut v = a[p * w + (p - j)];
            for q in p.saturating_sub(b).max(j.saturating_sub(b))..j {
                v -= a[p * w + (p - q)] * a[j * w + (j - q)] * a[q * w];
            }
            a[p * w + (p - j)] = v / a[j * w];
        }
        let mut d = a[p * w];
        for q in p.saturating_sub(b)..p {
            let l = a[p * w + (p - q)];
            d -= l * l * a[q * w];
        }
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        a[p * w] = d;
    }
    true
}

/// Solves (L D Lᵀ) x = y in place with the factors of `ldl_band`.
fn solve_band(f: &[f64], y: &mut [f64], b: usize) {
    let w = b + 1;
    let m = y.len();
    for p in 0..m {
        let mut v = y[p];
        for q in p.saturating_sub(b)..p {
            v -= f[p * w + (p - q)] * y[q];
        }
        y[p] = v;
    }
    for p in 0..m {
        y[p] /= f[p * w];
    }
    for p in (0..m).rev() {
        let mut v = y[p];
        for q in p + 1..(p + w).min(m) {
            v -= f[q * w + (q - p)] * y[q];
        }
        y[p] = v;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn banded_ldl_solves_a_tridiagonal_system() {
        // A 1D chain: A = tridiag(−1, 2 + ε, −1), solved by the band solver and by the Thomas
        // algorithm.
        let m = 30;
        let eps = 1e-3;
        let mut a = vec![0.0; m * 2];
        for p in 0..m {
            a[p * 2] = 2.0 + eps;
            if p > 0 {
                a[p * 2 + 1] = -1.0;
            }
        }
        assert!(ldl_band(&mut a, m, 1));
        let rhs: Vec<f64> = (0..m).map(|p| ((p * 7) % 5) as f64 - 2.0).collect();
        let mut x = rhs.clone();
        solve_band(&a, &mut x, 1);
        // Thomas.
        let (mut c, mut d) = (vec![0.0; m], vec![0.0; m]);
        for p in 0..m {
            let den = 2.0 + eps - if p > 0 { -c[p - 1] } else { 0.0 };
            c[p] = -1.0 / den;
            d[p] = (rhs[p] + if p > 0 { d[p - 1] } else { 0.0 }) / den;
        }
        let mut t = vec![0.0; m];
        for p in (0..m).rev() {
            t[p] = d[p] - c[p] * if p + 1 < m { t[p + 1] } else { 0.0 };
        }
        for p in 0..m {
            assert!((x[p] - t[p]).abs() <= 1e-12 * t.iter().map(|v| v.abs()).fold(0.0, f64::max), "{p}: {} vs {}", x[p], t[p]);
        }
    }

    #[test]
    fn banded_ldl_solves_a_pentadiagonal_system() {
        // A = B Bᵀ + I with B bidiagonal: pentadiagonal SPD; check A x = y.
        let m = 12;
        let full = |i: usize, j: usize| -> f64 {
            let bb = |i: usize, k: usize| if i == k { 2.0 } else if i == k + 1 { -1.0 } else { 0.0 };
            (0..m).map(|k| bb(i, k) * bb(j, k)).sum::<f64>() + if i == j { 1.0 } else { 0.0 }
        };
        let mut a = vec![0.0; m * 3];
        for p in 0..m {
            for q in 0..=2.min(p) {
                a[p * 3 + q] = full(p, p - q);
            }
        }
        assert!(ldl_band(&mut a, m, 2));
        let y: Vec<f64> = (0..m).map(|p| (p as f64).sin()).collect();
        let mut x = y.clone();
        solve_band(&a, &mut x, 2);
        for (i, yi) in y.iter().enumerate() {
            let ax: f64 = x.iter().enumerate().map(|(j, xj)| full(i, j) * xj).sum();
            assert!((ax - yi).abs() < 1e-12, "{i}: {ax} vs {yi}");
        }
    }
}
