//! Reference results of the C and Fortran examples, computed through the Rust API, and the
//! comparison ctest runs when the command line is not built (else `meshmove compare`):
//!
//! ```text
//! reference_case free_surface OUT.vtu        # fortran_examples/free_surface.f90 (triangles)
//! reference_case free_surface_quads OUT.vtu  # c_examples/free_surface.c (quads)
//! reference_case fv_cylinder OUT.vtu         # c_examples/fv_cylinder.c, biharmonic run
//! reference_case fv_interface OUT.vtu        # fortran_examples/fv_interface.f90
//! reference_case fv_body3d OUT.vtu           # c_examples/fv_body3d.c (3D, hexahedra)
//! reference_case free_surface3d OUT.vtu      # fortran_examples/free_surface3d.f90 (3D, hexahedra)
//! reference_case compare A.vtu B.vtu TOL     # max |difference| of points and point data <= TOL
//! ```
//!
//! The set-ups here must match the examples operation for operation: the same mesh, built from
//! the same arrays (the grids of c_examples/box_grid.h and fortran_examples/box_grid.f90, the
//! O-grid of c_examples/fv_cylinder.c, the hexahedral grids of c_examples/fv_body3d.c and
//! fortran_examples/box_grid.f90), the same boundary conditions, the same per-step boundary
//! displacement expressions and rigid motions.

use meshmove::{BoundaryConditions, InterfaceVariant, Kind, Mesh, Motion, Options, RigidMotion, Solver};
use meshmove::{CellType, MeshData};
use std::f64::consts::PI;
use std::path::Path;
use std::process::exit;

/// c_examples/box_grid.h (triangles): the box `[b0,b1]×[b2,b3]` in `nx × ny` squares of two
/// triangles, vertex (i, j) at j (nx + 1) + i, its sides (bottom, right, top, left) tagged with
/// `side` (0: untagged), in that order.
fn box_grid(nx: u32, ny: u32, b: [f64; 4], side: [i32; 4], quads: bool) -> MeshData {
    let mut d = MeshData::new(2);
    for j in 0..=ny {
        for i in 0..=nx {
            d.push_vertex(&[b[0] + (b[1] - b[0]) * i as f64 / nx as f64, b[2] + (b[3] - b[2]) * j as f64 / ny as f64]);
        }
    }
    for j in 0..ny {
        for i in 0..nx {
            let a = j * (nx + 1) + i;
            let (c, e) = (a + nx + 2, a + nx + 1);
            if quads {
                d.push_cell(CellType::Quad, &[a, a + 1, c, e], 0);
            } else {
                d.push_cell(CellType::Triangle, &[a, a + 1, c], 0);
                d.push_cell(CellType::Triangle, &[a, c, e], 0);
            }
        }
    }
    for (k, &p) in side.iter().enumerate().filter(|(_, &p)| p != 0) {
        let (n, step) = if k % 2 == 0 { (nx, 1) } else { (ny, nx + 1) };
        for i in 0..n {
            let v = match k {
                0 => i,
                1 => i * (nx + 1) + nx,
                2 => ny * (nx + 1) + i,
                _ => i * (nx + 1),
            };
            d.push_face(&[v, v + step], p);
        }
    }
    d
}

/// Free-surface case: the 32 × 32 grid of [0,1]×[−1,0], top y-displacement 0.25 cos(2πx),
/// x-periodic sides; as quads c_examples/free_surface.c, as triangles
/// fortran_examples/free_surface.f90.
fn free_surface_case(out: &Path, quads: bool) {
    let (bottom, right, top, left) = (1, 2, 3, 4);
    let n = 32;
    let mesh = Mesh::from_data(&box_grid(n, n, [0.0, 1.0, -1.0, 0.0], [bottom, right, top, left], quads)).unwrap();
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(bottom, Kind::Fixed).set_kinds(top, Kind::Clamped);
    for p in [left, right] {
        bcs.set_kind(p, 0, Kind::Clamped).unwrap().set_kind(p, 1, Kind::Free).unwrap();
    }
    bcs.add_link(meshmove::Link::ByOffset { a: left, b: right, offset: [1.0, 0.0, 0.0], tol: 1e-9 });
    let mut motion = Motion::zero(&mesh);
    for i in 0..=n {
        let v = (n * (n + 1) + i) as usize;
        motion.displacement[2 * v + 1] = 0.25 * (2.0 * PI * mesh.point(v)[0]).cos();
    }
    let s = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    let sol = s.solve(&motion).unwrap();
    meshmove::io::write_deformed(out, &mesh, &sol.displacement).unwrap();
    println!("free_surface: {} cycles, rel residual {:e}", sol.report.cycles, sol.report.rel_residual);
}

