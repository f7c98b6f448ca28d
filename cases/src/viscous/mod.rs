//! Wall-layered (viscous) meshes: a NACA 0012 airfoil in 2D, a prolate spheroid and an extruded
//! wing section in 3D, each with thin structured cells at the body (quads, wedges or hexahedra)
//! growing away from it, and simplices (or wedges in the wing) outside. They are the meshes of
//! turbulent-flow codes, whose wall cells reach aspect ratios of 10³–10⁴.
//!
//! Every generator is deterministic and pure Rust. Patches: [`WALL`] (the body), [`FARFIELD`]
//! (the outer boundary) and, for the wing, [`END_WALLS`] (the two planes bounding the span).
//! Every mesh comes with the wall layer of each cell ([`ViscousMesh::cell_layer`]) so a run can
//! measure how the layers moved ([`layer_volume_ratios`]).

mod airfoil;
mod motions;
mod quality;
mod spheroid;
mod wing;

pub use airfoil::{airfoil_2d, naca0012_half_thickness, AirfoilParams};
pub use motions::{body_motion, boundary_conditions, motion, BodyMotion, PITCH_DEG, PLUNGE};
pub use quality::{layer_volume_ratios, mesh_quality, MeshQuality};
pub use spheroid::{spheroid_3d, SpheroidParams};
pub use wing::{wing_3d, WingParams};

use meshmove::mesh::Mesh;

/// Patch of the body's surface (airfoil, spheroid, wing).
pub const WALL: i32 = 1;
/// Patch of the outer boundary (circle, box, or the extruded circle).
pub const FARFIELD: i32 = 2;
/// Patch of the wing's two end walls (the planes z = 0 and z = span).
pub const END_WALLS: i32 = 3;
/// [`ViscousMesh::cell_layer`] of a cell outside the wall layers.
pub const NO_LAYER: u32 = u32::MAX;

/// The wall layers: the first cell's height, how many, and the ratio of successive heights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layers {
    /// Height of the first layer (the cell on the wall).
    pub first_height: f64,
    /// Number of structured layers.
    pub count: usize,
    /// Ratio of successive layer heights.
    pub growth: f64,
}

impl Layers {
    /// `count` layers, the first `first_height` high, each `growth` times the last.
    pub fn new(first_height: f64, count: usize, growth: f64) -> Layers {
        Layers { first_height, count, growth }
    }

    /// Offset of the top of layer `k` (k = 0 is the wall) from the wall: the sum of the
    /// first k heights.
    pub fn offset(&self, k: usize) -> f64 {
        (0..k).map(|i| self.first_height * self.growth.powi(i as i32)).sum()
    }

    fn check(&self) -> Result<(), String> {
        let ok = self.first_height > 0.0 && self.first_height.is_finite() && self.count >= 1;
        if !(ok && (1.0..=2.0).contains(&self.growth)) {
            return Err(format!(
                "viscous: layers {self:?}: need a positive first height, one layer or more, growth in [1, 2]"
            ));
        }
        Ok(())
    }
}

/// The mesh of kind `kind` at `size`, as the probes and the size table name them: `airfoil`
/// (points per side), `spheroid` (cells across), `wing` (points per side and span cells, `P:S`).
pub fn by_name(kind: &str, size: &str) -> Result<ViscousMesh, String> {
    let num = |x: &str| x.parse::<usize>().map_err(|_| format!("viscous: size {x:?} is not a count"));
    match kind {
        "airfoil" => airfoil_2d(&AirfoilParams::new(num(size)?)),
        "spheroid" => spheroid_3d(&SpheroidParams::new(num(size)?)),
        "wing" => {
            let (p, z) = size.split_once(':').ok_or_else(|| format!("viscous: wing size {size:?} is not P:S"))?;
            wing_3d(&WingParams::new(num(p)?, num(z)?))
        }
        _ => Err(format!("viscous: no mesh kind {kind:?} (airfoil, spheroid, wing)")),
    }
}

/// A wall-layered mesh, with the wall layer of every cell.
#[derive(Clone, Debug)]
pub struct ViscousMesh {
    /// The validated mesh; patches [`WALL`], [`FARFIELD`] (and [`END_WALLS`] for the wing).
    pub mesh: Mesh,
    /// Per cell: its wall layer, 0 on the wall, or [`NO_LAYER`] outside the layers.
    pub cell_layer: Vec<u32>,
    /// The layers the mesh was made with.
    pub layers: Layers,
    /// Patch ids and their names (`wall`, `farfield`, `end_walls`).
    pub patches: Vec<(i32, &'static str)>,
    /// The centre the body pitches about: the quarter chord (airfoil, wing) or the centre
    /// (spheroid).
    pub pitch_center: [f64; 3],
}

/// The patch names of a 2D airfoil or a spheroid.
fn body_patches() -> Vec<(i32, &'static str)> {
    vec![(WALL, "wall"), (FARFIELD, "farfield")]
}
