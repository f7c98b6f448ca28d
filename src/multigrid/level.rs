//! One level of the multigrid hierarchy: its unknowns, flags, operator, smoother bounds, slip
//! frames and layout, and the transfer to the next coarser level. The hierarchy builds the
//! levels (`multigrid::hierarchy`), the coarseners make their transfers, the group operator
//! (`multigrid::group`) reads them.

use super::cell_edges::Graph;
use super::layout::Distribution;
use super::line_smoother::LineBlocks;
use super::restriction::Restriction;
use crate::bc::{BoundaryConditions, Dofs, SlipFrames};
use crate::operator::LevelOperator;
use crate::sparse::CsrMatrix;
use crate::Mesh;
use std::borrow::Cow;
use std::cell::OnceCell;
use std::ops::Range;
use std::sync::Arc;

/// Interpolation from the next coarser level and its transpose.
pub(crate) struct Transfer {
    /// Fine unknowns × coarse unknowns: the coarsener's interpolation weights.
    pub(crate) prolong: Arc<CsrMatrix>,
    /// Its transpose, stored (pattern only, weights read from `prolong`) so restriction is a
    /// gather too.
    pub(crate) restrict: Restriction,
}

/// One level of the hierarchy; read through its accessors outside the crate. Per-component data (`flags`, `inv_d`, `lambda_max`) has one
/// entry per component of the displacement. What a coarsener knows of the level stays in the
/// coarsener; the coarsest level's direct solves are the hierarchy's.
pub struct Level {
    /// The level's mesh: the user's on the finest level, a coarse mesh from a coarsener that
    /// makes them; None on a level of kept unknowns.
    pub(crate) mesh: Option<Mesh>,
    /// The positions of the unknowns of a level without a mesh (`dim` values each); empty
    /// otherwise (`unknown_points` derives them from the mesh).
    pub(crate) points: Vec<f64>,
    /// The level's link pairs (periodic sides), on a level with a mesh.
    pub(crate) pairs: Vec<[u32; 2]>,
    pub(crate) dofs: Dofs,
    pub(crate) op: LevelOperator,
    pub(crate) flags: Vec<Vec<u8>>,
    pub(crate) inv_d: Vec<Vec<f64>>,
    pub(crate) lambda_max: Vec<f64>,
    /// The lines of strong coupling across thin wall layers and their factored blocks, which
    /// the smoother solves along (`multigrid::line_smoother`); empty on isotropic levels.
    pub(crate) lines: LineBlocks,
    /// Vertex i of this level is vertex `parent_vertex[i]` of the next finer level; on a level
    /// without a mesh, unknown i is unknown `parent_vertex[i]` of the next finer level.
    pub(crate) parent_vertex: Vec<u32>,
    /// Transfer to the next coarser level; None on the coarsest.
    pub(crate) down: Option<Transfer>,
    /// Slip walls: the constrained directions of the slip unknowns (`multigrid::slip` builds
    /// them from the mesh on the finest level; the coarse levels inherit them); None without
    /// slip walls.
    pub(crate) slip: Option<LevelSlip>,
    /// How the level's vectors are spread over processes (`multigrid::layout`).
    pub(crate) layout: Distribution,
}

/// What a level keeps for its slip walls.
pub(crate) struct LevelSlip {
    /// The constrained directions of the level's slip unknowns.
    pub(crate) frames: SlipFrames,
    /// The conditions the fine level's frames come from, to remake them at a new reference (fine
    /// level only).
    pub(crate) bcs: Option<BoundaryConditions>,
    /// The components are one coupled system: the finest level has slip unknowns with frames
    /// (walls not normal to an axis). Without, the walls only prescribe components (axis walls,
    /// pinned corners) and the components are solved apart. Every level has its finest's.
    pub(crate) coupled: bool,
}

impl Level {
    /// The level's unknowns: linked vertices merged, interface vertices split.
    pub fn dofs(&self) -> &Dofs {
        &self.dofs
    }

    /// The level's operator (K, V and the method's products).
    pub fn op(&self) -> &LevelOperator {
        &self.op
    }

    /// The flags (P, Z) of each component's unknowns.
    pub fn flags(&self) -> &[Vec<u8>] {
        &self.flags
    }

    /// The inverse Jacobi (l1) diagonal of each component.
    pub fn inv_d(&self) -> &[Vec<f64>] {
        &self.inv_d
    }

    /// The slip frames of the level's unknowns; None without slip walls.
    pub fn slip_frames(&self) -> Option<&SlipFrames> {
        self.slip.as_ref().map(|s| &s.frames)
    }

    /// The position of each unknown: its (first) vertex's on a level with a mesh, else stored.
    pub fn unknown_points(&self) -> Cow<'_, [f64]> {
        match &self.mesh {
            Some(m) => {
                let dim = m.dim();
                Cow::Owned(self.dofs.dof_vertex.iter().flat_map(|&v| m.point(v as usize)[..dim].iter().copied()).collect())
            }
            None => Cow::Borrowed(&self.points),
        }
    }

    /// The prolongation from the next coarser level (fine unknowns × coarse unknowns); None on
    /// the coarsest level.
    pub fn prolong(&self) -> Option<&CsrMatrix> {
        self.down.as_ref().map(|t| &*t.prolong)
    }

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

    /// Finds the level's lines across wall layers (once) and factors their blocks for its
    /// current operator and flags (`multigrid::line_smoother`); the slip unknowns of a coupled
    /// group stay off the blocks.
    pub(crate) fn refresh_lines(&mut self) {
        let mut apart = vec![false; self.n()];
        if let Some(s) = self.slip.as_ref().filter(|s| s.coupled) {
            s.frames.dofs.iter().for_each(|&d| apart[d as usize] = true);
        }
        // The lines start where the cells' edges are stretched; a level without a mesh takes
        // K's graph for its edges (its lines are its finer level's, so it is searched already).
        // The edges are built at the finder's first look at them: it reads them only at unknowns
        // anisotropic over K's graph, which an isotropic level lacks.
        let dim = self.dim();
        let points = if self.lines.searched() { Vec::new() } else { self.unknown_points().into_owned() };
        let edges = OnceCell::new();
        let Level { lines, op, flags, dofs, mesh, .. } = self;
        let (op, dofs, mesh) = (&*op, &*dofs, mesh.as_ref());
        let edges_of = |i: usize| {
            edges
                .get_or_init(|| match mesh {
                    Some(mesh) => Graph::cell_edges(mesh, dofs, &op.k),
                    None => Graph::of_entries(&op.k, |_| true),
                })
                .neighbours(i)
        };
        lines.refresh(op, flags, &apart, (&points, dim, edges_of), |d| dofs.vertices_of(d).len() > 1);
    }

    /// The slip frames coupling the group `comps`: the level's frames when its components are
    /// one coupled system and `comps` is all of them.
    pub(crate) fn coupled_frames(&self, comps: &Range<usize>) -> Option<&SlipFrames> {
        let s = self.slip.as_ref().filter(|s| s.coupled && comps.len() == self.dim() && comps.len() > 1)?;
        Some(&s.frames)
    }
}
