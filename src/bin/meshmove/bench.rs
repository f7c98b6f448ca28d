//! `meshmove bench`: every method, paper-faithful and default mode, against a direct sparse
//! solve and the legacy Jacobi spring mover, on the free-surface case (docs/DESIGN.md §7) refined
//! uniformly from about 16 thousand to 4 million vertices. Writes `DIR/bench.csv`, prints a table;
//! then iterations with SLIP walls against FIXED ones (`slip`, `DIR/slip.csv`).

mod alloc;
mod direct;
mod extrapolate;
mod jacobi;
mod slip;

use extrapolate::seconds_to_tol;
use meshmove::bc::P;
use meshmove::cases::meshes::{free_surface, FS_BOTTOM, FS_LEFT, FS_RIGHT, FS_TOP};
use meshmove::multigrid::hierarchy::Level;
use meshmove::{BoundaryConditions, Kind, Link, Mesh, Method, Mode, Motion, Options, SolveParams, Solver};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

pub const HEADER: &str =
    "solver,vertices,threads,levels,setup_s,cycle_s,iterations,solve_s,work_units,bytes_per_vertex,rel_residual";

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Directory for bench.csv (created if missing).
    #[arg(long)]
    pub out: PathBuf,
    /// Largest mesh: refine while the next mesh has at most this many vertices.
    #[arg(long, default_value_t = 4_500_000)]
    pub max_vertices: usize,
    /// Thread counts, comma separated; the multigrid default modes run at each, the rest
    /// (paper-faithful modes, direct, Jacobi) at the largest only.
    #[arg(long, value_delimiter = ',', default_values_t = vec![1, 2])]
    pub threads: Vec<usize>,
    /// Direct solves only up to this many vertices (fill grows as N log N in memory, N^1.5 in time).
    #[arg(long, default_value_t = 1_100_000)]
    pub direct_max_vertices: usize,
    /// Time cap of the Jacobi spring mover per size, as a multiple of our spring-mg solve of the
    /// same system: when it is capped, its ratio to ours is at least this (a measured lower
    /// bound, not an extrapolation).
    #[arg(long, default_value_t = 60.0)]
    pub jacobi_cap_x: f64,
    /// Absolute time cap of the Jacobi spring mover per size, seconds.
    #[arg(long, default_value_t = 600.0)]
    pub jacobi_cap_s: f64,
    /// Time cap of a paper-faithful solve per size, seconds (it stops at the cycle count that
    /// fits, and its rel_residual says how far it got).
    #[arg(long, default_value_t = 40.0)]
    pub paper_cap_s: f64,
    /// Relative residual every solver is run to.
    #[arg(long, default_value_t = 1e-8)]
    pub tol: f64,
}

/// One csv row.
#[derive(Clone, Debug)]
struct Row {
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
            "{},{},{},{},{:.6},{:.6},{},{:.6},{:.1},{:.0},{:.3e}",
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

/// The free-surface case: bottom fixed, top clamped and moved by A cos(2πx), periodic sides.
fn case(mesh: &Mesh) -> (BoundaryConditions, Motion) {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(FS_BOTTOM, Kind::Fixed).set_kinds(FS_TOP, Kind::Clamped);
    for p in [FS_LEFT, FS_RIGHT] {
        bcs.set_kind(p, 0, Kind::Clamped).expect("component 0").set_kind(p, 1, Kind::Free).expect("component 1");
    }
    bcs.add_link(Link::ByOffset { a: FS_LEFT, b: FS_RIGHT, offset: [1.0, 0.0, 0.0], tol: 1e-9 });
    let mut motion = Motion::zero(mesh);
    for v in mesh.patch_vertices(FS_TOP) {
        let x = mesh.point(v as usize)[0];
        motion.displacement[2 * v as usize + 1] = 0.25 * (std::f64::consts::TAU * x).cos();
    }
    (bcs, motion)
}

/// Base mesh spacing: about 16.8 thousand vertices; each uniform refinement ×4.
const BASE_H: f64 = 1.0 / 120.0;
/// The motion is in y: component 1 carries the whole solve (x has a zero right-hand side).
const COMP: usize = 1;

/// Right-hand side of component `c` (the solver's own, rebuilt for the alternatives).
fn rhs(lev: &Level, motion: &Motion, c: usize) -> Vec<f64> {
    let vals = motion.vertex_values(lev.mesh());
    let flags = &lev.flags[c];
    let dp: Vec<f64> = (0..lev.n())
        .map(|d| if flags[d] & P != 0 { vals[lev.dofs.dof_vertex[d] as usize * 2 + c] } else { 0.0 })
        .collect();
    let (mut b, mut s) = (vec![0.0; lev.n()], vec![0.0; lev.n()]);
    lev.op.rhs(flags, &dp, None, &mut b, &mut s);
    b
}

fn rel_residual(lev: &Level, c: usize, b: &[f64], x: &[f64]) -> f64 {
    let (mut r, mut s) = (vec![0.0; lev.n()], vec![0.0; lev.n()]);
    lev.op.residual(&lev.flags[c], b, x, &mut r, &mut s);
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
            lev.op.apply(&lev.flags[c], &x, &mut y, &mut s);
        }
        best = best.min(t.elapsed().as_secs_f64() / reps as f64);
    }
    best
}

