//! Which of the paper's cases find lines across wall layers (docs/DESIGN.md §5, "Wall layers"),
//! and the iterations of each method on them: one step, or the most of any step.
use meshmove::{Method, Options, Solver};
use meshmove_cases::setups::{case, Scale};
use meshmove_cases::setups3d::case3d;

fn main() {
    let names2d = [
        "free_surface_a0.25",
        "free_surface_a0.25_10steps",
        "deforming_interface_A",
        "cylinder_channel",
        "cylinder_channel_1.5D_slip",
        "boundary_layer_cylinder",
        "boundary_layer_cylinder_hybrid",
    ];
    let cases = names2d
        .iter()
        .map(|n| case(n, Scale::Paper).expect("a 2D case"))
        .chain(["boundary_layer_cylinder_3d"].iter().map(|n| case3d(n, Scale::Quick).expect("a 3D case")));
    for s in cases {
        for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
            let mut solver = Solver::new(&s.mesh, &s.bcs, Options { method, ..Default::default() }).unwrap();
            let lines = solver.hierarchy().has_lines();
            let its = if s.steps == 1 {
                solver.solve(&s.motion).map(|r| r.report.cycles).unwrap_or(0)
            } else {
                match solver.move_in_steps(&s.motion, s.steps) {
                    Ok(reps) => reps.iter().map(|r| r.cycles).max().unwrap_or(0),
                    Err(_) => 0,
                }
            };
            println!("{:32} {method:?}: lines {lines}, iterations {its}", s.name);
        }
    }
}
