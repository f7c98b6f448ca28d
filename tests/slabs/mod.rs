//! Meshes split into slabs by x, each rank's part with one layer of ghost cells: what an MPI
//! host hands `DistributedMesh::new`. Shared by the distributed test and the distributed example
//! (which includes this file by its path).

use meshmove::{CellType, Mesh, MeshData};
use std::collections::HashMap;

/// The boundary motion: smooth, different in every component.
#[allow(dead_code)] // the cases' test moves its cases' boundaries
pub fn motion(x: &[f64]) -> [f64; 3] {
    let z = x.get(2).copied().unwrap_or(0.0);
    [0.1 * (2.0 * x[0] + x[1]).sin(), 0.08 * (x[0] - 3.0 * x[1] + z).cos(), 0.05 * (x[0] + x[1] + 2.0 * z).sin()]
}

/// A jitter in [-0.5, 0.5) from an index (deterministic).
fn jitter(k: usize) -> f64 {
    ((k as u64).wrapping_mul(2654435761) % 1000) as f64 / 1000.0 - 0.5
}

/// nx × ny squares of the unit square, each split into two triangles, interior vertices moved.
pub fn grid2d(nx: usize, ny: usize) -> MeshData {
    let mut d = MeshData::new(2);
    for j in 0..=ny {
        for i in 0..=nx {
            let inner = i > 0 && i < nx && j > 0 && j < ny;
            let s = if inner { 0.3 } else { 0.0 };
            let k = j * (nx + 1) + i;
            d.push_vertex(&[
                (i as f64 + s * jitter(2 * k)) / nx as f64,
                (j as f64 + s * jitter(2 * k + 1)) / ny as f64,
            ]);
        }
    }
    let v = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    for j in 0..ny {
        for i in 0..nx {
            d.push_cell(CellType::Triangle, &[v(i, j), v(i + 1, j), v(i + 1, j + 1)], 0);
            d.push_cell(CellType::Triangle, &[v(i, j), v(i + 1, j + 1), v(i, j + 1)], 0);
        }
    }
    d
}

/// n³ cubes of the unit cube (hexahedra, or six tetrahedra each), interior vertices moved.
pub fn box3d(n: usize, tets: bool) -> MeshData {
    let mut d = MeshData::new(3);
    let v = |i: usize, j: usize, k: usize| ((k * (n + 1) + j) * (n + 1) + i) as u32;
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let inner = [i, j, k].iter().all(|&a| a > 0 && a < n);
                let s = if inner { 0.25 } else { 0.0 };
                let m = v(i, j, k) as usize;
                let p = [i, j, k].map(|a| a as f64);
                d.push_vertex(&[0, 1, 2].map(|c| (p[c] + s * jitter(3 * m + c)) / n as f64));
            }
        }
    }
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = [
                    v(i, j, k),
                    v(i + 1, j, k),
                    v(i + 1, j + 1, k),
                    v(i, j + 1, k),
                    v(i, j, k + 1),
                    v(i + 1, j, k + 1),
                    v(i + 1, j + 1, k + 1),
                    v(i, j + 1, k + 1),
                ];
                if !tets {
                    d.push_cell(CellType::Hexahedron, &c, 0);
                    continue;
                }
                // Six tetrahedra around the diagonal 0–6 (positively oriented).
                for [a, b] in [[1, 2], [2, 3], [3, 7], [7, 4], [4, 5], [5, 1]] {
                    d.push_cell(CellType::Tetra, &[c[0], c[a], c[b], c[6]], 0);
                }
            }
        }
    }
    d
}

/// The patch of the body (the side x = 0), CLAMPED in the tests.
pub const BODY: i32 = 1;
/// The patch of the side y = 0, FREE in the tests.
pub const SIDE: i32 = 2;

