//! General cells and face-based meshes: polyhedra (hexahedra merged in 2 × 2 × 1 blocks, their
//! sides split) and polygons (quads merged in pairs) reproduce linear fields and agree with a
//! dense direct solve; hexahedral and tetrahedral meshes given by their faces move bitwise as
//! the same meshes given by their cells; broken polyhedra and face lists are refused by name.

#[path = "common/direct.rs"]
mod direct;

use direct::{at_dofs, direct_solve};
use meshmove::{
    BoundaryConditions, CellType, FaceMeshData, Kind, Mesh, MeshData, MeshError, Method, Motion, Options, Solver,
};

/// Vertex (i, j, k) of an n³ grid of the unit cube (n² in 2D), jittered inside.
fn grid(dim: usize, n: usize) -> MeshData {
    let mut d = MeshData::new(dim);
    for k in 0..if dim == 3 { n + 1 } else { 1 } {
        for j in 0..=n {
            for i in 0..=n {
                let mut p = [i, j, k].map(|a| a as f64 / n as f64);
                if [i, j, k][..dim].iter().all(|&a| a > 0 && a < n) {
                    let s = (7 * i + 3 * j + 5 * k) as f64;
                    p[0] += 0.1 / n as f64 * s.sin();
                    p[1] += 0.1 / n as f64 * (1.3 * s).cos();
                    p[2] += 0.1 / n as f64 * (0.7 * s).sin() * (dim == 3) as u8 as f64;
                }
                d.push_vertex(&p[..dim]);
            }
        }
    }
    d
}

/// The corners of grid cube (i, j, k) of an n³ grid in VTK hexahedron order.
fn cube(n: usize, i: usize, j: usize, k: usize) -> [u32; 8] {
    let id = |i: usize, j: usize, k: usize| ((k * (n + 1) + j) * (n + 1) + i) as u32;
    let [a, b, c, e] = [id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k)];
    let [f, g, h, l] = [id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)];
    [a, b, c, e, f, g, h, l]
}

/// Hexahedra of an n³ grid (n even) where every third 2 × 2 × 1 block of cubes is one
/// polyhedron of 16 quad faces and 18 vertices (the cubes' outer faces).
fn polyhedral(n: usize) -> MeshData {
    let mut d = grid(3, n);
    for k in 0..n {
        for bj in 0..n / 2 {
            for bi in 0..n / 2 {
                let cubes: Vec<[u32; 8]> =
                    [(0, 0), (1, 0), (0, 1), (1, 1)].iter().map(|&(a, b)| cube(n, 2 * bi + a, 2 * bj + b, k)).collect();
                if (bi + bj + k) % 3 != 0 {
                    cubes.iter().for_each(|c| d.push_cell(CellType::Hexahedron, c, 0));
                    continue;
                }
                // The cubes' faces, less those between two cubes of the block (seen twice).
                let mut faces: Vec<Vec<u32>> = Vec::new();
                for c in &cubes {
                    for f in CellType::Hexahedron.faces() {
                        faces.push(f.iter().map(|&k| c[k as usize]).collect());
                    }
                }
                let key = |f: &Vec<u32>| {
                    let mut s = f.clone();
                    s.sort_unstable();
                    s
                };
                let outer: Vec<&[u32]> = faces
                    .iter()
                    .filter(|f| faces.iter().filter(|g| key(g) == key(f)).count() == 1)
                    .map(|f| f.as_slice())
                    .collect();
                assert_eq!(outer.len(), 16);
                d.push_polyhedron(&outer, 0);
            }
        }
    }
    d
}

