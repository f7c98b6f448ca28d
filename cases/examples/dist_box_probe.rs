//! The bench's box on distributed slabs against the serial solver (docs/PERFORMANCE.md,
//! "Distributed meshes: the command line on 1, 2 and 4 ranks"): run under `mpirun -np N`, it
//! builds the unit cube of `n=N` hexahedra per side (15 without one) as the bench does (bottom
//! FIXED, top CLAMPED and moved by A cos(2πx) cos(2πy) in z, the sides' normal component FIXED
//! and the others FREE), and with `top=fixed` the top FIXED instead, with `sides=fixed` the
//! sides FIXED in every component, and prints the distributed iterations beside the serial
//! cycles (both to 1e-8), the difference from the serial displacement and the level sizes.
//! With `sphere=V` it solves the bench's graded sphere of about V vertices instead
//! (`ogrid::sphere_with_vertices`, tetrahedra, the box's walls FIXED, the body CLAMPED and
//! moved 0.1 in x; the `--quick` ranks bench's at 30000).
//! Arguments as `dist_slip_probe`'s besides: `method=biharmonic` or `method=laplacian`.
#[path = "common/against_serial.rs"]
mod against_serial;
#[path = "../../tests/slabs/mod.rs"]
mod slabs;

use against_serial::{compare, methods, solve_params};
use meshmove::distributed::mpi::traits::*;
use meshmove::{BoundaryConditions, Kind, Motion, RigidMotion};
use meshmove_cases::boxes::{structured_box, BoxCells, BOX_BOTTOM, BOX_SIDES, BOX_TOP};
use meshmove_cases::ogrid::{self, CellKind};
use std::f64::consts::TAU;

fn main() {
    let universe = meshmove::distributed::mpi::initialize().expect("MPI initialises once");
    let world = universe.world();
    let size = world.size() as usize;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |key: &str| args.iter().find_map(|a| a.strip_prefix(key).map(str::to_string));
    if let Some(vertices) = arg("sphere=").and_then(|s| s.parse().ok()) {
        let mesh = ogrid::sphere_with_vertices(vertices, CellKind::Simplex).expect("the sphere");
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(ogrid::OG_WALL, Kind::Fixed).set_kinds(ogrid::OG_BODY, Kind::Clamped);
        let r = RigidMotion { translation: [0.1, 0.0, 0.0], rotation: [0.0; 3], center: [0.0; 3] };
        let motion = Motion::zero(&mesh).with_rigid(ogrid::OG_BODY, r);
        let owner = slabs::slabs_across_x(&mesh.to_data(), size);
        let given = (&mesh, &bcs, &motion);
        compare(&world, "graded sphere", given, &owner, &methods(&args), &[1e-8], solve_params(&args));
        return;
    }
    let n: usize = arg("n=").and_then(|s| s.parse().ok()).unwrap_or(15);
    let top = if arg("top=").as_deref() == Some("fixed") { Kind::Fixed } else { Kind::Clamped };
    let sides_fixed = arg("sides=").as_deref() == Some("fixed");
    let mesh = structured_box(n, BoxCells::Hexes);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BOX_BOTTOM, Kind::Fixed).set_kinds(BOX_TOP, top);
    for (p, normal) in BOX_SIDES {
        for c in 0..3 {
            let kind = if c == normal || sides_fixed { Kind::Fixed } else { Kind::Free };
            bcs.set_kind(p, c, kind).expect("3 components");
        }
    }
    let mut motion = Motion::zero(&mesh);
    for v in mesh.patch_vertices(BOX_TOP) {
        let p = mesh.point(v as usize);
        motion.displacement[3 * v as usize + 2] = 0.1 * (TAU * p[0]).cos() * (TAU * p[1]).cos();
    }
    let owner = slabs::slabs_across_x(&mesh.to_data(), size);
    let name = format!("box-hex {n}³ top {top:?}{}", if sides_fixed { " sides Fixed" } else { "" });
    compare(&world, &name, (&mesh, &bcs, &motion), &owner, &methods(&args), &[1e-8], solve_params(&args));
}
