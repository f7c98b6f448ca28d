//! The discrete equations reproduce what they must exactly (issue: core solver, tests 1–3).

mod common;
use common::*;
use glam::DVec2;
use meshmove::{BoundaryConditions, Kind, Mesh, Method, Motion, Options, RigidMotion, Solver};

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

fn max_err(a: &[DVec2], f: impl Fn(usize) -> DVec2) -> f64 {
    a.iter().enumerate().map(|(i, d)| (*d - f(i)).abs().max_element()).fold(0.0, f64::max)
}

#[test]
fn zero_boundary_motion_gives_exactly_zero() {
    let mesh = Grid::new(16, 12).jitter(0.3).mesh();
    for method in METHODS {
        for (name, bcs) in kinds_sets() {
            let s = solver(&mesh, &bcs, method);
            let sol = s.solve(&Motion::zero(&mesh)).unwrap();
            assert!(sol.displacement.iter().all(|d| *d == DVec2::ZERO), "{method:?} {name}");
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
            let sol = s.solve(&Motion::from_displacement(vec![t; mesh.num_vertices()])).unwrap();
            let e = max_err(&sol.displacement, |_| t);
            assert!(e < 1e-12, "{method:?} {name}: error {e:e}");
        }
    }
}

#[test]
fn linear_field_on_fixed_boundaries_is_exact_for_laplacian_and_biharmonic() {
    let mesh = Grid::new(16, 12).jitter(0.35).mesh();
    let lin = |x: DVec2| DVec2::new(0.1 * x.x - 0.05 * x.y + 0.01, 0.07 * x.x + 0.12 * x.y - 0.02);
    let field: Vec<DVec2> = mesh.coords().iter().map(|&x| lin(x)).collect();
    let bcs = &kinds_sets()[0].1;
    for method in [Method::Biharmonic, Method::Laplacian] {
        let s = solver(&mesh, bcs, method);
        let sol = s.solve(&Motion::from_displacement(field.clone())).unwrap();
        let e = max_err(&sol.displacement, |i| field[i]);
        assert!(e < 1e-12, "{method:?}: error {e:e}");
    }
    // The spring analogy is not exact for a linear field on an irregular mesh: that is expected.
    let s = solver(&mesh, bcs, Method::Spring);
    let e = max_err(&s.solve(&Motion::from_displacement(field.clone())).unwrap().displacement, |i| field[i]);
    assert!(e > 1e-6, "spring unexpectedly exact ({e:e})");
}

#[test]
fn rigid_rotation_of_clamped_boundaries_is_exact_with_the_rigid_flux() {
    let mesh = Grid::new(16, 12).jitter(0.35).mesh();
    let rm = RigidMotion { translation: DVec2::new(0.05, -0.02), angle: 0.3, center: DVec2::new(0.4, 0.6) };
    let bcs = &kinds_sets()[1].1;
    let s = solver(&mesh, bcs, Method::Biharmonic);
    let mut motion = Motion::zero(&mesh);
    for p in [BOTTOM, RIGHT, TOP, LEFT] {
        motion = motion.with_rigid(p, rm);
    }
    let sol = s.solve(&motion).unwrap();
    let e = max_err(&sol.displacement, |i| rm.displacement(mesh.coords()[i]));
    assert!(e < 1e-12, "error {e:e}");
    // Without the rigid flux (the same displacements given per vertex), held spacing is wrong.
    let plain: Vec<DVec2> = mesh.coords().iter().map(|&x| rm.displacement(x)).collect();
    let sol = s.solve(&Motion::from_displacement(plain)).unwrap();
    let e = max_err(&sol.displacement, |i| rm.displacement(mesh.coords()[i]));
    assert!(e > 1e-4, "plain clamped unexpectedly exact ({e:e})");
}

#[test]
fn rigid_motion_is_exact_on_both_sides_of_a_split_interface() {
    use meshmove::InterfaceVariant;
    let mesh = Grid::new(12, 12).jitter(0.3).two_regions();
    let rm = RigidMotion { translation: DVec2::new(-0.03, 0.04), angle: -0.25, center: DVec2::new(0.5, 0.5) };
    for variant in [InterfaceVariant::Separate, InterfaceVariant::Continuous] {
        let mut bcs = BoundaryConditions::new();
        bcs.default_kind = [Kind::Clamped; 2];
        bcs.set_interface(INTERFACE, variant);
        let s = solver(&mesh, &bcs, Method::Biharmonic);
        let mut motion = Motion::zero(&mesh);
        for p in [BOTTOM, RIGHT, TOP, LEFT, INTERFACE] {
            motion = motion.with_rigid(p, rm);
        }
        let sol = s.solve(&motion).unwrap();
        let e = max_err(&sol.displacement, |i| rm.displacement(mesh.coords()[i]));
        assert!(e < 1e-12, "{variant:?}: error {e:e}");
    }
}