/// Quads of an n² grid (n a multiple of 4) where every other pair of quads along x is one
/// hexagon (its middle vertices on its long sides).
fn polygonal(n: usize) -> MeshData {
    let mut d = grid(2, n);
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        let mut i = 0;
        while i < n {
            if (i / 2 + j) % 2 == 0 {
                let hexagon = [id(i, j), id(i + 1, j), id(i + 2, j), id(i + 2, j + 1), id(i + 1, j + 1), id(i, j + 1)];
                d.push_cell(CellType::Polygon, &hexagon, 0);
            } else {
                for a in [i, i + 1] {
                    d.push_cell(CellType::Quad, &[id(a, j), id(a + 1, j), id(a + 1, j + 1), id(a, j + 1)], 0);
                }
            }
            i += 2;
        }
    }
    d
}

fn linear(p: &[f64]) -> [f64; 3] {
    let z = p.get(2).copied().unwrap_or(0.0);
    [
        0.01 + 0.05 * p[0] - 0.02 * p[1] + 0.03 * z,
        -0.03 + 0.04 * p[0] + 0.06 * p[1] - 0.01 * z,
        0.02 - 0.03 * p[0] + 0.01 * p[1] + 0.05 * z,
    ]
}

fn wavy(p: &[f64]) -> [f64; 3] {
    let w = std::f64::consts::TAU * p[0];
    let z = p.get(2).copied().unwrap_or(0.5);
    [0.02 * w.sin() + 0.01 * z * z, 0.05 * w.cos() * p[1], 0.03 * (w * z).sin()]
}

/// Solves with the whole boundary (patch 0) prescribed by `field`, `kind` for every component,
/// coarsening to a few dozen unknowns or fewer.
fn run(mesh: &Mesh, method: Method, kind: Kind, field: fn(&[f64]) -> [f64; 3]) -> (Solver, Vec<f64>) {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(0, kind);
    let mut o = Options { method, ..Default::default() };
    o.solve.tol = 1e-13;
    o.hierarchy.coarsen.coarsest_unknowns = Some(20);
    let s = Solver::new(mesh, &bcs, o).unwrap();
    let dim = mesh.dim();
    let mut motion = Motion::zero(mesh);
    for v in 0..mesh.num_vertices() {
        motion.displacement[dim * v..dim * v + dim].copy_from_slice(&field(mesh.point(v))[..dim]);
    }
    let sol = s.solve(&motion).unwrap();
    assert_eq!(sol.quality.inverted, 0);
    (s, sol.displacement)
}

fn meshes() -> Vec<(&'static str, Mesh)> {
    let p = Mesh::from_data(&polyhedral(8)).unwrap();
    let g = Mesh::from_data(&polygonal(12)).unwrap();
    let count = |m: &Mesh, t| m.cell_types().iter().filter(|&&x| x == t).count();
    assert!(count(&p, CellType::Polyhedron) >= 15 && count(&p, CellType::Hexahedron) >= 100);
    assert!(count(&g, CellType::Polygon) >= 30 && count(&g, CellType::Quad) >= 60);
    vec![("polyhedra", p), ("polygons", g)]
}

#[test]
fn general_cells_reproduce_linear_fields() {
    for (name, m) in meshes() {
        for method in [Method::Biharmonic, Method::Laplacian] {
            let (_, d) = run(&m, method, Kind::Fixed, linear);
            let (d, dim) = (&d, m.dim());
            let err = (0..m.num_vertices())
                .flat_map(|v| {
                    let u = linear(m.point(v));
                    (0..dim).map(move |c| (d[dim * v + c] - u[c]).abs())
                })
                .fold(0.0f64, f64::max);
            assert!(err < 1e-12, "{name} {method:?}: {err:e}");
        }
    }
}

#[test]
fn general_cells_match_a_direct_solve() {
    for (name, m) in meshes() {
        for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
            for bc in [Kind::Fixed, Kind::Clamped] {
                let (s, d) = run(&m, method, bc, wavy);
                assert!(s.hierarchy().levels.len() >= 3, "{name}: {} levels", s.hierarchy().levels.len());
                for c in 0..m.dim() {
                    let mg = at_dofs(&s, &d, c);
                    let direct = direct_solve(&s, c, &mg);
                    let scale = direct.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    let err = mg.iter().zip(&direct).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                    assert!(scale > 1e-3 && err <= 1e-10 * scale, "{name} {method:?} {bc:?} {c}: {err:e}");
                }
            }
        }
    }
}

