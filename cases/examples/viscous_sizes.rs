//! Builds the wall-layered meshes at the given sizes and prints their counts and shape:
//! `cargo run --release -p meshmove-cases --example viscous_sizes -- airfoil 64 128`
//! (kinds `airfoil` (points per side), `spheroid` (cells across), `wing` (points per side,
//! span cells as `P:S`)).

use meshmove_cases::viscous::*;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((kind, sizes)) = args.split_first() else {
        eprintln!("usage: viscous_sizes airfoil|spheroid|wing SIZE…");
        std::process::exit(2);
    };
    for s in sizes {
        let t = Instant::now();
        let m = by_name(kind, s);
        match m {
            Ok(m) => {
                let q = mesh_quality(&m);
                println!(
                    "{kind} {s}: {} vertices, {} cells, max aspect {:.0}, min angle {:.2}°, wall-normal edge {:.3e}, {:.1} s",
                    q.vertices,
                    q.cells,
                    q.max_aspect_ratio,
                    q.min_angle_deg,
                    q.wall_normal_edge,
                    t.elapsed().as_secs_f64()
                );
            }
            Err(e) => println!("{kind} {s}: {e}"),
        }
    }
}
