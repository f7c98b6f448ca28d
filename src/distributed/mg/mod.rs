//! The distributed multigrid: a hierarchy of kept-unknowns levels built across ranks from a
//! symmetric operator given as each rank's owned rows, and its cycle as the preconditioner of
//! the distributed conjugate gradients (`distributed::pcg`).
//!
//! Each level is a rank's owned rows over its local columns (owned, then a halo) with its own
//! exchange lists. Coarsening keeps an independent set of the strong-coupling graph chosen by
//! priorities from the global ids (`select`), interpolates the other unknowns by the serial kept
//! levels' donor rule and least-squares fit over two rings of the operator at the unknowns'
//! positions (`donors`; the operator's own weights, `interpolate`, where no bounded fit exists),
//! and forms the coarse operator as the Galerkin product Pᵀ A P across ranks (`galerkin`), so no
//! coarse level needs a mesh: the Laplacian's and the spring's levels, as serially.
//! The biharmonic's levels follow K's coarsening instead, interpolated by the same rule on K's
//! graph (`donors`), each A = K V⁻¹ K assembled across ranks (`biharmonic`; under wall layers
//! from the first coarse level on the Galerkin product of the level above, and in 2D rows along
//! the lines, `along_lines`), and its cycle is a W-cycle. A coarse level with few unknowns per rank
//! is moved onto fewer ranks, which carry it and the levels below on a communicator of their
//! own (`agglomerate`, with the values moved by `mover`); once a level is small it is gathered
//! onto one rank and solved there by a dense factor (`gathered`). The smoother is the serial multigrid's Chebyshev–Jacobi smoother on owned rows,
//! run through the level's `GroupOp` and halo layout.

#[cfg(test)]
mod against_serial;
mod agglomerate;
mod along_lines;
mod biharmonic;
mod coupled;
mod donors;
mod galerkin;
mod gathered;
mod interpolate;
mod lines;
mod mover;
mod select;

use super::agreement::agree;
use super::comm::Comm;
use super::error::{DistError, DistErrorKind};
use super::halo::HaloLayout;
use super::level_layout::Distribution;
use super::pcg::Preconditioner;
use super::reduce::{gather, max_over_ranks, sum_in_rank_order};
use crate::bc::{Dofs, P, Z};
use crate::multigrid::group::{estimate_lambda_max, GroupOp, Scratch};
use crate::multigrid::layout::Layout;
use crate::multigrid::level::{Level, Transfer};
use crate::multigrid::line_smoother::band_of;
use crate::multigrid::lines::Lines;
use crate::multigrid::restriction::Restriction;
use crate::multigrid::smoother::{smooth, Coefficients, Smoother, Start};
use crate::operator::{assembled_below, LevelOperator, Method};
use crate::sparse::{par_update, CsrMatrix};
use agglomerate::{halvings, Agglomeration, Landing};
pub(crate) use biharmonic::{biharmonic_rows, Guide};
pub(crate) use coupled::CoupledSolve;
pub(crate) use donors::Positions;
use gathered::Gathered;
pub(crate) use lines::owned_lines;
use std::sync::Arc;

/// A level of this many unknowns over all ranks, or fewer, is gathered onto one rank and solved
/// there directly: its dense factor is cheap, and below it the smoothed levels would do little
/// local work per message.
const GATHER_ROWS: u64 = 400;

/// A coarse level with fewer unknowns than this per rank is moved onto fewer ranks
/// (`agglomerate`): below a few hundred a rank's smoothing of a level costs less than the
/// latency of its messages to its neighbours, and a level moved onto fewer ranks adds their
/// work to each of them, so the threshold sits where the weak-scaling model of
/// docs/PERFORMANCE.md finds an iteration cheapest.
pub(crate) const ROWS_PER_RANK: u64 = 200;

/// A coarse level that keeps more than this share of its fine level's unknowns ends the
/// coarsening: another level would cost nearly as much as the one above it.
const MIN_REDUCTION: f64 = 0.85;

