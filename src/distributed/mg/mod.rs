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
//! graph (`donors`), each A = K V⁻¹ K assembled across ranks (`biharmonic`; below the second coarse
//! level, and under wall layers, the Galerkin product of the level above, in 2D from the first
//! coarse level on with rows along the lines, `along_lines`), and its cycle is a W-cycle. A coarse
//! level with few unknowns per rank is moved onto fewer ranks, which carry it and the levels below
//! on a communicator of their own (`agglomerate`, with the values moved by `mover`); once a level
//! is small it is gathered onto one rank and solved there by a dense factor (`gathered`). With slip
//! walls one hierarchy carries every component (`Multigrid::build_group`): each level keeps each
//! component's flags and the slip frames its unknowns inherit, each group of components is smoothed
//! with its projection on every level and its coarsest level is factored coupled (`coupled`). The
//! smoother is the serial multigrid's Chebyshev–Jacobi smoother on owned rows, run through the
//! level's `GroupOp` and halo layout.

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
use crate::bc::{inherit_slip_frames, Dofs, SlipFrames, P, Z};
use crate::multigrid::group::{block, block_mut, estimate_lambda_max, GroupOp, Scratch};
use crate::multigrid::hierarchy::layered_lines;
use crate::multigrid::layout::Layout;
use crate::multigrid::level::{Level, LevelSlip, Transfer};
use crate::multigrid::line_smoother::band_of;
use crate::multigrid::lines::Lines;
use crate::multigrid::restriction::Restriction;
use crate::multigrid::slip::equalise_bounds;
use crate::multigrid::smoother::{smooth, Coefficients, Smoother, Start};
use crate::operator::{assembled_below, LevelOperator, Method};
use crate::sparse::{par_update, CsrMatrix};
use agglomerate::{halvings, Agglomeration, Landing};
use biharmonic::Product;
pub(crate) use biharmonic::{biharmonic_rows, Guide};
pub(crate) use coupled::CoupledSolve;
pub(crate) use donors::Positions;
use gathered::Gathered;
pub(crate) use lines::owned_lines;
use std::collections::HashMap;
use std::ops::Range;
use std::sync::Arc;

/// A level of this many unknowns over all ranks, or fewer, is gathered onto one rank and solved
/// there directly: its dense factor is cheap, and below it the smoothed levels would do little
/// local work per message.
pub(crate) const GATHER_ROWS: u64 = 400;

/// A coarse level with fewer unknowns than this per rank is moved onto fewer ranks
/// (`agglomerate`): below a few hundred a rank's smoothing of a level costs less than the
/// latency of its messages to its neighbours, and a level moved onto fewer ranks adds their
/// work to each of them, so the threshold sits where the weak-scaling model of
/// docs/PERFORMANCE.md finds an iteration cheapest.
pub(crate) const ROWS_PER_RANK: u64 = 200;

/// How many of the biharmonic's coarse levels, the first ones, are made as K_c V_c⁻¹ K_c at most;
/// each level below them is the Galerkin product Pᵀ A P of the level above. The guide interpolates
/// the wall's dropped CLAMPED vertices from free donors too, so its K_c holds coarse functions that
/// move the wall, which the cycle's corrections never do: K_c V_c⁻¹ K_c then underestimates A next
/// to a CLAMPED wall, more on each level made from K_c, and a deep level's correction overshoots
/// there (docs/DESIGN.md §5, "The biharmonic's levels").
const KVK_LEVELS: usize = 2;

/// The strong-coupling threshold (`select::strong`) of the biharmonic's first coarsening, above
/// `select::THETA` of every other: fewer couplings are strong, so the first coarse level keeps
/// more of the finest, as the serial kept levels do. The finest level pair makes the count, and
/// the gentler first level brings the graded sphere, the bench's box and the cylinder channel to
/// the serial count or within one of it (docs/DESIGN.md §5, "The biharmonic's levels").
const FIRST_THETA: f64 = 0.75;

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

