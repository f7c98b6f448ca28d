//! Graded O-grid meshes of bodies in boxes (cases/src/ogrid.rs) and the 3D body cases
//! (cases/src/bodies3d.rs), on small meshes: validity, volumes, graded sizes, quality, and a
//! biharmonic run of the sphere channel.

use meshmove::mesh::signed_measures;
use meshmove::{Mesh, Method, Options};
use meshmove_cases::bodies3d::{
    pitching_spheroid_case, pitching_spheroid_mesh, sphere_channel_case, sphere_channel_mesh, CHANNEL, SPHERE_CENTER,
    SPHERE_RADIUS, SPHEROID_AXES,
};
use meshmove_cases::ogrid::{
    cylinder_with_vertices, measure, ogrid, plan, sphere_with_vertices, CellKind, OgridParams, OG_BODY, OG_WALL,
};
use meshmove_cases::report::run_case;
use meshmove_cases::setups::Scale;
use std::f64::consts::PI;

/// Small sphere-channel parameters: wall 0.1, far 0.3 (the quick scale).
fn small_sphere(kind: CellKind) -> OgridParams {
    OgridParams::sphere(SPHERE_CENTER, SPHERE_RADIUS, CHANNEL, 0.1, 0.3).with_kind(kind)
}

/// Longest edge of the faces on `patch`.
fn longest_patch_edge(m: &Mesh, patch: i32) -> f64 {
    let x = m.coords();
    let d = m.dim();
    let len =
        |a: u32, b: u32| (0..d).map(|k| (x[a as usize * d + k] - x[b as usize * d + k]).powi(2)).sum::<f64>().sqrt();
    let mut l = 0.0f64;
    for f in m.patch_faces().filter(|f| f.patch == patch) {
        let v = f.vertices;
        for i in 0..v.len() {
            for j in i + 1..v.len() {
                l = l.max(len(v[i], v[j]));
            }
        }
    }
    l
}

#[test]
fn sphere_in_channel_is_valid_and_graded() {
    for kind in [CellKind::Tensor, CellKind::Simplex] {
        let p = small_sphere(kind);
        let pl = plan(&p).unwrap();
        let m = ogrid(&p).unwrap();
        assert_eq!(m.num_vertices(), pl.num_vertices(kind), "{kind:?}");
        assert_eq!(m.num_cells(), pl.num_cells(kind), "{kind:?}");
        assert_eq!(m.patch_ids(), vec![OG_WALL, OG_BODY]);
        // Every body vertex on the sphere; every wall vertex on a side of the channel.
        for &v in &m.patch_vertices(OG_BODY) {
            let x = m.point(v as usize);
            let r = (0..3).map(|k| (x[k] - SPHERE_CENTER[k]).powi(2)).sum::<f64>().sqrt();
            assert!((r - SPHERE_RADIUS).abs() < 1e-12, "body vertex {v} at radius {r}");
        }
        for &v in &m.patch_vertices(OG_WALL) {
            let x = m.point(v as usize);
            assert!((0..3).any(|k| CHANNEL[k].contains(&x[k])), "wall vertex {v} at {x:?}");
        }
        let s = measure(&m, OG_BODY);
        // Volume: the channel minus the sphere, less the polyhedral body's deficit; the body's
        // faces have their corners on the sphere, so the deficit is positive and below the
        // sphere's area times the sagitta of the longest face chord ℓ: r − √(r² − ℓ²/4).
        let exact = 54.0 - 4.0 / 3.0 * PI * SPHERE_RADIUS.powi(3);
        let l = longest_patch_edge(&m, OG_BODY);
        let r = SPHERE_RADIUS;
        let bound = 4.0 * PI * r * r * (r - (r * r - l * l / 4.0).sqrt());
        let deficit = s.total_measure - exact;
        assert!(deficit > 0.0 && deficit < bound, "{kind:?}: deficit {deficit:e}, bound {bound:e}");
        assert!(signed_measures(&m, m.coords()).iter().all(|&v| v > 0.0));
        eprintln!(
            "{kind:?}: {} vertices, {} cells, {s:?}, deficit {deficit:.2e} (bound {bound:.2e})",
            m.num_vertices(),
            m.num_cells()
        );
        if kind == CellKind::Tensor {
            // The first layer is exactly the wall size; the body's spacing about it (a quarter
            // circumference over n = ⌈π r / (2 h_w)⌉ = 8 cells: 0.098 at most, 0.091 mean).
            assert!((s.wall_normal_edge - 0.1).abs() < 1e-12, "{}", s.wall_normal_edge);
            assert!((0.08..=0.1).contains(&s.body_edge), "{}", s.body_edge);
            // Far: the inner box's spacing is the far size; no edge much longer (measured 0.311).
            assert!(s.max_edge <= 1.1 * 0.3, "{}", s.max_edge);
            // Hexahedra: measured min dihedral 45°, max edge ratio 3.95.
            assert!(s.min_angle_deg >= 44.9, "{}", s.min_angle_deg);
            assert!(s.max_edge_ratio <= 4.2, "{}", s.max_edge_ratio);
        } else {
            // Tetrahedra (12 per hexahedron): measured min dihedral 14.6°, max edge ratio 4.07.
            assert!(s.min_angle_deg >= 14.0, "{}", s.min_angle_deg);
            assert!(s.max_edge_ratio <= 4.5, "{}", s.max_edge_ratio);
        }
    }
}