/// A symmetric operator over one level's vectors: a rank's owned rows over its local columns
/// (owned entries first, then the halo); the rows past the owned ones are empty, as is the row
/// of an owned unknown that is prescribed (kept out of the solve).
pub(crate) struct OwnedRows {
    /// Local entries × local entries.
    pub(crate) a: CsrMatrix,
    /// The global id of each local entry (unique over all ranks).
    pub(crate) gids: Vec<u64>,
    pub(crate) halo: Arc<HaloLayout>,
}

/// What a hierarchy's coarse levels are made from besides the finest level's rows.
pub(crate) enum Coarsening {
    /// The Galerkin product of the level above, interpolated by the serial donor rule at the
    /// positions of the level's local entries (`donors`): the Laplacian's and the spring's
    /// levels, as their serial kept levels are made.
    Galerkin(Positions),
    /// The biharmonic's guide (`biharmonic::coarsen`).
    Guide(Guide),
}

/// The smoothers of the finest level and of every coarser one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Smoothers {
    pub(crate) fine: Smoother,
    pub(crate) coarse: Smoother,
}

impl Smoothers {
    /// The smoother of level `l`.
    fn at(&self, l: usize) -> Smoother {
        if l == 0 {
            self.fine
        } else {
            self.coarse
        }
    }
}

/// One level of the distributed hierarchy: the smoother's view of it (`Level`, with the
/// transfer to the next coarser level) and its exchange lists.
struct DistLevel {
    level: Level,
    /// The global id of each local entry (`against_serial` maps the levels by it).
    #[cfg(test)]
    gids: Vec<u64>,
    halo: Arc<HaloLayout>,
    /// The digest of this rank's owned rows of the prolongation to the next coarser level
    /// (`transfer_digest`; 0 on the coarsest).
    digest: u64,
    /// When the next coarser level is agglomerated onto fewer ranks: the layout the
    /// prolongation's columns refer to on this level's ranks, and the move onto those ranks.
    landing: Option<Arc<Landing>>,
}

/// How the coarsest level is solved.
enum Coarsest {
    /// Gathered on every rank and factored.
    Gathered(Gathered),
    /// Too large to gather (coarsening stopped early): a fixed number of smoothing sweeps, a
    /// fixed symmetric operator, so still a valid preconditioner.
    Smoothed,
}

/// Vectors of one level's visit; the finest level's right-hand side and iterate are the
/// caller's, so its `b` and `x` stay empty.
struct Work {
    b: Vec<f64>,
    x: Vec<f64>,
    r: Vec<f64>,
    scratch: Vec<Scratch>,
    coefficients: Coefficients,
    /// A later visit's right-hand side and correction (a W-cycle's coarse levels).
    again: (Vec<f64>, Vec<f64>),
    /// The restricted residual and the correction in the next level's landing layout, when
    /// that level is agglomerated onto fewer ranks.
    landing: (Vec<f64>, Vec<f64>),
}

/// The size of one level over all ranks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct LevelSize {
    /// Unknowns over all ranks (the finest level's prescribed vertices are not unknowns).
    pub(crate) rows: u64,
    /// Values all ranks send per halo exchange of one vector.
    pub(crate) halo_values: u64,
    /// Messages all ranks send per halo exchange (one per rank and neighbour it sends to).
    pub(crate) messages: u64,
    /// Ranks that hold the level (fewer than all where it is agglomerated).
    pub(crate) ranks: u64,
    /// A digest of the prolongation from the next coarser level over all ranks
    /// (`transfer_digest`): the same on every partition and rank count when P is.
    pub(crate) transfer: u64,
}

