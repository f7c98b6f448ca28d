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
    let pairs: Vec<usize> = args
        .get(2)
        .map_or(Vec::new(), |s| s.split(',').filter(|x| !x.is_empty()).map(|x| x.parse().expect("a level")).collect());
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
    let names = [
        "layers 0-9",
        "layers 10+",
        "outside layers",
        "end walls",
        "trailing edge x>0.9",
        "leading edge x<0.1",
        "far r>2",
    ];
    let rings = airfoil_rings(&v);
    for l in 0..h.levels.len() - 1 {
        if !pairs.is_empty() && !pairs.contains(&l) {
            continue;
        }
        let t = Instant::now();
        let Some(a) = analyse_pair(h, &cp, comps.clone(), l, 1e-8, 12) else { continue };
        // Level l's unknowns are finest unknowns; their vertices (the finest level numbers its
        // unknowns apart from the mesh's vertices).
        let dof_vertex = &h.levels[0].dofs().dof_vertex;
        let vertex: Vec<u32> =
            finest_unknowns(h, l).expect("kept unknowns").iter().map(|&u| dof_vertex[u as usize]).collect();
        let n = vertex.len();
        let mag: Vec<f64> = (0..n).map(|i| (0..comps.len()).map(|k| a.mode[k * n + i].powi(2)).sum()).collect();
        println!("{}; {:.1} s", a.summary(h), t.elapsed().as_secs_f64());
        for (what, values) in [
            ("|e|^2", &mag),
            ("energy", &a.density),
            ("energy after smoothing", &a.smoothed_density),
            ("energy after coarse correction", &a.corrected_density),
        ] {
            let total: f64 = values.iter().sum();
            let mut share = [0.0; 7];
            for (i, &u) in vertex.iter().enumerate() {
                for (r, s) in share.iter_mut().enumerate() {
                    if regions[u as usize] & (1 << r) != 0 {
                        *s += values[i];
                    }
                }
            }
            let shares: Vec<String> = names.iter().zip(share).map(|(n, s)| format!("{n} {:.3}", s / total)).collect();
            println!("  {what} (total {total:.3}) share: {}", shares.join(", "));
        }
        let mut top: Vec<usize> = (0..n).collect();
        top.sort_by(|&i, &j| a.density[j].total_cmp(&a.density[i]));
        let at = |i: usize| {
            let p = v.mesh.point(vertex[i] as usize);
            let ring = rings.as_ref().and_then(|r| r.ring_of(vertex[i] as usize));
            format!(
                "({:.4}, {:.4}{}) ring {ring:?}",
                p[0],
                p[1],
                if p.len() > 2 { format!(", {:.3}", p[2]) } else { String::new() }
            )
        };
        for &i in top.iter().take(6) {
            println!("  energy {:.4} after coarse correction {:.4} at {}", a.density[i], a.corrected_density[i], at(i));
        }
        if let Some(r) = &rings {
            let y = 1 - comps.start;
            r.profiles(&vertex, &a.mode[y * n..(y + 1) * n], &a.density, &a.corrected_density);
        }
        if let Some(prefix) = vtu {
            let mut field = vec![0.0; v.mesh.num_vertices()];
            let mut energy = vec![0.0; v.mesh.num_vertices()];
            let mut missed = vec![0.0; v.mesh.num_vertices()];
            for (i, &u) in vertex.iter().enumerate() {
                field[u as usize] = mag[i].sqrt();
                energy[u as usize] = a.density[i];
                missed[u as usize] = a.corrected_density[i];
            }
            let path = format!("{prefix}_{kind}_{size}_{l}.vtu");
            write_vtu(
                std::path::Path::new(&path),
                &v.mesh.to_data(),
                &[
                    ("slow_mode", PointField::Scalar(&field)),
                    ("energy", PointField::Scalar(&energy)),
                    ("energy_after_coarse_correction", PointField::Scalar(&missed)),
                ],
                &[],
            )
            .expect("the mode written");
            println!("  written {path}");
        }
    }
}

/// The airfoil's structured rings: vertex `base + k ns + j` is ring k (0 the wall) at surface
/// index j for k below the layers' count, and the outermost ring (the layers' top) is the
/// triangles' loop after the far circle (`airfoil_2d`'s vertex order).
struct Rings {
    base: usize,
    far: usize,
    ns: usize,
    nl: usize,
}

