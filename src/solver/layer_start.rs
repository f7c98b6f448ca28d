//! The biharmonic's first iterate under wall layers (docs/DESIGN.md §5, "The first
//! iterate"). A zero start leaves the whole motion of a CLAMPED body as error between the wall and
//! its first layer, a cell 10⁻⁵–10⁻⁴ of the body thick: the iterations that take it out meet the
//! relative residual long before the first layer follows the wall (the stop test under wall
//! layers then holds the solve on). The clamped layers move with the body (the rigid flux holds
//! their spacing), so each line of strong coupling that hangs off a CLAMPED patch moved rigidly
//! starts at that rigid motion, and the rest of the mesh at zero: the start's error is then
//! smooth through the layers, and its jump lies at the lines' outer ends, among cells about as
//! wide as they are thick, where the cycle takes it out at its isotropic rate.

use crate::bc::{BoundaryConditions, Kind};
use crate::motion::Motion;
use crate::multigrid::hierarchy::Hierarchy;
use crate::operator::Method;

/// The first iterate of a biharmonic solve with no guess (`dim` values per vertex) when its
/// finest level has lines hanging off a CLAMPED patch that `motion` moves rigidly: each such
/// line's vertices at the patch's rigid displacement, every other vertex at zero. None when no
/// line hangs off such a patch (the solve starts from zero).
pub(crate) fn of_layers(h: &Hierarchy, bcs: &BoundaryConditions, motion: &Motion) -> Option<Vec<f64>> {
    let lev = h.fine();
    if lev.op.method != Method::Biharmonic || lev.lines.is_empty() || motion.rigid.is_empty() {
        return None;
    }
    let (mesh, dim, k) = (lev.mesh(), lev.dim(), &lev.op.k);
    let lines = lev.lines.lines();
    let mut start: Option<Vec<f64>> = None;
    for &(patch, m) in &motion.rigid {
        if (0..dim).any(|c| bcs.kind(patch, c) != Kind::Clamped) {
            continue;
        }
        let mut on_patch = vec![false; mesh.num_vertices()];
        mesh.patch_vertices(patch).iter().for_each(|&v| on_patch[v as usize] = true);
        let held = |d: u32| lev.dofs.vertices_of(d as usize).iter().any(|&v| on_patch[v as usize]);
        // An end of a line is on the patch, or a neighbour of it in K's graph.
        let at_patch = |d: u32| {
            held(d)
                || k.cols[k.row_ptr[d as usize] as usize..k.row_ptr[d as usize + 1] as usize].iter().any(|&j| held(j))
        };
        for l in 0..lines.len() {
            let line = lines.line(l);
            let (Some(&first), Some(&last)) = (line.first(), line.last()) else { continue };
            if !at_patch(first) && !at_patch(last) {
                continue;
            }
            let start = start.get_or_insert_with(|| vec![0.0; mesh.coords().len()]);
            for &d in line {
                for &v in lev.dofs.vertices_of(d as usize) {
                    let v = v as usize;
                    let l = m.displacement(mesh.point(v));
                    start[v * dim..(v + 1) * dim].copy_from_slice(&l[..dim]);
                }
            }
        }
    }
    start
}
