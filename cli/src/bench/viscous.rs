//! The bench's wall-layered meshes (`--parts viscous`): the NACA 0012 airfoil (2D, 30 quad
//! layers, first height 10⁻⁵), the prolate spheroid (3D, 25 wedge layers, first height 10⁻⁴,
//! tetrahedra outside) and the extruded wing section (3D, hexahedral layers between SLIP end
//! walls), three sizes each; the body CLAMPED and pitched by 10° or plunged by 0.2 as a rigid
//! body, in one step and in `--viscous-steps` re-referenced steps (`Solver::advance`), by every
//! method. Each row: counts and times, CG iterations (the largest and the mean over the steps),
//! how the wall layers' cells changed volume, the whole mesh's smallest volume ratio and its
//! inverted cells, and the mesh's shape before the motion. A run that fails (no convergence
//! within `--viscous-max-cycles`, an error, or a panic) is a row saying so. Writes
//! `DIR/viscous.csv`.

use super::alloc;
use meshmove::{Method, Options, SolveParams, Solver};
use meshmove_cases::viscous::{self, BodyMotion, MeshQuality, ViscousMesh};
use std::fmt::Write as _;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::time::Instant;

pub const HEADER: &str =
    "mesh,size,vertices,cells,method,motion,steps,status,setup_s,solve_s,step_s,us_per_vertex_step,\
bytes_per_vertex,iterations_max,iterations_mean,first_layer_min,first_layer_max,layers10_min,layers10_max,\
min_volume_ratio,inverted,max_aspect_ratio,min_angle_deg";

/// The meshes.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshKind {
    /// The NACA 0012 airfoil, 2D.
    Airfoil,
    /// The prolate spheroid, 3D.
    Spheroid,
    /// The extruded wing section, 3D.
    Wing,
}

impl MeshKind {
    pub fn name(self) -> &'static str {
        match self {
            MeshKind::Airfoil => "airfoil-2d",
            MeshKind::Spheroid => "spheroid-3d",
            MeshKind::Wing => "wing-3d",
        }
    }

    /// The size parameter of size `i` (0 to [`SIZES`] − 1): points per side of the airfoil (and
    /// the wing's section, with its span cells), the spheroid's inner-box cells across. Sizes
    /// 0–2 are the three of every run; size 3 (`--viscous-sizes 4`) is the ≥ 1M-vertex mesh of
    /// each 3D kind (the airfoil's fourth, 2D, has 300 947).
    fn size(self, i: usize) -> (usize, usize) {
        match self {
            MeshKind::Airfoil => ([64, 128, 256, 512][i], 0),
            MeshKind::Spheroid => ([4, 8, 12, 30][i], 0),
            MeshKind::Wing => [(32, 4), (64, 8), (96, 12), (192, 24)][i],
        }
    }

    /// The mesh of size `i`, and its label.
    pub fn build(self, i: usize) -> Result<(ViscousMesh, String), String> {
        let (n, z) = self.size(i);
        Ok(match self {
            MeshKind::Airfoil => (viscous::airfoil_2d(&viscous::AirfoilParams::new(n))?, format!("pps{n}")),
            MeshKind::Spheroid => (viscous::spheroid_3d(&viscous::SpheroidParams::new(n))?, format!("cells{n}")),
            MeshKind::Wing => (viscous::wing_3d(&viscous::WingParams::new(n, z))?, format!("pps{n}x{z}")),
        })
    }
}

/// How many sizes [`MeshKind::build`] knows.
pub const SIZES: usize = 4;

/// The columns of `DIR/viscous_steps.csv`: one line per step of every run.
pub const STEPS_HEADER: &str = "mesh,size,vertices,method,motion,steps,step,iterations,converged,inverted,\
step_min_volume_ratio,first_layer_min,first_layer_max,step_s";

/// One step of a run: its iterations, whether it converged, the step's inverted cells and
/// smallest volume ratio (against the mesh it began on), the first layer's volume range against
/// the original mesh, and the `advance` call's seconds.
struct Step {
    iterations: usize,
    converged: bool,
    inverted: usize,
    min_volume_ratio: f64,
    first: Option<(f64, f64)>,
    seconds: f64,
}

/// A method of the viscous part.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum MethodName {
    /// The biharmonic.
    Biharmonic,
    /// The Laplacian.
    Laplacian,
    /// The spring analogy.
    Spring,
}

impl MethodName {
    /// The library's method.
    pub fn method(self) -> Method {
        match self {
            MethodName::Biharmonic => Method::Biharmonic,
            MethodName::Laplacian => Method::Laplacian,
            MethodName::Spring => Method::Spring,
        }
    }
}

/// A motion of the viscous part.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionName {
    /// The pitch by 10°.
    Pitch,
    /// The plunge by 0.2.
    Plunge,
}

impl MotionName {
    /// The cases' motion.
    pub fn motion(self) -> BodyMotion {
        match self {
            MotionName::Pitch => BodyMotion::Pitch,
            MotionName::Plunge => BodyMotion::Plunge,
        }
    }
}

