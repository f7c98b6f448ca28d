//! The biharmonic's PCG iterations on wall-layered meshes (docs/DESIGN.md §5, "Wall layers"):
//! counts, which do not depend on the machine or the thread timing.

use meshmove::{Method, Options, Solver};
use meshmove_cases::viscous::*;

/// The biharmonic's solver on `v` with its boundary conditions.
fn biharmonic(v: &ViscousMesh) -> Solver {
    Solver::new(&v.mesh, &boundary_conditions(v), Options { method: Method::Biharmonic, ..Default::default() }).unwrap()
}

/// The smallest volume ratio of the biharmonic's solve of `m` on `v` to a relative residual of
/// 1e-11.
fn tight_min_volume_ratio(v: &ViscousMesh, m: &meshmove::Motion) -> f64 {
    let opts = Options {
        method: Method::Biharmonic,
        solve: meshmove::SolveParams { tol: 1e-11, ..Default::default() },
        ..Default::default()
    };
    let tight = Solver::new(&v.mesh, &boundary_conditions(v), opts).unwrap().solve(m).unwrap();
    assert!(tight.report.converged, "{:?}", tight.report);
    tight.quality.min_area_ratio
}

/// The iterations of one step of `m` by the biharmonic on `v`, and whether the hierarchy found
/// lines across the layers.
fn iterations(v: &ViscousMesh, m: BodyMotion) -> (usize, bool) {
    let solver = biharmonic(v);
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
        assert!(its <= 7, "{m:?}: {its}");
    }
}

/// The wing section (the airfoil extruded between two SLIP end walls, hexahedral layers): its
/// kept levels keep its lines where their unknowns couple along them, and coarsen on to a
/// factored coarsest level (docs/DESIGN.md §5); the smallest size's pitch holds a fixed count,
/// the iterations its first layer needs beyond the residual's 1e-8 (the stop test under wall
/// layers) included.
#[test]
fn wing_biharmonic_takes_a_bounded_number_of_iterations() {
    let v = wing_3d(&WingParams::new(32, 4)).unwrap();
    for m in [BodyMotion::Pitch, BodyMotion::Plunge] {
        let (its, lines) = iterations(&v, m);
        assert!(lines);
        assert!(its <= 5, "{m:?}: {its}");
    }
}

/// Under 3D wall layers the cycle visits the levels from the fifth on once (the W-cycle's
/// second visits there cost most of a cycle and no iteration, docs/DESIGN.md §5); the 2D
/// hierarchies, which lose iterations without them, keep the W-cycle on every level.
#[test]
fn deep_levels_under_3d_layers_are_visited_once() {
    use meshmove::multigrid::policy::CycleParams;
    let once_from = |v: &ViscousMesh| CycleParams::resolve(biharmonic(v).hierarchy(), &Default::default()).once_from;
    let wing = wing_3d(&WingParams::new(32, 4)).unwrap();
    assert_eq!(once_from(&wing), 4);
    let airfoil = airfoil_2d(&AirfoilParams::new(64)).unwrap();
    assert_eq!(once_from(&airfoil), usize::MAX);
}

#[test]
fn spheroid_biharmonic_takes_a_bounded_number_of_iterations() {
    let v = spheroid_3d(&SpheroidParams::new(4)).unwrap();
    for (m, cap) in [(BodyMotion::Pitch, 4), (BodyMotion::Plunge, 4)] {
        let (its, lines) = iterations(&v, m);
        assert!(lines);
        assert!(its <= cap, "{m:?}: {its}");
    }
}

/// The smallest spheroid's pitch and plunge stop at the tight solve's mesh: their smallest volume
/// ratios within 5e-4 of the same systems solved to 1e-11.
#[test]
fn spheroid_stops_at_the_tight_solves_mesh() {
    let v = spheroid_3d(&SpheroidParams::new(4)).unwrap();
    for m in [BodyMotion::Pitch, BodyMotion::Plunge] {
        let m = motion(&v, m);
        let sol = biharmonic(&v).solve(&m).unwrap();
        assert!(sol.report.converged && sol.quality.inverted == 0, "{:?}", sol.report);
        let (got, want) = (sol.quality.min_area_ratio, tight_min_volume_ratio(&v, &m));
        assert!((got - want).abs() < 5e-4, "min volume ratio {got} against the tight solve's {want}");
    }
}