fn airfoil_rings(v: &ViscousMesh) -> Option<Rings> {
    if v.mesh.dim() != 2 {
        return None;
    }
    let ns = v.mesh.patch_vertices(WALL).len();
    let nl = v.layers.count;
    let far = v.mesh.patch_vertices(FARFIELD).len();
    Some(Rings { base: v.mesh.num_vertices() - nl * ns, far, ns, nl })
}

impl Rings {
    fn ring_of(&self, u: usize) -> Option<(usize, usize)> {
        if u >= self.base {
            Some(((u - self.base) / self.ns, (u - self.base) % self.ns))
        } else if (self.far..self.far + self.ns).contains(&u) {
            Some((self.nl, u - self.far))
        } else {
            None
        }
    }

    /// Per ring, the slow mode's energy before and after the coarse correction; its y
    /// component across the rings where its energy in the layers peaks and along the wall at a
    /// few rings; and its roughness across and along the rings (Σ of squared differences of
    /// neighbours over Σ e² on the rings), on the unknowns the level keeps.
    fn profiles(&self, vertex: &[u32], mode_y: &[f64], density: &[f64], corrected: &[f64]) {
        let (nl, ns) = (self.nl, self.ns);
        let mut e = vec![vec![f64::NAN; ns]; nl + 1];
        let mut per_ring = vec![(0.0, 0.0); nl + 2];
        let mut per_sector = vec![(0.0, 0.0); 16];
        for (i, &u) in vertex.iter().enumerate() {
            match self.ring_of(u as usize) {
                Some((k, j)) => {
                    e[k][j] = mode_y[i];
                    per_ring[k].0 += density[i];
                    per_ring[k].1 += corrected[i];
                    let s = &mut per_sector[j * 16 / ns];
                    s.0 += density[i];
                    s.1 += corrected[i];
                }
                None => {
                    per_ring[nl + 1].0 += density[i];
                    per_ring[nl + 1].1 += corrected[i];
                }
            }
        }
        let rings: Vec<String> = per_ring.iter().map(|(a, b)| format!("{a:.3}/{b:.3}")).collect();
        println!("  energy / after coarse correction per ring 0..={nl}, then outside: {}", rings.join(" "));
        let sectors: Vec<String> = per_sector.iter().map(|(a, b)| format!("{a:.3}/{b:.3}")).collect();
        println!(
            "  the same per sixteenth of the wall from the trailing edge over the upper side: {}",
            sectors.join(" ")
        );
        let (mut across, mut along, mut sq) = (0.0, 0.0, 0.0);
        for k in 0..=nl {
            for j in 0..ns {
                if e[k][j].is_nan() {
                    continue;
                }
                sq += e[k][j] * e[k][j];
                if k < nl && !e[k + 1][j].is_nan() {
                    across += (e[k + 1][j] - e[k][j]).powi(2);
                }
                let next = e[k][(j + 1) % ns];
                if !next.is_nan() {
                    along += (next - e[k][j]).powi(2);
                }
            }
        }
        println!("  roughness on the rings: across {:.3e}, along {:.3e}", across / sq, along / sq);
        let jmax = (0..ns)
            .max_by(|&a, &b| {
                let s =
                    |j: usize| (0..=nl).map(|k| if e[k][j].is_nan() { 0.0 } else { e[k][j] * e[k][j] }).sum::<f64>();
                s(a).total_cmp(&s(b))
            })
            .unwrap_or(0);
        let col: Vec<String> = (0..=nl).map(|k| format!("{:.2e}", e[k][jmax])).collect();
        println!("  y across the rings at j = {jmax}: {}", col.join(" "));
        for k in [1, nl / 2, nl] {
            let row: Vec<String> = (0..ns).step_by((ns / 32).max(1)).map(|j| format!("{:.2e}", e[k][j])).collect();
            println!("  y along ring {k} (every {}th): {}", (ns / 32).max(1), row.join(" "));
        }
    }
}

/// Per fine vertex, bits: 1 in layers 0-9, 2 in layers 10 and on, 4 outside the layers, 8 on
/// the end walls, 16 near the trailing edge (x > 0.9 within 0.05 of the chord line), 32 near
/// the leading edge (x < 0.1 within 0.1 of it), 64 over 2 chords from the mid-chord.
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
            let le = if p[0] < 0.1 && p[1].abs() < 0.1 { 32 } else { 0 };
            let far = if ((p[0] - 0.5).powi(2) + p[1] * p[1]).sqrt() > 2.0 { 64 } else { 0 };
            te | le
                | far
                | match k {
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