/// The mesh's faces as a finite-volume code stores them: each face once, outward from its
/// owner (the lower cell), boundary faces on their patch.
fn faces_of(mesh: &Mesh) -> FaceMeshData {
    let mut all: Vec<(Vec<u32>, usize, Vec<u32>)> = Vec::new();
    for c in 0..mesh.num_cells() {
        let t = mesh.cell(c);
        let faces: Vec<Vec<u32>> = match mesh.cell_type(c) {
            CellType::Polyhedron => mesh.polyhedron_faces(c).map(|f| f.to_vec()).collect(),
            CellType::Polygon => (0..t.len()).map(|k| vec![t[k], t[(k + 1) % t.len()]]).collect(),
            ty => ty.faces().iter().map(|f| f.iter().map(|&k| t[k as usize]).collect()).collect(),
        };
        for f in faces {
            let mut key = f.clone();
            key.sort_unstable();
            all.push((key, c, f));
        }
    }
    all.sort();
    let patch_of = |key: &[u32]| {
        mesh.patch_faces()
            .find(|p| {
                let mut k = p.vertices.to_vec();
                k.sort_unstable();
                k == key
            })
            .map(|p| p.patch)
    };
    let mut d =
        FaceMeshData { dim: mesh.dim(), coords: mesh.coords().to_vec(), face_offsets: vec![0], ..Default::default() };
    let mut i = 0;
    while i < all.len() {
        let shared = i + 1 < all.len() && all[i + 1].0 == all[i].0;
        d.face_vertices.extend_from_slice(&all[i].2);
        d.face_offsets.push(d.face_vertices.len() as u32);
        d.owner.push(all[i].1 as i64);
        d.neighbour.push(if shared { all[i + 1].1 as i64 } else { -1 });
        d.patch.push(if shared { -1 } else { patch_of(&all[i].0).unwrap() });
        i += 1 + usize::from(shared);
    }
    d
}

/// Hexahedra of an n³ grid, or its cubes cut into six tetrahedra each; patches by side.
fn solid(n: usize, tets: bool) -> MeshData {
    let mut d = grid(3, n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = cube(n, i, j, k);
                if tets {
                    for path in [[1, 2], [2, 3], [3, 7], [7, 4], [4, 5], [5, 1]] {
                        d.push_cell(CellType::Tetra, &[c[0], c[path[0]], c[path[1]], c[6]], 0);
                    }
                } else {
                    d.push_cell(CellType::Hexahedron, &c, 0);
                }
            }
        }
    }
    // The x = 0 side on patch 1 (its faces as the cells list them).
    let m = Mesh::from_data(&d).unwrap();
    for f in m.patch_faces() {
        if f.vertices.iter().all(|&v| m.point(v as usize)[0] == 0.0) {
            d.push_face(f.vertices, 1);
        }
    }
    d
}

