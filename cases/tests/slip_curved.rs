//! SLIP walls that are curved (docs/DESIGN.md §4 "Slip walls"): slipped vertices stay on the wall
//! (its original faces, or the analytic shape the caller gives), and a body turning inside a
//! slip wall keeps the mesh far better than a fixed wall.

#[path = "../../tests/common/mod.rs"]
mod common;
#[path = "../../tests/slip_meshes/mod.rs"]
mod slip_meshes;

use meshmove::bc::SlipSurface;
use meshmove::mesh::quality;
use meshmove::{BoundaryConditions, Kind, Link, Mesh, Method, Motion, Options, RigidMotion, Solver};

const METHODS: [Method; 3] = [Method::Biharmonic, Method::Laplacian, Method::Spring];

/// The annulus 1 ≤ r ≤ 3, the inner circle turned by 90° in 10 steps, the outer one `outer`:
/// returns the moved positions.
fn turned_annulus(mesh: &Mesh, method: Method, outer: Kind, circle: bool) -> (Vec<f64>, f64) {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(common::INNER, Kind::Clamped).set_kinds(common::OUTER, outer);
    if circle {
        bcs.set_slip_surface(
            common::OUTER,
            SlipSurface::new(|x| {
                let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
                [3.0 * x[0] / r, 3.0 * x[1] / r, 0.0]
            }),
        );
    }
    let mut solver = Solver::new(mesh, &bcs, Options { method, ..Default::default() }).unwrap();
    let turn = RigidMotion::planar([0.0, 0.0], std::f64::consts::FRAC_PI_2, [0.0, 0.0]);
    let reports = solver.move_in_steps(&Motion::zero(mesh).with_rigid(common::INNER, turn), 10).unwrap();
    let offwall = reports.iter().map(|r| r.max_slip_offwall).fold(0.0, f64::max);
    (solver.mesh().coords().to_vec(), offwall)
}

/// Largest |r − 3| over the outer circle's vertices at positions `x`.
fn off_circle(mesh: &Mesh, x: &[f64]) -> f64 {
    mesh.patch_vertices(common::OUTER)
        .iter()
        .map(|&v| ((x[2 * v as usize].powi(2) + x[2 * v as usize + 1].powi(2)).sqrt() - 3.0).abs())
        .fold(0.0, f64::max)
}

/// The outer circle's vertices turn with the body when it slips (0.2 of the body's turn for the
/// Laplacian, whose exact answer is u_θ = ω (r + 9/r) / 10, not a rigid rotation).
fn outer_turn(mesh: &Mesh, x: &[f64]) -> f64 {
    let vs = mesh.patch_vertices(common::OUTER);
    let turn: f64 = vs
        .iter()
        .map(|&v| {
            let (p, q) = (mesh.point(v as usize), &x[2 * v as usize..2 * v as usize + 2]);
            (p[0] * q[1] - p[1] * q[0]).atan2(p[0] * q[0] + p[1] * q[1])
        })
        .sum();
    turn / vs.len() as f64
}

#[test]
fn a_body_turning_inside_a_slip_circle() {
    let (nt, nr) = (96, 16);
    let mesh = common::annulus(nr, nt, 1.0, 3.0, 1.1);
    let chord = 3.0 * (1.0 - (std::f64::consts::PI / nt as f64).cos());
    for method in METHODS {
        let (fixed, _) = turned_annulus(&mesh, method, Kind::Fixed, false);
        let (slip, offwall) = turned_annulus(&mesh, method, Kind::Slip, false);
        let (qf, qs) = (quality(&mesh, &fixed), quality(&mesh, &slip));
        let (d, turn) = (off_circle(&mesh, &slip), outer_turn(&mesh, &slip).to_degrees());
        println!(
            "{method:?}: FIXED min area ratio {:.3}, min angle {:.1}°, inverted {}; SLIP {:.3}, {:.1}°, inverted {}; \
             outer circle turned {turn:.1}°, off the circle {d:.2e} (chord error {chord:.2e}), off its faces {offwall:.1e}",
            qf.min_area_ratio, qf.min_angle_deg, qf.inverted, qs.min_area_ratio, qs.min_angle_deg, qs.inverted
        );
        assert_eq!(qs.inverted, 0, "{method:?}");
        assert!(qs.min_angle_deg > 1.4 * qf.min_angle_deg && qs.min_area_ratio > qf.min_area_ratio, "{method:?}");
        assert!(d <= chord + 1e-12, "{method:?}: {d:e} off the circle");
        assert!(offwall < 1e-12, "{method:?}: {offwall:e} off the polygon");
        assert!(turn > 5.0, "{method:?}: the outer wall slides");
        // With the circle itself as the wall: on it to rounding.
        let (exact, offwall) = turned_annulus(&mesh, method, Kind::Slip, true);
        let d = off_circle(&mesh, &exact);
        assert!(d < 1e-12 && offwall < 1e-12, "{method:?}: {d:e}");
    }
}

