//! The printed tables: every row with its time ratio to our default multigrid solve of the same
//! system; per case and size the biharmonic's cost against the Laplacian's, per vertex and per
//! thread count; and coarse meshes against the default kept unknowns.

use super::Row;
use std::fmt::Write as _;

/// The default multigrid row an alternative is compared with.
fn ours(solver: &str) -> Option<&'static str> {
    match solver {
        "biharmonic-mg-paper" | "biharmonic-direct" | "biharmonic-mg-meshes" => Some("biharmonic-mg"),
        "laplacian-mg-paper" | "laplacian-direct" | "laplacian-mg-meshes" => Some("laplacian-mg"),
        "spring-jacobi" | "spring-mg-meshes" => Some("spring-mg"),
        _ => None,
    }
}

/// The distinct values of `key` over `rows`, in order of first appearance.
fn distinct<T: PartialEq + Copy>(rows: &[Row], key: impl Fn(&Row) -> T) -> Vec<T> {
    let mut out = Vec::new();
    for r in rows {
        let k = key(r);
        if !out.contains(&k) {
            out.push(k);
        }
    }
    out
}

/// The table of every row; a multigrid row that stopped above `tol` (at its cycle limit) says
/// so in place of a ratio.
pub fn table(rows: &[Row], tol: f64) -> String {
    let rows: Vec<Row> = rows.iter().filter(|r| !r.solver.contains("-step")).cloned().collect();
    let rows = &rows[..];
    let find = |case: &str, name: &str, nv: usize, t: usize| {
        rows.iter().find(|r| r.case == case && r.solver == name && r.vertices == nv && r.threads == t)
    };
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<16} {:<20} {:>8} {:>3} {:>3} {:>8} {:>9} {:>6} {:>9} {:>8} {:>6} {:>9}  ratio to ours",
        "case",
        "solver",
        "vertices",
        "thr",
        "lev",
        "setup_s",
        "cycle_s",
        "iter",
        "solve_s",
        "work_u",
        "B/vert",
        "rel_res",
    );
    for r in rows {
        let stopped = r.solver.contains("-mg") && !r.solver.ends_with("-paper") && r.rel_residual > tol;
        let ratio = ours(r.solver)
            .and_then(|o| find(r.case, o, r.vertices, r.threads))
            .map(|o| match r.est_solve_s {
                Some(e) if e.is_finite() => {
                    format!(">= {:.1}x (capped; est. {:.0}x)", r.solve_s / o.solve_s, e / o.solve_s)
                }
                Some(_) => format!(">= {:.1}x (capped; no estimate)", r.solve_s / o.solve_s),
                None => format!("{:.1}x", r.solve_s / o.solve_s),
            })
            .unwrap_or_default();
        let ratio = if stopped { format!("NOT converged ({} iterations) {ratio}", r.iterations) } else { ratio };
        let _ = writeln!(
            s,
            "{:<16} {:<20} {:>8} {:>3} {:>3} {:>8.3} {:>9.5} {:>6} {:>9.3} {:>8.0} {:>6.0} {:>9.1e}  {}",
            r.case,
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
    // Per case and size: biharmonic/Laplacian time, µs per vertex, setup in solves, thread
    // speed-up.
    let tmax = rows.iter().map(|r| r.threads).max().unwrap_or(1);
    let tmin = rows.iter().map(|r| r.threads).min().unwrap_or(1);
    let _ = writeln!(
        s,
        "\n{:<16} {:>8} {:>14} {:>16} {:>16} {:>22}",
        "case",
        "vertices",
        "bih/lap time",
        "bih us/vertex",
        "setup/solve",
        format!("speed-up {tmin}->{tmax} thr")
    );
    for case in distinct(rows, |r| r.case) {
        for nv in distinct(rows, |r| r.vertices) {
            let (Some(b), Some(l)) = (find(case, "biharmonic-mg", nv, tmax), find(case, "laplacian-mg", nv, tmax))
            else {
                continue;
            };
            // One thread count has no speed-up to show (the column stays blank, not 1.00x).
            let sp = find(case, "biharmonic-mg", nv, tmin)
                .filter(|_| tmin < tmax)
                .map_or(String::new(), |b1| format!("{:.2}x", b1.solve_s / b.solve_s));
            let _ = writeln!(
                s,
                "{case:<16} {nv:>8} {:>14.2} {:>16.3} {:>16.2} {:>22}",
                b.solve_s / l.solve_s,
                1e6 * b.solve_s / nv as f64,
                b.setup_s / b.solve_s,
                sp
            );
        }
    }
    s += &meshes_table(rows);
    s
}

/// Coarse meshes (`-mg-meshes`) against the default kept unknowns of the same case, size and
/// thread count: iterations, solve and setup seconds, bytes per vertex.
fn meshes_table(rows: &[Row]) -> String {
    let mut s = String::new();
    let meshes: Vec<&Row> = rows.iter().filter(|r| r.solver.ends_with("-mg-meshes")).collect();
    if meshes.is_empty() {
        return s;
    }
    let _ = writeln!(
        s,
        "\ncoarse levels: kept unknowns (default) against coarse meshes\n{:<16} {:<12} {:>8} {:>3} {:>11} {:>17} {:>17} {:>11}",
        "case", "method", "vertices", "thr", "iter", "solve_s", "setup_s", "B/vert"
    );
    for r in meshes {
        let Some(d) = ours(r.solver).and_then(|o| {
            rows.iter()
                .find(|q| q.case == r.case && q.solver == o && q.vertices == r.vertices && q.threads == r.threads)
        }) else {
            continue;
        };
        let method = r.solver.trim_end_matches("-mg-meshes");
        let _ = writeln!(
            s,
            "{:<16} {:<12} {:>8} {:>3} {:>5} / {:<3} {:>7.3} / {:<7.3} {:>7.3} / {:<7.3} {:>5.0} / {:<4.0}",
            r.case,
            method,
            r.vertices,
            r.threads,
            d.iterations,
            r.iterations,
            d.solve_s,
            r.solve_s,
            d.setup_s,
            r.setup_s,
            d.bytes_per_vertex,
            r.bytes_per_vertex
        );
    }
    let _ = writeln!(s, "(each pair: kept unknowns / coarse meshes)");
    s
}
