//! Thin wall layers (cells of aspect ratio 10³–10⁴ at a wall, growing 1.2 per layer) move in a
//! fixed number of iterations with every method: the multigrid's line smoothing across the
//! layers (docs/DESIGN.md §5) holds the counts of isotropic meshes.

use meshmove::{BoundaryConditions, CellType, Kind, Mesh, MeshData, Method, Motion, Options, RigidMotion, Solver};
use std::f64::consts::PI;

/// The heights of layers on a wall: at most `layers` of them from `first`, each `growth` times
/// the last while below `h`, then `h`, up to the total height `to` (the last one ends exactly
/// there).
fn graded(first: f64, growth: f64, layers: usize, h: f64, to: f64) -> Vec<f64> {
    let mut z = vec![0.0];
    let mut dz = first;
    while z.last().unwrap() + 1.5 * dz.min(h) < to {
        z.push(z.last().unwrap() + dz.min(h));
        dz = if z.len() > layers { h } else { dz * growth };
    }
    z.push(to);
    z
}

/// A cylinder of radius 0.5 (patch 1) in a circular far field of radius 20 (patch 2), `nt`
/// vertices around: quad layers from the wall of first height `first` growing by 1.2 until they
/// are as high as they are wide, then isotropic rings of triangles.
fn cylinder_layers(nt: usize, first: f64, layers: usize) -> Mesh {
    let mut radii = vec![0.5];
    let mut dr = first;
    while *radii.last().unwrap() < 20.0 {
        let r = *radii.last().unwrap();
        let wide = 2.0 * PI * r / nt as f64;
        let quad = dr < wide && radii.len() <= layers;
        if !quad {
            dr = wide;
        }
        radii.push(r + dr.min(wide));
        if quad {
            dr *= 1.2;
        }
    }
    let nr = radii.len();
    let mut d = MeshData::new(2);
    for &r in &radii {
        for j in 0..nt {
            let t = 2.0 * PI * j as f64 / nt as f64;
            d.push_vertex(&[r * t.cos(), r * t.sin()]);
        }
    }
    let id = |k: usize, j: usize| (k * nt + j % nt) as u32;
    for k in 0..nr - 1 {
        let quad = k < layers && radii[k + 1] - radii[k] < 0.99 * 2.0 * PI * radii[k] / nt as f64;
        for j in 0..nt {
            let q = [id(k, j), id(k, j + 1), id(k + 1, j + 1), id(k + 1, j)];
            if quad {
                d.push_cell(CellType::Quad, &q, 0);
            } else {
                d.push_cell(CellType::Triangle, &[q[0], q[1], q[2]], 0);
                d.push_cell(CellType::Triangle, &[q[0], q[2], q[3]], 0);
            }
        }
    }
    for j in 0..nt {
        d.push_face(&[id(0, j + 1), id(0, j)], 1);
        d.push_face(&[id(nr - 1, j), id(nr - 1, j + 1)], 2);
    }
    Mesh::from_data(&d).unwrap()
}

