//! The runs whose multigrid did not converge (cases/examples/convergence_check.rs), redone with the
//! exact discrete solve of every step (`report::run_case_reference`): is the result the method's
//! or the solver's? (docs/RESULTS.md)
use meshmove::mesh::quality;
use meshmove::Method;
use meshmove_cases::report::*;
use meshmove_cases::setups::*;
fn main() {
    for name in ["free_surface_a0.25_10steps", "deforming_interface_A", "deforming_interface_B"] {
        let s = case(name, Scale::Paper).unwrap();
        let t = std::time::Instant::now();
        match run_case_reference(&s, Method::Spring, 1e-10) {
            Ok((coords, first)) => {
                let q = quality(&s.mesh, &coords);
                let pm = patch_measures(&s.mesh, &coords, s.moved_patch, s.upper_region);
                println!("{name} spring exact: inverted {} (first at step {first:?}), min area ratio {:.4}, spacing var {:.3} ({:.1} s)",
                    q.inverted, q.min_area_ratio, pm.spacing_variation, t.elapsed().as_secs_f64());
            }
            Err(e) => println!("{name} spring exact: {e}"),
        }
    }
}
