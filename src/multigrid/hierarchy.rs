//! The multigrid hierarchy (docs/DESIGN.md §5): its levels (`multigrid::level`), built with a
//! coarsener, and the coarsest level's direct solves. The finest level has the user's mesh; a
//! coarse level has a coarse mesh (2D) or is a subset of the finer level's unknowns without a
//! mesh.
//!
//! Coarse vertices and unknowns are a subset of the fine ones, so when the fine mesh moves the
//! coarse levels follow it with their topology kept; only values are re-evaluated.

use super::coarse_solve::CoarseSolve;
use super::coarsen::CoarsenParams;
use super::coarsener::{CoarseUnknowns, Coarsener};
use super::bounds::{biharmonic_estimates, Calibration};
use super::lag::{refills, waits, Anchor};
use super::group::GroupOp;
use super::refit::{donor_offsets, rows_to_redo, updated_offsets};
use super::layout::Distribution;
use super::line_smoother::LineBlocks;
pub use super::level::Level;
use super::phases::{timed, Phases};
use super::level::Transfer;
use super::restriction::Restriction;
use super::slip;
use super::{coarsener_for, CoarseLevels};
use crate::bc::{check_well_posed, component_flags, BoundaryConditions, Dofs, Z};
use crate::mesh::quality::is_inverted;
use crate::operator::{assembled_below, LevelOperator, Method};
use crate::{Mesh, Result};
use crate::sparse::{same_pattern, CsrMatrix};
use std::ops::Range;
use std::sync::Arc;

/// What a level computes from its mesh (everything but the mesh itself), so it can be built
/// while the same mesh is being coarsened.
struct LevelParts {
    dofs: Dofs,
    op: LevelOperator,
    flags: Vec<Vec<u8>>,
}

impl LevelParts {
    /// The parts and the seconds of their unknowns and of their assembly.
    fn build(mesh: &Mesh, pairs: &[[u32; 2]], bcs: &BoundaryConditions, method: Method) -> (LevelParts, Phases) {
        let mut t = Phases::default();
        let (dofs, flags) = timed(&mut t.unknowns, || {
            let dofs = Dofs::build(mesh, pairs, &bcs.split_patches());
            let flags = (0..mesh.dim()).map(|c| component_flags(mesh, &dofs, bcs, c)).collect();
            (dofs, flags)
        });
        let op = timed(&mut t.assemble, || LevelOperator::new(method, mesh, &dofs));
        (LevelParts { dofs, op, flags }, t)
    }

    fn into_level(self, mesh: Mesh, pairs: Vec<[u32; 2]>, parent_vertex: Vec<u32>) -> Level {
        let LevelParts { dofs, op, flags } = self;
        let n = dofs.n;
        Level {
            mesh: Some(mesh),
            points: Vec::new(),
            pairs,
            dofs,
            op,
            flags,
            inv_d: Vec::new(),
            lambda_max: Vec::new(),
            lines: LineBlocks::default(),
            parent_vertex,
            down: None,
            slip: None,
            layout: Distribution::new(n),
        }
        // The slip frames may prescribe unknowns (`slip::attach`): bounds come after them.
    }
}

/// The level kept from `fine`'s unknowns `c.kept`: their flags, slip frames and positions,
/// no mesh, the Galerkin operator.
fn kept_level(fine: &Level, c: CoarseUnknowns, bcs: &BoundaryConditions, t: &mut Phases) -> (Level, Transfer, Calibration) {
    let CoarseUnknowns { kept, transfer } = c;
    let fine_points = fine.unknown_points();
    let dim = fine.dim();
    let points = kept.iter().flat_map(|&d| fine_points[d as usize * dim..(d as usize + 1) * dim].iter().copied()).collect();
    let flags = fine.flags.iter().map(|f| kept.iter().map(|&d| f[d as usize]).collect()).collect();
    let op = timed(&mut t.galerkin, || coarse_operator(fine, &transfer.prolong));
    let layout = Distribution::new(kept.len());
    let mut level = Level {
        mesh: None,
        points,
        pairs: Vec::new(),
        dofs: Dofs::identity(kept.len()),
        op,
        flags,
        inv_d: Vec::new(),
        lambda_max: Vec::new(),
        lines: LineBlocks::default(),
        parent_vertex: kept,
        down: None,
        slip: None,
        layout,
    };
    level.lines = fine.lines.kept(&level.parent_vertex, fine.op.method);
    timed(&mut t.unknowns, || slip::attach(&mut level, Some(fine), bcs));
    let calibration = timed(&mut t.bounds, || refresh_bounds(&mut level, None));
    (level, transfer, calibration)
}

