use meshmove::cases::report::*;
use meshmove::cases::setups::*;
use meshmove::{Method, Mode, Options};
fn main() {
    let s = case("boundary_layer_cylinder", Scale::Paper).unwrap();
    println!("nv {} nc {}", s.mesh.num_vertices(), s.mesh.num_cells());
    for m in [Method::Biharmonic, Method::Spring] {
        for (mode, maxc) in [(Mode::Default, 500), (Mode::Default, 5000), (Mode::PaperFaithful, 5000)] {
            let mut o = Options::default();
            o.solve.mode = mode;
            o.solve.max_cycles = maxc;
            let r = run_case(&s, m, &o).unwrap();
            let rep = &r.reports[0];
            println!(
                "{m:?} {mode:?} {maxc}: inv {} cycles {} rel {:e} conv {} secs {:.2} wall {:?}",
                r.inverted, rep.cycles, rep.rel_residual, rep.converged, r.seconds, r.patch.area_ratio
            );
        }
    }
}