/// The pitch turns the spheroid about z, which moves z by rounding alone: every method solves
/// that component as zero (its interior exactly 0, the wall's values as given) instead of to the
/// tolerance against a right-hand side of rounding, and the pitch takes the plunge's count.
#[test]
fn spheroid_pitch_solves_its_axis_component_of_rounding_as_zero() {
    let v = spheroid_3d(&SpheroidParams::new(4)).unwrap();
    let m = motion(&v, BodyMotion::Pitch);
    let vals = m.vertex_values(&v.mesh).into_owned();
    let on_wall: std::collections::HashSet<u32> = v.mesh.patch_vertices(WALL).iter().copied().collect();
    for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
        let solver = Solver::new(&v.mesh, &boundary_conditions(&v), Options { method, ..Default::default() }).unwrap();
        let sol = solver.solve(&m).unwrap();
        for p in 0..v.mesh.num_vertices() {
            let want = if on_wall.contains(&(p as u32)) { vals[p * 3 + 2] } else { 0.0 };
            assert_eq!(sol.displacement[p * 3 + 2], want, "{method:?}: vertex {p}");
        }
        if method == Method::Biharmonic {
            assert!(sol.report.cycles <= 4, "{}", sol.report.cycles);
        }
    }
}

/// Under wall layers the kept levels interpolate from a few donors each, so the Galerkin levels
/// stay sparse: every row of every transfer has at most 24 entries (12, or in 3D 24 where 12
/// candidates only extrapolate; all strongly coupled kept neighbours, the choice elsewhere,
/// reach over 64 on the spheroid's deep levels), and the levels' applied operators sum to a
/// bounded multiple of the finest level's K.
#[test]
fn spheroid_kept_levels_stay_sparse() {
    let v = spheroid_3d(&SpheroidParams::new(4)).unwrap();
    let solver = biharmonic(&v);
    let levels = &solver.hierarchy().levels;
    assert!(levels.len() >= 4, "{}", solver.describe());
    for (l, level) in levels.iter().enumerate() {
        if let Some(p) = level.prolong() {
            let widest = (0..p.nrows).map(|i| p.row(i).0.len()).max().unwrap();
            assert!(widest <= 24, "level {l}: a row of {widest} donors");
        }
    }
    let applied: usize = levels.iter().map(|l| l.op().assembled_nnz().unwrap_or(l.op().k.nnz())).sum();
    let complexity = applied as f64 / levels[0].op().k.nnz() as f64;
    assert!(complexity <= 6.0, "operator complexity {complexity}\n{}", solver.describe());
}

/// The 25k-vertex airfoil: its eight levels' coarse biharmonic K_c V_c⁻¹ K_c over-corrected on
/// the deep levels, the W-cycle's two visits per level compounded it until the preconditioned
/// residual overflowed, and CG broke down at its first iteration (pᵀAp not finite).
#[test]
fn airfoil_of_25k_vertices_does_not_break_down() {
    let v = airfoil_2d(&AirfoilParams::new(128)).unwrap();
    let (its, _) = iterations(&v, BodyMotion::Pitch);
    assert!(its <= 9, "{its}");
}

