//! The biharmonic's hierarchy on the graded 2D cylinder (`cases::ogrid`, the bench's `graded`
//! case): its rays are lines across the grading, but its cells are not thin wall layers, so its
//! coarse levels take the general rule and K_c V_c⁻¹ K_c (docs/DESIGN.md §5, "Wall layers").

use meshmove::{BoundaryConditions, Kind, Motion, Options, RigidMotion, Solver};
use meshmove_cases::ogrid::{self, CellKind};

/// At 14 568 vertices the rays are lines for the smoother, and the hierarchy coarsens to a
/// coarsest level near the coarsest size (at most a quarter above the 2D coarsest size of 150),
/// which the solve factors. Kept along its rays with assembled Galerkin levels, as under thin
/// wall layers, the cylinder took 12 iterations (and 15 at 120k vertices); with the general rule
/// it takes 7.
#[test]
fn graded_cylinder_coarsens_to_the_coarsest_size() {
    let mesh = ogrid::cylinder_with_vertices(15_000, CellKind::Simplex).unwrap();
    assert_eq!(mesh.num_vertices(), 14_568);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(ogrid::OG_WALL, Kind::Fixed).set_kinds(ogrid::OG_BODY, Kind::Clamped);
    let solver = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    let h = solver.hierarchy();
    assert!(h.has_lines(), "{}", solver.describe());
    let coarsest = h.levels.last().unwrap().op().k.nrows;
    assert!(coarsest <= 187, "coarsest level of {coarsest} unknowns\n{}", solver.describe());
    let r = RigidMotion { translation: [0.1, 0.0, 0.0], rotation: [0.0; 3], center: [0.0; 3] };
    let sol = solver.solve(&Motion::zero(&mesh).with_rigid(ogrid::OG_BODY, r)).unwrap();
    assert!(sol.report.converged, "{:?}", sol.report.rel_residual);
    assert_eq!(sol.quality.inverted, 0);
    assert!(sol.report.cycles <= 8, "{} iterations", sol.report.cycles);
    assert!(h.levels.iter().all(|l| !l.op().is_assembled()), "K_c V_c⁻¹ K_c on every level\n{}", solver.describe());
    assert!(sol.quality.min_area_ratio > 0.99, "{}", sol.quality.min_area_ratio);
}
