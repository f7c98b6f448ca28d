//! The l1 Jacobi bound of docs/DESIGN.md §3 dominates the assembled matrix's rows, and a sweep with
//! C = 0.9 never grows the error, even where the bare diagonal would diverge.

#[path = "../../tests/common/mod.rs"]
mod common;
use common::*;
use meshmove::bc::P;
use meshmove::{BoundaryConditions, Kind, Mesh, Method, Options, Solver};
use meshmove_cases::meshes::{free_surface, structured_rectangle};

/// Dense A of component `c` by applying the operator to unit vectors (free rows/cols only).
fn dense_a(s: &Solver, c: usize) -> (Vec<usize>, Vec<Vec<f64>>) {
    let lev = &s.hierarchy().levels[0];
    let n = lev.n();
    let free: Vec<usize> = (0..n).filter(|&i| lev.flags()[c][i] & P == 0).collect();
    let (mut e, mut y, mut t) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut a = vec![vec![0.0; free.len()]; free.len()];
    for (jj, &j) in free.iter().enumerate() {
        e[j] = 1.0;
        lev.op().apply(&lev.flags()[c], &e, &mut y, &mut t);
        e[j] = 0.0;
        for (ii, &i) in free.iter().enumerate() {
            a[ii][jj] = y[i];
        }
    }
    (free, a)
}

/// Growth of ‖e‖ over many sweeps e ← (I − C D⁻¹A) e, per sweep (geometric mean).
fn sweep_growth(a: &[Vec<f64>], inv_d: &[f64], c: f64) -> f64 {
    let m = a.len();
    let mut e: Vec<f64> = (0..m).map(|i| ((i * 7919) % 101) as f64 / 101.0 - 0.5).collect();
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let n0 = norm(&e);
    let sweeps = 400;
    for _ in 0..sweeps {
        let ae: Vec<f64> = a.iter().map(|row| row.iter().zip(&e).map(|(x, y)| x * y).sum()).collect();
        for i in 0..m {
            e[i] -= c * inv_d[i] * ae[i];
        }
    }
    (norm(&e) / n0).powf(1.0 / sweeps as f64)
}

fn meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("right-diagonal", structured_rectangle(14, 14, 0.0, 1.0, 0.0, 1.0)),
        ("alternating", Grid::new(14, 12).alternate().mesh()),
        ("jittered", Grid::new(14, 14).jitter(0.4).mesh()),
        ("annulus", annulus(6, 32, 0.5, 2.0, 1.3)),
        ("free-surface", free_surface(1.0 / 12.0)),
    ]
}

#[test]
fn l1_bound_dominates_rows_and_sweeps_contract() {
    for (name, mesh) in meshes() {
        for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
            // Mixed kinds so P, Z and free boundary vertices all occur.
            let mut bcs = BoundaryConditions::new();
            let ids = mesh.patch_ids();
            for (k, &p) in ids.iter().enumerate() {
                bcs.set_kinds(p, [Kind::Fixed, Kind::Clamped, Kind::Free][k % 3]);
            }
            bcs.set_kinds(ids[0], Kind::Fixed);
            let s = Solver::new(&mesh, &bcs, Options { method, ..Default::default() }).unwrap();
            let lev = &s.hierarchy().levels[0];
            for c in 0..2 {
                let (free, a) = dense_a(&s, c);
                let inv_d: Vec<f64> = free.iter().map(|&i| lev.inv_d()[c][i]).collect();
                for (ii, row) in a.iter().enumerate() {
                    let l1: f64 = row.iter().map(|x| x.abs()).sum();
                    assert!(1.0 / inv_d[ii] >= l1 * (1.0 - 1e-12), "{name} {method:?}: D below the l1 row sum");
                }
                let g = sweep_growth(&a, &inv_d, 0.9);
                assert!(g <= 1.0, "{name} {method:?} c{c}: C = 0.9 sweep grows the error ({g})");
            }
        }
    }
}

#[test]
fn bare_diagonal_diverges_where_the_l1_bound_does_not() {
    let mesh = structured_rectangle(14, 14, 0.0, 1.0, 0.0, 1.0);
    let mut bcs = BoundaryConditions::new();
    bcs.default_kind = [Kind::Clamped; 3];
    let s = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    let lev = &s.hierarchy().levels[0];
    let (free, a) = dense_a(&s, 1);
    let bare: Vec<f64> = (0..a.len()).map(|i| 1.0 / a[i][i]).collect();
    let l1: Vec<f64> = free.iter().map(|&i| lev.inv_d()[1][i]).collect();
    let g_bare = sweep_growth(&a, &bare, 0.9);
    let g_l1 = sweep_growth(&a, &l1, 0.9);
    assert!(g_bare > 1.01, "bare diagonal unexpectedly stable ({g_bare})");
    assert!(g_l1 < 1.0, "l1 bound not contracting ({g_l1})");
    println!("right-diagonal mesh, biharmonic, C = 0.9: growth per sweep bare {g_bare:.3}, l1 {g_l1:.6}");
}
