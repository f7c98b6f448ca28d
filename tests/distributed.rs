//! The distributed mesh and the first distributed solve (the `mpi` feature). Run by
//! `cargo test --features mpi --test distributed`: the test starts itself under `mpirun` on 1,
//! 2, 3 and 4 ranks (each run under a time limit, so a rank left waiting fails the test instead
//! of hanging it); each rank partitions the mesh into slabs by x and into hashed blocks, checks
//! its part of the distributed Laplacian solve (PCG with the distributed multigrid) against the
//! serial solver, and checks that bad input on one rank makes every rank return the error naming
//! that rank. The launching process then compares the runs: the multigrid's iterations and
//! level sizes do not depend on the rank count or the partition. Then each method (Laplacian,
//! spring, biharmonic) with each set of conditions (every patch FIXED; a CLAMPED body moving
//! rigidly and the rest FIXED; a FREE side) on a 2D and a 3D mesh equals the serial solver, with
//! the same quality report, and bad conditions or motions on one rank fail on every rank. SLIP
//! walls: a quarter annulus (2D) and a quarter cylindrical shell (3D) whose inner curved wall,
//! straight side and (3D) ends slide, put back on the curved wall from its faces or its
//! closest-point function, equal the serial solver for the three methods.

mod slabs;

use meshmove::distributed::{DistErrorKind, DistSolveParams, DistributedMesh, DistributedSolver};
use meshmove::{
    BoundaryConditions, Kind, Link, Mesh, MeshData, Method, Motion, Options, RigidMotion, SlipSurface, Solver,
};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use slabs::{block_owner, box3d, grid2d, motion, part, slab_owner, tagged, Part, BODY, SIDE};
use std::collections::BTreeMap;
use std::process::{Command, ExitCode};