/// How deep a hierarchy goes and where its levels are held.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Limits {
    /// Most levels, the gathered one included.
    pub(crate) levels: usize,
    /// A coarse level with fewer unknowns than this per rank is moved onto fewer ranks (0 never).
    pub(crate) per_rank: u64,
    /// A level of at most this many unknowns over all ranks is the coarsest, gathered onto one
    /// rank (`GATHER_ROWS`; the tests make deep hierarchies on small meshes with less).
    pub(crate) gather: u64,
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
    /// The global id of each local entry.
    gids: Vec<u64>,
    halo: Arc<HaloLayout>,
    /// The digest of this rank's owned rows of the prolongation to the next coarser level
    /// (`transfer_digest`; 0 on the coarsest).
    digest: u64,
    /// When the next coarser level is agglomerated onto fewer ranks: the layout the
    /// prolongation's columns refer to on this level's ranks, and the move onto those ranks.
    landing: Option<Arc<Landing>>,
    /// The biharmonic's level is the assembled Galerkin product of the level above, not made
    /// from its guide (`assembled_below`, `KVK_LEVELS`).
    galerkin: bool,
}

/// How the coarsest level is solved.
enum Coarsest {
    /// Gathered on every rank and factored.
    Gathered(Gathered),
    /// Too large to gather (coarsening stopped early): a fixed number of smoothing sweeps, a
    /// fixed symmetric operator, so still a valid preconditioner.
    Smoothed,
    /// A hierarchy of several components: per group of them (its components), the group's
    /// system gathered on one rank with its slip frames and factored (`CoupledSolve`).
    Groups(Vec<(Range<usize>, CoupledSolve)>),
}

/// The components a hierarchy of several carries down its levels (`Multigrid::build_group`):
/// each component's flags over a level's local entries and the level's slip frames. A coarse
/// unknown is a fine unknown (its global id), so it takes that unknown's flags and frame, as
/// the serial kept levels inherit them (`bc::inherit_slip_frames`).
pub(crate) struct Components {
    /// Per component, the flags of each local entry (the halo P).
    pub(crate) flags: Vec<Vec<u8>>,
    /// The slip frames of the owned entries, on every rank when the walls couple the components.
    pub(crate) slip: Option<LevelSlip>,
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
    /// The biharmonic's level is the assembled Galerkin product of the level above (the same
    /// on every rank that holds it).
    pub(crate) galerkin: bool,
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
    /// The components of the group the cycle runs on (`0..1` for a scalar hierarchy; a group of
    /// a hierarchy of several, `apply_group`).
    comps: Range<usize>,
    work: Vec<Work>,
    /// The finest level's right-hand side and iterate when the caller's vectors have another
    /// halo (`Preconditioner::apply`).
    entry: (Vec<f64>, Vec<f64>),
}

impl Multigrid {
    /// Builds the hierarchy of the operator `fine` as deep as `limits` allow (its levels, the
    /// gathered one included, and the size gathered), smoothed by `smoothers`, its coarse levels
    /// moved onto fewer ranks below `limits.per_rank` unknowns per rank (collective; every rank
    /// returns the same result).
    ///
    /// With `Coarsening::Guide` (the biharmonic's K, V and positions beside its A = K V⁻¹ K) each
    /// coarse level is made from the guide's (`biharmonic::coarsen`; below `KVK_LEVELS`, and under
    /// lines, the Galerkin product of the level above, `assembled_below`, in 2D from the first
    /// coarse level on); with `Coarsening::Galerkin`, by the Galerkin product of the level above.
    /// `lines` are the finest level's lines across wall layers over its owned unknowns
    /// (`owned_lines`; none on meshes without such layers), smoothed as blocks there and on the
    /// coarse levels that keep them (`lines`).
    pub(crate) fn build(
        fine: OwnedRows,
        coarsening: Coarsening,
        lines: Lines,
        limits: Limits,
        smoothers: Smoothers,
    ) -> Result<Multigrid, DistError> {
        Self::build_with(fine, coarsening, None, lines, limits, smoothers)
    }

