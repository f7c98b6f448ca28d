//! Per-unknown flags P (displacement prescribed) and Z (S fixed to zero), docs/DESIGN.md §3–§4.

use super::{BoundaryConditions, Dofs, Kind};
use crate::Mesh;

/// The displacement is prescribed.
pub const P: u8 = 1;
/// S is fixed to zero.
pub const Z: u8 = 2;

/// Flags of every unknown for one component. A vertex takes P if any of its patches prescribes
/// the component and Z if any of its patches is FIXED for it; an unknown takes the union over
/// its vertices.
pub(crate) fn component_flags(mesh: &Mesh, dofs: &Dofs, bcs: &BoundaryConditions, component: usize) -> Vec<u8> {
    let mut vflags = vec![0u8; mesh.num_vertices()];
    for e in mesh.patch_faces() {
        let f = match bcs.kind(e.patch, component) {
            Kind::Fixed => P | Z,
            Kind::Clamped => P,
            // The normal is prescribed through the level's slip frames (`bc::slip`), which make
            // the components one coupled system; no component alone is prescribed.
            Kind::Free | Kind::Slip => 0,
        };
        for &v in e.vertices {
            vflags[v as usize] |= f;
        }
    }
    (0..dofs.n).map(|d| dofs.vertices_of(d).iter().fold(0u8, |f, &v| f | vflags[v as usize])).collect()
}
