//! SLIP walls are exact on flat walls (docs/DESIGN.md §4 "Slip walls"): a body translated along a
//! periodic channel whose walls slip moves the whole mesh with it, for every method, also when
//! the channel is slanted, and in a 3D duct with four slip walls.

mod slip_meshes;

use meshmove::{BoundaryConditions, Kind, Link, Mesh, Method, Motion, Options, RigidMotion, Solver};
use slip_meshes::*;

const METHODS: [Method; 3] = [Method::Biharmonic, Method::Laplacian, Method::Spring];

/// Largest |d − t| over every vertex.
fn error_from_translation(d: &[f64], t: &[f64]) -> f64 {
    let dim = t.len();
    d.chunks(dim).map(|v| (0..dim).map(|c| (v[c] - t[c]).abs()).fold(0.0, f64::max)).fold(0.0, f64::max)
}

fn solver(mesh: &Mesh, bcs: &BoundaryConditions, method: Method) -> Solver {
    let mut o = Options { method, ..Default::default() };
    o.solve.tol = 1e-12;
    Solver::new(mesh, bcs, o).unwrap()
}

/// A channel along `angle`, slip walls, periodic ends, the body clamped and translated by 0.3
/// along the channel: every vertex moves by that translation.
fn slanted_channel(angle: f64) {
    let len = 4.0;
    let mesh = channel(32, 10, len, [[12, 16], [4, 7]], 0.3, angle);
    let (s, c) = angle.sin_cos();
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BOTTOM, Kind::Slip).set_kinds(TOP, Kind::Slip).set_kinds(BODY, Kind::Clamped);
    bcs.set_kinds(LEFT, Kind::Free).set_kinds(RIGHT, Kind::Free);
    bcs.add_link(Link::ByOffset { a: LEFT, b: RIGHT, offset: [len * c, len * s, 0.0], tol: 1e-9 });
    let t = [0.3 * c, 0.3 * s];
    let motion = Motion::zero(&mesh).with_rigid(BODY, RigidMotion::translation([t[0], t[1], 0.0]));
    for method in METHODS {
        let solver = solver(&mesh, &bcs, method);
        // Walls normal to an axis prescribe that component: the components stay apart. Slanted
        // walls couple them.
        let groups = if angle == 0.0 { 2 } else { 1 };
        assert_eq!(solver.hierarchy().groups().len(), groups, "angle {angle}");
        assert!(solver.num_levels() >= 2, "{method:?}: multigrid levels");
        let sol = solver.solve(&motion).unwrap();
        let e = error_from_translation(&sol.displacement, &t);
        println!(
            "angle {:.0}°, {method:?}: {} iterations, error {e:.2e}, off-wall {:.1e}",
            angle.to_degrees(),
            sol.report.cycles,
            sol.report.max_slip_offwall
        );
        assert!(e < 1e-10, "angle {angle}, {method:?}: error {e:e}");
        assert!(sol.report.max_slip_offwall < 1e-12);
    }
}

#[test]
fn translated_body_in_a_periodic_slip_channel_moves_the_mesh_uniformly() {
    slanted_channel(0.0);
}

#[test]
fn the_same_channel_rotated_by_30_degrees() {
    slanted_channel(30f64.to_radians());
}

/// With FIXED walls instead, the same motion is not a translation (the walls hold the mesh).
#[test]
fn fixed_walls_do_not_translate() {
    let mesh = channel(32, 10, 4.0, [[12, 16], [4, 7]], 0.3, 0.0);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BOTTOM, Kind::Fixed).set_kinds(TOP, Kind::Fixed).set_kinds(BODY, Kind::Clamped);
    bcs.set_kinds(LEFT, Kind::Free).set_kinds(RIGHT, Kind::Free);
    bcs.add_link(Link::ByOffset { a: LEFT, b: RIGHT, offset: [4.0, 0.0, 0.0], tol: 1e-9 });
    let motion = Motion::zero(&mesh).with_rigid(BODY, RigidMotion::translation([0.3, 0.0, 0.0]));
    let sol = solver(&mesh, &bcs, Method::Biharmonic).solve(&motion).unwrap();
    assert!(error_from_translation(&sol.displacement, &[0.3, 0.0]) > 0.1);
}

/// A periodic duct with four slip walls (their edges slide along x) and a hexahedral body moved
/// along it: the uniform translation, for every method.
#[test]
fn duct_with_four_slip_walls_translates_uniformly() {
    let mesh = duct([9, 4, 4], 3.0, [[3, 5], [1, 3], [1, 3]], 0.25);
    let mut bcs = BoundaryConditions::new();
    for p in [BOTTOM, TOP, FRONT, BACK] {
        bcs.set_kinds(p, Kind::Slip);
    }
    bcs.set_kinds(BODY, Kind::Clamped).set_kinds(LEFT, Kind::Free).set_kinds(RIGHT, Kind::Free);
    bcs.add_link(Link::ByOffset { a: LEFT, b: RIGHT, offset: [3.0, 0.0, 0.0], tol: 1e-9 });
    let t = [0.2, 0.0, 0.0];
    let motion = Motion::zero(&mesh).with_rigid(BODY, RigidMotion::translation(t));
    let turned = turned_about_x(&mesh, 20f64.to_radians());
    for (mesh, coupled) in [(&mesh, false), (&turned, true)] {
        for method in METHODS {
            let solver = solver(mesh, &bcs, method);
            let frames = &solver.hierarchy().fine().slip_frames().expect("slip frames");
            // Edge unknowns where two walls meet have two constrained directions: the axes of
            // two components in the straight duct, two coupled directions in the turned one.
            if coupled {
                assert!((0..frames.dofs.len()).any(|k| frames.directions(k).len() == 2));
                assert_eq!(solver.hierarchy().groups().len(), 1);
            } else {
                assert!(frames.dofs.is_empty() && frames.axes.iter().any(|&(_, m)| m.count_ones() == 2));
                assert_eq!(solver.hierarchy().groups().len(), 3);
            }
            let sol = solver.solve(&motion).unwrap();
            let e = error_from_translation(&sol.displacement, &t);
            println!("duct (coupled {coupled}), {method:?}: {} iterations, error {e:.2e}", sol.report.cycles);
            assert!(e < 1e-10, "{method:?}: error {e:e}");
        }
    }
}

