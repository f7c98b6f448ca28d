//! The `meshmove` binary: demo, deform with the shipped example, bad input, compare.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn meshmove(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_meshmove")).args(args).output().expect("runs meshmove")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("meshmove-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn example(f: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/examples").join(f).to_str().unwrap().to_string()
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

#[test]
fn demo_quick_writes_results_csv_and_pictures() {
    let d = tmp("demo");
    let o = meshmove(&["demo", "--quick", "--out", d.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let csv = std::fs::read_to_string(d.join("results.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "case,method,steps,inverted,negative_volume_cells,min_volume_ratio,min_corner_jacobian_ratio,min_angle_deg,spacing_variation,cycles,seconds,max_y_upper,dim"
    );
    // The header and 25 cases (12 in 2D, 13 in 3D) × 3 methods.
    assert_eq!(lines.len(), 76, "{csv}");
    for l in &lines[1..] {
        assert_eq!(l.split(',').count(), 13, "{l}");
    }
    assert_eq!(lines.iter().filter(|l| l.ends_with(",3")).count(), 39, "{csv}");
    assert!(lines.iter().any(|l| l.starts_with("free_surface_3d_prisms_a0.1,biharmonic,1,0,")));
    assert!(lines.iter().any(|l| l.starts_with("boundary_layer_cylinder_3d,spring,1,0,")));
    // The largest amplitude each method moves in one step: 4 free surfaces × 3 methods.
    let amp = std::fs::read_to_string(d.join("largest_amplitude.csv")).unwrap();
    assert_eq!(amp.lines().next(), Some("case,method,dim,largest_valid_a,first_inverted_a,cycles,seconds"));
    assert_eq!(amp.lines().count(), 13, "{amp}");
    assert!(lines.iter().any(|l| l.starts_with("boundary_layer_cylinder,spring,")));
    assert!(lines.iter().any(|l| l.starts_with("deforming_interface_B,biharmonic,15,")));
    assert!(lines.iter().any(|l| l.starts_with("boundary_layer_cylinder_hybrid,laplacian,")));
    assert!(lines.iter().any(|l| l.starts_with("cylinder_channel_1.5D_slip,biharmonic,1,")));
    assert!(lines.iter().any(|l| l.starts_with("sphere_channel_1.5D_slip,laplacian,1,")));
    for f in [
        "convergence.png",
        "convergence.csv",
        "free_surface_a0.25_laplacian.png",
        "cylinder_channel_biharmonic.vtu",
        "free_surface_3d_tets_a0.1_laplacian.png",
        "boundary_layer_cylinder_3d_biharmonic.vtu",
    ] {
        assert!(d.join(f).is_file(), "{f} missing");
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn deform_the_example_and_compare() {
    let d = tmp("deform");
    let out = d.join("out.vtu");
    let o = meshmove(&[
        "deform",
        &example("channel.msh"),
        "--config",
        &example("channel.toml"),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("inverted cells  0"), "{}", text(&o));
    let data = meshmove::io::read_vtu(&out).unwrap();
    assert_eq!(data.mesh.num_vertices(), 319);
    // The cylinder (centre (2, 0), radius 1/2) moved by 0.5 in x.
    let on_cyl =
        data.mesh.coords.chunks_exact(2).filter(|p| ((p[0] - 2.5).powi(2) + p[1] * p[1]).sqrt() - 0.5 < 1e-9).count();
    assert!(on_cyl >= 16, "{on_cyl} vertices on the moved cylinder");

    // The same motion as a CSV displacement field (cylinder vertices, by id) gives the same mesh
    // up to the rigid-flux source (translation: none), so compare agrees to the solver tolerance.
    let mesh = meshmove::io::read_msh(Path::new(&example("channel.msh"))).unwrap().mesh;
    let mut csv = String::from("vertex,dx,dy\n");
    for v in mesh.patch_vertices(2) {
        csv.push_str(&format!("{v},0.5,0\n"));
    }
    std::fs::write(d.join("disp.csv"), csv).unwrap();
    let cfg = "method = \"biharmonic\"\ntolerance = 1e-12\nsteps = 2\n[[patch]]\npatch = 1\nkind = \"fixed\"\n\
               [[patch]]\npatch = 2\nkind = \"clamped\"\n[[motion]]\npatch = 2\nfile = \"disp.csv\"\n";
    std::fs::write(d.join("csv.toml"), cfg).unwrap();
    let out2 = d.join("out2.vtu");
    let o = meshmove(&[
        "deform",
        &example("channel.msh"),
        "--config",
        d.join("csv.toml").to_str().unwrap(),
        "-o",
        out2.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = meshmove(&["compare", out.to_str().unwrap(), out2.to_str().unwrap(), "--tol", "1e-6"]);
    assert!(o.status.success(), "{}", text(&o));
    // And as the point data `displacement` of the first result (.vtu), on the cylinder only.
    std::fs::write(d.join("vtu.toml"), cfg.replace("disp.csv", "out.vtu")).unwrap();
    let out3 = d.join("out3.vtu");
    let o = meshmove(&[
        "deform",
        &example("channel.msh"),
        "--config",
        d.join("vtu.toml").to_str().unwrap(),
        "-o",
        out3.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = meshmove(&["compare", out2.to_str().unwrap(), out3.to_str().unwrap(), "--tol", "1e-9"]);
    assert!(o.status.success(), "{}", text(&o));
    let o = meshmove(&["compare", out.to_str().unwrap(), out.to_str().unwrap(), "--tol", "0"]);
    assert!(o.status.success(), "{}", text(&o));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn compare_reports_the_difference() {
    let d = tmp("compare");
    let m = meshmove_cases::meshes::structured_rectangle(2, 2, 0.0, 1.0, 0.0, 1.0);
    let a = d.join("a.vtu");
    let b = d.join("b.vtu");
    meshmove::io::write_deformed(&a, &m, &vec![0.0; 2 * m.num_vertices()]).unwrap();
    let mut disp = vec![0.0; 2 * m.num_vertices()];
    disp[2 * 4] = 1e-3;
    meshmove::io::write_deformed(&b, &m, &disp).unwrap();
    let o = meshmove(&["compare", a.to_str().unwrap(), b.to_str().unwrap(), "--tol", "1e-4"]);
    assert!(!o.status.success());
    assert!(text(&o).contains("max coordinate difference 1.0") && text(&o).contains("point 4"), "{}", text(&o));
    let o = meshmove(&["compare", a.to_str().unwrap(), b.to_str().unwrap(), "--tol", "1e-2"]);
    assert!(o.status.success(), "{}", text(&o));
    let o = meshmove(&["compare", a.to_str().unwrap(), d.join("missing.vtu").to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(text(&o).contains("missing.vtu"), "{}", text(&o));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_config_fails_with_a_message_naming_the_problem() {
    let d = tmp("bad");
    let mesh = example("channel.msh");
    let cases = [
        ("[[patch]]\npatch = \"wal\"\nkind = \"fixed\"\n", "no patch named `wal`"),
        ("[[patch]]\npatch = 7\nkind = \"fixed\"\n", "patch 7 is not in the mesh"),
        ("[[patch]]\npatch = 1\nkind = \"glued\"\n", "kind `glued`"),
        ("method = \"elastic\"\n", "method `elastic`"),
        ("stepz = 3\n", "unknown field"),
        ("steps = 0\n", "steps must be 1 to"),
        ("steps = \"often\"\n", "not a count or \"auto\""),
        ("[[patch]]\npatch = 1\nkind = \"fixed\"\n[[patch]]\npatch = \"wall\"\nkind = \"free\"\n", "already given a kind by [[patch]] 1"),
        (
            "[[patch]]\npatch = \"cylinder\"\nkind = [\"free\", \"fixed\"]\n[[motion]]\npatch = \"cylinder\"\ntranslation = [0.1, 0.0]\n",
            "moves its vertices in x, which is FREE",
        ),
        (
            "[[motion]]\npatch = \"cylinder\"\ntranslation = [0.1, 0.0]\n[[motion]]\npatch = \"cylinder\"\nrotation_deg = 5.0\n",
            "already moved by [[motion]] 1",
        ),
        ("[[motion]]\npatch = 2\nfile = \"nope.csv\"\n", "nope.csv"),
        ("[[patch]]\npatch = 2\nkind = \"clamped\"\nshape = \"circle\"\ncenter = [2, 0]\nradius = 0.5\n", "for a patch of kind \"slip\""),
        ("[[patch]]\npatch = 2\nkind = \"slip\"\nshape = \"torus\"\n", "shape `torus` is not one of"),
        ("[[patch]]\npatch = 2\nkind = \"slip\"\nshape = \"circle\"\ncenter = [2, 0]\n", "`radius` is required by shape `circle`"),
        ("[[patch]]\npatch = 2\nkind = \"slip\"\nshape = \"circle\"\ncenter = [2, 0]\nradius = -1\n", "`radius` must be a positive"),
        ("[[patch]]\npatch = 2\nkind = \"slip\"\nshape = \"line\"\npoint = [0, 0]\nnormal = [0, 0]\n", "`normal` is zero"),
        ("[[patch]]\npatch = 2\nkind = \"slip\"\nshape = \"line\"\npoint = [0, 0]\nnormal = [0, 1]\nradius = 1\n", "`radius` is not a key of shape `line`"),
        ("[[patch]]\npatch = 2\nkind = \"slip\"\nradius = 1\n", "`radius` belongs to a `shape`"),
        ("[[patch]]\npatch = 2\nkind = \"slip\"\nshape = \"cylinder\"\n", "shape `cylinder` is for 3D meshes"),
        ("method = \n", "config"),
    ];
    for (i, (cfg, want)) in cases.iter().enumerate() {
        let p = d.join(format!("bad{i}.toml"));
        std::fs::write(&p, cfg).unwrap();
        let o = meshmove(&["deform", &mesh, "--config", p.to_str().unwrap(), "-o", d.join("o.vtu").to_str().unwrap()]);
        assert!(!o.status.success(), "{cfg}");
        assert!(text(&o).contains(want), "{cfg}: {}", text(&o));
    }
    // A bad mesh file.
    let bad = d.join("bad.msh");
    std::fs::write(&bad, "$MeshFormat\n9.9 0 8\n$EndMeshFormat\n").unwrap();
    let o = meshmove(&["deform", bad.to_str().unwrap(), "--config", &example("channel.toml"), "-o", "x.vtu"]);
    assert!(!o.status.success());
    assert!(text(&o).contains("bad.msh"), "{}", text(&o));
    // An inverted result: the cylinder pushed through the wall with the Laplacian.
    let p = d.join("tangle.toml");
    std::fs::write(
        &p,
        "method = \"laplacian\"\n[[patch]]\npatch = \"wall\"\nkind = \"fixed\"\n[[patch]]\npatch = \"cylinder\"\nkind = \"clamped\"\n\
         [[motion]]\npatch = \"cylinder\"\ntranslation = [0.0, 0.45]\n",
    )
    .unwrap();
    let o = meshmove(&["deform", &mesh, "--config", p.to_str().unwrap(), "-o", d.join("t.vtu").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3), "{}", text(&o));
    assert!(text(&o).contains("inverted cells"), "{}", text(&o));
    let _ = std::fs::remove_dir_all(&d);
}

/// A step that cannot reach its tolerance: exit 4, the message, the last valid mesh beside the
/// requested output, and the requested output not written. Every sub-step is in the report.
#[test]
fn failed_step_writes_the_last_valid_mesh_and_exits_4() {
    let d = tmp("fail");
    let mesh = example("channel.msh");
    let (cfg, out, report) = (d.join("c.toml"), d.join("o.vtu"), d.join("r.jsonl"));
    // The cylinder moved 0.2 in x in two steps, with `extra` keys first.
    let deform = |extra: &str| {
        let case = "steps = 2\n[[patch]]\npatch = \"cylinder\"\nkind = \"clamped\"\n\
                    [[motion]]\npatch = \"cylinder\"\ntranslation = [0.2, 0.0]\n";
        std::fs::write(&cfg, format!("{extra}{case}")).unwrap();
        let path = |p: &PathBuf| p.to_str().unwrap().to_string();
        meshmove(&["deform", &mesh, "--config", &path(&cfg), "-o", &path(&out), "--report", &path(&report)])
    };
    let o = deform("tolerance = 1e-30\n");
    assert_eq!(o.status.code(), Some(4), "{}", text(&o));
    assert!(text(&o).contains("not converged") && text(&o).contains("o.last-valid.vtu"), "{}", text(&o));
    assert!(d.join("o.last-valid.vtu").exists() && !out.exists());
    let lines = std::fs::read_to_string(&report).unwrap();
    assert!(lines.lines().count() >= 1 && lines.contains("\"converged\":false"), "{lines}");

    // A run that succeeds: one JSON object per sub-step, one line per sub-step on stderr.
    let o = deform("");
    assert!(o.status.success(), "{}", text(&o));
    let lines = std::fs::read_to_string(&report).unwrap();
    assert_eq!(lines.lines().count(), 2, "{lines}");
    assert!(lines.lines().nth(1).unwrap().starts_with("{\"step\":2,\"substep\":1,\"fraction\":1.0,"), "{lines}");
    for key in ["solve_seconds", "quality_seconds", "reference_seconds"] {
        assert!(lines.lines().all(|l| l.contains(&format!("\"{key}\":"))), "{lines}");
    }
    assert!(String::from_utf8_lossy(&o.stderr).contains("step 2.1 at 1.0000"), "{}", text(&o));
    let _ = std::fs::remove_dir_all(&d);
}

/// `deform` moves a 3D mesh: the unit box of tetrahedra with its bottom and sides fixed and its
/// top translated by 0.1 in z, as a rigid motion and as the resulting displacement field read
/// back from the .vtu; the output has the moved top and no inverted cell.
#[test]
fn deform_moves_a_3d_mesh() {
    let dir = tmp("deform3d");
    let mesh = format!("{}/../tests/data/box_tets_41.msh", env!("CARGO_MANIFEST_DIR"));
    let original = meshmove::io::read_msh(Path::new(&mesh)).unwrap().mesh;
    assert_eq!(original.dim(), 3);
    let check = |out: &Path| {
        let d = meshmove::io::read_vtu(out).unwrap();
        let (_, inverted, _) = d.cell_data.iter().find(|(n, _, _)| n == "inverted").expect("cell data `inverted`");
        assert!(inverted.iter().all(|&x| x == 0.0), "inverted cells in {}", out.display());
        let moved = d.to_mesh().unwrap();
        assert_eq!(moved.dim(), 3);
        let (x0, x1) = (original.coords(), moved.coords());
        let mut top = 0;
        for v in 0..original.num_vertices() {
            let z0 = x0[3 * v + 2];
            if (z0 - 1.0).abs() < 1e-12 {
                top += 1;
                assert!((x1[3 * v + 2] - 1.1).abs() < 1e-9, "top vertex {v} at z = {}", x1[3 * v + 2]);
            } else if z0.abs() < 1e-12 {
                assert!(x1[3 * v + 2].abs() < 1e-12, "bottom vertex {v} moved");
            }
        }
        assert!(top >= 4);
    };
    let case = dir.join("case.toml");
    std::fs::write(
        &case,
        "[[patch]]\npatch = \"bottom\"\nkind = \"fixed\"\n[[patch]]\npatch = 0\nkind = [\"fixed\", \"fixed\", \"fixed\"]\n\
         [[patch]]\npatch = \"top\"\nkind = \"clamped\"\n[[motion]]\npatch = \"top\"\ntranslation = [0.0, 0.0, 0.1]\n",
    )
    .unwrap();
    let out = dir.join("out.vtu");
    let o = meshmove(&["deform", &mesh, "--config", case.to_str().unwrap(), "--output", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("inverted cells  0"), "{}", text(&o));
    check(&out);
    // The same motion as the 3-component displacement of that result, on the top only.
    let from_file = dir.join("file.toml");
    std::fs::write(&from_file, "[[motion]]\npatch = \"top\"\nfile = \"out.vtu\"\n").unwrap();
    let out2 = dir.join("out2.vtu");
    let o = meshmove(&["deform", &mesh, "--config", from_file.to_str().unwrap(), "-o", out2.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    check(&out2);
    // A rotation about z through the top's centre: needs `axis` in 3D.
    let rot = dir.join("rot.toml");
    std::fs::write(
        &rot,
        "[[motion]]\npatch = \"top\"\nrotation_deg = 10.0\naxis = [0, 0, 1]\ncenter = [0.5, 0.5, 1.0]\n",
    )
    .unwrap();
    let o =
        meshmove(&["deform", &mesh, "--config", rot.to_str().unwrap(), "-o", dir.join("rot.vtu").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every vector of the case file has the mesh's dimension: a 2-vector in a 3D case and a 3-vector
/// in a 2D case are errors naming the key; `axis` is required in 3D and refused in 2D.
#[test]
fn deform_vectors_have_the_mesh_dimension() {
    let d = tmp("vectors");
    let box3 = format!("{}/../tests/data/box_tets_41.msh", env!("CARGO_MANIFEST_DIR"));
    let channel = example("channel.msh");
    let cases = [
        (
            &box3,
            "[[motion]]\npatch = \"top\"\ntranslation = [0.0, 0.1]\n",
            "`translation` has 2 components; the mesh is 3D: expected 3",
        ),
        (
            &box3,
            "[[motion]]\npatch = 2\nrotation_deg = 5.0\ncenter = [0.5, 0.5]\naxis = [0, 0, 1]\n",
            "`center` has 2 components",
        ),
        (
            &box3,
            "[[patch]]\npatch = 2\nkind = [\"fixed\", \"free\"]\n",
            "`kind` has 2 components; the mesh is 3D: expected 3",
        ),
        (
            &box3,
            "[[link]]\na = 1\nb = 2\noffset = [0.0, 1.0]\n",
            "`offset` has 2 components; the mesh is 3D: expected 3",
        ),
        (&box3, "[[motion]]\npatch = 2\nrotation_deg = 5.0\n", "needs `axis"),
        (
            &channel,
            "[[motion]]\npatch = \"cylinder\"\ntranslation = [0.1, 0.0, 0.0]\n",
            "`translation` has 3 components; the mesh is 2D: expected 2",
        ),
        (
            &channel,
            "[[link]]\na = 1\nb = 2\noffset = [1.0, 0.0, 0.0]\n",
            "`offset` has 3 components; the mesh is 2D: expected 2",
        ),
        (
            &channel,
            "[[patch]]\npatch = 1\nkind = [\"fixed\", \"free\", \"free\"]\n",
            "`kind` has 3 components; the mesh is 2D: expected 2",
        ),
        (&channel, "[[motion]]\npatch = 2\nrotation_deg = 5.0\naxis = [0, 0, 1]\n", "`axis` is for 3D meshes"),
    ];
    for (i, (mesh, cfg, want)) in cases.iter().enumerate() {
        let p = d.join(format!("v{i}.toml"));
        std::fs::write(&p, cfg).unwrap();
        let out = d.join("o.vtu");
        let o = meshmove(&["deform", mesh, "--config", p.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(1), "{cfg}: {}", text(&o));
        assert!(text(&o).contains(want), "{cfg}: {}", text(&o));
        assert!(!out.exists(), "{cfg}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// A slip cylinder given its circle (`shape`) and moved along the channel in 4 steps: its
/// vertices slide along the moved circle and end on it to rounding.
#[test]
fn a_slip_patch_with_an_analytic_shape_stays_on_it() {
    let dir = tmp("shape");
    let mesh = example("channel.msh");
    let case = dir.join("case.toml");
    std::fs::write(
        &case,
        "steps = 4\n[[patch]]\npatch = \"wall\"\nkind = \"slip\"\n[[patch]]\npatch = \"cylinder\"\nkind = \"slip\"\n\
         shape = \"circle\"\ncenter = [2.0, 0.0]\nradius = 0.5\n[[motion]]\npatch = \"cylinder\"\ntranslation = [1.0, 0.2]\n",
    )
    .unwrap();
    let out = dir.join("out.vtu");
    let o = meshmove(&["deform", &mesh, "--config", case.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let original = meshmove::io::read_msh(Path::new(&mesh)).unwrap().mesh;
    let moved = meshmove::io::read_vtu(&out).unwrap().to_mesh().unwrap();
    let on = original.patch_vertices(2);
    assert_eq!(on.len(), 16);
    let mut slid = 0.0f64;
    for &v in &on {
        let (p, q) = (original.point(v as usize), moved.point(v as usize));
        let r = (q[0] - 3.0).hypot(q[1] - 0.2);
        assert!((r - 0.5).abs() < 1e-12, "vertex {v}: {r} from the moved centre");
        let a = |x: &[f64], c: [f64; 2]| (x[1] - c[1]).atan2(x[0] - c[0]);
        slid = slid.max((a(q, [3.0, 0.2]) - a(p, [2.0, 0.0])).abs());
    }
    // The normal part of the motion moves the circle; the vertices slide along it.
    assert!(slid > 1e-3, "the vertices slide along the circle: {slid}");
    let _ = std::fs::remove_dir_all(&dir);
}
