//! Quad and mixed triangle/quad meshes: linear displacement fields reproduced exactly by every
//! method (the Q1 stiffness and lumped mass keep linear fields in the discrete solution).

#[path = "../../tests/common/mod.rs"]
mod common;
#[path = "../../tests/common/direct.rs"]
mod direct;

use common::{to_flat, wavy};
use direct::{at_dofs, direct_solve};
use meshmove::{BoundaryConditions, CellType, Kind, Mesh, MeshData, Method, Motion, Options, Solver};
use meshmove_cases::report::{patch_measures, run_case};
use meshmove_cases::setups::{case, Scale};

/// An n × n grid on [0,1]², perturbed inside, quads (or, with `mixed`, the left half split
/// into triangles); every boundary face on patch 1.
fn grid(n: usize, mixed: bool) -> Mesh {
    let mut d = MeshData::new(2);
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..=n {
        for i in 0..=n {
            let (mut x, mut y) = (i as f64 / n as f64, j as f64 / n as f64);
            if i > 0 && i < n && j > 0 && j < n {
                x += 0.15 / n as f64 * ((7 * i + 3 * j) as f64).sin();
                y += 0.15 / n as f64 * ((5 * i + 11 * j) as f64).cos();
            }
            d.push_vertex(&[x, y]);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if mixed && i < n / 2 {
                d.push_cell(CellType::Triangle, &[q[0], q[1], q[2]], 0);
                d.push_cell(CellType::Triangle, &[q[0], q[2], q[3]], 0);
            } else {
                d.push_cell(CellType::Quad, &q, 0);
            }
        }
    }
    for k in 0..n {
        for f in
            [[id(k, 0), id(k + 1, 0)], [id(n, k), id(n, k + 1)], [id(k, n), id(k + 1, n)], [id(0, k), id(0, k + 1)]]
        {
            d.push_face(&f, 1);
        }
    }
    Mesh::from_data(&d).expect("valid grid")
}

#[test]
fn linear_fields_are_exact_on_quads_and_mixed_meshes() {
    for mixed in [false, true] {
        let mesh = grid(16, mixed);
        assert_eq!(mesh.cell_types().contains(&CellType::Triangle), mixed);
        let lin = |p: &[f64]| [0.1 + 0.2 * p[0] - 0.05 * p[1], -0.03 + 0.07 * p[0] + 0.11 * p[1]];
        let mut motion = Motion::zero(&mesh);
        for v in 0..mesh.num_vertices() {
            let u = lin(mesh.point(v));
            motion.displacement[2 * v..2 * v + 2].copy_from_slice(&u);
        }
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(1, Kind::Fixed);
        for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
            let mut opts = Options { method, ..Default::default() };
            opts.solve.tol = 1e-13;
            let sol = Solver::new(&mesh, &bcs, opts).unwrap().solve(&motion).unwrap();
            let err = (0..mesh.num_vertices())
                .flat_map(|v| {
                    let u = lin(mesh.point(v));
                    [sol.displacement[2 * v] - u[0], sol.displacement[2 * v + 1] - u[1]]
                })
                .fold(0.0f64, |m, e| m.max(e.abs()));
            // The spring analogy (graph Laplacian, 1/L² weights) is not linear-exact on a
            // perturbed grid; the finite element operators are.
            if method == Method::Spring {
                assert!(err < 0.05, "{method:?} mixed={mixed}: {err:e}");
            } else {
                assert!(err < 1e-11, "{method:?} mixed={mixed}: {err:e}");
            }
            assert_eq!(sol.quality.inverted, 0);
        }
    }
}

#[test]
fn non_convex_quads_are_refused() {
    let mut d = MeshData::new(2);
    for p in [[0.0, 0.0], [2.0, 0.0], [0.5, 0.5], [0.0, 2.0]] {
        d.push_vertex(&p);
    }
    d.push_cell(CellType::Quad, &[0, 1, 2, 3], 0);
    let e = Mesh::from_data(&d).unwrap_err();
    assert!(e.to_string().contains("not convex"), "{e}");
}

/// The multigrid solution on quad and mixed meshes equals a dense direct solve of the same
/// discrete system, for every method, with FIXED and CLAMPED walls.
#[test]
fn quads_and_mixed_meshes_match_direct_solve() {
    for mixed in [false, true] {
        let mesh = grid(12, mixed);
        let field = to_flat(&mesh.points_2d().iter().map(|&x| wavy(x)).collect::<Vec<_>>());
        for kind in [Kind::Fixed, Kind::Clamped] {
            let mut bcs = BoundaryConditions::new();
            bcs.set_kinds(1, kind);
            for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
                let mut o = Options { method, ..Default::default() };
                o.solve.tol = 1e-13;
                // A coarsest size below 2D's default keeps a coarse level on this small mesh.
                o.hierarchy.coarsen.coarsest_unknowns = Some(40);
                let s = Solver::new(&mesh, &bcs, o).unwrap();
                assert!(s.num_levels() >= 2, "no coarse level");
                let sol = s.solve(&Motion::from_displacement(field.clone())).unwrap();
                for c in 0..2 {
                    let mg = at_dofs(&s, &sol.displacement, c);
                    let direct = direct_solve(&s, c, &mg);
                    let scale = direct.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    let err = mg.iter().zip(&direct).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                    assert!(scale > 1e-3 && err <= 1e-10 * scale, "mixed={mixed} {kind:?} {method:?} {c}: {err:e}");
                }
            }
        }
    }
}

/// The boundary-layer finding of the paper on the hybrid mesh (the 15 wall layers as quads):
/// biharmonic and spring valid with the wall layer kept, the Laplacian inverts.
#[test]
fn boundary_layer_finding_holds_on_the_hybrid_mesh() {
    let setup = case("boundary_layer_cylinder_hybrid", Scale::Paper).unwrap();
    assert!(setup.mesh.cell_types().contains(&CellType::Quad));
    assert!(setup.mesh.cell_types().contains(&CellType::Triangle));
    for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
        let r = run_case(&setup, method, &Options::default()).unwrap();
        if method == Method::Laplacian {
            assert!(r.inverted > 500, "Laplacian: {} inverted", r.inverted);
            continue;
        }
        assert_eq!(r.inverted, 0, "{method:?}");
        let pm = patch_measures(&setup.mesh, &r.coords, setup.moved_patch, None);
        assert!(pm.area_ratio.0 > 0.99 && pm.area_ratio.1 < 1.01, "{method:?}: wall cells {:?}", pm.area_ratio);
    }
}