/// The least share of a kept level's unknowns on its lines for the biharmonic's next level to
/// take the assembled Pᵀ A P (`coarse_operator`). Below wall layers the first kept level keeps
/// a third or more of its unknowns on lines (a wing, a spheroid, an airfoil); a graded mesh whose
/// line finder meets a few short lines off its walls (the graded sphere's box corners) keeps a
/// few percent or less, and there K_c V_c⁻¹ K_c on every level takes fewer iterations
/// (docs/perf-history.md, "The graded sphere's coarse rows at the clamped body").
const LAYERED_SHARE: f64 = 0.1;

/// Whether a level's lines make the biharmonic's levels below it layered (the assembled
/// Galerkin product): lines across thin layers (`Lines::thin`) holding at least `LAYERED_SHARE`
/// of the level's `unknowns` (`on_lines` of them). The serial hierarchy and the distributed one
/// decide by it.
pub(crate) fn layered_lines(thin: bool, on_lines: f64, unknowns: f64) -> bool {
    thin && on_lines >= LAYERED_SHARE * unknowns
}

/// The operator of a level of kept unknowns below `fine` with the interpolation `prolong`:
/// Galerkin K_c and V_c, and for the biharmonic below wall layers A_c = Pᵀ A P assembled
/// (`LevelOperator::galerkin_assembled`) when `fine` is itself a level of kept unknowns with
/// `LAYERED_SHARE` of its unknowns on lines across thin layers (`Lines::thin`: a graded mesh's
/// rays keep K_c V_c⁻¹ K_c), or already assembled, and every component holds S
/// free at the same unknowns; else K_c V_c⁻¹ K_c. The first kept level keeps K_c V_c⁻¹ K_c:
/// with linear interpolation the product of the fourth-order operator is stiffer there than the
/// operator itself on coarse functions, while below it the product's faithfulness across the
/// coarsened layers wins (docs/DESIGN.md §5, "Wall layers"). In 3D the product's entries far
/// below their diagonals are dropped onto them (`small_entries`), which bounds the deep levels'
/// rows; the 2D hierarchies, which interpolate along their lines, keep the whole product (the
/// drop cost the airfoil iterations there).
fn coarse_operator(fine: &Level, prolong: &CsrMatrix) -> LevelOperator {
    let restrict = prolong.transpose();
    let on_lines = fine.lines.lines().unknowns.len() as f64;
    let thin = layered_lines(fine.lines.lines().thin(), on_lines, fine.n() as f64);
    let layered = assembled_below(fine.mesh.is_none(), thin, fine.op.is_assembled());
    let z = |f: &Vec<u8>| f.iter().map(|&v| v & Z == 0).collect::<Vec<bool>>();
    let s_free = fine.flags.first().map(z).filter(|s| fine.flags.iter().all(|f| z(f) == *s));
    match s_free {
        Some(s_free) if fine.op.method == Method::Biharmonic && layered => {
            LevelOperator::galerkin_assembled(&fine.op, s_free, prolong, &restrict, fine.dim() == 3)
        }
        _ => LevelOperator::galerkin(&fine.op, prolong, &restrict),
    }
}

