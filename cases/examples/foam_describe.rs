//! The multigrid hierarchy `meshmove deform` builds on an OpenFOAM case of
//! `scripts/peer-openfoam-steps.sh` (the unit cube minus a sphere; patches `sphere` and `walls`):
//! per method whether lines were found, the setup's seconds and `Solver::describe`:
//! `cargo run --release -p meshmove-cases --example foam_describe -- CASE_DIR [METHODS]`
//! (METHODS: `b`, `l` letters, default `bl`; the sphere clamped for the biharmonic and fixed for
//! the Laplacian, every other patch fixed; one thread).

use meshmove::io::read_polymesh;
use meshmove::{BoundaryConditions, Kind, Method, Options, Solver};
use std::path::PathBuf;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = PathBuf::from(args.first().expect("an OpenFOAM case directory"));
    let methods = args.get(1).map_or("bl", |s| s.as_str());
    let foam = read_polymesh(&dir).expect("a polyMesh");
    let mesh = foam.to_mesh().expect("a mesh");
    let sphere = foam.patch_names.iter().find(|(_, n)| n == "sphere").expect("a patch `sphere`").0;
    println!("{}: {} vertices, {} cells", dir.display(), mesh.num_vertices(), mesh.num_cells());
    for c in methods.chars() {
        let (method, body) = match c {
            'b' => (Method::Biharmonic, Kind::Clamped),
            'l' => (Method::Laplacian, Kind::Fixed),
            _ => panic!("methods are b, l"),
        };
        let mut bcs = BoundaryConditions::new();
        for (id, _) in &foam.patch_names {
            bcs.set_kinds(*id, if *id == sphere { body } else { Kind::Fixed });
        }
        let t = Instant::now();
        let solver = Solver::new(&mesh, &bcs, Options { method, threads: 1, ..Default::default() }).expect("a solver");
        println!("{method:?}: lines {}, setup {:.2} s", solver.hierarchy().has_lines(), t.elapsed().as_secs_f64());
        print!("{}", solver.describe());
    }
}
