use meshmove::cases::report::*;
use meshmove::cases::setups::*;
use meshmove::Options;
fn main() {
    let scale = if std::env::args().any(|a| a == "quick") { Scale::Quick } else { Scale::Paper };
    let only: Vec<String> = std::env::args().skip(1).filter(|a| a != "quick").collect();
    println!("{} first_inv across area_lo area_hi fail", CaseResult::CSV_HEADER);
    for name in CASE_NAMES {
        if !only.is_empty() && !only.iter().any(|o| o == name) {
            continue;
        }
        let s = case(name, scale).unwrap();
        for m in METHODS {
            let r = run_case(&s, m, &Options::default()).unwrap();
            println!(
                "{} {:?} {:?} {:.3} {:.3} {:?}",
                r.csv_row(),
                r.first_inverted_step,
                r.patch.spacing_ratio_across,
                r.patch.area_ratio.0,
                r.patch.area_ratio.1,
                r.failure
            );
        }
    }
}