    /// As `build`, over every component at once: the operator `fine` has the rows free in any
    /// component, and `components` gives each component's flags and the slip frames on the
    /// finest level, which every coarse level inherits from the level above. Each group of
    /// components is then smoothed on every level as one system with its slip projection Π
    /// (`GroupOp`), and its coarsest level gathered and factored coupled (`CoupledSolve`).
    /// The levels are not agglomerated (their flags and frames stay with their owners):
    /// `limits.per_rank` is not read.
    pub(crate) fn build_group(
        fine: OwnedRows,
        coarsening: Coarsening,
        components: Components,
        lines: Lines,
        limits: Limits,
        smoothers: Smoothers,
    ) -> Result<Multigrid, DistError> {
        let limits = Limits { per_rank: 0, ..limits };
        Self::build_with(fine, coarsening, Some(components), lines, limits, smoothers)
    }

    fn build_with(
        fine: OwnedRows,
        coarsening: Coarsening,
        components: Option<Components>,
        lines: Lines,
        limits: Limits,
        smoothers: Smoothers,
    ) -> Result<Multigrid, DistError> {
        let comm = fine.halo.shared_comm().clone();
        // The biharmonic's coarse operators K_c V_c⁻¹ K_c are softer than the Galerkin product of
        // the level above, so one coarse visit corrects too little: the W-cycle's second visit
        // makes it up, as in the serial cycle. The Galerkin levels need no second visit: with the
        // donor rule their V-cycle takes as few iterations as a W-cycle (docs/perf-history.md).
        let visits = if matches!(coarsening, Coarsening::Guide(_)) { 2 } else { 1 };
        // A failure on the ranks of an agglomerated level reaches the ranks idle below it here,
        // where every rank of the finest level meets again.
        let built = levels_of(fine, coarsening, components, lines, limits);
        let (levels, coarsest) = agree(&comm, built)?;
        // Rank 0 holds every level (it receives the rows of every agglomeration).
        let gathers = matches!(coarsest, Some(Coarsest::Gathered(_) | Coarsest::Groups(_)));
        let shape = gather(&comm, &[levels.len() as u64, u64::from(gathers)]);
        let (depth, gathered) = (shape[0] as usize, shape[1] == 1);
        let work = levels.iter().enumerate().map(|(l, d)| work(d, l == 0)).collect();
        let entry = Default::default();
        let comps = 0..1;
        Ok(Multigrid { levels, coarsest, depth, gathered, comm, smoothers, visits, comps, work, entry })
    }

    /// Unknowns, halo values, ranks and products per level, finest first (collective).
    pub(crate) fn sizes(&self) -> Vec<LevelSize> {
        let mut mine = vec![0.0; 5 * self.depth];
        for (d, m) in self.levels.iter().zip(mine.chunks_exact_mut(5)) {
            m.copy_from_slice(&[
                unknowns(&d.level.op.k, d.halo.owned()) as f64,
                d.halo.sent_per_exchange() as f64,
                d.halo.send_lists().len() as f64,
                1.0,
                f64::from(u8::from(d.galerkin)),
            ]);
        }
        let all = sum_in_rank_order(&self.comm, &mine);
        let mut digests = vec![0u64; self.depth];
        digests.iter_mut().zip(&self.levels).for_each(|(d, l)| *d = l.digest);
        let mut transfer = vec![0u64; self.depth];
        for rank in gather(&self.comm, &digests).chunks_exact(self.depth.max(1)) {
            transfer.iter_mut().zip(rank).for_each(|(t, &d)| *t = t.wrapping_add(d));
        }
        all.chunks_exact(5)
            .zip(transfer)
            .map(|(a, transfer)| LevelSize {
                rows: a[0] as u64,
                halo_values: a[1] as u64,
                messages: a[2] as u64,
                ranks: a[3] as u64,
                transfer,
                galerkin: a[4] > 0.0,
            })
            .collect()
    }

    /// Whether the coarsest level is gathered onto one rank (else it is smoothed).
    pub(crate) fn gathers(&self) -> bool {
        self.gathered
    }

