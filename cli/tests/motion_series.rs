//! Time series of motions in `meshmove deform`: a periodic rigid motion (`period`), a table of
//! rigid totals per step (`translations`, `rotations_deg`), a displacement file per step
//! (`files`), `--every K` writing the step meshes, and the errors of ill-formed series.

use meshmove::io::read_vtu;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/examples")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("meshmove-series-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn deform(mesh: &str, dir: &Path, case: &str, extra: &[&str]) -> Output {
    std::fs::write(dir.join("case.toml"), case).unwrap();
    Command::new(env!("CARGO_BIN_EXE_meshmove"))
        .arg("deform")
        .arg(examples().join(mesh))
        .arg("--config")
        .arg(dir.join("case.toml"))
        .arg("-o")
        .arg(dir.join("out.vtu"))
        .args(extra)
        .output()
        .expect("runs meshmove")
}

fn ok(o: &Output) {
    assert!(o.status.success(), "{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
}

/// The original and moved points of a written mesh (3 coordinates each) where `pick` holds.
fn points(path: &Path, pick: impl Fn(&[f64]) -> bool) -> Vec<([f64; 3], [f64; 3])> {
    let d = read_vtu(path).unwrap();
    let dim = d.mesh.dim;
    let disp = &d.point_data.iter().find(|p| p.0 == "displacement").unwrap().1;
    let mut out = Vec::new();
    for (v, x) in d.mesh.coords.chunks_exact(dim).enumerate() {
        let mut moved = [0.0; 3];
        moved[..dim].copy_from_slice(x);
        let x0: [f64; 3] = std::array::from_fn(|c| moved[c] - disp[3 * v + c]);
        if pick(&x0) {
            out.push((x0, moved));
        }
    }
    out
}

/// The box's top heaving 0.1 and pitching 8° about y through its centre, one period in 20
/// steps: the meshes of steps 5, 10, 15 and 20 are written, the top is where the formula puts it
/// at each, back at its start after the period, and the report has one line a step.
#[test]
fn periodic_heave_and_pitch_of_the_box_top() {
    let dir = tmp("periodic");
    let case = std::fs::read_to_string(examples().join("box_oscillate.toml")).unwrap();
    let report = dir.join("r.jsonl");
    ok(&deform("box.msh", &dir, &case, &["--every", "5", "--report", report.to_str().unwrap()]));
    let steps: Vec<String> = std::fs::read_to_string(&report).unwrap().lines().map(String::from).collect();
    assert_eq!(steps.len(), 20);
    assert!(steps[19].starts_with("{\"step\":20,"), "{}", steps[19]);
    for k in [5, 10, 15, 20] {
        let path = dir.join(format!("out_{k:04}.vtu"));
        let s = (std::f64::consts::TAU * k as f64 / 20.0).sin();
        let (c, sn) = ((8.0 * s).to_radians().cos(), (8.0 * s).to_radians().sin());
        let top = points(&path, |x| (x[2] - 1.0).abs() < 1e-12);
        assert_eq!(top.len(), 12);
        for (x, y) in top {
            let (rx, rz) = (x[0] - 0.5, x[2] - 1.0);
            let want = [0.5 + c * rx + sn * rz, x[1], 1.0 - sn * rx + c * rz + 0.1 * s];
            assert!((0..3).all(|i| (y[i] - want[i]).abs() < 1e-12), "step {k}: {x:?} -> {y:?}, not {want:?}");
        }
    }
    assert!(!dir.join("out_0004.vtu").exists());
    let last = points(&dir.join("out.vtu"), |x| (x[2] - 1.0).abs() < 1e-12);
    assert!(last.iter().all(|(x, y)| (0..3).all(|i| (x[i] - y[i]).abs() < 1e-12)));
}

/// The cylinder of the channel moved by a table of totals (a translation and a turn about its
/// centre per step): after the last step it is where the last row puts it. The number of steps
/// is the table's.
#[test]
fn table_of_rigid_totals() {
    let dir = tmp("table");
    let case = "[[patch]]\npatch = \"cylinder\"\nkind = \"clamped\"\n\n[[motion]]\npatch = \"cylinder\"\n\
                translations = [[0.1, 0.0], [0.2, 0.05], [0.3, 0.0]]\nrotations_deg = [5.0, 10.0, 20.0]\n\
                center = [2.0, 0.0]\n";
    let report = dir.join("r.jsonl");
    ok(&deform("channel.msh", &dir, case, &["--report", report.to_str().unwrap()]));
    assert_eq!(std::fs::read_to_string(&report).unwrap().lines().count(), 3);
    let (c, s) = (20f64.to_radians().cos(), 20f64.to_radians().sin());
    let cylinder = points(&dir.join("out.vtu"), |x| ((x[0] - 2.0).hypot(x[1]) - 0.5).abs() < 1e-9);
    assert_eq!(cylinder.len(), 16);
    for (x, y) in cylinder {
        let (rx, ry) = (x[0] - 2.0, x[1]);
        let want = [2.0 + c * rx - s * ry + 0.3, s * rx + c * ry];
        assert!((0..2).all(|i| (y[i] - want[i]).abs() < 1e-12), "{x:?} -> {y:?}, not {want:?}");
    }
}

/// A displacement file per step, each the total at the end of its step; and one file scaled by
/// a periodic factor.
#[test]
fn displacement_files_per_step_and_periodic_file() {
    let dir = tmp("files");
    for (k, dx) in [(1, 0.1), (2, -0.05)] {
        let rows: String = (80..96).map(|v| format!("{v},{dx},0.02\n")).collect();
        std::fs::write(dir.join(format!("d{k}.csv")), format!("vertex,dx,dy\n{rows}")).unwrap();
    }
    let case = "[[patch]]\npatch = 2\nkind = \"clamped\"\n\n[[motion]]\npatch = 2\nfiles = [\"d1.csv\", \"d2.csv\"]\n";
    ok(&deform("channel.msh", &dir, case, &["--every", "1"]));
    for (k, dx) in [(1, 0.1), (2, -0.05)] {
        let cylinder = points(&dir.join(format!("out_{k:04}.vtu")), |x| ((x[0] - 2.0).hypot(x[1]) - 0.5).abs() < 1e-9);
        assert_eq!(cylinder.len(), 16);
        assert!(cylinder.iter().all(|(x, y)| (y[0] - x[0] - dx).abs() < 1e-12 && (y[1] - x[1] - 0.02).abs() < 1e-12));
    }
    std::fs::remove_file(dir.join("out_0001.vtu")).unwrap();
    // Three steps of a period of 4 from phase 90°: factors cos(π/2·k) − 1 = −1, −2, −1.
    let case = "steps = 3\n[[patch]]\npatch = 2\nkind = \"clamped\"\n\n[[motion]]\npatch = 2\nfile = \"d1.csv\"\n\
                period = 4\nphase_deg = 90\n";
    ok(&deform("channel.msh", &dir, case, &["--every", "2"]));
    let at2 = points(&dir.join("out_0002.vtu"), |x| ((x[0] - 2.0).hypot(x[1]) - 0.5).abs() < 1e-9);
    assert!(at2.iter().all(|(x, y)| (y[0] - x[0] + 0.2).abs() < 1e-12 && (y[1] - x[1] + 0.04).abs() < 1e-12));
    assert!(!dir.join("out_0001.vtu").exists() && dir.join("out_0003.vtu").exists());
}

#[test]
fn ill_formed_series_are_errors_naming_the_key() {
    let dir = tmp("errors");
    let head = "[[patch]]\npatch = 2\nkind = \"clamped\"\n\n[[motion]]\npatch = 2\n";
    for (motion, top, needle) in [
        ("translations = [[0.1, 0.0], [0.2, 0.0]]\n", "steps = 3\n", "steps = 3, but the tables"),
        ("translations = [[0.1, 0.0]]\nrotations_deg = [1.0, 2.0]\n", "", "`rotations_deg` has 2 rows"),
        ("translations = [[0.1, 0.0]]\nperiod = 4\n", "", "`period` is for a rigid motion or a `file`"),
        ("translation = [0.1, 0.0]\nphase_deg = 4\n", "", "`phase_deg` without `period`"),
        ("translation = [0.1, 0.0]\nperiod = 4\n", "", "needs `steps = N`"),
        ("translation = [0.1, 0.0]\nperiod = 0\n", "steps = 4\n", "`period` (steps per period) must be a positive"),
        ("translation = [0.1, 0.0]\nperiod = 4\n", "steps = \"auto\"\n", "a table or `period` needs steps = N"),
        ("translations = [[0.1, 0.0, 0.0]]\n", "", "`translations[0]` has 3 components"),
        ("translation = [0.1, 0.0]\ntranslations = [[0.1, 0.0]]\n", "", "not several"),
        ("rotations_deg = [1.0]\naxis = [0.0, 0.0, 1.0]\n", "", "`axis` is for 3D meshes"),
    ] {
        let o = deform("channel.msh", &dir, &format!("{top}{head}{motion}"), &[]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{motion}: {err}");
        assert!(err.contains(needle), "{motion}: expected `{needle}` in: {err}");
        assert!(!dir.join("out.vtu").exists());
    }
}
