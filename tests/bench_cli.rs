//! `meshmove bench` runs on the smallest mesh and writes bench.csv with the header and a
//! row for every solver.

use std::process::Command;

#[test]
fn bench_writes_csv_with_every_solver() {
    let out = std::env::temp_dir().join(format!("meshmove-bench-{}", std::process::id()));
    let status = Command::new(env!("CARGO_BIN_EXE_meshmove"))
        .args(["bench", "--out"])
        .arg(&out)
        .args(["--max-vertices", "20000", "--threads", "1,2", "--jacobi-cap-s", "1", "--paper-cap-s", "2"])
        .output()
        .expect("meshmove runs");
    assert!(status.status.success(), "bench failed: {}", String::from_utf8_lossy(&status.stderr));
    let stdout = String::from_utf8_lossy(&status.stdout);
    assert!(stdout.contains("ratio to ours"), "table printed:\n{stdout}");
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
    let _ = std::fs::remove_dir_all(&out);
}
