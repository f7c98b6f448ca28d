//! The serial boundary-condition vocabulary on a rank's part: which kinds are distributed, the
//! check that every rank was given the same conditions, and the per-vertex flags P and Z of
//! each component, made by each vertex's owner (who holds every face at it) and copied to the
//! halo, with the owners' slip frames (`distributed::slip`).

use super::error::{DistError, DistErrorKind};
use super::halo::HaloLayout;
use super::reduce::{gather, sum_in_rank_order};
use super::ties::Ties;
use crate::bc::{component_flags, Dofs, COMPONENT, P, Z};
use crate::multigrid::layout::Layout;
use crate::multigrid::level::LevelSlip;
use crate::{BoundaryConditions, Mesh};

/// The conditions the distributed solver takes: FIXED, CLAMPED, FREE and SLIP (flat or curved,
/// with or without a closest-point function) per patch and component, links by offset or by
/// pairs (periodic pairs, `distributed::ties`), also together with SLIP walls, and interfaces
/// of both variants (`distributed::interfaces` splits variant A's). Checked on the patches of
/// the rank's part (a patch no rank has acts nowhere).
pub(crate) fn check_supported(me: usize, bcs: &BoundaryConditions, mesh: &Mesh) -> Result<(), DistError> {
    bcs.check_slip_kinds(mesh.dim(), &mesh.patch_ids())
        .map_err(|e| DistError::new(me, DistErrorKind::Input, e.to_string()))
}

/// Every rank was given the same conditions (kinds, links, interfaces, which patches have slip
/// surfaces): else the lowest rank whose conditions differ from rank 0's is blamed (collective;
/// the closures of slip surfaces cannot be compared, only where they are given).
pub(crate) fn check_same_everywhere(me: usize, halo: &HaloLayout, bcs: &BoundaryConditions) -> Result<(), DistError> {
    let all = gather(halo.comm(), &[bcs.digest()]);
    match all.iter().position(|&d| d != all[0]) {
        Some(r) if r == me => Err(DistError::new(
            me,
            DistErrorKind::Input,
            format!("the boundary conditions given on rank {me} differ from rank 0's: every rank must give the same"),
        )),
        _ => Ok(()),
    }
}

/// The flags of every component on every vertex of `mesh` from the patch faces at it (the
/// owners' are the complete ones).
pub(crate) fn vertex_flags(mesh: &Mesh, bcs: &BoundaryConditions) -> Vec<Vec<u8>> {
    let n = mesh.num_vertices();
    (0..mesh.dim()).map(|c| component_flags(mesh, &Dofs::identity(n), bcs, c)).collect()
}

/// The flags of every component on every local vertex (layout order) with the slip frames of
/// the owned vertices: each owner's flags `base` (`vertex_flags`, or a split mesh's), copied to
/// the halo, where P is added (only owned rows are equations); the frames then make pinned and
/// axis unknowns P (collective).
pub(crate) fn flags_and_frames(
    mesh: &Mesh,
    halo: &HaloLayout,
    bcs: &BoundaryConditions,
    base: &[Vec<u8>],
    ties: Option<&Ties>,
) -> (Vec<Vec<u8>>, Option<LevelSlip>) {
    let mut flags: Vec<Vec<u8>> = base.iter().map(|f| component_flags_of(f.clone(), halo, ties)).collect();
    let slip = super::slip::frames(mesh, halo, bcs, &mut flags, ties);
    (flags, slip)
}

/// The flags `f` of one component on every local vertex (layout order): each owner's flags (a
/// tied vertex's those of any vertex of its class, as one process's merged unknown has),
/// copied to the halo, where P is added. Collective.
fn component_flags_of(mut f: Vec<u8>, halo: &HaloLayout, ties: Option<&Ties>) -> Vec<u8> {
    if let Some(t) = ties {
        for bit in [P, Z] {
            let mut any: Vec<f64> = f.iter().map(|&x| f64::from(u8::from(x & bit != 0))).collect();
            t.total(&mut any);
            t.members().filter(|&v| any[v] > 0.0).for_each(|v| f[v] |= bit);
        }
    }
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
