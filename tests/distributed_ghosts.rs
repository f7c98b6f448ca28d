//! The ghost layer the library completes (the `mpi` feature). Run by
//! `cargo test --features mpi --test distributed_ghosts`: the test starts itself under `mpirun`
//! on 1 to 4 ranks (each run under a time limit). Each rank's part is given with its layer of
//! ghost cells, without any, or (odd ranks) without: the distributed solves are bitwise the same
//! and equal the serial solver, after a step that moves the reference too. Polyhedral meshes
//! likewise, and a polyhedral mesh given face-based, each rank its own cells' faces alone.

mod slabs;

use meshmove::distributed::{DistSolveParams, DistributedMesh, DistributedSolver};
use meshmove::{BoundaryConditions, CellType, FaceMeshData, Mesh, MeshData, Method, Motion, Options, Solver};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use slabs::{block_owner, box3d, grid2d, motion, part, slab_owner};
use std::collections::HashMap;
use std::process::ExitCode;

fn main() -> ExitCode {
    if std::env::var_os("OMPI_COMM_WORLD_SIZE").is_some() || std::env::var_os("PMI_SIZE").is_some() {
        return rank_main();
    }
    let mut ok = true;
    for np in 1..=4 {
        let out = slabs::mpirun(np);
        print!("{}", String::from_utf8_lossy(&out.stdout));
        if !out.status.success() {
            eprint!("{}", String::from_utf8_lossy(&out.stderr));
            eprintln!("FAILED on {np} ranks: {}", out.status);
            ok = false;
        }
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

fn rank_main() -> ExitCode {
    let universe = mpi::initialize().expect("MPI initialises once");
    let world = universe.world();
    let size = world.size() as usize;
    let poly = polyhedral_box(5);
    let meshes = [
        ("2D triangles", grid2d(16, 12)),
        ("3D hexahedra", box3d(6, false)),
        ("3D tetrahedra", box3d(5, true)),
        ("3D polyhedra", poly.to_data().expect("a valid face mesh")),
    ];
    for (name, d) in &meshes {
        for (how, owner) in [("slabs", slab_owner(d, size)), ("hashed blocks", block_owner(d, size))] {
            for method in [Method::Laplacian, Method::Biharmonic] {
                with_and_without_ghosts(&world, &format!("{name}, {how}, {method:?}"), d, &owner, method);
            }
        }
    }
    for method in [Method::Laplacian, Method::Biharmonic] {
        face_based_parts(&world, &poly, method);
    }
    ExitCode::SUCCESS
}

/// The serial displacement of `d` (every boundary vertex FIXED, moved by `motion`, then a
/// second step of the same motion from the moved mesh), solved to 1e-12.
fn serial(d: &MeshData, method: Method) -> [Vec<f64>; 2] {
    let all: Vec<f64> = (0..d.num_vertices()).flat_map(|v| motion(d.point(v))[..d.dim].to_vec()).collect();
    let mut o = Options { method, threads: 1, ..Default::default() };
    o.solve.tol = 1e-12;
    let mut s = Solver::new(&Mesh::from_data(d).unwrap(), &BoundaryConditions::new(), o).unwrap();
    let first = s.solve(&Motion::from_displacement(all.clone())).unwrap().displacement;
    s.advance(&Motion::from_displacement(all.clone())).unwrap();
    let second = s.solve(&Motion::from_displacement(all)).unwrap().displacement;
    [first, second]
}

/// The distributed displacement of a rank's mesh `dm` (vertex `global[i]` of `d` at local i):
/// a solve, then a step that moves the reference, then the same solve from there.
fn distributed(dm: &DistributedMesh, d: &MeshData, global: &[usize], method: Method) -> [Vec<f64>; 2] {
    let dim = d.dim;
    let local: Vec<f64> = global.iter().flat_map(|&v| motion(d.point(v))[..dim].to_vec()).collect();
    let params = DistSolveParams { tol: 1e-12, ..Default::default() };
    let mut solver = DistributedSolver::new(dm, &BoundaryConditions::new(), method, params).unwrap();
    let first = solver.solve(&Motion::from_displacement(local.clone())).unwrap().displacement;
    solver.advance(&Motion::from_displacement(local.clone())).unwrap();
    let second = solver.solve(&Motion::from_displacement(local)).unwrap().displacement;
    [first, second]
}

/// The largest difference between a rank's displacement and the serial one, over the motion.
fn difference(dim: usize, global: &[usize], dist: &[Vec<f64>; 2], serial: &[Vec<f64>; 2]) -> f64 {
    let mut worst = 0.0f64;
    let scale = serial.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    for (a, b) in dist.iter().zip(serial) {
        for (i, &v) in global.iter().enumerate() {
            (0..dim).for_each(|c| worst = worst.max((a[i * dim + c] - b[v * dim + c]).abs()));
        }
    }
    worst / scale
}

/// Each rank's part given with its ghost layer, without any, and with only the even ranks'
/// ghosts: the same displacement to the bit on every vertex, equal to the serial one.
fn with_and_without_ghosts(world: &SimpleCommunicator, name: &str, d: &MeshData, owner: &[usize], method: Method) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let reference = serial(d, method);
    let mut by_vertex: Vec<HashMap<usize, [u64; 2]>> = Vec::new();
    for (k, ghosts) in [true, false, rank % 2 == 0].into_iter().enumerate() {
        let p = part(d, owner, rank, ghosts);
        let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
        assert_eq!(dm.num_local_vertices(), p.global.len(), "{name}");
        assert_eq!(dm.num_global_vertices(), d.num_vertices() as u64, "{name}");
        let out = distributed(&dm, d, &p.global, method);
        assert_eq!(out[0].len(), p.data.coords.len(), "{name}: one value per host vertex and component");
        let worst = difference(d.dim, &p.global, &out, &reference);
        assert!(worst <= 1e-10, "{name}, variant {k}, on {size} ranks: rank {rank} differs by {worst:e} of the motion");
        let mut mine = HashMap::new();
        for (i, &v) in p.global.iter().enumerate() {
            for c in 0..d.dim {
                let bits = [out[0][i * d.dim + c].to_bits(), out[1][i * d.dim + c].to_bits()];
                mine.insert(v * d.dim + c, bits);
            }
        }
        by_vertex.push(mine);
    }
    for (k, other) in by_vertex.iter().enumerate().skip(1) {
        for (key, bits) in other {
            assert_eq!(Some(bits), by_vertex[0].get(key), "{name}, variant {k} on {size} ranks: value {key} differs");
        }
    }
    if rank == 0 {
        println!("{size} ranks, {name}: with, without and with some ghost cells bitwise the same");
    }
}

/// A box of n³ hexahedra in which the face between cells (i, j, k) and (i + 1, j, k), i even, is
/// split into two triangles: both cells are polyhedra of seven faces. Faces with owner and
/// neighbour; boundary faces on patch 0.
fn polyhedral_box(n: usize) -> FaceMeshData {
    let d = box3d(n, false);
    let cell = |i: usize, j: usize, k: usize| ((k * n + j) * n + i) as i64;
    let mut f = FaceMeshData { dim: 3, coords: d.coords.clone(), face_offsets: vec![0], ..Default::default() };
    let push = |f: &mut FaceMeshData, v: &[u32], o: i64, nb: i64| {
        f.face_vertices.extend_from_slice(v);
        f.face_offsets.push(f.face_vertices.len() as u32);
        f.owner.push(o);
        f.neighbour.push(nb);
        f.patch.push(if nb < 0 { 0 } else { -1 });
    };
    let faces = CellType::Hexahedron.faces();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = cell(i, j, k);
                let corners = d.cell(c as usize);
                for (side, face) in faces.iter().enumerate() {
                    let v: Vec<u32> = face.iter().map(|&q| corners[q as usize]).collect();
                    // The neighbour across each face of the hexahedron: -z, +z, -y, +x, +y, -x.
                    let (di, dj, dk) = [(0, 0, -1), (0, 0, 1), (0, -1, 0), (1, 0, 0), (0, 1, 0), (-1, 0, 0)][side];
                    let (a, b, e) = (i as i64 + di, j as i64 + dj, k as i64 + dk);
                    let inside = [a, b, e].iter().all(|&x| (0..n as i64).contains(&x));
                    if !inside {
                        push(&mut f, &v, c, -1);
                        continue;
                    }
                    let nb = cell(a as usize, b as usize, e as usize);
                    if nb < c {
                        continue;
                    }
                    if di == 1 && i % 2 == 0 {
                        push(&mut f, &[v[0], v[1], v[2]], c, nb);
                        push(&mut f, &[v[0], v[2], v[3]], c, nb);
                    } else {
                        push(&mut f, &v, c, nb);
                    }
                }
            }
        }
    }
    f
}

