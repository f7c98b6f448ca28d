//! `meshmove bench`: every method, paper-faithful and default mode, against a direct sparse
//! solve and the legacy Jacobi spring mover, on the free-surface case (docs/DESIGN.md §7) refined
//! uniformly from about 16 thousand to 4 million vertices; the same free surface with
//! least-squares coarse levels; its 3D analogue on hexahedral and tetrahedral boxes from about
//! 33 thousand to 2 million vertices; and the per-step cost of a 10-step motion in 2D and 3D.
//! Writes `DIR/bench.csv`, prints a table; then iterations with SLIP walls against FIXED ones
//! (`slip`, `DIR/slip.csv`).

mod alloc;
mod cases;
mod direct;
mod extrapolate;
mod jacobi;
mod peer;
#[cfg(feature = "mpi")]
mod ranks;
mod slip;
mod steps;
mod table;
mod viscous;

use cases::Case;
use extrapolate::seconds_to_tol;
use meshmove::bc::P;
use meshmove::multigrid::hierarchy::{HierarchyParams, Level};
use meshmove::{CoarseLevels, Method, Mode, Motion, Options, SolveParams, Solver};
use meshmove_cases::boxes::BoxCells;
use std::path::PathBuf;
use std::time::Instant;

pub const HEADER: &str =
    "case,solver,vertices,threads,levels,setup_s,cycle_s,iterations,solve_s,work_units,bytes_per_vertex,rel_residual";

/// The parts of a bench run.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// The 2D free surface: every method, paper-faithful mode, direct solve, Jacobi mover.
    #[value(name = "2d")]
    Uniform2d,
    /// The 2D free surface again on coarse meshes (`CoarseLevels::Remeshed`) instead of the
    /// default kept unknowns.
    #[value(name = "meshes")]
    Meshes2d,
    /// The 3D box of hexahedra and of tetrahedra: every method and the direct solve.
    #[value(name = "3d")]
    Uniform3d,
    /// The per-step cost of a 10-step motion, 2D and 3D.
    #[value(name = "steps")]
    Steps,
    /// Graded meshes: the 2D cylinder and the 3D sphere, wall cells 1/50 of the far cells (not in
    /// `--quick`).
    #[value(name = "graded")]
    Graded,
    /// Wall-layered meshes (airfoil, spheroid, wing) pitched and plunged, every method
    /// (`DIR/viscous.csv`; not in the default parts).
    #[value(name = "viscous")]
    Viscous,
    /// The distributed solver on the hexahedral box and the graded sphere, run under
    /// `mpirun -np N` in a build with the `mpi` feature (`DIR/ranks.csv`; alone, not in the
    /// default parts).
    #[value(name = "ranks")]
    Ranks,
}

/// A method of the `ranks` part.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum RanksMethod {
    /// Conjugate gradients with the distributed multigrid.
    Laplacian,
    /// Conjugate gradients with the Chebyshev–Jacobi smoother alone.
    Biharmonic,
}

/// A mesh of the `ranks` part.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum RanksMesh {
    /// The hexahedral box (`--cells-3d` cells per side with `--quick`, twice as many without).
    Box,
    /// The graded sphere.
    Sphere,
}

/// A method of the `steps` part.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepsMethod {
    /// The biharmonic (the paper's method).
    Biharmonic,
    /// The Laplacian.
    Laplacian,
}

impl StepsMethod {
    /// The library's method.
    pub fn method(self) -> Method {
        match self {
            StepsMethod::Biharmonic => Method::Biharmonic,
            StepsMethod::Laplacian => Method::Laplacian,
        }
    }
}

/// The cells of a 3D box.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoxKind {
    /// Hexahedra.
    Hex,
    /// Freudenthal tetrahedra.
    Tet,
}

