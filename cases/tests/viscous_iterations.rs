//! The biharmonic's PCG iterations on wall-layered meshes (docs/DESIGN.md §5, "Wall layers"):
//! counts, which do not depend on the machine or the thread timing.

use meshmove::{Method, Options, Solver};
use meshmove_cases::viscous::*;

/// The iterations of one step of `m` by the biharmonic on `v`, and whether the hierarchy found
/// lines across the layers.
fn iterations(v: &ViscousMesh, m: BodyMotion) -> (usize, bool) {
    let solver =
        Solver::new(&v.mesh, &boundary_conditions(v), Options { method: Method::Biharmonic, ..Default::default() })
            .unwrap();
    let sol = solver.solve(&motion(v, m)).unwrap();
    assert!(sol.report.converged, "{:?}", sol.report.rel_residual);
    assert_eq!(sol.quality.inverted, 0);
    (sol.report.cycles, solver.hierarchy().has_lines())
}

#[test]
fn airfoil_biharmonic_takes_a_bounded_number_of_iterations() {
    let v = airfoil_2d(&AirfoilParams::new(64)).unwrap();
    for m in [BodyMotion::Pitch, BodyMotion::Plunge] {
        let (its, lines) = iterations(&v, m);
        assert!(lines);
        assert!(its <= 12, "{m:?}: {its}");
    }
}

#[test]
fn spheroid_biharmonic_takes_a_bounded_number_of_iterations() {
    let v = spheroid_3d(&SpheroidParams::new(4)).unwrap();
    let (its, lines) = iterations(&v, BodyMotion::Pitch);
    assert!(lines);
    assert!(its <= 9, "{its}");
}

/// The 25k-vertex airfoil: its eight levels' coarse biharmonic K_c V_c⁻¹ K_c over-corrected on
/// the deep levels, the W-cycle's two visits per level compounded it until the preconditioned
/// residual overflowed, and CG broke down at its first iteration (pᵀAp not finite).
#[test]
fn airfoil_of_25k_vertices_does_not_break_down() {
    let v = airfoil_2d(&AirfoilParams::new(128)).unwrap();
    let (its, _) = iterations(&v, BodyMotion::Pitch);
    assert!(its <= 12, "{its}");
}
