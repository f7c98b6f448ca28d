//! The 3D cases (cases/src/meshes3d.rs, setups3d.rs): the box and extruded meshes are valid, of
//! the right volume and patches; linear fields are exact on an extruded mixed mesh; the free
//! surface on the cube and the extruded boundary-layer cylinder give the findings of
//! docs/RESULTS.md ("3D"), on meshes smaller than the demo's.

use meshmove::mesh::signed_measures;
use meshmove::{BoundaryConditions, CellType, Kind, Mesh, MeshData, Method, Motion, Options, RigidMotion, Solver};
use meshmove_cases::amplitude::largest_valid_amplitude;
use meshmove_cases::hybrid::{boundary_layer_cylinder_hybrid, structured_quads};
use meshmove_cases::meshes::{BL_CYLINDER, BL_FAR, BL_LAYERS, BL_N_THETA};
use meshmove_cases::meshes3d::*;
use meshmove_cases::report::{run_case, CaseResult};
use meshmove_cases::setups::{case, Scale};
use meshmove_cases::setups3d::{boundary_layer_cylinder_3d_case, free_surface_3d_case, BL_Z0, BL_Z1};

/// The sum of `v`, compensated (Neumaier): thousands of cell volumes sum to 1 within 1e-15.
fn sum(v: impl Iterator<Item = f64>) -> f64 {
    let (mut s, mut c) = (0.0f64, 0.0);
    for x in v {
        let t = s + x;
        c += if s.abs() >= x.abs() { (s - t) + x } else { (x - t) + s };
        s = t;
    }
    s + c
}

fn volume(m: &Mesh) -> f64 {
    sum(signed_measures(m, m.coords()).into_iter())
}

/// The number of faces of `patch` with `corners` vertices.
fn faces(m: &Mesh, patch: i32, corners: usize) -> usize {
    m.patch_faces().filter(|f| f.patch == patch && f.vertices.len() == corners).count()
}

#[test]
fn box_meshes_are_valid_with_their_volume_and_patches() {
    let (nx, ny, nz) = (3, 4, 5);
    let bounds = [0.0, 1.0, -1.0, 1.0, 0.0, 0.5];
    for cells in BoxCells::ALL {
        let m = Mesh::from_data(&structured_box(cells, [nx, ny, nz], bounds)).unwrap();
        assert_eq!(m.num_vertices(), 4 * 5 * 6, "{cells:?}");
        let (per_cube, ty) = match cells {
            BoxCells::Hexes => (1, CellType::Hexahedron),
            BoxCells::Tets => (6, CellType::Tetra),
            BoxCells::Prisms => (2, CellType::Wedge),
        };
        assert_eq!(m.num_cells(), per_cube * nx * ny * nz, "{cells:?}");
        assert!(m.cell_types().iter().all(|&t| t == ty));
        assert!(signed_measures(&m, m.coords()).iter().all(|&v| v > 0.0), "{cells:?}");
        assert!((volume(&m) - 1.0).abs() < 1e-14, "{cells:?}: {}", volume(&m));
        // Every boundary face is tagged: no patch 0.
        assert_eq!(m.patch_ids(), vec![BOX_BOTTOM, BOX_RIGHT, BOX_TOP, BOX_LEFT, BOX_FRONT, BOX_BACK]);
        // Faces per side: a square of the grid is one quad or two triangles.
        let split = |quads_split: bool, squares: usize| if quads_split { (0, 2 * squares) } else { (squares, 0) };
        let (top_quads, top_tris) = split(cells != BoxCells::Hexes, nx * ny);
        let (side_quads, side_tris) = split(cells == BoxCells::Tets, nx * nz);
        let (end_quads, end_tris) = split(cells == BoxCells::Tets, ny * nz);
        for p in [BOX_BOTTOM, BOX_TOP] {
            assert_eq!((faces(&m, p, 4), faces(&m, p, 3)), (top_quads, top_tris), "{cells:?} patch {p}");
            assert_eq!(m.patch_vertices(p).len(), (nx + 1) * (ny + 1));
        }
        for p in [BOX_FRONT, BOX_BACK] {
            assert_eq!((faces(&m, p, 4), faces(&m, p, 3)), (side_quads, side_tris), "{cells:?} patch {p}");
            assert_eq!(m.patch_vertices(p).len(), (nx + 1) * (nz + 1));
        }
        for p in [BOX_LEFT, BOX_RIGHT] {
            assert_eq!((faces(&m, p, 4), faces(&m, p, 3)), (end_quads, end_tris), "{cells:?} patch {p}");
            assert_eq!(m.patch_vertices(p).len(), (ny + 1) * (nz + 1));
        }
        for (p, axis, value) in [
            (BOX_BOTTOM, 2, 0.0),
            (BOX_TOP, 2, 0.5),
            (BOX_LEFT, 0, 0.0),
            (BOX_RIGHT, 0, 1.0),
            (BOX_FRONT, 1, -1.0),
            (BOX_BACK, 1, 1.0),
        ] {
            assert!(m.patch_vertices(p).iter().all(|&v| m.point(v as usize)[axis] == value), "{cells:?} patch {p}");
        }
    }
}