/// The distributed multigrid preconditioner: its levels, its coarsest solve, its smoother and
/// the scratch of its cycles.
pub(crate) struct Multigrid {
    /// The levels this rank holds, finest first: all of them, or those above the level at
    /// which its rows were agglomerated onto another rank.
    levels: Vec<DistLevel>,
    /// The coarsest level's solve, on the ranks that hold it.
    coarsest: Option<Coarsest>,
    /// Levels over all ranks.
    depth: usize,
    /// The coarsest level is gathered onto one rank (else it is smoothed).
    gathered: bool,
    /// The finest level's communicator, over which the sizes are reported.
    comm: Arc<Comm>,
    smoothers: Smoothers,
    /// Coarse visits per level: 1 a V-cycle, 2 a W-cycle.
    visits: usize,
    work: Vec<Work>,
    /// The finest level's right-hand side and iterate when the caller's vectors have another
    /// halo (`Preconditioner::apply`).
    entry: (Vec<f64>, Vec<f64>),
}

impl Multigrid {
    /// Builds the hierarchy of the operator `fine` with at most `max_levels` levels (the gathered
    /// one included), smoothed by `smoothers`, its coarse levels moved onto fewer ranks below
    /// `per_rank` unknowns per rank (collective; every rank returns the same result).
    ///
    /// With `Coarsening::Guide` (the biharmonic's K, V and positions beside its A = K V⁻¹ K) each
    /// coarse level is made from the guide's (`biharmonic::coarsen`; under lines from the first
    /// coarse level on the Galerkin product of the level above, `assembled_below`); with
    /// `Coarsening::Galerkin`, by the Galerkin product of the level above. `lines` are the
    /// finest level's lines across wall layers over its owned unknowns (`owned_lines`; none on
    /// meshes without such layers), smoothed as blocks there and on the coarse levels that keep
    /// them (`lines`).
    pub(crate) fn build(
        fine: OwnedRows,
        coarsening: Coarsening,
        lines: Lines,
        max_levels: usize,
        smoothers: Smoothers,
        per_rank: u64,
    ) -> Result<Multigrid, DistError> {
        let comm = fine.halo.shared_comm().clone();
        // The biharmonic's coarse operators K_c V_c⁻¹ K_c are softer than the Galerkin product of
        // the level above, so one coarse visit corrects too little: the W-cycle's second visit
        // makes it up, as in the serial cycle. The Galerkin levels need no second visit: with the
        // donor rule their V-cycle takes as few iterations as a W-cycle (docs/perf-history.md).
        let visits = if matches!(coarsening, Coarsening::Guide(_)) { 2 } else { 1 };
        // A failure on the ranks of an agglomerated level reaches the ranks idle below it here,
        // where every rank of the finest level meets again.
        let (levels, coarsest) = agree(&comm, levels_of(fine, coarsening, lines, max_levels, per_rank))?;
        // Rank 0 holds every level (it receives the rows of every agglomeration).
        let gathers = matches!(coarsest, Some(Coarsest::Gathered(_)));
        let shape = gather(&comm, &[levels.len() as u64, u64::from(gathers)]);
        let (depth, gathered) = (shape[0] as usize, shape[1] == 1);
        let work = levels.iter().enumerate().map(|(l, d)| work(d, l == 0)).collect();
        let entry = Default::default();
        Ok(Multigrid { levels, coarsest, depth, gathered, comm, smoothers, visits, work, entry })
    }

    /// Unknowns, halo values and ranks per level, finest first (collective).
    pub(crate) fn sizes(&self) -> Vec<LevelSize> {
        let mut mine = vec![0.0; 4 * self.depth];
        for (d, m) in self.levels.iter().zip(mine.chunks_exact_mut(4)) {
            m.copy_from_slice(&[
                unknowns(&d.level.op.k, d.halo.owned()) as f64,
                d.halo.sent_per_exchange() as f64,
                d.halo.send_lists().len() as f64,
                1.0,
            ]);
        }
        let all = sum_in_rank_order(&self.comm, &mine);
        let mut digests = vec![0u64; self.depth];
        digests.iter_mut().zip(&self.levels).for_each(|(d, l)| *d = l.digest);
        let mut transfer = vec![0u64; self.depth];
        for rank in gather(&self.comm, &digests).chunks_exact(self.depth.max(1)) {
            transfer.iter_mut().zip(rank).for_each(|(t, &d)| *t = t.wrapping_add(d));
        }
        all.chunks_exact(4)
            .zip(transfer)
            .map(|(a, transfer)| LevelSize {
                rows: a[0] as u64,
                halo_values: a[1] as u64,
                messages: a[2] as u64,
                ranks: a[3] as u64,
                transfer,
            })
            .collect()
    }

