//! A small coupled group solved whole on one rank: the group's finest level (every component's
//! rows, the slip frames, the classes of tied vertices) gathered onto rank 0 and factored there
//! with its coupling, as the serial coarsest solve factors Π A Π on the group's free directions.
//!
//! The per-component multigrids (`Multigrid`) are scalar: a group coupled by slip walls or
//! periodic links is otherwise preconditioned by each component's cycle followed by the
//! projection Π (`distributed::blocks`), which drops the coupling. Where each component's
//! finest level is small enough to be gathered at once (at most `GATHER_ROWS` unknowns per
//! component over all ranks), its scalar gathered solve is replaced by this one: Π A Π is
//! inverted on the subspace Π leaves, so the preconditioned conjugate gradients converge as
//! the serial solve's dense coarsest level does.
//!
//! Rank 0 assembles the group's operator A from the owners' rows of K (complete on each
//! owner): K itself for the Laplacian and the spring, K W K for the biharmonic, W the inverse
//! lumped mass (zero at Z; one merged source Σ (K x) / Σ V per class of tied vertices, as the
//! solver's operator merges it). Π is the slip frames' projection at each framed vertex
//! followed by the mean over each class (the two commute: a class's members have one frame),
//! a symmetric projector, and the matrix factored is Π A Π + σ (I − Π), positive definite when
//! A is positive on Π's range: its inverse on that range is (Π A Π)⁻¹, its complement is
//! scaled by σ (A's largest diagonal entry) so that neither part's rounding swamps the other.

use super::mover::Mover;
use super::GATHER_ROWS;
use crate::bc::{P, Z};
use crate::dense::Cholesky;
use crate::distributed::agreement::agree;
use crate::distributed::error::{DistError, DistErrorKind};
use crate::distributed::halo::HaloLayout;
use crate::distributed::reduce::{all_to_all, sum_in_rank_order};
use crate::distributed::ties::Ties;
use crate::multigrid::coarse_solve::symmetric_cholesky;
use crate::multigrid::group::GroupOp;
use crate::multigrid::layout::Layout;
use crate::operator::Method;
use std::collections::{BTreeMap, HashMap};

/// One group's gathered coupled solve, as one rank holds it.
pub(crate) struct CoupledSolve {
    /// This rank's unknowns (block, owned vertex), block by block: the order its values move in.
    free: Vec<(usize, usize)>,
    /// Every rank's unknowns' values onto rank 0 and back.
    mover: Mover,
    /// On rank 0: the dense position of each moved value.
    at: Vec<usize>,
    /// On rank 0, when the group has unknowns: Π and the factor.
    dense: Option<Dense>,
}

/// Rank 0's projector and factor.
struct Dense {
    /// Row a of Π: (column, weight).
    pi: Vec<Vec<(usize, f64)>>,
    chol: Cholesky,
}

/// One owned vertex as its owner sends it to rank 0.
struct Vertex {
    gid: u64,
    /// Its class of tied vertices (the class's lowest global id), or its own id.
    class: u64,
    inv_v: f64,
    /// Byte k: the flags of the group's block k.
    flags: u64,
    /// Its slip frame's constrained directions (none off the walls).
    dirs: Vec<[f64; 3]>,
    /// Its row of K: (column's global id, value).
    row: Vec<(u64, f64)>,
}

impl Vertex {
    fn flag(&self, k: usize) -> u8 {
        (self.flags >> (8 * k)) as u8
    }
}

impl CoupledSolve {
    /// The gathered solve of the group `op` on the solver's level (`gids` its local vertices'
    /// global ids, `halo` its layout, `ties` its classes of tied vertices), or None where the
    /// group has more than `GATHER_ROWS` unknowns per component over all ranks (collective;
    /// every rank returns the same result).
    pub(crate) fn new(
        op: &GroupOp,
        gids: &[u64],
        halo: &HaloLayout,
        ties: Option<&Ties>,
    ) -> Result<Option<CoupledSolve>, DistError> {
        let comm = halo.shared_comm().clone();
        let (owned, len) = (halo.owned(), op.len());
        let flags: Vec<&[u8]> = (0..len).map(|k| op.flags(k)).collect();
        let fl = &flags;
        let free: Vec<(usize, usize)> =
            (0..len).flat_map(|k| (0..owned).filter(move |&v| fl[k][v] & P == 0).map(move |v| (k, v))).collect();
        let total = sum_in_rank_order(&comm, &[free.len() as f64])[0];
        if total > (GATHER_ROWS as usize * len) as f64 {
            return Ok(None);
        }
        let level = op.level();
        let frames = op.frames();
        let mut words: Vec<u64> = vec![owned as u64];
        for v in 0..owned {
            let class = ties.and_then(|t| t.class_of(v)).unwrap_or(gids[v]);
            let flag_word = (0..len).fold(0u64, |w, k| w | u64::from(flags[k][v]) << (8 * k));
            let dirs = frames.and_then(|f| f.directions_of(v as u32)).unwrap_or(&[]);
            words.extend([gids[v], class, level.op.inv_v[v].to_bits(), flag_word, dirs.len() as u64]);
            words.extend(dirs.iter().flatten().map(|x| x.to_bits()));
            let (cols, vals) = level.op.k.row(v);
            words.push(cols.len() as u64);
            words.extend(cols.iter().zip(vals).flat_map(|(&j, &a)| [gids[j as usize], a.to_bits()]));
        }
        let mut send = vec![Vec::new(); comm.size()];
        send[0] = words;
        let received = all_to_all(&comm, &send);
        let assembled = if comm.rank() == 0 {
            let first = op.components().start;
            factor(&received, len, first, level.op.method)
        } else {
            Ok((Vec::new(), None))
        };
        let (at, dense) = agree(&comm, assembled)?;
        // Every rank sends to rank 0: the shift that takes the highest rank there.
        let shift = usize::BITS - (comm.size() - 1).leading_zeros();
        let mover = Mover::new(&comm, shift, free.len());
        Ok(Some(CoupledSolve { free, mover, at, dense }))
    }