fn main() -> ExitCode {
    if std::env::var_os("OMPI_COMM_WORLD_SIZE").is_some() || std::env::var_os("PMI_SIZE").is_some() {
        return rank_main();
    }
    let exe = std::env::current_exe().expect("the test's own path");
    let mut ok = true;
    // Per mesh and partition: the iterations and level sizes each rank count reported.
    let mut runs: BTreeMap<String, Vec<(usize, String, String)>> = BTreeMap::new();
    for np in 1..=4 {
        let out = Command::new("timeout")
            .args(["300", "mpirun", "--oversubscribe", "-np", &np.to_string()])
            .arg(&exe)
            .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
            .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
            .output()
            .expect("mpirun (openmpi-bin) and timeout on PATH");
        let stdout = String::from_utf8_lossy(&out.stdout);
        print!("{stdout}");
        for line in stdout.lines().filter_map(|l| l.strip_prefix("multigrid: ")) {
            let f: Vec<&str> = line.split(" | ").collect();
            runs.entry(f[0].to_string()).or_default().push((np, f[1].to_string(), f[2].to_string()));
        }
        if !out.status.success() {
            eprint!("{}", String::from_utf8_lossy(&out.stderr));
            eprintln!("FAILED on {np} ranks: {}", out.status);
            ok = false;
        }
    }
    ok &= same_multigrid_on_every_rank_count(&runs);
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// Every rank count and partition built the same levels, and took the same iterations as one
/// rank within one.
fn same_multigrid_on_every_rank_count(runs: &BTreeMap<String, Vec<(usize, String, String)>>) -> bool {
    let mut ok = !runs.is_empty();
    for (mesh, list) in runs {
        let (_, iters1, levels1) = &list[0];
        let first: Vec<i64> = numbers(iters1);
        for (np, iters, levels) in list {
            let close = numbers(iters).iter().zip(&first).all(|(a, b)| (a - b).abs() <= 1);
            if levels != levels1 || !close {
                eprintln!("{mesh} on {np} ranks: iterations {iters} levels {levels}, on 1 rank {iters1} {levels1}");
                ok = false;
            }
        }
        println!("{mesh}: {} rank counts, iterations {iters1}, levels {levels1}", list.len());
    }
    ok
}

/// The integers of a printed list such as "[5, 6]".
fn numbers(s: &str) -> Vec<i64> {
    s.split(|c: char| !c.is_ascii_digit()).filter(|t| !t.is_empty()).filter_map(|t| t.parse().ok()).collect()
}

/// One rank: every check, in the same order on every rank (they are collective).
fn rank_main() -> ExitCode {
    let universe = mpi::initialize().expect("MPI initialises once");
    let world = universe.world();
    let meshes =
        [("2D triangles", grid2d(40, 32)), ("3D hexahedra", box3d(16, false)), ("3D tetrahedra", box3d(12, true))];
    let size = world.size() as usize;
    for (name, mesh) in &meshes {
        agrees_with_serial(&world, &format!("{name}, slabs"), mesh, &slab_owner(mesh, size));
        agrees_with_serial(&world, &format!("{name}, hashed blocks"), mesh, &block_owner(mesh, size));
    }
    bad_input_fails_on_every_rank(&world, &meshes[0].1);
    bad_input_fails_on_every_rank(&world, &meshes[1].1);
    for (name, mesh) in [("2D triangles", tagged(&grid2d(14, 12))), ("3D hexahedra", tagged(&box3d(5, false)))] {
        for method in [Method::Laplacian, Method::Spring, Method::Biharmonic] {
            for case in [Case::AllFixed, Case::ClampedBody, Case::FreeSide] {
                let unscaled = (mesh.clone(), vec![1.0; mesh.num_vertices()]);
                solver_agrees_with_serial(&world, name, &unscaled, method, case);
            }
        }
    }
    for (name, flat) in [("2D quarter annulus", grid2d(10, 16)), ("3D quarter shell", box3d(5, false))] {
        for method in [Method::Laplacian, Method::Spring, Method::Biharmonic] {
            for surface in [false, true] {
                solver_agrees_with_serial(&world, name, &bent(&flat), method, Case::Slip { surface });
            }
        }
    }
    bad_conditions_fail_on_every_rank(&world, &tagged(&grid2d(14, 12)));
    failing_wall_fails_on_every_rank(&world, &bent(&grid2d(10, 16)));
    for (name, d) in [("2D periodic triangles", grid2d(16, 10)), ("3D periodic hexahedra", box3d(5, false))] {
        for method in [Method::Laplacian, Method::Spring, Method::Biharmonic] {
            solver_agrees_with_serial(&world, name, &periodic(&d), method, Case::Periodic);
        }
    }
    advance_moves_the_reference(&world, &grid2d(14, 12));
    ExitCode::SUCCESS
}

/// The distributed Laplacian solve on the partition `owner` equals the serial one to 1e-10 of
/// the motion (both to a relative residual of 1e-12), is bitwise the same on a second run and a
/// second mesh with the same levels, and takes far fewer iterations than with one level.
fn agrees_with_serial(world: &SimpleCommunicator, name: &str, d: &MeshData, owner: &[usize]) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let dim = d.dim;
    let all: Vec<f64> = (0..d.num_vertices()).flat_map(|v| motion(d.point(v))[..dim].to_vec()).collect();
    let mut o = Options { method: Method::Laplacian, threads: 1, ..Default::default() };
    o.solve.tol = 1e-12;
    let serial = Solver::new(&Mesh::from_data(d).unwrap(), &BoundaryConditions::new(), o).unwrap();
    let reference = serial.solve(&Motion::from_displacement(all.clone())).unwrap();
    let scale = all.iter().fold(0.0f64, |m, x| m.max(x.abs()));

    let p = part(d, owner, rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    assert_eq!(dm.num_global_vertices(), d.num_vertices() as u64, "{name}");
    let owned = dm.owner_ranks().iter().filter(|&&o| o == rank).count();
    assert_eq!(owned, dm.num_owned_vertices());
    let boundary: Vec<f64> = p.global.iter().flat_map(|&v| all[v * dim..(v + 1) * dim].to_vec()).collect();
    let params = DistSolveParams { tol: 1e-12, ..Default::default() };
    let sol = dm.solve_laplacian(&boundary, &params).unwrap();
    let mut worst = 0.0f64;
    for (i, &v) in p.global.iter().enumerate() {
        for c in 0..dim {
            worst = worst.max((sol.displacement[i * dim + c] - reference.displacement[v * dim + c]).abs());
        }
    }
    assert!(worst <= 1e-10 * scale, "{name} on {size} ranks: rank {rank} differs by {worst:e} (motion {scale:e})");
    assert!(sol.rel_residual <= 1e-12, "{name}: {}", sol.rel_residual);
    // The global numbering: every number below the total, each owned one once over all ranks.
    let numbers = dm.global_numbers();
    assert!(numbers.iter().all(|&g| g < dm.num_global_vertices()));
    let again = dm.solve_laplacian(&boundary, &params).unwrap();
    let bits = |s: &[f64]| s.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&sol.displacement), bits(&again.displacement), "{name}: a second solve differs");
    let dm2 = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    let third = dm2.solve_laplacian(&boundary, &params).unwrap();
    assert_eq!(bits(&sol.displacement), bits(&third.displacement), "{name}: a second mesh differs");
    assert_eq!(sol.level_rows, again.level_rows, "{name}: a second solve's levels differ");
    assert_eq!(sol.level_rows, third.level_rows, "{name}: a second mesh's levels differ");
    assert!(sol.level_rows.len() >= 2 && sol.coarsest_gathered, "{name}: levels {:?}", sol.level_rows);
    let one = dm.solve_laplacian(&boundary, &DistSolveParams { max_levels: 1, ..params }).unwrap();
    for (mg, one) in sol.iterations.iter().zip(&one.iterations) {
        assert!(*mg <= 15 && 3 * mg <= 2 * one, "{name}: {mg} iterations with the multigrid, {one} with one level");
    }
    if rank == 0 {
        println!(
            "{size} ranks, {name}: {} vertices, iterations {:?} (one level {:?}; serial {} cycles), largest \
             difference {:.1e} of the motion",
            d.num_vertices(),
            sol.iterations,
            one.iterations,
            reference.report.cycles,
            worst / scale
        );
        println!("multigrid: {name} | {:?} | {:?}", sol.iterations, sol.level_rows);
    }
}