/// The level's Jacobi diagonals and λmax estimates, after its flags and slip frames; the
/// biharmonic's from `previous`, the calibration of the level's last estimates (None on a new
/// level; `multigrid::bounds`). Returns the calibration to keep (empty for the other methods).
fn refresh_bounds(level: &mut Level, previous: Option<&Calibration>) -> Calibration {
    // Every component has the same K and V: components with the same flags (walls fixed in
    // every direction) have the same diagonal, line factors and λmax, computed once for the
    // first of them. The others are independent: side by side, so small levels use several
    // threads.
    let nc = level.flags.len();
    let alike: Vec<usize> = (0..nc).map(|c| (0..c).find(|&e| level.flags[e] == level.flags[c]).unwrap_or(c)).collect();
    let own: Vec<usize> = (0..nc).filter(|&c| alike[c] == c).collect();
    // Component c's values among those of `own`.
    let at: Vec<usize> = alike.iter().map(|e| own.iter().position(|o| o == e).unwrap_or(0)).collect();
    let own_flags: Vec<&[u8]> = own.iter().map(|&c| level.flags[c].as_slice()).collect();
    let inv_d = level.op.inv_l1_diags(&own_flags);
    level.inv_d = at.iter().map(|&i| inv_d[i].clone()).collect();
    level.refresh_lines();
    // The l1 bound guarantees λmax(D⁻¹A) ≤ 1. For the second-order operators it is nearly
    // tight (the CG iteration counts of the estimate, see docs/perf-history.md), and the
    // estimate, redone at every re-evaluated step, costs a sizeable part of a Laplacian
    // solve (30 products per level). The biharmonic's bound is looser, so it keeps the
    // estimate.
    let mut calibration = Calibration::default();
    level.lambda_max = if level.op.method == Method::Biharmonic {
        let estimates;
        (estimates, calibration) = biharmonic_estimates(level, &own, previous);
        at.iter().map(|&i| estimates[i]).collect()
    } else {
        vec![1.0; level.flags.len()]
    };
    slip::equalise_bounds(level);
    calibration
}

/// What a re-reference carries from one reference to the next beyond the positions: each
/// transfer's weights and the donor offsets they were chosen at. A failed call puts them back
/// (`Hierarchy::restore`), so the hierarchy is bitwise as before it.
#[derive(Clone)]
pub(crate) struct Carried {
    prolong: Vec<Option<Arc<CsrMatrix>>>,
    offsets: Vec<Arc<Vec<f64>>>,
    /// The calibrations the bounds were estimated from (`Hierarchy::calibrated_from`).
    calibrated_from: Vec<Calibration>,
    /// The last full refresh, and whether the coarse levels are still its (`multigrid::lag`).
    anchor: Anchor,
    coarse_kept: bool,
    /// Where the first coarse level's product was last refilled, when not at the positions
    /// (`Hierarchy::refilled`).
    refilled: Option<Anchor>,
}

/// What a re-reference does with the coarse levels.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Coarse {
    /// Keeps them while the fine level's change since the anchor allows (`multigrid::lag`).
    Decide,
    /// Refreshes them at the new positions.
    Refresh,
    /// Keeps them, refilling the first one's product or not.
    Keep { refill: bool },
}

/// The donor offsets of level l's transfer when the coarse level below it has kept unknowns
/// (see `refit`), empty otherwise.
fn transfer_offsets(levels: &[Level], l: usize) -> Vec<f64> {
    match (levels.get(l + 1), &levels[l].down) {
        (Some(coarse), Some(down)) if coarse.mesh.is_none() => {
            donor_offsets(&down.prolong, &coarse.parent_vertex, &levels[l].unknown_points(), levels[l].dim())
        }
        _ => Vec::new(),
    }
}

/// How a coarse level's K and V are made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CoarseOperator {
    /// Galerkin for the spring analogy, rediscretised otherwise.
    ///
    /// Rediscretised spring operators are far too soft on coarse levels (their 1/L² weights
    /// shrink fourfold per level): CG diverges or stalls with them, and converges in a few
    /// iterations with Galerkin ones. The biharmonic and Laplacian converge as fast
    /// rediscretised and their solves are cheaper that way (sparser coarse operators), so they
    /// keep docs/DESIGN.md §5's rediscretisation (measurements in docs/perf-history.md).
    #[default]
    Auto,
    /// K and V rediscretised on the coarse mesh (docs/DESIGN.md §5).
    Rediscretised,
    /// K_c = PᵀKP, V_c = PᵀV; see `LevelOperator::galerkin`.
    Galerkin,
}

