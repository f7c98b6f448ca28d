//! Boundary conditions (docs/DESIGN.md §4): a kind per patch and component, links between patches, and
//! interface variants. `flags` turns them into the per-unknown P/Z flags of docs/DESIGN.md §3; `dofs`
//! merges linked vertices and splits "clamped on each side" interfaces.

mod dofs;
mod flags;
mod links;
mod numbering;
mod slip;
mod slip_walls;
mod wall_tree;
mod well_posed;

pub use dofs::Dofs;
pub(crate) use flags::component_flags;
pub use flags::{P, Z};
pub use slip::{Constraint, SlipFrames};
pub(crate) use slip::{fine_slip_frames, inherit_slip_frames};
#[cfg(feature = "mpi")]
pub(crate) use slip::{slip_frames_from_areas, WallAreas};
pub use slip_walls::{Placements, SlipSurface, SlipWalls};
pub(crate) use links::resolve_links;
#[cfg(feature = "mpi")]
pub(crate) use links::{check_offset, match_by_offset};
pub(crate) use well_posed::{check_well_posed, COMPONENT};

use crate::{Error, Mesh, Result};
use std::collections::BTreeMap;

/// The most components a displacement has (3D).
const MAX_DIM: usize = 3;

/// The boundary condition of one component on one patch (the paper's three well-posed pairs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    /// Position prescribed and ∇²d = 0: spacing free to change (flags P, Z).
    Fixed,
    /// Position prescribed and normal spacing held (flag P).
    Clamped,
    /// ∇d·n = 0 and ∇³d·n = 0: the vertex moves (no flag).
    Free,
    /// The vertex slides along its wall: the displacement normal to the wall is prescribed, the
    /// tangential components are free (docs/DESIGN.md §4). A kind of the whole patch: every
    /// component of a SLIP patch must be SLIP ([`BoundaryConditions::set_kinds`]).
    Slip,
}

/// How an internal interface between two regions couples them (docs/DESIGN.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum InterfaceVariant {
    /// Variant A: each side clamped separately; S is two-valued at the interface.
    Separate,
    /// Variant B: the shared (or merged) vertex is one unknown, S and ∇d·n continuous.
    Continuous,
}

/// Two patches joined vertex by vertex.
#[derive(Clone, Debug, PartialEq)]
pub enum Link {
    /// Every vertex `v` of patch `a` is joined to the vertex of patch `b` at `v + offset`
    /// (within `tol`); both patches must be matched completely.
    ByOffset {
        /// The first patch.
        a: i32,
        /// The partner patch.
        b: i32,
        /// From a vertex of `a` to its partner on `b` (the z component is ignored in 2D).
        offset: [f64; 3],
        /// Largest distance between `v + offset` and the partner.
        tol: f64,
    },
    /// Explicit vertex pairs (0-based vertex indices; on a distributed mesh, global ids: the same
    /// pairs on every rank).
    Pairs(Vec<[u32; 2]>),
}

/// Kinds per patch and component, links and interface variants.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryConditions {
    kinds: BTreeMap<i32, [Kind; MAX_DIM]>,
    /// Kind of patches not named, per component: FIXED, the safe choice (boundary stays where
    /// it is told).
    pub default_kind: [Kind; MAX_DIM],
    pub(crate) links: Vec<Link>,
    interfaces: BTreeMap<i32, InterfaceVariant>,
    /// Analytic shapes of SLIP walls (closest point), by patch; a SLIP patch without one is
    /// projected onto its original faces.
    surfaces: BTreeMap<i32, SlipSurface>,
}

impl Default for BoundaryConditions {
    fn default() -> Self {
        BoundaryConditions {
            kinds: BTreeMap::new(),
            default_kind: [Kind::Fixed; MAX_DIM],
            links: Vec::new(),
            interfaces: BTreeMap::new(),
            surfaces: BTreeMap::new(),
        }
    }
}

impl BoundaryConditions {
    /// Every patch FIXED in every component, no links, no interfaces.
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets the kind of one component (0 = x, 1 = y, 2 = z) on a patch. A z kind is ignored on a
    /// 2D mesh.
    pub fn set_kind(&mut self, patch: i32, component: usize, kind: Kind) -> Result<&mut Self> {
        if component >= MAX_DIM {
            return Err(Error::InvalidArgument(format!("component {component} does not exist (0 = x, 1 = y, 2 = z)")));
        }
        self.kinds.entry(patch).or_insert(self.default_kind)[component] = kind;
        Ok(self)
    }

    /// Sets the same kind for every component on a patch.
    pub fn set_kinds(&mut self, patch: i32, kind: Kind) -> &mut Self {
        self.kinds.insert(patch, [kind; MAX_DIM]);
        self
    }

    /// The kind of a component on a patch.
    pub fn kind(&self, patch: i32, component: usize) -> Kind {
        self.kinds.get(&patch).unwrap_or(&self.default_kind)[component]
    }