/// One rank's bad input makes every rank return the error naming that rank.
fn bad_input_fails_on_every_rank(world: &SimpleCommunicator, d: &MeshData) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let owner = slab_owner(d, size);
    let last = size - 1;
    let expect = |what: &str, p: &Part, bad: usize, kind: DistErrorKind| {
        let e =
            DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).err().unwrap_or_else(|| panic!("{what}: accepted"));
        assert_eq!((e.rank, e.kind), (bad, kind), "{what} on rank {rank}: {e}");
        assert!(e.message.contains("global id"), "{what}: the error names no global id: {e}");
        if rank == 0 {
            println!("{size} ranks, {what}: every rank returns \"{e}\"");
        }
    };
    // A NaN coordinate on the last rank.
    let mut p = part(d, &owner, rank, true);
    if rank == last {
        p.data.coords[0] = f64::NAN;
    }
    expect("a NaN coordinate", &p, last, DistErrorKind::LocalMesh);
    // A tangled cell on the last rank: two corners of its first owned cell swapped.
    let mut p = part(d, &owner, rank, true);
    if rank == last {
        let c = p.ghost.iter().position(|g| !g).unwrap();
        let at = p.data.cell_offsets[c] as usize;
        p.data.cell_vertices.swap(at + 1, at + 2);
    }
    expect("a tangled cell", &p, last, DistErrorKind::LocalMesh);
    // Two global ids given twice on the last rank.
    let mut p = part(d, &owner, rank, true);
    if rank == last {
        p.gids[1] = p.gids[0];
    }
    expect("a global id twice on one rank", &p, last, DistErrorKind::Inconsistent);
    // A NaN boundary value on the last rank fails the solve on every rank.
    let p = part(d, &owner, rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    let nan = if rank == last { f64::NAN } else { 0.0 };
    let e = dm.solve_laplacian(&vec![nan; p.data.coords.len()], &DistSolveParams::default()).unwrap_err();
    assert_eq!((e.rank, e.kind), (last, DistErrorKind::Input), "{e}");
    if size < 2 {
        return;
    }
    // Two vertices the last rank shares with the rank before it, their global ids swapped: each
    // is then where its owner does not have it.
    let mut p = part(d, &owner, rank, true);
    if rank == last {
        let mut shared_with_prev = vec![false; d.num_vertices()];
        (0..d.num_cells())
            .filter(|&c| owner[c] < last)
            .for_each(|c| d.cell(c).iter().for_each(|&v| shared_with_prev[v as usize] = true));
        let mine: Vec<usize> = (0..p.data.num_cells())
            .filter(|&c| !p.ghost[c])
            .flat_map(|c| p.data.cell(c).to_vec())
            .map(|v| v as usize)
            .filter(|&v| shared_with_prev[p.global[v]])
            .collect();
        let a = mine[0];
        let b = *mine.iter().find(|&&v| v != a).unwrap();
        p.gids.swap(a, b);
    }
    expect("swapped global ids", &p, last, DistErrorKind::Inconsistent);
    // Rank 0 without ghost cells: it owns the vertices it shares with rank 1 but lacks rank 1's
    // cells around them.
    let p = part(d, &owner, rank, rank != 0);
    expect("no ghost layer", &p, 0, DistErrorKind::MissingGhostCell);
}

