//! `meshmove deform` on small wall-layered meshes (a NACA 0012 airfoil of first height 1e-5 in
//! 2D, a prolate spheroid of first height 1e-4 with wedge layers and tetrahedra in 3D), written
//! as .msh files with a case file: the body CLAMPED and pitched by 10° about its pitch centre,
//! the far field FIXED. Every method ends with a clear status, never a panic; the biharmonic's
//! result is valid and its first wall layer keeps its volume within 1 %.

use meshmove_cases::viscous::{self, Layers, ViscousMesh, PITCH_DEG, WALL};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn meshmove(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_meshmove")).args(args).output().expect("runs meshmove")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("meshmove-cli-viscous-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// The case file: `method`, the wall clamped and pitched nose up, the far field fixed (the
/// default kind).
fn case(v: &ViscousMesh, method: &str) -> String {
    let c = v.pitch_center;
    let (center, axis) = if v.mesh.dim() == 2 {
        (format!("[{}, {}]", c[0], c[1]), String::new())
    } else {
        (format!("[{}, {}, {}]", c[0], c[1], c[2]), "axis = [0.0, 0.0, 1.0]\n".to_string())
    };
    format!(
        "method = \"{method}\"\n[[patch]]\npatch = {WALL}\nkind = \"clamped\"\n\
         [[motion]]\npatch = {WALL}\nrotation_deg = {}\n{axis}center = {center}\n",
        -PITCH_DEG
    )
}

/// Runs every method on `v` through `meshmove deform`; returns the biharmonic's first-layer
/// volume ratio range.
fn deform_every_method(v: &ViscousMesh, name: &str) -> (f64, f64) {
    let dir = tmp(name);
    let mesh = dir.join("mesh.msh");
    meshmove::io::write_msh22(&v.mesh, &mesh).unwrap();
    // The file holds the generator's vertices in the generator's order.
    let read = meshmove::io::read_msh(&mesh).unwrap().mesh;
    assert_eq!(read.coords(), v.mesh.coords());
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let mut first = None;
    for method in ["biharmonic", "laplacian", "spring"] {
        let cfg = dir.join(format!("{method}.toml"));
        std::fs::write(&cfg, case(v, method)).unwrap();
        let out = dir.join(format!("{method}.vtu"));
        let o = meshmove(&["deform", &path(&mesh), "--config", &path(&cfg), "-o", &path(&out)]);
        let code = o.status.code();
        eprintln!("{name} {method}: exit {code:?}\n{}", text(&o));
        assert!(!text(&o).contains("panicked"), "{name} {method}: {}", text(&o));
        // 0: valid; 3: inverted cells (the Laplacian and the spring may fold the thin layers);
        // 4: a step failed, with its message.
        assert!(matches!(code, Some(0) | Some(3) | Some(4)), "{name} {method}: {code:?} {}", text(&o));
        if method == "biharmonic" {
            assert_eq!(code, Some(0), "{name}: {}", text(&o));
            let moved = meshmove::io::read_vtu(&out).unwrap().to_mesh().unwrap();
            let q = meshmove::mesh::quality(&v.mesh, moved.coords());
            assert_eq!(q.inverted, 0);
            assert!(q.min_area_ratio > 0.0);
            first = viscous::layer_volume_ratios(v, moved.coords(), 1);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    first.expect("the first layer's cells")
}

#[test]
fn airfoil_of_first_height_1e5_pitched_by_every_method() {
    let v = viscous::airfoil_2d(&viscous::AirfoilParams::new(16)).unwrap();
    let (lo, hi) = deform_every_method(&v, "airfoil");
    eprintln!("airfoil first layer volume ratio {lo}–{hi}");
    assert!(lo > 0.99 && hi < 1.01, "{lo} {hi}");
}

#[test]
fn spheroid_of_first_height_1e4_pitched_by_every_method() {
    let p = viscous::SpheroidParams::new(2).with_layers(Layers::new(1e-4, 10, 1.2));
    let v = viscous::spheroid_3d(&p).unwrap();
    eprintln!("spheroid: {:?}", viscous::mesh_quality(&v));
    let (lo, hi) = deform_every_method(&v, "spheroid");
    eprintln!("spheroid first layer volume ratio {lo}–{hi}");
    assert!(lo > 0.99 && hi < 1.01, "{lo} {hi}");
}
