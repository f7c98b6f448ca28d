//! A call returns a valid result at its tolerance or says why not: unconverged steps, tangled
//! references and impossible prescriptions are errors; sub-stepping keeps a mesh valid through
//! large rotations; a failed call leaves the solver as it was; solves from the original mesh do
//! not drift.

#[path = "../../tests/common/mod.rs"]
mod common;
use common::*;
use meshmove::{BoundaryConditions, Error, Kind, Method, Motion, Options, ReferenceMode, RigidMotion, Solver};
use meshmove_cases::meshes::{cylinder_channel, ellipse_in_box, CH_CYLINDER, CH_WALL, EL_BOX, EL_ELLIPSE};
use meshmove_cases::meshes::{unstructured_rectangle, FS_BOTTOM, FS_LEFT, FS_RIGHT, FS_TOP};
use std::f64::consts::PI;

fn ellipse_bcs() -> BoundaryConditions {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(EL_BOX, Kind::Fixed).set_kinds(EL_ELLIPSE, Kind::Clamped);
    bcs
}

fn rotation(deg: f64) -> RigidMotion {
    RigidMotion::planar([0.0, 0.0], deg.to_radians(), [0.0, 0.0])
}

/// A Gaussian bump of height 0.55 raised in 10 steps on the bottom of [0,4]×[0,1] (unstructured,
/// h = 0.03), every side FIXED: every step reaches the tolerance 1e-10. From the third step on,
/// the smoother's power-iteration estimate of λmax falls below the true one and CG stagnated at a
/// residual of 1e-4 at any Chebyshev degree (it was returned as a result); a stalled solve now
/// also tries the l1 bound's interval and every step converges in well under 100 iterations.
#[test]
fn bump_steps_converge() {
    let mesh = unstructured_rectangle([0.0, 4.0, 0.0, 1.0], 0.03);
    let mut bcs = BoundaryConditions::new();
    for p in [FS_BOTTOM, FS_RIGHT, FS_TOP, FS_LEFT] {
        bcs.set_kinds(p, Kind::Fixed);
    }
    let mut motion = Motion::zero(&mesh);
    for v in mesh.patch_vertices(FS_BOTTOM) {
        let x = mesh.point(v as usize)[0];
        motion.displacement[2 * v as usize + 1] = 0.55 * (-((x - 2.0) / 0.3).powi(2)).exp();
    }
    let mut o = Options::default();
    o.solve.tol = 1e-10;
    let mut s = Solver::new(&mesh, &bcs, o).unwrap();
    let reps = s.move_in_steps(&motion, 10).unwrap();
    assert_eq!(reps.len(), 10);
    for r in &reps {
        assert!(r.accepted && r.converged && r.rel_residual <= 1e-10 && r.inverted == 0, "{}", r.line());
    }
    assert!(reps[2].cycles < 100, "{}", reps[2].line());
}

/// The Laplacian rotating a thin ellipse by 90° in 10 steps tangles the mesh; the call stops
/// with an error at the step that tangled, instead of solving on the tangled mesh (which gave
/// zero updates while the body went on rotating).
#[test]
fn laplacian_rotation_stops_at_the_first_tangled_step() {
    let mesh = ellipse_in_box(0.5, 0.1);
    let mut s =
        Solver::new(&mesh, &ellipse_bcs(), Options { method: Method::Laplacian, ..Default::default() }).unwrap();
    let motion = Motion::zero(&mesh).with_rigid(EL_ELLIPSE, rotation(90.0));
    let before = s.mesh().coords().to_vec();
    let e = s.move_in_steps(&motion, 10).unwrap_err();
    assert!(matches!(e, Error::Tangled(_)), "{e}");
    let reps = s.step_reports();
    let last = reps.last().unwrap();
    assert!(last.inverted > 0 && last.converged, "{}", last.line());
    assert!(reps[..reps.len() - 1].iter().all(|r| r.inverted == 0 && r.accepted));
    eprintln!("laplacian 90°: {e}");
    // Transactional: the solver is back on the mesh it started from.
    assert_eq!(s.mesh().coords(), &before[..]);
    // How far it got: a valid mesh.
    let q = meshmove::mesh::quality(&mesh, s.last_valid_coords());
    assert_eq!(q.inverted, 0);
}

