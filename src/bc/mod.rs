//! Boundary conditions (docs/DESIGN.md §4): a kind per patch and component, links between patches, and
//! interface variants. `flags` turns them into the per-unknown P/Z flags of docs/DESIGN.md §3; `dofs`
//! merges linked vertices and splits "clamped on each side" interfaces.

mod dofs;
mod flags;
mod links;
mod numbering;
mod well_posed;

pub use dofs::Dofs;
pub(crate) use flags::component_flags;
pub use flags::{P, Z};
pub(crate) use links::resolve_links;
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
    /// Explicit vertex pairs (0-based).
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
}

impl Default for BoundaryConditions {
    fn default() -> Self {
        BoundaryConditions {
            kinds: BTreeMap::new(),
            default_kind: [Kind::Fixed; MAX_DIM],
            links: Vec::new(),
            interfaces: BTreeMap::new(),
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

    /// Patches whose shared vertices are split per region (variant A).
    pub(crate) fn split_patches(&self) -> Vec<i32> {
        self.interfaces.iter().filter(|(_, &v)| v == InterfaceVariant::Separate).map(|(&p, _)| p).collect()
    }

    /// Checks the conditions against a mesh: named patches exist, split interfaces are interior
    /// and prescribe both components.
    pub fn check(&self, mesh: &Mesh) -> Result<()> {
        let ids = mesh.patch_ids();
        for &p in self.kinds.keys().chain(self.interfaces.keys()) {
            if ids.binary_search(&p).is_err() {
                return Err(Error::Bc(format!("patch {p} is not in the mesh (patches: {ids:?})")));
            }
        }
        for p in self.split_patches() {
            if !mesh.patch_faces().any(|e| e.patch == p && e.interior) {
                return Err(Error::Bc(format!("interface patch {p} has no interior face between two cells")));
            }
            for c in 0..mesh.dim() {
                if self.kind(p, c) == Kind::Free {
                    return Err(Error::Bc(format!(
                        "interface patch {p} is split (variant A) but component {c} is FREE: each side must prescribe the position"
                    )));
                }
            }
        }
        Ok(())
    }
}
