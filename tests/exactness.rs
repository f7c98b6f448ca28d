//! The discrete equations reproduce what they must exactly (issue: core solver, tests 1–3).

mod common;
use common::*;
use glam::DVec2;
use meshmove::{BoundaryConditions, Kind, Mesh, Method, Motion, Options, Solver};

const METHODS: [Method; 3] = [Method::Biharmonic, Method::Laplacian, Method::Spring];

fn kinds_sets() -> Vec<(&'static str, BoundaryConditions)> {
    let mut all_fixed = BoundaryConditions::new();
    for p in [BOTTOM, RIGHT, TOP, LEFT] {
        all_fixed.set_kinds(p, Kind::Fixed);
    }
    let mut all_clamped = BoundaryConditions::new();
    for p in [BOTTOM, RIGHT, TOP, LEFT] {
        all_clamped.set_kinds(p, Kind::Clamped);
    }
    let mut mixed = BoundaryConditions::new();
    mixed.set_kinds(BOTTOM, Kind::Fixed).set_kinds(TOP, Kind::Clamped).set_kinds(LEFT, Kind::Fixed);
    mixed.set_kinds(RIGHT, Kind::Free);
    vec![("fixed", all_fixed), ("clamped", all_clamped), ("mixed", mixed)]
}

fn solver(mesh: &Mesh, bcs: &BoundaryConditions, method: Method) -> Solver {
    let mut o = Options { method, ..Default::default() };
    o.solve.tol = 1e-13;
    Solver::new(mesh, bcs, o).unwrap()
}

/// Largest component error of a flat 2D displacement `a` against `f(vertex)`.
fn max_err(a: &[f64], f: impl Fn(usize) -> DVec2) -> f64 {
    to_vec2(a).iter().enumerate().map(|(i, d)| (*d - f(i)).abs().max_element()).fold(0.0, f64::max)
}

#[test]
fn zero_boundary_motion_gives_exactly_zero() {
    let mesh = Grid::new(16, 12).jitter(0.3).mesh();
    for method in METHODS {
        for (name, bcs) in kinds_sets() {
            let s = solver(&mesh, &bcs, method);
            let sol = s.solve(&Motion::zero(&mesh)).unwrap();
            assert!(sol.displacement.iter().all(|d| *d == 0.0), "{method:?} {name}");
            assert_eq!(sol.report.cycles, 0);
        }
    }
}

#[test]
fn uniform_translation_is_reproduced() {
    let mesh = Grid::new(16, 12).jitter(0.3).mesh();
    let t = DVec2::new(0.13, -0.07);
    for method in METHODS {
        for (name, bcs) in kinds_sets() {
            let s = solver(&mesh, &bcs, method);
            let sol = s.solve(&Motion::from_displacement(to_flat(&vec![t; mesh.num_vertices()]))).unwrap();
            let e = max_err(&sol.displacement, |_| t);
            assert!(e < 1e-12, "{method:?} {name}: error {e:e}");
        }
    }
}

#[test]
fn linear_field_on_fixed_boundaries_is_exact_for_laplacian_and_biharmonic() {
    let mesh = Grid::new(16, 12).jitter(0.35).mesh();
    let lin = |x: DVec2| DVec2::new(0.1 * x.x - 0.05 * x.y + 0.01, 0.07 * x.x + 0.12 * x.y - 0.02);
    let field: Vec<DVec2> = mesh.points_2d().iter().map(|&x| lin(x)).collect();
    let bcs = &kinds_sets()[0].1;
    for method in [Method::Biharmonic, Method::Laplacian] {
        let s = solver(&mesh, bcs, method);
        let sol = s.solve(&Motion::from_displacement(to_flat(&field))).unwrap();
        let e = max_err(&sol.displacement, |i| field[i]);
        assert!(e < 1e-12, "{method:?}: error {e:e}");
    }
    // The spring analogy is not exact for a linear field on an irregular mesh: that is expected.
    let s = solver(&mesh, bcs, Method::Spring);
    let e = max_err(&s.solve(&Motion::from_displacement(to_flat(&field))).unwrap().displacement, |i| field[i]);
    assert!(e > 1e-6, "spring unexpectedly exact ({e:e})");
}

#[test]
fn rigid_rotation_of_clamped_boundaries_is_exact_with_the_rigid_flux() {
    let mesh = Grid::new(16, 12).jitter(0.35).mesh();
    let rm = planar(DVec2::new(0.05, -0.02), 0.3, DVec2::new(0.4, 0.6));
    let x = mesh.points_2d();
    let bcs = &kinds_sets()[1].1;
    let s = solver(&mesh, bcs, Method::Biharmonic);
    let mut motion = Motion::zero(&mesh);
    for p in [BOTTOM, RIGHT, TOP, LEFT] {
        motion = motion.with_rigid(p, rm);
    }
    let sol = s.solve(&motion).unwrap();
    let e = max_err(&sol.displacement, |i| rigid_at(&rm, x[i]));
    assert!(e < 1e-12, "error {e:e}");
    // Without the rigid flux (the same displacements given per vertex), held spacing is wrong.
    let plain: Vec<DVec2> = x.iter().map(|&x| rigid_at(&rm, x)).collect();
    let sol = s.solve(&Motion::from_displacement(to_flat(&plain))).unwrap();
    let e = max_err(&sol.displacement, |i| rigid_at(&rm, x[i]));
    assert!(e > 1e-4, "plain clamped unexpectedly exact ({e:e})");
}

#[test]
fn rigid_motion_is_exact_on_both_sides_of_a_split_interface() {
    use meshmove::InterfaceVariant;
    let mesh = Grid::new(12, 12).jitter(0.3).two_regions();
    let rm = planar(DVec2::new(-0.03, 0.04), -0.25, DVec2::new(0.5, 0.5));
    let x = mesh.points_2d();
    for variant in [InterfaceVariant::Separate, InterfaceVariant::Continuous] {
        let mut bcs = BoundaryConditions::new();
        bcs.default_kind = [Kind::Clamped; 3];
        bcs.set_interface(INTERFACE, variant);
        let s = solver(&mesh, &bcs, Method::Biharmonic);
        let mut motion = Motion::zero(&mesh);
        for p in [BOTTOM, RIGHT, TOP, LEFT, INTERFACE] {
            motion = motion.with_rigid(p, rm);
        }
        let sol = s.solve(&motion).unwrap();
        let e = max_err(&sol.displacement, |i| rigid_at(&rm, x[i]));
        assert!(e < 1e-12, "{variant:?}: error {e:e}");
    }
}
