//! What a host relies on from the Rust API: a total motion from the original mesh that follows
//! a cleared rigid motion, failing calls that leave every observable state as it was, and
//! progress with cancellation.

mod common;
use common::*;
use meshmove::{BoundaryConditions, IndexBase, Mesh, Motion, Options, ReferenceMode, RigidMotion, Solver};

fn grid_solver(reference: ReferenceMode) -> (meshmove::Mesh, Solver) {
    let mesh = Grid::new(6, 6).jitter(0.2).mesh();
    let opts = Options { reference, ..Default::default() };
    let s = Solver::new(&mesh, &BoundaryConditions::new(), opts).unwrap();
    (mesh, s)
}

/// A displacement of `d` on every vertex of `patch`, nothing elsewhere.
fn on_patch(mesh: &meshmove::Mesh, patch: i32, d: [f64; 2]) -> Motion {
    let mut m = Motion::zero(mesh);
    for v in mesh.patch_vertices(patch) {
        m.displacement[v as usize * 2..v as usize * 2 + 2].copy_from_slice(&d);
    }
    m
}

#[test]
fn a_displacement_after_a_cleared_rigid_motion_moves_the_patch_in_both_modes() {
    for mode in [ReferenceMode::Incremental, ReferenceMode::Original] {
        let (mesh, mut s) = grid_solver(mode);
        let shift = RigidMotion::translation([0.1, 0.0, 0.0]);
        s.advance(&Motion::zero(&mesh).with_rigid(TOP, shift)).unwrap();
        s.advance(&on_patch(&mesh, TOP, [0.0, 0.05])).unwrap();
        let x = s.current_coords();
        for v in mesh.patch_vertices(TOP) {
            let (v, p) = (v as usize, mesh.point(v as usize));
            assert!((x[v * 2] - (p[0] + 0.1)).abs() < 1e-12, "{mode:?}: vertex {v} x {}", x[v * 2]);
            assert!((x[v * 2 + 1] - (p[1] + 0.05)).abs() < 1e-12, "{mode:?}: vertex {v} y {}", x[v * 2 + 1]);
        }
    }
}

#[test]
fn a_rigid_motion_after_a_displacement_starts_where_the_patch_is() {
    for mode in [ReferenceMode::Incremental, ReferenceMode::Original] {
        let (mesh, mut s) = grid_solver(mode);
        s.advance(&on_patch(&mesh, TOP, [0.0, 0.05])).unwrap();
        let turn = RigidMotion::planar([0.0, 0.0], 0.1, [0.5, 1.0]);
        s.advance(&Motion::zero(&mesh).with_rigid(TOP, turn)).unwrap();
        let x = s.current_coords();
        for v in mesh.patch_vertices(TOP) {
            let (v, p) = (v as usize, mesh.point(v as usize));
            let want = turn.apply(&[p[0], p[1] + 0.05]);
            for c in 0..2 {
                assert!((x[v * 2 + c] - want[c]).abs() < 1e-12, "{mode:?}: vertex {v}");
            }
        }
    }
}

#[test]
fn a_progress_hook_sees_every_step_and_cancels_after_k() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;
    for mode in [ReferenceMode::Incremental, ReferenceMode::Original] {
        let (mesh, mut s) = grid_solver(mode);
        s.move_in_steps(&on_patch(&mesh, TOP, [0.02, 0.0]), 2).unwrap();
        let before = s.current_coords().to_vec();
        let seen = Arc::new(AtomicUsize::new(0));
        let count = Arc::clone(&seen);
        let mut o = s.options().clone();
        o.progress = Some(meshmove::Progress::new(move |r, steps| {
            assert_eq!(steps, 10);
            let k = count.fetch_add(1, Ordering::Relaxed) + 1;
            assert_eq!(r.step, k);
            k < 3
        }));
        s.set_options(o).unwrap();
        let e = s.move_in_steps(&on_patch(&mesh, TOP, [0.0, 0.05]), 10).unwrap_err();
        assert!(matches!(e, meshmove::Error::Cancelled(_)), "{mode:?}: {e}");
        assert!(e.to_string().contains("after step 3.1 of 10"), "{e}");
        assert_eq!(seen.load(Ordering::Relaxed), 3);
        assert_eq!(s.current_coords(), before.as_slice(), "{mode:?}");
        assert_eq!(s.step_reports().len(), 3);
        // The same solver goes on normally once the hook lets it.
        let mut o = s.options().clone();
        o.progress = None;
        s.set_options(o).unwrap();
        s.move_in_steps(&on_patch(&mesh, TOP, [0.0, 0.05]), 10).unwrap();
        assert_ne!(s.current_coords(), before.as_slice());
    }
}