/// The mesh and partition an example's command line names: argument 1 is n (16 unless given),
/// an n³ box of hexahedra, of tetrahedra with `tets`, or an n × n square of triangles with
/// `tri`; slabs by x over `size` ranks, or hashed blocks with `blocks`. Returns the mesh, the
/// name of its cells and each vertex's owner.
#[allow(dead_code)] // the test chooses its own meshes
pub fn from_args(args: &[String], size: usize) -> (MeshData, &'static str, Vec<usize>) {
    let n: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(16);
    let has = |w: &str| args.iter().skip(2).any(|a| a == w);
    let (d, cells) = if has("tri") {
        (grid2d(n, n), "triangles")
    } else if has("tets") {
        (box3d(n, true), "tetrahedra")
    } else {
        (box3d(n, false), "hexahedra")
    };
    let owner = if has("blocks") { block_owner(&d, size) } else { slab_owner(&d, size) };
    (d, cells, owner)
}

/// `d` with its boundary faces on x = 0 tagged `BODY` and those on y = 0 (the others) `SIDE`;
/// the rest stay untagged (patch 0, the far field).
#[allow(dead_code)] // the distributed example does not tag
pub fn tagged(d: &MeshData) -> MeshData {
    let mesh = Mesh::from_data(d).expect("a valid mesh");
    let mut out = d.clone();
    for f in mesh.patch_faces() {
        let on = |c: usize| f.vertices.iter().all(|&v| d.point(v as usize)[c] == 0.0);
        let patch = if on(0) {
            BODY
        } else if on(1) {
            SIDE
        } else {
            continue;
        };
        out.push_face(f.vertices, patch);
    }
    out
}

/// The slab of x that owns each cell of `d` on `size` ranks (by its centroid).
pub fn slab_owner(d: &MeshData, size: usize) -> Vec<usize> {
    (0..d.num_cells())
        .map(|c| {
            let t = d.cell(c);
            let x = t.iter().map(|&v| d.point(v as usize)[0]).sum::<f64>() / t.len() as f64;
            ((x * size as f64) as usize).min(size - 1)
        })
        .collect()
}

/// An irregular partition of `d` on `size` ranks: the unit box cut into 4 blocks per axis, each
/// block's cells given to a rank by a hash of the block's index, so parts are scattered blocks
/// with boundaries in every direction.
pub fn block_owner(d: &MeshData, size: usize) -> Vec<usize> {
    (0..d.num_cells())
        .map(|c| {
            let t = d.cell(c);
            let key = (0..d.dim).fold(0u64, |key, a| {
                let x = t.iter().map(|&v| d.point(v as usize)[a]).sum::<f64>() / t.len() as f64;
                key * 4 + ((x * 4.0) as u64).min(3)
            });
            ((key.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40) % size as u64) as usize
        })
        .collect()
}

/// Rank `rank`'s part: its owned cells (with their regions), the cells sharing a vertex with
/// them as ghosts (unless `with_ghosts` is false), their vertices in reverse global order (any order is allowed),
/// global ids offset from the indices; polyhedra with their faces.
pub struct Part {
    pub data: MeshData,
    pub gids: Vec<u64>,
    pub ghost: Vec<bool>,
    /// The global vertex of each local one.
    pub global: Vec<usize>,
}

/// The global id of vertex 0 (vertex v's is `GID_BASE + v`).
#[allow(dead_code)] // the cases' test names pairs by global id
pub const GID_BASE: u64 = 1000;