/// Hexahedra and tetrahedra given by their faces are recognised, in the corner order of the
/// grid's cells (hexahedra) or its canonical order (tetrahedra: the same cells), and move
/// bitwise as the meshes given by their cells.
#[test]
fn face_based_meshes_move_as_cell_based_ones() {
    for tets in [false, true] {
        let cells = Mesh::from_data(&solid(4, tets)).unwrap();
        let faces = faces_of(&cells).to_mesh().unwrap();
        let want = if tets { CellType::Tetra } else { CellType::Hexahedron };
        assert!(faces.cell_types().iter().all(|&t| t == want));
        let same_sets = (0..cells.num_cells()).all(|c| {
            let (mut a, mut b) = (cells.cell(c).to_vec(), faces.cell(c).to_vec());
            a.sort_unstable();
            b.sort_unstable();
            a == b
        });
        assert!(same_sets, "tets {tets}: cells differ");
        // Hexahedra come back in the grid's order; the tetrahedra's corners are re-ordered, so
        // the cell-based mesh to compare with lists them in that order.
        let reference = if tets { Mesh::from_data(&faces.to_data()).unwrap() } else { cells.clone() };
        assert_eq!(faces.to_data(), reference.to_data());
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(0, Kind::Fixed).set_kinds(1, Kind::Clamped);
        for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
            let o = Options { method, ..Default::default() };
            let solve = |m: &Mesh| {
                let s = Solver::new(m, &bcs, o.clone()).unwrap();
                let mut motion = Motion::zero(m);
                for v in 0..m.num_vertices() {
                    motion.displacement[3 * v..3 * v + 3].copy_from_slice(&wavy(m.point(v)));
                }
                s.solve(&motion).unwrap().displacement
            };
            let (a, b) = (solve(&reference), solve(&faces));
            assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()), "tets {tets} {method:?}");
        }
    }
}

/// The polyhedral and polygonal meshes given by their faces are the same meshes.
#[test]
fn general_cells_from_faces() {
    for (name, m) in meshes() {
        let f = Mesh::from_faces(&faces_of(&m)).unwrap();
        assert_eq!(f.cell_types(), m.cell_types(), "{name}");
        assert_eq!(f.num_patch_faces(), m.num_patch_faces(), "{name}");
        let v0 = meshmove::mesh::signed_measures(&m, m.coords());
        let v1 = meshmove::mesh::signed_measures(&f, f.coords());
        assert!(v0.iter().zip(&v1).all(|(a, b)| (a - b).abs() < 1e-15), "{name}");
    }
}

#[test]
fn broken_polyhedra_and_faces_are_refused() {
    // A polyhedron with a face left out is open.
    let mut d = polyhedral(6);
    let first = d.cell_types.iter().position(|&t| t == CellType::Polyhedron).unwrap();
    let nf = d.polyhedron_faces[0] as usize;
    assert_eq!(nf, 16);
    d.polyhedron_faces[0] = 15;
    d.polyhedron_faces.drain(1..6);
    assert!(matches!(Mesh::from_data(&d), Err(MeshError::OpenCell { cell, .. }) if cell == first));
    // One of its faces turned inside out.
    let mut d = polyhedral(6);
    d.polyhedron_faces[2..6].reverse();
    assert!(matches!(Mesh::from_data(&d), Err(MeshError::OpenCell { cell, .. }) if cell == first));
    // The unit cube as one polyhedron, a corner pushed in through the cell: its volume stays
    // positive, a sub-tetrahedron turns over.
    let mut d = MeshData::new(3);
    for p in [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [0.2, 0.2, 0.2],
        [0., 1., 1.],
    ] {
        d.push_vertex(&p);
    }
    let c = [0u32, 1, 2, 3, 4, 5, 6, 7];
    let faces: Vec<Vec<u32>> =
        CellType::Hexahedron.faces().iter().map(|f| f.iter().map(|&k| c[k as usize]).collect()).collect();
    d.push_polyhedron(&faces.iter().map(|f| f.as_slice()).collect::<Vec<_>>(), 0);
    let e = Mesh::from_data(&d).unwrap_err();
    assert_eq!(e, MeshError::InvertedCorner { cell: 0, cell_type: CellType::Polyhedron });
    assert!(
        meshmove::mesh::signed_measures(
            &Mesh::from_data(&{
                let mut ok = d.clone();
                ok.coords[18..21].copy_from_slice(&[1.0, 1.0, 1.0]);
                ok
            })
            .unwrap(),
            &d.coords
        )[0] > 0.0
    );

    let hexes = Mesh::from_data(&solid(2, false)).unwrap();
    let good = faces_of(&hexes);
    let mut f = good.clone();
    f.owner[3] = 99;
    assert!(matches!(f.to_mesh(), Err(MeshError::FaceArrays { .. })));
    let mut f = good.clone();
    f.owner[3] = -2;
    assert!(matches!(f.to_mesh(), Err(MeshError::FaceIndexOutOfRange { face: 3, what: "owner", .. })));
    let mut f = good.clone();
    let b = f.neighbour.iter().position(|&n| n < 0).unwrap();
    f.patch[b] = -1;
    assert_eq!(f.to_mesh().unwrap_err(), MeshError::BoundaryFaceWithoutPatch { face: b, patch: -1 });
    let mut f = good.clone();
    f.face_vertices.drain(2..4);
    f.face_offsets[1..].iter_mut().for_each(|o| *o -= 2);
    assert_eq!(f.to_mesh().unwrap_err(), MeshError::FaceSize { face: 0, count: 2, dim: 3 });
    // A face dropped: its cells are open.
    let mut f = good.clone();
    let n0 = f.face_offsets[1];
    f.face_vertices.drain(..n0 as usize);
    f.face_offsets.remove(0);
    f.face_offsets.iter_mut().for_each(|o| *o -= n0);
    let owner = f.owner.remove(0) as usize;
    f.neighbour.remove(0);
    f.patch.remove(0);
    assert!(matches!(f.to_mesh(), Err(MeshError::OpenCell { cell, .. }) if cell == owner));
}