/// A 2D mesh of [0, 2] × [0, 1]: quads left of x = 1, each quad right of it split into two
/// triangles, with the rectangle's patches (bottom 1, right 2, top 3, left 4).
fn mixed_2d() -> MeshData {
    let q = structured_quads(4, 3, [0.0, 2.0, 0.0, 1.0]);
    let mut d = MeshData::new(2);
    d.coords = q.coords.clone();
    for c in 0..q.num_cells() {
        let v = q.cell(c);
        if q.point(v[0] as usize)[0] < 1.0 {
            d.push_cell(CellType::Quad, v, 0);
        } else {
            d.push_cell(CellType::Triangle, &[v[0], v[1], v[2]], 0);
            d.push_cell(CellType::Triangle, &[v[0], v[2], v[3]], 0);
        }
    }
    for f in 0..q.num_faces() {
        d.push_face(q.face(f), q.face_patch[f]);
    }
    d
}

#[test]
fn extrusion_counts_volume_and_patches() {
    let flat = mixed_2d();
    let d = extrude(&flat, 3, [-0.2, 0.5], [7, 8]);
    let m = Mesh::from_data(&d).unwrap();
    assert_eq!(m.num_vertices(), 4 * flat.num_vertices());
    let count = |t: CellType| m.cell_types().iter().filter(|&&x| x == t).count();
    assert_eq!((count(CellType::Hexahedron), count(CellType::Wedge)), (3 * 6, 3 * 12));
    assert!((volume(&m) - 2.0 * 0.7).abs() < 1e-14, "{}", volume(&m));
    assert_eq!(m.patch_ids(), vec![1, 2, 3, 4, 7, 8]);
    // The z sides: one face per 2D cell, quads and triangles; the other sides: one quad per
    // 2D edge and layer.
    for p in [7, 8] {
        assert_eq!((faces(&m, p, 4), faces(&m, p, 3)), (6, 12), "patch {p}");
    }
    assert_eq!(faces(&m, 1, 4), 3 * 4);
    assert_eq!(faces(&m, 2, 4), 3 * 3);
    // The same mesh given clockwise extrudes to the same cells' volumes.
    let mut cw = flat.clone();
    cw.cell_vertices.clear();
    cw.cell_offsets = vec![0];
    let types = std::mem::take(&mut cw.cell_types);
    for (c, t) in types.into_iter().enumerate() {
        let v: Vec<u32> = flat.cell(c).iter().rev().copied().collect();
        cw.push_cell(t, &v, 0);
    }
    let m2 = Mesh::from_data(&extrude(&cw, 3, [-0.2, 0.5], [7, 8])).unwrap();
    assert_eq!(signed_measures(&m2, m2.coords()), signed_measures(&m, m.coords()));
}

#[test]
fn linear_fields_are_exact_on_the_extruded_mixed_mesh() {
    let m = Mesh::from_data(&extrude(&mixed_2d(), 3, [-0.2, 0.5], [7, 8])).unwrap();
    let field = |p: &[f64]| {
        [
            0.01 + 0.05 * p[0] - 0.02 * p[1] + 0.03 * p[2],
            -0.03 + 0.04 * p[0] + 0.06 * p[1] - 0.01 * p[2],
            0.02 - 0.03 * p[0] + 0.01 * p[1] + 0.05 * p[2],
        ]
    };
    let mut motion = Motion::zero(&m);
    for v in 0..m.num_vertices() {
        motion.displacement[3 * v..3 * v + 3].copy_from_slice(&field(m.point(v)));
    }
    let mut bcs = BoundaryConditions::new();
    for p in [1, 2, 3, 4, 7, 8] {
        bcs.set_kinds(p, Kind::Fixed);
    }
    for method in [Method::Biharmonic, Method::Laplacian] {
        let mut o = Options { method, ..Default::default() };
        o.solve.tol = 1e-13;
        let sol = Solver::new(&m, &bcs, o).unwrap().solve(&motion).unwrap();
        let err = (0..m.num_vertices())
            .flat_map(|v| (0..3).map(move |c| (v, c)))
            .map(|(v, c)| (sol.displacement[3 * v + c] - field(m.point(v))[c]).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-12, "{method:?}: error {err:e}");
    }
    // The whole boundary CLAMPED and moved rigidly (a rotation about a tilted axis and a
    // translation): the biharmonic with the rigid flux moves the whole mesh rigidly.
    let r = RigidMotion { translation: [0.1, -0.05, 0.2], rotation: [0.2, -0.1, 0.3], center: [1.0, 0.5, 0.1] };
    let mut bcs = BoundaryConditions::new();
    let mut motion = Motion::zero(&m);
    for p in [1, 2, 3, 4, 7, 8] {
        bcs.set_kinds(p, Kind::Clamped);
        motion = motion.with_rigid(p, r);
    }
    let mut o = Options::default();
    o.solve.tol = 1e-13;
    let d = Solver::new(&m, &bcs, o).unwrap().solve(&motion).unwrap().displacement;
    let err = (0..m.num_vertices())
        .flat_map(|v| (0..3).map(move |c| (v, c)))
        .map(|(v, c)| (d[3 * v + c] - r.displacement(m.point(v))[c]).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-12, "rigid: error {err:e}");
}