impl CoarseOperator {
    fn galerkin(self, method: Method) -> bool {
        match self {
            CoarseOperator::Auto => method == Method::Spring,
            CoarseOperator::Rediscretised => false,
            CoarseOperator::Galerkin => true,
        }
    }
}

/// Hierarchy parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct HierarchyParams {
    /// When the coarsener stops.
    pub coarsen: CoarsenParams,
    /// How coarse levels get their operator.
    pub coarse_operator: CoarseOperator,
    /// Stop after this many levels (the paper used six).
    pub max_levels: usize,
    /// How coarse levels are made.
    pub coarse_levels: CoarseLevels,
}

impl Default for HierarchyParams {
    fn default() -> Self {
        HierarchyParams { coarsen: CoarsenParams::default(), coarse_operator: CoarseOperator::Auto, max_levels: 20, coarse_levels: CoarseLevels::Auto }
    }
}

pub struct Hierarchy {
    pub levels: Vec<Level>,
    pub method: Method,
    galerkin: bool,
    /// Built from the current fine mesh (true) or moved there from the mesh it was built on.
    pub fresh: bool,
    coarsener: Box<dyn Coarsener>,
    /// The direct solve of each group (`Level::groups`) on the coarsest level.
    coarse: Vec<(Range<usize>, CoarseSolve)>,
    /// Seconds per phase of the last build or re-reference.
    phases: Phases,
    /// Per level with a transfer of kept unknowns below it: the donor offsets its weights were
    /// chosen at (`refit`; empty for other levels). Shared with the `Carried` a call keeps to
    /// restore (replaced, never changed in place), so keeping them copies nothing.
    offsets: Vec<Arc<Vec<f64>>>,
    /// Per level: the calibration of its last λmax estimates (`multigrid::bounds`), and the one
    /// those estimates were made from (what a restore estimates from again).
    calibration: Vec<Calibration>,
    calibrated_from: Vec<Calibration>,
    /// The last full refresh the coarse levels come from, and whether the last re-reference
    /// kept them (`multigrid::lag`).
    anchor: Anchor,
    coarse_kept: bool,
    /// The fine level's positions and diagonal where the first coarse level's product was last
    /// refilled, when they are not its positions now: a Laplacian's kept re-reference leaves the
    /// product while the diagonal changed little since (`lag::refills`). None where the product
    /// is the current fine operator's.
    refilled: Option<Anchor>,
    /// Counts the re-references: a failed call restores the hierarchy when it changed.
    generation: u64,
}