    /// Joins two patches (periodic sides) or explicit vertex pairs.
    pub fn add_link(&mut self, link: Link) -> &mut Self {
        self.links.push(link);
        self
    }

    /// Declares how an internal (tagged interior) patch couples its two regions.
    pub fn set_interface(&mut self, patch: i32, variant: InterfaceVariant) -> &mut Self {
        self.interfaces.insert(patch, variant);
        self
    }

    /// Gives the SLIP patch `patch` an analytic shape: after each solve its slipped vertices are
    /// moved to `surface`'s closest point instead of onto the patch's original faces. The shape
    /// is where the wall is in the mesh a solver is made with; a wall moved rigidly carries it
    /// along (the closure is asked in the wall's original frame).
    pub fn set_slip_surface(&mut self, patch: i32, surface: SlipSurface) -> &mut Self {
        self.surfaces.insert(patch, surface);
        self
    }

    /// Removes the analytic shape of a SLIP patch (its original faces are its wall again).
    pub fn remove_slip_surface(&mut self, patch: i32) -> &mut Self {
        self.surfaces.remove(&patch);
        self
    }

    /// The analytic shape of a SLIP patch, if one was given.
    pub fn slip_surface(&self, patch: i32) -> Option<&SlipSurface> {
        self.surfaces.get(&patch)
    }

    /// True when the patch is SLIP (in its first component: `check` makes sure in all).
    pub fn is_slip(&self, patch: i32) -> bool {
        self.kind(patch, 0) == Kind::Slip
    }

    /// Patches whose shared vertices are split per region (variant A).
    pub(crate) fn split_patches(&self) -> Vec<i32> {
        self.interfaces.iter().filter(|(_, &v)| v == InterfaceVariant::Separate).map(|(&p, _)| p).collect()
    }

    /// SLIP is a kind of whole patches: every component of a SLIP patch (of `patches` and of
    /// those named) is SLIP, and only SLIP patches have slip surfaces.
    pub(crate) fn check_slip_kinds(&self, dim: usize, patches: &[i32]) -> Result<()> {
        for p in patches.iter().copied().chain(self.kinds.keys().copied()) {
            let slip = (0..dim).filter(|&c| self.kind(p, c) == Kind::Slip).count();
            if slip != 0 && slip != dim {
                return Err(Error::Bc(format!(
                    "patch {p} is SLIP in {slip} of its {dim} components: SLIP is a kind of the whole patch (the \
                     normal is prescribed, the tangential components are free), set it for every component"
                )));
            }
        }
        for &p in self.surfaces.keys() {
            if !self.is_slip(p) {
                return Err(Error::Bc(format!("patch {p} has a slip surface but is not SLIP")));
            }
        }
        Ok(())
    }

    /// Some patch (named or by default) is SLIP.
    #[cfg(feature = "mpi")]
    pub(crate) fn any_slip(&self) -> bool {
        self.kinds.values().chain([&self.default_kind]).any(|k| k.contains(&Kind::Slip))
    }

    /// A digest of everything the conditions say (kinds, links, interfaces, which patches have
    /// slip surfaces), to check that every rank of a distributed solver was given the same.
    #[cfg(feature = "mpi")]
    pub(crate) fn digest(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let text = format!(
            "{:?} {:?} {:?} {:?} {:?}",
            self.kinds,
            self.default_kind,
            self.links,
            self.interfaces,
            self.surfaces.keys().collect::<Vec<_>>()
        );
        // SipHash with its fixed keys: the same digest in every process of one build.
        let mut h = std::collections::hash_map::DefaultHasher::new();
        text.hash(&mut h);
        h.finish()
    }

    /// Checks the conditions against a mesh: named patches exist, split interfaces are interior
    /// and prescribe both components.
    pub fn check(&self, mesh: &Mesh) -> Result<()> {
        let ids = mesh.patch_ids();
        for &p in self.kinds.keys().chain(self.interfaces.keys()).chain(self.surfaces.keys()) {
            if ids.binary_search(&p).is_err() {
                return Err(Error::Bc(format!("patch {p} is not in the mesh (patches: {ids:?})")));
            }
        }
        self.check_slip_kinds(mesh.dim(), &ids)?;
        for p in self.split_patches() {
            if !mesh.patch_faces().any(|e| e.patch == p && e.interior) {
                return Err(Error::Bc(format!("interface patch {p} has no interior face between two cells")));
            }
        }
        self.check_split_prescribed(mesh.dim())
    }

    /// Every split interface (variant A) prescribes each of the `dim` components on each side.
    pub(crate) fn check_split_prescribed(&self, dim: usize) -> Result<()> {
        for p in self.split_patches() {
            if let Some(c) = (0..dim).find(|&c| matches!(self.kind(p, c), Kind::Free | Kind::Slip)) {
                return Err(Error::Bc(format!(
                    "interface patch {p} is split (variant A) but component {c} is {}: each side must prescribe the position",
                    format!("{:?}", self.kind(p, c)).to_uppercase()
                )));
            }
        }
        Ok(())
    }
}
