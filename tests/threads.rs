//! Results are bitwise identical for any thread count (DESIGN §5).

use glam::DVec2;
use meshmove::cases::meshes::{free_surface, FS_BOTTOM, FS_LEFT, FS_RIGHT, FS_TOP};
use meshmove::{BoundaryConditions, Kind, Link, Method, Mode, Motion, Options, Solver};

#[test]
fn one_and_two_threads_agree_bitwise() {
    let mesh = free_surface(1.0 / 96.0);
    assert!(mesh.num_vertices() > 8000, "mesh large enough for the parallel paths");
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(FS_BOTTOM, Kind::Fixed).set_kinds(FS_TOP, Kind::Clamped);
    for p in [FS_LEFT, FS_RIGHT] {
        bcs.set_kind(p, 0, Kind::Clamped).unwrap().set_kind(p, 1, Kind::Free).unwrap();
    }
    bcs.add_link(Link::ByOffset { a: FS_LEFT, b: FS_RIGHT, offset: DVec2::X, tol: 1e-9 });
    let mut motion = Motion::zero(mesh.num_vertices());
    for v in mesh.patch_vertices(FS_TOP) {
        let x = mesh.coords()[v as usize].x;
        motion.displacement[v as usize].y = 0.1 * (std::f64::consts::TAU * x).cos();
    }
    for method in [Method::Biharmonic, Method::Laplacian] {
        for mode in [Mode::Default, Mode::PaperFaithful] {
            let run = |threads| {
                let mut o = Options { method, threads, ..Default::default() };
                o.solve.mode = mode;
                o.solve.tol = 1e-6;
                let mut s = Solver::new(&mesh, &bcs, o).unwrap();
                let d = s.solve(&motion).unwrap().displacement;
                s.move_in_steps(&motion, 2).unwrap();
                (d, s.mesh().coords().to_vec())
            };
            let (a, b) = (run(1), run(2));
            assert!(
                a.0.iter().zip(&b.0).all(|(p, q)| p.x.to_bits() == q.x.to_bits() && p.y.to_bits() == q.y.to_bits()),
                "{method:?} {mode:?}"
            );
            assert!(
                a.1.iter().zip(&b.1).all(|(p, q)| p.x.to_bits() == q.x.to_bits() && p.y.to_bits() == q.y.to_bits()),
                "{method:?} {mode:?} steps"
            );
        }
    }
}
