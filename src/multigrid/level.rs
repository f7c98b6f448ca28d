//! One level of the multigrid hierarchy: its unknowns, flags, operator, smoother bounds, slip
//! frames and layout, and the transfer to the next coarser level. The hierarchy builds the
//! levels (`multigrid::hierarchy`), the coarseners make their transfers, the group operator
//! (`multigrid::group`) reads them.

use super::layout::Distribution;
use super::restriction::Restriction;
use crate::bc::{BoundaryConditions, Dofs, SlipFrames};
use crate::operator::LevelOperator;
use crate::sparse::CsrMatrix;
use crate::Mesh;
use std::ops::Range;
use std::sync::Arc;

/// Interpolation from the next coarser level and its transpose.
pub struct Transfer {
    /// Fine unknowns × coarse unknowns: the coarsener's interpolation weights.
    pub prolong: Arc<CsrMatrix>,
    /// Its transpose, stored (pattern only, weights read from `prolong`) so restriction is a
    /// gather too.
    pub restrict: Restriction,
}

/// One level of the hierarchy. Per-component data (`flags`, `inv_d`, `lambda_max`) has one
/// entry per component of the displacement. What a coarsener knows of the level stays in the
/// coarsener; the coarsest level's direct solves are the hierarchy's.
pub struct Level {
    /// The level's mesh: the user's on the finest level, a coarse mesh from a coarsener that
    /// makes them; None on a level of kept unknowns.
    pub mesh: Option<Mesh>,
    /// The positions of the unknowns of a level without a mesh (`dim` values each); empty
    /// otherwise (`unknown_points` derives them from the mesh).
    pub points: Vec<f64>,
    pub pairs: Vec<[u32; 2]>,
    pub dofs: Dofs,
    pub op: LevelOperator,
    pub flags: Vec<Vec<u8>>,
    pub inv_d: Vec<Vec<f64>>,
    pub lambda_max: Vec<f64>,
    /// Vertex i of this level is vertex `parent_vertex[i]` of the next finer level; on a level
    /// without a mesh, unknown i is unknown `parent_vertex[i]` of the next finer level.
    pub parent_vertex: Vec<u32>,
    /// Transfer to the next coarser level; None on the coarsest.
    pub down: Option<Transfer>,
    /// Slip walls: the constrained directions of the slip unknowns (`multigrid::slip` builds them), built
    /// from the mesh on the finest level and inherited below; None without slip walls.
    pub slip: Option<LevelSlip>,
    /// How the level's vectors are spread over processes (`multigrid::layout`).
    pub(crate) layout: Distribution,
}

/// What a level keeps for its slip walls.
pub struct LevelSlip {
    /// The constrained directions of the level's slip unknowns.
    pub frames: SlipFrames,
    /// The conditions the fine level's frames come from, to remake them at a new reference (fine
    /// level only).
    pub(crate) bcs: Option<BoundaryConditions>,
    /// The components are one coupled system: the finest level has slip unknowns with frames
    /// (walls not normal to an axis). Without, the walls only prescribe components (axis walls,
    /// pinned corners) and the components are solved apart. Every level has its finest's.
    pub coupled: bool,
}

impl Level {

    /// The level's mesh; only for levels that have one (the finest always has).
    pub fn mesh(&self) -> &Mesh {
        self.mesh.as_ref().expect("a level with a mesh")
    }


    /// The groups of components solved as one system: every component alone, as the methods
    /// decouple them, or all together when a slip wall couples them.
    pub fn groups(&self) -> Vec<Range<usize>> {
        if self.slip.as_ref().is_some_and(|s| s.coupled) {
            return std::iter::once(0..self.dim()).collect();
        }
        (0..self.dim()).map(|c| c..c + 1).collect()
    }


    pub fn n(&self) -> usize {
        self.dofs.n
    }

    /// The number of components of the displacement.
    pub fn dim(&self) -> usize {
        self.flags.len()
    }

    /// The region each unknown should be interpolated from: its own when it lies inside one
    /// region (or is a split copy of one), None on an unsplit interface.
    pub fn dof_regions(&self) -> Vec<Option<i32>> {
        // A vertex inside one region interpolates from that region's coarse cells only.
        let mesh = self.mesh();
        let mut vregion: Vec<Option<Option<i32>>> = vec![None; mesh.num_vertices()];
        for (c, &r) in mesh.regions().iter().enumerate() {
            for &v in mesh.cell(c) {
                let e = &mut vregion[v as usize];
                *e = match *e {
                    None => Some(Some(r)),
                    Some(Some(q)) if q == r => Some(Some(r)),
                    _ => Some(None),
                };
            }
        }
        (0..self.dofs.n).map(|d| self.dofs.region_of(d).or(vregion[self.dofs.dof_vertex[d] as usize].flatten())).collect()
    }

    /// The slip frames coupling the group `comps`: the level's frames when its components are
    /// one coupled system and `comps` is all of them.
    pub(crate) fn coupled_frames(&self, comps: &Range<usize>) -> Option<&SlipFrames> {
        let s = self.slip.as_ref().filter(|s| s.coupled && comps.len() == self.dim() && comps.len() > 1)?;
        Some(&s.frames)
    }
}