/// The unit box's wall z = 0 (patch 1) under prism layers of first height `first` growing by
/// 1.2 until as high as wide (`n` cells across), tetrahedra above; the top z = 1 is patch 2 and
/// the four sides patch 3.
fn box_layers(n: usize, first: f64, layers: usize) -> Mesh {
    let h = 1.0 / n as f64;
    let z = graded(first, 1.2, layers, h, 1.0);
    let nz = z.len() - 1;
    let mut d = MeshData::new(3);
    for &zk in &z {
        for j in 0..=n {
            for i in 0..=n {
                d.push_vertex(&[i as f64 * h, j as f64 * h, zk]);
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| (k * (n + 1) * (n + 1) + j * (n + 1) + i) as u32;
    for k in 0..nz {
        let prisms = z[k + 1] - z[k] < 0.99 * h;
        for j in 0..n {
            for i in 0..n {
                let c = |a: usize, b: usize, e: usize| id(i + a, j + b, k + e);
                if prisms {
                    // Both halves of the square cut by its diagonal (0,0)–(1,1).
                    d.push_cell(
                        CellType::Wedge,
                        &[c(0, 0, 0), c(1, 1, 0), c(1, 0, 0), c(0, 0, 1), c(1, 1, 1), c(1, 0, 1)],
                        0,
                    );
                    d.push_cell(
                        CellType::Wedge,
                        &[c(0, 0, 0), c(0, 1, 0), c(1, 1, 0), c(0, 0, 1), c(0, 1, 1), c(1, 1, 1)],
                        0,
                    );
                } else {
                    // Kuhn's six tetrahedra about the diagonal (0,0,0)–(1,1,1): conforming.
                    let (o, x) = (c(0, 0, 0), c(1, 1, 1));
                    for [a, b] in [
                        [c(1, 0, 0), c(1, 1, 0)],
                        [c(1, 1, 0), c(0, 1, 0)],
                        [c(0, 1, 0), c(0, 1, 1)],
                        [c(0, 1, 1), c(0, 0, 1)],
                        [c(0, 0, 1), c(1, 0, 1)],
                        [c(1, 0, 1), c(1, 0, 0)],
                    ] {
                        d.push_cell(CellType::Tetra, &[o, a, b, x], 0);
                    }
                }
            }
        }
    }
    // Quads with their first corner lowest and third highest; split along that diagonal where
    // the cells beside them are simplices or prisms' triangles.
    let mut face = |q: [u32; 4], p: i32, split: bool| {
        if split {
            d.push_face(&[q[0], q[1], q[2]], p);
            d.push_face(&[q[0], q[2], q[3]], p);
        } else {
            d.push_face(&q, p);
        }
    };
    let tets = |k: usize| z[k + 1] - z[k] >= 0.99 * h;
    for a in 0..n {
        for b in 0..n {
            face([id(a, b, 0), id(a, b + 1, 0), id(a + 1, b + 1, 0), id(a + 1, b, 0)], 1, true);
            face([id(a, b, nz), id(a + 1, b, nz), id(a + 1, b + 1, nz), id(a, b + 1, nz)], 2, true);
        }
        for k in 0..nz {
            face([id(a, 0, k), id(a + 1, 0, k), id(a + 1, 0, k + 1), id(a, 0, k + 1)], 3, tets(k));
            face([id(a, n, k), id(a, n, k + 1), id(a + 1, n, k + 1), id(a + 1, n, k)], 3, tets(k));
            face([id(0, a, k), id(0, a, k + 1), id(0, a + 1, k + 1), id(0, a + 1, k)], 3, tets(k));
            face([id(n, a, k), id(n, a + 1, k), id(n, a + 1, k + 1), id(n, a, k + 1)], 3, tets(k));
        }
    }
    Mesh::from_data(&d).unwrap()
}

/// PCG iterations of a one-step pitch of the cylinder by 10° about (−0.25, 0), wall CLAMPED,
/// far field FIXED.
fn cylinder_iterations(mesh: &Mesh, method: Method) -> usize {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(1, Kind::Clamped).set_kinds(2, Kind::Fixed);
    let solver = Solver::new(mesh, &bcs, Options { method, ..Default::default() }).unwrap();
    let motion = Motion::zero(mesh).with_rigid(1, RigidMotion::planar([0.0, 0.05], 10f64.to_radians(), [-0.25, 0.0]));
    let s = solver.solve(&motion).unwrap();
    assert!(s.report.converged, "{method:?}: {:?}", s.report.rel_residual);
    s.report.cycles
}

/// PCG iterations of a one-step bulge of the box's wall (CLAMPED), top FIXED, sides SLIP.
fn box_iterations(mesh: &Mesh, method: Method) -> usize {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(1, Kind::Clamped).set_kinds(2, Kind::Fixed).set_kinds(3, Kind::Slip);
    let solver = Solver::new(mesh, &bcs, Options { method, ..Default::default() }).unwrap();
    let disp = (0..mesh.num_vertices())
        .flat_map(|v| {
            let p = mesh.point(v);
            [0.0, 0.0, 0.02 + 0.05 * (PI * p[0]).sin() * (PI * p[1]).sin()]
        })
        .collect();
    let s = solver.solve(&Motion::from_displacement(disp)).unwrap();
    assert!(s.report.converged, "{method:?}: {:?}", s.report.rel_residual);
    s.report.cycles
}

const METHODS: [Method; 3] = [Method::Biharmonic, Method::Laplacian, Method::Spring];

#[test]
fn cylinder_layers_of_first_height_1e5() {
    // Wall cells of aspect ratio about 6500 (quads 1e-5 high, 0.065 wide): the layers grow until
    // as high as wide, and as 30 layers met by triangles 14 times their top's height.
    for (layers, bounds) in [(100, [6, 5, 5]), (30, [5, 8, 8])] {
        let mesh = cylinder_layers(48, 1e-5, layers);
        for (method, bound) in METHODS.into_iter().zip(bounds) {
            let it = cylinder_iterations(&mesh, method);
            eprintln!("cylinder, {layers} layers, {} vertices: {method:?} {it}", mesh.num_vertices());
            assert!(it <= bound, "{method:?}: {it} iterations");
        }
    }
}

#[test]
fn box_layers_of_first_height_1e4() {
    // Prisms of aspect ratio about 1250 at the wall, tetrahedra above, sides SLIP.
    let mesh = box_layers(8, 1e-4, 100);
    for (method, bound) in METHODS.into_iter().zip([7, 6, 6]) {
        let it = box_iterations(&mesh, method);
        eprintln!("box, {} vertices: {method:?} {it}", mesh.num_vertices());
        assert!(it <= bound, "{method:?}: {it} iterations");
    }
}

#[test]
fn cylinder_layers_move_in_re_referenced_steps() {
    // The pitch in 5 steps, each from the mesh the last one made (the lines are kept, their
    // blocks refactored on the moved mesh): the moved layers take a few more iterations than
    // the first step, and no step more than the bounds.
    let mesh = cylinder_layers(48, 1e-5, 30);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(1, Kind::Clamped).set_kinds(2, Kind::Fixed);
    let motion = Motion::zero(&mesh).with_rigid(1, RigidMotion::planar([0.0, 0.05], 10f64.to_radians(), [-0.25, 0.0]));
    for (method, bound) in METHODS.into_iter().zip([5, 11, 4]) {
        let mut solver = Solver::new(&mesh, &bcs, Options { method, ..Default::default() }).unwrap();
        let steps = solver.move_in_steps(&motion, 5).unwrap();
        let its: Vec<usize> = steps.iter().map(|s| s.cycles).collect();
        eprintln!("cylinder, 5 steps: {method:?} {its:?}");
        assert_eq!(its.len(), 5);
        assert!(its.iter().all(|&i| i <= bound), "{method:?}: {its:?}");
    }
}

#[test]
fn cylinder_layers_plunge_in_re_referenced_steps_stays_valid() {
    // A plunge (a translation) in 20 steps, each from the mesh the last one made: every step
    // after the first is warm-started from the last steps' increments, whose residual already
    // meets the tolerance. Under wall layers such a step still takes one iteration, which
    // corrects the error the tolerance leaves in the thinnest cells; accepted as it is, that
    // error is carried into every next reference and the layers fold.
    let mesh = cylinder_layers(48, 1e-5, 30);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(1, Kind::Clamped).set_kinds(2, Kind::Fixed);
    let motion = Motion::zero(&mesh).with_rigid(1, RigidMotion::translation([0.0, 2.0, 0.0]));
    let mut solver = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    // A tangled step before the last is an error (the next step cannot start from it).
    let steps = solver.move_in_steps(&motion, 20).unwrap_or_else(|e| panic!("{e}"));
    let its: Vec<usize> = steps.iter().map(|s| s.cycles).collect();
    let worst = steps.iter().map(|s| s.min_volume_ratio).fold(f64::INFINITY, f64::min);
    let moved: Vec<f64> = solver.current_coords().iter().zip(mesh.coords()).map(|(x, o)| x - o).collect();
    let q = Solver::new(&mesh, &bcs, Options::default()).unwrap().quality(&moved);
    eprintln!("cylinder plunge, 20 steps: {its:?}, worst step {worst}, against the original {q:?}");
    assert!(steps.iter().all(|s| s.accepted && s.inverted == 0), "{steps:?}");
    assert!(its[0] <= 5 && its[1..].iter().all(|&i| i == 1), "{its:?}");
    assert!(q.inverted == 0 && q.min_area_ratio > 0.8, "{q:?}");
}