impl Hierarchy {
    /// Builds every level from the fine mesh and its resolved link pairs.
    pub fn build(
        mesh: &Mesh,
        pairs: Vec<[u32; 2]>,
        bcs: &BoundaryConditions,
        method: Method,
        params: &HierarchyParams,
    ) -> Result<Hierarchy> {
        let mut coarsener = coarsener_for(mesh.dim(), params.coarse_levels, params.coarsen)?;
        let galerkin = params.coarse_operator.galerkin(method);
        let mut levels: Vec<Level> = Vec::new();
        let mut calibration: Vec<Calibration> = Vec::new();
        let mut t = Phases::default();
        let (mut mesh, mut pairs, mut parent_vertex) = (mesh.clone(), pairs, Vec::new());
        // Levels with meshes.
        loop {
            // A level's unknowns and operator do not depend on its coarsening, and both are
            // mostly serial work: on two threads they run side by side.
            let last = levels.len() + 1 >= params.max_levels;
            let mut coarsen_s = 0.0;
            let ((parts, pt), cm) = rayon::join(
                || LevelParts::build(&mesh, &pairs, bcs, method),
                || timed(&mut coarsen_s, || if last { Ok(None) } else { coarsener.coarsen_mesh(&mesh, &pairs) }),
            );
            (t.unknowns, t.assemble, t.coarsen) = (t.unknowns + pt.unknowns, t.assemble + pt.assemble, t.coarsen + coarsen_s);
            let mut level = parts.into_level(mesh, pairs, parent_vertex);
            timed(&mut t.unknowns, || slip::attach(&mut level, levels.last(), bcs));
            let mut cal = timed(&mut t.bounds, || refresh_bounds(&mut level, None));
            let l = levels.len();
            match levels.last_mut() {
                None => check_well_posed(&level.op.k, &level.flags, &level.dofs, level.slip.as_ref().map(|s| &s.frames))?,
                Some(fine) => {
                    let down = timed(&mut t.coarsen, || coarsener.transfer(l - 1, fine, &level));
                    if galerkin {
                        level.op = timed(&mut t.galerkin, || {
                            LevelOperator::galerkin(&fine.op, &down.prolong, &down.prolong.transpose())
                        });
                        cal = timed(&mut t.bounds, || refresh_bounds(&mut level, None));
                    }
                    fine.down = Some(down);
                }
            }
            levels.push(level);
            calibration.push(cal);
            let Some(cm) = cm? else {
                break;
            };
            (mesh, pairs, parent_vertex) = (cm.mesh, cm.links, cm.fine_vertex);
        }
        // Levels of kept unknowns.
        while levels.len() < params.max_levels {
            let l = levels.len() - 1;
            let Some(c) = timed(&mut t.coarsen, || coarsener.coarsen_unknowns(l, &levels[l])) else {
                break;
            };
            let (level, down, cal) = kept_level(&levels[l], c, bcs, &mut t);
            levels[l].down = Some(down);
            levels.push(level);
            calibration.push(cal);
        }
        let offsets = (0..levels.len()).map(|l| Arc::new(transfer_offsets(&levels, l))).collect();
        let anchor = Anchor::new(levels[0].mesh().coords(), &levels[0].inv_d[0]);
        let mut h = Hierarchy {
            levels,
            method,
            galerkin,
            fresh: true,
            coarsener,
            coarse: Vec::new(),
            phases: t,
            offsets,
            calibrated_from: vec![Calibration::default(); calibration.len()],
            calibration,
            anchor,
            coarse_kept: false,
            refilled: None,
            generation: 0,
        };
        timed(&mut t.coarse_solve, || h.build_coarse_solve())?;
        h.phases = t;
        Ok(h)
    }

    fn build_coarse_solve(&mut self) -> Result<()> {
        let last = self.levels.last().expect("one level at least");
        // One solve per group the cycle runs over: the finest level's groups. A coupled group is
        // one system there (a component alone may have nothing prescribed and be singular), also
        // where the coarsest level's own frames no longer couple the components (its slip
        // unknowns all on walls normal to the axes, or none left).
        let solves = self
            .groups()
            .into_iter()
            .map(|g| Ok((g.clone(), CoarseSolve::new(&GroupOp::new(last, g, false))?)))
            .collect::<Result<Vec<_>>>()?;
        self.coarse = solves;
        Ok(())
    }

    /// The coarsest level's solve of the group `comps`.
    pub(crate) fn coarse_solve(&self, comps: &Range<usize>) -> Option<&CoarseSolve> {
        self.coarse.iter().find(|(g, _)| g == comps).map(|(_, s)| s)
    }

    /// Whether some level has no mesh (a level of kept unknowns).
    pub fn has_kept_levels(&self) -> bool {
        self.levels.iter().any(|l| l.mesh.is_none())
    }

    /// Seconds per phase of the last build or re-reference.
    pub fn phases(&self) -> Phases {
        self.phases
    }

    /// Whether some level has lines of strong coupling across thin wall layers
    /// (`multigrid::lines`).
    pub fn has_lines(&self) -> bool {
        self.levels.iter().any(|l| !l.lines.is_empty())
    }

    pub fn fine(&self) -> &Level {
        &self.levels[0]
    }

    /// The groups of components solved as one system (see `Level::groups`).
    pub fn groups(&self) -> Vec<Range<usize>> {
        self.fine().groups()
    }

    /// Re-evaluates every level at new fine-vertex positions, keeping the coarse topology.
    /// Returns false (and changes nothing) when a coarse cell would invert: the caller rebuilds.
    pub fn move_to(&mut self, fine_coords: Vec<f64>) -> Result<bool> {
        self.move_with(fine_coords, None)
    }

