//! `mpirun -np N meshmove deform` (the `mpi` feature): on 1 to 4 ranks the written mesh equals
//! the serial command's to 1e-10 of the motion (both solved to a relative residual of 1e-12) —
//! a 2D channel whose cylinder moves rigidly in two steps (biharmonic and Laplacian), the same
//! channel moved by a displacement file (spring), and a 3D box whose top heaves and pitches
//! through 20 steps with the step meshes written (`--every`); a case the distributed solver
//! cannot do (a SLIP wall) fails on every rank with one message. Skipped, with a message, where
//! `mpirun` is missing. Run by `cargo test --release -p meshmove-cli --features mpi --test
//! deform_mpi`.

use meshmove::io::read_vtu;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/examples")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("meshmove-mpi-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Whether `mpirun` runs here; prints why the test is skipped when not.
fn have_mpirun() -> bool {
    let ok = Command::new("mpirun").arg("--version").output().is_ok_and(|o| o.status.success());
    if !ok {
        eprintln!("skipped: mpirun is not on PATH (install openmpi-bin)");
    }
    ok
}

/// `meshmove deform MESH --config DIR/case.toml -o DIR/OUT` serially (`ranks` 0) or under
/// `mpirun -np ranks` (with a time limit, so a rank left waiting fails the test).
fn deform(ranks: usize, mesh: &str, dir: &Path, out: &str, extra: &[&str]) -> Output {
    let exe = env!("CARGO_BIN_EXE_meshmove");
    let mut cmd = if ranks == 0 {
        Command::new(exe)
    } else {
        let mut c = Command::new("timeout");
        c.args(["300", "mpirun", "--oversubscribe", "-np", &ranks.to_string(), exe]);
        c.env("OMPI_ALLOW_RUN_AS_ROOT", "1").env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
        c
    };
    cmd.arg("deform")
        .arg(examples().join(mesh))
        .arg("--config")
        .arg(dir.join("case.toml"))
        .arg("-o")
        .arg(dir.join(out))
        .args(extra)
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .expect("runs meshmove")
}

fn ok(o: &Output) {
    let text = format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "{text}");
}

/// The moved points of a written mesh.
fn moved(path: &Path) -> Vec<f64> {
    read_vtu(path).unwrap().mesh.coords
}

/// The largest difference between two meshes' points over the largest displacement of `a`
/// from the original mesh `original`.
fn relative_difference(a: &[f64], b: &[f64], original: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = a.iter().zip(original).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(scale > 0.0);
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

/// The case `case` on `mesh` serially and on 1 to 4 ranks: the same mesh (and the same files
/// of `also`, written beside the output) to 1e-10 of the motion, and the same summary of cells.
fn agrees_on_1_to_4_ranks(name: &str, mesh: &str, case: &str, extra: &[&str], also: &[&str]) {
    if !have_mpirun() {
        return;
    }
    let dir = tmp(name);
    std::fs::write(dir.join("case.toml"), case).unwrap();
    let serial = deform(0, mesh, &dir, "serial.vtu", extra);
    ok(&serial);
    let reference = moved(&dir.join("serial.vtu"));
    let original = original_points(&dir.join("serial.vtu"));
    for ranks in 1..=4 {
        let out = format!("ranks{ranks}.vtu");
        let o = deform(ranks, mesh, &dir, &out, extra);
        ok(&o);
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(stdout.contains(&format!("on {ranks} ranks (cells split by METIS)")), "{stdout}");
        let inverted = |s: &str| s.lines().find(|l| l.starts_with("inverted cells")).map(String::from);
        assert_eq!(inverted(&stdout), inverted(&String::from_utf8_lossy(&serial.stdout)));
        let d = relative_difference(&moved(&dir.join(&out)), &reference, &original);
        assert!(d < 1e-10, "{name} on {ranks} ranks: differs from serial by {d:e} of the motion");
        for f in also {
            let (a, b) = (dir.join(format!("serial_{f}.vtu")), dir.join(format!("ranks{ranks}_{f}.vtu")));
            let d = relative_difference(&moved(&b), &moved(&a), &original);
            assert!(d < 1e-10, "{name} on {ranks} ranks, {f}: differs from serial by {d:e}");
        }
    }
}

/// The original points of a mesh `deform` wrote (its points less its displacement).
fn original_points(path: &Path) -> Vec<f64> {
    let d = read_vtu(path).unwrap();
    let dim = d.mesh.dim;
    let disp = &d.point_data.iter().find(|p| p.0 == "displacement").unwrap().1;
    d.mesh.coords.iter().enumerate().map(|(i, x)| x - disp[3 * (i / dim) + i % dim]).collect()
}

/// The channel example with its cylinder moved rigidly 0.5 D in two steps.
fn channel_case(method: &str) -> String {
    let text = std::fs::read_to_string(examples().join("channel.toml")).unwrap();
    text.replace("method = \"biharmonic\"", &format!("method = \"{method}\""))
        .replace("tolerance = 1e-8", "tolerance = 1e-12")
}

#[test]
fn channel_biharmonic_equals_serial() {
    agrees_on_1_to_4_ranks("channel-biharmonic", "channel.msh", &channel_case("biharmonic"), &[], &[]);
}

#[test]
fn channel_laplacian_equals_serial() {
    agrees_on_1_to_4_ranks("channel-laplacian", "channel.msh", &channel_case("laplacian"), &[], &[]);
}

#[test]
fn channel_spring_by_displacement_file_equals_serial() {
    let case = format!(
        "method = \"spring\"\ntolerance = 1e-12\n[[patch]]\npatch = \"cylinder\"\nkind = \"clamped\"\n\
         [[motion]]\nfile = \"{}\"\n",
        examples().join("channel_disp.csv").display()
    );
    agrees_on_1_to_4_ranks("channel-file", "channel.msh", &case, &[], &[]);
}

#[test]
fn box_heaving_and_pitching_through_20_steps_equals_serial() {
    let case = std::fs::read_to_string(examples().join("box_oscillate.toml")).unwrap();
    let case = format!("tolerance = 1e-12\n{case}");
    agrees_on_1_to_4_ranks("box-steps", "box.msh", &case, &["--every", "10"], &["0010", "0020"]);
}

#[test]
fn a_slip_wall_fails_on_every_rank_with_one_message() {
    if !have_mpirun() {
        return;
    }
    let dir = tmp("slip");
    let case = channel_case("biharmonic").replace("kind = \"fixed\"", "kind = \"slip\"");
    std::fs::write(dir.join("case.toml"), case).unwrap();
    let o = deform(3, "channel.msh", &dir, "out.vtu", &[]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.matches("meshmove: error:").count(), 1, "{stderr}");
    assert!(stderr.contains("SLIP walls (patch `wall` (1))") && stderr.contains("without mpirun"), "{stderr}");
    assert!(!dir.join("out.vtu").exists());
}