#[derive(clap::Args, Clone, Debug)]
pub struct Args {
    /// Directory for bench.csv (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Largest 2D mesh: refine while the next mesh has at most this many vertices.
    #[arg(long, default_value_t = 4_500_000)]
    pub max_vertices: usize,
    /// Largest 3D box: double the cells per side while the box has at most this many vertices
    /// (33k, 250k, 1.95M, ...; below 32768 runs no 3D size). The default keeps a full run near
    /// a quarter of an hour; 2000000 adds the 1.95M boxes (about half an hour more, 2–3 GB).
    #[arg(long, default_value_t = 300_000)]
    pub max_vertices_3d: usize,
    /// The 3D boxes' cells, comma separated: hex, tet.
    #[arg(long, value_delimiter = ',', default_value = "hex,tet")]
    pub box_cells: Vec<BoxKind>,
    /// Cells per side of the smallest 3D box ((n + 1)³ vertices; 31 gives 32768).
    #[arg(long, default_value_t = cases::BASE_N_3D)]
    pub cells_3d: usize,
    /// Thread counts, comma separated; the multigrid default modes run at each, the rest
    /// (paper-faithful modes, direct, Jacobi, least-squares coarse levels, steps) at the
    /// largest only.
    #[arg(long, value_delimiter = ',', default_values_t = vec![1, 2])]
    pub threads: Vec<usize>,
    /// 2D direct solves only up to this many vertices (fill grows as N log N in memory, N^1.5
    /// in time).
    #[arg(long, default_value_t = 1_100_000)]
    pub direct_max_vertices: usize,
    /// 3D direct solves only up to this many vertices (fill grows as N^4/3 in memory, N² in
    /// time: the 33k biharmonic takes 0.7 GB and 8 s, the 250k one would take about 11 GB).
    #[arg(long, default_value_t = 40_000)]
    pub direct_max_vertices_3d: usize,
    /// Time-stepping rows only on meshes of at most this many vertices (the two smallest sizes
    /// of each dimension by default).
    #[arg(long, default_value_t = 300_000)]
    pub steps_max_vertices: usize,
    /// The methods of the `steps` part, comma separated: biharmonic, laplacian.
    #[arg(long, value_delimiter = ',', default_value = "biharmonic")]
    pub steps_methods: Vec<StepsMethod>,
    /// The `steps` part also on the graded sphere, at the graded part's 3D sizes up to
    /// --steps-max-vertices (and --max-vertices-3d).
    #[arg(long)]
    pub steps_graded: bool,
    /// Time cap of the Jacobi spring mover per size, as a multiple of our spring-mg solve of the
    /// same system: when it is capped, its ratio to ours is at least this (a measured lower
    /// bound, not an extrapolation).
    #[arg(long, default_value_t = 60.0)]
    pub jacobi_cap_x: f64,
    /// Absolute time cap of the Jacobi spring mover per size, seconds.
    #[arg(long, default_value_t = 600.0)]
    pub jacobi_cap_s: f64,
    /// Cap of the Jacobi spring mover as a sweep count (checked every 50 sweeps) instead of a
    /// time: the rows then do not depend on the machine's speed or load.
    #[arg(long, value_name = "SWEEPS")]
    pub jacobi_cap_sweeps: Option<usize>,
    /// Time cap of a paper-faithful solve per size, seconds (it stops at the cycle count that
    /// fits, and its rel_residual says how far it got).
    #[arg(long, default_value_t = 40.0)]
    pub paper_cap_s: f64,
    /// Cap of a paper-faithful solve as a cycle count instead of a time: which rows are capped
    /// then does not depend on the machine's speed or load.
    #[arg(long, value_name = "CYCLES")]
    pub paper_cap_cycles: Option<usize>,
    /// The headline numbers in a few minutes: the smallest 2D mesh (16.8k vertices) and 3D
    /// boxes (32.8k), no graded meshes, time caps of 5 s (a lower option value is kept).
    #[arg(long)]
    pub quick: bool,
    /// Relative residual every solver is run to.
    #[arg(long, default_value_t = 1e-8)]
    pub tol: f64,
    /// The parts to run, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "2d,meshes,3d,steps,graded")]
    pub parts: Vec<Part>,
    /// Sizes of each wall-layered mesh of the `viscous` part (1 to 4; `--quick`: 1): the
    /// smallest N. The 4th is the ≥ 1M-vertex mesh of each 3D kind, not in the default run.
    #[arg(long, default_value_t = 3)]
    pub viscous_sizes: usize,
    /// The smallest size the `viscous` part runs (1 to `--viscous-sizes`): with
    /// `--viscous-sizes 4 --viscous-from-size 4`, the ≥ 1M-vertex meshes alone.
    #[arg(long, default_value_t = 1)]
    pub viscous_from_size: usize,
    /// The methods of the `viscous` part, comma separated: biharmonic, laplacian, spring.
    #[arg(long, value_delimiter = ',', default_value = "biharmonic,laplacian,spring")]
    pub viscous_methods: Vec<viscous::MethodName>,
    /// The motions of the `viscous` part, comma separated, in the order they run: pitch, plunge.
    #[arg(long, value_delimiter = ',', default_value = "pitch,plunge")]
    pub viscous_motions: Vec<viscous::MotionName>,
    /// The meshes of the `viscous` part, comma separated: airfoil, spheroid, wing.
    #[arg(long, value_delimiter = ',', default_value = "airfoil,spheroid,wing")]
    pub viscous_meshes: Vec<viscous::MeshKind>,
    /// Steps of the `viscous` part's re-referenced runs (beside the one-step runs; `--quick`
    /// runs one step only).
    #[arg(long, default_value_t = 20)]
    pub viscous_steps: usize,
    /// Most CG iterations of one solve in the `viscous` part (a count, not a time, so which
    /// rows stop does not depend on the machine).
    #[arg(long, default_value_t = 500)]
    pub viscous_max_cycles: usize,
    /// The methods of the `ranks` part, comma separated: laplacian, biharmonic.
    #[arg(long, value_delimiter = ',', default_value = "laplacian,biharmonic")]
    pub ranks_methods: Vec<RanksMethod>,
    /// The meshes of the `ranks` part, comma separated: box, sphere.
    #[arg(long, value_delimiter = ',', default_value = "box,sphere")]
    pub ranks_meshes: Vec<RanksMesh>,
    /// Instead of running: write the 3D peer case (the hexahedral box of this many cells per
    /// side as box.msh, its motion as top.csv, the case as case.toml) to --out, for
    /// scripts/peer-openfoam.sh.
    #[arg(long, value_name = "CELLS")]
    pub peer_case: Option<usize>,
    /// Instead of running: write the points of this .vtu (`meshmove deform`'s result on the peer
    /// case's box.msh) as time 2 of the OpenFOAM case in --out/foam, for `checkMesh -time 2`.
    #[arg(long, value_name = "VTU")]
    pub peer_points: Option<PathBuf>,
}