/// What one run measured.
struct Run {
    status: String,
    setup_s: f64,
    /// The solves' seconds (the steps' reports).
    solve_s: f64,
    /// The `advance` calls' seconds: the solves, and the re-referencing after each step.
    step_s: f64,
    bytes_per_vertex: f64,
    iterations: Vec<usize>,
    first: Option<(f64, f64)>,
    ten: Option<(f64, f64)>,
    min_volume_ratio: f64,
    inverted: usize,
    /// Every step that gave a result.
    steps: Vec<Step>,
}

impl Run {
    /// A run that measured nothing yet, with `status`.
    fn with_status(status: String) -> Run {
        Run {
            status,
            setup_s: 0.0,
            solve_s: 0.0,
            step_s: 0.0,
            bytes_per_vertex: 0.0,
            iterations: Vec::new(),
            first: None,
            ten: None,
            min_volume_ratio: f64::NAN,
            inverted: 0,
            steps: Vec::new(),
        }
    }
}

/// Builds the solver of `method` and moves the body by `m` in `steps` steps; stops at the first
/// step that fails or inverts a cell (the rows report that step's result).
fn run(v: &ViscousMesh, method: Method, m: BodyMotion, steps: usize, max_cycles: usize, tol: f64) -> Run {
    let nv = v.mesh.num_vertices();
    let bcs = viscous::boundary_conditions(v);
    let motion = viscous::motion(v, m);
    let base = alloc::start();
    let mut r = Run::with_status("ok".into());
    let opts = Options { method, solve: SolveParams { tol, max_cycles, ..Default::default() }, ..Default::default() };
    let t = Instant::now();
    let mut solver = match Solver::new(&v.mesh, &bcs, opts) {
        Ok(s) => s,
        Err(e) => {
            r.status = format!("setup: {e}");
            return r;
        }
    };
    r.setup_s = t.elapsed().as_secs_f64();
    let mut coords = v.mesh.coords().to_vec();
    for i in 0..steps {
        let t = Instant::now();
        let sol = solver.advance(&motion.increment(i, steps));
        let seconds = t.elapsed().as_secs_f64();
        r.step_s += seconds;
        r.solve_s += solver.step_reports().iter().map(|s| s.seconds).sum::<f64>();
        match sol {
            Ok(sol) => {
                r.iterations.push(sol.report.cycles);
                if !sol.report.converged {
                    r.status = format!("step {}: not converged ({:.1e})", i + 1, sol.report.rel_residual);
                }
                let inverted = sol.quality.inverted > 0;
                coords = if inverted {
                    // Not adopted by the solver: measure the result itself.
                    solver.current_coords().iter().zip(&sol.displacement).map(|(x, d)| x + d).collect()
                } else {
                    solver.current_coords().to_vec()
                };
                r.steps.push(Step {
                    iterations: sol.report.cycles,
                    converged: sol.report.converged,
                    inverted: sol.quality.inverted,
                    min_volume_ratio: sol.quality.min_area_ratio,
                    first: viscous::layer_volume_ratios(v, &coords, 1),
                    seconds,
                });
                if inverted {
                    r.status = format!("step {}: {} cells inverted", i + 1, sol.quality.inverted);
                    break;
                }
            }
            Err(e) => {
                r.status = format!("step {}: {e}", i + 1);
                break;
            }
        }
    }
    r.bytes_per_vertex = alloc::peak_above(base) as f64 / nv as f64;
    if r.iterations.is_empty() {
        // No step gave a result: nothing moved to measure.
        return r;
    }
    let q = meshmove::mesh::quality(&v.mesh, &coords);
    r.min_volume_ratio = q.min_area_ratio;
    r.inverted = q.inverted;
    r.first = viscous::layer_volume_ratios(v, &coords, 1);
    r.ten = viscous::layer_volume_ratios(v, &coords, 10);
    r
}

/// [`run`], a panic caught and reported as the row's status.
fn run_caught(v: &ViscousMesh, method: Method, m: BodyMotion, steps: usize, max_cycles: usize, tol: f64) -> Run {
    catch_unwind(AssertUnwindSafe(|| run(v, method, m, steps, max_cycles, tol))).unwrap_or_else(|p| {
        let msg = p
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default();
        Run::with_status(format!("PANIC: {msg}"))
    })
}

/// What the viscous part runs. `us_per_vertex_step` is the solves' time per vertex and step;
/// `step_s` adds the re-referencing of every `advance` call.
pub struct Plan {
    pub meshes: Vec<MeshKind>,
    /// The sizes of each mesh run (indices into [`MeshKind::build`]'s sizes).
    pub sizes: std::ops::Range<usize>,
    pub methods: Vec<Method>,
    pub motions: Vec<BodyMotion>,
    /// Step counts of the runs (1 and the re-referenced run's).
    pub steps: Vec<usize>,
    pub max_cycles: usize,
    pub tol: f64,
}