/// The biharmonic turning the clamped thin ellipse in 10 steps: without sub-stepping its last
/// step inverts cells; with it, 270° completes valid through split steps. A
/// full turn winds the mesh between the ellipse and the fixed box until cells are needles (the
/// smallest angle falls below 0.01° near 300°) and the solves stall there: the call either
/// completes valid or fails cleanly with the last valid mesh.
#[test]
fn substepping_keeps_large_rotations_valid_or_fails_cleanly() {
    let mesh = ellipse_in_box(0.5, 0.1);
    let turn = |deg: f64, max_substeps: usize| {
        let mut s = Solver::new(&mesh, &ellipse_bcs(), Options { max_substeps, ..Default::default() }).unwrap();
        let motion = Motion::zero(&mesh).with_rigid(EL_ELLIPSE, rotation(deg));
        let r = s.move_in_steps(&motion, 10);
        (s, r)
    };
    // Without sub-stepping the last step inverts cells: the method's honest answer, returned
    // with its count and not adopted (the solver stays on the mesh it started from).
    let (_, r) = turn(270.0, 1);
    let last = r.unwrap().pop().unwrap();
    assert!(last.step == 10 && last.inverted > 0, "{}", last.line());

    let (s, r) = turn(270.0, 64);
    r.unwrap();
    let reps = s.step_reports();
    let rejected = reps.iter().filter(|r| !r.accepted).count();
    assert!(rejected > 0, "no step needed splitting");
    assert!(reps.iter().all(|r| !r.accepted || (r.inverted == 0 && r.converged)));
    assert_eq!(reps.last().unwrap().fraction, 1.0);
    assert_eq!(meshmove::mesh::quality(&mesh, s.mesh().coords()).inverted, 0);
    // The ellipse ends where the rotation puts it.
    let (x0, x1) = (mesh.points_2d(), s.mesh().points_2d());
    for v in mesh.patch_vertices(EL_ELLIPSE) {
        let x = x0[v as usize];
        assert!((x1[v as usize] - (x + rigid_at(&rotation(270.0), x))).length() < 1e-9);
    }
    eprintln!("270°: {} sub-steps, {rejected} rejected", reps.len() - rejected);

    let (s, r) = turn(360.0, 64);
    match r {
        Ok(_) => assert_eq!(meshmove::mesh::quality(&mesh, s.mesh().coords()).inverted, 0),
        Err(e) => {
            assert!(matches!(e, Error::NotConverged(_) | Error::Tangled(_)), "{e}");
            assert_eq!(s.mesh().coords(), mesh.coords());
            assert_eq!(meshmove::mesh::quality(&mesh, s.last_valid_coords()).inverted, 0);
            let done = s.step_reports().iter().filter(|r| r.accepted).map(|r| r.fraction).fold(0.0, f64::max);
            eprintln!("360°: stopped at {:.1}% of the turn: {e}", 100.0 * done);
        }
    }
}

