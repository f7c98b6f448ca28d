//! Where a viscous mesh's one-step biharmonic error sits after a few iterations: `cargo run
//! --release -p meshmove-cases --example error_probe -- spheroid 8 pitch|plunge ITS,ITS,...`.
//! The error against the solve to 1e-11, binned by the vertex's wall layer and its position
//! along the body's long axis (x).

use meshmove::{Options, Solver};
use meshmove_cases::viscous::*;

#[path = "common/viscous_args.rs"]
mod viscous_args;
use viscous_args::kind_size_motion;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (kind, size, m) = kind_size_motion(&args);
    let its: Vec<usize> = args.get(3).map_or("1,3", |s| s.as_str()).split(',').map(|s| s.parse().unwrap()).collect();
    let v = by_name(kind, size).expect("a mesh");
    let bcs = boundary_conditions(&v);
    let motion = motion(&v, m);
    let solve = |tol: f64, max_cycles: usize| {
        let opts =
            Options { solve: meshmove::SolveParams { tol, max_cycles, ..Default::default() }, ..Default::default() };
        let solver = Solver::new(&v.mesh, &bcs, opts).expect("a solver");
        solver.solve_report(&motion, None).expect("a solve").displacement
    };
    let exact = solve(1e-11, 500);
    let nv = v.mesh.num_vertices();
    let mut layer = vec![u32::MAX; nv];
    for c in 0..v.mesh.num_cells() {
        for &p in v.mesh.cell(c) {
            layer[p as usize] = layer[p as usize].min(v.cell_layer[c]);
        }
    }
    let coords = v.mesh.coords();
    let scale = exact.chunks(3).map(|d| d.iter().map(|x| x * x).sum::<f64>().sqrt()).fold(0.0, f64::max);
    let lbin = |l: u32| match l {
        0..=4 => 0,
        5..=14 => 1,
        15..=u32::MAX if l != u32::MAX => 2,
        _ => 3,
    };
    let lnames = ["layers 0-4", "layers 5-14", "layers 15+", "beyond"];
    let xbin = |x: f64| match x.abs() / 0.5 {
        r if r < 0.6 => 0,
        r if r < 0.9 => 1,
        r if r < 0.99 => 2,
        _ => 3,
    };
    let xnames = ["|x|<0.3", "0.3-0.45", "0.45-0.495", "tips"];
    for &k in &its {
        let x = solve(1e-30, k);
        println!("{kind} {size} {} after {k} iterations (error / largest displacement {scale:.3e}):", m.name());
        let mut most = [[0.0f64; 4]; 4];
        let mut sum = [[0.0f64; 4]; 4];
        let mut cnt = [[0usize; 4]; 4];
        let mut comp = [[0.0f64; 3]; 4];
        for p in 0..nv {
            let e: Vec<f64> = (0..3).map(|c| x[p * 3 + c] - exact[p * 3 + c]).collect();
            let n = e.iter().map(|x| x * x).sum::<f64>().sqrt() / scale;
            let (a, b) = (lbin(layer[p]), xbin(coords[p * 3]));
            most[a][b] = most[a][b].max(n);
            sum[a][b] += n * n;
            cnt[a][b] += 1;
            for c in 0..3 {
                comp[a][c] = comp[a][c].max(e[c].abs() / scale);
            }
        }
        println!("  {:12} {}", "", xnames.map(|s| format!("{s:>22}")).join(""));
        for a in 0..4 {
            let row: String = (0..4)
                .map(|b| {
                    let rms = if cnt[a][b] > 0 { (sum[a][b] / cnt[a][b] as f64).sqrt() } else { 0.0 };
                    format!("  {:9.2e}/{:9.2e}", most[a][b], rms)
                })
                .collect();
            println!("  {:12} {row}   max x,y,z {:.2e} {:.2e} {:.2e}", lnames[a], comp[a][0], comp[a][1], comp[a][2]);
        }
    }
}
