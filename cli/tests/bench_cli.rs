//! `meshmove bench` runs on the smallest meshes and writes bench.csv with the header and
//! a row for every solver: the 2D free surface (with least-squares coarse levels too), the 3D
//! boxes, the time-stepping rows; and it writes the 3D peer case that `meshmove deform` runs.

use std::path::Path;
use std::process::{Command, Output};

const HEADER: &str =
    "case,solver,vertices,threads,levels,setup_s,cycle_s,iterations,solve_s,work_units,bytes_per_vertex,rel_residual";

fn bench(out: &Path, args: &[&str]) -> Output {
    let run = Command::new(env!("CARGO_BIN_EXE_meshmove"))
        .args(["bench", "--out"])
        .arg(out)
        .args(args)
        .output()
        .expect("meshmove runs");
    assert!(run.status.success(), "bench failed: {}", String::from_utf8_lossy(&run.stderr));
    run
}

/// The csv's rows, each checked: 12 fields, every one after the case and solver a number.
fn rows(csv: &str) -> Vec<Vec<String>> {
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(HEADER));
    let rows: Vec<Vec<String>> = lines.map(|l| l.split(',').map(str::to_string).collect()).collect();
    for r in &rows {
        assert_eq!(r.len(), 12, "row {r:?}");
        for v in &r[2..] {
            assert!(v.parse::<f64>().is_ok(), "not a number: {v} in {r:?}");
        }
    }
    rows
}

fn num(r: &[String], i: usize) -> f64 {
    r[i].parse().unwrap()
}

#[test]
fn bench_writes_csv_with_every_solver() {
    let out = std::env::temp_dir().join(format!("meshmove-bench-{}", std::process::id()));
    let args = [
        "--parts",
        "2d,meshes",
        "--max-vertices",
        "20000",
        "--threads",
        "1,2",
        "--jacobi-cap-sweeps",
        "200",
        "--paper-cap-cycles",
        "20",
    ];
    let status = bench(&out, &args);
    let stdout = String::from_utf8_lossy(&status.stdout);
    assert!(stdout.contains("ratio to ours"), "table printed:\n{stdout}");
    // The slip-wall comparison: with the default coarse levels SLIP within 1.3× the iterations
    // of FIXED walls; coarse meshes beside them.
    let slip = std::fs::read_to_string(out.join("slip.csv")).expect("slip.csv written");
    assert!(slip.starts_with("walls,coarse_levels,method,vertices,levels,fixed_iterations,slip_iterations"));
    for walls in ["straight", "turned"] {
        let kept = format!("{walls},kept,");
        for l in slip.lines().filter(|l| l.starts_with(&kept)) {
            let f: Vec<f64> = l.split(',').skip(3).map(|v| v.parse().unwrap()).collect();
            assert!(f[3] <= 1.3 * f[2], "slip iterations: {l}");
        }
        assert_eq!(slip.lines().filter(|l| l.starts_with(&kept)).count(), 3, "{slip}");
        assert_eq!(slip.lines().filter(|l| l.starts_with(&format!("{walls},meshes,"))).count(), 3, "{slip}");
    }
    let csv = std::fs::read_to_string(out.join("bench.csv")).expect("bench.csv written");
    let all = rows(&csv);
    assert!(all.iter().all(|r| r[0] == "free-surface-2d"), "{all:?}");
    // From here on the 2D checks, the case column dropped.
    let rows: Vec<Vec<&str>> = all.iter().map(|r| r[1..].iter().map(String::as_str).collect()).collect();
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
    // The paper-faithful biharmonic needs ≈ 600 cycles here; 20 stop it early (a count, so the
    // outcome does not depend on the machine's load), and the table then gives its ratio as a
    // lower bound with an estimate, never as a finished solve.
    let paper = rows.iter().find(|r| r[0] == "biharmonic-mg-paper").expect("paper row");
    assert!(paper[10].parse::<f64>().unwrap() > 1e-8, "{paper:?}");
    let line = stdout.lines().find(|l| l.contains(" biharmonic-mg-paper ")).expect("paper line");
    assert!(line.contains(">= ") && line.contains("(capped; est. "), "{line}");
    assert_eq!(paper[6], "20", "{paper:?}");
    // The Jacobi mover stops at its 200 sweeps, far from the tolerance, and is marked the same way.
    let jacobi = rows.iter().find(|r| r[0] == "spring-jacobi").expect("jacobi row");
    assert!(jacobi[6] == "200" && jacobi[10].parse::<f64>().unwrap() > 1e-8, "{jacobi:?}");
    let line = stdout.lines().find(|l| l.contains(" spring-jacobi ")).expect("jacobi line");
    assert!(line.contains("(capped; est. "), "{line}");
    // Coarse meshes: every method, at the largest thread count only, converged, and compared
    // with the default kept unknowns in their own table.
    for name in ["biharmonic-mg-meshes", "laplacian-mg-meshes", "spring-mg-meshes"] {
        let r: Vec<_> = rows.iter().filter(|r| r[0] == name).collect();
        assert_eq!(r.len(), 1, "{name}: {r:?}");
        assert_eq!(r[0][2], "2");
        assert!(r[0][10].parse::<f64>().unwrap() <= 1e-8, "{r:?}");
    }
    assert!(stdout.contains("coarse levels: kept unknowns (default) against coarse meshes"), "{stdout}");
    let line = stdout.lines().find(|l| l.contains(" biharmonic ") && l.contains(" / ")).expect("coarse levels line");
    assert!(line.starts_with("free-surface-2d"), "{line}");
    let _ = std::fs::remove_dir_all(&out);
}