/// One csv row.
#[derive(Clone, Debug)]
pub struct Row {
    case: &'static str,
    solver: &'static str,
    vertices: usize,
    threads: usize,
    levels: usize,
    setup_s: f64,
    cycle_s: f64,
    iterations: usize,
    solve_s: f64,
    work_units: f64,
    bytes_per_vertex: f64,
    rel_residual: f64,
    /// Estimated solve seconds to the tolerance where the run was capped (Jacobi).
    est_solve_s: Option<f64>,
}

impl Row {
    fn csv(&self) -> String {
        format!(
            "{},{},{},{},{},{:.6},{:.6},{},{:.6},{:.1},{:.0},{:.3e}",
            self.case,
            self.solver,
            self.vertices,
            self.threads,
            self.levels,
            self.setup_s,
            self.cycle_s,
            self.iterations,
            self.solve_s,
            self.work_units,
            self.bytes_per_vertex,
            self.rel_residual
        )
    }
}

/// Right-hand side of component `c` (the solver's own, rebuilt for the alternatives).
fn rhs(lev: &Level, motion: &Motion, c: usize) -> Vec<f64> {
    let vals = motion.vertex_values(lev.mesh());
    let dim = lev.mesh().dim();
    let flags = &lev.flags()[c];
    let dp: Vec<f64> = (0..lev.n())
        .map(|d| if flags[d] & P != 0 { vals[lev.dofs().dof_vertex[d] as usize * dim + c] } else { 0.0 })
        .collect();
    let (mut b, mut s) = (vec![0.0; lev.n()], vec![0.0; lev.n()]);
    lev.op().rhs(flags, &dp, None, &mut b, &mut s);
    b
}

fn rel_residual(lev: &Level, c: usize, b: &[f64], x: &[f64]) -> f64 {
    let (mut r, mut s) = (vec![0.0; lev.n()], vec![0.0; lev.n()]);
    lev.op().residual(&lev.flags()[c], b, x, &mut r, &mut s);
    meshmove::sparse::dot(&r, &r).sqrt() / meshmove::sparse::dot(b, b).sqrt()
}

/// Seconds of one fine-level operator application (the work unit), best of a few batches.
fn op_seconds(lev: &Level, c: usize) -> f64 {
    let n = lev.n();
    let x: Vec<f64> = (0..n).map(|i| ((i * 7919) % 1000) as f64 * 1e-3).collect();
    let (mut y, mut s) = (vec![0.0; n], vec![0.0; n]);
    let reps = (2_000_000 / n).clamp(3, 200);
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let t = Instant::now();
        for _ in 0..reps {
            lev.op().apply(&lev.flags()[c], &x, &mut y, &mut s);
        }
        best = best.min(t.elapsed().as_secs_f64() / reps as f64);
    }
    best
}

/// How the coarse levels of a default-mode row are made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Levels {
    /// The default (`CoarseLevels::Auto`: kept unknowns).
    Default,
    /// `CoarseLevels::Remeshed` (the 2D comparison).
    Meshes,
}

