//! Two-level analysis of the biharmonic's hierarchy on the wall-layered meshes (docs/perf-history.md):
//! `cargo run --release -p meshmove-cases --example two_level_probe -- wing 32:4 [LEVELS,…] [VTU_PREFIX]`
//! (LEVELS: the pairs' finer levels, all when empty),
//! (kinds and sizes as in `galerkin_probe`). Per level pair (l, l + 1): PCG iterations on level
//! l's system with the hierarchy's cycle from l and with level l + 1 solved exactly, the
//! two-level convergence factor, and on its slowest error the reduction by the smoother alone
//! and by the exact coarse correction alone, and where that error's energy lies.

use meshmove::io::{write_vtu, PointField};
use meshmove::multigrid::policy::CycleParams;
use meshmove::multigrid::two_level::{analyse_pair, finest_unknowns};
use meshmove::{Options, SolveParams, Solver};
use meshmove_cases::viscous::*;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let kind = args.first().map_or("wing", |s| s.as_str());
    let size = args.get(1).map_or("32:4", |s| s.as_str());
    let pairs: Vec<usize> =
        args.get(2).map_or(Vec::new(), |s| s.split(',').map(|x| x.parse().expect("a level")).collect());
    let vtu = args.get(3);
    let v = by_name(kind, size).expect("a mesh");
    let bcs = boundary_conditions(&v);
    let solver = Solver::new(&v.mesh, &bcs, Options::default()).expect("a solver");
    let h = solver.hierarchy();
    let cp = CycleParams::resolve(h, &SolveParams::default());
    let comps = h.groups().into_iter().find(|g| g.contains(&1)).expect("a group with y");
    println!("{kind} {size} group {comps:?}: {} vertices", v.mesh.num_vertices());
    print!("{}", solver.describe());
    let regions = vertex_regions(&v);
    let names = ["layers 0-9", "layers 10+", "outside layers", "end walls", "trailing edge x>0.9"];
    for l in 0..h.levels.len() - 1 {
        if !pairs.is_empty() && !pairs.contains(&l) {
            continue;
        }
        let t = Instant::now();
        let Some(a) = analyse_pair(h, &cp, comps.clone(), l, 1e-8, 12) else { continue };
        let fine = finest_unknowns(h, l).expect("kept unknowns");
        // The slow mode's energy by region: e_i (A e)_i is not at hand here, so |e_i|² over the mode.
        let n = fine.len();
        let mag: Vec<f64> = (0..n).map(|i| (0..comps.len()).map(|k| a.mode[k * n + i].powi(2)).sum()).collect();
        let total: f64 = mag.iter().sum();
        let mut share = [0.0; 5];
        for (i, &u) in fine.iter().enumerate() {
            let w = mag[i] / total;
            for (r, s) in share.iter_mut().enumerate() {
                if regions[u as usize] & (1 << r) != 0 {
                    *s += w;
                }
            }
        }
        println!(
            "pair ({l}, {}): {} -> {} unknowns; PCG iterations multilevel {} two-level {} (Galerkin coarse {}); two-level factor {:.3}; on its slow mode: smoother {:.3}, exact coarse correction {:.3} (Galerkin {:.3}), position in D^-1 A {:.2e}; {:.1} s",
            l + 1,
            h.levels[l].n(),
            h.levels[l + 1].n(),
            a.multilevel,
            a.two_level,
            a.two_level_galerkin,
            a.rate,
            a.smoother_reduction,
            a.coarse_reduction,
            a.coarse_reduction_galerkin,
            a.smoother_position,
            t.elapsed().as_secs_f64()
        );
        let shares: Vec<String> = names.iter().zip(share).map(|(n, s)| format!("{n} {s:.3}")).collect();
        println!("  slow mode |e|^2 share: {}", shares.join(", "));
        if let Some(prefix) = vtu {
            let mut field = vec![0.0; v.mesh.num_vertices()];
            for (i, &u) in fine.iter().enumerate() {
                field[u as usize] = mag[i].sqrt();
            }
            let path = format!("{prefix}_{kind}_{l}.vtu");
            write_vtu(
                std::path::Path::new(&path),
                &v.mesh.to_data(),
                &[("slow_mode", PointField::Scalar(&field))],
                &[],
            )
            .expect("the mode written");
            println!("  written {path}");
        }
    }
}

/// Per fine vertex, bits: 1 in layers 0-9, 2 in layers 10 and on, 4 outside the layers, 8 on
/// the end walls, 16 near the trailing edge (x > 0.9 within 0.05 of the chord line).
fn vertex_regions(v: &ViscousMesh) -> Vec<u8> {
    let m = &v.mesh;
    let mut layer = vec![NO_LAYER; m.num_vertices()];
    for c in 0..m.num_cells() {
        for &p in m.cell(c) {
            layer[p as usize] = layer[p as usize].min(v.cell_layer[c]);
        }
    }
    let ends = m.patch_vertices(END_WALLS);
    let mut bits: Vec<u8> = layer
        .iter()
        .enumerate()
        .map(|(i, &k)| {
            let p = m.point(i);
            let te = if p[0] > 0.9 && p[1].abs() < 0.05 { 16 } else { 0 };
            te | match k {
                NO_LAYER => 4,
                k if k < 10 => 1,
                _ => 2,
            }
        })
        .collect();
    for e in ends {
        bits[e as usize] |= 8;
    }
    bits
}
