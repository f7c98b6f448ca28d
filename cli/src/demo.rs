//! `meshmove demo --out DIR [--quick]`: every case of docs/DESIGN.md §7 and their 3D versions
//! with every method, and the largest free-surface amplitude each method moves in one step.

use crate::plot::{deformed_png, patch_edges, semilog_png, Series, View};
use crate::write_deformed;
use glam::DVec2;
use indicatif::{ProgressBar, ProgressStyle};
use meshmove::mesh::signed_measures;
use meshmove::{Criterion, Method, Mode, Options, Solver};
use meshmove_cases::amplitude::largest_valid_amplitude;
use meshmove_cases::meshes3d::BoxCells;
use meshmove_cases::report::{method_name, run_case, run_case_reference, CaseResult, METHODS};
use meshmove_cases::setups::{case, free_surface_case, CaseSetup, Scale, CASE_NAMES};
use meshmove_cases::setups3d::{
    free_surface_3d_case, free_surface_3d_cells, free_surface_3d_name, FREE_SURFACE_3D_AMPLITUDES,
};
use plotters::style::RGBColor;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// Coarse meshes (h = 1/12 instead of 1/32, cubes of 6³ instead of 16³, one layer of the
    /// extruded cylinder instead of 4): a smoke run of about 10 s.
    #[arg(long)]
    quick: bool,
    /// Width of the pictures in pixels.
    #[arg(long, default_value_t = 800)]
    width: u32,
}

pub const BIHARMONIC_COLOUR: RGBColor = RGBColor(31, 119, 180);
pub const LAPLACIAN_COLOUR: RGBColor = RGBColor(255, 127, 14);

fn view_for(setup: &CaseSetup, coords: &[f64]) -> (View, Option<View>) {
    let coords = &crate::plot::xy(coords);
    match setup.name.as_str() {
        "boundary_layer_cylinder" => {
            // The inset follows the moved cylinder (its vertices' centroid).
            let cyl = setup.mesh.patch_vertices(setup.moved_patch);
            let c = cyl.iter().map(|&v| coords[v as usize]).sum::<DVec2>() / cyl.len() as f64;
            (View::around(&crate::plot::xy(setup.mesh.coords()), 0.0), Some(View::centred(c, 0.75)))
        }
        // The part of the channel around the cylinder (the rest barely moves).
        "cylinder_channel" => (View { x0: 0.5, x1: 4.5, y0: -1.02, y1: 1.02 }, None),
        "cylinder_channel_1.5D_fixed" | "cylinder_channel_1.5D_slip" => {
            (View { x0: 0.5, x1: 5.0, y0: -1.02, y1: 1.02 }, None)
        }
        _ => (View::around(coords, 0.01), None),
    }
}

/// The method as a picture names it.
fn method_title(method: Method) -> &'static str {
    match method {
        Method::Biharmonic => "biharmonic",
        Method::Laplacian => "Laplacian",
        Method::Spring => "spring analogy",
    }
}

/// The case's title for its pictures.
fn case_title(name: &str) -> String {
    let t = match name {
        "free_surface_a0.1" => "Free surface, A = 0.1, one step",
        "free_surface_a0.25" => "Free surface, A = 0.25, one step",
        "free_surface_a0.25_10steps" => "Free surface, A = 0.25, 10 steps",
        "rising_interface_0.5" => "Interface raised to 0.5",
        "rising_interface_0.75" => "Interface raised to 0.75",
        "deforming_interface_A" => "Deforming interface, variant A (separate), 15 steps",
        "deforming_interface_B" => "Deforming interface, variant B (continuous), 15 steps",
        "cylinder_channel" => "Cylinder in a channel, moved 1 D in x",
        "cylinder_channel_1.5D_fixed" => "Cylinder in a channel, moved 1.5 D in x, walls FIXED",
        "cylinder_channel_1.5D_slip" => "Cylinder in a channel, moved 1.5 D in x, walls SLIP",
        "boundary_layer_cylinder" => "Boundary-layer cylinder, moved 4.5 D",
        "boundary_layer_cylinder_3d" => "Boundary-layer cylinder extruded in z (hexes and wedges), moved 4.5 D",
        other => {
            let box_case = BoxCells::ALL
                .into_iter()
                .flat_map(|c| FREE_SURFACE_3D_AMPLITUDES.map(|a| (c, a)))
                .find(|&(c, a)| other == free_surface_3d_name(c, a));
            if let Some((c, a)) = box_case {
                return format!("Free surface 3D, unit cube of {}, A = {a}, one step", cells_title(c));
            }
            other
        }
    };
    t.to_string()
}

/// The cells of a box mesh as a caption names them.
fn cells_title(cells: BoxCells) -> &'static str {
    match cells {
        BoxCells::Tets => "tetrahedra",
        BoxCells::Hexes => "hexahedra",
        BoxCells::Prisms => "prisms",
    }
}