    /// What a re-reference carries beyond the positions (see `Carried`).
    pub(crate) fn carried(&self) -> Carried {
        Carried {
            prolong: self.levels.iter().map(|l| l.down.as_ref().map(|d| Arc::clone(&d.prolong))).collect(),
            offsets: self.offsets.clone(),
            calibrated_from: self.calibrated_from.clone(),
            anchor: self.anchor.clone(),
            coarse_kept: self.coarse_kept,
            refilled: self.refilled.clone(),
        }
    }

    /// Counts the re-references of this hierarchy.
    pub(crate) fn generation(&self) -> u64 {
        self.generation
    }

    /// Back to the positions `fine_coords` with the weights `carried` had there:
    /// bitwise the state `carried` was taken in.
    pub(crate) fn restore(&mut self, fine_coords: Vec<f64>, carried: Carried) -> Result<bool> {
        self.move_with(fine_coords, Some(carried))
    }

    /// `move_to`, or with `replay` the weights of an earlier state at these positions instead
    /// of choosing them. A state whose coarse levels were kept from an earlier full refresh is
    /// made again as it was made: every level at that refresh's positions, then the first coarse
    /// level's product where it was last refilled, then the fine level at its own positions.
    fn move_with(&mut self, fine_coords: Vec<f64>, replay: Option<Carried>) -> Result<bool> {
        let Some(r) = replay else {
            return self.move_levels(fine_coords, None, Coarse::Decide);
        };
        if !r.coarse_kept {
            return self.move_levels(fine_coords, Some(r), Coarse::Refresh);
        }
        let fine_only = Carried {
            prolong: Vec::new(),
            offsets: Vec::new(),
            calibrated_from: r.calibrated_from.clone(),
            anchor: r.anchor.clone(),
            coarse_kept: true,
            refilled: None,
        };
        let (anchor, refilled) = (Arc::clone(&r.anchor.coords), r.refilled.clone());
        if !self.move_levels(anchor.to_vec(), Some(r), Coarse::Refresh)? {
            return Ok(false);
        }
        if let Some(at) = refilled.as_ref().filter(|a| a.coords != anchor) {
            if !self.move_levels(at.coords.to_vec(), Some(fine_only.clone()), Coarse::Keep { refill: true })? {
                return Ok(false);
            }
        }
        self.move_levels(fine_coords, Some(fine_only), Coarse::Keep { refill: refilled.is_none() })
    }

