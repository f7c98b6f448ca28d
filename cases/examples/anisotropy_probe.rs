//! The line finder's anisotropy (strongest over weakest coupling, 1/d², docs/DESIGN.md §5
//! "Wall layers") of each vertex, measured over K's graph (every pair of a cell's corners) and
//! over the cells' edges, on the meshes whose lines decide the rule: the vertices anisotropic
//! over K's graph and their anisotropy over the edges.
//! `cargo run --release -p meshmove-cases --example anisotropy_probe -- [OPENFOAM_CASE_DIR ...]`
use meshmove::io::read_polymesh;
use meshmove::{BoundaryConditions, Kind, Mesh};
use meshmove_cases::setups::{case, Scale};
use meshmove_cases::setups3d::case3d;
use std::path::PathBuf;

fn ratios(mesh: &Mesh) -> Vec<(f64, f64)> {
    let n = mesh.num_vertices();
    let dim = mesh.coords().len() / n;
    let x = mesh.coords();
    let w = |i: usize, j: usize| {
        let d2: f64 = (0..dim).map(|c| (x[i * dim + c] - x[j * dim + c]).powi(2)).sum();
        1.0 / d2
    };
    let mut k = vec![(0.0f64, f64::INFINITY); n];
    let mut e = vec![(0.0f64, f64::INFINITY); n];
    let upd = |b: &mut (f64, f64), v: f64| {
        b.0 = b.0.max(v);
        b.1 = b.1.min(v);
    };
    for c in 0..mesh.num_cells() {
        let cell = mesh.cell(c);
        for (a, &i) in cell.iter().enumerate() {
            for &j in &cell[a + 1..] {
                let v = w(i as usize, j as usize);
                upd(&mut k[i as usize], v);
                upd(&mut k[j as usize], v);
            }
        }
        for &[a, b] in mesh.cell_type(c).edges() {
            let (i, j) = (cell[a as usize] as usize, cell[b as usize] as usize);
            let v = w(i, j);
            upd(&mut e[i], v);
            upd(&mut e[j], v);
        }
    }
    k.iter().zip(&e).map(|(k, e)| (k.0 / k.1, e.0 / e.1)).collect()
}

/// At each vertex anisotropic over K's graph and not prescribed: its strongest free neighbour's
/// coupling over the strongest of its other free neighbours (how much stronger the line's
/// direction is than the rest), and whether its strongest neighbour of all is prescribed.
fn along(mesh: &Mesh, prescribed: &[bool], r: &[(f64, f64)]) {
    let n = mesh.num_vertices();
    let dim = mesh.coords().len() / n;
    let x = mesh.coords();
    let mut nb: Vec<Vec<u32>> = vec![Vec::new(); n];
    for c in 0..mesh.num_cells() {
        let cell = mesh.cell(c);
        for &i in cell {
            for &j in cell {
                if i != j {
                    nb[i as usize].push(j);
                }
            }
        }
    }
    let w = |i: usize, j: usize| {
        let d2: f64 = (0..dim).map(|c| (x[i * dim + c] - x[j * dim + c]).powi(2)).sum();
        1.0 / d2
    };
    let mut out = Vec::new();
    let mut at_wall = 0;
    for i in 0..n {
        if prescribed[i] || r[i].0 < 16.0 {
            continue;
        }
        nb[i].sort_unstable();
        nb[i].dedup();
        let mut free: Vec<f64> =
            nb[i].iter().filter(|&&j| !prescribed[j as usize]).map(|&j| w(i, j as usize)).collect();
        free.sort_by(|a, b| b.total_cmp(a));
        let all = nb[i].iter().map(|&j| (w(i, j as usize), prescribed[j as usize])).fold((0.0, false), |a, b| {
            if b.0 > a.0 {
                b
            } else {
                a
            }
        });
        if all.1 {
            at_wall += 1;
        }
        if free.len() >= 2 {
            out.push(free[0] / free[1]);
        }
    }
    out.sort_by(f64::total_cmp);
    let q = |f: f64| if out.is_empty() { 0.0 } else { out[((out.len() - 1) as f64 * f) as usize] };
    println!(
        "    free candidates {}; strongest at a prescribed vertex {at_wall}; strongest free over next free: min {:.2} q10 {:.2} median {:.2} q90 {:.2} max {:.2}",
        out.len(), q(0.0), q(0.1), q(0.5), q(0.9), q(1.0)
    );
}

fn report(name: &str, mesh: &Mesh, prescribed: &[bool]) {
    let r = ratios(mesh);
    along(mesh, prescribed, &r);
    let cand: Vec<f64> = r.iter().filter(|p| p.0 >= 16.0).map(|p| p.1).collect();
    let mut sorted = cand.clone();
    sorted.sort_by(f64::total_cmp);
    let q = |f: f64| if sorted.is_empty() { 0.0 } else { sorted[((sorted.len() - 1) as f64 * f) as usize] };
    let count = |t: f64| cand.iter().filter(|&&v| v >= t).count();
    let emax = r.iter().map(|p| p.1).fold(0.0, f64::max);
    println!(
        "{name}: {} vertices; K-anisotropic {}; their edge ratio min {:.2} q10 {:.2} median {:.2} q90 {:.2} max {:.2}; >=4 {} >=6 {} >=8 {} >=10 {} >=12 {} >=16 {}; edge max over all {:.2}",
        r.len(),
        cand.len(),
        q(0.0),
        q(0.1),
        q(0.5),
        q(0.9),
        q(1.0),
        count(4.0),
        count(6.0),
        count(8.0),
        count(10.0),
        count(12.0),
        count(16.0),
        emax
    );
}

/// The vertices prescribed in every component by `bcs`.
fn prescribed(mesh: &Mesh, bcs: &BoundaryConditions) -> Vec<bool> {
    let mut p = vec![false; mesh.num_vertices()];
    for id in mesh.patch_ids() {
        if (0..mesh.dim()).all(|c| matches!(bcs.kind(id, c), Kind::Fixed | Kind::Clamped)) {
            for v in mesh.patch_vertices(id) {
                p[v as usize] = true;
            }
        }
    }
    p
}

fn main() {
    for dir in std::env::args().skip(1) {
        let foam = read_polymesh(&PathBuf::from(&dir)).expect("a polyMesh");
        let mesh = foam.to_mesh().expect("a mesh");
        let mut bcs = BoundaryConditions::new();
        for (id, _) in &foam.patch_names {
            bcs.set_kinds(*id, Kind::Fixed);
        }
        report(&dir, &mesh, &prescribed(&mesh, &bcs));
    }
    for n in ["sphere_channel_1.5D_fixed", "sphere_channel_1.5D_slip", "boundary_layer_cylinder", "cylinder_channel"] {
        if let Some(s) = case(n, Scale::Quick) {
            report(n, &s.mesh, &prescribed(&s.mesh, &s.bcs));
        }
    }
    for n in ["boundary_layer_cylinder_3d", "pitching_spheroid_1step", "sphere_channel_0.5"] {
        if let Some(s) = case3d(n, Scale::Quick) {
            report(n, &s.mesh, &prescribed(&s.mesh, &s.bcs));
        }
    }
}
