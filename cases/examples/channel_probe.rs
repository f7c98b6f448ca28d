use meshmove::Options;
use meshmove_cases::report::*;
use meshmove_cases::setups::*;
fn main() {
    for h in [1.0 / 8.0, 1.0 / 12.0, 1.0 / 16.0, 1.0 / 24.0] {
        let s = cylinder_channel_case(h);
        for m in METHODS {
            let r = run_case(&s, m, &Options::default()).unwrap();
            println!(
                "h=1/{:.0} nv {} {:?}: inverted {} wall area {:.3}..{:.3} conv {}",
                1.0 / h,
                s.mesh.num_vertices(),
                m,
                r.inverted,
                r.patch.area_ratio.0,
                r.patch.area_ratio.1,
                r.reports[0].converged
            );
        }
    }
}
