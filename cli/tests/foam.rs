//! `meshmove deform` on OpenFOAM polyMesh directories: the shipped snappyHexMesh mesh (hexahedra
//! and polyhedra around a ball, ASCII and binary) moved, written, read back; the result equal to
//! the same motion through the C ABI's face-based mesh; `checkMesh` on the moved mesh when
//! OpenFOAM is on PATH; the bench's hexahedral box as a polyMesh moved bitwise as the same box
//! from its .msh.

use meshmove::capi::*;
use meshmove::io::{read_polymesh, read_vtu};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::ptr::null_mut;

#[path = "../../tests/common/faces_c.rs"]
mod faces_c;
use faces_c::create_from_faces;

fn meshmove(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_meshmove")).args(args).output().expect("runs meshmove")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("meshmove-foam-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

fn data(dir: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/foam").join(dir)
}

/// The ball (patch `ball`, id 2) translated, the outer box (`outer`, id 1) fixed, in one step.
const BALL: [f64; 3] = [0.08, 0.05, -0.03];

fn case_file(dir: &Path) -> PathBuf {
    let toml = format!(
        "method = \"biharmonic\"\ntolerance = 1e-12\nthreads = 1\nsteps = 1\n\n\
         [[patch]]\npatch = \"outer\"\nkind = \"fixed\"\n\n\
         [[patch]]\npatch = \"ball\"\nkind = \"clamped\"\n\n\
         [[motion]]\npatch = \"ball\"\ntranslation = [{:?}, {:?}, {:?}]\n",
        BALL[0], BALL[1], BALL[2]
    );
    let path = dir.join("case.toml");
    std::fs::write(&path, toml).unwrap();
    path
}

/// The C ABI's last error message.
fn error() -> String {
    let mut buf = vec![0 as std::ffi::c_char; 512];
    let mut needed = 0usize;
    let _ = unsafe { meshmove_last_error_message(buf.as_mut_ptr(), buf.len(), &mut needed) };
    unsafe { std::ffi::CStr::from_ptr(buf.as_ptr()) }.to_string_lossy().into_owned()
}

/// The same motion through the C ABI: the mesh from the polyMesh's faces
/// (`meshmove_mesh_create_from_faces`), the ball moved rigidly by `meshmove_solver_move`.
fn moved_through_the_c_abi(polymesh: &Path) -> Vec<f64> {
    let f = read_polymesh(polymesh).unwrap().faces;
    let nv = f.coords.len() / 3;
    let (s, mesh) = create_from_faces(&f, 0, 243);
    assert_eq!(s, meshmove_status::Ok, "{}", error());
    unsafe {
        let mut bcs = null_mut();
        assert_eq!(meshmove_bcs_create(&mut bcs), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_set_kinds(bcs, 1, meshmove_kind::Fixed as i32), meshmove_status::Ok);
        assert_eq!(meshmove_bcs_set_kinds(bcs, 2, meshmove_kind::Clamped as i32), meshmove_status::Ok);
        let mut opts = null_mut();
        assert_eq!(meshmove_options_create(&mut opts), meshmove_status::Ok);
        assert_eq!(meshmove_options_set_method(opts, meshmove_method::Biharmonic as i32), meshmove_status::Ok);
        assert_eq!(meshmove_options_set_tol(opts, 1e-12), meshmove_status::Ok);
        assert_eq!(meshmove_options_set_threads(opts, 1), meshmove_status::Ok);
        let mut solver = null_mut();
        assert_eq!(meshmove_solver_create(mesh, bcs, opts, &mut solver), meshmove_status::Ok);
        let (zero, center) = ([0.0; 3], [0.0; 3]);
        let s = meshmove_solver_set_rigid_motion(solver, 2, BALL.as_ptr(), zero.as_ptr(), center.as_ptr());
        assert_eq!(s, meshmove_status::Ok);
        let disp = vec![0.0; 3 * nv];
        let mut coords = f.coords.clone();
        let s =
            meshmove_solver_move(solver, disp.len() as i32, disp.as_ptr(), coords.as_mut_ptr(), null_mut(), null_mut());
        assert_eq!(s, meshmove_status::Ok);
        for r in [
            meshmove_solver_free(solver),
            meshmove_options_free(opts),
            meshmove_bcs_free(bcs),
            meshmove_mesh_free(mesh),
        ] {
            assert_eq!(r, meshmove_status::Ok);
        }
        coords
    }
}

/// `checkMesh` of OpenFOAM on the case holding `polymesh`, when it is on PATH: it must say the
/// mesh is OK. Without OpenFOAM the check is skipped with a message.
fn check_mesh(case: &Path) {
    let run = Command::new("checkMesh")
        .arg("-case")
        .arg(case)
        .env("WM_PROJECT_DIR", std::env::var("WM_PROJECT_DIR").unwrap_or("/usr/share/openfoam".into()))
        .output();
    match run {
        Err(_) => eprintln!("checkMesh is not on PATH: the moved mesh is not checked by OpenFOAM"),
        Ok(o) => {
            let out = text(&o);
            assert!(o.status.success() && out.contains("Mesh OK."), "checkMesh:\n{out}");
        }
    }
}

/// A minimal OpenFOAM case in `dir/case` (checkMesh reads system/controlDict, fvSchemes and
/// fvSolution).
fn case_around(dir: &Path) -> PathBuf {
    let case = dir.join("case");
    std::fs::create_dir_all(case.join("system")).unwrap();
    let head = |object: &str| format!("FoamFile {{ version 2.0; format ascii; class dictionary; object {object}; }}\n");
    let files = [
        (
            "controlDict",
            "application checkMesh; startFrom startTime; startTime 0; stopAt endTime; endTime 1; deltaT 1;\n\
             writeControl timeStep; writeInterval 1;\n",
        ),
        (
            "fvSchemes",
            "ddtSchemes { default Euler; } gradSchemes { default Gauss linear; } divSchemes { default none; }\n\
             laplacianSchemes { default Gauss linear corrected; } interpolationSchemes { default linear; }\n\
             snGradSchemes { default corrected; }\n",
        ),
        ("fvSolution", ""),
    ];
    for (name, body) in files {
        std::fs::write(case.join("system").join(name), head(name) + body).unwrap();
    }
    case
}

#[test]
fn a_snappy_polymesh_moves_writes_and_reads_back_as_the_c_abi_moves_it() {
    for dir in ["sphere_ascii", "sphere_binary"] {
        let d = tmp(dir);
        let config = case_file(&d);
        let case = case_around(&d);
        let out = case.join("constant/polyMesh");
        let vtu = d.join("moved.vtu");
        let src = data(dir);
        let o = meshmove(&[
            "deform",
            src.to_str().unwrap(),
            "--config",
            config.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--vtu",
            vtu.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o));
        assert!(text(&o).contains("(444 vertices, 243 cells)"), "{}", text(&o));
        // Read back: faces, owners, patches as before; the points those of the .vtu.
        let (before, after) = (read_polymesh(&src).unwrap(), read_polymesh(&case).unwrap());
        assert_eq!(after.format, before.format);
        assert_eq!(after.patch_names, before.patch_names);
        assert_eq!(
            (&after.faces.face_vertices, &after.faces.owner, &after.faces.patch),
            (&before.faces.face_vertices, &before.faces.owner, &before.faces.patch)
        );
        for name in ["faces", "owner", "neighbour", "boundary"] {
            assert_eq!(std::fs::read(src.join(name)).unwrap(), std::fs::read(out.join(name)).unwrap(), "{name}");
        }
        let v = read_vtu(&vtu).unwrap();
        assert_eq!(v.mesh.coords, after.faces.coords);
        // The ball moved by BALL, the outer box kept.
        let moved = &after.faces.coords;
        for (f, &p) in after.faces.patch.iter().enumerate() {
            let (a, b) = (after.faces.face_offsets[f] as usize, after.faces.face_offsets[f + 1] as usize);
            for &vx in &after.faces.face_vertices[a..b] {
                for k in 0..3 {
                    let (x0, x1) = (before.faces.coords[3 * vx as usize + k], moved[3 * vx as usize + k]);
                    let want = if p == 2 {
                        x0 + BALL[k]
                    } else if p == 1 {
                        x0
                    } else {
                        x1
                    };
                    assert!((x1 - want).abs() < 1e-14, "face {f} vertex {vx}: {x1} vs {want}");
                }
            }
        }
        let c = moved_through_the_c_abi(&src);
        let diff = c.iter().zip(moved).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(diff <= 1e-12, "deform and the C ABI differ by {diff:e}");
        let interior = moved.iter().zip(&before.faces.coords).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(interior > 0.01, "the mesh did not move ({interior})");
        check_mesh(&case);
        std::fs::remove_dir_all(&d).unwrap();
    }
}

#[test]
fn a_case_directory_moves_in_place() {
    let d = tmp("inplace");
    let config = case_file(&d);
    let case = case_around(&d);
    let out = case.join("constant/polyMesh");
    std::fs::create_dir_all(&out).unwrap();
    for f in ["points", "faces", "owner", "neighbour", "boundary"] {
        std::fs::copy(data("sphere_binary").join(f), out.join(f)).unwrap();
    }
    let o = meshmove(&[
        "deform",
        case.to_str().unwrap(),
        "--config",
        config.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let after = read_polymesh(&case).unwrap();
    let c = moved_through_the_c_abi(&data("sphere_binary"));
    let diff = c.iter().zip(&after.faces.coords).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(diff <= 1e-12, "{diff:e}");
    let e = meshmove(&["deform", d.to_str().unwrap(), "--config", config.to_str().unwrap(), "-o", "x.vtu"]);
    assert_eq!(e.status.code(), Some(1));
    assert!(text(&e).contains("neither a polyMesh directory"), "{}", text(&e));
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn malformed_polymesh_is_a_clear_error_and_nothing_is_written() {
    let d = tmp("bad");
    let config = case_file(&d);
    let mesh = d.join("polyMesh");
    std::fs::create_dir_all(&mesh).unwrap();
    for f in ["points", "faces", "owner", "neighbour", "boundary"] {
        std::fs::copy(data("sphere_ascii").join(f), mesh.join(f)).unwrap();
    }
    let owner = std::fs::read_to_string(mesh.join("owner")).unwrap().replacen("904\n(\n0\n", "904\n(\n243\n", 1);
    std::fs::write(mesh.join("owner"), owner).unwrap();
    let out = d.join("out");
    let o = meshmove(&[
        "deform",
        mesh.to_str().unwrap(),
        "--config",
        config.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("owner: face 0: cell 243 outside the 243 cells (nCells)"), "{}", text(&o));
    assert!(!out.exists());
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn the_hexahedral_box_as_a_polymesh_moves_bitwise_as_from_its_msh() {
    let d = tmp("box");
    let o = meshmove(&["bench", "--peer-case", "8", "--out", d.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    // The same case with the polyMesh's patch names (bottom, top, x0, x1, y0, y1).
    let mut toml = String::from("method = \"biharmonic\"\ntolerance = 1e-8\nthreads = 1\n");
    for (p, kind) in [
        ("bottom", "\"fixed\""),
        ("top", "\"clamped\""),
        ("x0", "[\"fixed\", \"free\", \"free\"]"),
        ("x1", "[\"fixed\", \"free\", \"free\"]"),
        ("y0", "[\"free\", \"fixed\", \"free\"]"),
        ("y1", "[\"free\", \"fixed\", \"free\"]"),
    ] {
        toml += &format!("\n[[patch]]\npatch = \"{p}\"\nkind = {kind}\n");
    }
    toml += "\n[[motion]]\nfile = \"top.csv\"\npatch = \"top\"\n";
    std::fs::write(d.join("foam.toml"), toml).unwrap();
    let s = |p: PathBuf| p.to_str().unwrap().to_string();
    let run = |mesh: PathBuf, config: &str, out: PathBuf| {
        let o = meshmove(&["deform", &s(mesh), "--config", &s(d.join(config)), "-o", &s(out)]);
        assert!(o.status.success(), "{}", text(&o));
        assert!(text(&o).contains("(729 vertices, 512 cells)"), "{}", text(&o));
    };
    run(d.join("box.msh"), "case.toml", d.join("box.vtu"));
    run(d.join("foam"), "foam.toml", d.join("moved"));
    let cells = read_vtu(&d.join("box.vtu")).unwrap().mesh.coords;
    let faces = read_polymesh(&d.join("moved")).unwrap().faces.coords;
    assert_eq!(cells.len(), faces.len());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
    assert_eq!(bits(&cells), bits(&faces));
    std::fs::remove_dir_all(&d).unwrap();
}
