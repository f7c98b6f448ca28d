//! A rotating CLAMPED body rotates its wall layer (docs/DESIGN.md §4, rigid motion): with the rigid
//! flux the first off-wall vertices follow the rotation; with held spacing they shear.

mod common;
use common::*;
use glam::DVec2;
use meshmove::{BoundaryConditions, Kind, Motion, Options, Solver};

#[test]
fn rotating_clamped_patch_rotates_its_wall_layer() {
    let nt = 48;
    let mesh = annulus(12, nt, 0.5, 3.0, 1.25);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(INNER, Kind::Clamped).set_kinds(OUTER, Kind::Fixed);
    let s = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    let rot = planar(DVec2::ZERO, 0.4, DVec2::ZERO);
    let x = mesh.points_2d();
    let rigid = s.solve(&Motion::zero(&mesh).with_rigid(INNER, rot)).unwrap();
    let per_vertex: Vec<DVec2> =
        x.iter().map(|&x| if x.length() < 0.5001 { rigid_at(&rot, x) } else { DVec2::ZERO }).collect();
    let held = s.solve(&Motion::from_displacement(to_flat(&per_vertex))).unwrap();
    // Ring 1 (the first off-wall vertices) is vertices nt..2nt.
    let err = |d: &[f64]| {
        let d = to_vec2(d);
        (nt..2 * nt).map(|v| (d[v] - rigid_at(&rot, x[v])).length()).fold(0.0, f64::max)
    };
    let (e_rigid, e_held) = (err(&rigid.displacement), err(&held.displacement));
    let wall_motion = rigid_at(&rot, DVec2::new(0.5, 0.0)).length();
    println!("ring-1 deviation from rigid rotation: rigid flux {e_rigid:.2e}, held spacing {e_held:.2e} (wall moves {wall_motion:.3})");
    assert!(e_rigid < 0.1 * e_held, "rigid flux {e_rigid:e} vs held {e_held:e}");
    assert!(e_rigid < 0.02 * wall_motion);
    assert_eq!(s.quality(&rigid.displacement).inverted, 0);
}