    /// Whether the coarsest level is gathered onto one rank (else it is smoothed).
    pub(crate) fn gathers(&self) -> bool {
        self.gathered
    }

    /// x = B b on level `l` from a zero start: one V- or W-cycle (collective over the level's
    /// ranks and those idle below it).
    fn cycle(&mut self, l: usize, b: &[f64], x: &mut [f64]) {
        let lev = &self.levels[l];
        let op = GroupOp::new(&lev.level, 0..1, false);
        let sm = self.smoothers.at(l);
        if lev.level.down.is_none() {
            match &self.coarsest {
                Some(Coarsest::Gathered(g)) => g.solve(b, x),
                Some(Coarsest::Smoothed) | None => {
                    let w = &mut self.work[l];
                    let mut start = Start::Zero;
                    for _ in 0..COARSEST_SWEEPS {
                        smooth(&op, sm, b, x, &mut w.scratch, &mut w.coefficients, start, false);
                        start = Start::Guess;
                    }
                }
            }
            return;
        }
        let w = &mut self.work[l];
        smooth(&op, sm, b, x, &mut w.scratch, &mut w.coefficients, Start::Zero, false);
        self.correct(l, b, x);
        let op = GroupOp::new(&self.levels[l].level, 0..1, false);
        let w = &mut self.work[l];
        smooth(&op, sm, b, x, &mut w.scratch, &mut w.coefficients, Start::Guess, false);
    }

    /// x ← x + P x_c on level `l`, x_c from the coarser level's system A_c x_c = Pᵀ (b − A x)
    /// (`visit`), moved there and back when it is agglomerated onto fewer ranks; a rank that
    /// does not hold it only sends its part and receives its correction (collective).
    fn correct(&mut self, l: usize, b: &[f64], x: &mut [f64]) {
        let lev = &self.levels[l];
        if lev.level.down.is_none() {
            return;
        }
        let op = GroupOp::new(&lev.level, 0..1, false);
        let w = &mut self.work[l];
        op.residual(b, x, &mut w.r, &mut w.scratch[0].s);
        self.correct_residual(l, x);
    }

    /// x = P x_c with x_c one visit of the next coarser level to Pᵀ r: the cycle's coarse
    /// correction of a residual `r` formed by the caller on the finest level (its owned entries
    /// read; x's halo left zero); x = 0 for a hierarchy of one level (collective).
    pub(crate) fn coarse_correction(&mut self, r: &[f64], x: &mut [f64]) {
        let (owned, n) = (self.levels[0].halo.owned(), self.levels[0].level.n());
        let w = &mut self.work[0];
        w.r[..owned].copy_from_slice(&r[..owned]);
        w.r[owned..].iter_mut().for_each(|v| *v = 0.0);
        let mut x0 = std::mem::take(&mut self.entry.1);
        x0.clear();
        x0.resize(n, 0.0);
        if self.levels[0].level.down.is_some() {
            self.correct_residual(0, &mut x0);
        }
        x[..owned].copy_from_slice(&x0[..owned]);
        x[owned..].iter_mut().for_each(|v| *v = 0.0);
        self.entry.1 = x0;
    }