fn name(method: Method, mode: Mode, levels: Levels) -> &'static str {
    match (method, mode, levels) {
        (Method::Biharmonic, Mode::Default, Levels::Default) => "biharmonic-mg",
        (Method::Biharmonic, Mode::Default, Levels::Meshes) => "biharmonic-mg-meshes",
        (Method::Biharmonic, Mode::PaperFaithful, _) => "biharmonic-mg-paper",
        (Method::Laplacian, Mode::Default, Levels::Default) => "laplacian-mg",
        (Method::Laplacian, Mode::Default, Levels::Meshes) => "laplacian-mg-meshes",
        (Method::Laplacian, Mode::PaperFaithful, _) => "laplacian-mg-paper",
        (Method::Spring, _, Levels::Default) => "spring-mg",
        (Method::Spring, _, Levels::Meshes) => "spring-mg-meshes",
    }
}

/// The options of a default-mode solver at `threads` threads.
fn options(method: Method, solve: SolveParams, threads: usize, levels: Levels) -> Options {
    let coarse_levels = match levels {
        Levels::Default => CoarseLevels::Auto,
        Levels::Meshes => CoarseLevels::Remeshed,
    };
    Options {
        method,
        solve,
        threads,
        hierarchy: HierarchyParams { coarse_levels, ..Default::default() },
        ..Default::default()
    }
}

/// A default-mode solver built at one thread count, with what its construction and first
/// solve measured, and its fastest solve so far.
struct Built {
    solver: Solver,
    setup_s: f64,
    bytes_per_vertex: f64,
    best: (f64, meshmove::Report),
}

/// What every row of one case, size, thread count and method shares.
pub struct RowBase {
    case: &'static str,
    vertices: usize,
    threads: usize,
    levels: usize,
    /// The work unit: one fine-level application of the method's operator, seconds.
    op_s: f64,
}

impl RowBase {
    fn row(&self, solver: &'static str, solve_s: f64, iterations: usize, rel: f64, bytes: f64, setup_s: f64) -> Row {
        Row {
            case: self.case,
            solver,
            vertices: self.vertices,
            threads: self.threads,
            levels: self.levels,
            setup_s,
            cycle_s: solve_s / iterations.max(1) as f64,
            iterations,
            solve_s,
            work_units: solve_s / self.op_s,
            bytes_per_vertex: bytes,
            rel_residual: rel,
            est_solve_s: None,
        }
    }
}

/// The default-mode solver of `method` built in each pool (setup timed there, the solver's own
/// threads as many as the pool's), each solved once.
fn build_at_each(
    case: &Case,
    solve: SolveParams,
    method: Method,
    levels: Levels,
    pools: &[(usize, rayon::ThreadPool)],
) -> Result<Vec<Built>, String> {
    let nv = case.mesh.num_vertices();
    pools
        .iter()
        .map(|(threads, pool)| {
            // Memory: peak growth over construction and the first solve (counted allocation).
            let base = alloc::start();
            pool.install(|| {
                let t = Instant::now();
                let opts = options(method, solve, *threads, levels);
                let solver = Solver::new(&case.mesh, &case.bcs, opts).map_err(|e| e.to_string())?;
                let setup_s = t.elapsed().as_secs_f64();
                let t = Instant::now();
                let sol = solver.solve_report(&case.motion, None).map_err(|e| e.to_string())?;
                let best = (t.elapsed().as_secs_f64(), sol.report);
                let bytes_per_vertex = alloc::peak_above(base) as f64 / nv as f64;
                Ok(Built { solver, setup_s, bytes_per_vertex, best })
            })
        })
        .collect()
}

/// Alternating rounds stop once the solves so far took this long (seconds)...
const ROUND_BUDGET_S: f64 = 3.0;
/// ...or after this many solves per thread count.
const MAX_SOLVES: usize = 9;

/// More solves per thread count, the counts alternating round by round, keeping each count's
/// fastest: the machines this runs on are shared, and a slow phase of the host then hits every
/// thread count alike instead of one (the 1→2 thread speed-up is a ratio of these). With the
/// first solve of `build_at_each`, at least two solves per count; more while the solves so far
/// took under `ROUND_BUDGET_S`, up to `MAX_SOLVES`, so the short rows, which a host hiccup of a
/// few milliseconds moves most, get the most samples at a cost of seconds.
fn alternate_solves(built: &mut [Built], pools: &[(usize, rayon::ThreadPool)], motion: &Motion) -> Result<(), String> {
    let mut total: f64 = built.iter().map(|b| b.best.0).sum();
    for round in 1..MAX_SOLVES {
        if round > 1 && total > ROUND_BUDGET_S {
            break;
        }
        for (b, (_, pool)) in built.iter_mut().zip(pools) {
            let t = Instant::now();
            let sol = pool.install(|| b.solver.solve_report(motion, None)).map_err(|e| e.to_string())?;
            let dt = t.elapsed().as_secs_f64();
            total += dt;
            if dt < b.best.0 {
                b.best = (dt, sol.report);
            }
        }
    }
    Ok(())
}