    /// z = (Π A Π)⁻¹ r on the owned unknowns of the group's blocks (`n` entries each; the halo
    /// and the prescribed entries zero), from r's owned unknowns (collective).
    pub(crate) fn solve(&self, r: &[f64], z: &mut [f64], n: usize) {
        let mut mine: Vec<f64> = self.free.iter().map(|&(k, v)| r[k * n + v]).collect();
        let mut moved = vec![0.0; self.mover.len()];
        self.mover.gather(&mine, &mut moved);
        if let Some(d) = &self.dense {
            let mut rhs = vec![0.0; d.pi.len()];
            moved.iter().zip(&self.at).for_each(|(&v, &k)| rhs[k] = v);
            let mut y = d.project(&rhs);
            d.chol.solve(&mut y);
            let y = d.project(&y);
            moved.iter_mut().zip(&self.at).for_each(|(v, &k)| *v = y[k]);
        }
        self.mover.scatter(&moved, &mut mine);
        z.iter_mut().for_each(|v| *v = 0.0);
        self.free.iter().zip(&mine).for_each(|(&(k, v), &x)| z[k * n + v] = x);
    }
}

impl Dense {
    /// Π u.
    fn project(&self, u: &[f64]) -> Vec<f64> {
        self.pi.iter().map(|row| row.iter().map(|&(b, w)| w * u[b]).sum()).collect()
    }
}

/// The vertices of one rank's message (`CoupledSolve::new`), in its order; None if it is cut short.
fn vertices(words: &[u64]) -> Option<Vec<Vertex>> {
    let mut it = words.iter().copied();
    let mut next = || it.next();
    let count = next()?;
    let mut out = Vec::new();
    for _ in 0..count {
        let (gid, class, inv_v, flags, ndirs) = (next()?, next()?, f64::from_bits(next()?), next()?, next()?);
        let mut dirs = Vec::new();
        for _ in 0..ndirs {
            dirs.push([f64::from_bits(next()?), f64::from_bits(next()?), f64::from_bits(next()?)]);
        }
        let nnz = next()?;
        let mut row = Vec::new();
        for _ in 0..nnz {
            row.push((next()?, f64::from_bits(next()?)));
        }
        out.push(Vertex { gid, class, inv_v, flags, dirs, row });
    }
    Some(out)
}

