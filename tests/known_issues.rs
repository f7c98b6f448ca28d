//! Known failures, kept runnable so the next change can check them:
//! `cargo test --release --test known_issues -- --ignored`.

use meshmove::cases::meshes::FS_TOP;
use meshmove::cases::setups::free_surface_case;
use meshmove::{Method, Motion, Options, Solver};

/// The free surface moved by half its biharmonic solution, then asked for the same top motion
/// again: on that valid mesh (0 inverted) the biharmonic CG stalls. Here (h = 1/256): 500
/// iterations, residual 5.2e-6. On the bench's 67k mesh: residual 5e-2, 3e-3, 8e-4, 3e-4 after
/// 1, 10, 50, 200 iterations, whether the hierarchy is built on the moved mesh or follows it
/// (`set_reference`); the Laplacian takes 6 and spring 15; at 16.8k vertices it converges in
/// 26. Found 2026-11-23, not diagnosed (candidates: the coarse CDT of a wavy boundary, the
/// rediscretised/Galerkin ratio of the coarse operators varying in space).
#[test]
#[ignore = "known stall, see the comment"]
fn biharmonic_converges_on_a_premoved_free_surface() {
    let s = free_surface_case("fs", 1.0 / 128.0, 0.25, 1);
    let mesh = s.mesh.refine_uniform();
    let mut motion = Motion::zero(mesh.num_vertices());
    for v in mesh.patch_vertices(FS_TOP) {
        let x = mesh.coords()[v as usize].x;
        motion.displacement[v as usize].y = 0.25 * (std::f64::consts::TAU * x).cos();
    }
    let opts = Options { method: Method::Biharmonic, ..Default::default() };
    let first = Solver::new(&mesh, &s.bcs, opts.clone()).unwrap().solve(&motion).unwrap();
    let moved: Vec<_> = mesh.coords().iter().zip(&first.displacement).map(|(x, d)| *x + 0.5 * *d).collect();
    let again = Solver::new(&mesh.with_coords(moved), &s.bcs, opts).unwrap().solve(&motion).unwrap();
    assert!(again.report.converged, "{} iterations, residual {:e}", again.report.cycles, again.report.rel_residual);
}
