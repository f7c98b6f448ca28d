//! 3D cells: tetrahedra, hexahedra, wedges and pyramids, alone and mixed, reproduce linear
//! fields exactly and agree with a dense direct solve of the same discrete system; a 3D rigid
//! motion of the whole boundary moves the mesh rigidly.

mod common;
#[path = "common/direct.rs"]
mod direct;

use direct::{at_dofs, direct_solve};
use meshmove::{BoundaryConditions, CellType, Kind, Mesh, MeshData, Method, Motion, Options, RigidMotion, Solver};

/// Vertex (i, j, k) of an n³ grid of the unit cube, jittered inside.
fn grid_points(d: &mut MeshData, n: usize) {
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let mut p = [i, j, k].map(|a| a as f64 / n as f64);
                if [i, j, k].iter().all(|&a| a > 0 && a < n) {
                    let s = (7 * i + 3 * j + 5 * k) as f64;
                    p[0] += 0.12 / n as f64 * s.sin();
                    p[1] += 0.12 / n as f64 * (1.3 * s).cos();
                    p[2] += 0.12 / n as f64 * (0.7 * s).sin();
                }
                d.push_vertex(&p);
            }
        }
    }
}

/// The 8 corners of grid cube (i, j, k) in VTK hexahedron order.
fn cube(n: usize, i: usize, j: usize, k: usize) -> [u32; 8] {
    let id = |i: usize, j: usize, k: usize| ((k * (n + 1) + j) * (n + 1) + i) as u32;
    [
        id(i, j, k),
        id(i + 1, j, k),
        id(i + 1, j + 1, k),
        id(i, j + 1, k),
        id(i, j, k + 1),
        id(i + 1, j, k + 1),
        id(i + 1, j + 1, k + 1),
        id(i, j + 1, k + 1),
    ]
}

/// The kinds of 3D test mesh.
#[derive(Clone, Copy, Debug)]
enum Kind3 {
    Tets,
    Hexes,
    /// Hexes, and wedges where a cube is cut in two along a vertical diagonal plane (whole
    /// columns, so the triangles of the cut faces match).
    HexWedge,
    /// Hexes, and cubes cut into six pyramids around an added centre vertex.
    HexPyramid,
}

fn mesh(kind: Kind3, n: usize) -> Mesh {
    let mut d = MeshData::new(3);
    grid_points(&mut d, n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = cube(n, i, j, k);
                match kind {
                    Kind3::Tets => {
                        // Freudenthal: six tetrahedra along the diagonal 0–6, the same in every
                        // cube, so neighbouring cubes' face diagonals match.
                        for path in [[1, 2], [2, 3], [3, 7], [7, 4], [4, 5], [5, 1]] {
                            d.push_cell(CellType::Tetra, &[c[0], c[path[0]], c[path[1]], c[6]], 0);
                        }
                    }
                    Kind3::Hexes => d.push_cell(CellType::Hexahedron, &c, 0),
                    Kind3::HexWedge if (i + j) % 2 == 0 => {
                        d.push_cell(CellType::Wedge, &[c[0], c[3], c[1], c[4], c[7], c[5]], 0);
                        d.push_cell(CellType::Wedge, &[c[1], c[3], c[2], c[5], c[7], c[6]], 0);
                    }
                    Kind3::HexPyramid if (i + j + k) % 2 == 0 => {
                        let centre: Vec<f64> = (0..3)
                            .map(|a| c.iter().map(|&v| d.coords[3 * v as usize + a]).sum::<f64>() / 8.0)
                            .collect();
                        let o = d.push_vertex(&centre);
                        // Each face of the cube, its right-hand normal towards the centre.
                        for f in [[0, 1, 2, 3], [4, 7, 6, 5], [0, 4, 5, 1], [1, 5, 6, 2], [2, 6, 7, 3], [3, 7, 4, 0]] {
                            d.push_cell(CellType::Pyramid, &[c[f[0]], c[f[1]], c[f[2]], c[f[3]], o], 0);
                        }
                    }
                    _ => d.push_cell(CellType::Hexahedron, &c, 0),
                }
            }
        }
    }
    Mesh::from_data(&d).unwrap_or_else(|e| panic!("{kind:?}: {e}"))
}

const KINDS: [Kind3; 4] = [Kind3::Tets, Kind3::Hexes, Kind3::HexWedge, Kind3::HexPyramid];

fn linear(p: &[f64]) -> [f64; 3] {
    [
        0.01 + 0.05 * p[0] - 0.02 * p[1] + 0.03 * p[2],
        -0.03 + 0.04 * p[0] + 0.06 * p[1] - 0.01 * p[2],
        0.02 - 0.03 * p[0] + 0.01 * p[1] + 0.05 * p[2],
    ]
}

