//! The distributed mesh and the first distributed solve (the `mpi` feature). Run by
//! `cargo test --features mpi --test distributed`: the test starts itself under `mpirun` on 1,
//! 2, 3 and 4 ranks (each run under a time limit, so a rank left waiting fails the test instead
//! of hanging it); each rank partitions the mesh into slabs by x and into hashed blocks, checks
//! its part of the distributed Laplacian solve (PCG with the distributed multigrid) against the
//! serial solver, and checks that bad input on one rank makes every rank return the error naming
//! that rank. The launching process then compares the runs: the multigrid's iterations and
//! level sizes (and the biharmonic's prolongations, by a digest of their rows in global ids) do
//! not depend on the rank count or the partition. Then each method (Laplacian,
//! spring, biharmonic) with each set of conditions (every patch FIXED; a CLAMPED body moving
//! rigidly and the rest FIXED; a FREE side) on a 2D and a 3D mesh equals the serial solver, with
//! the same quality report (the biharmonic also on meshes large enough for its multigrid to
//! coarsen, and on the bench's CLAMPED-top box within one iteration of the serial cycles, its
//! hierarchy also made five levels deep by a smaller gathered level), a second solve reusing the
//! kept hierarchy gives bitwise the first, and bad conditions or motions on one rank fail on
//! every rank. SLIP walls: a quarter annulus (2D) and
//! a quarter cylindrical shell (3D) whose inner curved wall, straight side and (3D) ends slide,
//! put back on the curved wall from its faces or its closest-point function, equal the serial
//! solver for the three methods; so do periodic sides linked across ranks, alone and with a
//! wavy SLIP wall between them (the linked corners on the wall); these coupled groups take at
//! most one iteration more than the serial cycles, and so does a larger annulus whose multigrid
//! coarsens (a bound the components' projected cycles exceeded).
//! Then the steps (`move_in_steps`, `advance`, `advance_from`, sub-stepping) in both reference
//! modes, made with the serial `Options`, equal the serial solver's on a 2D and a 3D mesh; the
//! options the distributed solver does not take, positions with inverted cells and rank 0's
//! progress callback stop a call on every rank and change nothing.

mod slabs;

use meshmove::distributed::{DistErrorKind, DistSolveParams, DistStepReport, DistributedMesh, DistributedSolver};
use meshmove::{
    BoundaryConditions, Kind, Link, Mesh, MeshData, Method, Mode, Motion, Options, Progress, ReferenceMode,
    RigidMotion, SlipSurface, Solver, StepReport,
};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use slabs::{block_owner, box3d, grid2d, motion, part, slab_owner, tagged, Part, BODY, SIDE};
use std::collections::BTreeMap;
use std::process::ExitCode;