/// Moves `s` step by step as `meshmove_solver_move` does (`motion(n, s)`: step n's motion) and
/// writes the final mesh.
fn stepped(mut s: Solver, steps: usize, motion: impl Fn(usize, &Solver) -> Motion, out: &Path) {
    for n in 1..=steps {
        let m = motion(n, &s);
        // Adopted and re-referenced as the C call does, with the same start from the last step.
        s.advance(&m).unwrap();
    }
    meshmove::io::write_deformed(out, s.mesh(), &vec![0.0; s.mesh().coords().len()]).unwrap();
}

/// c_examples/fv_cylinder.c's O-grid around the cylinder of diameter 1 at (1, 0) in the box
/// [0,2]×[−1,1]: `nr` rings of cells, `4 ns` vertices per ring, the cylinder's edges on patch
/// `cylinder` and the box's on patch `wall`.
fn o_grid(ns: u32, nr: u32, wall: i32, cylinder: i32) -> MeshData {
    let nt = 4 * ns;
    let mut d = MeshData::new(2);
    for k in 0..=nr {
        for t in 0..nt {
            let th = -0.75 * PI + 2.0 * PI * t as f64 / nt as f64;
            let u = 2.0 * (t % ns) as f64 / ns as f64;
            let s = k as f64 / nr as f64;
            let (cx, cy) = (1.0 + 0.5 * th.cos(), 0.5 * th.sin());
            let (qx, qy) = match t / ns {
                0 => (u, -1.0),
                1 => (2.0, -1.0 + u),
                2 => (2.0 - u, 1.0),
                _ => (0.0, 1.0 - u),
            };
            d.push_vertex(&[(1.0 - s) * cx + s * qx, (1.0 - s) * cy + s * qy]);
        }
    }
    for k in 0..nr {
        for t in 0..nt {
            let (a, b) = (k * nt + t, k * nt + (t + 1) % nt);
            d.push_cell(CellType::Triangle, &[a, a + nt, b + nt], 0);
            d.push_cell(CellType::Triangle, &[a, b + nt, b], 0);
        }
    }
    for t in 0..nt {
        d.push_face(&[t, (t + 1) % nt], cylinder);
    }
    for t in 0..nt {
        d.push_face(&[nr * nt + t, nr * nt + (t + 1) % nt], wall);
    }
    d
}

/// Cylinder in a box, the O-grid of 10 rings of 48 vertices, cylinder y(t) = 0.25 sin(2π t / 20)
/// over 20 steps of dt = 1 (biharmonic, walls FIXED, cylinder CLAMPED), as
/// c_examples/fv_cylinder.c.
fn fv_cylinder_case(out: &Path) {
    let (wall, cylinder) = (1, 2);
    let mesh = Mesh::from_data(&o_grid(12, 10, wall, cylinder)).unwrap();
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(wall, Kind::Fixed).set_kinds(cylinder, Kind::Clamped);
    let cyl = mesh.patch_vertices(cylinder);
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
            Motion::from_displacement(d)
        },
        out,
    );
}