fn name(method: Method, mode: Mode) -> &'static str {
    match (method, mode) {
        (Method::Biharmonic, Mode::Default) => "biharmonic-mg",
        (Method::Biharmonic, Mode::PaperFaithful) => "biharmonic-mg-paper",
        (Method::Laplacian, Mode::Default) => "laplacian-mg",
        (Method::Laplacian, Mode::PaperFaithful) => "laplacian-mg-paper",
        (Method::Spring, _) => "spring-mg",
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

/// What every row of one size, thread count and method shares.
struct RowBase {
    vertices: usize,
    threads: usize,
    levels: usize,
    /// The work unit: one fine-level application of the method's operator, seconds.
    op_s: f64,
}

impl RowBase {
    fn row(&self, solver: &'static str, solve_s: f64, iterations: usize, rel: f64, bytes: f64, setup_s: f64) -> Row {
        Row {
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

/// The default-mode solver of `method` built in each pool (setup timed there), each solved once.
fn build_at_each(
    mesh: &Mesh,
    bcs: &BoundaryConditions,
    motion: &Motion,
    solve: SolveParams,
    method: Method,
    pools: &[(usize, rayon::ThreadPool)],
) -> Result<Vec<Built>, String> {
    let nv = mesh.num_vertices();
    pools
        .iter()
        .map(|(_, pool)| {
            // Memory: peak growth over construction and the first solve (counted allocation).
            let base = alloc::start();
            pool.install(|| {
                let t = Instant::now();
                let opts = Options { method, solve, threads: 0, ..Default::default() };
                let solver = Solver::new(mesh, bcs, opts).map_err(|e| e.to_string())?;
                let setup_s = t.elapsed().as_secs_f64();
                let t = Instant::now();
                let sol = solver.solve_report(motion, None).map_err(|e| e.to_string())?;
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

/// All rows of one mesh size: the default modes at every thread count of `pools`, the
/// paper-faithful modes and the alternatives at the last (largest) count.
fn run_size(a: &Args, mesh: &Mesh, pools: &[(usize, rayon::ThreadPool)], rows: &mut Vec<Row>) -> Result<(), String> {
    let nv = mesh.num_vertices();
    let (bcs, motion) = case(mesh);
    for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
        let solve = SolveParams { tol: a.tol, ..Default::default() };
        let mut built = build_at_each(mesh, &bcs, &motion, solve, method, pools)?;
        alternate_solves(&mut built, pools, &motion)?;
        let mut last = None;
        for (b, (threads, pool)) in built.into_iter().zip(pools) {
            let op_s = pool.install(|| op_seconds(b.solver.hierarchy().fine(), COMP));
            let base = RowBase { vertices: nv, threads: *threads, levels: b.solver.num_levels(), op_s };
            let (solve_s, rep) = &b.best;
            let r = rep.rel_residual;
            rows.push(base.row(name(method, Mode::Default), *solve_s, rep.cycles, r, b.bytes_per_vertex, b.setup_s));
            report(rows.last().expect("row"));
            last = Some((b, base, pool));
        }
        let Some((b, base, pool)) = last else {
            return Err("no thread count".into());
        };
        pool.install(|| alternatives(a, method, b, &base, &motion, rows))?;
    }
    Ok(())
}

/// The paper-faithful mode of `method` (on its default solver `b`, re-parametrised) and the
/// alternatives a user would pick instead: the direct solve, or for the spring the Jacobi mover.
fn alternatives(
    a: &Args,
    method: Method,
    b: Built,
    base: &RowBase,
    motion: &Motion,
    rows: &mut Vec<Row>,
) -> Result<(), String> {
    let Built { mut solver, setup_s, bytes_per_vertex: bytes, best: (solve_s, _) } = b;
    let nv = base.vertices;
    if method != Method::Spring {
        // Paper-faithful: time one cycle, then allow as many as fit in the cap.
        let mut solve = SolveParams { tol: a.tol, mode: Mode::PaperFaithful, max_cycles: 1, ..Default::default() };
        solver.set_solve_params(solve).map_err(|e| e.to_string())?;
        let t = Instant::now();
        solver.solve_report(motion, None).map_err(|e| e.to_string())?;
        let one = t.elapsed().as_secs_f64();
        solve.max_cycles = ((a.paper_cap_s / one) as usize).clamp(1, 5000);
        solver.set_solve_params(solve).map_err(|e| e.to_string())?;
        let mem = alloc::start();
        let t = Instant::now();
        let sol = solver.solve_report(motion, None).map_err(|e| e.to_string())?;
        let paper_s = t.elapsed().as_secs_f64();
        let extra = alloc::peak_above(mem) as f64 / nv as f64;
        let r = &sol.report;
        // Memory: the hierarchy (measured with the default solve) plus what this solve adds.
        let hier = bytes.max(extra);
        // Stopped by the cap: its time is a lower bound, and the table adds the estimate.
        let hist: Vec<(usize, f64)> = r.history.iter().enumerate().map(|(k, &(_, rel))| (k + 1, rel)).collect();
        let est = seconds_to_tol(&hist, paper_s, a.tol);
        rows.push(Row {
            est_solve_s: (r.rel_residual > a.tol).then_some(est),
            ..base.row(name(method, Mode::PaperFaithful), paper_s, r.cycles, r.rel_residual, hier, setup_s)
        });
        report(rows.last().expect("row"));
    }
    let lev = solver.hierarchy().fine();
    let b = rhs(lev, motion, COMP);
    let mut x = vec![0.0; lev.n()];
    if method == Method::Spring {
        let mem = alloc::start();
        let cap = (a.jacobi_cap_x * solve_s).min(a.jacobi_cap_s);
        let j = jacobi::solve(lev, COMP, &b, &mut x, a.tol, cap);
        // Its own vectors plus the fine K, V, 1/V, 1/D it sweeps with (no hierarchy).
        let k = &lev.op.k;
        let fine = std::mem::size_of_val(&k.row_ptr[..]) + k.nnz() * 12 + lev.n() * (3 * 8 + 2);
        let bytes = (alloc::peak_above(mem) + fine) as f64 / nv as f64;
        rows.push(Row {
            levels: 1,
            setup_s: 0.0,
            est_solve_s: (j.rel_residual > a.tol).then_some(j.est_seconds),
            ..base.row("spring-jacobi", j.seconds, j.sweeps, j.rel_residual, bytes, 0.0)
        });
        report(rows.last().expect("row"));
    } else if nv <= a.direct_max_vertices {
        let mem = alloc::start();
        let d = direct::solve(lev, COMP, &b, &mut x)?;
        let bytes = alloc::peak_above(mem) as f64 / nv as f64;
        let rel = rel_residual(lev, COMP, &b, &x);
        let nm = if method == Method::Biharmonic { "biharmonic-direct" } else { "laplacian-direct" };
        // A moving mesh changes A every step: the factorisation is part of each solve.
        rows.push(Row { levels: 1, ..base.row(nm, d.factor_s + d.solve_s, 1, rel, bytes, d.factor_s) });
        report(rows.last().expect("row"));
    } else {
        println!("  (direct {method:?} skipped at {nv} vertices: above --direct-max-vertices)");
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
    Ok(())
}

pub fn run(a: &Args) -> Result<(), String> {
    check_args(a)?;
    // The smallest mesh is cheap to build; checking against it first keeps a too-small
    // --max-vertices from writing anything.
    let mut mesh = free_surface(BASE_H);
    if mesh.num_vertices() > a.max_vertices {
        return Err(format!(
            "--max-vertices {} is below the smallest bench mesh ({} vertices)",
            a.max_vertices,
            mesh.num_vertices()
        ));
    }
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    // One pool per thread count, ascending: the alternatives run in the last (largest).
    let mut counts = a.threads.clone();
    counts.sort_unstable();
    counts.dedup();
    let pools = counts
        .iter()
        .map(|&t| Ok((t, rayon::ThreadPoolBuilder::new().num_threads(t).build().map_err(|e| e.to_string())?)))
        .collect::<Result<Vec<_>, String>>()?;
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into());
    println!(
        "meshmove bench: free-surface case, A = 0.25, to a {:e} relative residual; CPU {cpu}, {} cores",
        a.tol,
        std::thread::available_parallelism().map_or(0, |n| n.get())
    );
    let t_all = Instant::now();
    let mut rows = Vec::new();
    loop {
        let nv = mesh.num_vertices();
        eprintln!("{nv} vertices");
        run_size(a, &mesh, &pools, &mut rows)?;
        if 4 * nv > a.max_vertices {
            break;
        }
        mesh = mesh.refine_uniform();
    }
    let mut csv = String::from(HEADER);
    csv.push('\n');
    for r in &rows {
        csv += &r.csv();
        csv.push('\n');
    }
    let path = a.out.join("bench.csv");
    std::fs::write(&path, csv).map_err(|e| format!("{}: {e}", path.display()))?;
    print!("{}", table(&rows));
    // Slip walls against fixed ones on the cylinder channel (its own sizes, up to a quarter of
    // the largest free-surface mesh: its refinements grow the same way).
    print!("{}", slip::run(&a.out, a.max_vertices / 4, a.tol)?);
    println!(
        "wall {:.1} s; peak resident set (VmHWM) {:.0} MB; bytes_per_vertex counts allocation by the solver (counting allocator)",
        t_all.elapsed().as_secs_f64(),
        alloc::vm_hwm().unwrap_or(0) as f64 / 1e6
    );
    println!("wrote {}", path.display());
    Ok(())
}

/// The printed table: every row, with its time ratio to our default multigrid solve of the same
/// system at the same size and thread count.
fn table(rows: &[Row]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<20} {:>8} {:>3} {:>3} {:>8} {:>9} {:>6} {:>9} {:>8} {:>6} {:>9}  ratio to ours",
        "solver", "vertices", "thr", "lev", "setup_s", "cycle_s", "iter", "solve_s", "work_u", "B/vert", "rel_res",
    );
    for r in rows {
        let ours = match r.solver {
            "biharmonic-mg-paper" | "biharmonic-direct" => Some("biharmonic-mg"),
            "laplacian-mg-paper" | "laplacian-direct" => Some("laplacian-mg"),
            "spring-jacobi" => Some("spring-mg"),
            _ => None,
        };
        let ratio = ours
            .and_then(|o| rows.iter().find(|q| q.solver == o && q.vertices == r.vertices && q.threads == r.threads))
            .map(|o| match r.est_solve_s {
                Some(e) if e.is_finite() => {
                    format!(">= {:.1}x (capped; est. {:.0}x)", r.solve_s / o.solve_s, e / o.solve_s)
                }
                Some(_) => format!(">= {:.1}x (capped; no estimate)", r.solve_s / o.solve_s),
                None => format!("{:.1}x", r.solve_s / o.solve_s),
            })
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "{:<20} {:>8} {:>3} {:>3} {:>8.3} {:>9.5} {:>6} {:>9.3} {:>8.0} {:>6.0} {:>9.1e}  {}",
            r.solver,
            r.vertices,
            r.threads,
            r.levels,
            r.setup_s,
            r.cycle_s,
            r.iterations,
            r.solve_s,
            r.work_units,
            r.bytes_per_vertex,
            r.rel_residual,
            ratio
        );
    }
    // Per size: biharmonic/Laplacian time, seconds per vertex, thread speed-up.
    let get =
        |name: &str, nv: usize, t: usize| rows.iter().find(|r| r.solver == name && r.vertices == nv && r.threads == t);
    let mut sizes: Vec<usize> = rows.iter().map(|r| r.vertices).collect();
    sizes.dedup();
    let tmax = rows.iter().map(|r| r.threads).max().unwrap_or(1);
    let tmin = rows.iter().map(|r| r.threads).min().unwrap_or(1);
    let _ = writeln!(
        s,
        "\n{:>8} {:>14} {:>16} {:>16} {:>22}",
        "vertices",
        "bih/lap time",
        "bih us/vertex",
        "setup/solve",
        format!("speed-up {tmin}->{tmax} thr")
    );
    for &nv in &sizes {
        let (Some(b), Some(l)) = (get("biharmonic-mg", nv, tmax), get("laplacian-mg", nv, tmax)) else { continue };
        // One thread count has no speed-up to show (the column stays blank, not 1.00x).
        let sp = get("biharmonic-mg", nv, tmin)
            .filter(|_| tmin < tmax)
            .map_or(String::new(), |b1| format!("{:.2}x", b1.solve_s / b.solve_s));
        let _ = writeln!(
            s,
            "{nv:>8} {:>14.2} {:>16.3} {:>16.2} {:>22}",
            b.solve_s / l.solve_s,
            1e6 * b.solve_s / nv as f64,
            b.setup_s / b.solve_s,
            sp
        );
    }
    s
}