#[test]
fn spheroid_in_box_is_valid() {
    let m = pitching_spheroid_mesh(0.05, 0.5);
    let [a, b, c] = SPHEROID_AXES;
    for &v in &m.patch_vertices(OG_BODY) {
        let x = m.point(v as usize);
        let e = (x[0] / a).powi(2) + (x[1] / b).powi(2) + (x[2] / c).powi(2);
        assert!((e - 1.0).abs() < 1e-12, "body vertex {v}: {e}");
    }
    let s = measure(&m, OG_BODY);
    let exact = 216.0 - 4.0 / 3.0 * PI * a * b * c;
    // The deficit is below the spheroid's (smaller than its circumscribed cylinder's) area times
    // the largest sagitta of a chord ℓ on a curve of radius of curvature ≥ b²/a.
    let l = longest_patch_edge(&m, OG_BODY);
    let rho = b * b / a;
    let sag = if l < 2.0 * rho { rho - (rho * rho - l * l / 4.0).sqrt() } else { rho };
    let bound = (2.0 * PI * b * 2.0 * a + 2.0 * PI * b * b) * sag;
    let deficit = s.total_measure - exact;
    eprintln!("spheroid: {} vertices, {s:?}, deficit {deficit:.2e} (bound {bound:.2e})", m.num_vertices());
    assert!(deficit > 0.0 && deficit < bound, "deficit {deficit:e}, bound {bound:e}");
    // Measured: min dihedral 9.2° (tetrahedra at the inner box's corners, where the lines
    // from the elongated body meet the box obliquely), max edge ratio 6.1.
    assert!(s.min_angle_deg >= 8.5, "{}", s.min_angle_deg);
    assert!(s.max_edge_ratio <= 6.5, "{}", s.max_edge_ratio);
}

#[test]
fn cylinder_in_box_2d() {
    for kind in [CellKind::Tensor, CellKind::Simplex] {
        let p = OgridParams::cylinder([0.0, 0.0], 0.5, [[-10.0, 10.0], [-10.0, 10.0]], 0.05, 2.5).with_kind(kind);
        let m = ogrid(&p).unwrap();
        assert_eq!(m.num_vertices(), plan(&p).unwrap().num_vertices(kind));
        let s = measure(&m, OG_BODY);
        // Area: the square minus the inscribed polygon (sagitta bound as in 3D).
        let l = longest_patch_edge(&m, OG_BODY);
        let deficit = s.total_measure - (400.0 - PI * 0.25);
        let bound = PI * (0.5 - (0.25 - l * l / 4.0).sqrt());
        assert!(deficit > 0.0 && deficit < bound, "{kind:?}: {deficit:e} {bound:e}");
        eprintln!("cylinder {kind:?}: {} vertices, {s:?}", m.num_vertices());
        if kind == CellKind::Tensor {
            assert!((s.wall_normal_edge - 0.05).abs() < 1e-12);
            assert!(s.min_angle_deg >= 44.9, "{}", s.min_angle_deg);
        } else {
            assert!(s.min_angle_deg >= 17.0, "{}", s.min_angle_deg);
        }
        // Wall size 1/50 of the far size: the longest edge is about the far size.
        assert!(s.max_edge <= 1.3 * 2.5 * if kind == CellKind::Simplex { 2f64.sqrt() } else { 1.0 }, "{}", s.max_edge);
    }
}

#[test]
fn graded_meshes_of_a_given_size() {
    for (kind, n) in [(CellKind::Tensor, 20_000), (CellKind::Simplex, 30_000)] {
        let m = sphere_with_vertices(n, kind).unwrap();
        let s = measure(&m, OG_BODY);
        eprintln!("sphere {kind:?} {n}: {} vertices, {s:?}", m.num_vertices());
        assert!(m.num_vertices() <= n && m.num_vertices() >= n * 6 / 10, "{}", m.num_vertices());
        let m = cylinder_with_vertices(n / 10, kind).unwrap();
        assert!(m.num_vertices() <= n / 10 && m.num_vertices() >= n / 20, "{}", m.num_vertices());
    }
}