    /// x = B b on level `l` from a zero start: one V- or W-cycle of the group `comps` (its
    /// blocks of the level's unknowns; collective over the level's ranks and those idle below
    /// it).
    fn cycle(&mut self, l: usize, b: &[f64], x: &mut [f64]) {
        let lev = &self.levels[l];
        let op = GroupOp::new(&lev.level, self.comps.clone(), false);
        let sm = self.smoothers.at(l);
        if lev.level.down.is_none() {
            let exact = match &self.coarsest {
                Some(Coarsest::Gathered(g)) => {
                    g.solve(b, x);
                    true
                }
                Some(Coarsest::Groups(groups)) => match groups.iter().find(|g| g.0 == self.comps) {
                    Some((_, g)) => {
                        g.solve(b, x, op.n());
                        true
                    }
                    None => false,
                },
                Some(Coarsest::Smoothed) | None => false,
            };
            if !exact {
                let w = &mut self.work[l];
                let mut start = Start::Zero;
                for _ in 0..COARSEST_SWEEPS {
                    smooth(&op, sm, b, x, &mut w.scratch, &mut w.coefficients, start, false);
                    start = Start::Guess;
                }
            }
            return;
        }
        let w = &mut self.work[l];
        smooth(&op, sm, b, x, &mut w.scratch, &mut w.coefficients, Start::Zero, false);
        self.correct(l, b, x);
        let op = GroupOp::new(&self.levels[l].level, self.comps.clone(), false);
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
        let op = GroupOp::new(&lev.level, self.comps.clone(), false);
        let w = &mut self.work[l];
        op.residual(b, x, &mut w.r[..b.len()], &mut w.scratch[0].s);
        self.correct_residual(l, x);
    }

    /// x = P x_c with x_c one visit of the next coarser level to Pᵀ r: the cycle's coarse
    /// correction of a residual `r` formed by the caller on the finest level (one block per
    /// component of the group, each of the caller's length; its owned entries read; x's halo
    /// left zero); x = 0 for a hierarchy of one level (collective).
    pub(crate) fn coarse_correction(&mut self, r: &[f64], x: &mut [f64]) {
        let (owned, n, len) = (self.levels[0].halo.owned(), self.levels[0].level.n(), self.comps.len());
        let nr = r.len() / len;
        let w = &mut self.work[0];
        for k in 0..len {
            let to = block_mut(&mut w.r, n, k);
            to[..owned].copy_from_slice(&block(r, nr, k)[..owned]);
            to[owned..].iter_mut().for_each(|v| *v = 0.0);
        }
        let mut x0 = std::mem::take(&mut self.entry.1);
        x0.clear();
        x0.resize(n * len, 0.0);
        if self.levels[0].level.down.is_some() {
            self.correct_residual(0, &mut x0);
        }
        for k in 0..len {
            let to = block_mut(x, nr, k);
            to[..owned].copy_from_slice(&block(&x0, n, k)[..owned]);
            to[owned..].iter_mut().for_each(|v| *v = 0.0);
        }
        self.entry.1 = x0;
    }

    /// One cycle of the group `comps` of a hierarchy of several components (`build_group`) as
    /// the preconditioner of that group's system: `r` and `z` one block per component, each of
    /// the caller's length (see `Preconditioner::apply`); z in the range of the group's Π.
    pub(crate) fn apply_group(&mut self, comps: Range<usize>, r: &[f64], z: &mut [f64]) {
        self.comps = comps;
        let (n, len) = (self.levels[0].level.n(), self.comps.len());
        let nr = r.len() / len;
        if nr == n {
            return self.cycle(0, r, z);
        }
        let owned = self.levels[0].halo.owned();
        let (mut b, mut x) = std::mem::take(&mut self.entry);
        b.clear();
        b.resize(n * len, 0.0);
        x.resize(n * len, 0.0);
        for k in 0..len {
            block_mut(&mut b, n, k)[..owned].copy_from_slice(&block(r, nr, k)[..owned]);
        }
        self.cycle(0, &b, &mut x);
        for k in 0..len {
            let to = block_mut(z, nr, k);
            to[..owned].copy_from_slice(&block(&x, n, k)[..owned]);
            to[owned..].iter_mut().for_each(|v| *v = 0.0);
        }
        self.entry = (b, x);
    }