/// Two regions, interface y = 0 raised to 0.25 cos(2πx) in 15 equal steps (paper Fig. 11),
/// variant A (clamped each side), sides sliding in y, on the 16 × 32 grid of [0,1]×[−1,1] whose
/// middle row is the interface; as fortran_examples/fv_interface.f90.
fn fv_interface_case(out: &Path) {
    let (bottom, right, interface, left, top) = (1, 2, 3, 4, 5);
    let (nx, ny) = (16, 32);
    let mut data = box_grid(nx, ny, [0.0, 1.0, -1.0, 1.0], [bottom, right, top, left], false);
    let row = ny / 2 * (nx + 1);
    for i in 0..nx {
        data.push_face(&[row + i, row + i + 1], interface);
    }
    let nc = data.num_cells();
    data.regions = (0..nc).map(|c| i32::from(c >= nc / 2)).collect();
    let mesh = Mesh::from_data(&data).unwrap();
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(bottom, Kind::Fixed).set_kinds(top, Kind::Fixed);
    bcs.set_kinds(interface, Kind::Clamped).set_interface(interface, InterfaceVariant::Separate);
    for p in [left, right] {
        bcs.set_kind(p, 1, Kind::Free).unwrap();
    }
    let iface = mesh.patch_vertices(interface);
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
            Motion::from_displacement(d)
        },
        out,
    );
}

/// The faces of a VTK hexahedron (local corners, right-hand normal out of the cell) and the grid
/// direction of the neighbour behind each, in c_examples/fv_body3d.c's order.
const HEX_FACE: [[usize; 4]; 6] = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
const HEX_DIR: [[i64; 3]; 6] = [[0, 0, -1], [0, 0, 1], [0, -1, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0]];

/// The structured hexahedral grid of c_examples/fv_body3d.c and fortran_examples/box_grid.f90:
/// the box `lo`–`hi` in `n³` cells, without the cells `hole.0 .. hole.1` in each direction
/// (and the vertices strictly inside them). Vertices (i, j, k) with i fastest, then j, then k;
/// cells in the same order, corners (i,j,k) (i+1,j,k) (i+1,j+1,k) (i,j+1,k) and the same at
/// k+1; tagged faces: for each cell in order, each of its faces in `HEX_FACE` order whose
/// neighbour is outside the box or in the hole, on patch `patch(face, into the hole)`.
fn hex_grid(
    n: u32,
    lo: [f64; 3],
    hi: [f64; 3],
    hole: Option<(u32, u32)>,
    patch: impl Fn(usize, bool) -> i32,
) -> MeshData {
    let (a, b) = hole.unwrap_or((0, 0));
    let hole_cell = |i: u32, j: u32, k: u32| [i, j, k].iter().all(|&x| x >= a && x < b);
    let hole_vertex = |i: u32, j: u32, k: u32| [i, j, k].iter().all(|&x| x > a && x < b);
    let mut d = MeshData::new(3);
    let m = (n + 1) as usize;
    let mut vid = vec![u32::MAX; m * m * m];
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                if !hole_vertex(i, j, k) {
                    let x: Vec<f64> =
                        (0..3).map(|c| lo[c] + (hi[c] - lo[c]) * [i, j, k][c] as f64 / n as f64).collect();
                    vid[(k as usize * m + j as usize) * m + i as usize] = d.push_vertex(&x);
                }
            }
        }
    }
    let nn = n as usize;
    let mut cid = vec![usize::MAX; nn * nn * nn];
    let mut corners = Vec::new();
    for k in 0..nn {
        for j in 0..nn {
            for i in 0..nn {
                if hole_cell(i as u32, j as u32, k as u32) {
                    continue;
                }
                cid[(k * nn + j) * nn + i] = corners.len();
                let c: [u32; 8] = std::array::from_fn(|l| {
                    let (di, dj, dk) = ([1, 2, 5, 6].contains(&l), [2, 3, 6, 7].contains(&l), l >= 4);
                    vid[((k + dk as usize) * m + j + dj as usize) * m + i + di as usize]
                });
                d.push_cell(CellType::Hexahedron, &c, 0);
                corners.push(c);
            }
        }
    }
    for k in 0..nn {
        for j in 0..nn {
            for i in 0..nn {
                let c = cid[(k * nn + j) * nn + i];
                if c == usize::MAX {
                    continue;
                }
                for (side, (f, dir)) in HEX_FACE.iter().zip(HEX_DIR).enumerate() {
                    let q = [i as i64 + dir[0], j as i64 + dir[1], k as i64 + dir[2]];
                    let inside = q.iter().all(|&x| x >= 0 && x < n as i64);
                    let into_hole = inside && hole_cell(q[0] as u32, q[1] as u32, q[2] as u32);
                    if !inside || into_hole {
                        d.push_face(&f.map(|l| corners[c][l]), patch(side, into_hole));
                    }
                }
            }
        }
    }
    d
}

