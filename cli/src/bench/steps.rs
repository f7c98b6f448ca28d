//! The time-stepping rows: what a host pays per time step. One solver is built (the biharmonic,
//! or each of `--steps-methods`), then
//! the case's motion is applied in [`STEPS`] equal increments by `Solver::advance`, the call a
//! host makes every time step on the mesh of the previous step (each call re-evaluates K and V
//! on the moved mesh, keeping the coarse topology, then solves for the increment). The rows are
//! step 1, the median step and the worst step by the call's wall time.
//!
//! A step's wall time is split into the phases its reports give apart: the solve
//! (`StepReport::solve_seconds`, the PCG with its cycle), the re-reference (`reference_seconds`),
//! the quality check of the result (`quality_seconds`), and the rest of the `advance` call (the
//! copies, the undo state, the warm start: what is outside the three). The step's cost against
//! its solve is (advance − quality check) / solve; the quality check / solve is shown beside it.

use super::cases::Case;
use super::{alloc, op_seconds, report, Row, RowBase};
use meshmove::multigrid::phases::Phases;
use meshmove::{Method, Options, SolveParams, Solver};
use std::fmt::Write as _;
use std::time::Instant;

/// Steps of the motion.
pub const STEPS: usize = 10;

/// One step's measurements.
#[derive(Clone, Debug)]
pub struct Step {
    /// CG iterations.
    pub iterations: usize,
    pub rel_residual: f64,
    /// Wall time of the `advance` call.
    pub total_s: f64,
    /// Of which the solve (`StepReport::solve_seconds`, summed over sub-steps).
    pub solve_s: f64,
    /// Of which the re-reference (`StepReport::reference_seconds`, summed over sub-steps).
    pub reference_s: f64,
    /// Of which the quality check of the results (`StepReport::quality_seconds`, summed).
    pub quality_s: f64,
    /// Sub-steps (1 unless the step was split) and hierarchy rebuilds.
    pub substeps: usize,
    pub rebuilt: bool,
    /// The hierarchy's phases of the step's last re-reference.
    pub phases: Phases,
}

impl Step {
    /// The rest of the `advance` call: outside its solve, re-reference and quality check.
    pub fn rest_s(&self) -> f64 {
        self.total_s - self.solve_s - self.reference_s - self.quality_s
    }

    /// What the step costs beyond its solve except the quality check: re-reference and rest.
    pub fn beyond_solve(&self) -> f64 {
        self.total_s - self.quality_s - self.solve_s
    }

    /// The goal's ratio: (advance − quality check) / solve.
    pub fn step_per_solve(&self) -> f64 {
        (self.total_s - self.quality_s) / self.solve_s
    }
}

/// One time-stepping run.
pub struct Stepped {
    pub case: &'static str,
    pub method: Method,
    pub vertices: usize,
    pub threads: usize,
    /// `Solver::new`, once.
    pub setup_s: f64,
    /// The hierarchy's phases of the setup.
    pub setup_phases: Phases,
    pub steps: Vec<Step>,
    /// Counted allocation over construction and every step, per vertex.
    pub bytes_per_vertex: f64,
    /// Smallest cell volume ratio of the final mesh against the original one.
    pub min_volume_ratio: f64,
}

