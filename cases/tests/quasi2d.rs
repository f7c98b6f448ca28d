//! Quasi-2D meshes (docs/DESIGN.md §5 "Thin slabs"): the 2D cylinder in a channel extruded one
//! layer of wedges between two symmetry planes, as finite-volume codes run 2D flows. Its
//! hierarchy coarsens within the planes, it converges in the 2D case's iterations, its motion is
//! the 2D case's on both planes, and SLIP planes give bitwise the per-component result.

use meshmove::{Method, Options, Solver};
use meshmove_cases::setups::{cylinder_channel_case, CaseSetup};
use meshmove_cases::setups3d::{slab_case, SymmetryPlanes};

/// Levels, cycles and the displacement of a one-step solve of `case`.
fn solve(case: &CaseSetup, method: Method) -> (usize, usize, Vec<f64>) {
    let mut o = Options { method, threads: 1, ..Default::default() };
    o.solve.tol = 1e-10;
    let solver = Solver::new(&case.mesh, &case.bcs, o).unwrap();
    let sol = solver.solve(&case.motion).unwrap();
    assert!(sol.report.converged, "{}: not converged", case.name);
    (solver.num_levels(), sol.report.cycles, sol.displacement)
}

#[test]
fn a_thin_slab_coarsens_and_moves_as_its_2d_section() {
    let flat = cylinder_channel_case(1.0 / 8.0);
    let nv = flat.mesh.num_vertices();
    let mut failed = Vec::new();
    for method in [Method::Biharmonic, Method::Laplacian] {
        let (levels2, cycles2, d2) = solve(&flat, method);
        for thickness in [0.1, 0.02] {
            let slab = slab_case(&flat, thickness, SymmetryPlanes::PerComponent);
            let (levels, cycles, d3) = solve(&slab, method);
            // Both planes move as the 2D mesh does, and not at all across.
            let mut err = 0.0f64;
            for v in 0..nv {
                for plane in [v, v + nv] {
                    err = err.max((d3[3 * plane] - d2[2 * v]).abs()).max((d3[3 * plane + 1] - d2[2 * v + 1]).abs());
                    assert_eq!(d3[3 * plane + 2], 0.0);
                }
            }
            println!(
                "{method:?}, thickness {thickness}: 2D {levels2} levels, {cycles2} cycles; slab {levels} levels, \
                 {cycles} cycles, largest in-plane difference {err:.2e}"
            );
            // Iterations: the slab's smoother also meets the coupling across the layer, which
            // the 2D mesh has not (docs/DESIGN.md §5, "Thin slabs").
            let most = cycles2 + if thickness < 0.05 { 100 } else { 8 };
            if levels < 2 || cycles > most || err >= 1e-7 {
                failed.push(format!("{method:?}, thickness {thickness}: {levels} levels, {cycles} cycles, {err:e}"));
            }
        }
    }
    assert!(failed.is_empty(), "{failed:?}");
}

#[test]
fn slip_symmetry_planes_give_bitwise_the_per_component_result() {
    let flat = cylinder_channel_case(1.0 / 8.0);
    for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
        let slip = solve(&slab_case(&flat, 0.1, SymmetryPlanes::Slip), method);
        let per_component = solve(&slab_case(&flat, 0.1, SymmetryPlanes::PerComponent), method);
        assert_eq!(slip.0, per_component.0, "{method:?}: levels");
        assert_eq!(slip.1, per_component.1, "{method:?}: cycles");
        assert!(slip.2.iter().zip(&per_component.2).all(|(a, b)| a.to_bits() == b.to_bits()), "{method:?}");
    }
}