    /// x ← x + P x_c on level `l` from its residual in `work[l].r` (see `correct`).
    fn correct_residual(&mut self, l: usize, x: &mut [f64]) {
        let lev = &self.levels[l];
        let Some(down) = &lev.level.down else {
            return;
        };
        let (prolong, landing) = (down.prolong.clone(), lev.landing.clone());
        let held = l + 1 < self.levels.len();
        let (mut bc, mut xc) = if held {
            (std::mem::take(&mut self.work[l + 1].b), std::mem::take(&mut self.work[l + 1].x))
        } else {
            Default::default()
        };
        let coarse = match &landing {
            Some(landing) => {
                let (mut lb, mut lx) = std::mem::take(&mut self.work[l].landing);
                down.restrict.mul_vec(&self.work[l].r, &mut lb);
                // Pᵀ r: the contributions to coarse halo entries belong to their owners, whose
                // owned entries then move onto the agglomerated level's ranks.
                landing.layout.add_to_owners(&mut lb);
                landing.mover.gather(&lb, &mut bc);
                if held {
                    let owned = self.levels[l + 1].halo.owned();
                    bc[owned..].iter_mut().for_each(|v| *v = 0.0);
                    self.visit(l + 1, &bc, &mut xc);
                }
                landing.mover.scatter(&xc, &mut lx);
                landing.layout.refresh(&mut lx);
                self.work[l].landing.0 = lb;
                lx
            }
            None => {
                down.restrict.mul_vec(&self.work[l].r, &mut bc);
                let coarse_halo = self.levels[l + 1].halo.clone();
                coarse_halo.add_to_owners(&mut bc);
                bc[coarse_halo.owned()..].iter_mut().for_each(|v| *v = 0.0);
                self.visit(l + 1, &bc, &mut xc);
                coarse_halo.refresh(&mut xc);
                std::mem::take(&mut xc)
            }
        };
        // x ← x + P x_c on the owned unknowns (P's rows of the halo and prescribed are empty).
        let flags = &self.levels[l].level.flags[0];
        par_update(x, |i, xv| if flags[i] & P != 0 { xv } else { xv + prolong.row_dot(i, &coarse) });
        if landing.is_some() {
            self.work[l].landing.1 = coarse;
        } else {
            xc = coarse;
        }
        if held {
            self.work[l + 1].b = bc;
            self.work[l + 1].x = xc;
        }
    }

    /// x_c from `visits` cycles on level `l`'s system A x = b, each from the residual the
    /// previous left (collective over the level's ranks).
    fn visit(&mut self, l: usize, b: &[f64], x: &mut [f64]) {
        self.cycle(l, b, x);
        // A coarsest level solved exactly leaves nothing for a second visit.
        let exact = l + 1 == self.depth && self.gathered;
        for _ in 1..if exact { 1 } else { self.visits } {
            let (mut rc, mut dx) = std::mem::take(&mut self.work[l].again);
            let op = GroupOp::new(&self.levels[l].level, 0..1, false);
            op.residual(b, x, &mut rc, &mut self.work[l].scratch[0].s);
            self.cycle(l, &rc, &mut dx);
            x.iter_mut().zip(&dx).for_each(|(x, d)| *x += d);
            self.work[l].again = (rc, dx);
        }
    }
}

