//! The serial boundary-condition vocabulary on a rank's part: which kinds are distributed, and
//! the per-vertex flags P and Z of each component, made by each vertex's owner (who holds every
//! face at it) and copied to the halo.

use super::error::{DistError, DistErrorKind};
use super::halo::HaloLayout;
use super::reduce::sum_in_rank_order;
use crate::bc::{component_flags, Dofs, Kind, COMPONENT, P};
use crate::multigrid::layout::Layout;
use crate::{BoundaryConditions, Mesh};

/// The conditions the distributed solver takes: FIXED, CLAMPED and FREE per patch and
/// component. SLIP walls, links (periodic pairs) and split interfaces are serial only.
/// Checked on the patches of the rank's part (a patch no rank has acts nowhere).
pub(crate) fn check_supported(me: usize, bcs: &BoundaryConditions, mesh: &Mesh) -> Result<(), DistError> {
    let refuse = |what: String| Err(DistError::new(me, DistErrorKind::Input, format!("{what} (serial only)")));
    let slip = |p: i32| (0..mesh.dim()).any(|c| bcs.kind(p, c) == Kind::Slip);
    if let Some(p) = mesh.patch_ids().into_iter().find(|&p| slip(p)) {
        return refuse(format!("patch {p} is a SLIP wall, which the distributed solver does not take"));
    }
    if !bcs.links.is_empty() {
        return refuse("the boundary conditions link patches, which the distributed solver does not take".into());
    }
    if !bcs.split_patches().is_empty() {
        return refuse(
            "the boundary conditions split an interface per region, which the distributed solver does not take".into(),
        );
    }
    Ok(())
}

/// The flags of component `c` on every local vertex (layout order): each owner's flags from
/// the patch faces at its vertices, copied to the halo, where P is added (only owned rows are
/// equations). Collective.
pub(crate) fn flags(mesh: &Mesh, halo: &HaloLayout, bcs: &BoundaryConditions, c: usize) -> Vec<u8> {
    let n = mesh.num_vertices();
    let mut f = component_flags(mesh, &Dofs::identity(n), bcs, c);
    halo.refresh(&mut f);
    f[halo.owned()..].iter_mut().for_each(|f| *f |= P);
    f
}

/// Every component needs a prescribed vertex somewhere, or its displacement is undetermined
/// (collective; the error names rank 0, which speaks for all).
pub(crate) fn check_prescribed(me: usize, halo: &HaloLayout, flags: &[Vec<u8>]) -> Result<(), DistError> {
    let owned = halo.owned();
    let counts: Vec<f64> = flags.iter().map(|f| f[..owned].iter().filter(|&&f| f & P != 0).count() as f64).collect();
    let total = sum_in_rank_order(halo.comm(), &counts);
    match total.iter().position(|&t| t == 0.0) {
        Some(c) if me == 0 => Err(DistError::new(
            0,
            DistErrorKind::Input,
            format!(
                "no vertex of any rank prescribes the {} displacement: it is undetermined (make a patch FIXED or \
                 CLAMPED in it)",
                COMPONENT[c]
            ),
        )),
        _ => Ok(()),
    }
}