#[test]
fn biharmonic_moves_the_sphere_rigidly_without_inverting() {
    let setup = sphere_channel_case("sphere_channel_0.5", sphere_channel_mesh(0.1, 0.3), 0.5);
    let r = run_case(&setup, Method::Biharmonic, &Options::default()).unwrap();
    assert!(r.failure.is_none(), "{:?}", r.failure);
    let m = &setup.mesh;
    // The sphere itself moved by exactly 0.5 in x.
    for &v in &m.patch_vertices(OG_BODY) {
        let d = [0, 1, 2].map(|k| r.coords[3 * v as usize + k] - m.point(v as usize)[k]);
        assert!((d[0] - 0.5).abs() < 1e-12 && d[1].abs() < 1e-12 && d[2].abs() < 1e-12, "{d:?}");
    }
    // The cells touching the sphere keep their volume to about 10 %: the biharmonic moves the
    // layer next to a CLAMPED body nearly rigidly (measured ratios 0.904–1.114).
    let on_body: std::collections::HashSet<u32> = m.patch_vertices(OG_BODY).into_iter().collect();
    let (v0, v1) = (signed_measures(m, m.coords()), signed_measures(m, &r.coords));
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for c in 0..m.num_cells() {
        if m.cell(c).iter().any(|v| on_body.contains(v)) {
            lo = lo.min(v1[c] / v0[c]);
            hi = hi.max(v1[c] / v0[c]);
        }
    }
    eprintln!(
        "biharmonic sphere channel 0.5 (small): inverted {}, min volume ratio {:.3}, min dihedral {:.2}, body cells {lo:.3}–{hi:.3}",
        r.inverted, r.min_area_ratio, r.min_angle_deg
    );
    assert_eq!(r.inverted, 0);
    assert!(lo > 0.88 && hi < 1.13, "{lo} {hi}");
    // Measured: min volume ratio 0.674, min dihedral 10.3° (14.6° before the move).
    assert!(r.min_area_ratio > 0.6, "{}", r.min_area_ratio);
    assert!(r.min_angle_deg > 9.0, "{}", r.min_angle_deg);
}

/// The second-order methods' iterations on the demo's quick 3D body cases, at their 3D degrees
/// 4 / 3 (`policy::degrees`; at the 2D degrees 3 / 2 they take 10 and 8).
#[test]
fn second_order_methods_iterate_at_their_3d_degrees() {
    for (name, method, most) in
        [("sphere_channel_0.5", Method::Laplacian, 9), ("pitching_spheroid_1step", Method::Spring, 6)]
    {
        let setup = meshmove_cases::bodies3d::case(name, Scale::Quick).expect("a body case");
        let r = run_case(&setup, method, &Options::default()).unwrap();
        eprintln!("{name} {method:?}: {} iterations", r.cycles);
        assert!(r.cycles <= most, "{name} {method:?}: {} iterations", r.cycles);
    }
}

#[test]
fn pitching_spheroid_set_up() {
    let s = pitching_spheroid_case("pitching_spheroid_10steps", pitching_spheroid_mesh(0.05, 0.5), 10);
    assert_eq!(s.steps, 10);
    // Every spheroid vertex rotated 20° about y: (x, y, z) to (x cos + z sin, y, −x sin + z cos).
    let d = s.motion.vertex_values(&s.mesh);
    let a = 20f64.to_radians();
    let body = s.mesh.patch_vertices(OG_BODY);
    assert!(!body.is_empty());
    for &v in &body {
        let [x, y, z] = [0, 1, 2].map(|k| s.mesh.point(v as usize)[k]);
        let want = [x * a.cos() + z * a.sin() - x, 0.0, -x * a.sin() + z * a.cos() - z];
        for k in 0..3 {
            assert!((d[3 * v as usize + k] - want[k]).abs() < 1e-12, "vertex {v} ({x}, {y}, {z})");
        }
    }
}

/// The bench's graded sphere (25 194 vertices, the body CLAMPED and moved 0.1): its few short
/// lines (0.2 % of the first kept level's unknowns) leave it K_c V_c⁻¹ K_c on every level, 7
/// biharmonic iterations (11 with the assembled Pᵀ A P below them; docs/perf-history.md, "The
/// graded sphere's coarse rows at the clamped body").
#[test]
fn graded_sphere_biharmonic_keeps_its_coarse_products() {
    use meshmove::{BoundaryConditions, Kind, Motion, RigidMotion, Solver};
    let mesh = sphere_with_vertices(30_000, CellKind::Simplex).unwrap();
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(OG_WALL, Kind::Fixed).set_kinds(OG_BODY, Kind::Clamped);
    let r = RigidMotion { translation: [0.1, 0.0, 0.0], rotation: [0.0; 3], center: [0.0; 3] };
    let motion = Motion::zero(&mesh).with_rigid(OG_BODY, r);
    let solver = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    let sol = solver.solve(&motion).unwrap();
    eprintln!("graded sphere {}: {} iterations", mesh.num_vertices(), sol.report.cycles);
    assert!(sol.report.converged && sol.quality.inverted == 0);
    assert!(sol.report.cycles <= 7, "{} iterations", sol.report.cycles);
}