/// All rows of one case on one mesh: the default modes at every thread count of `pools`, and
/// with `Levels::Default` the alternatives at the last (largest) count (paper-faithful modes
/// and the Jacobi mover in 2D, the direct solve where it fits). A method whose solver cannot be
/// built or solve is a line in `failed`, and the bench goes on with the next.
fn run_case(
    a: &Args,
    case: &Case,
    levels: Levels,
    pools: &[(usize, rayon::ThreadPool)],
    rows: &mut Vec<Row>,
    failed: &mut Vec<String>,
) -> Result<(), String> {
    let nv = case.mesh.num_vertices();
    for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
        let solve = SolveParams { tol: a.tol, ..Default::default() };
        let built = build_at_each(case, solve, method, levels, pools)
            .and_then(|mut b| alternate_solves(&mut b, pools, &case.motion).map(|()| b));
        let built = match built {
            Ok(b) => b,
            Err(e) => {
                let line = format!("{} {} at {nv} vertices: {e}", case.name, name(method, Mode::Default, levels));
                eprintln!("  FAILED: {line}");
                failed.push(line);
                continue;
            }
        };
        let mut last = None;
        for (b, (threads, pool)) in built.into_iter().zip(pools) {
            let op_s = pool.install(|| op_seconds(b.solver.hierarchy().fine(), case.comp));
            let base =
                RowBase { case: case.name, vertices: nv, threads: *threads, levels: b.solver.num_levels(), op_s };
            let (solve_s, rep) = &b.best;
            let r = rep.rel_residual;
            let nm = name(method, Mode::Default, levels);
            rows.push(base.row(nm, *solve_s, rep.cycles, r, b.bytes_per_vertex, b.setup_s));
            report(rows.last().expect("row"));
            last = Some((b, base, pool));
        }
        let Some((b, base, pool)) = last else {
            return Err("no thread count".into());
        };
        if levels == Levels::Default {
            // A paper-faithful cycle may diverge (graded meshes): a failed row, not a failed run.
            if let Err(e) = pool.install(|| alternatives(a, method, b, &base, case, rows)) {
                let line = format!("{} {method:?} alternatives at {nv} vertices: {e}", case.name);
                eprintln!("  FAILED: {line}");
                failed.push(line);
            }
        }
    }
    Ok(())
}