/// The patch of the ends z = 0 and z = 1 of a 3D mesh, SLIP in the slip case.
const ENDS: i32 = 3;

/// `d` (the unit square or cube, as `grid2d` and `box3d` make it) with its faces on x = 0
/// tagged `BODY`, on y = 0 `SIDE` and in 3D on z = 0 and z = 1 `ENDS`, then bent into a quarter
/// annulus (a quarter cylindrical shell): radius 1 + x, angle y π/2. Its first component keeps
/// the unbent x (zero on the inner wall): (bent, x).
fn bent(d: &MeshData) -> (MeshData, Vec<f64>) {
    let mesh = Mesh::from_data(d).expect("a valid mesh");
    let mut out = d.clone();
    for f in mesh.patch_faces() {
        let on = |c: usize, x: f64| f.vertices.iter().all(|&v| d.point(v as usize)[c] == x);
        let patch = if on(0, 0.0) {
            BODY
        } else if on(1, 0.0) {
            SIDE
        } else if d.dim == 3 && (on(2, 0.0) || on(2, 1.0)) {
            ENDS
        } else {
            continue;
        };
        out.push_face(f.vertices, patch);
    }
    let x: Vec<f64> = (0..d.num_vertices()).map(|v| d.point(v)[0]).collect();
    for v in 0..d.num_vertices() {
        let p = d.point(v);
        let (r, t) = (1.0 + p[0], p[1] * std::f64::consts::FRAC_PI_2);
        out.coords[v * d.dim] = r * t.cos();
        out.coords[v * d.dim + 1] = r * t.sin();
    }
    (out, x)
}

/// The periodic side x = 0, linked to `RIGHT`.
const LEFT: i32 = 4;
/// The periodic side x = 1.
const RIGHT: i32 = 5;

/// `d` (the unit square or cube) with its faces on x = 0 tagged `LEFT` and on x = 1 `RIGHT`,
/// the rest untagged; no motion scaled.
fn periodic(d: &MeshData) -> (MeshData, Vec<f64>) {
    let mesh = Mesh::from_data(d).expect("a valid mesh");
    let mut out = d.clone();
    for f in mesh.patch_faces() {
        let on = |x: f64| f.vertices.iter().all(|&v| d.point(v as usize)[0] == x);
        let patch = if on(0.0) {
            LEFT
        } else if on(1.0) {
            RIGHT
        } else {
            continue;
        };
        out.push_face(f.vertices, patch);
    }
    (out, vec![1.0; d.num_vertices()])
}

/// A boundary motion periodic in x (period 1).
fn motion_periodic(x: &[f64]) -> [f64; 3] {
    let (s, c) = (2.0 * std::f64::consts::PI * x[0]).sin_cos();
    let z = x.get(2).copied().unwrap_or(0.0);
    [0.06 * s * (1.0 + x[1]), 0.05 * c * (x[1] - 0.5) + 0.02 * z, 0.04 * (s + c) * x[1]]
}