/// `advance` reports its result's quality against the positions the call started from, whether
/// one attempt made the step (its own check reused), the step was split, or the result is tangled
/// and not adopted: the same values as measuring that pair of meshes afresh.
#[test]
fn advance_reports_the_quality_against_its_start() {
    let mesh = ellipse_in_box(0.5, 0.1);
    let mut cases = 0;
    let (inc, orig) = (ReferenceMode::Incremental, ReferenceMode::Original);
    let cases_run = [
        (Method::Biharmonic, 20.0, 1, inc),
        (Method::Biharmonic, 20.0, 1, orig),
        (Method::Biharmonic, 20.0, 64, inc),
        (Method::Biharmonic, 120.0, 64, inc),
        (Method::Laplacian, 90.0, 1, inc),
    ];
    for (method, deg, max_substeps, reference) in cases_run {
        let opts = Options { method, max_substeps, reference, ..Default::default() };
        let mut s = Solver::new(&mesh, &ellipse_bcs(), opts).unwrap();
        // A first step, so the second starts from a moved reference.
        s.advance(&Motion::zero(&mesh).with_rigid(EL_ELLIPSE, rotation(5.0))).unwrap();
        let before = s.current_coords().to_vec();
        let sol = s.advance(&Motion::zero(&mesh).with_rigid(EL_ELLIPSE, rotation(deg))).unwrap();
        // The result: the new mesh, or the tangled one the call returned and did not adopt.
        let fresh = meshmove::mesh::quality(&mesh.with_coords(before), s.last_valid_coords());
        assert_eq!(sol.quality, fresh, "{method:?} {deg}° with {max_substeps} sub-steps, {reference:?}");
        let attempts = s.step_reports().len();
        cases += usize::from(attempts > 1 || sol.quality.inverted > 0);
        eprintln!("{method:?} {deg}°: {attempts} attempt(s), {} inverted", sol.quality.inverted);
    }
    assert!(cases >= 2, "a split step and a tangled result are among the cases");
}

#[test]
fn a_motion_on_a_free_patch_is_refused() {
    let mesh = ellipse_in_box(0.5, 0.1);
    let mut bcs = ellipse_bcs();
    bcs.set_kind(EL_ELLIPSE, 0, Kind::Free).unwrap();
    let s = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    let e = s.solve(&Motion::zero(&mesh).with_rigid(EL_ELLIPSE, rotation(10.0))).unwrap_err();
    assert!(e.to_string().contains("moves its vertices in x, which is FREE"), "{e}");
    // A translation along y only is fine: y is prescribed.
    let up = RigidMotion::translation([0.0, 0.05, 0.0]);
    assert!(s.solve(&Motion::zero(&mesh).with_rigid(EL_ELLIPSE, up)).is_ok());
    let two = Motion::zero(&mesh).with_rigid(EL_ELLIPSE, up).with_rigid(EL_ELLIPSE, up);
    assert!(s.solve(&two).unwrap_err().to_string().contains("two rigid motions"));
}

/// Every single-vertex move that tangles or flattens a cell of a small grid is refused by
/// `set_reference`, and the solver then gives bitwise the result it gave before.
#[test]
fn a_failed_set_reference_changes_nothing() {
    let mesh = Grid::new(4, 4).mesh();
    let bcs = all_fixed();
    let mut motion = Motion::zero(&mesh);
    for v in mesh.patch_vertices(TOP) {
        motion.displacement[2 * v as usize + 1] = 0.05;
    }
    for method in [Method::Biharmonic, Method::Laplacian] {
        let mut s = Solver::new(&mesh, &bcs, Options { method, ..Default::default() }).unwrap();
        let want = s.solve(&motion).unwrap().displacement;
        let mut refused = 0;
        for v in 0..mesh.num_vertices() {
            for target in [[0.0, 0.0], [1.0, 1.0], [0.5, 0.5], [2.0, -1.0], [0.25, 0.0]] {
                let mut x = mesh.coords().to_vec();
                x[2 * v..2 * v + 2].copy_from_slice(&target);
                if s.set_reference(x).is_err() {
                    refused += 1;
                    assert_eq!(s.mesh().coords(), mesh.coords());
                    let again = s.solve(&motion).unwrap().displacement;
                    assert_eq!(again.len(), want.len());
                    assert!(again.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits()));
                } else {
                    s.set_reference(mesh.coords().to_vec()).unwrap();
                }
            }
        }
        assert!(refused > 40, "{refused}");
    }
}

fn all_fixed() -> BoundaryConditions {
    let mut bcs = BoundaryConditions::new();
    for p in [BOTTOM, RIGHT, TOP, LEFT] {
        bcs.set_kinds(p, Kind::Fixed);
    }
    bcs
}