/// Options that coarsen small test meshes down to a few dozen unknowns (several levels) and
/// solve to 1e-13.
fn multilevel(method: Method) -> Options {
    let mut o = Options { method, ..Default::default() };
    o.solve.tol = 1e-13;
    o.hierarchy.coarsen.coarsest_unknowns = Some(40);
    o
}

/// The whole boundary (patch 0) prescribed by `field`, `kind` for every component.
fn run(mesh: &Mesh, method: Method, kind: Kind, field: impl Fn(&[f64]) -> [f64; 3]) -> (Solver, Vec<f64>) {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(0, kind);
    let s = Solver::new(mesh, &bcs, multilevel(method)).unwrap();
    let mut motion = Motion::zero(mesh);
    for v in 0..mesh.num_vertices() {
        motion.displacement[3 * v..3 * v + 3].copy_from_slice(&field(mesh.point(v)));
    }
    let sol = s.solve(&motion).unwrap();
    assert_eq!(sol.quality.inverted, 0);
    (s, sol.displacement)
}

#[test]
fn every_cell_type_reproduces_linear_fields() {
    for kind in KINDS {
        let m = mesh(kind, 5);
        assert_eq!(m.dim(), 3);
        for method in [Method::Biharmonic, Method::Laplacian] {
            let (_, d) = run(&m, method, Kind::Fixed, linear);
            let err = (0..m.num_vertices())
                .flat_map(|v| {
                    let u = linear(m.point(v));
                    (0..3).map(move |c| (c, u[c], v))
                })
                .fold(0.0f64, |e, (c, u, v)| e.max((d[3 * v + c] - u).abs()));
            assert!(err < 1e-12, "{kind:?} {method:?}: {err:e}");
        }
    }
}

#[test]
fn every_cell_type_matches_a_direct_solve() {
    let wavy = |p: &[f64]| {
        let w = std::f64::consts::TAU * p[0];
        [0.02 * w.sin() + 0.01 * p[2] * p[2], 0.05 * w.cos() * p[1], 0.03 * (w * p[2]).sin()]
    };
    for kind in KINDS {
        let m = mesh(kind, 8);
        for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
            for bc in [Kind::Fixed, Kind::Clamped] {
                let (s, d) = run(&m, method, bc, wavy);
                assert!(s.hierarchy().levels.len() >= 3, "{kind:?}: {} levels", s.hierarchy().levels.len());
                for c in 0..3 {
                    let mg = at_dofs(&s, &d, c);
                    let direct = direct_solve(&s, c, &mg);
                    let scale = direct.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    let err = mg.iter().zip(&direct).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                    assert!(scale > 1e-3 && err <= 1e-10 * scale, "{kind:?} {method:?} {bc:?} {c}: {err:e}");
                }
            }
        }
    }
}

/// Every coarse level's interpolation reproduces linear fields at every fine unknown, inside
/// and on the walls and edges of the cube (flat, so linear along them too).
#[test]
fn coarse_levels_interpolate_linear_fields_exactly() {
    let lin = |p: &[f64]| 0.3 + 0.7 * p[0] - 1.1 * p[1] + 0.4 * p[2];
    for kind in KINDS {
        let m = mesh(kind, 8);
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(0, Kind::Clamped);
        let s = Solver::new(&m, &bcs, multilevel(Method::Biharmonic)).unwrap();
        let levels = &s.hierarchy().levels;
        assert!(levels.len() >= 3, "{kind:?}: {} levels", levels.len());
        for l in 0..levels.len() - 1 {
            let (fine, coarse) = (&levels[l], &levels[l + 1]);
            let at = |lev: &meshmove::multigrid::hierarchy::Level| -> Vec<f64> {
                lev.unknown_points().chunks_exact(3).map(lin).collect()
            };
            let p = &fine.prolong().unwrap();
            let mut y = vec![0.0; fine.n()];
            p.mul_vec(&at(coarse), &mut y);
            let err = y.iter().zip(at(fine)).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(err < 1e-12, "{kind:?} level {l}: {err:e}");
            let ratio = fine.n() as f64 / coarse.n() as f64;
            assert!(ratio > 3.0, "{kind:?} level {l}: {} -> {} unknowns", fine.n(), coarse.n());
        }
    }
}