impl Stepped {
    /// Indices of step 1, the median step and the worst step by wall time, with their rows' names.
    fn picks(&self) -> [(usize, &'static str); 3] {
        let mut order: Vec<usize> = (0..self.steps.len()).collect();
        order.sort_by(|&i, &j| self.steps[i].total_s.total_cmp(&self.steps[j].total_s));
        let names = match self.method {
            Method::Laplacian => ["laplacian-step1", "laplacian-step-median", "laplacian-step-worst"],
            Method::Spring => ["spring-step1", "spring-step-median", "spring-step-worst"],
            Method::Biharmonic => ["biharmonic-step1", "biharmonic-step-median", "biharmonic-step-worst"],
        };
        [(0, names[0]), (order[order.len() / 2], names[1]), (*order.last().expect("steps"), names[2])]
    }
}

/// `run` with each of `--steps-methods`, the runs kept in `stepped` and the failures in `failed`.
pub fn run_methods(
    a: &super::Args,
    case: &Case,
    pool: &(usize, rayon::ThreadPool),
    rows: &mut Vec<Row>,
    stepped: &mut Vec<Stepped>,
    failed: &mut Vec<String>,
) {
    for m in &a.steps_methods {
        run(a, case, m.method(), pool, rows).map_or_else(|e| failed.push(e), |s| stepped.push(s));
    }
}

/// Builds the solver of `method` at the pool's thread count, advances it [`STEPS`] times, and
/// pushes the three rows: `solve_s` the solve, `setup_s` what the call costs beyond it except
/// the quality check (re-reference and rest), `iterations` its CG iterations.
pub fn run(
    a: &super::Args,
    case: &Case,
    method: Method,
    (threads, pool): &(usize, rayon::ThreadPool),
    rows: &mut Vec<Row>,
) -> Result<Stepped, String> {
    let nv = case.mesh.num_vertices();
    let original = case.mesh.coords().to_vec();
    let base = alloc::start();
    pool.install(|| {
        let t = Instant::now();
        let opts = Options {
            method,
            solve: SolveParams { tol: a.tol, ..Default::default() },
            threads: *threads,
            ..Default::default()
        };
        let mut solver = Solver::new(&case.mesh, &case.bcs, opts)
            .map_err(|e| format!("{} {method:?} steps at {nv} vertices: {e}", case.name))?;
        let setup_s = t.elapsed().as_secs_f64();
        let setup_phases = solver.phases();
        let op_s = op_seconds(solver.hierarchy().fine(), case.comp);
        let levels = solver.num_levels();
        let mut steps = Vec::with_capacity(STEPS);
        for i in 0..STEPS {
            let inc = case.motion.increment(i, STEPS);
            let t = Instant::now();
            let sol = solver.advance(&inc).map_err(|e| format!("{} step {}: {e}", case.name, i + 1))?;
            let total_s = t.elapsed().as_secs_f64();
            let reps = solver.step_reports();
            steps.push(Step {
                iterations: sol.report.cycles,
                rel_residual: sol.report.rel_residual,
                total_s,
                solve_s: reps.iter().map(|r| r.solve_seconds).sum(),
                reference_s: reps.iter().map(|r| r.reference_seconds).sum(),
                quality_s: reps.iter().map(|r| r.quality_seconds).sum(),
                substeps: reps.len(),
                rebuilt: reps.iter().any(|r| r.rebuilt),
                phases: solver.phases(),
            });
        }
        let bytes_per_vertex = alloc::peak_above(base) as f64 / nv as f64;
        let q = meshmove::mesh::quality(&case.mesh.with_coords(original), solver.current_coords());
        let stepped = Stepped {
            case: case.name,
            method,
            vertices: nv,
            threads: *threads,
            setup_s,
            setup_phases,
            steps,
            bytes_per_vertex,
            min_volume_ratio: q.min_area_ratio,
        };
        let rb = RowBase { case: case.name, vertices: nv, threads: *threads, levels, op_s };
        for (i, name) in stepped.picks() {
            let s = &stepped.steps[i];
            rows.push(rb.row(name, s.solve_s, s.iterations, s.rel_residual, bytes_per_vertex, s.beyond_solve()));
            report(rows.last().expect("row"));
        }
        Ok(stepped)
    })
}

/// The steps of every run: setup once, then per step its iterations and seconds, the median
/// step's phases apart.
pub fn table(runs: &[Stepped]) -> String {
    let mut s = String::new();
    if runs.is_empty() {
        return s;
    }
    let _ = writeln!(
        s,
        "\ntime stepping: the motion in {STEPS} steps by Solver::advance (re-referenced each step)\n\
         {:<16} {:<10} {:>8} {:>3} {:>8} {:>14} {:>14} {:>14} {:>30} {:>11} {:>10} {:>9} {:>6} {:>9}  iterations per step",
        "case",
        "method",
        "vertices",
        "thr",
        "setup_s",
        "step 1: it / s",
        "median: it / s",
        "worst: it / s",
        "median: solve reref qual rest",
        "setup/solve",
        "step/solve",
        "qual/solve",
        "B/vert",
        "min vol"
    );
    for r in runs {
        let picks = r.picks();
        let cell = |i: usize| {
            let st = &r.steps[i];
            format!("{} / {:.3}", st.iterations, st.total_s)
        };
        let median = &r.steps[picks[1].0];
        let phases =
            format!("{:.3} {:.3} {:.3} {:.3}", median.solve_s, median.reference_s, median.quality_s, median.rest_s());
        let its: Vec<String> = r
            .steps
            .iter()
            .map(|st| {
                let mark = if st.substeps > 1 || st.rebuilt { "*" } else { "" };
                format!("{}{mark}", st.iterations)
            })
            .collect();
        let _ = writeln!(
            s,
            "{:<16} {:<10} {:>8} {:>3} {:>8.3} {:>14} {:>14} {:>14} {:>30} {:>11.2} {:>10.2} {:>9.2} {:>6.0} {:>9.4}  {}",
            r.case,
            format!("{:?}", r.method).to_lowercase(),
            r.vertices,
            r.threads,
            r.setup_s,
            cell(picks[0].0),
            cell(picks[1].0),
            cell(picks[2].0),
            phases,
            r.setup_s / median_of(r.steps.iter().map(|st| st.solve_s)),
            median_of(r.steps.iter().map(Step::step_per_solve)),
            median_of(r.steps.iter().map(|st| st.quality_s / st.solve_s)),
            r.bytes_per_vertex,
            r.min_volume_ratio,
            its.join(" ")
        );
        let _ = writeln!(s, "  setup phases (s):        {}", phase_list(&r.setup_phases));
        let _ = writeln!(s, "  median re-reference (s): {}", phase_list(&median.phases));
    }
    let _ = writeln!(
        s,
        "(s: the advance call; its median step's phases: solve the PCG with its cycle, reref K and V re-evaluated \
         on the moved mesh, qual the quality check of the result, rest the rest of the call (copies, undo state, \
         warm start); setup/solve: Solver::new against the median step's solve; step/solve: the median of each \
         step's (advance call − quality check) against its solve; qual/solve: the median of each step's quality \
         check against its solve; * a step split or its hierarchy rebuilt; min vol: final mesh against the \
         original; phases: the hierarchy's seconds per phase of the setup and of the median step's re-reference)"
    );
    s
}

/// Every step of every run, a row each: `STEPS_HEADER`'s columns.
pub fn csv(runs: &[Stepped]) -> String {
    let mut s = String::from(STEPS_HEADER);
    s.push('\n');
    for r in runs {
        let method = format!("{:?}", r.method).to_lowercase();
        for (i, st) in r.steps.iter().enumerate() {
            let _ = writeln!(
                s,
                "{},{method},{},{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{},{},{:.3e}",
                r.case,
                r.vertices,
                r.threads,
                i + 1,
                st.iterations,
                st.total_s,
                st.solve_s,
                st.reference_s,
                st.quality_s,
                st.rest_s(),
                st.substeps,
                u8::from(st.rebuilt),
                st.rel_residual
            );
        }
    }
    s
}

/// The columns of `DIR/steps.csv`.
pub const STEPS_HEADER: &str =
    "case,method,vertices,threads,step,iterations,advance_s,solve_s,reference_s,quality_s,rest_s,substeps,rebuilt,rel_residual";

/// "name seconds" per phase, and their sum.
fn phase_list(p: &Phases) -> String {
    let mut s: Vec<String> = p.named().iter().map(|(n, v)| format!("{n} {v:.3}")).collect();
    s.push(format!("sum {:.3}", p.total()));
    s.join(", ")
}

/// The median of the values (the upper one of an even count).
fn median_of(values: impl Iterator<Item = f64>) -> f64 {
    let mut v: Vec<f64> = values.collect();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}
