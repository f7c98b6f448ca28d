//! The wall-layer meshes on distributed slabs (docs/PERFORMANCE.md, "the paper's cases on 1–4
//! ranks"): run under `mpirun -np N`, it solves the boundary-layer cylinder (2D, its hybrid
//! variant, the 3D extrusion) and the wall-layered airfoil with the biharmonic and the Laplacian to 1e-12 and 1e-14 on slabs
//! across x and prints, per solve, the distributed iterations beside the serial cycles and the
//! largest difference from the serial displacement relative to the motion. Arguments: the mesh
//! names to run (all without one), `tol=T` (repeatable; 1e-12 and 1e-14 without one) and
//! `method=biharmonic` or `method=laplacian` (both without one).
#[path = "common/against_serial.rs"]
mod against_serial;
#[path = "../../tests/slabs/mod.rs"]
mod slabs;

use against_serial::{compare, methods};
use meshmove::distributed::mpi::traits::*;
use meshmove_cases::setups::{case, CaseSetup, Scale};
use meshmove_cases::setups3d::case3d;
use meshmove_cases::viscous::{airfoil_2d, boundary_conditions, motion, AirfoilParams, BodyMotion};

fn main() {
    let universe = meshmove::distributed::mpi::initialize().expect("MPI initialises once");
    let world = universe.world();
    let size = world.size() as usize;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<String> = args.iter().filter(|a| !a.contains('=')).cloned().collect();
    let tols: Vec<f64> = args.iter().filter_map(|a| a.strip_prefix("tol=")?.parse().ok()).collect();
    let tols = if tols.is_empty() { vec![1e-12, 1e-14] } else { tols };
    let methods = methods(&args);
    let all = ["boundary_layer_cylinder", "boundary_layer_cylinder_hybrid", "boundary_layer_cylinder_3d", "airfoil"];
    for name in all.iter().filter(|n| names.is_empty() || names.iter().any(|m| m == *n)) {
        let setup = case(name, Scale::Quick).or_else(|| case3d(name, Scale::Quick)).unwrap_or_else(airfoil);
        let owner = slabs::slabs_across_x(&setup.mesh.to_data(), size);
        compare(&world, name, (&setup.mesh, &setup.bcs, &setup.motion), &owner, &methods, &tols);
    }
}

/// The smallest wall-layered airfoil (first height 1e-5 chord) pitched about its quarter chord.
fn airfoil() -> CaseSetup {
    let v = airfoil_2d(&AirfoilParams::new(64)).expect("the airfoil");
    let (bcs, motion) = (boundary_conditions(&v), motion(&v, BodyMotion::Pitch));
    CaseSetup {
        name: "airfoil".into(),
        mesh: v.mesh,
        bcs,
        motion,
        ..case("cylinder_channel", Scale::Quick).expect("a case")
    }
}