fn main() -> ExitCode {
    if std::env::var_os("OMPI_COMM_WORLD_SIZE").is_some() || std::env::var_os("PMI_SIZE").is_some() {
        return rank_main();
    }
    let mut ok = true;
    // Per mesh and partition: the iterations and level sizes each rank count reported.
    let mut runs: BTreeMap<String, Vec<(usize, String, String)>> = BTreeMap::new();
    for np in 1..=4 {
        let out = slabs::mpirun(np);
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
        agrees_with_serial(&world, &format!("{name}, boundary layers"), mesh, &layer_owner(mesh, size));
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
    // A quarter annulus large enough for the multigrid to coarsen: the coupled group's cycle
    // (one hierarchy of both components, the slip frames on every level) stays within one
    // iteration of the serial cycles, a bound the components' cycles projected exceeded
    // (docs/perf-history.md, "Slip walls across ranks: the counts before one hierarchy").
    for method in [Method::Laplacian, Method::Biharmonic] {
        let annulus = bent(&grid2d(30, 48));
        solver_agrees_with_serial(&world, "2D quarter annulus 31×49", &annulus, method, Case::Slip { surface: false });
    }
    // Meshes large enough for the biharmonic's multigrid to coarsen (the small ones above are
    // gathered at once).
    for (name, mesh) in [
        ("2D triangles 40×32", tagged(&grid2d(40, 32))),
        ("3D hexahedra 12³", tagged(&box3d(12, false))),
        ("3D tetrahedra 10³", tagged(&box3d(10, true))),
    ] {
        let unscaled = (mesh.clone(), vec![1.0; mesh.num_vertices()]);
        for case in [Case::AllFixed, Case::ClampedBody, Case::FreeSide] {
            solver_agrees_with_serial(&world, name, &unscaled, Method::Biharmonic, case);
        }
        biharmonic_agglomerated(&world, name, &mesh);
    }
    clamped_top_within_serial(&world, "box", &box3d(15, false), (DistSolveParams::default().gather_at_most, 3));
    let grid = on_grid(&box3d(15, false), 15);
    clamped_top_within_serial(&world, "box on its grid, deep", &grid, (DEEP_GATHER, DEEP));
    bad_conditions_fail_on_every_rank(&world, &tagged(&grid2d(14, 12)));
    failing_wall_fails_on_every_rank(&world, &bent(&grid2d(10, 16)));
    for (name, d) in [("2D periodic triangles", grid2d(16, 10)), ("3D periodic hexahedra", box3d(5, false))] {
        for method in [Method::Laplacian, Method::Spring, Method::Biharmonic] {
            solver_agrees_with_serial(&world, name, &periodic(&d), method, Case::Periodic);
            solver_agrees_with_serial(&world, name, &wavy_periodic(&d), method, Case::PeriodicSlip);
        }
    }
    advance_moves_the_reference(&world, &grid2d(14, 12));
    for (name, mesh) in [("2D triangles", tagged(&grid2d(14, 12))), ("3D hexahedra", tagged(&box3d(5, false)))] {
        for method in [Method::Laplacian, Method::Biharmonic] {
            for reference in [ReferenceMode::Incremental, ReferenceMode::Original] {
                steps_agree_with_serial(&world, name, &mesh, method, reference);
            }
        }
        substeps_agree_with_serial(&world, name, &mesh);
    }
    calls_stop_on_every_rank(&world, &tagged(&grid2d(14, 12)));
    host_messages_stay_the_hosts(&world, &tagged(&grid2d(14, 12)));
    slip_steps_agree_with_serial(&world, &bent(&grid2d(10, 16)));
    ExitCode::SUCCESS
}

/// The distributed Laplacian solve on the partition `owner` equals the serial one to 1e-10 of
/// the motion (both to a relative residual of 1e-12), is bitwise the same on a second run and a
/// second mesh with the same levels, and takes no more iterations than the serial cycles (its
/// levels interpolate by the serial donor rule) and far fewer than with one level.
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
    let cycles = reference.report.cycles;
    for (mg, one) in sol.iterations.iter().zip(&one.iterations) {
        let what = format!("{name}: {mg} iterations with the multigrid, {one} with one level, {cycles} serial cycles");
        assert!(*mg <= cycles && 3 * mg <= 2 * one, "{what}");
    }
    // The default threshold (200 unknowns per rank) moves the first coarse level onto two of
    // three or four ranks; 0 keeps every level on every rank, 1 000 moves it onto one. All equal
    // serial, with the same levels and the iterations of the solve without agglomeration within
    // one.
    let expected: Vec<u64> = sol.level_rows.iter().enumerate().map(|(l, _)| halved_ranks(size, l)).collect();
    assert_eq!(sol.level_ranks, expected, "{name}: ranks per level");
    assert_eq!(expected, ranks_by_rule(&sol.level_rows, size, 200), "{name}: ranks per level");
    let flat = dm.solve_laplacian(&boundary, &DistSolveParams { agglomerate_below: 0, ..params }).unwrap();
    assert!(flat.level_ranks.iter().all(|&r| r == size as u64), "{name}: {:?}", flat.level_ranks);
    let onto_one = dm.solve_laplacian(&boundary, &DistSolveParams { agglomerate_below: 1000, ..params }).unwrap();
    assert!(onto_one.level_ranks[1..].iter().all(|&r| r == 1), "{name}: {:?}", onto_one.level_ranks);
    for other in [&sol, &flat, &onto_one] {
        assert_eq!(other.level_rows, sol.level_rows, "{name}: agglomeration changed the levels");
        let close = other.iterations.iter().zip(&flat.iterations).all(|(a, b)| a.abs_diff(*b) <= 1);
        assert!(close, "{name}: iterations {:?} against {:?} without agglomeration", other.iterations, flat.iterations);
        let worst = largest_difference(&p, dim, &other.displacement, &reference.displacement);
        assert!(worst <= 1e-10 * scale, "{name} on {size} ranks: agglomerated, rank {rank} differs by {worst:e}");
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
        println!("multigrid: {name} | {:?} | {:?} {:?}", sol.iterations, sol.level_rows, sol.level_transfers);
        println!(
            "{size} ranks, {name}: ranks per level {:?} by default, {:?} below 1 000 per rank (iterations {:?}, \
             without agglomeration {:?}); halo values per exchange {:?}, {:?}, without {:?}",
            sol.level_ranks,
            onto_one.level_ranks,
            onto_one.iterations,
            flat.iterations,
            sol.level_halo_values,
            onto_one.level_halo_values,
            flat.level_halo_values
        );
    }
}

/// The ranks of each level of the test meshes (the first coarse level has 451–582 unknowns, the
/// next at most 400, gathered) with 200 unknowns per rank: two of three or four ranks hold the
/// first coarse level; the gathered level is held by the ranks of the level above.
fn halved_ranks(size: usize, level: usize) -> u64 {
    match (size, level) {
        (_, 0) | (1 | 2, _) => size as u64,
        _ => 2,
    }
}

