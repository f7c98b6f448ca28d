//! Writes the small wall-layered meshes the C test `tests/c/viscous.c` reads:
//! `cargo run --release -p meshmove-cases --example viscous_fixtures -- tests/data`
//! gives `viscous_airfoil_22.msh` (the NACA 0012, 16 points per side, 30 quad layers from
//! 1e-5) and `viscous_spheroid_22.msh` (the spheroid, 2 cells across, 10 wedge layers from
//! 1e-4, tetrahedra outside); patches 1 (wall) and 2 (far field).

use meshmove_cases::viscous::*;
use std::path::PathBuf;

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "tests/data".into()));
    let airfoil = airfoil_2d(&AirfoilParams::new(16)).expect("airfoil");
    let spheroid = spheroid_3d(&SpheroidParams::new(2).with_layers(Layers::new(1e-4, 10, 1.2))).expect("spheroid");
    for (v, name) in [(airfoil, "viscous_airfoil_22.msh"), (spheroid, "viscous_spheroid_22.msh")] {
        let path = dir.join(name);
        meshmove::io::write_msh22(&v.mesh, &path).expect("writes the mesh");
        println!("{}: {:?}", path.display(), mesh_quality(&v));
    }
}