fn run(setup: &meshmove_cases::setups::CaseSetup, method: Method) -> CaseResult {
    let r = run_case(setup, method, &Options::default()).unwrap();
    assert!(r.failure.is_none(), "{} {method:?}: {:?}", setup.name, r.failure);
    assert!(r.reports.iter().all(|x| x.converged), "{} {method:?}", setup.name);
    // The result's quality (a one-step run's is its step's own check, not measured again) is
    // that of the moved mesh against the original, bit for bit.
    let q = meshmove::mesh::quality(&setup.mesh, &r.coords);
    let got = (r.inverted, r.negative_volume_cells, r.min_area_ratio, r.min_corner_jacobian_ratio, r.min_angle_deg);
    assert_eq!(
        got,
        (q.inverted, q.non_positive_measure, q.min_area_ratio, q.min_corner_jacobian_ratio, q.min_angle_deg)
    );
    r
}

/// Measured at n = 8 (729 vertices), A = 0.1, one step: (cells, minimum volume ratio of the
/// biharmonic, of the Laplacian, of the spring analogy).
const FS_A01: [(BoxCells, f64, f64, f64); 3] = [
    (BoxCells::Tets, 0.6839, 0.4841, 0.4818),
    (BoxCells::Hexes, 0.7333, 0.5866, 0.6364),
    (BoxCells::Prisms, 0.7771, 0.5947, 0.5793),
];

#[test]
fn free_surface_3d_a01_all_valid_biharmonic_compresses_least() {
    for (cells, bih, lap, spring) in FS_A01 {
        let s = free_surface_3d_case(cells, 8, 0.1, 1);
        let b = run(&s, Method::Biharmonic);
        let l = run(&s, Method::Laplacian);
        let sp = run(&s, Method::Spring);
        assert_eq!((b.inverted, l.inverted, sp.inverted), (0, 0, 0), "{}", s.name);
        for (r, want) in [(&b, bih), (&l, lap), (&sp, spring)] {
            assert!((r.min_area_ratio - want).abs() < 5e-3, "{} {:?}: {}", s.name, r.method, r.min_area_ratio);
        }
        // The top cells' heights vary least under the biharmonic (0.49–0.59 against 0.77–1.08).
        let (vb, vl, vs) = (b.patch.spacing_variation, l.patch.spacing_variation, sp.patch.spacing_variation);
        assert!(vb < 0.6 && vl > 0.75 && vs > 0.75, "{}: {vb} {vl} {vs}", s.name);
    }
}

/// Measured at n = 8: (cells, largest A moved in one step without an inverted cell, by the
/// biharmonic, the Laplacian, the spring analogy).
const FS_LARGEST_A: [(BoxCells, f64, f64, f64); 3] = [
    (BoxCells::Tets, 0.3156, 0.1938, 0.1922),
    (BoxCells::Hexes, 0.2758, 0.1773, 0.2055),
    (BoxCells::Prisms, 0.3609, 0.1984, 0.1930),
];

#[test]
fn free_surface_3d_largest_amplitude() {
    for (cells, bih, lap, spring) in FS_LARGEST_A {
        let s = free_surface_3d_case(cells, 8, 0.1, 1);
        for (method, want) in [(Method::Biharmonic, bih), (Method::Laplacian, lap), (Method::Spring, spring)] {
            let l = largest_valid_amplitude(&s, 0.1, method, &Options::default(), (0.05, 1.0, 1e-3)).unwrap();
            let first = l.first_inverted.unwrap();
            assert!(first > l.largest_valid && first - l.largest_valid <= 1e-3, "{l:?}");
            assert!((l.largest_valid - want).abs() < 2e-3, "{} {method:?}: {}", s.name, l.largest_valid);
            // Checked by a solve at each end: valid just below, inverted just above.
            for (a, inverted) in [(l.largest_valid, false), (first, true)] {
                let r = run_case(&free_surface_3d_case(cells, 8, a, 1), method, &Options::default()).unwrap();
                assert_eq!(r.inverted > 0, inverted, "{} {method:?} A = {a}", s.name);
            }
        }
        assert!(bih > 1.3 * lap.max(spring));
    }
}