/// The bump 0.25 exp(−(x − 2)² / 0.4) under a channel [0, 4] × [0, 1], periodic along x (the
/// bump is symmetric, so the ends match); the lower wall slips,
/// a body above it moves along it by 1.2 in 8 steps.
fn bump(x: f64) -> f64 {
    0.25 * (-(x - 2.0) * (x - 2.0) / 0.4).exp()
}

#[test]
fn vertices_sliding_over_a_bump_stay_on_it() {
    use slip_meshes::*;
    let (nx, ny) = (64, 16);
    let mesh = channel_mapped(nx, ny, 4.0, [[10, 14], [9, 12]], 0.2, |x, y| [x, bump(x) + y * (1.0 - bump(x))]);
    // The chord error of each wall segment: the largest vertical gap between bump and chord.
    let h = 4.0 / nx as f64;
    let chord = (0..nx)
        .map(|i| {
            let (a, b) = (i as f64 * h, (i + 1) as f64 * h);
            (0..=50)
                .map(|k| {
                    let x = a + (b - a) * k as f64 / 50.0;
                    let lin = bump(a) + (bump(b) - bump(a)) * (x - a) / (b - a);
                    (bump(x) - lin).abs()
                })
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    for method in METHODS {
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(BOTTOM, Kind::Slip).set_kinds(BODY, Kind::Clamped);
        bcs.set_kinds(TOP, Kind::Slip).set_kinds(LEFT, Kind::Free).set_kinds(RIGHT, Kind::Free);
        bcs.add_link(Link::ByOffset { a: LEFT, b: RIGHT, offset: [4.0, 0.0, 0.0], tol: 1e-9 });
        let mut solver = Solver::new(&mesh, &bcs, Options { method, ..Default::default() }).unwrap();
        let m = Motion::zero(&mesh).with_rigid(BODY, RigidMotion::translation([1.2, 0.0, 0.0]));
        let reports = solver.move_in_steps(&m, 8).unwrap();
        let x = solver.mesh().coords();
        let gap = mesh
            .patch_vertices(BOTTOM)
            .iter()
            .map(|&v| (x[2 * v as usize + 1] - bump(x[2 * v as usize])).abs())
            .fold(0.0, f64::max);
        let offwall = reports.iter().map(|r| r.max_slip_offwall).fold(0.0, f64::max);
        let q = quality(&mesh, x);
        let slid = mesh
            .patch_vertices(BOTTOM)
            .iter()
            .map(|&v| (x[2 * v as usize] - mesh.point(v as usize)[0]).abs())
            .fold(0.0, f64::max);
        println!(
            "{method:?}: wall vertices slid up to {slid:.3}, {gap:.2e} from the bump (chord error {chord:.2e}), \
             {offwall:.1e} from its faces; min area ratio {:.3}",
            q.min_area_ratio
        );
        assert!(slid > 0.1, "{method:?}: the wall vertices slide");
        assert!(gap <= chord + 1e-12, "{method:?}: {gap:e} from the bump, chord error {chord:e}");
        assert!(offwall < 1e-12, "{method:?}: {offwall:e}");
        assert_eq!(q.inverted, 0);
    }
}

/// "reaches 90°," or where a run of `a_sphere_turning_inside_a_slip_sphere` stopped.
fn stop_text(stop: Option<usize>, inverted: usize) -> String {
    stop.map_or("reaches 90°,".to_string(), |k| {
        format!("inverts {inverted} cells at step {k} ({}°); at step {}:", 9 * k, k - 1)
    })
}

/// The 3D analogue: a sphere turned by 90° about z in 10 steps inside a spherical shell whose
/// outer sphere (radius 3) is SLIP or FIXED.
#[test]
fn a_sphere_turning_inside_a_slip_sphere() {
    use meshmove_cases::spheres3d::{sphere_shell, SH_INNER, SH_OUTER};
    let mesh = sphere_shell(6, 4, 1.0, 3.0, 1.2);
    let off_sphere = |x: &[f64]| {
        mesh.patch_vertices(SH_OUTER)
            .iter()
            .map(|&v| {
                let p = &x[3 * v as usize..3 * v as usize + 3];
                ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 3.0).abs()
            })
            .fold(0.0, f64::max)
    };
    let turn =
        RigidMotion { translation: [0.0; 3], rotation: [0.0, 0.0, std::f64::consts::FRAC_PI_2], center: [0.0; 3] };
    for method in [Method::Biharmonic, Method::Laplacian] {
        let run = |outer: Kind, sphere: bool| {
            let mut bcs = BoundaryConditions::new();
            bcs.set_kinds(SH_INNER, Kind::Clamped).set_kinds(SH_OUTER, outer);
            if sphere {
                bcs.set_slip_surface(
                    SH_OUTER,
                    SlipSurface::new(|x| {
                        let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
                        [3.0 * x[0] / r, 3.0 * x[1] / r, 3.0 * x[2] / r]
                    }),
                );
            }
            let mut s = Solver::new(&mesh, &bcs, Options { method, ..Default::default() }).unwrap();
            let done = s.move_in_steps(&Motion::zero(&mesh).with_rigid(SH_INNER, turn), 10);
            let reps = s.step_reports().to_vec();
            let offwall = reps.iter().filter(|r| r.accepted).map(|r| r.max_slip_offwall).fold(0.0, f64::max);
            // A failed run: where it stopped (the last step's result, inverted cells and all).
            let stopped = done.is_err().then(|| reps.last().map_or(0, |r| r.step));
            (s.last_valid_coords().to_vec(), offwall, stopped, reps.last().map_or(0, |r| r.inverted))
        };
        let (fixed, _, fixed_stop, fixed_inv) = run(Kind::Fixed, false);
        let (slip, offwall, slip_stop, slip_inv) = run(Kind::Slip, false);
        let (qf, qs) = (quality(&mesh, &fixed), quality(&mesh, &slip));
        let d = off_sphere(&slip);
        println!(
            "3D {method:?}: FIXED {} min volume ratio {:.3}, min angle {:.1}°; SLIP {} min volume ratio {:.3}, min angle \
             {:.1}°, outer sphere {d:.2e} off the sphere, {offwall:.1e} off its faces",
            stop_text(fixed_stop, fixed_inv),
            qf.min_area_ratio,
            qf.min_angle_deg,
            stop_text(slip_stop, slip_inv),
            qs.min_area_ratio,
            qs.min_angle_deg
        );
        assert!(offwall < 1e-12, "{method:?}: {offwall:e}");
        if method == Method::Biharmonic {
            assert_eq!(slip_stop, None, "SLIP reaches 90°");
            assert!(qs.min_angle_deg > 1.5 * qf.min_angle_deg && qs.min_area_ratio > qf.min_area_ratio);
            let (exact, offwall, _, _) = run(Kind::Slip, true);
            assert!(off_sphere(&exact) < 1e-12 && offwall < 1e-12, "{method:?}");
        } else {
            // The Laplacian twists the hexahedra next to the turning sphere until their corners
            // fold, with either wall; with SLIP far fewer of them, and no earlier.
            assert!(slip_stop.unwrap_or(11) >= fixed_stop.unwrap_or(11));
            assert!(slip_stop != fixed_stop || slip_inv * 4 < fixed_inv, "{slip_inv} vs {fixed_inv}");
        }
    }
}

/// Slip walls keep the solver's determinism: bitwise the same result on one and two threads
/// (a curved wall: two solves and the projection onto its faces).
#[test]
fn slip_results_do_not_depend_on_the_thread_count() {
    let mesh = common::annulus(8, 48, 1.0, 3.0, 1.1);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(common::INNER, Kind::Clamped).set_kinds(common::OUTER, Kind::Slip);
    let turn = RigidMotion::planar([0.0, 0.0], 0.3, [0.0, 0.0]);
    let motion = Motion::zero(&mesh).with_rigid(common::INNER, turn);
    let run = |threads| {
        let s = Solver::new(&mesh, &bcs, Options { threads, ..Default::default() }).unwrap();
        s.solve(&motion).unwrap().displacement
    };
    let (a, b) = (run(1), run(2));
    assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
}

/// The distance of `x` from the polygon whose corners are `corners` (closed).
fn off_polygon(corners: &[[f64; 2]], x: [f64; 2]) -> f64 {
    let mut best = f64::MAX;
    for k in 0..corners.len() {
        let (a, b) = (corners[k], corners[(k + 1) % corners.len()]);
        let (ab, ax) = ([b[0] - a[0], b[1] - a[1]], [x[0] - a[0], x[1] - a[1]]);
        let t = ((ab[0] * ax[0] + ab[1] * ax[1]) / (ab[0] * ab[0] + ab[1] * ab[1])).clamp(0.0, 1.0);
        best = best.min((ax[0] - t * ab[0]).hypot(ax[1] - t * ab[1]));
    }
    best
}

/// A moving curved slip wall: the inner circle of the annulus 1 ≤ r ≤ 3 is SLIP and moves rigidly
/// (translated by (0.4, 0.2) and turned by 30° in 8 steps; the outer circle FIXED). After every
/// step each inner vertex lies on the polygon of the original inner faces carried along by the
/// motion so far (to rounding), within the chord error of the moved circle, and on the moved
/// circle itself when it is given as the wall; in both reference modes.
#[test]
fn vertices_stay_on_a_moving_slip_circle() {
    let (nt, nr) = (64, 12);
    let mesh = common::annulus(nr, nt, 1.0, 3.0, 1.1);
    let chord = 1.0 - (std::f64::consts::PI / nt as f64).cos();
    let inner = mesh.patch_vertices(common::INNER);
    let ring: Vec<[f64; 2]> = {
        // The inner circle's vertices in order of angle: the polygon of its faces.
        let mut r: Vec<[f64; 2]> =
            inner.iter().map(|&v| [mesh.point(v as usize)[0], mesh.point(v as usize)[1]]).collect();
        r.sort_by(|a, b| a[1].atan2(a[0]).total_cmp(&b[1].atan2(b[0])));
        r
    };
    let whole = RigidMotion::planar([0.4, 0.2], 30f64.to_radians(), [0.0, 0.0]);
    let steps = 8;
    for reference in [meshmove::ReferenceMode::Incremental, meshmove::ReferenceMode::Original] {
        for analytic in [false, true] {
            let mut bcs = BoundaryConditions::new();
            bcs.set_kinds(common::INNER, Kind::Slip).set_kinds(common::OUTER, Kind::Fixed);
            if analytic {
                // The circle where it is in the mesh the solver is made with.
                bcs.set_slip_surface(
                    common::INNER,
                    SlipSurface::new(|x| {
                        let r = x[0].hypot(x[1]);
                        [x[0] / r, x[1] / r, 0.0]
                    }),
                );
            }
            let opts = Options { method: Method::Biharmonic, reference, ..Default::default() };
            let mut solver = Solver::new(&mesh, &bcs, opts).unwrap();
            let (mut worst_faces, mut worst_circle, mut min_ratio) = (0.0f64, 0.0f64, f64::MAX);
            for k in 0..steps {
                let sol =
                    solver.advance(&Motion::zero(&mesh).with_rigid(common::INNER, whole.increment(k, steps))).unwrap();
                assert_eq!(sol.quality.inverted, 0);
                // Where the motion so far takes the circle.
                let done = whole.between(0.0, (k + 1) as f64 / steps as f64);
                let polygon: Vec<[f64; 2]> = ring.iter().map(|p| done.apply(p)).map(|q| [q[0], q[1]]).collect();
                let centre = done.apply(&[0.0, 0.0]);
                let x = solver.current_coords();
                let (mut off_faces, mut off_circle) = (0.0f64, 0.0f64);
                for &v in &inner {
                    let p = [x[2 * v as usize], x[2 * v as usize + 1]];
                    off_faces = off_faces.max(off_polygon(&polygon, p));
                    off_circle = off_circle.max(((p[0] - centre[0]).hypot(p[1] - centre[1]) - 1.0).abs());
                }
                let what = format!("{reference:?}, analytic {analytic}, step {}", k + 1);
                (worst_faces, worst_circle) = (worst_faces.max(off_faces), worst_circle.max(off_circle));
                min_ratio = min_ratio.min(quality(&mesh, x).min_area_ratio);
                assert!(sol.report.max_slip_offwall < 1e-12, "{what}: report {:e}", sol.report.max_slip_offwall);
                if analytic {
                    assert!(off_circle < 1e-12, "{what}: {off_circle:e} off the moved circle");
                } else {
                    assert!(off_faces < 1e-12, "{what}: {off_faces:e} off the moved faces");
                    assert!(off_circle <= chord + 1e-12, "{what}: {off_circle:e} off the moved circle");
                }
            }
            println!(
                "moving slip circle, {reference:?}, analytic {analytic}: off the moved faces ≤ {worst_faces:.1e}, off the \
                 moved circle ≤ {worst_circle:.2e} (chord error {chord:.2e}), min area ratio {min_ratio:.3}"
            );
        }
    }
}