#[test]
fn an_inverted_last_step_is_reported_not_accepted() {
    let (mesh, mut s) = grid_solver(ReferenceMode::Incremental);
    let before = s.current_coords().to_vec();
    let sol = s.advance(&on_patch(&mesh, TOP, [0.0, -2.0])).unwrap();
    assert!(sol.quality.inverted > 0);
    let r = s.step_reports();
    assert_eq!(r.len(), 1);
    assert!(r[0].inverted > 0 && r[0].converged && !r[0].accepted, "{}", r[0].line());
    assert!(sol.report.cycles > 0 && sol.report.converged);
    assert_eq!(s.current_coords(), before.as_slice());
}

/// The top of the 6 × 6 grid bent up by `a` sin(πx).
fn bend(mesh: &meshmove::Mesh, a: f64) -> Motion {
    let mut m = Motion::zero(mesh);
    for v in mesh.patch_vertices(TOP) {
        let v = v as usize;
        m.displacement[v * 2 + 1] = a * (std::f64::consts::PI * mesh.point(v)[0]).sin();
    }
    m
}

#[test]
fn the_solve_does_not_depend_on_the_size_of_the_motion() {
    let (mesh, s) = grid_solver(ReferenceMode::Incremental);
    let normal = s.solve(&bend(&mesh, 0.05)).unwrap().displacement;
    let big = normal.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    let top = mesh.patch_vertices(TOP);
    let interior = |d: &[f64]| (0..mesh.num_vertices()).any(|v| d[2 * v + 1] != 0.0 && !top.contains(&(v as u32)));
    assert!(interior(&normal));
    let scaled = |a: f64, sol: meshmove::Solution| {
        assert!(interior(&sol.displacement), "amplitude {a:e}: the interior did not move");
        let f = a / 0.05;
        let worst = sol.displacement.iter().zip(&normal).map(|(d, n)| (d / f - n).abs()).fold(0.0, f64::max);
        assert!(worst <= 1e-9 * big, "amplitude {a:e}: {worst:e} off the scaled answer");
    };
    for a in [1e-170, 1e-300, 1e100] {
        scaled(a, s.solve(&bend(&mesh, a)).unwrap_or_else(|e| panic!("amplitude {a:e}: {e}")));
    }
    // Up to what the moved mesh's areas can hold (the bend moves y alone): the answer, or an
    // overflow said so.
    for a in [1e154, 1e200, 1e300] {
        match s.solve(&bend(&mesh, a)) {
            Ok(sol) => scaled(a, sol),
            Err(meshmove::Error::InvalidArgument(m)) if m.contains("overflow") => {}
            Err(e) => panic!("amplitude {a:e}: {e}"),
        }
    }
    // Beyond it (x and y of 1e300: areas of 1e600): refused, naming the overflow.
    let e = s.solve(&on_patch(&mesh, TOP, [1e300, 1e300])).unwrap_err();
    assert!(matches!(&e, meshmove::Error::InvalidArgument(m) if m.contains("overflow")), "{e}");
}