/// On rank 0, from every rank's message: the dense position of each moved value and, when the
/// group has unknowns, Π and the factor of Π A Π + σ (I − Π) for the group of `len` blocks
/// from component `first` of `method`'s operator.
fn factor(
    received: &[Vec<u64>],
    len: usize,
    first: usize,
    method: Method,
) -> Result<(Vec<usize>, Option<Dense>), DistError> {
    let fail = |msg: String| DistError::new(0, DistErrorKind::Solve, msg);
    let messages: Vec<Vec<Vertex>> = received
        .iter()
        .map(|w| vertices(w))
        .collect::<Option<_>>()
        .ok_or_else(|| fail("a rank's rows of the coupled gathered level arrived cut short".into()))?;
    let mut all: Vec<&Vertex> = messages.iter().flatten().collect();
    all.sort_unstable_by_key(|v| v.gid);
    // The unknowns block by block, each in global id order.
    let mut position: HashMap<(usize, u64), usize> = HashMap::new();
    for k in 0..len {
        for v in all.iter().filter(|v| v.flag(k) & P == 0) {
            let next = position.len();
            position.insert((k, v.gid), next);
        }
    }
    let at: Vec<usize> = messages
        .iter()
        .flat_map(|m| (0..len).flat_map(move |k| m.iter().filter(move |v| v.flag(k) & P == 0).map(move |v| (k, v.gid))))
        .map(|key| position[&key])
        .collect();
    let m = position.len();
    if m == 0 {
        return Ok((at, None));
    }
    let unknown = |k: usize, g: u64| position.get(&(k, g)).copied();
    let g = operator(&all, len, method, m, &unknown);
    let pi = projector(&all, len, first, &unknown);
    let mut a = projected(&g, &pi, m);
    let sigma = (0..m).map(|i| g[i * m + i].abs()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    for (i, row) in pi.iter().enumerate() {
        a[i * m + i] += sigma;
        row.iter().for_each(|&(j, w)| a[i * m + j] -= sigma * w);
    }
    let chol = symmetric_cholesky(m, a)
        .ok_or_else(|| fail(format!("the coupled gathered level ({m} unknowns) is not positive definite")))?;
    Ok((at, Some(Dense { pi, chol })))
}

/// The group's operator A (dense, m × m): per block k, K on its unknowns, or for the
/// biharmonic K W K with W the inverse lumped mass off Z, one merged source per class.
fn operator(
    all: &[&Vertex],
    len: usize,
    method: Method,
    m: usize,
    unknown: &impl Fn(usize, u64) -> Option<usize>,
) -> Vec<f64> {
    let mut g = vec![0.0; m * m];
    for k in 0..len {
        if method != Method::Biharmonic {
            for v in all {
                let Some(i) = unknown(k, v.gid) else { continue };
                for &(c, a) in &v.row {
                    if let Some(j) = unknown(k, c) {
                        g[i * m + j] += a;
                    }
                }
            }
            continue;
        }
        // Per source (a class, or a vertex of its own): its summed mass and the entries its
        // members' rows of K have on the block's unknowns (K symmetric: K_im from row m).
        let mut sources: BTreeMap<u64, (f64, Vec<(usize, f64)>)> = BTreeMap::new();
        for v in all.iter().filter(|v| v.flag(k) & Z == 0) {
            let s = sources.entry(v.class).or_default();
            s.0 += 1.0 / v.inv_v;
            s.1.extend(v.row.iter().filter_map(|&(c, a)| unknown(k, c).map(|j| (j, a))));
        }
        for (mass, entries) in sources.values() {
            for &(i, x) in entries {
                for &(j, y) in entries {
                    g[i * m + j] += x * y / mass;
                }
            }
        }
    }
    g
}

/// Π's rows: at unknown (k, v), the slip projection I − Σ e eᵀ of v's frame (components
/// `first + k`) spread over v's class with weight 1 / its size.
fn projector(
    all: &[&Vertex],
    len: usize,
    first: usize,
    unknown: &impl Fn(usize, u64) -> Option<usize>,
) -> Vec<Vec<(usize, f64)>> {
    let mut members: HashMap<u64, Vec<u64>> = HashMap::new();
    all.iter().for_each(|v| members.entry(v.class).or_default().push(v.gid));
    let mut rows: Vec<(usize, Vec<(usize, f64)>)> = Vec::new();
    for v in all {
        let class = &members[&v.class];
        let share = 1.0 / class.len() as f64;
        for k in 0..len {
            let Some(a) = unknown(k, v.gid) else { continue };
            let mut row = Vec::new();
            for kk in 0..len {
                let along: f64 = v.dirs.iter().map(|e| e[first + k] * e[first + kk]).sum();
                let s = f64::from(u8::from(k == kk)) - along;
                if s == 0.0 {
                    continue;
                }
                row.extend(class.iter().filter_map(|&w| unknown(kk, w)).map(|b| (b, s * share)));
            }
            rows.push((a, row));
        }
    }
    rows.sort_unstable_by_key(|r| r.0);
    rows.into_iter().map(|r| r.1).collect()
}

/// Π G Π (dense, m × m) for the symmetric projector Π given by its rows.
fn projected(g: &[f64], pi: &[Vec<(usize, f64)>], m: usize) -> Vec<f64> {
    // H = G Π: Π's column b is its row b.
    let mut h = vec![0.0; m * m];
    for (b, row) in pi.iter().enumerate() {
        for &(d, w) in row {
            (0..m).for_each(|i| h[i * m + b] += g[i * m + d] * w);
        }
    }
    let mut out = vec![0.0; m * m];
    for (a, row) in pi.iter().enumerate() {
        for &(c, w) in row {
            let (dst, src) = (&mut out[a * m..(a + 1) * m], &h[c * m..(c + 1) * m]);
            dst.iter_mut().zip(src).for_each(|(o, x)| *o += w * x);
        }
    }
    out
}
