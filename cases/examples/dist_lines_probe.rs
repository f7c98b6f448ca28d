//! The wall-layer meshes on distributed slabs (docs/PERFORMANCE.md, "the paper's cases on 1–4
//! ranks"): run under `mpirun -np N`, it solves the boundary-layer cylinder (2D, its hybrid
//! variant, the 3D extrusion), the wall-layered airfoil pitched and the small wing plunged
//! (`wing`, docs/perf-history.md "The polish of a tangled result across ranks") with the
//! biharmonic and the Laplacian to 1e-12 and 1e-14 on slabs
//! across x and prints, per solve, the distributed iterations beside the serial cycles and the
//! largest difference from the serial displacement relative to the motion, and the distributed
//! levels beside the serial ones. Arguments: the mesh names to run (those above without one; any
//! other case of the cases crate by its name; `airfoil:N:pitch` or `airfoil:N:plunge` the
//! airfoil of N points a side so moved), `tol=T` (repeatable; 1e-12 and 1e-14 without one),
//! `method=biharmonic` or `method=laplacian` (both without one), `max=N` the most
//! distributed iterations (2000 without one) and `gather=N` the size of the level gathered
//! onto one rank (the solver's default without one).
#[path = "common/against_serial.rs"]
mod against_serial;
#[path = "../../tests/slabs/mod.rs"]
mod slabs;

use against_serial::{compare, methods, solve_params};
use meshmove::distributed::mpi::traits::*;
use meshmove::Kind;
use meshmove_cases::setups::{case, CaseSetup, Scale};
use meshmove_cases::setups3d::case3d;
use meshmove_cases::viscous::{
    airfoil_2d, boundary_conditions, motion, wing_3d, AirfoilParams, BodyMotion, WingParams, END_WALLS,
};

fn main() {
    let universe = meshmove::distributed::mpi::initialize().expect("MPI initialises once");
    let world = universe.world();
    let size = world.size() as usize;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<String> = args.iter().filter(|a| !a.contains('=')).cloned().collect();
    let tols: Vec<f64> = args.iter().filter_map(|a| a.strip_prefix("tol=")?.parse().ok()).collect();
    let tols = if tols.is_empty() { vec![1e-12, 1e-14] } else { tols };
    let methods = methods(&args);
    let all =
        ["boundary_layer_cylinder", "boundary_layer_cylinder_hybrid", "boundary_layer_cylinder_3d", "airfoil", "wing"];
    let named = |n: &&String| n.starts_with("airfoil:") || n.starts_with("wing:");
    let asked = names.iter().filter(named).map(String::as_str);
    let others = names.iter().filter(|n| !named(n)).map(String::as_str);
    let listed: Vec<&str> = if names.is_empty() { all.to_vec() } else { others.collect() };
    for name in asked.chain(listed) {
        let setup = match name.split(':').collect::<Vec<_>>()[..] {
            ["wing"] => wing(None),
            ["wing", ends] => wing(Some(ends)),
            ["airfoil", n, how] => airfoil(n.parse().unwrap_or(64), how),
            _ => {
                case(name, Scale::Quick).or_else(|| case3d(name, Scale::Quick)).unwrap_or_else(|| airfoil(64, "pitch"))
            }
        };
        let owner = slabs::slabs_across_x(&setup.mesh.to_data(), size);
        let given = (&setup.mesh, &setup.bcs, &setup.motion);
        compare(&world, name, given, &owner, &methods, &tols, solve_params(&args));
    }
}

/// The wall-layered airfoil (first height 1e-5 chord) of `n` points a side (64: the smallest of
/// the bench), pitched about its quarter chord or plunged (`how`).
fn airfoil(n: usize, how: &str) -> CaseSetup {
    let v = airfoil_2d(&AirfoilParams::new(n)).expect("the airfoil");
    let how = if how == "plunge" { BodyMotion::Plunge } else { BodyMotion::Pitch };
    let (bcs, motion) = (boundary_conditions(&v), motion(&v, how));
    CaseSetup {
        name: "airfoil".into(),
        mesh: v.mesh,
        bcs,
        motion,
        ..case("cylinder_channel", Scale::Quick).expect("a case")
    }
}

/// The small wing of `cases/tests/viscous.rs` (16 × 2, slip end walls) plunged: at 1e-8 the
/// serial solver polishes its tangled trailing edge. `ends` (`wing:fixed`, `wing:free`) makes
/// the end walls FIXED or FREE instead, which tells what the slip walls cost.
fn wing(ends: Option<&str>) -> CaseSetup {
    let v = wing_3d(&WingParams::new(16, 2)).expect("the wing");
    let (mut bcs, motion) = (boundary_conditions(&v), motion(&v, BodyMotion::Plunge));
    match ends {
        Some("fixed") => {
            bcs.set_kinds(END_WALLS, Kind::Fixed);
        }
        Some("free") => {
            bcs.set_kinds(END_WALLS, Kind::Free);
        }
        _ => {}
    }
    CaseSetup {
        name: "wing".into(),
        mesh: v.mesh,
        bcs,
        motion,
        ..case("cylinder_channel", Scale::Quick).expect("a case")
    }
}
