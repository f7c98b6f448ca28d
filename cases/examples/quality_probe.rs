//! The quality check of a moved mesh (`meshmove::mesh::quality`, what every step runs on its
//! result), in CPU seconds per run: the bench's box of N³ cells, its vertices moved off the grid
//! by a smooth field, measured against the box; with the quality's values and a hash of their
//! bits (bitwise checks of a change):
//! `cargo run --release -p meshmove-cases --example quality_probe -- [hex|tet] [N] [REPEATS]`
//! (default `hex 62 10`: the 250k box).

use meshmove_cases::boxes::{structured_box, BoxCells};
use meshmove_cases::report::thread_cpu_seconds;
use std::hash::{Hash, Hasher};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let cells = if args.first().map(|s| s.as_str()) == Some("tet") { BoxCells::Tets } else { BoxCells::Hexes };
    let n: usize = args.get(1).map_or(62, |s| s.parse().expect("cells per side"));
    let repeats: usize = args.get(2).map_or(10, |s| s.parse().expect("repeats"));
    let mesh = structured_box(n, cells);
    let h = 1.0 / n as f64;
    let moved: Vec<f64> = mesh
        .coords()
        .chunks(3)
        .flat_map(|x| {
            let s = |a: f64, b: f64| 0.3 * h * (7.0 * a + 3.0 * b).sin();
            [x[0] + s(x[1], x[2]), x[1] + s(x[2], x[0]), x[2] + s(x[0], x[1]) + 0.1 * x[2] * x[0]]
        })
        .collect();
    let mut q = meshmove::mesh::quality(&mesh, &moved);
    let c0 = thread_cpu_seconds();
    for _ in 0..repeats {
        q = meshmove::mesh::quality(&mesh, &moved);
    }
    let cpu = (thread_cpu_seconds() - c0) / repeats as f64;
    let mut hash = std::collections::hash_map::DefaultHasher::new();
    let values = [q.min_corner_jacobian_ratio, q.min_area_ratio, q.max_area_ratio, q.min_angle_deg];
    (q.inverted, q.non_positive_measure).hash(&mut hash);
    values.iter().for_each(|v| v.to_bits().hash(&mut hash));
    println!(
        "{} cells: quality {cpu:.4} CPU s per run; inverted {}, min volume ratio {}, max {}, min corner Jacobian ratio {}, min angle {}°; hash {:016x}",
        mesh.num_cells(),
        q.inverted,
        q.min_area_ratio,
        q.max_area_ratio,
        q.min_corner_jacobian_ratio,
        q.min_angle_deg,
        hash.finish()
    );
}
