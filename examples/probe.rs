use glam::DVec2;
use meshmove::cases::meshes::{free_surface, FS_BOTTOM, FS_LEFT, FS_RIGHT, FS_TOP};
use meshmove::*;
use std::time::Instant;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let h: f64 = args[1].parse().unwrap();
    let refs: usize = args[2].parse().unwrap();
    let deg: usize = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(3);
    let t = Instant::now();
    let mut mesh = free_surface(h);
    println!("base {} verts {:.2}s", mesh.num_vertices(), t.elapsed().as_secs_f64());
    for _ in 0..refs {
        mesh = mesh.refine_uniform();
    }
    println!("fine {} verts {:.2}s", mesh.num_vertices(), t.elapsed().as_secs_f64());
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(FS_BOTTOM, Kind::Fixed).set_kinds(FS_TOP, Kind::Clamped);
    for p in [FS_LEFT, FS_RIGHT] {
        bcs.set_kind(p, 0, Kind::Clamped).unwrap().set_kind(p, 1, Kind::Free).unwrap();
    }
    bcs.add_link(Link::ByOffset { a: FS_LEFT, b: FS_RIGHT, offset: DVec2::X, tol: 1e-9 });
    let mut motion = Motion::zero(mesh.num_vertices());
    for v in mesh.patch_vertices(FS_TOP) {
        let x = mesh.coords()[v as usize].x;
        motion.displacement[v as usize].y = 0.25 * (std::f64::consts::TAU * x).cos();
    }
    for method in [Method::Biharmonic, Method::Laplacian] {
        for mode in [Mode::Default] {
            let mut o = Options { method, threads: 2, ..Default::default() };
            o.solve.mode = mode;
            o.solve.cheb_degree = deg;
            if let Some(r) = args.get(4) {
                o.solve.cheb_lower_ratio = Some(r.parse().unwrap());
            }
            let t = Instant::now();
            let s = Solver::new(&mesh, &bcs, o).unwrap();
            let ts = t.elapsed().as_secs_f64();
            let t = Instant::now();
            let r = s.solve(&motion).unwrap().report;
            println!(
                "{method:?} {mode:?} levels {} setup {ts:.2} solve {:.2} cycles {} rel {:.1e}",
                s.num_levels(),
                t.elapsed().as_secs_f64(),
                r.cycles,
                r.rel_residual
            );
        }
    }
}
