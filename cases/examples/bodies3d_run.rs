//! The 3D body cases (sphere channel, pitching spheroid) with every method, as a table:
//! `cargo run --release -p meshmove-cases --example bodies3d_run [quick|paper] [case filter] [method filter]`
//! (docs/RESULTS.md).
use meshmove::Options;
use meshmove_cases::ogrid::{measure, OG_BODY};
use meshmove_cases::report::{method_name, run_case, METHODS};
use meshmove_cases::setups::{case, Scale};

fn main() {
    let scale = if std::env::args().nth(1).as_deref() == Some("quick") { Scale::Quick } else { Scale::Paper };
    let filter = std::env::args().nth(2).unwrap_or_default();
    let method_filter = std::env::args().nth(3).unwrap_or_default();
    let names = ["sphere_channel_0.5", "sphere_channel_1.0", "pitching_spheroid_1step", "pitching_spheroid_10steps"];
    let names = names.into_iter().filter(|n| n.contains(filter.as_str()));
    println!(
        "| case | method | vertices | cells | inverted | min volume ratio | min dihedral (°) | iterations | seconds |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|");
    for name in names {
        let s = case(name, scale).expect("a case");
        let st = measure(&s.mesh, OG_BODY);
        eprintln!("{name}: original min dihedral {:.2}, max edge ratio {:.2}", st.min_angle_deg, st.max_edge_ratio);
        for m in METHODS.into_iter().filter(|&m| method_name(m).contains(method_filter.as_str())) {
            let r = run_case(&s, m, &Options::default()).expect("run");
            println!(
                "| {name} | {} | {} | {} | {} | {:.3} | {:.2} | {} | {:.1} |{}",
                method_name(m),
                s.mesh.num_vertices(),
                s.mesh.num_cells(),
                r.inverted,
                r.min_area_ratio,
                r.min_angle_deg,
                r.cycles,
                r.seconds,
                r.failure.map(|f| format!(" {f}")).unwrap_or_default()
            );
        }
    }
}