/// The paper-faithful mode of `method` (its own solver: in 2D on the paper's coarse meshes) and the
/// alternatives a user would pick instead: the direct solve, or for the spring the Jacobi mover.
/// In 3D only the direct solve: the paper-faithful W-cycle and the Jacobi mover need hundreds to
/// thousands of cycles or sweeps, minutes per 3D size, to show what the 2D rows already show.
fn alternatives(
    a: &Args,
    method: Method,
    b: Built,
    base: &RowBase,
    case: &Case,
    rows: &mut Vec<Row>,
) -> Result<(), String> {
    let Built { solver, best: (solve_s, _), .. } = b;
    let (nv, motion, comp) = (base.vertices, &case.motion, case.comp);
    let dim = case.mesh.dim();
    if method != Method::Spring && dim == 2 {
        // Paper-faithful: its own solver on the paper's coarse meshes; time one cycle, then
        // allow as many as fit in the cap (or the given count).
        let mut solve = SolveParams { tol: a.tol, mode: Mode::PaperFaithful, max_cycles: 1, ..Default::default() };
        let opts = Options { solve, ..solver.options().clone() };
        let mem = alloc::start();
        let t = Instant::now();
        let mut paper = Solver::new(&case.mesh, &case.bcs, opts).map_err(|e| e.to_string())?;
        let paper_setup_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        paper.solve_report(motion, None).map_err(|e| e.to_string())?;
        let one = t.elapsed().as_secs_f64();
        solve.max_cycles = match a.paper_cap_cycles {
            Some(n) => n,
            None => ((a.paper_cap_s / one) as usize).clamp(1, 5000),
        };
        paper.set_solve_params(solve).map_err(|e| e.to_string())?;
        let t = Instant::now();
        let sol = paper.solve_report(motion, None).map_err(|e| e.to_string())?;
        let paper_s = t.elapsed().as_secs_f64();
        let bytes = alloc::peak_above(mem) as f64 / nv as f64;
        let r = &sol.report;
        // Stopped by the cap: its time is a lower bound, and the table adds the estimate.
        let hist: Vec<(usize, f64)> = r.history.iter().enumerate().map(|(k, &(_, rel))| (k + 1, rel)).collect();
        let est = seconds_to_tol(&hist, paper_s, a.tol);
        let nm = name(method, Mode::PaperFaithful, Levels::Default);
        rows.push(Row {
            est_solve_s: (r.rel_residual > a.tol).then_some(est),
            levels: paper.num_levels(),
            ..base.row(nm, paper_s, r.cycles, r.rel_residual, bytes, paper_setup_s)
        });
        report(rows.last().expect("row"));
    }
    let lev = solver.hierarchy().fine();
    let b = rhs(lev, motion, comp);
    let mut x = vec![0.0; lev.n()];
    let direct_max = if dim == 2 { a.direct_max_vertices } else { a.direct_max_vertices_3d };
    if method == Method::Spring {
        if dim != 2 {
            return Ok(());
        }
        let mem = alloc::start();
        let cap = match a.jacobi_cap_sweeps {
            Some(n) => jacobi::Cap::Sweeps(n),
            None => jacobi::Cap::Seconds((a.jacobi_cap_x * solve_s).min(a.jacobi_cap_s)),
        };
        let j = jacobi::solve(lev, comp, &b, &mut x, a.tol, cap);
        // Its own vectors plus the fine K, V, 1/V, 1/D it sweeps with (no hierarchy).
        let k = &lev.op().k;
        let fine = std::mem::size_of_val(&k.row_ptr[..]) + k.nnz() * 12 + lev.n() * (3 * 8 + 2);
        let bytes = (alloc::peak_above(mem) + fine) as f64 / nv as f64;
        rows.push(Row {
            levels: 1,
            setup_s: 0.0,
            est_solve_s: (j.rel_residual > a.tol).then_some(j.est_seconds),
            ..base.row("spring-jacobi", j.seconds, j.sweeps, j.rel_residual, bytes, 0.0)
        });
        report(rows.last().expect("row"));
    } else if nv <= direct_max {
        let mem = alloc::start();
        let d = direct::solve(lev, comp, &b, &mut x)?;
        let bytes = alloc::peak_above(mem) as f64 / nv as f64;
        let rel = rel_residual(lev, comp, &b, &x);
        let nm = if method == Method::Biharmonic { "biharmonic-direct" } else { "laplacian-direct" };
        // A moving mesh changes A every step: the factorisation is part of each solve.
        rows.push(Row { levels: 1, ..base.row(nm, d.factor_s + d.solve_s, 1, rel, bytes, d.factor_s) });
        report(rows.last().expect("row"));
    } else {
        let opt = if dim == 2 { "--direct-max-vertices" } else { "--direct-max-vertices-3d" };
        eprintln!("  (direct {method:?} skipped on {} at {nv} vertices: above {opt})", case.name);
    }
    Ok(())
}

fn report(r: &Row) {
    eprintln!("  {}", r.csv());
}

/// Every option checked before anything runs or is written, so a bad value costs nothing and
/// names itself. Unchecked, a bad cap would be silently replaced by another: `f64::min` drops
/// a NaN Jacobi multiple for the absolute cap, and a NaN or zero paper budget becomes 1 cycle.
fn check_args(a: &Args) -> Result<(), String> {
    if a.threads.is_empty() || a.threads.contains(&0) {
        return Err("--threads needs thread counts of at least 1".into());
    }
    if a.out.exists() && !a.out.is_dir() {
        return Err(format!("--out {} exists and is not a directory", a.out.display()));
    }
    let positive = |name: &str, v: f64| {
        if v > 0.0 && v.is_finite() {
            Ok(())
        } else {
            Err(format!("{name} must be a positive finite number, got {v}"))
        }
    };
    positive("--jacobi-cap-x", a.jacobi_cap_x)?;
    positive("--jacobi-cap-s", a.jacobi_cap_s)?;
    positive("--paper-cap-s", a.paper_cap_s)?;
    if !(a.tol > 0.0 && a.tol < 1.0) {
        return Err(format!("--tol must be a relative residual between 0 and 1, got {}", a.tol));
    }
    if a.parts.is_empty() {
        return Err("--parts needs at least one part".into());
    }
    if a.cells_3d < 2 {
        return Err(format!("--cells-3d must be at least 2, got {}", a.cells_3d));
    }
    if a.jacobi_cap_sweeps == Some(0) || a.paper_cap_cycles == Some(0) {
        return Err("--jacobi-cap-sweeps and --paper-cap-cycles must be at least 1".into());
    }
    if !(1..=viscous::SIZES).contains(&a.viscous_sizes) || a.viscous_steps == 0 || a.viscous_max_cycles == 0 {
        return Err(format!(
            "--viscous-sizes takes 1 to {}; --viscous-steps and --viscous-max-cycles at least 1",
            viscous::SIZES
        ));
    }
    if !(1..=a.viscous_sizes).contains(&a.viscous_from_size) {
        return Err(format!("--viscous-from-size takes 1 to --viscous-sizes ({})", a.viscous_sizes));
    }
    if a.viscous_methods.is_empty() || a.viscous_motions.is_empty() {
        return Err("--viscous-methods and --viscous-motions need at least one each".into());
    }
    if let Some(n) = a.peer_case {
        if !(1..=400).contains(&n) {
            return Err(format!("--peer-case takes 1 to 400 cells per side, got {n}"));
        }
    }
    Ok(())
}