/// The cylinder of `c_examples/fv_cylinder.c` oscillating for 10 periods, moved by one call per
/// step with the increment since the last: solved from the original mesh it comes back to its
/// start; re-referenced every step it drifts.
#[test]
fn periodic_motion_returns_to_the_start_from_the_original_mesh() {
    let mesh = cylinder_channel(1.0 / 8.0);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(CH_WALL, Kind::Fixed).set_kinds(CH_CYLINDER, Kind::Clamped);
    let cyl = mesh.patch_vertices(CH_CYLINDER);
    let (amp, steps) = (0.25, 20);
    let mut offsets = Vec::new();
    for reference in [ReferenceMode::Original, ReferenceMode::Incremental] {
        let mut s = Solver::new(&mesh, &bcs, Options { reference, ..Default::default() }).unwrap();
        for n in 1..=10 * steps {
            let w = 2.0 * PI / steps as f64;
            let dy = amp * ((w * n as f64).sin() - (w * (n - 1) as f64).sin());
            let mut inc = Motion::zero(&mesh);
            for &v in &cyl {
                inc.displacement[2 * v as usize + 1] = dy;
            }
            let sol = s.advance(&inc).unwrap();
            assert_eq!(sol.quality.inverted, 0);
        }
        let (now, start) = (to_vec2(s.current_coords()), mesh.points_2d());
        let off = now.iter().zip(&start).map(|(a, b)| (*a - *b).length()).fold(0.0, f64::max);
        offsets.push(off);
    }
    eprintln!("largest offset after 10 periods: original {:e}, incremental {:e}", offsets[0], offsets[1]);
    assert!(offsets[0] < 1e-10, "{}", offsets[0]);
    assert!(offsets[1] > 1e-4, "{}", offsets[1]);
}

/// `tests/data/ellipse_box.msh` (read by `tests/c/steps.c`) is the mesh of `ellipse_in_box(0.5,
/// 0.1)`; `MESHMOVE_BLESS=1` rewrites it.
#[test]
fn ellipse_fixture_is_fresh() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/ellipse_box.msh");
    let tmp = std::env::temp_dir().join(format!("ellipse_box_{}.msh", std::process::id()));
    meshmove::io::write_msh22(&ellipse_in_box(0.5, 0.1), &tmp).unwrap();
    let want = std::fs::read(&tmp).unwrap();
    let _ = std::fs::remove_file(&tmp);
    if std::env::var_os("MESHMOVE_BLESS").is_some() {
        std::fs::write(&path, &want).unwrap();
    }
    assert!(
        std::fs::read(&path).unwrap() == want,
        "{} is stale: MESHMOVE_BLESS=1 cargo test -p meshmove-cases --test robustness",
        path.display()
    );
}

/// Switching the reference mode keeps the current positions: they become the reference mesh
/// (incremental) or the new original mesh.
#[test]
fn switching_the_reference_mode_keeps_the_current_mesh() {
    let mesh = cylinder_channel(1.0 / 8.0);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(CH_WALL, Kind::Fixed).set_kinds(CH_CYLINDER, Kind::Clamped);
    let mut s = Solver::new(&mesh, &bcs, Options { reference: ReferenceMode::Original, ..Default::default() }).unwrap();
    let up = Motion::zero(&mesh).with_rigid(CH_CYLINDER, RigidMotion::translation([0.0, 0.1, 0.0]));
    s.advance(&up).unwrap();
    let moved = s.current_coords().to_vec();
    assert_eq!(s.mesh().coords(), mesh.coords(), "the original mode keeps the original reference");
    let mut o = s.options().clone();
    o.reference = ReferenceMode::Incremental;
    s.set_options(o).unwrap();
    assert_eq!(s.mesh().coords(), &moved[..]);
    assert_eq!(s.current_coords(), &moved[..]);
    s.advance(&up).unwrap();
    let cyl = mesh.patch_vertices(CH_CYLINDER)[0] as usize;
    assert!((s.current_coords()[2 * cyl + 1] - mesh.coords()[2 * cyl + 1] - 0.2).abs() < 1e-12);
}