/// The 3D rows on small boxes (--cells-3d 11: 1728 vertices) and the time-stepping rows.
#[test]
fn bench_3d_and_steps_rows() {
    let out = std::env::temp_dir().join(format!("meshmove-bench-3d-{}", std::process::id()));
    let args = [
        "--parts",
        "3d,steps",
        "--max-vertices",
        "20000",
        "--cells-3d",
        "11",
        "--max-vertices-3d",
        "2000",
        "--steps-methods",
        "biharmonic,laplacian",
    ];
    let run = bench(&out, &[&args[..], &["--threads", "1,2"]].concat());
    let stdout = String::from_utf8_lossy(&run.stdout);
    let rows = rows(&std::fs::read_to_string(out.join("bench.csv")).expect("bench.csv written"));
    let find = |case: &str, solver: &str| -> Vec<&Vec<String>> {
        rows.iter().filter(|r| r[0] == case && r[1] == solver).collect()
    };
    for case in ["box-hex-3d", "box-tet-3d"] {
        for solver in ["biharmonic-mg", "laplacian-mg", "spring-mg"] {
            let r = find(case, solver);
            // Both thread counts, 1728 vertices, converged, the same iterations on both.
            assert_eq!(r.len(), 2, "{case} {solver}: {r:?}");
            assert!(r.iter().all(|r| r[2] == "1728" && num(r, 11) <= 1e-8), "{r:?}");
            assert_eq!(r[0][7], r[1][7], "{r:?}");
        }
        for solver in ["biharmonic-direct", "laplacian-direct"] {
            let r = find(case, solver);
            assert_eq!(r.len(), 1, "{case} {solver}: {r:?}");
            assert!(num(r[0], 11) <= 1e-12, "{r:?}");
        }
        // No paper-faithful or Jacobi rows in 3D.
        assert!(rows.iter().all(|r| r[0] != case || !(r[1].ends_with("-paper") || r[1] == "spring-jacobi")));
    }
    // The biharmonic's iterations: within the goal of 12 (measured: hexahedra 5, tetrahedra 10).
    for case in ["box-hex-3d", "box-tet-3d"] {
        let it: usize = find(case, "biharmonic-mg")[0][7].parse().unwrap();
        assert!(it <= 12, "{case}: {it} iterations");
    }
    // Steps: the 2D free surface (16.8k) and both boxes, three rows each per method, at the
    // largest thread count, converged.
    for case in ["free-surface-2d", "box-hex-3d", "box-tet-3d"] {
        for method in ["biharmonic", "laplacian"] {
            for pick in ["step1", "step-median", "step-worst"] {
                let r = find(case, &format!("{method}-{pick}"));
                assert_eq!(r.len(), 1, "{case} {method}-{pick}: {r:?}");
                assert!(r[0][3] == "2" && num(r[0], 11) <= 1e-8 && num(r[0], 7) >= 1.0, "{r:?}");
            }
            let line = stdout
                .lines()
                .find(|l| l.starts_with(case) && l.contains(&format!(" {method} ")) && l.contains(" / "))
                .expect("steps line");
            // Ten iteration counts at the end of the line.
            let its: Vec<&str> = line.split("  ").last().unwrap().split_whitespace().collect();
            assert_eq!(its.len(), 10, "{line}");
        }
    }
    assert!(stdout.contains("time stepping: the motion in 10 steps"), "{stdout}");
    assert!(stdout.contains("  median re-reference (s): unknowns "), "{stdout}");
    // steps.csv: every step of every run, its phases apart and within the call's seconds.
    let steps = std::fs::read_to_string(out.join("steps.csv")).expect("steps.csv written");
    let mut lines = steps.lines();
    assert_eq!(
        lines.next(),
        Some(
            "case,method,vertices,threads,step,iterations,advance_s,solve_s,reference_s,quality_s,rest_s,substeps,\
             rebuilt,rel_residual"
        )
    );
    let steps: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(steps.len(), 3 * 2 * 10, "{steps:?}");
    for r in &steps {
        let v: Vec<f64> = r[2..].iter().map(|v| v.parse().expect("a number")).collect();
        let (advance, solve, reference, quality, rest) = (v[4], v[5], v[6], v[7], v[8]);
        assert!(v[3] >= 1.0 && solve > 0.0 && reference >= 0.0 && quality > 0.0, "{r:?}");
        // The four phases are disjoint parts of the call (printed to a microsecond).
        assert!(rest >= -2e-6 && (solve + reference + quality + rest - advance).abs() <= 5e-6, "{r:?}");
    }
    // Step 1 has no re-reference (the solver starts at the mesh); every later step has one.
    for r in &steps {
        assert_eq!(r[8] == "0.000000", r[4] == "1", "{r:?}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// `--peer-case N` writes the hexahedral box, its motion and case file, and `meshmove deform`
/// moves the box's top by 0.1 cos 2πx cos 2πy.
#[test]
fn bench_writes_the_peer_case_that_deform_runs() {
    let dir = std::env::temp_dir().join(format!("meshmove-bench-peer-{}", std::process::id()));
    bench(&dir, &["--peer-case", "4"]);
    for f in ["box.msh", "top.csv", "case.toml"] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    let top = std::fs::read_to_string(dir.join("top.csv")).unwrap();
    assert_eq!(top.lines().count(), 1 + 25, "{top}");
    let out = dir.join("out.vtu");
    let run = Command::new(env!("CARGO_BIN_EXE_meshmove"))
        .arg("deform")
        .arg(dir.join("box.msh"))
        .arg("--config")
        .arg(dir.join("case.toml"))
        .arg("-o")
        .arg(&out)
        .output()
        .expect("meshmove runs");
    assert!(run.status.success(), "deform failed: {}", String::from_utf8_lossy(&run.stderr));
    let moved = meshmove::io::read_vtu(&out).unwrap();
    let (_, d, nc) = moved.point_data.iter().find(|f| f.0 == "displacement").expect("displacement");
    assert_eq!(*nc, 3);
    // The written positions are the moved ones: top vertices at 1 + 0.1 cos 2πx cos 2πy.
    let m = &moved.mesh;
    let mut top = 0;
    for v in 0..m.num_vertices() {
        let p = m.point(v);
        let z0 = p[2] - d[3 * v + 2];
        if (z0 - 1.0).abs() < 1e-12 {
            let (x, y) = (p[0] - d[3 * v], p[1] - d[3 * v + 1]);
            let want = 0.1 * (std::f64::consts::TAU * x).cos() * (std::f64::consts::TAU * y).cos();
            assert!(
                (d[3 * v + 2] - want).abs() < 1e-12 && d[3 * v].abs() < 1e-12,
                "vertex {v}: {:?}",
                &d[3 * v..3 * v + 3]
            );
            top += 1;
        }
    }
    assert_eq!(top, 25);
    // The OpenFOAM case: 4³ cells, 3·4²·3 = 144 internal faces and 6·4² = 96 boundary faces, the
    // top's 25 displacements; our moved points written beside OpenFOAM's as time 2.
    let owner = std::fs::read_to_string(dir.join("foam/constant/polyMesh/owner")).unwrap();
    assert!(owner.contains("nPoints:125  nCells:64  nFaces:240  nInternalFaces:144"), "{owner}");
    let disp = std::fs::read_to_string(dir.join("foam/0/pointDisplacement")).unwrap();
    assert!(disp.contains("nonuniform List<vector>\n25\n(\n(0 0 0.1)\n"), "{disp}");
    bench(&dir, &["--peer-points", out.to_str().unwrap()]);
    let points = std::fs::read_to_string(dir.join("foam/2/polyMesh/points")).unwrap();
    assert!(points.contains("\n125\n(\n(0.0 0.0 0.0)\n"), "{points}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The viscous part on the smallest airfoil with the spring in 1 and 3 steps: a row a run in
/// viscous.csv and a row a step in viscous_steps.csv, up to the step that ended the run (the
/// spring's pitch tangles the layers; its plunge, a translation, does not).
#[test]
fn bench_viscous_rows_and_steps() {
    let out = std::env::temp_dir().join(format!("meshmove-bench-viscous-{}", std::process::id()));
    let args = ["--parts", "viscous", "--viscous-meshes", "airfoil", "--viscous-sizes", "1", "--threads", "1"];
    bench(&out, &[&args[..], &["--viscous-methods", "spring", "--viscous-steps", "3"]].concat());
    let runs = std::fs::read_to_string(out.join("viscous.csv")).unwrap();
    let runs: Vec<Vec<&str>> = runs.lines().skip(1).map(|l| l.split(',').collect()).collect();
    let steps = std::fs::read_to_string(out.join("viscous_steps.csv")).unwrap();
    let mut lines = steps.lines();
    assert_eq!(
        lines.next(),
        Some(
            "mesh,size,vertices,method,motion,steps,step,iterations,converged,inverted,step_min_volume_ratio,\
first_layer_min,first_layer_max,step_s"
        )
    );
    let steps: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // Pitch and plunge, 1 and 3 steps, the spring only.
    let kinds: Vec<(&str, &str)> = runs.iter().map(|r| (r[5], r[6])).collect();
    assert_eq!(kinds, [("pitch", "1"), ("pitch", "3"), ("plunge", "1"), ("plunge", "3")]);
    let mut rest = &steps[..];
    for r in &runs {
        assert_eq!((r[0], r[1], r[2], r[4]), ("airfoil-2d", "pps64", "8328", "spring"), "{r:?}");
        // The steps the run took: all it asked for, or up to the step its status names.
        let n: usize = match r[7] {
            "ok" => r[6].parse().unwrap(),
            s => s.strip_prefix("step ").and_then(|s| s.split(':').next()).unwrap().parse().unwrap(),
        };
        let (mine, others) = rest.split_at(n);
        rest = others;
        for (i, st) in mine.iter().enumerate() {
            assert_eq!((st[0], st[1], st[2], st[3], st[4], st[5]), (r[0], r[1], r[2], r[4], r[5], r[6]), "{st:?}");
            assert_eq!((st[6].parse::<usize>().unwrap(), st[8]), (i + 1, "true"), "{st:?}");
            let it: usize = st[7].parse().unwrap();
            assert!((1..=10).contains(&it), "{st:?}");
            let (lo, hi): (f64, f64) = (st[11].parse().unwrap(), st[12].parse().unwrap());
            assert!(0.0 < lo && lo <= hi, "{st:?}");
            // Only the step that ended a run tangled.
            let inverted: usize = st[9].parse().unwrap();
            assert_eq!(inverted > 0, r[7].contains("inverted") && i + 1 == n, "{st:?} of {r:?}");
            if r[5] == "plunge" {
                assert!(0.999 < lo && hi < 1.001, "{st:?}");
            }
        }
        // The run's own first-layer range is its last step's.
        let last = &mine[n - 1];
        assert_eq!((r[15], r[16]), (last[11], last[12]), "{r:?}");
    }
    assert!(rest.is_empty(), "{rest:?}");
    assert_eq!(runs.iter().filter(|r| r[7] == "ok").count(), 2, "the plunges: {runs:?}");
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
        (&["--paper-cap-cycles", "0"], "--paper-cap-cycles"),
        (&["--jacobi-cap-sweeps", "0"], "--jacobi-cap-sweeps"),
        (&["--threads", "0"], "--threads"),
        (&["--threads", "1,0"], "--threads"),
        (&["--max-vertices", "0"], "--max-vertices"),
        (&["--max-vertices", "16000"], "below the smallest bench mesh"),
        (&["--cells-3d", "1"], "--cells-3d"),
        (&["--peer-case", "0"], "--peer-case"),
        (&["--viscous-sizes", "5"], "--viscous-sizes"),
        (&["--viscous-from-size", "4"], "--viscous-from-size"),
        (&["--viscous-sizes", "2", "--viscous-from-size", "0"], "--viscous-from-size"),
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
