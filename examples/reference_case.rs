//! Reference results of the C and Fortran examples, computed through the Rust API, and the
//! comparison ctest runs (`meshmove compare` stands in until the CLI lands):
//!
//! ```text
//! reference_case free_surface OUT.vtu        # c_examples/free_surface.c, fortran_examples/free_surface.f90
//! reference_case fv_cylinder OUT.vtu         # c_examples/fv_cylinder.c, biharmonic run
//! reference_case fv_interface OUT.vtu        # fortran_examples/fv_interface.f90
//! reference_case compare A.vtu B.vtu TOL     # max |difference| of points and point data <= TOL
//! ```
//!
//! The set-ups here must match the examples operation for operation: same mesh, same boundary
//! conditions, same per-step boundary displacement expressions.

use meshmove::cases::meshes::*;
use meshmove::{BoundaryConditions, InterfaceVariant, Kind, Motion, Options, Solver};
use std::f64::consts::PI;
use std::path::Path;
use std::process::exit;

/// Free-surface case: h = 1/32, top y-displacement 0.25 cos(2πx), x-periodic sides.
fn free_surface_case(out: &Path) {
    let case = meshmove::cases::setups::free_surface_case("free_surface", 1.0 / 32.0, 0.25, 1);
    let (mesh, m) = (&case.mesh, &case.motion);
    let s = Solver::new(mesh, &case.bcs, Options::default()).unwrap();
    let sol = s.solve(m).unwrap();
    write_deformed(out, mesh, &sol.displacement);
    println!("free_surface: {} cycles, rel residual {:e}", sol.report.cycles, sol.report.rel_residual);
}

/// Moves `s` step by step as `meshmove_solver_move` does and writes the final mesh.
fn stepped(mut s: Solver, steps: usize, bdisp: impl Fn(usize, &Solver) -> Vec<f64>, out: &Path) {
    for n in 1..=steps {
        let d = bdisp(n, &s);
        let sol = s.solve(&Motion::from_displacement(d)).unwrap();
        let moved: Vec<f64> = s.mesh().coords().iter().zip(&sol.displacement).map(|(a, b)| *a + *b).collect();
        s.set_reference(moved).unwrap();
    }
    let n = s.mesh().coords().len();
    write_deformed(out, s.mesh(), &vec![0.0; n]);
}

/// Cylinder in a channel, h = 1/8, cylinder y(t) = 0.25 sin(2π t / 20) over 20 steps of dt = 1
/// (biharmonic, walls FIXED, cylinder CLAMPED), as c_examples/fv_cylinder.c.
fn fv_cylinder_case(out: &Path) {
    let mesh = cylinder_channel(1.0 / 8.0);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(CH_WALL, Kind::Fixed).set_kinds(CH_CYLINDER, Kind::Clamped);
    let cyl = mesh.patch_vertices(CH_CYLINDER);
    let s = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    let (amp, w, dt) = (0.25, 2.0 * PI / 20.0, 1.0);
    stepped(
        s,
        20,
        |n, s| {
            let t1 = n as f64 * dt;
            let t0 = (n - 1) as f64 * dt;
            let dy = amp * ((w * t1).sin() - (w * t0).sin());
            let mut d = vec![0.0; s.mesh().coords().len()];
            for &v in &cyl {
                d[2 * v as usize + 1] = dy;
            }
            d
        },
        out,
    );
}

/// Two regions, interface y = 0 raised to 0.25 cos(2πx) in 15 equal steps (paper Fig. 11),
/// variant A (clamped each side), sides sliding in y; h = 1/16; as fortran_examples/fv_interface.f90.
fn fv_interface_case(out: &Path) {
    let mesh = two_region_interface(1.0 / 16.0);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(IF_BOTTOM, Kind::Fixed).set_kinds(IF_TOP, Kind::Fixed);
    bcs.set_kinds(IF_INTERFACE, Kind::Clamped).set_interface(IF_INTERFACE, InterfaceVariant::Separate);
    for p in [IF_LEFT, IF_RIGHT] {
        bcs.set_kind(p, 1, Kind::Free).unwrap();
    }
    let iface = mesh.patch_vertices(IF_INTERFACE);
    let s = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    stepped(
        s,
        15,
        |_, s| {
            let mut d = vec![0.0; s.mesh().coords().len()];
            for &v in &iface {
                let x = s.mesh().point(v as usize)[0];
                d[2 * v as usize + 1] = 0.25 * (2.0 * PI * x).cos() / 15.0;
            }
            d
        },
        out,
    );
}

/// `meshmove::io::write_deformed` of a displacement per vertex (`dim` values per vertex).
fn write_deformed(out: &Path, mesh: &meshmove::Mesh, displacement: &[f64]) {
    meshmove::io::write_deformed(out, mesh, displacement).unwrap();
}

fn compare(a: &Path, b: &Path, tol: f64) -> bool {
    let (a, b) = (meshmove::io::read_vtu(a).unwrap(), meshmove::io::read_vtu(b).unwrap());
    let (ma, mb) = (&a.mesh, &b.mesh);
    let same_cells = (&ma.cell_types, &ma.cell_vertices) == (&mb.cell_types, &mb.cell_vertices);
    if ma.coords.len() != mb.coords.len() || !same_cells {
        println!("meshes differ: {} vs {} points, cells equal: {same_cells}", ma.num_vertices(), mb.num_vertices());
        return false;
    }
    let mut worst = 0.0f64;
    for (p, q) in ma.coords.iter().zip(&mb.coords) {
        worst = worst.max((p - q).abs());
    }
    let mut fields = 0;
    for (name, v, k) in &a.point_data {
        if let Some((_, w, _)) = b.point_data.iter().find(|(n, _, kk)| n == name && kk == k) {
            fields += 1;
            for (x, y) in v.iter().zip(w) {
                worst = worst.max((x - y).abs());
            }
        }
    }
    println!(
        "compared {} points and {fields} point fields: max |difference| = {worst:e} (tol {tol:e})",
        ma.num_vertices()
    );
    worst <= tol
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.iter().map(String::as_str).collect::<Vec<_>>().as_slice() {
        ["free_surface", out] => free_surface_case(Path::new(out)),
        ["fv_cylinder", out] => fv_cylinder_case(Path::new(out)),
        ["fv_interface", out] => fv_interface_case(Path::new(out)),
        ["compare", a, b, tol] => {
            if !compare(Path::new(a), Path::new(b), tol.parse().expect("tolerance")) {
                exit(1);
            }
        }
        _ => {
            eprintln!("usage: reference_case free_surface|fv_cylinder|fv_interface OUT.vtu | compare A.vtu B.vtu TOL");
            exit(2);
        }
    }
}