#[test]
fn a_mesh_too_large_for_its_areas_is_refused_as_an_overflow() {
    let mut g = Grid::new(4, 4);
    g.x = [0.0, 1e155];
    g.y = [0.0, 1e155];
    let e = Mesh::triangles(&g.coords(), &g.cells(), IndexBase::Zero, &g.tagged(), None).unwrap_err();
    assert!(e.to_string().contains("overflows") && !e.to_string().contains("zero area"), "{e}");
    // Cells of 1e90 still work.
    g.x = [0.0, 1e90];
    g.y = [0.0, 1e90];
    let mesh = Mesh::triangles(&g.coords(), &g.cells(), IndexBase::Zero, &g.tagged(), None).unwrap();
    let s = Solver::new(&mesh, &BoundaryConditions::new(), Options::default()).unwrap();
    assert!(s.solve(&on_patch(&mesh, TOP, [0.0, 1e88])).is_ok());
}

#[test]
fn a_cancel_request_stops_a_solve_within_one_cycle_and_is_consumed() {
    // A grid large enough for a solve of several cycles.
    let mesh = Grid::new(24, 24).jitter(0.2).mesh();
    let mut s = Solver::new(&mesh, &BoundaryConditions::new(), Options::default()).unwrap();
    // Both components move, so the first group's solve (x) has cycles to stop.
    let m = on_patch(&mesh, TOP, [0.03, 0.05]);
    let want = s.solve(&m).unwrap();
    assert!(want.report.cycles > 1);
    s.canceller().cancel();
    let e = s.solve(&m).unwrap_err();
    assert!(matches!(&e, meshmove::Error::Cancelled(_)) && e.to_string().contains("after 1 of its cycles"), "{e}");
    assert!(!s.canceller().is_requested());
    let again = s.solve(&m).unwrap();
    assert_eq!(again.displacement, want.displacement);
    // A request from the progress hook, while move_in_steps holds the solver: the next step's
    // solve stops after its first cycle and the call changes nothing.
    let before = s.current_coords().to_vec();
    let cancel = s.canceller();
    let mut o = s.options().clone();
    o.progress = Some(meshmove::Progress::new(move |r, _| {
        if r.step == 2 {
            cancel.cancel();
        }
        true
    }));
    s.set_options(o).unwrap();
    let e = s.move_in_steps(&m, 5).unwrap_err();
    assert!(e.to_string().contains("after 1 of its cycles"), "{e}");
    assert_eq!(s.step_reports().len(), 2);
    assert_eq!(s.current_coords(), before.as_slice());
}