/// The levels of `fine` this rank holds and, on the ranks that hold the coarsest level, its
/// solve (collective over the ranks of each level; see `Multigrid::build`).
fn levels_of(
    fine: OwnedRows,
    coarsening: Coarsening,
    lines: Lines,
    max_levels: usize,
    per_rank: u64,
) -> Result<(Vec<DistLevel>, Option<Coarsest>), DistError> {
    let mut levels = Vec::new();
    // The biharmonic's guide, or the positions of the current level's local entries.
    let (mut guide, mut at) = match coarsening {
        Coarsening::Guide(g) => (Some(g), None),
        Coarsening::Galerkin(at) => (None, Some(at)),
    };
    // The biharmonic's rows couple two neighbours along a line.
    let band = band_of(if guide.is_some() { Method::Biharmonic } else { Method::Laplacian });
    // The segments the rows along the lines join across ranks (`lines::kept_segments`), of which
    // the smoother's lines are those of two or more unknowns (`lines::smoothed`).
    let mut segments = lines.clone();
    let (mut current, mut lines) = (fine, lines);
    // The current level's operator is the assembled Galerkin product of the level above.
    let mut assembled = false;
    // The biharmonic's hierarchies with lines on their finest level (asked on every rank): in 2D
    // they interpolate along the lines on every level, as serially (`multigrid::lsq`).
    let layered = guide.is_some() && any_lines(current.halo.comm(), &lines);
    let along = layered && guide.as_ref().is_some_and(|g| g.at.dim == 2);
    loop {
        let rows = global_rows(&current);
        let last = rows <= GATHER_ROWS || levels.len() + 1 >= max_levels.max(1);
        let coarse = match (&guide, last) {
            (_, true) => None,
            (None, false) => galerkin_level(&current, &mut at)?,
            (Some(g), false) => {
                // The serial rule on the level's lines over all its ranks (collective over them;
                // asked only where it decides).
                // Under wall layers the first coarse level is assembled too, where the serial
                // hierarchy keeps K_c V_c⁻¹ K_c: the distributed levels leave the prescribed
                // vertices out, so their K_c V_c⁻¹ K_c holds S at zero next to a CLAMPED wall,
                // where the layers are (docs/DESIGN.md §5, "Wall layers across ranks").
                let kept = layered || !levels.is_empty();
                let lined = kept && !assembled && any_lines(current.halo.comm(), &lines);
                let below = assembled_below(kept, lined, assembled);
                match biharmonic::coarsen(&current, g, below, along.then_some(&segments))? {
                    Some((next, prolong, next_guide)) => {
                        guide = Some(next_guide);
                        assembled = below;
                        Some((next, prolong))
                    }
                    None => None,
                }
            }
        };
        let Some((next, prolong)) = coarse else {
            return coarsest((current, lines, band), rows, levels);
        };
        let next_rows = global_rows(&next);
        if next_rows as f64 >= MIN_REDUCTION * rows as f64 {
            return coarsest((current, lines, band), rows, levels);
        }
        let next_segments = lines::kept_segments(&segments, &current.gids, &next);
        let next_lines = lines::smoothed(&next_segments);
        // A level small enough to gather goes onto one rank by its own solve.
        let ranks = next.halo.comm().size();
        let shift = if next_rows <= GATHER_ROWS { 0 } else { halvings(next_rows, ranks, per_rank) };
        let digest = transfer_digest(&prolong, &current, &next.gids);
        if shift == 0 {
            levels.push(dist_level((current, lines, band), Some((prolong, digest)), None));
            (current, lines, segments) = (next, next_lines, next_segments);
            continue;
        }
        let agglomeration = Agglomeration::new(next.halo.comm(), shift);
        let landing = agglomeration.landing(&next);
        // Everything over the level's ranks first (its rows, the guide's rows and masses), then
        // the receiving ranks' own work, so that a failure among them leaves no rank waiting.
        let sent = agglomeration.send(&next);
        let sent_guide = guide.take().map(|g| {
            let mut mass = vec![0.0; landing.mover.len()];
            landing.mover.gather(&g.mass[..landing.mover.count()], &mut mass);
            (agglomeration.send(&g.k), mass, g.at.moved(&landing.mover))
        });
        let moved_at = at.take().map(|a| a.moved(&landing.mover));
        let moved_segments = lines::moved_lines(&next_segments, &landing.mover, next.halo.comm().rank());
        let moved_lines = lines::smoothed(&moved_segments);
        levels.push(dist_level((current, lines, band), Some((prolong, digest)), Some(Arc::new(landing))));
        let Some(moved) = agglomeration.assemble(&sent)? else {
            return Ok((levels, None));
        };
        if let Some((sent, mut mass, mut at)) = sent_guide {
            let k = agglomeration.assemble(&sent)?.ok_or_else(|| lost(&moved))?;
            mass.resize(k.halo.len(), 0.0);
            k.halo.refresh(&mut mass);
            at.coords.resize(k.halo.len(), [0.0; 3]);
            at.refresh(&k.halo);
            guide = Some(Guide { k, mass, at });
        }
        if let Some(mut a) = moved_at {
            a.coords.resize(moved.halo.len(), [0.0; 3]);
            a.refresh(&moved.halo);
            at = Some(a);
        }
        (current, lines, segments) = (moved, moved_lines, moved_segments);
    }
}

