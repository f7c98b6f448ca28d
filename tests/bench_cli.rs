//! `meshmove bench` runs on the smallest mesh and writes bench.csv with the header and a
//! row for every solver.

use std::process::Command;

#[test]
fn bench_writes_csv_with_every_solver() {
    let out = std::env::temp_dir().join(format!("meshmove-bench-{}", std::process::id()));
    let status = Command::new(env!("CARGO_BIN_EXE_meshmove"))
        .args(["bench", "--out"])
        .arg(&out)
        .args(["--max-vertices", "20000", "--threads", "1,2", "--jacobi-cap-s", "1", "--paper-cap-s", "0.05"])
        .output()
        .expect("meshmove runs");
    assert!(status.status.success(), "bench failed: {}", String::from_utf8_lossy(&status.stderr));
    let stdout = String::from_utf8_lossy(&status.stdout);
    assert!(stdout.contains("ratio to ours"), "table printed:\n{stdout}");
    // The slip-wall comparison: SLIP within 1.3× the iterations of FIXED walls.
    let slip = std::fs::read_to_string(out.join("slip.csv")).expect("slip.csv written");
    assert!(slip.starts_with("method,vertices,levels,fixed_iterations,slip_iterations"));
    for l in slip.lines().skip(1) {
        let f: Vec<f64> = l.split(',').skip(1).map(|v| v.parse().unwrap()).collect();
        assert!(f[3] <= 1.3 * f[2], "slip iterations: {l}");
    }
    assert_eq!(slip.lines().count(), 4, "{slip}");
    let csv = std::fs::read_to_string(out.join("bench.csv")).expect("bench.csv written");
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("solver,vertices,threads,levels,setup_s,cycle_s,iterations,solve_s,work_units,bytes_per_vertex,rel_residual")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    for r in &rows {
        assert_eq!(r.len(), 11, "row {r:?}");
        for v in &r[1..] {
            assert!(v.parse::<f64>().is_ok(), "not a number: {v} in {r:?}");
        }
    }
    for name in [
        "biharmonic-mg",
        "biharmonic-mg-paper",
        "laplacian-mg",
        "laplacian-mg-paper",
        "spring-mg",
        "biharmonic-direct",
        "laplacian-direct",
        "spring-jacobi",
    ] {
        assert!(rows.iter().any(|r| r[0] == name), "no row for {name}");
    }
    // One mesh size (about 16.8k vertices); the default multigrid modes at both thread counts.
    assert!(rows.iter().all(|r| r[1] == rows[0][1]));
    assert!(rows.iter().any(|r| r[0] == "biharmonic-mg" && r[2] == "1"));
    assert!(rows.iter().any(|r| r[0] == "biharmonic-mg" && r[2] == "2"));
    // Multigrid and direct rows reach the tolerance.
    for r in rows.iter().filter(|r| r[0].ends_with("-mg") || r[0].ends_with("-direct")) {
        assert!(r[10].parse::<f64>().unwrap() <= 1e-8, "{r:?}");
    }
    // The paper-faithful biharmonic needs ≈ 600 cycles here; 0.05 s stops it early, and the table
    // then gives its ratio as a lower bound with an estimate, never as a finished solve.
    let paper = rows.iter().find(|r| r[0] == "biharmonic-mg-paper").expect("paper row");
    assert!(paper[10].parse::<f64>().unwrap() > 1e-8, "{paper:?}");
    let line = stdout.lines().find(|l| l.starts_with("biharmonic-mg-paper")).expect("paper line");
    assert!(line.contains(">= ") && line.contains("(capped; est. "), "{line}");
    let _ = std::fs::remove_dir_all(&out);
}

/// A bad option is refused before anything runs: exit status 1, a message naming the option,
/// and no output directory created.
#[test]
fn bench_refuses_bad_options_before_running() {
    let cases: &[(&[&str], &str)] = &[
        (&["--tol", "nan"], "--tol"),
        (&["--tol", "0"], "--tol"),
        (&["--tol", "1.5"], "--tol"),
        (&["--jacobi-cap-x", "0"], "--jacobi-cap-x"),
        (&["--jacobi-cap-x=-3"], "--jacobi-cap-x"),
        (&["--jacobi-cap-s", "inf"], "--jacobi-cap-s"),
        (&["--paper-cap-s", "nan"], "--paper-cap-s"),
        (&["--threads", "0"], "--threads"),
        (&["--threads", "1,0"], "--threads"),
        (&["--max-vertices", "0"], "--max-vertices"),
        (&["--max-vertices", "16000"], "below the smallest bench mesh"),
    ];
    for (i, (args, names)) in cases.iter().enumerate() {
        let out = std::env::temp_dir().join(format!("meshmove-bench-bad-{}-{i}", std::process::id()));
        let run = Command::new(env!("CARGO_BIN_EXE_meshmove"))
            .args(["bench", "--out"])
            .arg(&out)
            .args(*args)
            .output()
            .expect("meshmove runs");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{args:?} exits 1: {stderr}");
        assert!(stderr.contains("error") && stderr.contains(names), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} created {}", out.display());
    }
    // An --out that is a file.
    let file = std::env::temp_dir().join(format!("meshmove-bench-file-{}", std::process::id()));
    std::fs::write(&file, "not a directory").unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_meshmove")).args(["bench", "--out"]).arg(&file).output().unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("is not a directory"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "not a directory");
    let _ = std::fs::remove_file(&file);
    // A value clap cannot parse is clap's usage error (exit 2), also before anything runs.
    let run = Command::new(env!("CARGO_BIN_EXE_meshmove"))
        .args(["bench", "--out", "unused", "--max-vertices", "-1"])
        .output()
        .expect("meshmove runs");
    assert_eq!(run.status.code(), Some(2));
}