/// The whole boundary CLAMPED and moved by a 3D rigid motion (axis-angle rotation about a centre
/// and a translation): with the rigid flux of the clamped condition the biharmonic returns the
/// rigid motion of the whole mesh.
#[test]
fn a_rigid_boundary_motion_moves_the_mesh_rigidly() {
    let r = RigidMotion { translation: [0.1, -0.05, 0.2], rotation: [0.2, -0.1, 0.3], center: [0.5, 0.5, 0.5] };
    for kind in KINDS {
        let m = mesh(kind, 4);
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(0, Kind::Clamped);
        let s = Solver::new(&m, &bcs, multilevel(Method::Biharmonic)).unwrap();
        let d = s.solve(&Motion::zero(&m).with_rigid(0, r)).unwrap().displacement;
        let err = (0..m.num_vertices())
            .map(|v| {
                let u = r.displacement(m.point(v));
                (0..3).map(|c| (d[3 * v + c] - u[c]).abs()).fold(0.0, f64::max)
            })
            .fold(0.0f64, f64::max);
        assert!(err < 1e-12, "{kind:?}: {err:e}");
    }
}

/// A rigid motion in four steps, the reference re-evaluated after each (the coarse levels of
/// kept unknowns follow the moved mesh: new weights, new Galerkin operators): the mesh ends
/// rigidly moved, as in one step.
#[test]
fn a_rigid_motion_in_steps_moves_the_mesh_rigidly() {
    let r = RigidMotion { translation: [0.08, 0.0, -0.04], rotation: [0.0, 0.3, 0.1], center: [0.5, 0.5, 0.5] };
    for kind in [Kind3::Tets, Kind3::HexWedge] {
        let m = mesh(kind, 8);
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(0, Kind::Clamped);
        let mut s = Solver::new(&m, &bcs, multilevel(Method::Biharmonic)).unwrap();
        assert!(s.hierarchy().levels.len() >= 3);
        let reports = s.move_in_steps(&Motion::zero(&m).with_rigid(0, r), 4).unwrap();
        assert_eq!(reports.len(), 4);
        let x = s.current_coords();
        let err = (0..m.num_vertices())
            .map(|v| {
                let u = r.displacement(m.point(v));
                (0..3).map(|c| (x[3 * v + c] - m.point(v)[c] - u[c]).abs()).fold(0.0, f64::max)
            })
            .fold(0.0f64, f64::max);
        assert!(err < 1e-10, "{kind:?}: {err:e}");
    }
}

/// Meshes written by Gmsh (tetrahedra; prisms, converted to VTK wedges on reading) and by VTK
/// (mixed cells, appended zlib data) are moved exactly by a linear field.
#[test]
fn gmsh_and_vtk_3d_files_reproduce_linear_fields() {
    let data = |f: &str| std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(f);
    let meshes = [
        meshmove::io::read_msh(&data("box_tets_41.msh")).unwrap().mesh,
        meshmove::io::read_msh(&data("slab_prisms_41_bin.msh")).unwrap().mesh,
        meshmove::io::read_vtu(&data("mixed3d_appended.vtu")).unwrap().to_mesh().unwrap(),
    ];
    for m in &meshes {
        assert_eq!(m.dim(), 3);
        let mut bcs = BoundaryConditions::new();
        for p in m.patch_ids() {
            bcs.set_kinds(p, Kind::Fixed);
        }
        let mut motion = Motion::zero(m);
        for v in 0..m.num_vertices() {
            motion.displacement[3 * v..3 * v + 3].copy_from_slice(&linear(m.point(v)));
        }
        let mut o = Options::default();
        o.solve.tol = 1e-13;
        let d = Solver::new(m, &bcs, o).unwrap().solve(&motion).unwrap().displacement;
        let err = d.iter().zip(&motion.displacement).fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
        assert!(err < 1e-12, "{:?}: {err:e}", m.cell_types().first());
    }
}

/// A 3D solve gives bitwise the same displacement on one thread and on two.
#[test]
fn threads_do_not_change_a_3d_result() {
    let m = mesh(Kind3::HexPyramid, 12);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(0, Kind::Fixed);
    let mut motion = Motion::zero(&m);
    for v in 0..m.num_vertices() {
        let p = m.point(v);
        motion.displacement[3 * v + 2] = 0.05 * (7.0 * p[0]).sin() * p[1];
    }
    let solve = |threads| {
        let s = Solver::new(&m, &bcs, Options { threads, ..Default::default() }).unwrap();
        s.solve(&motion).unwrap().displacement
    };
    let (one, two) = (solve(1), solve(2));
    assert!(m.num_vertices() > 2000);
    assert_eq!(one.len(), two.len());
    assert!(one.iter().zip(&two).all(|(a, b)| a.to_bits() == b.to_bits()));
}
