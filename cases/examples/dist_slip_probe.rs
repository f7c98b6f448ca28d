//! Slip walls on distributed slabs (docs/PERFORMANCE.md, "Distributed meshes: slip walls across
//! ranks"): run under `mpirun -np N`, it solves the paper's slip-walled channels (the cylinder
//! channel and the sphere channel, walls normal to the axes) and a quarter annulus of 31 × 49
//! vertices (a curved SLIP wall, which couples the components) with the biharmonic and the
//! Laplacian to 1e-12 on slabs across x, and prints per solve the distributed iterations beside
//! the serial cycles, the largest difference from the serial displacement relative to the motion
//! and the level sizes. Arguments: the case names to run (all without one) and
//! `method=biharmonic` or `method=laplacian` (both without one); `max=N` and `gather=N` as
//! `dist_lines_probe`'s.
#[path = "common/against_serial.rs"]
mod against_serial;
#[path = "../../tests/slabs/mod.rs"]
mod slabs;

use against_serial::{compare, methods, solve_params};
use meshmove::distributed::mpi::traits::*;
use meshmove::{BoundaryConditions, Kind, Mesh, MeshData, Motion};
use meshmove_cases::setups::{case, Scale};

/// The SLIP cylinder channel with its ends (x = const) FIXED instead, its sides still SLIP.
const ENDS_FIXED: &str = "cylinder_channel_ends_fixed";
/// The SLIP cylinder channel with its sides (y = const) FIXED instead, its ends still SLIP.
const SIDES_FIXED: &str = "cylinder_channel_sides_fixed";

/// The annulus's inner curved wall and its straight side (`slabs::BODY`, `slabs::SIDE`).
const ANNULUS: &str = "quarter_annulus_31x49";

fn main() {
    let universe = meshmove::distributed::mpi::initialize().expect("MPI initialises once");
    let world = universe.world();
    let size = world.size() as usize;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<String> = args.iter().filter(|a| !a.contains('=')).cloned().collect();
    let all = ["cylinder_channel_1.5D_slip", "sphere_channel_1.5D_slip", ANNULUS, ENDS_FIXED, SIDES_FIXED];
    for name in all.iter().filter(|n| names.is_empty() || names.iter().any(|m| m == *n)) {
        let (mesh, bcs, motion) = match *name {
            ANNULUS => annulus(),
            ENDS_FIXED | SIDES_FIXED => split_channel(*name == ENDS_FIXED),
            _ => {
                let s = case(name, Scale::Quick).expect("a case");
                (s.mesh, s.bcs, s.motion)
            }
        };
        // The annulus on the slabs of `tests/distributed.rs`, the cases on those of theirs.
        let d = mesh.to_data();
        let owner = if *name == ANNULUS { slabs::slab_owner(&d, size) } else { slabs::slabs_across_x(&d, size) };
        compare(&world, name, (&mesh, &bcs, &motion), &owner, &methods(&args), &[1e-12], solve_params(&args));
    }
}

/// The quarter annulus of `tests/distributed.rs` (radii 1 and 2, 31 × 49 vertices, triangles):
/// its inner curved wall and its straight side y = 0 SLIP, the rest FIXED, every vertex moved by
/// `slabs::motion` scaled by its distance from the inner wall in the unbent square, on the slabs
/// of that test.
fn annulus() -> (Mesh, BoundaryConditions, Motion) {
    let d = slabs::grid2d(30, 48);
    let mesh = Mesh::from_data(&d).expect("a valid mesh");
    let mut out: MeshData = d.clone();
    for f in mesh.patch_faces() {
        let on = |c: usize, x: f64| f.vertices.iter().all(|&v| d.point(v as usize)[c] == x);
        if on(0, 0.0) {
            out.push_face(f.vertices, slabs::BODY);
        } else if on(1, 0.0) {
            out.push_face(f.vertices, slabs::SIDE);
        }
    }
    let mut displacement = Vec::with_capacity(2 * d.num_vertices());
    for v in 0..d.num_vertices() {
        let p = d.point(v);
        let (r, t) = (1.0 + p[0], p[1] * std::f64::consts::FRAC_PI_2);
        out.coords[v * 2] = r * t.cos();
        out.coords[v * 2 + 1] = r * t.sin();
        let m = slabs::motion(out.point(v));
        displacement.extend([m[0] * p[0], m[1] * p[0]]);
    }
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(slabs::BODY, Kind::Slip).set_kinds(slabs::SIDE, Kind::Slip);
    (Mesh::from_data(&out).expect("the annulus"), bcs, Motion { displacement, rigid: Vec::new() })
}

/// The slip-walled cylinder channel with the walls at its ends (`ends`) or along its sides made
/// FIXED, the others left SLIP: which of the x component's walls (free along the sides, its
/// normal prescribed without Z at the ends) the distributed levels treat unlike the serial ones.
fn split_channel(ends: bool) -> (Mesh, BoundaryConditions, Motion) {
    const FIXED_WALLS: i32 = 99;
    let s = case("cylinder_channel_1.5D_slip", Scale::Quick).expect("a case");
    let mut d = s.mesh.to_data();
    let xs = (0..d.num_vertices()).map(|v| d.point(v)[0]);
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
    for f in 0..d.num_faces() {
        let x: Vec<f64> = d.face(f).iter().map(|&v| d.point(v as usize)[0]).collect();
        let at_end = x.iter().all(|&x| x == lo) || x.iter().all(|&x| x == hi);
        let wall = s.bcs.is_slip(d.face_patch[f]);
        if wall && at_end == ends {
            d.face_patch[f] = FIXED_WALLS;
        }
    }
    let mut bcs = s.bcs.clone();
    bcs.set_kinds(FIXED_WALLS, Kind::Fixed);
    let mesh = Mesh::from_data(&d).expect("the channel");
    let motion = Motion { displacement: s.motion.displacement.clone(), rigid: s.motion.rigid.clone() };
    (mesh, bcs, motion)
}
