//! What a kept re-reference of a 3D box repeats, timed one piece at a time in CPU seconds per
//! run: the finest level's K and V from the element kernels (`LevelOperator::reassemble`), the
//! first coarse level's Galerkin refill (`update_galerkin`) and the l1 diagonals; with a hash of
//! their values (bitwise checks of a change):
//! `cargo run --release -p meshmove-cases --example rereference_probe -- [hex|tet] [N] [REPEATS]`
//! (the bench's box of N³ cells, default 31: 32 768 vertices, its bottom fixed and top clamped,
//! its vertices moved off the grid; `RAYON_NUM_THREADS=1` for one thread).

use meshmove::multigrid::hierarchy::Hierarchy;
use meshmove::operator::LevelOperator;
use meshmove::{BoundaryConditions, Kind, Method, Options, Solver};
use meshmove_cases::boxes::{structured_box, BoxCells, BOX_BOTTOM, BOX_TOP};
use meshmove_cases::report::thread_cpu_seconds;
use std::hash::{Hash, Hasher};

/// The mean CPU seconds of `repeats` runs of `f`.
fn cpu_per_run(repeats: usize, mut f: impl FnMut()) -> f64 {
    let start = thread_cpu_seconds();
    (0..repeats).for_each(|_| f());
    (thread_cpu_seconds() - start) / repeats as f64
}

/// A hash of the bits of `values`.
fn hash(values: &[f64]) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    values.iter().for_each(|v| v.to_bits().hash(&mut h));
    h.finish()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let cells = if args.first().map(|s| s.as_str()) == Some("tet") { BoxCells::Tets } else { BoxCells::Hexes };
    let n: usize = args.get(1).map_or(31, |s| s.parse().expect("cells per side"));
    let repeats: usize = args.get(2).map_or(10, |s| s.parse().expect("repeats"));
    let mesh = structured_box(n, cells);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BOX_BOTTOM, Kind::Fixed).set_kinds(BOX_TOP, Kind::Clamped);
    let opts = Options { method: Method::Biharmonic, threads: 1, ..Default::default() };
    let solver = Solver::new(&mesh, &bcs, opts).expect("a solver");
    let h: &Hierarchy = solver.hierarchy();
    let fine = h.fine();
    let p = fine.prolong().expect("a coarse level");
    let restrict = p.transpose();
    // The vertices moved off the grid by a smooth field, as a step moves them.
    let moved = mesh.with_coords(
        mesh.coords()
            .chunks(3)
            .flat_map(|x| {
                let w = 0.01 * (std::f64::consts::TAU * x[0]).sin() * (std::f64::consts::TAU * x[1]).cos();
                [x[0] + w, x[1] - 0.5 * w, x[2] + w * x[2]]
            })
            .collect(),
    );
    {
        let mut op: LevelOperator = fine.op().clone();
        let assemble = cpu_per_run(repeats, || op.reassemble(&moved, fine.dofs()));
        let mut coarse = LevelOperator::galerkin(&op, p, &restrict);
        let transpose = cpu_per_run(repeats, || drop(p.transpose()));
        let galerkin = cpu_per_run(repeats, || coarse.update_galerkin(&op, p, &restrict));
        let flags: Vec<&[u8]> = fine.flags().iter().map(|f| f.as_slice()).collect();
        let mut diags = Vec::new();
        let l1 = cpu_per_run(repeats, || diags = op.inv_l1_diags(&flags));
        println!(
            "{} vertices, {} cells, P {}×{} ({} entries), K_c {} entries: assemble {:.4} s, Galerkin refill {:.4} s, Pᵀ {:.4} s, l1 diagonals {:.4} s",
            mesh.num_vertices(),
            mesh.num_cells(),
            p.nrows,
            p.ncols,
            p.nnz(),
            coarse.k.nnz(),
            assemble,
            galerkin,
            transpose,
            l1
        );
        let d: Vec<f64> = diags.concat();
        println!(
            "hashes: K {:016x}, 1/V {:016x}, K_c {:016x}, 1/V_c {:016x}, l1 {:016x}",
            hash(&op.k.vals),
            hash(&op.inv_v),
            hash(&coarse.k.vals),
            hash(&coarse.inv_v),
            hash(&d)
        );
    }
}
