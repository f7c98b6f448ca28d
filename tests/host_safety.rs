//! What a host relies on from the Rust API: a total motion from the original mesh that follows
//! a cleared rigid motion, failing calls that leave every observable state as it was, and
//! progress with cancellation.

mod common;
use common::*;
use meshmove::{BoundaryConditions, Motion, Options, ReferenceMode, RigidMotion, Solver};

fn grid_solver(reference: ReferenceMode) -> (meshmove::Mesh, Solver) {
    let mesh = Grid::new(6, 6).jitter(0.2).mesh();
    let opts = Options { reference, ..Default::default() };
    let s = Solver::new(&mesh, &BoundaryConditions::new(), opts).unwrap();
    (mesh, s)
}

/// A displacement of `d` on every vertex of `patch`, nothing elsewhere.
fn on_patch(mesh: &meshmove::Mesh, patch: i32, d: [f64; 2]) -> Motion {
    let mut m = Motion::zero(mesh);
    for v in mesh.patch_vertices(patch) {
        m.displacement[v as usize * 2..v as usize * 2 + 2].copy_from_slice(&d);
    }
    m
}

#[test]
fn a_displacement_after_a_cleared_rigid_motion_moves_the_patch_in_both_modes() {
    for mode in [ReferenceMode::Incremental, ReferenceMode::Original] {
        let (mesh, mut s) = grid_solver(mode);
        let shift = RigidMotion::translation([0.1, 0.0, 0.0]);
        s.advance(&Motion::zero(&mesh).with_rigid(TOP, shift)).unwrap();
        s.advance(&on_patch(&mesh, TOP, [0.0, 0.05])).unwrap();
        let x = s.current_coords();
        for v in mesh.patch_vertices(TOP) {
            let (v, p) = (v as usize, mesh.point(v as usize));
            assert!((x[v * 2] - (p[0] + 0.1)).abs() < 1e-12, "{mode:?}: vertex {v} x {}", x[v * 2]);
            assert!((x[v * 2 + 1] - (p[1] + 0.05)).abs() < 1e-12, "{mode:?}: vertex {v} y {}", x[v * 2 + 1]);
        }
    }
}

#[test]
fn a_rigid_motion_after_a_displacement_starts_where_the_patch_is() {
    for mode in [ReferenceMode::Incremental, ReferenceMode::Original] {
        let (mesh, mut s) = grid_solver(mode);
        s.advance(&on_patch(&mesh, TOP, [0.0, 0.05])).unwrap();
        let turn = RigidMotion::planar([0.0, 0.0], 0.1, [0.5, 1.0]);
        s.advance(&Motion::zero(&mesh).with_rigid(TOP, turn)).unwrap();
        let x = s.current_coords();
        for v in mesh.patch_vertices(TOP) {
            let (v, p) = (v as usize, mesh.point(v as usize));
            let want = turn.apply(&[p[0], p[1] + 0.05]);
            for c in 0..2 {
                assert!((x[v * 2 + c] - want[c]).abs() < 1e-12, "{mode:?}: vertex {v}");
            }
        }
    }
}