/// The next coarser level of `m` and the prolongation to it, as the serial kept levels of the
/// Laplacian and the spring are made: P's rows by the serial donor rule at the positions `at` of
/// `m`'s local entries (`donors`), the coarse operator the Galerkin product Pᵀ m P; `at` becomes
/// the coarse level's positions. None when no rank keeps an unknown (collective).
fn galerkin_level(m: &OwnedRows, at: &mut Option<Positions>) -> Result<Option<(OwnedRows, CsrMatrix)>, DistError> {
    let Some(here) = at.as_ref() else {
        return Ok(None);
    };
    let rows = donors::interpolation(m, here, None)?;
    let Some((next, prolong)) = galerkin::product(m, &rows)? else {
        return Ok(None);
    };
    *at = Some(biharmonic::coarse_positions(m, here, &next)?);
    Ok(Some((next, prolong)))
}

/// The coarsest level `m` (`rows` unknowns over its ranks) after `levels`, and its solve
/// (collective over its ranks).
fn coarsest(
    (m, lines, band): (OwnedRows, Lines, usize),
    rows: u64,
    mut levels: Vec<DistLevel>,
) -> Result<(Vec<DistLevel>, Option<Coarsest>), DistError> {
    let coarsest = if rows <= GATHER_ROWS { Coarsest::Gathered(Gathered::new(&m)?) } else { Coarsest::Smoothed };
    levels.push(dist_level((m, lines, band), None, None));
    Ok((levels, Some(coarsest)))
}

/// A receiving rank without the guide's rows, which the level's move sent with it: cannot occur.
fn lost(m: &OwnedRows) -> DistError {
    let me = m.halo.comm().rank();
    DistError::new(me, DistErrorKind::Solve, format!("rank {me} lost the agglomerated guide"))
}

/// Smoothing sweeps of a coarsest level too large to gather.
const COARSEST_SWEEPS: usize = 4;

impl Preconditioner for Multigrid {
    /// One cycle. The caller's vectors share the finest level's owned entries; their halo may
    /// differ (the biharmonic's assembled rows reach two rings of vertices, the solve's one), so
    /// then the owned entries are copied in and out. z's halo is not the owners' values (zero
    /// after a gathered solve): the operator exchanges it before reading it.
    fn apply(&mut self, r: &[f64], z: &mut [f64]) {
        let n = self.levels[0].level.n();
        if r.len() == n {
            return self.cycle(0, r, z);
        }
        let owned = self.levels[0].halo.owned();
        let (mut b, mut x) = std::mem::take(&mut self.entry);
        b.clear();
        b.extend_from_slice(&r[..owned]);
        b.resize(n, 0.0);
        x.resize(n, 0.0);
        self.cycle(0, &b, &mut x);
        z[..owned].copy_from_slice(&x[..owned]);
        z[owned..].iter_mut().for_each(|v| *v = 0.0);
        self.entry = (b, x);
    }
}

/// Whether some rank of `comm` has `lines` on it (collective).
pub(crate) fn any_lines(comm: &Comm, lines: &Lines) -> bool {
    max_over_ranks(comm, f64::from(u8::from(!lines.is_empty()))) > 0.0
}