/// The free surfaces whose largest valid amplitude the demo finds: the 2D one and the 3D cube of
/// each cell kind, each at A = 0.1, with the name its `largest_amplitude.csv` rows carry.
fn amplitude_cases(scale: Scale) -> Vec<(String, CaseSetup)> {
    let h = if scale == Scale::Paper { 1.0 / 32.0 } else { 1.0 / 12.0 };
    let mut out = vec![("free_surface".to_string(), free_surface_case("free_surface_a0.1", h, 0.1, 1))];
    for cells in BoxCells::ALL {
        let setup = free_surface_3d_case(cells, free_surface_3d_cells(scale), 0.1, 1);
        out.push((format!("free_surface_3d_{}", cells.name()), setup));
    }
    out
}

/// `largest_amplitude.csv`: for each free surface and method, the largest A moved in one step
/// without an inverted cell ([`largest_valid_amplitude`]: A scanned in steps of 0.05 up to 1,
/// then bisected to 0.001).
fn largest_amplitudes(dir: &Path, scale: Scale, bar: &ProgressBar) -> Result<String, String> {
    let mut csv = String::from("case,method,dim,largest_valid_a,first_inverted_a,cycles,seconds\n");
    for (name, setup) in amplitude_cases(scale) {
        for method in METHODS {
            bar.set_message(format!("largest A: {name} {}", method_name(method)));
            let l = largest_valid_amplitude(&setup, 0.1, method, &Options::default(), (0.05, 1.0, 1e-3))
                .map_err(|e| format!("largest A, {name} {method:?}: {e}"))?;
            let _ = writeln!(
                csv,
                "{name},{},{},{:.4},{},{},{:.4}",
                method_name(method),
                setup.mesh.dim(),
                l.largest_valid,
                l.first_inverted.map(|a| format!("{a:.4}")).unwrap_or_default(),
                l.cycles,
                l.seconds
            );
            bar.inc(1);
        }
    }
    let p = dir.join("largest_amplitude.csv");
    std::fs::write(&p, &csv).map_err(|e| format!("{}: {e}", p.display()))?;
    Ok(csv)
}

/// What the picture's window and blue edges are, when that needs saying.
fn view_notes(setup: &CaseSetup) -> Vec<String> {
    let mut notes = Vec::new();
    notes.push(if setup.upper_region.is_some() { "blue: the interface" } else { "blue: the moved patch" }.to_string());
    match setup.name.as_str() {
        "cylinder_channel" => notes[0].push_str("; cropped to x from 0.5 to 4.5 of the channel [0, 8] x [-1, 1]"),
        "cylinder_channel_1.5D_fixed" | "cylinder_channel_1.5D_slip" => {
            notes[0].push_str("; cropped to x from 0.5 to 5 of the channel [0, 8] x [-1, 1]")
        }
        "boundary_layer_cylinder" => notes[0].push_str("; inset (blue frame): 1.5 D x 1.5 D around the cylinder"),
        _ => {}
    }
    notes
}

