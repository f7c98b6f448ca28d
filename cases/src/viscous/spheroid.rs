//! A prolate spheroid in a box: an O-grid shell of wedge layers on the body, tetrahedra beyond.
//!
//! The mesh is the O-grid of [`crate::ogrid`] around the spheroid with the inner box's cells
//! given (so the body's tangential spacing is independent of the first layer's height): its
//! shell lines run from the body to the inner box's surface, cut into layers whose heights
//! start at the first height and grow by the growth ratio. The shell's first layers are
//! wedges: each hexahedron split in two along the diagonal of its wall-side face from that
//! face's smallest vertex index, the same diagonal in every layer (a shell vertex's index is its
//! body vertex's plus the layer). Every other hexahedron is split into 12 tetrahedra around its
//! centroid, each face along the diagonal from its smallest vertex: on the face between the last
//! wedge layer and the first tetrahedra that is the wedges' diagonal, so the mesh conforms.

use super::{body_patches, Layers, ViscousMesh, FARFIELD, NO_LAYER, WALL};
use crate::ogrid::{
    plan_with_cells, push_hex_as_tets, push_oriented, split_quad, tensor_mesh, CellKind, OgridParams, OG_BODY,
};
use meshmove::geometry::CellType;
use meshmove::mesh::{Mesh, MeshData};

/// The spheroid mesh's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpheroidParams {
    /// Cells of the inner box along y and z; twice as many along x (the long axis).
    pub cells: usize,
    /// The wall layers (wedges).
    pub layers: Layers,
    /// The spheroid's semi-axes.
    pub semi_axes: [f64; 3],
    /// Half the box's side (the box is centred on the spheroid).
    pub box_half: f64,
}

impl SpheroidParams {
    /// A spheroid of axes 1, 0.25, 0.25 at the origin in the box [−10, 10]³ (20 body lengths),
    /// `cells` inner-box cells across; 25 wedge layers, the first 10⁻⁴ high, growth 1.2.
    pub fn new(cells: usize) -> SpheroidParams {
        SpheroidParams { cells, layers: Layers::new(1e-4, 25, 1.2), semi_axes: [0.5, 0.125, 0.125], box_half: 10.0 }
    }

    /// The same with the wall layers `layers`.
    pub fn with_layers(mut self, layers: Layers) -> SpheroidParams {
        self.layers = layers;
        self
    }
}

/// The six corners of the two wedges of hexahedron `v` (bottom face 0–3, top 4–7, corner k
/// below corner k + 4): its bottom face split by [`split_quad`], each triangle with the corners
/// above it.
fn wedges(v: &[u32]) -> [[u32; 6]; 2] {
    let pos = |x: u32| v.iter().position(|&y| y == x).expect("a corner of the bottom face");
    split_quad([v[0], v[1], v[2], v[3]]).map(|t| {
        let k = t.map(pos);
        [v[k[0]], v[k[1]], v[k[2]], v[k[0] + 4], v[k[1] + 4], v[k[2] + 4]]
    })
}

/// The spheroid in its box (patches [`WALL`], [`FARFIELD`]): `p.layers.count` wedge layers on
/// the body, tetrahedra beyond; an error when the layers do not fit the shell.
pub fn spheroid_3d(p: &SpheroidParams) -> Result<ViscousMesh, String> {
    p.layers.check()?;
    let b = p.box_half;
    let mut o = OgridParams::spheroid([0.0; 3], p.semi_axes, [[-b, b]; 3], p.layers.first_height, 2.0 * b);
    o.growth = p.layers.growth.max(1.01);
    o.kind = CellKind::Simplex;
    let plan = plan_with_cells(&o, Some([2 * p.cells, p.cells, p.cells]))?;
    let m = plan.layers;
    if m <= p.layers.count {
        return Err(format!("spheroid: the shell has {m} layers, not more than the {} wall layers", p.layers.count));
    }
    let hex = tensor_mesh(&o, &plan);
    let first_shell = hex.num_cells() - m * plan.surface_faces();
    let mut d = MeshData::new(3);
    d.coords = hex.coords.clone();
    let mut cell_layer = Vec::new();
    for c in 0..hex.num_cells() {
        let v = hex.cell(c);
        let layer = (c >= first_shell).then(|| (c - first_shell) % m).filter(|&l| l < p.layers.count);
        if let Some(l) = layer {
            for w in wedges(v) {
                push_oriented(&mut d, CellType::Wedge, &w);
                cell_layer.push(l as u32);
            }
            continue;
        }
        let tets = push_hex_as_tets(&mut d, v);
        cell_layer.extend(std::iter::repeat_n(NO_LAYER, tets));
    }
    for f in 0..hex.num_faces() {
        let v = hex.face(f);
        let patch = if hex.face_patch[f] == OG_BODY { WALL } else { FARFIELD };
        for tri in split_quad([v[0], v[1], v[2], v[3]]) {
            d.push_face(&tri, patch);
        }
    }
    let mesh = Mesh::from_data(&d).map_err(|e| format!("spheroid: invalid mesh: {e}"))?;
    Ok(ViscousMesh { mesh, cell_layer, layers: p.layers, patches: body_patches(), pitch_center: [0.0; 3] })
}
