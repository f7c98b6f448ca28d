//! How long reading and writing a mesh takes: the `n`³ hexahedral box (default 62: 250047
//! vertices) written in each `.vtu` encoding by `write_vtu_as` (the mesh alone) and by
//! `write_deformed_as` (a displacement and the cells' quality fields too), read back by
//! `read_vtu` (and built into a `Mesh`), and any `.msh` files given read by `read_msh` (which
//! builds the `Mesh`). Prints the best of three runs of each, in seconds, and the file sizes.
//!
//! `cargo run --release -p meshmove-cases --example io_timing -- [N] [FILE.msh ...]`

use meshmove::io::{read_msh, read_vtu, write_deformed_as, write_vtu_as, VtuEncoding};
use meshmove_cases::boxes::{structured_box, BoxCells};
use std::time::Instant;

/// The shortest of three runs of `f`, in seconds.
fn best_of_3(mut f: impl FnMut()) -> f64 {
    (0..3)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(62);
    let mesh = structured_box(n, BoxCells::Hexes);
    let data = mesh.to_data();
    let disp: Vec<f64> = mesh.coords().iter().map(|x| 0.01 * (3.0 * x).sin()).collect();
    let dir = std::env::temp_dir().join(format!("meshmove-io-timing-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    println!("{n}^3 hexahedra: {} vertices, {} cells", mesh.num_vertices(), mesh.num_cells());
    println!("| file | write mesh s | write_deformed s | read s | read + Mesh s | MB |");
    println!("|---|---|---|---|---|---|");
    for enc in [VtuEncoding::Binary, VtuEncoding::Compressed, VtuEncoding::Ascii] {
        let path = dir.join(format!("box_{enc:?}.vtu"));
        let plain = best_of_3(|| write_vtu_as(&path, &data, &[], &[], enc).expect("written"));
        let write = best_of_3(|| write_deformed_as(&path, &data, &disp, enc).expect("written"));
        let read = best_of_3(|| drop(read_vtu(&path).expect("read")));
        let build = best_of_3(|| drop(read_vtu(&path).expect("read").to_mesh().expect("a mesh")));
        let mb = std::fs::metadata(&path).map_or(0.0, |m| m.len() as f64 / 1e6);
        println!("| .vtu {enc:?} | {plain:.3} | {write:.3} | {read:.3} | {build:.3} | {mb:.1} |");
    }
    for file in args.iter().skip(1) {
        let read = best_of_3(|| drop(read_msh(std::path::Path::new(file)).expect("read")));
        let mb = std::fs::metadata(file).map_or(0.0, |m| m.len() as f64 / 1e6);
        println!("| {file} (read_msh) | | | | {read:.3} | {mb:.1} |");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