/// One mesh picture, `DIR/{stem}.png`, titled with the case and `label` (the method): a 2D mesh
/// whole, a 3D mesh as its middle section ([`crate::plot3d::section_png`]).
fn picture(dir: &Path, setup: &CaseSetup, coords: &[f64], stem: &str, label: &str, width: u32) -> Result<(), String> {
    let path = dir.join(format!("{stem}.png"));
    let title = format!("{}: {label}", case_title(&setup.name));
    if setup.mesh.dim() == 3 {
        let axis = crate::plot3d::section_axis(&setup.mesh, &setup.motion);
        return crate::plot3d::section_png(
            &path,
            (&setup.mesh, coords),
            (title, &[]),
            (axis, setup.moved_patch),
            width,
        )
        .map_err(|e| format!("{}: {e}", path.display()));
    }
    let (view, inset) = view_for(setup, coords);
    let highlight = patch_edges(&setup.mesh, setup.moved_patch);
    let notes = view_notes(setup);
    deformed_png(&path, (&setup.mesh, coords), (title, &notes), &highlight, (Some(view), inset), width)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Paper Fig. 8: largest vertex correction per W-cycle, paper-faithful mode, free surface A = 0.25.
fn convergence(dir: &Path, scale: Scale, width: u32) -> Result<(), String> {
    let h = if scale == Scale::Paper { 1.0 / 32.0 } else { 1.0 / 12.0 };
    let setup = free_surface_case("free_surface_a0.25", h, 0.25, 1);
    let mut hist = Vec::new();
    for method in [Method::Biharmonic, Method::Laplacian] {
        let mut o = Options { method, ..Default::default() };
        o.solve.mode = Mode::PaperFaithful;
        o.solve.criterion = Criterion::MaxCorrection;
        o.solve.tol = 1e-8;
        o.solve.max_cycles = 400;
        let s = Solver::new(&setup.mesh, &setup.bcs, o).map_err(|e| e.to_string())?;
        let sol = s.solve(&setup.motion).map_err(|e| format!("convergence plot, {method:?}: {e}"))?;
        hist.push(sol.report.history.iter().map(|p| p.0).collect::<Vec<f64>>());
    }
    let mut csv = String::from("cycle,biharmonic_max_correction,laplacian_max_correction\n");
    for k in 0..hist[0].len().max(hist[1].len()) {
        let f = |h: &Vec<f64>| h.get(k).map(|v| format!("{v:e}")).unwrap_or_default();
        let _ = writeln!(csv, "{},{},{}", k + 1, f(&hist[0]), f(&hist[1]));
    }
    let p = dir.join("convergence.csv");
    std::fs::write(&p, csv).map_err(|e| format!("{}: {e}", p.display()))?;
    let p = dir.join("convergence.png");
    let lines = [
        format!("Multigrid convergence: free surface, A = 0.25, h = 1/{}", (1.0 / h).round()),
        "paper-faithful mode: W-cycles, one Jacobi sweep, C = 0.9 (paper Fig. 8)".to_string(),
    ];
    let series = [
        Series { name: "biharmonic", values: &hist[0], colour: BIHARMONIC_COLOUR },
        Series { name: "Laplacian", values: &hist[1], colour: LAPLACIAN_COLOUR },
    ];
    let axes = ("W-cycle", "largest vertex correction");
    semilog_png(&p, &lines, axes, &series, width, width * 5 / 8).map_err(|e| format!("{}: {e}", p.display()))
}

/// A message above the bar, or on stderr when the bar is hidden (not a terminal).
fn say(bar: &ProgressBar, m: String) {
    if bar.is_hidden() {
        eprintln!("{m}");
    } else {
        bar.println(m);
    }
}

pub fn run(args: Args) -> Result<ExitCode, String> {
    let dir = &args.out;
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let scale = if args.quick { Scale::Quick } else { Scale::Paper };
    let bar =
        ProgressBar::new((CASE_NAMES.len() * METHODS.len() + 1 + amplitude_cases(scale).len() * METHODS.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} {elapsed} {msg}").unwrap_or(ProgressStyle::default_bar()),
    );
    let mut csv = format!("{}\n", CaseResult::CSV_HEADER);
    for name in CASE_NAMES {
        let setup = case(name, scale).ok_or_else(|| format!("unknown case {name}"))?;
        for method in METHODS {
            bar.set_message(format!("{name} {}", method_name(method)));
            let r = run_case(&setup, method, &Options::default()).map_err(|e| format!("{name}, {method:?}: {e}"))?;
            let unconverged = r.reports.iter().filter(|x| !x.converged).count();
            if unconverged > 0 {
                say(
                    &bar,
                    format!(
                        "note: {name} {}: {unconverged} of {} steps did not reach the tolerance (see docs/RESULTS.md)",
                        method_name(method),
                        r.steps
                    ),
                );
            }
            if let Some(f) = &r.failure {
                say(&bar, format!("{name} {}: stopped at {f}", method_name(method)));
            }
            let vtu = dir.join(format!("{name}_{}.vtu", method_name(method)));
            write_deformed(&vtu, &setup.mesh, &r.displacement(&setup.mesh))?;
            let stem = format!("{name}_{}", method_name(method));
            let label = match (&r.failure, r.reports.last()) {
                (Some(_), Some(last)) => format!("{}, stopped at step {}", method_title(method), last.step),
                _ => method_title(method).to_string(),
            };
            picture(dir, &setup, &r.coords, &stem, &label, args.width)?;
            if unconverged > 0 {
                // What the method gives: every step solved exactly (slow, independent of the
                // multigrid), written beside the multigrid's result as *_exact.{vtu,png}.
                bar.set_message(format!("{name} {}: exact solve", method_name(method)));
                match run_case_reference(&setup, method, 1e-10) {
                    Ok((coords, first)) => {
                        let inv = signed_measures(&setup.mesh, &coords).iter().filter(|&&a| a <= 0.0).count();
                        say(&bar, format!(
                            "      exact solves of every step: {inv} inverted cells{}; written as {stem}_exact.vtu/.png",
                            first.map(|k| format!(" (first at step {k})")).unwrap_or_default()
                        ));
                        let disp: Vec<f64> = coords.iter().zip(setup.mesh.coords()).map(|(a, b)| a - b).collect();
                        let vtu = dir.join(format!("{stem}_exact.vtu"));
                        write_deformed(&vtu, &setup.mesh, &disp)?;
                        let label = format!("{}, every step solved exactly", method_title(method));
                        picture(dir, &setup, &coords, &format!("{stem}_exact"), &label, args.width)?;
                    }
                    Err(e) => say(&bar, format!("      exact solve failed: {e}")),
                }
            }
            csv.push_str(&r.csv_row());
            csv.push('\n');
            bar.inc(1);
        }
    }
    bar.set_message("convergence plot");
    convergence(dir, scale, args.width)?;
    bar.inc(1);
    let amplitudes = largest_amplitudes(dir, scale, &bar)?;
    bar.finish_and_clear();
    let p = dir.join("results.csv");
    std::fs::write(&p, &csv).map_err(|e| format!("{}: {e}", p.display()))?;
    print!("{csv}");
    print!("{amplitudes}");
    println!("wrote {}", dir.display());
    Ok(ExitCode::SUCCESS)
}