fn range(r: Option<(f64, f64)>) -> (String, String) {
    r.map_or(("".into(), "".into()), |(a, b)| (format!("{a:.6}"), format!("{b:.6}")))
}

/// Runs `plan` at the pool's thread count (`pool`); writes `out/viscous.csv` (a row a run) and
/// `out/viscous_steps.csv` (a row a step), returns the table.
pub fn run_all(out: &Path, plan: &Plan, pool: &rayon::ThreadPool) -> Result<String, String> {
    let mut csv = format!("{HEADER}\n");
    let mut steps_csv = format!("{STEPS_HEADER}\n");
    let mut table = String::from(
        "viscous layers: body CLAMPED and moved rigidly, far field FIXED (wing end walls SLIP)\n\
         mesh         size        vertices method      motion steps   it max  mean  setup_s  solve_s   step_s us/v/st   B/vert  \
         1st layer vol       10 layers vol     min vol  inv  max AR  min ang  status\n",
    );
    for &kind in &plan.meshes {
        for size in plan.sizes.clone() {
            let (v, label) = match kind.build(size) {
                Ok(x) => x,
                Err(e) => {
                    let _ = writeln!(table, "{} size {size}: {e}", kind.name());
                    continue;
                }
            };
            let q: MeshQuality = viscous::mesh_quality(&v);
            eprintln!(
                "{} {label}: {} vertices, {} cells, max aspect ratio {:.0}, min angle {:.2}°",
                kind.name(),
                q.vertices,
                q.cells,
                q.max_aspect_ratio,
                q.min_angle_deg
            );
            for &method in &plan.methods {
                for &m in &plan.motions {
                    for &steps in &plan.steps {
                        let r = pool.install(|| run_caught(&v, method, m, steps, plan.max_cycles, plan.tol));
                        let its = &r.iterations;
                        let max = its.iter().copied().max().unwrap_or(0);
                        let mean = its.iter().sum::<usize>() as f64 / its.len().max(1) as f64;
                        let per = 1e6 * r.solve_s / (q.vertices * its.len().max(1)) as f64;
                        let (f0, f1) = range(r.first);
                        let (t0, t1) = range(r.ten);
                        let name = format!("{method:?}").to_lowercase();
                        let status = r.status.replace(',', ";");
                        for (i, st) in r.steps.iter().enumerate() {
                            let (f0, f1) = range(st.first);
                            let _ = writeln!(
                                steps_csv,
                                "{},{label},{},{name},{},{steps},{},{},{},{},{:.6},{f0},{f1},{:.4}",
                                kind.name(),
                                q.vertices,
                                m.name(),
                                i + 1,
                                st.iterations,
                                st.converged,
                                st.inverted,
                                st.min_volume_ratio,
                                st.seconds
                            );
                        }
                        let _ = writeln!(
                            csv,
                            "{},{label},{},{},{name},{},{steps},{status},{:.4},{:.4},{:.4},{:.3},{:.0},{max},{mean:.1},{f0},{f1},{t0},{t1},{:.6},{},{:.1},{:.3}",
                            kind.name(),
                            q.vertices,
                            q.cells,
                            m.name(),
                            r.setup_s,
                            r.solve_s,
                            r.step_s,
                            per,
                            r.bytes_per_vertex,
                            r.min_volume_ratio,
                            r.inverted,
                            q.max_aspect_ratio,
                            q.min_angle_deg
                        );
                        let span = |x: Option<(f64, f64)>| x.map_or("-".into(), |(a, b)| format!("{a:.4}–{b:.4}"));
                        let line = format!(
                            "{:<12} {label:<11} {:>8} {name:<11} {:<6} {steps:>5} {max:>8} {mean:>5.1} {:>8.3} {:>8.3} {:>8.3} {per:>7.2} {:>8.0} {:>17} {:>17} {:>8.4} {:>4} {:>7.0} {:>7.2}  {}",
                            kind.name(),
                            q.vertices,
                            m.name(),
                            r.setup_s,
                            r.solve_s,
                            r.step_s,
                            r.bytes_per_vertex,
                            span(r.first),
                            span(r.ten),
                            r.min_volume_ratio,
                            r.inverted,
                            q.max_aspect_ratio,
                            q.min_angle_deg,
                            r.status
                        );
                        eprintln!("  {line}");
                        table.push_str(&line);
                        table.push('\n');
                        // Written after every run: a long run's finished rows survive its end.
                        write_csvs(out, &csv, &steps_csv)?;
                    }
                }
            }
        }
    }
    write_csvs(out, &csv, &steps_csv)?;
    Ok(table)
}

/// Writes `out/viscous.csv` and `out/viscous_steps.csv`.
fn write_csvs(out: &Path, csv: &str, steps_csv: &str) -> Result<(), String> {
    for (name, text) in [("viscous.csv", csv), ("viscous_steps.csv", steps_csv)] {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}