/// The boundary conditions of a comparison.
#[derive(Clone, Copy, Debug)]
enum Case {
    /// Every patch FIXED, each vertex moved by `motion`.
    AllFixed,
    /// The body CLAMPED, moved rigidly (rotated and translated); the rest FIXED, moved by `motion`.
    ClampedBody,
    /// The side FREE; the rest FIXED, moved by `motion`.
    FreeSide,
    /// On a `bent` mesh the inner curved wall, the straight side and the ends SLIP, the curved
    /// wall given by its faces or (`surface`) as a cylinder; the rest FIXED. Every vertex moved
    /// by `motion` scaled by the unbent x, so the curved wall's normal parts are zero and its
    /// slipped vertices are put back on it.
    Slip { surface: bool },
    /// On a `periodic` mesh the sides x = 0 and x = 1 FREE and linked by the offset 1 in x;
    /// the rest FIXED, moved by `motion_periodic`.
    Periodic,
}

impl Case {
    fn conditions(self, dim: usize) -> BoundaryConditions {
        let mut bcs = BoundaryConditions::new();
        match self {
            Case::AllFixed => {}
            Case::ClampedBody => {
                bcs.set_kinds(BODY, Kind::Clamped);
            }
            Case::FreeSide => {
                bcs.set_kinds(SIDE, Kind::Free);
            }
            Case::Periodic => {
                bcs.set_kinds(LEFT, Kind::Free).set_kinds(RIGHT, Kind::Free);
                bcs.add_link(Link::ByOffset { a: LEFT, b: RIGHT, offset: [1.0, 0.0, 0.0], tol: 1e-9 });
            }
            Case::Slip { surface } => {
                bcs.set_kinds(BODY, Kind::Slip).set_kinds(SIDE, Kind::Slip);
                if dim == 3 {
                    bcs.set_kinds(ENDS, Kind::Slip);
                }
                if surface {
                    bcs.set_slip_surface(BODY, SlipSurface::cylinder([0.0; 3], [0.0, 0.0, 1.0], 1.0));
                }
            }
        }
        bcs
    }

    fn rigid(self) -> Vec<(i32, RigidMotion)> {
        match self {
            Case::ClampedBody => vec![(
                BODY,
                RigidMotion { translation: [0.02, -0.01, 0.01], rotation: [0.0, 0.0, 0.05], center: [0.0, 0.5, 0.5] },
            )],
            _ => Vec::new(),
        }
    }
}