pub fn part(d: &MeshData, owner: &[usize], rank: usize, with_ghosts: bool) -> Part {
    let mut touches = vec![false; d.num_vertices()];
    (0..d.num_cells())
        .filter(|&c| owner[c] == rank)
        .for_each(|c| d.cell(c).iter().for_each(|&v| touches[v as usize] = true));
    let cells: Vec<usize> = (0..d.num_cells())
        .filter(|&c| owner[c] == rank || (with_ghosts && d.cell(c).iter().any(|&v| touches[v as usize])))
        .collect();
    let mut used = vec![false; d.num_vertices()];
    cells.iter().for_each(|&c| d.cell(c).iter().for_each(|&v| used[v as usize] = true));
    let global: Vec<usize> = (0..d.num_vertices()).rev().filter(|&v| used[v]).collect();
    let mut local_of = vec![u32::MAX; d.num_vertices()];
    global.iter().enumerate().for_each(|(i, &v)| local_of[v] = i as u32);
    let mut data = MeshData::new(d.dim);
    global.iter().for_each(|&v| {
        data.push_vertex(d.point(v));
    });
    let polyhedra = polyhedron_faces(d);
    let region = |c: usize| d.regions.get(c).copied().unwrap_or(0);
    for &c in &cells {
        match polyhedra.get(&c) {
            Some(faces) => {
                let faces: Vec<Vec<u32>> =
                    faces.iter().map(|f| f.iter().map(|&v| local_of[v as usize]).collect()).collect();
                let refs: Vec<&[u32]> = faces.iter().map(|f| f.as_slice()).collect();
                data.push_polyhedron(&refs, region(c));
            }
            None => {
                let t: Vec<u32> = d.cell(c).iter().map(|&v| local_of[v as usize]).collect();
                data.push_cell(d.cell_types[c], &t, region(c));
            }
        }
    }
    // The tagged faces of the part's cells.
    for f in 0..d.num_faces() {
        let face = d.face(f);
        if cells.iter().any(|&c| face.iter().all(|v| d.cell(c).contains(v))) {
            let t: Vec<u32> = face.iter().map(|&v| local_of[v as usize]).collect();
            data.push_face(&t, d.face_patch[f]);
        }
    }
    let ghost = cells.iter().map(|&c| owner[c] != rank).collect();
    let gids = global.iter().map(|&v| v as u64 + GID_BASE).collect();
    Part { data, gids, ghost, global }
}

/// The faces of each polyhedron of `d`, by cell.
fn polyhedron_faces(d: &MeshData) -> HashMap<usize, Vec<Vec<u32>>> {
    let mut out = HashMap::new();
    let s = &d.polyhedron_faces;
    let mut at = 0;
    for c in (0..d.num_cells()).filter(|&c| d.cell_types[c] == CellType::Polyhedron) {
        let n = s[at] as usize;
        at += 1;
        let mut faces = Vec::with_capacity(n);
        for _ in 0..n {
            let len = s[at] as usize;
            faces.push(s[at + 1..at + 1 + len].to_vec());
            at += 1 + len;
        }
        out.insert(c, faces);
    }
    out
}

/// Runs this test's own executable under `mpirun` on `np` ranks (oversubscribed, allowed as
/// root), within a time limit so that a rank left waiting fails the run instead of hanging it.
/// The limit is far above a run's length on an idle machine, so that a loaded machine (four
/// oversubscribed ranks sharing its cores with other jobs) never reaches it; only a wait that
/// never ends does. A rank that waits for a message yields its core (OpenMPI's
/// `mpi_yield_when_idle`, which it sets itself only when the ranks outnumber the cores), so that
/// on a busy machine a waiting rank does not hold the core its partner needs to send.
#[allow(dead_code)] // the distributed example does not launch itself
pub fn mpirun(np: usize) -> std::process::Output {
    let exe = std::env::current_exe().expect("the test's own path");
    std::process::Command::new("timeout")
        .args(["1500", "mpirun", "--oversubscribe", "-np", &np.to_string()])
        .arg(&exe)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_mpi_yield_when_idle", "1")
        .output()
        .expect("mpirun (openmpi-bin) and timeout on PATH")
}

/// The slab across x of the mesh's bounding box that owns each cell of `d` on `size` ranks
/// (by its centroid).
#[allow(dead_code)] // the library's test and the distributed example choose their own slabs
pub fn slabs_across_x(d: &MeshData, size: usize) -> Vec<usize> {
    let xs = (0..d.num_vertices()).map(|v| d.point(v)[0]);
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
    (0..d.num_cells())
        .map(|c| {
            let t = d.cell(c);
            let x = t.iter().map(|&v| d.point(v as usize)[0]).sum::<f64>() / t.len() as f64;
            (((x - lo) / (hi - lo) * size as f64) as usize).min(size - 1)
        })
        .collect()
}

/// The largest difference between a rank's displacement `local` (`dim` values per local
/// vertex) and the whole mesh's `reference`, the local vertices being `global` of it.
#[allow(dead_code)] // the library's test and the distributed example compare otherwise
pub fn largest_difference(global: &[usize], local: &[f64], reference: &[f64], dim: usize) -> f64 {
    let mut worst = 0.0f64;
    for (i, &v) in global.iter().enumerate() {
        for c in 0..dim {
            worst = worst.max((local[i * dim + c] - reference[v * dim + c]).abs());
        }
    }
    worst
}