    /// x ← x + Π P x_c on level `l` from its residual in `work[l].r` (see `correct`), block by
    /// block of the group.
    fn correct_residual(&mut self, l: usize, x: &mut [f64]) {
        let lev = &self.levels[l];
        let Some(down) = &lev.level.down else {
            return;
        };
        let (n, len) = (lev.level.n(), self.comps.len());
        let (prolong, landing) = (down.prolong.clone(), lev.landing.clone());
        let held = l + 1 < self.levels.len();
        let nc = if held { self.levels[l + 1].level.n() } else { 0 };
        let (mut bc, mut xc) = if held {
            (std::mem::take(&mut self.work[l + 1].b), std::mem::take(&mut self.work[l + 1].x))
        } else {
            Default::default()
        };
        let coarse = match &landing {
            Some(landing) => {
                let (mut lb, mut lx) = std::mem::take(&mut self.work[l].landing);
                let nl = landing.layout.len();
                for k in 0..len {
                    let lbk = block_mut(&mut lb, nl, k);
                    down.restrict.mul_vec(block(&self.work[l].r, n, k), lbk);
                    // Pᵀ r: the contributions to coarse halo entries belong to their owners,
                    // whose owned entries then move onto the agglomerated level's ranks.
                    landing.layout.add_to_owners(lbk);
                    let moved = if held { block_mut(&mut bc, nc, k) } else { &mut [] };
                    landing.mover.gather(lbk, moved);
                }
                if held {
                    self.prescribe(l + 1, &mut bc[..nc * len]);
                    self.visit(l + 1, &bc[..nc * len], &mut xc[..nc * len]);
                }
                for k in 0..len {
                    let lxk = block_mut(&mut lx, nl, k);
                    landing.mover.scatter(if held { block(&xc, nc, k) } else { &[] }, lxk);
                    landing.layout.refresh(lxk);
                }
                self.work[l].landing.0 = lb;
                (lx, nl)
            }
            None => {
                let coarse_halo = self.levels[l + 1].halo.clone();
                for k in 0..len {
                    let bck = block_mut(&mut bc, nc, k);
                    down.restrict.mul_vec(block(&self.work[l].r, n, k), bck);
                    coarse_halo.add_to_owners(bck);
                }
                self.prescribe(l + 1, &mut bc[..nc * len]);
                self.visit(l + 1, &bc[..nc * len], &mut xc[..nc * len]);
                (0..len).for_each(|k| coarse_halo.refresh(block_mut(&mut xc, nc, k)));
                (std::mem::take(&mut xc), nc)
            }
        };
        let (coarse, m) = coarse;
        // x ← x + P x_c on the owned unknowns (P's rows of the halo and prescribed are empty),
        // then Π x: x is in Π's range, so this adds Π P x_c.
        let lev = &self.levels[l].level;
        for (k, c) in self.comps.clone().enumerate() {
            let (flags, xc) = (&lev.flags[c], block(&coarse, m, k));
            par_update(block_mut(x, n, k), |i, xv| if flags[i] & P != 0 { xv } else { xv + prolong.row_dot(i, xc) });
        }
        GroupOp::new(lev, self.comps.clone(), false).project(&mut x[..n * len]);
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

    /// Zeroes the prescribed entries of the group's blocks of `b` on level `l` (its halo, and in
    /// a hierarchy of several components each component's prescribed unknowns), so that the
    /// restriction is the transpose of the prolongation, which leaves them.
    fn prescribe(&self, l: usize, b: &mut [f64]) {
        let lev = &self.levels[l].level;
        let n = lev.n();
        for (k, c) in self.comps.clone().enumerate() {
            let flags = &lev.flags[c];
            block_mut(b, n, k).iter_mut().zip(flags).filter(|(_, f)| *f & P != 0).for_each(|(v, _)| *v = 0.0);
        }
    }

    /// x_c from `visits` cycles on level `l`'s system A x = b, each from the residual the
    /// previous left (collective over the level's ranks).
    fn visit(&mut self, l: usize, b: &[f64], x: &mut [f64]) {
        self.cycle(l, b, x);
        // A coarsest level solved exactly leaves nothing for a second visit.
        let exact = l + 1 == self.depth && self.gathered;
        let m = b.len();
        for _ in 1..if exact { 1 } else { self.visits } {
            let (mut rc, mut dx) = std::mem::take(&mut self.work[l].again);
            let op = GroupOp::new(&self.levels[l].level, self.comps.clone(), false);
            op.residual(b, x, &mut rc[..m], &mut self.work[l].scratch[0].s);
            self.cycle(l, &rc[..m], &mut dx[..m]);
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
    components: Option<Components>,
    lines: Lines,
    limits: Limits,
) -> Result<(Vec<DistLevel>, Option<Coarsest>), DistError> {
    let mut levels = Vec::new();
    // The current level's components, for a hierarchy of several.
    let mut comp = components;
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
    // The biharmonic's hierarchies with lines on their finest level (asked on every rank). They
    // interpolate along the lines on every level in 2D, as serially (`multigrid::lsq`), and in 3D
    // under thin layers (`lines::thin_layers`), where the serial 3D levels keep the least-squares
    // rows; their selection keeps the walls and the wall's lines, as the serial one
    // (docs/DESIGN.md §5, "Wall layers across ranks").
    let layered = guide.is_some() && any_lines(current.halo.comm(), &lines);
    let along = layered && guide.as_ref().is_some_and(|g| g.at.dim == 2 || lines::thin_layers(&g.k, &g.at));
    // Lines across thin layers make the levels below them layered (the assembled Galerkin
    // product), as serially: a graded mesh's rays are lines for the smoother alone.
    let thin = layered && layered_over_ranks(current.halo.comm(), &lines, global_rows(&current));
    loop {
        // The current level is the assembled Galerkin product of the level above.
        let galerkin = assembled;
        let rows = global_rows(&current);
        let last = rows <= limits.gather || levels.len() + 1 >= limits.levels.max(1);
        let coarse = match (&guide, last) {
            (_, true) => None,
            (None, false) => galerkin_level(&current, &mut at)?,
            (Some(g), false) => {
                // The serial rule on the level's lines over all its ranks (collective over them;
                // asked only where it decides): the first coarse level K_c V_c⁻¹ K_c, the levels
                // below one that keeps lines the product, as below the first `KVK_LEVELS` on
                // every mesh.
                let kept = !levels.is_empty();
                let lined = kept && !assembled && layered_over_ranks(current.halo.comm(), &lines, rows);
                let below = assembled_below(kept, lined, assembled) || levels.len() >= KVK_LEVELS;
                // Under thin 2D wall layers a first coarse level that keeps lines is assembled
                // too: the 2D levels keep their lines as any unknowns (docs/DESIGN.md §5, "Wall
                // layers across ranks").
                let product = match (below, along && thin && !kept && g.at.dim == 2) {
                    (true, _) => Product::Galerkin,
                    (false, true) => Product::GalerkinWhereLinesKept(&segments),
                    (false, false) => Product::Guided,
                };
                let theta = if kept { select::THETA } else { FIRST_THETA };
                match biharmonic::coarsen(&current, g, product, along.then_some(&segments), theta)? {
                    Some((next, prolong, next_guide, galerkin)) => {
                        guide = Some(next_guide);
                        assembled = galerkin;
                        Some((next, prolong))
                    }
                    None => None,
                }
            }
        };
        let Some((next, prolong)) = coarse else {
            return coarsest((current, lines, band, galerkin), comp, (rows, limits.gather), levels);
        };
        let next_rows = global_rows(&next);
        if next_rows as f64 >= MIN_REDUCTION * rows as f64 {
            return coarsest((current, lines, band, galerkin), comp, (rows, limits.gather), levels);
        }
        let next_segments = lines::kept_segments(&segments, &current.gids, &next);
        let next_lines = lines::smoothed(&next_segments);
        // A level small enough to gather goes onto one rank by its own solve.
        let ranks = next.halo.comm().size();
        // A hierarchy of several components keeps its levels on their ranks (`build_group`).
        let stay = next_rows <= limits.gather || comp.is_some();
        let shift = if stay { 0 } else { halvings(next_rows, ranks, limits.per_rank) };
        let digest = transfer_digest(&prolong, &current, &next.gids);
        if shift == 0 {
            let next_comp = comp.as_ref().map(|c| inherited(&current, &next, c));
            levels.push(dist_level((current, lines, band, galerkin), comp, Some((prolong, digest)), None));
            comp = next_comp;
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
            let mine: Vec<f64> = g.flags[..landing.mover.count()].iter().map(|&f| f64::from(f)).collect();
            let mut flags = vec![0.0; landing.mover.len()];
            landing.mover.gather(&mine, &mut flags);
            (agglomeration.send(&g.k), (mass, flags), g.at.moved(&landing.mover))
        });
        let moved_at = at.take().map(|a| a.moved(&landing.mover));
        let moved_segments = lines::moved_lines(&next_segments, &landing.mover, next.halo.comm().rank());
        let moved_lines = lines::smoothed(&moved_segments);
        let landing = Some(Arc::new(landing));
        levels.push(dist_level((current, lines, band, galerkin), None, Some((prolong, digest)), landing));
        let Some(moved) = agglomeration.assemble(&sent)? else {
            return Ok((levels, None));
        };
        if let Some((sent, (mut mass, moved_flags), mut at)) = sent_guide {
            let k = agglomeration.assemble(&sent)?.ok_or_else(|| lost(&moved))?;
            mass.resize(k.halo.len(), 0.0);
            k.halo.refresh(&mut mass);
            // The flags are 0–3, exact in f64.
            let mut flags: Vec<u8> = moved_flags.iter().map(|&f| f as u8).collect();
            flags.resize(k.halo.len(), 0);
            k.halo.refresh(&mut flags);
            at.coords.resize(k.halo.len(), [0.0; 3]);
            at.refresh(&k.halo);
            guide = Some(Guide { k, flags, mass, at });
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
    let rows = donors::interpolation(m, here, None, (select::THETA, None, None))?;
    let Some((next, prolong)) = galerkin::product(m, &rows)? else {
        return Ok(None);
    };
    *at = Some(biharmonic::coarse_positions(m, here, &next)?);
    Ok(Some((next, prolong)))
}

/// The coarsest level `m` (`rows` unknowns over its ranks, gathered when at most `gather`; its
/// components `comp` for a hierarchy of several) after `levels`, and its solve (collective over
/// its ranks).
fn coarsest(
    (m, lines, band, galerkin): (OwnedRows, Lines, usize, bool),
    comp: Option<Components>,
    (rows, gather): (u64, u64),
    mut levels: Vec<DistLevel>,
) -> Result<(Vec<DistLevel>, Option<Coarsest>), DistError> {
    if rows > gather {
        levels.push(dist_level((m, lines, band, galerkin), comp, None, None));
        return Ok((levels, Some(Coarsest::Smoothed)));
    }
    if comp.is_none() {
        let coarsest = Coarsest::Gathered(Gathered::new(&m)?);
        levels.push(dist_level((m, lines, band, galerkin), None, None, None));
        return Ok((levels, Some(coarsest)));
    }
    let d = dist_level((m, lines, band, galerkin), comp, None, None);
    // The groups the solver forms: every component as one where the walls couple them, else
    // each component alone.
    let dim = d.level.dim();
    let groups: Vec<Range<usize>> = if d.level.coupled_frames(&(0..dim)).is_some() {
        std::iter::once(0..dim).collect()
    } else {
        (0..dim).map(|c| c..c + 1).collect()
    };
    let mut solves = Vec::with_capacity(groups.len());
    for g in groups {
        let op = GroupOp::new(&d.level, g.clone(), false);
        match CoupledSolve::new(&op, &d.gids, &d.halo, None)? {
            Some(s) => solves.push((g, s)),
            None => {
                levels.push(d);
                return Ok((levels, Some(Coarsest::Smoothed)));
            }
        }
    }
    levels.push(d);
    Ok((levels, Some(Coarsest::Groups(solves))))
}

/// The components of the coarse level `coarse` of `fine` (whose components are `comp`): each
/// owned coarse unknown is the fine owned unknown of its global id and takes its flags and slip
/// frame (`bc::inherit_slip_frames`); the halo and the empty rows are P and Z.
fn inherited(fine: &OwnedRows, coarse: &OwnedRows, comp: &Components) -> Components {
    let at: HashMap<u64, u32> =
        fine.gids[..fine.halo.owned()].iter().enumerate().map(|(i, &g)| (g, i as u32)).collect();
    let owned = coarse.halo.owned();
    let map: Vec<u32> = (0..coarse.halo.len())
        .map(|i| {
            let unknown = i < owned && !coarse.a.row(i).0.is_empty();
            let fine = unknown.then(|| at.get(&coarse.gids[i]).copied()).flatten();
            fine.unwrap_or(u32::MAX)
        })
        .collect();
    let mut flags: Vec<Vec<u8>> =
        comp.flags.iter().map(|f| map.iter().map(|&j| f.get(j as usize).copied().unwrap_or(P | Z)).collect()).collect();
    let slip = comp.slip.as_ref().map(|s| {
        let frames = inherit_slip_frames(&s.frames, &map, &mut flags);
        let frames = frames.unwrap_or_else(|| SlipFrames::empty(s.frames.dim));
        LevelSlip { frames, bcs: None, coupled: s.coupled }
    });
    Components { flags, slip }
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
        let comps = self.comps.clone();
        self.apply_group(comps, r, z);
    }
}

/// Whether a level's `lines` over all ranks of `comm` make the biharmonic's levels below it
/// layered, as the serial hierarchy decides (`hierarchy::layered_lines`): across thin layers on
/// some rank and holding their share of the level's `rows` unknowns (collective).
fn layered_over_ranks(comm: &Comm, lines: &Lines, rows: u64) -> bool {
    let thin = max_over_ranks(comm, f64::from(u8::from(lines.thin()))) > 0.0;
    let on_lines = sum_in_rank_order(comm, &[lines.unknowns.len() as f64])[0];
    layered_lines(thin, on_lines, rows as f64)
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
/// nor read as an unknown; a hierarchy of several components: their flags and slip frames
/// `comp`) with its `lines` (blocks of `band`) and the transfer `prolong` to the next coarser
/// level with its digest (collective: the smoother's bound is estimated over every rank's rows).
fn dist_level(
    (m, lines, band, galerkin): (OwnedRows, Lines, usize, bool),
    comp: Option<Components>,
    prolong: Option<(CsrMatrix, u64)>,
    landing: Option<Arc<Landing>>,
) -> DistLevel {
    let OwnedRows { a, halo, gids } = m;
    let (n, owned) = (halo.len(), halo.owned());
    let (flags, slip) = match comp {
        Some(c) => (c.flags, c.slip),
        None => (vec![(0..n).map(|i| if i >= owned || a.row(i).0.is_empty() { P | Z } else { 0 }).collect()], None),
    };
    let op = LevelOperator::from_matrix(Method::Laplacian, a);
    let inv_d = flags.iter().map(|f| op.inv_l1_diag(f)).collect();
    let lambda_max = vec![1.0; flags.len()];
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
        flags,
        inv_d,
        lambda_max,
        lines: Default::default(),
        parent_vertex: Vec::new(),
        down,
        slip,
        layout: Distribution::Halo(halo.clone()),
    };
    lines::attach(&mut level, lines, band);
    equalise_bounds(&mut level);
    let dim = level.dim();
    level.lambda_max = match level.coupled_frames(&(0..dim)) {
        // One polynomial for the coupled group, tuned to its projected operator.
        Some(_) => vec![estimate_lambda_max(&GroupOp::new(&level, 0..dim, false)); dim],
        None => (0..dim).map(|c| estimate_lambda_max(&GroupOp::new(&level, c..c + 1, false))).collect(),
    };
    DistLevel { level, gids, halo, digest, landing, galerkin }
}

/// The vectors of a visit to `d` (`finest`: its b and x are the caller's).
fn work(d: &DistLevel, finest: bool) -> Work {
    let n = d.level.n();
    let nl = d.landing.as_ref().map_or(0, |l| l.layout.len());
    // One block per component of a hierarchy of several.
    let (len, n1) = (d.level.dim(), n);
    let (n, nl) = (n * len, nl * len);
    let nbx = if finest { 0 } else { n };
    Work {
        b: vec![0.0; nbx],
        x: vec![0.0; nbx],
        r: vec![0.0; n],
        scratch: (0..len).map(|_| Scratch::new(n1, Method::Laplacian)).collect(),
        coefficients: Coefficients::default(),
        again: (vec![0.0; nbx], vec![0.0; nbx]),
        landing: (vec![0.0; nl], vec![0.0; nl]),
    }
}