/// The distributed solver equals the serial one to 1e-10 of the motion (both to a relative
/// residual of 1e-12), with the same inverted count and smallest area ratio.
/// On a `bent` mesh (given with its unbent x) every vertex's motion is scaled by that x.
fn solver_agrees_with_serial(
    world: &SimpleCommunicator,
    name: &str,
    (d, scaled): &(MeshData, Vec<f64>),
    method: Method,
    case: Case,
) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let dim = d.dim;
    let moved = |x: &[f64]| if let Case::Periodic = case { motion_periodic(x) } else { motion(x) };
    let all: Vec<f64> = (0..d.num_vertices())
        .flat_map(|v| moved(d.point(v))[..dim].iter().map(|m| m * scaled[v]).collect::<Vec<_>>())
        .collect();
    let bcs = case.conditions(dim);
    let mut o = Options { method, threads: 1, ..Default::default() };
    o.solve.tol = 1e-12;
    let serial = Solver::new(&Mesh::from_data(d).unwrap(), &bcs, o).unwrap();
    let reference = serial.solve(&Motion { displacement: all.clone(), rigid: case.rigid() }).unwrap();
    let scale = reference.displacement.iter().fold(0.0f64, |m, x| m.max(x.abs()));

    let p = part(d, &slab_owner(d, size), rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    let params = DistSolveParams { tol: 1e-12, ..Default::default() };
    let solver = DistributedSolver::new(&dm, &bcs, method, params).unwrap();
    let local: Vec<f64> = p.global.iter().flat_map(|&v| all[v * dim..(v + 1) * dim].to_vec()).collect();
    let sol = solver.solve(&Motion { displacement: local, rigid: case.rigid() }).unwrap();
    let mut worst = 0.0f64;
    for (i, &v) in p.global.iter().enumerate() {
        for c in 0..dim {
            worst = worst.max((sol.displacement[i * dim + c] - reference.displacement[v * dim + c]).abs());
        }
    }
    let what = format!("{name}, {method:?}, {case:?} on {size} ranks");
    assert!(worst <= 1e-10 * scale, "{what}: rank {rank} differs by {worst:e} (motion {scale:e})");
    assert!(sol.rel_residual <= 1e-12, "{what}: {}", sol.rel_residual);
    let (q, r) = (sol.quality, reference.quality);
    assert_eq!((q.inverted, q.non_positive_measure), (r.inverted, r.non_positive_measure), "{what}");
    for (a, b) in [
        (q.min_area_ratio, r.min_area_ratio),
        (q.max_area_ratio, r.max_area_ratio),
        (q.min_corner_jacobian_ratio, r.min_corner_jacobian_ratio),
        (q.min_angle_deg, r.min_angle_deg),
    ] {
        assert!((a - b).abs() <= 1e-8 * b.abs().max(1.0), "{what}: quality {q:?} against serial {r:?}");
    }
    // Every rank has the same report.
    let mut reports = vec![0.0; 2 * size];
    world.all_gather_into(&[q.min_area_ratio, sol.worst_rank as f64][..], &mut reports[..]);
    assert!(reports.chunks(2).all(|x| x == &reports[..2]), "{what}: the ranks' reports differ");
    if rank == 0 {
        println!(
            "{size} ranks, {what}: iterations {:?} (serial {} cycles), largest difference {:.1e} of the motion, \
             min ratio {:.6} on rank {}",
            sol.iterations,
            reference.report.cycles,
            worst / scale,
            q.min_area_ratio,
            sol.worst_rank
        );
    }
}

/// Conditions the distributed solver does not take, or a bad motion, on the last rank alone
/// make every rank return the error naming that rank.
fn bad_conditions_fail_on_every_rank(world: &SimpleCommunicator, d: &MeshData) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let last = size - 1;
    let p = part(d, &slab_owner(d, size), rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    // A patch SLIP in one component only, on the last rank.
    let mut bcs = BoundaryConditions::new();
    if rank == last {
        bcs.set_kind(0, 1, Kind::Slip).unwrap();
    }
    let e = DistributedSolver::new(&dm, &bcs, Method::Biharmonic, DistSolveParams::default()).unwrap_err();
    assert_eq!((e.rank, e.kind), (last, DistErrorKind::Input), "{e}");
    assert!(e.message.contains("SLIP"), "{e}");
    // Conditions that differ between ranks: a SLIP patch on the last rank alone.
    if size > 1 {
        let mut bcs = BoundaryConditions::new();
        if rank == last {
            bcs.set_kinds(0, Kind::Slip);
        }
        let e = DistributedSolver::new(&dm, &bcs, Method::Biharmonic, DistSolveParams::default()).unwrap_err();
        assert_eq!((e.rank, e.kind), (last, DistErrorKind::Input), "{e}");
        assert!(e.message.contains("differ from rank 0"), "{e}");
    }
    // A link whose patches do not match vertex by vertex (the far field has more vertices than
    // the body's side): refused on every rank, naming a global id.
    let mut linked = BoundaryConditions::new();
    linked.add_link(Link::ByOffset { a: BODY, b: 0, offset: [1.0, 0.0, 0.0], tol: 1e-9 });
    let e = DistributedSolver::new(&dm, &linked, Method::Laplacian, DistSolveParams::default()).unwrap_err();
    assert!(
        e.kind == DistErrorKind::Input && e.message.contains("link 1 -> 0") && e.message.contains("global id"),
        "{e}"
    );
    // Explicit pairs name local vertices: refused.
    let mut pairs = BoundaryConditions::new();
    pairs.add_link(Link::Pairs(vec![[0, 1]]));
    let e = DistributedSolver::new(&dm, &pairs, Method::Laplacian, DistSolveParams::default()).unwrap_err();
    assert!(e.kind == DistErrorKind::Input && e.message.contains("vertex pairs"), "{e}");
    // No component prescribed anywhere: every patch FREE.
    let mut free = BoundaryConditions::new();
    free.default_kind = [Kind::Free; 3];
    let e = DistributedSolver::new(&dm, &free, Method::Laplacian, DistSolveParams::default()).unwrap_err();
    assert_eq!(e.kind, DistErrorKind::Input, "{e}");
    let solver =
        DistributedSolver::new(&dm, &BoundaryConditions::new(), Method::Biharmonic, DistSolveParams::default())
            .unwrap();
    let mut m = Motion::from_displacement(vec![0.0; p.data.coords.len()]);
    if rank == last {
        m.displacement.pop();
    }
    let e = solver.solve(&m).unwrap_err();
    assert_eq!((e.rank, e.kind), (last, DistErrorKind::Input), "{e}");
    if rank == 0 {
        println!("{size} ranks, bad conditions and motions on the last rank: every rank returns the error");
    }
}