/// `--quick`'s sizes and caps: each option keeps its own value where that is smaller.
fn quick(a: &Args) -> Args {
    let mut q = a.clone();
    q.max_vertices = a.max_vertices.min(QUICK_MAX_VERTICES);
    q.max_vertices_3d = a.max_vertices_3d.min(QUICK_MAX_VERTICES_3D);
    q.jacobi_cap_s = a.jacobi_cap_s.min(QUICK_CAP_S);
    q.paper_cap_s = a.paper_cap_s.min(QUICK_CAP_S);
    q.parts.retain(|&p| p != Part::Graded);
    q.viscous_sizes = 1;
    q.viscous_from_size = 1;
    if q.parts.is_empty() {
        q.parts = a.parts.clone();
    }
    q
}

/// `--quick`: the smallest 2D mesh, the 32.8k boxes, 5 s caps.
const QUICK_MAX_VERTICES: usize = 20_000;
const QUICK_MAX_VERTICES_3D: usize = 40_000;
const QUICK_CAP_S: f64 = 5.0;

pub fn run(a: &Args) -> Result<(), String> {
    check_args(a)?;
    let quick_args;
    let a = if a.quick {
        quick_args = quick(a);
        &quick_args
    } else {
        a
    };
    if let Some(n) = a.peer_case {
        std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
        return peer::write_case(&a.out, n);
    }
    if let Some(vtu) = &a.peer_points {
        return peer::write_points(vtu, &a.out.join("foam"));
    }
    if a.parts.contains(&Part::Ranks) {
        return distributed(a);
    }
    let has = |p: Part| a.parts.contains(&p);
    // The smallest mesh is cheap to build; checking against it first keeps a too-small
    // --max-vertices from writing anything.
    let mut mesh = cases::free_surface_base();
    if mesh.num_vertices() > a.max_vertices {
        return Err(format!(
            "--max-vertices {} is below the smallest bench mesh ({} vertices)",
            a.max_vertices,
            mesh.num_vertices()
        ));
    }
    let boxes = cases::box_sizes(a.cells_3d, a.max_vertices_3d);
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    // One pool per thread count, ascending: the alternatives run in the last (largest).
    let mut counts = a.threads.clone();
    counts.sort_unstable();
    counts.dedup();
    let pools = counts
        .iter()
        .map(|&t| Ok((t, rayon::ThreadPoolBuilder::new().num_threads(t).build().map_err(|e| e.to_string())?)))
        .collect::<Result<Vec<_>, String>>()?;
    let last = std::slice::from_ref(pools.last().expect("a thread count"));
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into());
    println!(
        "meshmove bench: free surface (2D: A = {}; 3D box: A = {}), to a {:e} relative residual; CPU {cpu}, {} cores",
        cases::A_2D,
        cases::A_3D,
        a.tol,
        std::thread::available_parallelism().map_or(0, |n| n.get())
    );
    let t_all = Instant::now();
    let mut rows = Vec::new();
    let mut stepped = Vec::new();
    let mut failed = Vec::new();
    let stepping = has(Part::Steps);
    let mut steps_done = [0usize; 2];
    loop {
        let nv = mesh.num_vertices();
        let case = cases::free_surface_2d(mesh);
        eprintln!("{} {nv} vertices", case.name);
        if has(Part::Uniform2d) {
            run_case(a, &case, Levels::Default, &pools, &mut rows, &mut failed)?;
        }
        if has(Part::Meshes2d) {
            run_case(a, &case, Levels::Meshes, last, &mut rows, &mut failed)?;
        }
        if stepping && nv <= a.steps_max_vertices && steps_done[0] < 2 {
            steps::run_methods(a, &case, &last[0], &mut rows, &mut stepped, &mut failed);
            steps_done[0] += 1;
        }
        // The next size is needed by the 2D parts, or by the steps while they have sizes to go.
        let more = has(Part::Uniform2d)
            || has(Part::Meshes2d)
            || (stepping && steps_done[0] < 2 && 4 * nv <= a.steps_max_vertices);
        if 4 * nv > a.max_vertices || !more {
            break;
        }
        mesh = case.mesh.refined().map_err(|e| e.to_string())?;
    }
    for &n in &boxes {
        let nv = (n + 1).pow(3);
        let run3d = has(Part::Uniform3d);
        let step = stepping && nv <= a.steps_max_vertices && steps_done[1] < 2;
        if !run3d && !step {
            continue;
        }
        for cells in [BoxCells::Hexes, BoxCells::Tets] {
            let wanted = a.box_cells.contains(if cells == BoxCells::Hexes { &BoxKind::Hex } else { &BoxKind::Tet });
            // The steps run on the hexahedral box whichever boxes the 3D part runs, and on the
            // tetrahedral one when it is asked for.
            let steps_here = step && (cells == BoxCells::Hexes || wanted);
            if !(steps_here || run3d && wanted) {
                continue;
            }
            let case = cases::free_surface_box(n, cells);
            eprintln!("{} {nv} vertices", case.name);
            if run3d && wanted {
                run_case(a, &case, Levels::Default, &pools, &mut rows, &mut failed)?;
            }
            if steps_here {
                steps::run_methods(a, &case, &last[0], &mut rows, &mut stepped, &mut failed);
                steps_done[1] += 1;
            }
        }
    }
    if stepping && a.steps_graded {
        for n in cases::graded_sphere_sizes(a.max_vertices_3d.min(a.steps_max_vertices)) {
            let case = cases::graded_sphere(n);
            eprintln!("{} {} vertices", case.name, case.mesh.num_vertices());
            steps::run_methods(a, &case, &last[0], &mut rows, &mut stepped, &mut failed);
        }
    }
    if has(Part::Graded) {
        for make in cases::graded_cases(a.max_vertices, a.max_vertices_3d) {
            let case = make();
            eprintln!("{} {} vertices", case.name, case.mesh.num_vertices());
            run_case(a, &case, Levels::Default, &pools, &mut rows, &mut failed)?;
            if case.mesh.dim() == 2 {
                // Where the 2D routes part: graded meshes.
                run_case(a, &case, Levels::Meshes, &pools, &mut rows, &mut failed)?;
            }
        }
    }
    let viscous_table = if has(Part::Viscous) {
        let plan = viscous::Plan {
            meshes: a.viscous_meshes.clone(),
            sizes: a.viscous_from_size - 1..a.viscous_sizes,
            methods: a.viscous_methods.iter().map(|m| m.method()).collect(),
            motions: a.viscous_motions.iter().map(|m| m.motion()).collect(),
            steps: if a.quick || a.viscous_steps == 1 { vec![1] } else { vec![1, a.viscous_steps] },
            max_cycles: a.viscous_max_cycles,
            tol: a.tol,
        };
        viscous::run_all(&a.out, &plan, &last[0].1)?
    } else {
        String::new()
    };
    let mut csv = String::from(HEADER);
    csv.push('\n');
    for r in &rows {
        csv += &r.csv();
        csv.push('\n');
    }
    let path = a.out.join("bench.csv");
    std::fs::write(&path, csv).map_err(|e| format!("{}: {e}", path.display()))?;
    if !stepped.is_empty() {
        let steps_path = a.out.join("steps.csv");
        std::fs::write(&steps_path, steps::csv(&stepped)).map_err(|e| format!("{}: {e}", steps_path.display()))?;
    }
    print!("{}", table::table(&rows, a.tol));
    print!("{}", steps::table(&stepped));
    for f in &failed {
        println!("FAILED: {f}");
    }
    if has(Part::Uniform3d) && !boxes.is_empty() {
        println!("3D: no paper-faithful or Jacobi rows (hundreds to thousands of cycles or sweeps per size; the 2D rows measure them)");
    }
    // Slip walls against fixed ones on the cylinder channel (its own sizes, up to a quarter of
    // the largest free-surface mesh: its refinements grow the same way); not for the viscous
    // part alone.
    if a.parts.iter().any(|&p| p != Part::Viscous) {
        print!("{}", slip::run(&a.out, a.max_vertices / 4, a.tol)?);
    }
    print!("{viscous_table}");
    println!(
        "wall {:.1} s; peak resident set (VmHWM) {:.0} MB; bytes_per_vertex counts allocation by the solver (counting allocator)",
        t_all.elapsed().as_secs_f64(),
        alloc::vm_hwm().unwrap_or(0) as f64 / 1e6
    );
    println!("wrote {}", path.display());
    Ok(())
}

/// The `ranks` part: alone, under mpirun, in a build with the `mpi` feature.
fn distributed(a: &Args) -> Result<(), String> {
    if a.parts.len() > 1 {
        return Err("--parts ranks runs alone (every rank would run the other parts)".into());
    }
    #[cfg(feature = "mpi")]
    if crate::distributed::launched() {
        return ranks::run(a);
    }
    Err("--parts ranks runs under `mpirun -np N` in a build with the `mpi` feature \
         (cargo build --release -p meshmove-cli --features mpi)"
        .into())
}