/// Polyhedra (VTK type 42 with `faces` and `faceoffsets`) and polygons (type 7) round-trip
/// through `.vtu` bit for bit in every encoding; the deformed mesh's fields cover them; VTK
/// itself reads them where Python's `vtk` module is installed.
#[test]
fn general_cells_round_trip_through_vtu() {
    use meshmove::io::{read_vtu, write_deformed_data, write_vtu_as, VtuEncoding};
    let dir = std::env::temp_dir().join(format!("meshmove_general_cells_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, m) in meshes() {
        let d = m.to_data();
        for enc in [VtuEncoding::Binary, VtuEncoding::Compressed, VtuEncoding::Ascii] {
            let path = dir.join(format!("{name}_{enc:?}.vtu"));
            write_vtu_as(&path, &d, &[], &[], enc).unwrap();
            let back = read_vtu(&path).unwrap();
            assert_eq!(back.mesh, d, "{name} {enc:?}");
            assert_eq!(back.to_mesh().unwrap().to_data(), d, "{name} {enc:?}");
        }
        let path = dir.join(format!("{name}_deformed.vtu"));
        write_deformed_data(&path, &d, &vec![0.0; d.coords.len()]).unwrap();
        let back = read_vtu(&path).unwrap();
        let field = |f: &str| back.cell_data.iter().find(|c| c.0 == f).unwrap().1.clone();
        let ratio = field(if m.dim() == 2 { "area_ratio" } else { "volume_ratio" });
        assert!(ratio.iter().all(|&r| r == 1.0) && field("inverted").iter().all(|&i| i == 0.0), "{name}");
        let python = ["python3", "/usr/bin/python3"].into_iter().find(|p| {
            std::process::Command::new(p).args(["-c", "import vtk"]).output().is_ok_and(|o| o.status.success())
        });
        let Some(python) = python else {
            eprintln!("skipped: no Python with the vtk module");
            continue;
        };
        let script = "import sys, vtk\n\
            r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update()\n\
            g = r.GetOutput()\n\
            print(g.GetNumberOfPoints(), sum(1 for c in range(g.GetNumberOfCells()) if g.GetCellType(c) in (7, 42)))\n";
        let out = std::process::Command::new(python).args(["-c", script]).arg(&path).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let general = d.cell_types.iter().filter(|t| t.is_general()).count();
        assert_eq!(String::from_utf8_lossy(&out.stdout), format!("{} {general}\n", d.num_vertices()));
    }
}