/// Each rank gives its own cells' faces alone (a face to another rank's cell with that side and
/// its patch negative): the distributed solves equal the serial one on the whole face mesh.
fn face_based_parts(world: &SimpleCommunicator, faces: &FaceMeshData, method: Method) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let d = faces.to_data().unwrap();
    assert!(d.cell_types.iter().filter(|&&t| t == CellType::Polyhedron).count() >= d.num_cells() / 3);
    let owner = slab_owner(&d, size);
    let reference = serial(&d, method);
    let mut local_cell = HashMap::new();
    for c in (0..d.num_cells()).filter(|&c| owner[c] == rank) {
        let n = local_cell.len() as i64;
        local_cell.insert(c as i64, n);
    }
    let mut p = FaceMeshData { dim: 3, face_offsets: vec![0], ..Default::default() };
    let mut vertex_of = HashMap::new();
    let mut global = Vec::new();
    for f in 0..faces.num_faces() {
        let side = |c: i64| local_cell.get(&c).copied().unwrap_or(-1);
        let (o, n) = (side(faces.owner[f]), if faces.neighbour[f] < 0 { -1 } else { side(faces.neighbour[f]) });
        if o < 0 && n < 0 {
            continue;
        }
        for &v in faces.face(f) {
            let next = vertex_of.len() as u32;
            let l = *vertex_of.entry(v).or_insert_with(|| {
                global.push(v as usize);
                next
            });
            p.face_vertices.push(l);
        }
        p.face_offsets.push(p.face_vertices.len() as u32);
        p.owner.push(o);
        p.neighbour.push(n);
        p.patch.push(if o >= 0 && n >= 0 || faces.neighbour[f] >= 0 { -1 } else { faces.patch[f] });
    }
    p.coords = global.iter().flat_map(|&v| d.point(v).to_vec()).collect();
    let gids: Vec<u64> = global.iter().map(|&v| v as u64 + 1000).collect();
    let dm = DistributedMesh::from_faces(world, &p, &gids).unwrap();
    let out = distributed(&dm, &d, &global, method);
    let worst = difference(3, &global, &out, &reference);
    assert!(worst <= 1e-10, "face-based polyhedra, {method:?}, on {size} ranks: rank {rank} differs by {worst:e}");
    if rank == 0 {
        println!(
            "{size} ranks, face-based polyhedral parts without ghost cells, {method:?}: {} polyhedra, largest \
             difference {worst:.1e} of the motion",
            d.cell_types.iter().filter(|&&t| t == CellType::Polyhedron).count()
        );
    }
}