/// A cold solve starts the lines hanging off the clamped body at its rigid motion and the rest
/// of the mesh falling off from it to the far field (docs/DESIGN.md §5, "The first iterate"),
/// and the stop test under wall layers holds in 2D too: the largest airfoil's plunge keeps its
/// first layer within 1 % (from a zero start, with the test in 3D only, it left the first layer
/// 1.1 % off) and takes a few iterations (6; 11 when the start was zero beyond the lines' outer
/// ends, whose jump the stop test on every edge's stretch sees the more the finer the mesh).
#[test]
fn largest_airfoil_plunge_keeps_its_first_layer() {
    let v = airfoil_2d(&AirfoilParams::new(256)).unwrap();
    let solver = biharmonic(&v);
    let sol = solver.solve(&motion(&v, BodyMotion::Plunge)).unwrap();
    assert!(sol.report.converged && sol.quality.inverted == 0, "{:?}", sol.report);
    assert!(sol.report.cycles <= 7, "{}", sol.report.cycles);
    let moved: Vec<f64> = v.mesh.coords().iter().zip(&sol.displacement).map(|(x, d)| x + d).collect();
    let (lo, hi) = layer_volume_ratios(&v, &moved, 1).unwrap();
    assert!(lo > 0.99 && hi < 1.01, "first layer {lo}..{hi}");
}

/// The start along the lines leaves its error at the lines' outer ends, where the rows are tiny
/// against the wall's and a relative residual of 1e-8 does not see it: the smallest airfoil's
/// pitch met 1e-8 in two iterations with its smallest volume ratio 0.970 against the converged
/// 0.981. The stop test on every edge's stretch (docs/DESIGN.md §5, "The tolerance and the
/// thinnest cells") holds the solve on until the mesh is the tight solve's within the
/// tolerance's meaning.
#[test]
fn start_along_the_lines_stops_at_the_tight_solves_mesh() {
    let v = airfoil_2d(&AirfoilParams::new(64)).unwrap();
    let m = motion(&v, BodyMotion::Pitch);
    let sol = biharmonic(&v).solve(&m).unwrap();
    assert!(sol.report.converged && sol.quality.inverted == 0, "{:?}", sol.report);
    let (got, want) = (sol.quality.min_area_ratio, tight_min_volume_ratio(&v, &m));
    assert!((got - want).abs() < 5e-4, "min volume ratio {got} against the tight solve's {want}");
}

/// The start falling off beyond the lines' outer ends leaves the largest airfoil's plunge at
/// most two iterations more than the smallest's (5 against 4; 11 against 7 with the start zero
/// beyond the lines), and the
/// mesh it stops at is the tight solve's: its smallest volume ratio within 5e-4 of the same
/// system solved to 1e-11.
#[test]
fn largest_airfoil_plunge_takes_about_the_smallest_ones_count() {
    let small = airfoil_2d(&AirfoilParams::new(64)).unwrap();
    let (few, _) = iterations(&small, BodyMotion::Plunge);
    let v = airfoil_2d(&AirfoilParams::new(256)).unwrap();
    let m = motion(&v, BodyMotion::Plunge);
    let sol = biharmonic(&v).solve(&m).unwrap();
    assert!(sol.report.converged && sol.quality.inverted == 0, "{:?}", sol.report);
    assert!(sol.report.cycles <= few + 2, "{} against the smallest airfoil's {few}", sol.report.cycles);
    let (got, want) = (sol.quality.min_area_ratio, tight_min_volume_ratio(&v, &m));
    assert!((got - want).abs() < 5e-4, "min volume ratio {got} against the tight solve's {want}");
}

/// The largest airfoil takes at most one iteration more than the smallest on either motion (5
/// against 4, issue 27's growth of at most 1.3×): below its lines its hierarchy stops at a
/// coarsest level of up to 800 unknowns, factored, where it took 6 while it coarsened on to
/// 106 unknowns through levels whose W-cycle lost more of the slow error the more of them there
/// were (docs/DESIGN.md §5, "Coarse levels").
#[test]
fn largest_airfoil_takes_at_most_one_more_than_the_smallest() {
    let small = airfoil_2d(&AirfoilParams::new(64)).unwrap();
    let large = airfoil_2d(&AirfoilParams::new(256)).unwrap();
    for m in [BodyMotion::Pitch, BodyMotion::Plunge] {
        let (few, _) = iterations(&small, m);
        let (its, lines) = iterations(&large, m);
        assert!(lines);
        assert!(its <= few + 1, "{m:?}: {its} against the smallest airfoil's {few}");
    }
}
