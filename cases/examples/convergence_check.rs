//! Which runs of the demo reached the tolerance: per case and method, steps not converged and the
//! worst final relative residual (docs/RESULTS.md).
use meshmove::Options;
use meshmove_cases::report::*;
use meshmove_cases::setups::*;
fn main() {
    for name in CASE_NAMES {
        let s = case(name, Scale::Paper).unwrap();
        for m in METHODS {
            let r = run_case(&s, m, &Options::default()).unwrap();
            let bad = r.reports.iter().filter(|x| !x.converged).count();
            let worst = r.reports.iter().map(|x| x.rel_residual).fold(0.0, f64::max);
            let maxc = r.reports.iter().map(|x| x.cycles).max().unwrap_or(0);
            println!("{name:28} {:10} steps not converged {bad:2}/{:2}  worst rel residual {worst:.1e}  max cycles/step {maxc}", method_name(m), r.steps);
        }
    }
}
