//! A wing section: the airfoil mesh extruded along z between two end walls.

use super::airfoil::airfoil_parts;
use super::{AirfoilParams, ViscousMesh, END_WALLS, FARFIELD, NO_LAYER, WALL};
use crate::ogrid::push_oriented;
use meshmove::geometry::CellType;
use meshmove::mesh::{Mesh, MeshData};

/// The wing section's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WingParams {
    /// The section: the 2D airfoil mesh extruded.
    pub airfoil: AirfoilParams,
    /// Length of the span (chords).
    pub span: f64,
    /// Cells along the span (equal).
    pub span_cells: usize,
}

impl WingParams {
    /// The airfoil mesh of `points_per_side` ([`AirfoilParams::new`]) extruded over a span of 1
    /// in `span_cells` equal cells.
    pub fn new(points_per_side: usize, span_cells: usize) -> WingParams {
        WingParams { airfoil: AirfoilParams::new(points_per_side), span: 1.0, span_cells }
    }
}

/// The airfoil mesh of `p.airfoil` extruded from z = 0 to z = `p.span`: its quads become
/// hexahedra (the wall layers), its triangles wedges. Patches [`WALL`] (the wing's surface),
/// [`FARFIELD`] (the cylinder of the far field), [`END_WALLS`] (both planes z = 0 and z = span,
/// meant to be SLIP walls). Vertex (v, i) of the section's vertex v on plane i is at index
/// i · (section's vertices) + v; cells span cell by span cell.
pub fn wing_3d(p: &WingParams) -> Result<ViscousMesh, String> {
    if p.span_cells < 1 || !(p.span > 0.0 && p.span.is_finite()) {
        return Err(format!("wing: span {} in {} cells", p.span, p.span_cells));
    }
    let h = airfoil_parts(&p.airfoil)?;
    let nv = h.coords.len();
    let nz = p.span_cells;
    if nv.checked_mul(nz + 1).is_none_or(|n| n > u32::MAX as usize) {
        return Err("wing: over 2³² vertices".into());
    }
    let at = |v: u32, i: usize| v + (i * nv) as u32;
    let mut d = MeshData::new(3);
    for i in 0..=nz {
        let z = super::super::meshes::lerp_step(0.0, p.span, i, nz);
        h.coords.iter().for_each(|q| {
            d.push_vertex(&[q.x, q.y, z]);
        });
    }
    let mut cell_layer = Vec::with_capacity(nz * (h.tris.len() + h.quads.len()));
    for i in 0..nz {
        for t in &h.tris {
            let c: Vec<u32> = (0..6).map(|k| at(t[k % 3], i + k / 3)).collect();
            push_oriented(&mut d, CellType::Wedge, &c);
            cell_layer.push(NO_LAYER);
        }
        for (q, layer) in &h.quads {
            let c: Vec<u32> = (0..8).map(|k| at(q[k % 4], i + k / 4)).collect();
            push_oriented(&mut d, CellType::Hexahedron, &c);
            cell_layer.push(*layer);
        }
    }
    for i in 0..nz {
        for (e, patch) in &h.tagged {
            d.push_face(&[at(e[0], i), at(e[1], i), at(e[1], i + 1), at(e[0], i + 1)], *patch);
        }
    }
    for i in [0, nz] {
        h.tris.iter().for_each(|t| d.push_face(&t.map(|v| at(v, i)), END_WALLS));
        h.quads.iter().for_each(|(q, _)| d.push_face(&q.map(|v| at(v, i)), END_WALLS));
    }
    let mesh = Mesh::from_data(&d).map_err(|e| format!("wing: invalid mesh: {e}"))?;
    let patches = vec![(WALL, "wall"), (FARFIELD, "farfield"), (END_WALLS, "end_walls")];
    Ok(ViscousMesh { mesh, cell_layer, layers: p.airfoil.layers, patches, pitch_center: [0.25, 0.0, 0.0] })
}