/// `advance` makes the moved positions the reference; a motion that inverts cells is refused on
/// every rank, naming the rank of the worst cell, and changes nothing.
fn advance_moves_the_reference(world: &SimpleCommunicator, d: &MeshData) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let p = part(d, &slab_owner(d, size), rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    let params = DistSolveParams { tol: 1e-12, ..Default::default() };
    let mut solver = DistributedSolver::new(&dm, &BoundaryConditions::new(), Method::Laplacian, params).unwrap();
    let local: Vec<f64> = p.global.iter().flat_map(|&v| motion(d.point(v))[..2].to_vec()).collect();
    let before = solver.current_coords();
    assert_eq!(before, p.data.coords, "the reference starts at the host's positions");
    let sol = solver.advance(&Motion::from_displacement(local.clone())).unwrap();
    let after = solver.current_coords();
    let moved: Vec<f64> = before.iter().zip(&sol.displacement).map(|(x, d)| x + d).collect();
    assert_eq!(after, moved, "the reference is the moved mesh");
    let big: Vec<f64> = local.iter().map(|x| 50.0 * x).collect();
    let e = solver.advance(&Motion::from_displacement(big)).unwrap_err();
    assert_eq!(e.kind, DistErrorKind::Inverted, "{e}");
    assert_eq!(solver.current_coords(), after, "a refused step changes nothing");
    let mut ranks = vec![0u64; size];
    world.all_gather_into(&(e.rank as u64), &mut ranks[..]);
    assert!(ranks.iter().all(|&r| r == ranks[0]), "the ranks blame different ranks: {ranks:?}");
    if rank == 0 {
        println!("{size} ranks, advance: the reference moves; an inverting step is refused: \"{e}\"");
    }
}

/// A curved wall's closest-point function that fails on the last rank alone makes every rank's
/// solve fail, naming that rank and a global id.
fn failing_wall_fails_on_every_rank(world: &SimpleCommunicator, (d, scaled): &(MeshData, Vec<f64>)) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let last = size - 1;
    let p = part(d, &slab_owner(d, size), rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    let mut bcs = Case::Slip { surface: true }.conditions(2);
    if rank == last {
        bcs.set_slip_surface(BODY, SlipSurface::fallible(|_| None));
    }
    let solver = DistributedSolver::new(&dm, &bcs, Method::Laplacian, DistSolveParams::default()).unwrap();
    let local: Vec<f64> = p
        .global
        .iter()
        .flat_map(|&v| motion(d.point(v))[..2].iter().map(|m| m * scaled[v]).collect::<Vec<_>>())
        .collect();
    let e = solver.solve(&Motion::from_displacement(local)).unwrap_err();
    assert_eq!((e.rank, e.kind), (last, DistErrorKind::Input), "{e}");
    assert!(e.message.contains("closest-point") && e.message.contains("global id"), "{e}");
    if rank == 0 {
        println!("{size} ranks, a slip wall's function failing on the last rank: every rank returns \"{e}\"");
    }
}