/// A partition in which the last rank (on two ranks and more) and the one before it (on three
/// and more) own only the cells touching the largest and smallest x, so the vertices they own
/// lie on the boundary: prescribed in the Laplacian's test, they own no unknown on any level.
/// The other cells go in slabs by x to the other ranks.
fn layer_owner(d: &MeshData, size: usize) -> Vec<usize> {
    let xs: Vec<f64> = (0..d.num_vertices()).map(|v| d.point(v)[0]).collect();
    let (lo, hi) = xs.iter().fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    let layers = size.saturating_sub(1).min(2);
    let slabs = slab_owner(d, size - layers);
    (0..d.num_cells())
        .map(|c| {
            let cell = d.cell(c);
            if layers >= 1 && cell.iter().any(|&v| xs[v as usize] == hi) {
                size - 1
            } else if layers == 2 && cell.iter().any(|&v| xs[v as usize] == lo) {
                size - 2
            } else {
                slabs[c]
            }
        })
        .collect()
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
    // The faces of y = 0 on the last rank's ghost cells tagged with another patch than their
    // owner's: each part is valid alone, and the ranks disagree on the conditions there.
    let t = tagged(d);
    let on_ghost = |p: &Part, f: usize| {
        let face = p.data.face(f);
        (0..p.data.num_cells()).any(|c| p.ghost[c] && face.iter().all(|v| p.data.cell(c).contains(v)))
    };
    let mut p = part(&t, &owner, rank, true);
    if rank == last {
        let retag: Vec<usize> =
            (0..p.data.num_faces()).filter(|&f| p.data.face_patch[f] == SIDE && on_ghost(&p, f)).collect();
        assert!(!retag.is_empty(), "the last rank's ghost cells have faces on y = 0");
        retag.into_iter().for_each(|f| p.data.face_patch[f] = SIDE + 5);
    }
    expect("a face tagged otherwise on a ghost copy than by its owner", &p, last, DistErrorKind::Inconsistent);
    // The rank before the last gives its part untagged: the last rank's ghost copies of its
    // cells on y = 0 carry tags their owner does not have (the lowest rank holding such ghost
    // copies is named: the last one's left neighbour on three ranks and more).
    let mut p = part(&t, &owner, rank, true);
    if rank + 1 == last {
        let untagged = MeshData { face_vertices: Vec::new(), face_offsets: vec![0], face_patch: Vec::new(), ..p.data };
        p.data = untagged;
    }
    let blamed = if size > 2 { last - 2 } else { last };
    expect("a face tagged on a ghost copy and not by its owner", &p, blamed, DistErrorKind::Inconsistent);
    // Rank 0 without ghost cells: the library fetches rank 1's cells around the vertices it owns.
    let p = part(d, &owner, rank, rank != 0);
    assert!(DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).is_ok(), "a part without ghost cells");
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