#[test]
fn boundary_layer_cylinder_3d_keeps_the_2d_finding() {
    // Two layers (11,772 vertices): the demo's four take about twice as long.
    let s = boundary_layer_cylinder_3d_case(2);
    let flat = boundary_layer_cylinder_hybrid();
    let n = flat.num_vertices();
    assert_eq!(s.mesh.num_vertices(), 3 * n);
    assert_eq!(s.mesh.patch_ids(), vec![BL_FAR, BL_CYLINDER, BL_Z0, BL_Z1]);
    let hexes: Vec<usize> = (0..s.mesh.num_cells()).filter(|&c| s.mesh.cell_type(c) == CellType::Hexahedron).collect();
    assert_eq!(hexes.len(), 2 * BL_LAYERS * BL_N_THETA);
    assert!(
        (volume(&s.mesh) - sum(signed_measures(&Mesh::from_data(&flat).unwrap(), &flat.coords).into_iter())).abs()
            < 1e-9
    );
    let v0 = signed_measures(&s.mesh, s.mesh.coords());
    let flat_case = case("boundary_layer_cylinder_hybrid", Scale::Paper).unwrap();
    for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
        // Solved far below the default tolerance: the layers agree to what the solve leaves.
        let mut o = Options::default();
        o.solve.tol = 1e-12;
        let r = run_case(&s, method, &o).unwrap();
        assert!(r.failure.is_none() && r.reports.iter().all(|x| x.converged), "{method:?}");
        let v1 = signed_measures(&s.mesh, &r.coords);
        let (lo, hi) = hexes
            .iter()
            .map(|&c| v1[c] / v0[c])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
        // z stays put and every layer moves alike, as the 2D mesh does.
        let disp = |k: usize, v: usize, c: usize| r.coords[3 * (k * n + v) + c] - s.mesh.coords()[3 * (k * n + v) + c];
        assert!((0..3 * n).all(|v| disp(0, v, 2) == 0.0), "{method:?}: z moved");
        let r2 = run_case(&flat_case, method, &Options::default()).unwrap();
        let (mut layers, mut vs_2d) = (0.0f64, 0.0f64);
        for v in 0..n {
            for c in 0..2 {
                layers = layers.max((disp(0, v, c) - disp(1, v, c)).abs()).max((disp(1, v, c) - disp(2, v, c)).abs());
                vs_2d = vs_2d.max((disp(1, v, c) - (r2.coords[2 * v + c] - flat_case.mesh.coords()[2 * v + c])).abs());
            }
        }
        let (first_lo, first_hi) = r.patch.area_ratio;
        eprintln!(
            "{method:?}: {} inverted, min volume ratio {:.4}, wall layer {lo:.4}..{hi:.4}, first cells \
             {first_lo:.4}..{first_hi:.4}, layers differ by {layers:.1e}, from 2D by {vs_2d:.1e}",
            r.inverted, r.min_area_ratio
        );
        // At a 1e-12 residual the layers agree to 7.5e-8 (biharmonic, of a 2.25 displacement).
        assert!(layers < 1e-6, "{method:?}: layers differ by {layers:e}");
        match method {
            // Measured: 0.4909, wall layer 0.873–1.086, first cells 0.9986–1.0009; 4.7e-5 from
            // the 2D solution (the wedges' averaged tetrahedra are not the 2D triangles).
            Method::Biharmonic => {
                assert_eq!(r.inverted, 0);
                assert!((r.min_area_ratio - 0.4906).abs() < 5e-3, "{}", r.min_area_ratio);
                assert!(lo > 0.85 && hi < 1.11, "{lo} {hi}");
                assert!(first_lo > 0.995 && first_hi < 1.005, "{first_lo} {first_hi}");
                assert!(vs_2d < 1e-2, "{vs_2d}");
            }
            // The 2D count on each layer: 2 × 1043.
            Method::Laplacian => {
                assert_eq!(r.inverted, 2 * 1043);
                assert!(vs_2d < 1e-6, "{vs_2d}");
            }
            // Measured: 0.1463, wall layer 0.976–1.022, first cells 0.998–1.002.
            Method::Spring => {
                assert_eq!(r.inverted, 0);
                assert!((r.min_area_ratio - 0.1463).abs() < 2e-3, "{}", r.min_area_ratio);
                assert!(lo > 0.97 && hi < 1.03, "{lo} {hi}");
                assert!(first_lo > 0.995 && first_hi < 1.005, "{first_lo} {first_hi}");
                assert!(vs_2d < 1e-5, "{vs_2d}");
            }
        }
    }
}