    /// Moves the fine level to `fine_coords`, and the coarse levels as `coarse` says (see
    /// `move_with` for `replay`).
    fn move_levels(&mut self, fine_coords: Vec<f64>, replay: Option<Carried>, coarse: Coarse) -> Result<bool> {
        let mut t = Phases::default();
        let start = std::time::Instant::now();
        let dim = self.fine().dim();
        // Where the first coarse product was last refilled: here, unless an earlier re-reference
        // left it (`refilled`). Only a method whose product may wait needs it.
        let mut here = (waits(self.method) && self.refilled.is_none())
            .then(|| Anchor::new(self.fine().mesh().coords(), &self.fine().inv_d[0]));
        // Per level: its mesh's vertex positions, or its unknowns' positions without a mesh.
        let mut coords = vec![fine_coords];
        for l in 1..self.levels.len() {
            let (prev, finer, level) = (&coords[l - 1], &self.levels[l - 1], &self.levels[l]);
            let at = |v: u32| &prev[v as usize * dim..(v as usize + 1) * dim];
            let c: Vec<f64> = match (&finer.mesh, &level.mesh) {
                // A kept unknown below a mesh is at its (first) vertex.
                (Some(_), None) => level.parent_vertex.iter().flat_map(|&d| at(finer.dofs.dof_vertex[d as usize])).copied().collect(),
                _ => level.parent_vertex.iter().flat_map(|&v| at(v)).copied().collect(),
            };
            if let Some(m) = &level.mesh {
                if (0..m.num_cells()).any(|k| is_inverted(m, &c, k)) {
                    return Ok(false);
                }
            }
            coords.push(c);
        }
        // Per level: its moved mesh, or its unknowns' positions without a mesh.
        let moved: Vec<(Option<Mesh>, Vec<f64>)> = self
            .levels
            .iter()
            .zip(coords)
            .map(|(l, c)| match &l.mesh {
                Some(m) => (Some(m.with_coords(c)), Vec::new()),
                None => (None, c),
            })
            .collect();
        // The slip frames at the new positions; a changed wall structure needs a new hierarchy.
        let meshes: Vec<Option<&Mesh>> = moved.iter().map(|(m, _)| m.as_ref()).collect();
        let Some(mut frames) = slip::moved_frames(&self.levels, &meshes) else {
            return Ok(false);
        };
        drop(meshes);
        t.unknowns = start.elapsed().as_secs_f64();
        // Whether the finer level's K has a new pattern (a Galerkin K after a new P's pattern).
        let mut k_pattern_changed = false;
        // The bounds are estimated from the calibrations of the last estimates, or on a restore
        // from those the restored state's estimates were made from, so they come out bitwise.
        let from = match &replay {
            Some(r) => r.calibrated_from.clone(),
            None => self.calibration.clone(),
        };
        self.generation += 1;
        let mut kept = false;
        for (l, (m, points)) in moved.into_iter().enumerate() {
            if l == 1 {
                kept = match coarse {
                    Coarse::Decide => self.anchor.keeps(&self.levels[0].inv_d[0]),
                    Coarse::Refresh => false,
                    Coarse::Keep { .. } => true,
                };
                if kept {
                    let last = self.refilled.as_ref().or(here.as_ref());
                    let refill = match coarse {
                        Coarse::Keep { refill } => refill,
                        _ => last.is_none_or(|a| refills(self.method, &a.inv_d, &self.levels[0].inv_d[0])),
                    };
                    if refill || last.is_none() {
                        self.refill_first_coarse(&from, &mut t)?;
                        self.refilled = None;
                    } else if self.refilled.is_none() {
                        self.refilled = here.take();
                    }
                    break;
                }
            }
            let level = &mut self.levels[l];
            match m {
                Some(m) => level.mesh = Some(m),
                None => level.points = points,
            }
            if !frames.is_empty() {
                slip::set_frames(level, std::mem::take(&mut frames[l].0));
            }
            if l == 0 || (!self.galerkin && level.mesh.is_some()) {
                let Level { mesh, op, dofs, .. } = level;
                timed(&mut t.assemble, || op.reassemble(mesh.as_ref().expect("a level with a mesh"), dofs));
            }
            if l > 0 {
                // The transfer from the level above, then (Galerkin) this level's operator.
                let (upper, rest) = self.levels.split_at_mut(l);
                let (fine, coarse) = (&mut upper[l - 1], &mut rest[0]);
                let mut down = fine.down.take().expect("not the coarsest level");
                let before = Arc::clone(&down.prolong);
                let offsets = &mut self.offsets[l - 1];
                timed(&mut t.transfer, || match &replay {
                    Some(r) => {
                        let p = r.prolong[l - 1].as_ref().expect("a level with a transfer");
                        down.prolong = Arc::clone(p);
                        down.restrict = Restriction::new(Arc::clone(p));
                        *offsets = Arc::clone(&r.offsets[l - 1]);
                    }
                    // Kept unknowns keep the weights of the rows whose donors moved little;
                    // barycentric weights on coarse meshes are all chosen again (a point may
                    // have left its triangle).
                    None if coarse.mesh.is_none() => {
                        let (points, kept) = (fine.unknown_points(), &coarse.parent_vertex);
                        let redo = rows_to_redo(&down.prolong, kept, &offsets[..], &points, dim);
                        if redo.iter().any(|&r| r) {
                            self.coarsener.update_rows(l - 1, &mut down, fine, coarse, &redo);
                            *offsets = Arc::new(updated_offsets(&before, &offsets[..], &down.prolong, &redo, kept, &points, dim));
                        }
                    }
                    None => self.coarsener.update(l - 1, &mut down, fine, coarse),
                });
                fine.down = Some(down);
                let down = fine.down.as_ref().expect("just put back");
                if self.galerkin || coarse.mesh.is_none() {
                    // The product's pattern is kept while K's and P's are: only its values change.
                    let same = !k_pattern_changed && same_pattern(&before, &down.prolong);
                    let (p, op) = (&*down.prolong, &mut coarse.op);
                    timed(&mut t.galerkin, || match same {
                        true => op.update_galerkin(&fine.op, p, &p.transpose()),
                        false => *op = op.galerkin_again(&fine.op, p, &p.transpose()),
                    });
                    k_pattern_changed = !same;
                }
            }
            let cal = timed(&mut t.bounds, || refresh_bounds(&mut self.levels[l], from.get(l)));
            self.calibration[l] = cal;
            self.calibrated_from[l] = from[l].clone();
        }
        if !kept {
            timed(&mut t.coarse_solve, || self.build_coarse_solve())?;
            let fine = &self.levels[0];
            self.anchor = Anchor::new(fine.mesh().coords(), &fine.inv_d[0]);
            self.refilled = None;
        }
        self.coarse_kept = kept;
        t.coarse_kept = kept;
        self.phases = t;
        self.fresh = false;
        Ok(true)
    }

