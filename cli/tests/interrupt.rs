//! Ctrl-C during `meshmove deform`: the run stops at the next sub-step, writes the last valid
//! mesh beside the requested output and exits with 5. The signal is sent once the first step's
//! line is on stderr (the run is then certainly under way), never after a fixed sleep; the case
//! has so many steps that it cannot end on its own before the signal arrives.

#![cfg(unix)]

use meshmove::io::{read_msh, read_vtu};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("meshmove-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn ctrl_c_writes_the_last_valid_mesh_and_exits_5() {
    let d = tmp("ctrl-c");
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/examples/channel.msh");
    let (cfg, out, report) = (d.join("c.toml"), d.join("o.vtu"), d.join("r.jsonl"));
    // The cylinder moved 0.2 in x in 100000 steps: hours of work, stopped after the first.
    let case = "steps = 100000\n[[patch]]\npatch = \"cylinder\"\nkind = \"clamped\"\n\
                [[motion]]\npatch = \"cylinder\"\ntranslation = [0.2, 0.0]\n";
    std::fs::write(&cfg, case).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_meshmove"))
        .args(["deform", mesh.to_str().unwrap(), "--config", cfg.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .args(["--report", report.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs meshmove");
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let mut stderr = String::new();
    // Read until the first step's line (stderr is not a terminal: one line per sub-step).
    for line in lines.by_ref() {
        let line = line.unwrap();
        stderr += &line;
        stderr.push('\n');
        if line.starts_with("step 1.") {
            break;
        }
    }
    assert!(stderr.contains("step 1."), "no step line before the end: {stderr}");
    let kill = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(kill.success());
    for line in lines {
        stderr += &line.unwrap();
        stderr.push('\n');
    }
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(5), "{stderr}");
    let partial = d.join("o.last-valid.vtu");
    assert!(partial.exists() && !out.exists(), "{stderr}");
    assert!(stderr.contains("o.last-valid.vtu"), "{stderr}");

    // The last valid mesh is the last accepted sub-step's: the cylinder moved by that fraction
    // of the translation.
    let reports = std::fs::read_to_string(&report).unwrap();
    let fraction: f64 = reports
        .lines()
        .rev()
        .find(|l| l.contains("\"accepted\":true"))
        .map(|l| l.split("\"fraction\":").nth(1).unwrap().split(',').next().unwrap().parse().unwrap())
        .expect("at least one accepted step");
    assert!(fraction > 0.0 && fraction < 0.5, "{fraction}");
    let original = read_msh(&mesh).unwrap();
    let cylinder = original.physical_names.iter().find(|(_, _, n)| n == "cylinder").unwrap().1;
    let written = read_vtu(&partial).unwrap();
    let (_, disp, comps) = written.point_data.iter().find(|(n, _, _)| n == "displacement").expect("displacement");
    let on_cylinder = original.mesh.patch_vertices(cylinder);
    assert!(!on_cylinder.is_empty());
    for v in on_cylinder {
        let dx = disp[v as usize * comps];
        assert!((dx - 0.2 * fraction).abs() < 1e-12, "vertex {v}: {dx} for fraction {fraction}");
    }
    let _ = std::fs::remove_dir_all(&d);
}