/// Unknowns of `m` over all ranks: owned rows that are not empty (collective).
fn global_rows(m: &OwnedRows) -> u64 {
    sum_in_rank_order(m.halo.comm(), &[unknowns(&m.a, m.halo.owned()) as f64])[0] as u64
}

/// The rows of `a` among its first `owned` that are not empty.
fn unknowns(a: &CsrMatrix, owned: usize) -> usize {
    (0..owned).filter(|&i| !a.row(i).0.is_empty()).count()
}

/// A digest of the owned rows of `p` (`fine`'s local entries × the local entries of the coarse
/// level whose global ids are `coarse`): each entry's fine and coarse global ids and its weight
/// to 2⁻³⁰ hashed, the hashes added, so that it depends on P's rows in global terms and not on
/// which rank holds them.
fn transfer_digest(p: &CsrMatrix, fine: &OwnedRows, coarse: &[u64]) -> u64 {
    let mut digest = 0u64;
    for i in 0..fine.halo.owned() {
        let (cols, w) = p.row(i);
        for (&c, &w) in cols.iter().zip(w) {
            let q = (w * f64::from(1u32 << 30)).round() as i64 as u64;
            let g = coarse.get(c as usize).copied().unwrap_or(u64::MAX);
            digest = digest.wrapping_add(select::mix(select::mix(fine.gids[i]) ^ g).wrapping_add(q));
        }
    }
    digest
}

/// The smoother's level of `m` (its empty rows and its halo prescribed, so neither is smoothed
/// nor read as an unknown) with its `lines` (blocks of `band`) and the transfer `prolong` to the
/// next coarser level with its digest (collective: the smoother's bound is estimated over every
/// rank's rows).
fn dist_level(
    (m, lines, band): (OwnedRows, Lines, usize),
    prolong: Option<(CsrMatrix, u64)>,
    landing: Option<Arc<Landing>>,
) -> DistLevel {
    let OwnedRows { a, halo, gids: _gids } = m;
    let (n, owned) = (halo.len(), halo.owned());
    let flags: Vec<u8> = (0..n).map(|i| if i >= owned || a.row(i).0.is_empty() { P | Z } else { 0 }).collect();
    let op = LevelOperator::from_matrix(Method::Laplacian, a);
    let inv_d = vec![op.inv_l1_diag(&flags)];
    let digest = prolong.as_ref().map_or(0, |p| p.1);
    let down = prolong.map(|(p, _)| {
        let prolong = Arc::new(p);
        Transfer { restrict: Restriction::new(prolong.clone()), prolong }
    });
    let mut level = Level {
        mesh: None,
        points: Vec::new(),
        pairs: Vec::new(),
        dofs: Dofs::identity(n),
        op,
        flags: vec![flags],
        inv_d,
        lambda_max: vec![1.0],
        lines: Default::default(),
        parent_vertex: Vec::new(),
        down,
        slip: None,
        layout: Distribution::Halo(halo.clone()),
    };
    lines::attach(&mut level, lines, band);
    level.lambda_max = vec![estimate_lambda_max(&GroupOp::new(&level, 0..1, false))];
    DistLevel {
        level,
        #[cfg(test)]
        gids: _gids,
        halo,
        digest,
        landing,
    }
}

/// The vectors of a visit to `d` (`finest`: its b and x are the caller's).
fn work(d: &DistLevel, finest: bool) -> Work {
    let n = d.level.n();
    let nl = d.landing.as_ref().map_or(0, |l| l.layout.len());
    let nbx = if finest { 0 } else { n };
    Work {
        b: vec![0.0; nbx],
        x: vec![0.0; nbx],
        r: vec![0.0; n],
        scratch: vec![Scratch::new(n, Method::Laplacian)],
        coefficients: Coefficients::default(),
        again: (vec![0.0; nbx], vec![0.0; nbx]),
        landing: (vec![0.0; nl], vec![0.0; nl]),
    }
}