/// `periodic(d)` with its side y = 0 tagged `SIDE` and made a wave y = 0.1 sin 2πx (each
/// vertex raised by 0.1 sin 2πx (1 − y)), so the wall's normals are no coordinate axes and
/// couple the components, and the linked corners on it have the wall's two sides' faces at
/// them. Its second component keeps the flat y (zero on the wave): (wavy, y).
fn wavy_periodic(d: &MeshData) -> (MeshData, Vec<f64>) {
    let (mut out, _) = periodic(d);
    let mesh = Mesh::from_data(d).expect("a valid mesh");
    for f in mesh.patch_faces() {
        if f.vertices.iter().all(|&v| d.point(v as usize)[1] == 0.0) {
            out.push_face(f.vertices, SIDE);
        }
    }
    let y: Vec<f64> = (0..d.num_vertices()).map(|v| d.point(v)[1]).collect();
    for (v, &y) in y.iter().enumerate() {
        let x = d.point(v)[0];
        out.coords[v * d.dim + 1] += 0.1 * (2.0 * std::f64::consts::PI * x).sin() * (1.0 - y);
    }
    (out, y)
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
    /// On a `wavy_periodic` mesh the periodic case with the wave y = 0 SLIP, the motion scaled
    /// by the flat y, so the wave's normal parts are zero and its slipped vertices are put back
    /// on its faces.
    PeriodicSlip,
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
            Case::Periodic | Case::PeriodicSlip => {
                bcs.set_kinds(LEFT, Kind::Free).set_kinds(RIGHT, Kind::Free);
                bcs.add_link(Link::ByOffset { a: LEFT, b: RIGHT, offset: [1.0, 0.0, 0.0], tol: 1e-9 });
                if let Case::PeriodicSlip = self {
                    bcs.set_kinds(SIDE, Kind::Slip);
                }
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
    let periodic_motion = matches!(case, Case::Periodic | Case::PeriodicSlip);
    let moved = |x: &[f64]| if periodic_motion { motion_periodic(x) } else { motion(x) };
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
    let motion = Motion { displacement: local, rigid: case.rigid() };
    let sol = solver.solve(&motion).unwrap();
    // A second solve reuses the kept hierarchy and gives bitwise the same answer.
    let again = solver.solve(&motion).unwrap();
    assert_eq!((&again.displacement, &again.iterations), (&sol.displacement, &sol.iterations));
    let mut worst = 0.0f64;
    for (i, &v) in p.global.iter().enumerate() {
        for c in 0..dim {
            worst = worst.max((sol.displacement[i * dim + c] - reference.displacement[v * dim + c]).abs());
        }
    }
    let what = format!("{name}, {method:?}, {case:?} on {size} ranks, levels {:?}", sol.level_rows);
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
    // The biharmonic's multigrid across ranks stays within two iterations of the serial cycles
    // (its levels interpolate by the serial donor rule and keep the CLAMPED vertices with S free,
    // as the serial levels do), and within 12 iterations where the serial hierarchy is its dense
    // coarsest level alone. A group coupled by slip walls or periodic links on a mesh this small
    // is solved whole on one rank with its coupling (`CoupledSolve`, docs/DESIGN.md §5 "Slip
    // walls across ranks"): at most one iteration more than the serial cycles (one per solve; the
    // curved walls' two added).
    let coupled = matches!(case, Case::Slip { .. } | Case::Periodic | Case::PeriodicSlip);
    let serial = reference.report.cycles;
    let bound = match (coupled, method) {
        (true, _) if d.num_vertices() <= 400 => Some(serial + 1),
        // A larger slip-walled group: one hierarchy of every component whose levels carry the
        // slip frames, as the serial levels do (docs/DESIGN.md §5 "Slip walls across ranks").
        (true, _) if matches!(case, Case::Slip { .. }) => Some(serial + 1),
        (true, Method::Laplacian) => Some(3 * serial / 2),
        (true, _) => Some(3 * serial),
        (false, Method::Biharmonic) => Some((serial + 2).max(12)),
        (false, _) => None,
    };
    if let Some(bound) = bound {
        assert!(sol.iterations.iter().all(|&i| i <= bound), "{what}: iterations {:?} above {bound}", sol.iterations);
    }
    // Every method's levels and their prolongations (digests of P's rows in global ids) are the
    // same on every rank count: the launching process compares these lines.
    let slip = matches!(case, Case::Slip { .. } | Case::PeriodicSlip);
    if !slip && sol.level_rows.len() >= 2 && rank == 0 {
        println!(
            "multigrid: {name}, {method:?}, {case:?} | {:?} | {:?} {:?}",
            sol.iterations, sol.level_rows, sol.level_transfers
        );
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

/// The biharmonic's levels K_c V_c⁻¹ K_c agglomerated onto fewer ranks (below 1 000 unknowns
/// per rank and below the default threshold, with the guide K_c and V_c moved along): the levels
/// are on the ranks the rule gives, and the result equals the one without agglomeration to
/// 1e-10 of the motion, with the same levels and iterations within one; a second solver gives
/// bitwise the same.
fn biharmonic_agglomerated(world: &SimpleCommunicator, name: &str, d: &MeshData) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let dim = d.dim;
    let p = part(d, &slab_owner(d, size), rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    let bcs = Case::ClampedBody.conditions(dim);
    let local: Vec<f64> = p.global.iter().flat_map(|&v| motion(d.point(v))[..dim].to_vec()).collect();
    let moved = Motion { displacement: local, rigid: Case::ClampedBody.rigid() };
    let solve = |below: u64| {
        let params = DistSolveParams { tol: 1e-12, agglomerate_below: below, ..Default::default() };
        DistributedSolver::new(&dm, &bcs, Method::Biharmonic, params).unwrap().solve(&moved).unwrap()
    };
    let (flat, onto_one, default) = (solve(0), solve(1000), solve(DistSolveParams::default().agglomerate_below));
    let scale = flat.displacement.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let what = format!("{name}, biharmonic on {size} ranks: levels {:?}", flat.level_rows);
    assert!(flat.level_rows.len() >= 2 && flat.level_ranks.iter().all(|&r| r == size as u64), "{what}");
    assert_eq!(onto_one.level_ranks, ranks_by_rule(&flat.level_rows, size, 1000), "{what}");
    let below = DistSolveParams::default().agglomerate_below;
    assert_eq!(default.level_ranks, ranks_by_rule(&flat.level_rows, size, below), "{what}");
    for other in [&onto_one, &default] {
        assert_eq!(other.level_rows, flat.level_rows, "{what}");
        let worst = other.displacement.iter().zip(&flat.displacement).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(worst <= 1e-10 * scale, "{what}: agglomerated, rank {rank} differs by {worst:e}");
        let close = other.iterations.iter().zip(&flat.iterations).all(|(a, b)| a.abs_diff(*b) <= 1);
        assert!(close, "{what}: iterations {:?} against {:?}", other.iterations, flat.iterations);
    }
    let bits = |s: &[f64]| s.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&solve(1000).displacement), bits(&onto_one.displacement), "{what}: a second solver differs");
    if rank == 0 {
        println!(
            "{size} ranks, {name}, biharmonic: ranks per level {:?} below 1 000 per rank, {:?} by default; iterations \
             {:?}, {:?}, without agglomeration {:?}",
            onto_one.level_ranks, default.level_ranks, onto_one.iterations, default.iterations, flat.iterations
        );
    }
}

/// The bench's box (`meshmove bench`, docs/PERFORMANCE.md): the top z = 1 CLAMPED and moved by
/// 0.1 cos 2πx cos 2πy in z, the bottom FIXED, the sides' normal component FIXED and the others
/// FREE (`name` says which box `d` is). The distributed biharmonic, its level of at most
/// `gather` unknowns gathered (`depth` levels), equals the serial solver to 1e-10 of the motion
/// and takes at most one iteration more than the serial cycles: its coarse levels keep the
/// CLAMPED vertices with S free, as the serial levels do (docs/DESIGN.md §5, "The biharmonic's
/// levels"), where levels without them took half as many again, and below the first two coarse
/// levels they are the Galerkin product, which holds the count at any depth.
fn clamped_top_within_serial(world: &SimpleCommunicator, name: &str, d: &MeshData, (gather, depth): (u64, usize)) {
    const TOP: i32 = 6;
    const BOTTOM: i32 = 7;
    // The sides x = const and y = const.
    const SIDES: [(i32, usize); 2] = [(8, 0), (9, 1)];
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let mesh = Mesh::from_data(d).expect("a valid mesh");
    let mut tagged = d.clone();
    for f in mesh.patch_faces() {
        let on = |c: usize, x: f64| f.vertices.iter().all(|&v| d.point(v as usize)[c] == x);
        let patch = match (0..3).find(|&c| on(c, 0.0) || on(c, 1.0)) {
            Some(2) if on(2, 1.0) => TOP,
            Some(2) => BOTTOM,
            Some(c) => SIDES[c].0,
            None => continue,
        };
        tagged.push_face(f.vertices, patch);
    }
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BOTTOM, Kind::Fixed).set_kinds(TOP, Kind::Clamped);
    for (p, normal) in SIDES {
        for c in 0..3 {
            bcs.set_kind(p, c, if c == normal { Kind::Fixed } else { Kind::Free }).unwrap();
        }
    }
    let tau = std::f64::consts::TAU;
    let all: Vec<f64> = (0..d.num_vertices())
        .flat_map(|v| {
            let x = d.point(v);
            let dz = if x[2] == 1.0 { 0.1 * (tau * x[0]).cos() * (tau * x[1]).cos() } else { 0.0 };
            [0.0, 0.0, dz]
        })
        .collect();
    let mut o = Options { method: Method::Biharmonic, threads: 1, ..Default::default() };
    o.solve.tol = 1e-12;
    let serial = Solver::new(&Mesh::from_data(&tagged).unwrap(), &bcs, o).unwrap();
    let reference = serial.solve(&Motion::from_displacement(all.clone())).unwrap();
    let scale = reference.displacement.iter().fold(0.0f64, |m, x| m.max(x.abs()));

    let p = part(&tagged, &slab_owner(&tagged, size), rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    let cycles = reference.report.cycles;
    let params = DistSolveParams { tol: 1e-12, gather_at_most: gather, ..Default::default() };
    let solver = DistributedSolver::new(&dm, &bcs, Method::Biharmonic, params).unwrap();
    let sol = solver.solve(&Motion::from_displacement(local_of(&p, 3, &all))).unwrap();
    let worst = largest_difference(&p, 3, &sol.displacement, &reference.displacement);
    let what = format!("CLAMPED-top {name} on {size} ranks: iterations {:?}, serial {cycles} cycles", sol.iterations);
    assert!(worst <= 1e-10 * scale, "{what}: rank {rank} differs by {worst:e} (motion {scale:e})");
    assert!(sol.level_rows.len() == depth && sol.coarsest_gathered, "{what}: levels {:?}", sol.level_rows);
    assert!(sol.iterations[2] <= cycles + 1, "{what}");
    if rank == 0 {
        println!("{size} ranks, {what}, levels {:?}", sol.level_rows);
        let (iterations, rows, transfers) = (&sol.iterations, &sol.level_rows, &sol.level_transfers);
        println!("multigrid: CLAMPED-top {name} | {iterations:?} | {rows:?} {transfers:?}");
    }
}

/// The gathered level's size that makes the CLAMPED-top box on its grid `DEEP` levels deep, as
/// deep as the bench's box of 250k vertices is with the default. With K_c V_c⁻¹ K_c on every
/// coarse level (not only the first two) that hierarchy exceeds the bound on one rank: its deep
/// levels' corrections overshoot next to the CLAMPED wall (docs/DESIGN.md §5, "The biharmonic's
/// levels"; the counts in docs/perf-history.md, "The distributed biharmonic next to a CLAMPED wall").
const DEEP_GATHER: u64 = 30;
/// Levels of the CLAMPED-top box's deep hierarchy.
const DEEP: usize = 5;

/// `d` with every vertex put back on the grid of `n` cells a side (the jitter of `box3d`, less
/// than half a cell, undone).
fn on_grid(d: &MeshData, n: usize) -> MeshData {
    let mut grid = d.clone();
    grid.coords.iter_mut().for_each(|x| *x = (*x * n as f64).round() / n as f64);
    grid
}

/// The ranks of each level of `rows` unknowns on `size` ranks agglomerated below `per_rank`
/// unknowns per rank: the finest on every rank; a coarse level of more than 400 unknowns (one of
/// fewer is gathered from the ranks of the level above) on ranks onto_one until each holds
/// `per_rank` or one rank is left.
fn ranks_by_rule(rows: &[u64], size: usize, per_rank: u64) -> Vec<u64> {
    let mut ranks = size as u64;
    let mut out = vec![ranks];
    for &r in &rows[1..] {
        while r > 400 && ranks > 1 && r < per_rank * ranks {
            ranks = (ranks - 1) / 2 + 1;
        }
        out.push(ranks);
    }
    out
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
    // Explicit pairs name global ids: ids no rank has are refused.
    let mut pairs = BoundaryConditions::new();
    pairs.add_link(Link::Pairs(vec![[0, 1]]));
    let e = DistributedSolver::new(&dm, &pairs, Method::Laplacian, DistSolveParams::default()).unwrap_err();
    assert!(e.kind == DistErrorKind::Input && e.message.contains("global id 0, which no rank has"), "{e}");
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
    let off = after.iter().zip(&moved).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(off <= 1e-15, "the reference is the moved mesh: {off:e} away");
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

/// The serial options of a comparison: `method` to a relative residual of 1e-12, one thread.
fn options(method: Method, reference: ReferenceMode) -> Options {
    let mut o = Options { method, threads: 1, reference, ..Default::default() };
    o.solve.tol = 1e-12;
    // The biharmonic's distributed solve is preconditioned by its smoother alone.
    o.solve.max_cycles = 5000;
    o
}

/// A serial field of `dim` values per vertex on the local vertices of `p`.
fn local_of(p: &Part, dim: usize, all: &[f64]) -> Vec<f64> {
    p.global.iter().flat_map(|&v| all[v * dim..(v + 1) * dim].to_vec()).collect()
}

/// The largest difference between the local field `dist` and the serial field `serial`.
fn largest_difference(p: &Part, dim: usize, dist: &[f64], serial: &[f64]) -> f64 {
    local_of(p, dim, serial).iter().zip(dist).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
}

/// The same sub-steps (numbers, fractions, accepted or not, inverted counts) and, to 1e-8,
/// the same smallest ratios.
fn same_reports(what: &str, serial: &[StepReport], dist: &[DistStepReport]) {
    let key = |r: &StepReport| (r.step, r.substep, r.fraction.to_bits(), r.accepted, r.inverted, r.converged);
    let s: Vec<_> = serial.iter().map(key).collect();
    let d: Vec<_> = dist.iter().map(|r| key(&r.report)).collect();
    assert_eq!(s, d, "{what}: the step reports differ");
    for (a, b) in serial.iter().zip(dist) {
        let (a, b) = (a.min_volume_ratio, b.report.min_volume_ratio);
        assert!((a - b).abs() <= 1e-8 * a.abs().max(1.0), "{what}: min ratio {b} against serial {a}");
    }
}

/// `move_in_steps`, then `advance`, then `advance_from` positions the host moved itself, made
/// with the serial options, equal the serial calls to 1e-10 of the motion, with the same step
/// reports.
fn steps_agree_with_serial(
    world: &SimpleCommunicator,
    name: &str,
    d: &MeshData,
    method: Method,
    reference: ReferenceMode,
) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let dim = d.dim;
    // A quarter of the comparisons' motions: the clamped side turning against the moving ones
    // inverts cells near their corners under the whole of them, repeated.
    let all: Vec<f64> = (0..d.num_vertices())
        .flat_map(|v| motion(d.point(v))[..dim].iter().map(|x| 0.25 * x).collect::<Vec<_>>())
        .collect();
    let bcs = Case::ClampedBody.conditions(dim);
    let rigid: Vec<(i32, RigidMotion)> =
        Case::ClampedBody.rigid().iter().map(|&(p, m)| (p, m.between(0.0, 0.25))).collect();
    let o = options(method, reference);
    let mut serial = Solver::new(&Mesh::from_data(d).unwrap(), &bcs, o.clone()).unwrap();
    let p = part(d, &slab_owner(d, size), rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    let mut dist = DistributedSolver::with_options(&dm, &bcs, o).unwrap();
    let what = format!("{name}, {method:?}, {reference:?} on {size} ranks");
    let whole = |d: &[f64]| Motion { displacement: d.to_vec(), rigid: rigid.clone() };
    let local = |d: &[f64]| Motion { displacement: local_of(&p, dim, d), rigid: rigid.clone() };

    let sr = serial.move_in_steps(&whole(&all), 3).unwrap();
    let dr = dist.move_in_steps(&local(&all), 3).unwrap();
    let scale = serial.total_displacement().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let off = largest_difference(&p, dim, &dist.current_coords(), serial.current_coords());
    assert!(off <= 1e-10 * scale, "{what}: move_in_steps: rank {rank} differs by {off:e} (motion {scale:e})");
    assert_eq!(sr.len(), 3, "{what}");
    same_reports(&format!("{what}, move_in_steps"), &sr, &dr);
    assert_eq!(dist.step_reports(), &dr[..], "{what}");

    let half: Vec<f64> = all.iter().map(|x| 0.5 * x).collect();
    let sa = serial.advance(&whole(&half)).unwrap();
    let da = dist.advance(&local(&half)).unwrap();
    let off = largest_difference(&p, dim, &da.displacement, &sa.displacement);
    assert!(off <= 1e-10 * scale, "{what}: advance: rank {rank} differs by {off:e}");
    assert_eq!(da.quality.inverted, sa.quality.inverted, "{what}");
    let (a, b) = (sa.quality.min_area_ratio, da.quality.min_area_ratio);
    assert!((a - b).abs() <= 1e-8, "{what}: advance: min ratio {b} against serial {a}");

    // The host moves every vertex a little itself, then asks for the next step from there.
    let moved: Vec<f64> = serial
        .current_coords()
        .chunks(dim)
        .flat_map(|x| {
            let m = motion(x);
            (0..dim).map(move |c| x[c] + 0.05 * m[(c + 1) % dim]).collect::<Vec<_>>()
        })
        .collect();
    let sf = serial.advance_from(&moved, &whole(&half)).unwrap();
    let df = dist.advance_from(&local_of(&p, dim, &moved), &local(&half)).unwrap();
    let off = largest_difference(&p, dim, &df.displacement, &sf.displacement);
    let at = largest_difference(&p, dim, &dist.current_coords(), serial.current_coords());
    assert!(off.max(at) <= 1e-10 * scale, "{what}: advance_from: rank {rank} differs by {off:e}, positions {at:e}");
    if rank == 0 {
        println!(
            "{size} ranks, {what}: move_in_steps, advance and advance_from equal the serial calls (iterations per step \
             {:?}, serial {:?})",
            dr.iter().map(|r| r.report.cycles).collect::<Vec<_>>(),
            sr.iter().map(|r| r.cycles).collect::<Vec<_>>()
        );
    }
}

/// Sub-stepping takes the serial solver's sub-steps: a step whose smallest area ratio falls
/// below the options' minimum is split in halves, with the same reports and the same result.
fn substeps_agree_with_serial(world: &SimpleCommunicator, name: &str, d: &MeshData) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let dim = d.dim;
    let big: Vec<f64> = (0..d.num_vertices())
        .flat_map(|v| motion(d.point(v))[..dim].iter().map(|x| 3.0 * x).collect::<Vec<_>>())
        .collect();
    let bcs = BoundaryConditions::new();
    let mesh = Mesh::from_data(d).unwrap();
    // The minimum ratio halfway between the whole step's and half of it's, from the mesh.
    let probe = Solver::new(&mesh, &bcs, options(Method::Laplacian, ReferenceMode::Incremental)).unwrap();
    let ratio = |f: f64| {
        let m = Motion::from_displacement(big.iter().map(|x| f * x).collect());
        probe.solve(&m).unwrap().quality.min_area_ratio
    };
    let (whole, half) = (ratio(1.0), ratio(0.5));
    assert!(half > whole, "{name}: half the motion ({half}) is no better than all of it ({whole})");
    let mut o = options(Method::Laplacian, ReferenceMode::Incremental);
    (o.max_substeps, o.min_volume_ratio) = (8, 0.5 * (whole + half));
    let mut serial = Solver::new(&mesh, &bcs, o.clone()).unwrap();
    let p = part(d, &slab_owner(d, size), rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    let mut dist = DistributedSolver::with_options(&dm, &bcs, o).unwrap();
    let what = format!("{name}, sub-steps on {size} ranks");
    // Both reach the end, or both stop at the limit of sub-steps at the same place.
    let sr = serial.move_in_steps(&Motion::from_displacement(big.clone()), 1);
    let dr = dist.move_in_steps(&Motion::from_displacement(local_of(&p, dim, &big)), 1);
    assert_eq!(sr.is_ok(), dr.is_ok(), "{what}: serial {sr:?}, distributed {dr:?}");
    let (sr, dr) = (serial.step_reports(), dist.step_reports());
    assert!(sr.iter().any(|r| !r.accepted), "{what}: no sub-step was rejected");
    same_reports(&what, sr, dr);
    let scale = big.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let off = largest_difference(&p, dim, &dist.current_coords(), serial.current_coords());
    assert!(off <= 1e-10 * scale, "{what}: rank {rank} differs by {off:e}");
    if rank == 0 {
        let fractions: Vec<String> = dr
            .iter()
            .map(|r| format!("{:.3}{}", r.report.fraction, if r.report.accepted { "" } else { " rejected" }))
            .collect();
        println!("{size} ranks, {what}: the serial sub-steps [{}]", fractions.join(", "));
    }
}

/// Options the distributed solver does not take (on the last rank alone), positions with
/// inverted cells and rank 0's progress callback stop a call on every rank; a stopped call
/// changes nothing.
fn calls_stop_on_every_rank(world: &SimpleCommunicator, d: &MeshData) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let last = size - 1;
    let p = part(d, &slab_owner(d, size), rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    let bcs = BoundaryConditions::new();
    let mut o = options(Method::Laplacian, ReferenceMode::Incremental);
    if rank == last {
        o.solve.mode = Mode::PaperFaithful;
    }
    let e = DistributedSolver::with_options(&dm, &bcs, o).unwrap_err();
    assert_eq!((e.rank, e.kind), (last, DistErrorKind::Input), "{e}");
    assert!(e.message.contains("paper-faithful"), "{e}");

    let mut o = options(Method::Laplacian, ReferenceMode::Incremental);
    o.progress = Some(Progress::new(|r, _| r.step < 2));
    let mut solver = DistributedSolver::with_options(&dm, &bcs, o).unwrap();
    let dim = d.dim;
    let all: Vec<f64> = p.data.coords.chunks(dim).flat_map(|x| motion(x)[..dim].to_vec()).collect();
    let before = solver.current_coords();
    let e = solver.move_in_steps(&Motion::from_displacement(all.clone()), 3).unwrap_err();
    assert_eq!((e.rank, e.kind), (0, DistErrorKind::Cancelled), "{e}");
    assert_eq!(solver.current_coords(), before, "a cancelled call changes nothing");
    assert_eq!(solver.step_reports().len(), 2, "the reports say how far it got");

    // Every position mirrored: every cell inverted, rank 0 the first to say so.
    let mirrored: Vec<f64> =
        p.data.coords.iter().enumerate().map(|(i, &x)| if i % dim == 0 { -x } else { x }).collect();
    let e = solver.advance_from(&mirrored, &Motion::from_displacement(all)).unwrap_err();
    assert_eq!((e.rank, e.kind), (0, DistErrorKind::Tangled), "{e}");
    assert_eq!(solver.current_coords(), before, "a refused call changes nothing");
    if rank == 0 {
        println!("{size} ranks, refused options, cancelled steps and tangled positions: every rank returns the error");
    }
}

/// The tag of the library's halo exchanges, which the host's own messages use here.
const LIBRARY_HALO_TAG: i32 = 28;

/// The host's own messages on its communicator, sent to the next rank before the distributed
/// mesh is made and a biharmonic solve runs, and received after it, with the library's halo
/// tag: they reach the host unchanged and the solve is bitwise the one made without them (the
/// library exchanges on its duplicate of the communicator).
fn host_messages_stay_the_hosts(world: &SimpleCommunicator, d: &MeshData) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let p = part(d, &slab_owner(d, size), rank, true);
    let local: Vec<f64> = p.global.iter().flat_map(|&v| motion(d.point(v))[..2].to_vec()).collect();
    let m = Motion::from_displacement(local);
    let params = DistSolveParams { tol: 1e-12, ..Default::default() };
    let solved = || {
        let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
        let solver = DistributedSolver::new(&dm, &BoundaryConditions::new(), Method::Biharmonic, params).unwrap();
        solver.solve(&m).unwrap().displacement
    };
    let alone = solved();
    let sent: Vec<f64> = (0..p.data.coords.len()).map(|i| (rank * 100_000 + i) as f64).collect();
    let (next, prev) = ((rank + 1) % size, (rank + size - 1) % size);
    let (beside, got) = mpi::request::scope(|scope| {
        let to_next = world.process_at_rank(next as i32).immediate_send_with_tag(scope, &sent[..], LIBRARY_HALO_TAG);
        let beside = solved();
        let (got, _) = world.process_at_rank(prev as i32).receive_vec_with_tag::<f64>(LIBRARY_HALO_TAG);
        to_next.wait();
        (beside, got)
    });
    assert_eq!(beside, alone, "the host's pending messages change the solve");
    let expected = (0..got.len()).map(|i| (prev * 100_000 + i) as f64);
    assert!(!got.is_empty() && got.iter().copied().eq(expected), "the host's message from rank {prev} is altered");
    if rank == 0 {
        println!("{size} ranks, the host's messages on its communicator: received intact, the solve unchanged");
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

/// Steps with SLIP walls, the curved wall given as a cylinder and moved rigidly: `move_in_steps`
/// then `advance` equal the serial calls to 1e-10 of the motion; a refused `advance` (its result
/// inverts cells) puts the walls back where they were, so the next `advance` still equals the
/// serial one.
fn slip_steps_agree_with_serial(world: &SimpleCommunicator, (d, scaled): &(MeshData, Vec<f64>)) {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let dim = d.dim;
    let all: Vec<f64> = (0..d.num_vertices())
        .flat_map(|v| motion(d.point(v))[..dim].iter().map(|m| 0.5 * m * scaled[v]).collect::<Vec<_>>())
        .collect();
    let bcs = Case::Slip { surface: true }.conditions(dim);
    let rigid = vec![(BODY, RigidMotion { translation: [0.01, 0.005, 0.0], rotation: [0.0; 3], center: [0.0; 3] })];
    let o = options(Method::Laplacian, ReferenceMode::Incremental);
    let mut serial = Solver::new(&Mesh::from_data(d).unwrap(), &bcs, o.clone()).unwrap();
    let p = part(d, &slab_owner(d, size), rank, true);
    let dm = DistributedMesh::new(world, &p.data, &p.gids, &p.ghost).unwrap();
    let mut dist = DistributedSolver::with_options(&dm, &bcs, o).unwrap();
    let what = format!("quarter annulus, slip walls moved rigidly, on {size} ranks");
    let whole = |d: &[f64]| Motion { displacement: d.to_vec(), rigid: rigid.clone() };
    let local = |d: &[f64]| Motion { displacement: local_of(&p, dim, d), rigid: rigid.clone() };

    serial.move_in_steps(&whole(&all), 2).unwrap();
    dist.move_in_steps(&local(&all), 2).unwrap();
    let scale = serial.total_displacement().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let off = largest_difference(&p, dim, &dist.current_coords(), serial.current_coords());
    assert!(off <= 1e-10 * scale, "{what}: move_in_steps: rank {rank} differs by {off:e} (motion {scale:e})");

    let big: Vec<f64> = all.iter().map(|x| 40.0 * x).collect();
    let before = dist.current_coords();
    let e = dist.advance(&local(&big)).unwrap_err();
    assert_eq!(e.kind, DistErrorKind::Inverted, "{what}: {e}");
    assert_eq!(dist.current_coords(), before, "{what}: a refused step changes nothing");
    assert!(serial.advance(&whole(&big)).unwrap().quality.inverted > 0, "{what}: the big step inverts cells");

    let sa = serial.advance(&whole(&all)).unwrap();
    let da = dist.advance(&local(&all)).unwrap();
    let off = largest_difference(&p, dim, &da.displacement, &sa.displacement);
    let at = largest_difference(&p, dim, &dist.current_coords(), serial.current_coords());
    assert!(off.max(at) <= 1e-10 * scale, "{what}: advance: rank {rank} differs by {off:e}, positions {at:e}");
    if rank == 0 {
        println!(
            "{size} ranks, {what}: move_in_steps and advance equal the serial calls (iterations {:?})",
            da.iterations
        );
    }
}