    /// With the coarse levels kept: the first coarse level's Galerkin product refilled from the
    /// re-evaluated fine operator through the kept interpolation, and its bounds estimated again
    /// (from `from`'s calibration), so the fine level's first correction sees the moved mesh; the
    /// levels below it stay. A rediscretised coarse mesh does not depend on the fine operator:
    /// it stays too.
    fn refill_first_coarse(&mut self, from: &[Calibration], t: &mut Phases) -> Result<()> {
        if !(self.galerkin || self.levels[1].mesh.is_none()) {
            return Ok(());
        }
        let (upper, rest) = self.levels.split_at_mut(1);
        let (fine, coarse) = (&upper[0], &mut rest[0]);
        let p = &*fine.down.as_ref().expect("not the coarsest level").prolong;
        timed(&mut t.galerkin, || coarse.op.update_galerkin(&fine.op, p, &p.transpose()));
        self.calibration[1] = timed(&mut t.bounds, || refresh_bounds(coarse, from.get(1)));
        self.calibrated_from[1] = from[1].clone();
        if self.levels.len() == 2 {
            timed(&mut t.coarse_solve, || self.build_coarse_solve())?;
        }
        Ok(())
    }

    /// A table of the levels (PyAMG style): unknowns, cells, nonzeros of K and of the assembled
    /// biharmonic where a level has one, nonzeros per row, P's entries per row, the lines
    /// across wall layers and the unknowns on them, and the complexities (operator complexity
    /// over what each level applies: K, or the assembled A).
    pub fn describe(&self) -> String {
        let mut s =
            String::from("level  unknowns     cells       nnz(K)       nnz(A)  per row  P per row  lines (unknowns on them)\n");
        let (mut nsum, mut zsum) = (0usize, 0usize);
        let applied = |lev: &Level| lev.op.assembled_nnz().unwrap_or(lev.op.k.nnz());
        for (l, lev) in self.levels.iter().enumerate() {
            let cells = lev.mesh.as_ref().map_or("-".to_string(), |m| m.num_cells().to_string());
            let a = lev.op.assembled_nnz().map_or("-".to_string(), |z| z.to_string());
            let per_row = applied(lev) as f64 / lev.n().max(1) as f64;
            let p = lev.down.as_ref().map_or(0.0, |d| d.prolong.nnz() as f64 / d.prolong.nrows.max(1) as f64);
            let lines = lev.lines.lines();
            s += &format!(
                "{l:>5} {:>9} {cells:>9} {:>12} {a:>12} {per_row:>8.1} {p:>10.2} {:>6} ({})\n",
                lev.n(),
                lev.op.k.nnz(),
                lines.len(),
                lines.unknowns.len()
            );
            nsum += lev.n();
            zsum += applied(lev);
        }
        let f = &self.levels[0];
        s += &format!(
            "grid complexity {:.3}, operator complexity {:.3}\n",
            nsum as f64 / f.n() as f64,
            zsum as f64 / applied(f) as f64
        );
        s += &format!("setup phases: {:?}\n", self.phases);
        s
    }
}