/// A cube pitching in a box, as c_examples/fv_body3d.c: the box [−1,1]³ in 16³ hexahedra
/// without the body [−0.25,0.25]³, walls FIXED, body CLAMPED, the body turned about y through
/// its centre by θ(t) = 10° sin(2π t / 20), one rigid motion per step, 20 steps (biharmonic).
fn fv_body3d_case(out: &Path) {
    let (wall, body) = (1, 2);
    let mesh =
        Mesh::from_data(&hex_grid(16, [-1.0; 3], [1.0; 3], Some((6, 10)), |_, b| if b { body } else { wall })).unwrap();
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(wall, Kind::Fixed).set_kinds(body, Kind::Clamped);
    let s = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    let (amp, w) = (10.0 * PI / 180.0, 2.0 * PI / 20.0);
    stepped(
        s,
        20,
        |n, s| {
            let dth = amp * ((w * n as f64).sin() - (w * (n - 1) as f64).sin());
            let r = RigidMotion { translation: [0.0; 3], rotation: [0.0, dth, 0.0], center: [0.0; 3] };
            Motion::zero(s.mesh()).with_rigid(body, r)
        },
        out,
    );
}

/// The free surface of a box of hexahedra, as fortran_examples/free_surface3d.f90: [0,1]²×[−1,0]
/// in 8³ cells, the top raised to z = 0.15 cos(2πx) cos(2πy) in 5 equal steps, bottom FIXED,
/// top CLAMPED, the sides sliding (normal component CLAMPED, the others FREE).
fn free_surface3d_case(out: &Path) {
    let (bottom, top, xside, yside) = (1, 2, 3, 4);
    let sides = [bottom, top, yside, xside, yside, xside];
    let mesh = Mesh::from_data(&hex_grid(8, [0.0, 0.0, -1.0], [1.0, 1.0, 0.0], None, |f, _| sides[f])).unwrap();
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(bottom, Kind::Fixed).set_kinds(top, Kind::Clamped);
    bcs.set_kinds(xside, Kind::Free).set_kind(xside, 0, Kind::Clamped).unwrap();
    bcs.set_kinds(yside, Kind::Free).set_kind(yside, 1, Kind::Clamped).unwrap();
    let tops = mesh.patch_vertices(top);
    let s = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    stepped(
        s,
        5,
        |_, s| {
            let mut d = vec![0.0; s.mesh().coords().len()];
            for &v in &tops {
                let p = s.mesh().point(v as usize);
                d[3 * v as usize + 2] = 0.15 * (2.0 * PI * p[0]).cos() * (2.0 * PI * p[1]).cos() / 5.0;
            }
            Motion::from_displacement(d)
        },
        out,
    );
}

fn compare(a: &Path, b: &Path, tol: f64) -> bool {
    let (a, b) = (meshmove::io::read_vtu(a).unwrap(), meshmove::io::read_vtu(b).unwrap());
    let (ma, mb) = (&a.mesh, &b.mesh);
    let same_cells = ma.cell_types == mb.cell_types && ma.cell_vertices == mb.cell_vertices;
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
        ["free_surface", out] => free_surface_case(Path::new(out), false),
        ["free_surface_quads", out] => free_surface_case(Path::new(out), true),
        ["fv_cylinder", out] => fv_cylinder_case(Path::new(out)),
        ["fv_interface", out] => fv_interface_case(Path::new(out)),
        ["fv_body3d", out] => fv_body3d_case(Path::new(out)),
        ["free_surface3d", out] => free_surface3d_case(Path::new(out)),
        ["compare", a, b, tol] => {
            if !compare(Path::new(a), Path::new(b), tol.parse().expect("tolerance")) {
                exit(1);
            }
        }
        _ => {
            eprintln!(
                "usage: reference_case CASE OUT.vtu | compare A.vtu B.vtu TOL (CASE: free_surface, \
                 free_surface_quads, fv_cylinder, fv_interface, fv_body3d, free_surface3d)"
            );
            exit(2);
        }
    }
}