/// On walls normal to an axis SLIP is the per-component condition (that component CLAMPED, the
/// others FREE): the same flags, the same result to the last bit.
#[test]
fn axis_walls_are_the_per_component_condition() {
    let mesh = channel(32, 10, 4.0, [[12, 16], [4, 7]], 0.3, 0.0);
    let motion = Motion::zero(&mesh).with_rigid(BODY, RigidMotion::planar([0.3, 0.1], 0.2, [1.6, 0.55]));
    let mut results = Vec::new();
    for slip in [true, false] {
        let mut bcs = BoundaryConditions::new();
        for p in [BOTTOM, TOP] {
            if slip {
                bcs.set_kinds(p, Kind::Slip);
            } else {
                bcs.set_kind(p, 0, Kind::Free).unwrap().set_kind(p, 1, Kind::Clamped).unwrap();
            }
        }
        bcs.set_kinds(BODY, Kind::Clamped).set_kinds(LEFT, Kind::Free).set_kinds(RIGHT, Kind::Free);
        bcs.add_link(Link::ByOffset { a: LEFT, b: RIGHT, offset: [4.0, 0.0, 0.0], tol: 1e-9 });
        let s = solver(&mesh, &bcs, Method::Biharmonic);
        results.push((s.hierarchy().fine().flags().to_vec(), s.solve(&motion).unwrap().displacement));
    }
    assert!(results[0] == results[1], "SLIP on axis walls differs from CLAMPED y, FREE x");
}

/// A channel with slip walls, a free body and free ends can slide as a whole: an error, not a
/// hang. (A slip body is enough to hold it: its sides' normals point along the channel.)
#[test]
fn a_mesh_free_to_slide_is_ill_posed() {
    let mesh = channel(16, 6, 4.0, [[6, 8], [2, 4]], 0.2, 0.0);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BOTTOM, Kind::Slip).set_kinds(TOP, Kind::Slip).set_kinds(BODY, Kind::Free);
    bcs.set_kinds(LEFT, Kind::Free).set_kinds(RIGHT, Kind::Free);
    bcs.add_link(Link::ByOffset { a: LEFT, b: RIGHT, offset: [4.0, 0.0, 0.0], tol: 1e-9 });
    let err = Solver::new(&mesh, &bcs, Options::default()).err().expect("ill posed");
    assert!(err.to_string().contains("slide along (1.000, 0.000)"), "{err}");
    bcs.set_kinds(BODY, Kind::Slip);
    assert!(Solver::new(&mesh, &bcs, Options::default()).is_ok());
    // SLIP must be the kind of every component.
    let mut half = BoundaryConditions::new();
    half.set_kind(BOTTOM, 0, Kind::Slip).unwrap();
    assert!(Solver::new(&mesh, &half, Options::default()).is_err());
}

/// The multigrid keeps its iteration counts on slip problems: within 1.3× of the same channel
/// with FIXED walls (the coarse levels carry the slip constraint).
#[test]
fn slip_iterations_stay_within_1_3_of_fixed() {
    let mesh = channel(64, 20, 4.0, [[24, 32], [8, 13]], 0.3, 0.4);
    let (s, c) = 0.4f64.sin_cos();
    for method in METHODS {
        let mut cycles = Vec::new();
        for wall in [Kind::Fixed, Kind::Slip] {
            let mut bcs = BoundaryConditions::new();
            bcs.set_kinds(BOTTOM, wall).set_kinds(TOP, wall).set_kinds(BODY, Kind::Clamped);
            bcs.set_kinds(LEFT, Kind::Free).set_kinds(RIGHT, Kind::Free);
            bcs.add_link(Link::ByOffset { a: LEFT, b: RIGHT, offset: [4.0 * c, 4.0 * s, 0.0], tol: 1e-9 });
            let m = RigidMotion { translation: [0.2 * c, 0.2 * s, 0.0], rotation: [0.0, 0.0, 0.2], center: [0.0; 3] };
            let motion = Motion::zero(&mesh).with_rigid(BODY, m);
            let solver = Solver::new(&mesh, &bcs, Options { method, ..Default::default() }).unwrap();
            cycles.push(solver.solve(&motion).unwrap().report.cycles);
        }
        println!("{method:?}: FIXED {} SLIP {} iterations", cycles[0], cycles[1]);
        assert!(cycles[1] as f64 <= 1.3 * cycles[0] as f64, "{method:?}: {cycles:?}");
    }
}