/// A cancelled call puts back the interpolation weights it started with (a re-reference keeps
/// those of rows whose donors moved little): the calls after it give bitwise what they give on
/// a solver that never made it.
#[test]
fn a_cancelled_call_leaves_the_next_results_bitwise() {
    let mesh = Grid::new(40, 40).jitter(0.2).mesh();
    let make = || Solver::new(&mesh, &BoundaryConditions::new(), Options::default()).unwrap();
    let (mut a, mut b) = (make(), make());
    assert!(a.num_levels() > 2, "{} levels", a.num_levels());
    let first = on_patch(&mesh, TOP, [0.03, 0.0]);
    a.move_in_steps(&first, 2).unwrap();
    b.move_in_steps(&first, 2).unwrap();
    let mut o = a.options().clone();
    o.progress = Some(meshmove::Progress::new(|r, _| r.step < 3));
    a.set_options(o).unwrap();
    assert!(a.move_in_steps(&on_patch(&mesh, TOP, [0.0, 0.2]), 5).is_err());
    assert_eq!(a.step_reports().len(), 3);
    let mut o = a.options().clone();
    o.progress = None;
    a.set_options(o).unwrap();
    let next = on_patch(&mesh, TOP, [-0.02, 0.06]);
    a.move_in_steps(&next, 3).unwrap();
    b.move_in_steps(&next, 3).unwrap();
    let (xa, xb) = (a.current_coords(), b.current_coords());
    assert!(xa.iter().zip(xb).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert_ne!(xa, mesh.coords());
}

/// Each step report splits its time into the solve and the quality check, and gives the
/// re-reference apart; a rejected attempt made no new reference.
#[test]
fn step_reports_give_solve_quality_and_reference_apart() {
    let (mesh, mut s) = grid_solver(ReferenceMode::Incremental);
    s.move_in_steps(&on_patch(&mesh, TOP, [0.0, 0.05]), 3).unwrap();
    let r = s.step_reports();
    assert_eq!(r.len(), 3);
    for r in r {
        let parts = [r.solve_seconds, r.quality_seconds, r.reference_seconds];
        assert!(parts.iter().all(|v| v.is_finite() && *v >= 0.0), "{}", r.line());
        assert!((r.solve_seconds + r.quality_seconds - r.seconds).abs() <= 1e-9 * r.seconds.max(1.0), "{}", r.line());
    }
    let mut o = s.options().clone();
    o.max_substeps = 8;
    o.min_volume_ratio = 0.5;
    s.set_options(o).unwrap();
    // Whether or not the call ends well, its reports stay.
    let _ = s.move_in_steps(&on_patch(&mesh, TOP, [0.0, -0.6]), 1);
    let r = s.step_reports();
    assert!(r.len() > 1 && !r[0].accepted, "{}", r[0].line());
    // The first attempt moved the hierarchy to the last call's result; an attempt after a
    // rejected one starts from the same reference.
    assert!(r.windows(2).filter(|w| !w[0].accepted).all(|w| w[1].reference_seconds == 0.0));
}

/// A step's result is the reference at once, and the hierarchy follows when a call needs it: a
/// call's last step leaves it where it was, and the results are bitwise those of a solver whose
/// hierarchy a read-only call moves after every step.
#[test]
fn the_hierarchy_follows_the_reference_when_a_call_needs_it() {
    let (mesh, mut lazy) = grid_solver(ReferenceMode::Incremental);
    let (_, mut eager) = grid_solver(ReferenceMode::Incremental);
    let built = lazy.phases();
    let inc = on_patch(&mesh, TOP, [0.01, 0.03]);
    let bitwise = |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
    for k in 0..4 {
        let a = lazy.advance(&inc).unwrap();
        let b = eager.advance(&inc).unwrap();
        // A read-only call moves the eager one's hierarchy to the new reference.
        assert!(eager.num_levels() >= 1);
        assert!(bitwise(&a.displacement, &b.displacement), "step {k}");
        assert!(bitwise(lazy.mesh().coords(), eager.mesh().coords()), "step {k}");
        if k == 0 {
            // Nothing was re-referenced yet: the phases are the build's.
            assert_eq!(lazy.phases(), built);
        }
    }
    let m = on_patch(&mesh, TOP, [0.02, -0.01]);
    let (a, b) = (lazy.solve(&m).unwrap(), eager.solve(&m).unwrap());
    assert!(bitwise(&a.displacement, &b.displacement));
    assert_ne!(lazy.mesh().coords(), mesh.coords());
}

/// A smooth motion's steps start from the last step's displacement scaled to their prescribed
/// values: they take fewer iterations than the same steps solved from zero (a reference set
/// from outside forgets the last step), and land within the tolerance of them.
#[test]
fn steps_of_a_smooth_motion_start_from_the_last_increment() {
    let mesh = Grid::new(40, 40).jitter(0.2).mesh();
    let make = || Solver::new(&mesh, &BoundaryConditions::new(), Options::default()).unwrap();
    let (mut warm, mut cold) = (make(), make());
    let inc = on_patch(&mesh, TOP, [0.01, 0.02]);
    let (mut it_warm, mut it_cold) = (0, 0);
    for k in 0..4 {
        let w = warm.advance(&inc).unwrap();
        let x = cold.current_coords().to_vec();
        cold.set_reference(x).unwrap();
        let c = cold.advance(&inc).unwrap();
        if k > 0 {
            it_warm += w.report.cycles;
            it_cold += c.report.cycles;
        }
    }
    assert!(it_warm < it_cold, "{it_warm} iterations from the last increment, {it_cold} from zero");
    let far = warm.current_coords().iter().zip(cold.current_coords()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(far < 1e-6, "{far}");
}
