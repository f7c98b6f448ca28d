//! `mpirun -np N meshmove deform` (the `mpi` feature): on 1 to 4 ranks the written mesh equals
//! the serial command's to 1e-10 of the motion (both solved to a relative residual of 1e-12),
//! with the same inverted-cell summary and the same sub-step report lines (printed by rank 0
//! alone): a 2D channel whose cylinder moves rigidly in two steps (biharmonic and Laplacian), the
//! same channel moved by a displacement file (spring), a 3D box whose top heaves and pitches
//! through 20 steps with the step meshes written (`--every`), SLIP walls (flat; a slipping
//! cylinder put back on its circle or on its faces), periodic sides whose links METIS's parts
//! split between ranks, automatic sub-steps (the same `--report` lines, with the worst rank),
//! the original-reference mode, a run whose sub-stepping reaches its limit (the same last valid
//! mesh, status 4), a last step that inverts cells (the same mesh, status 3), and a `.pvtu`
//! whose pieces give the serial points by global id, a split interface, and periodic links
//! together with a SLIP wall (bitwise the same on a second run).
//! Skipped, with a message, where `mpirun` is missing. Run by `cargo test --release -p
//! meshmove-cli --features mpi --test deform_mpi`.

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
fn deform<S: AsRef<std::ffi::OsStr>>(ranks: usize, mesh: &str, dir: &Path, out: &str, extra: &[S]) -> Output {
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
    // `--report FILE`: FILE beside the output, named after it.
    let report = |stem: &str| dir.join(format!("{stem}.jsonl"));
    let with = |stem: &str| -> Vec<String> {
        let named = |a: &&str| if *a == "--report" { None } else { Some(a.to_string()) };
        let mut v: Vec<String> = extra.iter().filter_map(named).collect();
        if extra.contains(&"--report") {
            v.push("--report".into());
            v.push(report(stem).display().to_string());
        }
        v
    };
    let serial = deform(0, mesh, &dir, "serial.vtu", &with("serial"));
    ok(&serial);
    let reference = moved(&dir.join("serial.vtu"));
    let original = original_points(&dir.join("serial.vtu"));
    // The sub-steps' report lines (stderr): rank 0's alone, as many as serially.
    let substeps = |o: &Output| String::from_utf8_lossy(&o.stderr).lines().filter(|l| l.starts_with("step ")).count();
    for ranks in 1..=4 {
        let out = format!("ranks{ranks}.vtu");
        let stem = format!("ranks{ranks}");
        let o = deform(ranks, mesh, &dir, &out, &with(&stem));
        ok(&o);
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(stdout.contains(&format!("on {ranks} ranks (cells split by METIS)")), "{stdout}");
        let inverted = |s: &str| s.lines().find(|l| l.starts_with("inverted cells")).map(String::from);
        assert_eq!(inverted(&stdout), inverted(&String::from_utf8_lossy(&serial.stdout)));
        assert_eq!(substeps(&o), substeps(&serial), "{}", String::from_utf8_lossy(&o.stderr));
        if extra.contains(&"--report") {
            let lines = |p: PathBuf| std::fs::read_to_string(p).unwrap().lines().map(String::from).collect::<Vec<_>>();
            let (a, b) = (lines(report("serial")), lines(report(&stem)));
            assert_eq!(a.len(), b.len(), "{a:?}\n{b:?}");
            // The same sub-steps (where each ends, accepted or not), each with its worst rank.
            let field = |l: &str, k: &str| {
                l.split(&format!("\"{k}\":")).nth(1).map(|x| x.split([',', '}']).next().unwrap().to_string())
            };
            for (x, y) in a.iter().zip(&b) {
                for k in ["step", "substep", "fraction", "accepted", "inverted"] {
                    assert_eq!(field(x, k), field(y, k), "{k}: {x}\n{y}");
                }
                let worst: usize = field(y, "worst_rank").unwrap().parse().unwrap();
                assert!(worst < ranks, "{y}");
            }
            assert!(a.len() > 1, "the motion is split: {a:?}");
        }
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

/// The channel's walls slipping while its cylinder moves a whole diameter in four steps.
#[test]
fn channel_slip_walls_equal_serial() {
    let case = channel_case("biharmonic")
        .replace("kind = \"fixed\"", "kind = \"slip\"")
        .replace("steps = 2", "steps = 4")
        .replace("translation = [0.5, 0.0]", "translation = [1.0, 0.0]");
    agrees_on_1_to_4_ranks("channel-slip", "channel.msh", &case, &[], &[]);
}

/// A slipping cylinder moved along the slipping channel: once put back on its circle (the
/// shape), once on its own faces (none given).
#[test]
fn slipping_cylinder_on_its_circle_and_on_its_faces_equals_serial() {
    let case = "method = \"biharmonic\"\ntolerance = 1e-12\nsteps = 4\n[[patch]]\npatch = \"wall\"\nkind = \"slip\"\n\
                [[patch]]\npatch = \"cylinder\"\nkind = \"slip\"\nshape = \"circle\"\ncenter = [2.0, 0.0]\nradius = 0.5\n\
                [[motion]]\npatch = \"cylinder\"\ntranslation = [1.0, 0.2]\n";
    agrees_on_1_to_4_ranks("bubble-circle", "channel.msh", case, &[], &[]);
    // To 1e-11: at 1e-12 the coupled group's conjugate gradients on 3 ranks break down at a
    // residual of 6e-11 in the second step (rounding at the tolerance).
    let faces = case
        .replace("shape = \"circle\"\ncenter = [2.0, 0.0]\nradius = 0.5\n", "")
        .replace("tolerance = 1e-12", "tolerance = 1e-11");
    agrees_on_1_to_4_ranks("bubble-faces", "channel.msh", &faces, &[], &[]);
}

/// The two-region mesh's periodic sides (x clamped, y free, linked), its interface raised in
/// three steps: on 2 to 4 ranks METIS's parts split the linked pairs between ranks.
#[test]
fn periodic_sides_linked_across_ranks_equal_serial() {
    for method in ["biharmonic", "laplacian"] {
        let case = format!(
            "method = \"{method}\"\ntolerance = 1e-12\nsteps = 3\n\
             [[patch]]\npatch = \"left\"\nkind = [\"clamped\", \"free\"]\n\
             [[patch]]\npatch = \"right\"\nkind = [\"clamped\", \"free\"]\n\
             [[patch]]\npatch = \"interface\"\nkind = \"clamped\"\n\
             [[link]]\na = \"left\"\nb = \"right\"\noffset = [1.0, 0.0]\n\
             [[motion]]\npatch = \"interface\"\ntranslation = [0.0, 0.3]\n"
        );
        agrees_on_1_to_4_ranks(&format!("periodic-{method}"), "two_region.msh", &case, &[], &[]);
    }
}

/// The cylinder moved 2.5 D in one step split automatically (`steps = "auto"`): the same
/// sub-steps (the `--report` lines, with the worst cell's rank under mpirun) and the same mesh.
#[test]
fn automatic_sub_steps_equal_serial() {
    let case = channel_case("biharmonic")
        .replace("steps = 2", "steps = \"auto\"")
        .replace("translation = [0.5, 0.0]", "translation = [2.5, 0.0]");
    agrees_on_1_to_4_ranks("substeps", "channel.msh", &case, &["--report"], &[]);
}

/// Every step solved from the original mesh (`reference = "original"`).
#[test]
fn original_reference_equals_serial() {
    let case = format!("reference = \"original\"\n{}", channel_case("biharmonic"));
    agrees_on_1_to_4_ranks("original", "channel.msh", &case, &[], &[]);
    let case = std::fs::read_to_string(examples().join("box_oscillate.toml")).unwrap();
    let case = format!("tolerance = 1e-12\nreference = \"original\"\n{case}");
    agrees_on_1_to_4_ranks("box-original", "box.msh", &case, &[], &[]);
}

/// An interface clamped on each side (split per region, each region's copy of an interface
/// vertex its own unknown) raised in three steps, the sides sliding: the same mesh as serially.
#[test]
fn a_split_interface_equals_serial() {
    let case = "tolerance = 1e-12\nsteps = 3\n[[patch]]\npatch = \"interface\"\nkind = \"clamped\"\n\
                [[patch]]\npatch = \"left\"\nkind = [\"clamped\", \"free\"]\n\
                [[patch]]\npatch = \"right\"\nkind = [\"clamped\", \"free\"]\n\
                [[interface]]\npatch = \"interface\"\nvariant = \"separate\"\n\
                [[motion]]\npatch = \"interface\"\ntranslation = [0.0, 0.3]\n";
    agrees_on_1_to_4_ranks("interface", "two_region.msh", case, &[], &[]);
}

/// The periodic sides (x clamped, y free, linked) with the bottom SLIP, its interface raised in
/// three steps: the linked corners on the slipping bottom are one unknown serially, and on 2
/// to 4 ranks METIS's parts split the linked pairs between ranks. Both methods equal serial;
/// a second run on 3 ranks gives bitwise the same mesh.
#[test]
fn links_with_slip_walls_equal_serial() {
    for method in ["biharmonic", "laplacian"] {
        let case = format!(
            "method = \"{method}\"\ntolerance = 1e-12\nsteps = 3\n[[patch]]\npatch = \"bottom\"\nkind = \"slip\"\n\
             [[patch]]\npatch = \"left\"\nkind = [\"clamped\", \"free\"]\n\
             [[patch]]\npatch = \"right\"\nkind = [\"clamped\", \"free\"]\n\
             [[patch]]\npatch = \"interface\"\nkind = \"clamped\"\n\
             [[link]]\na = \"left\"\nb = \"right\"\noffset = [1.0, 0.0]\n\
             [[motion]]\npatch = \"interface\"\ntranslation = [0.0, 0.3]\n"
        );
        let name = format!("links-slip-{method}");
        agrees_on_1_to_4_ranks(&name, "two_region.msh", &case, &[], &[]);
        if !have_mpirun() {
            return;
        }
        // The directory `agrees_on_1_to_4_ranks` wrote (`tmp` would empty it).
        let dir = std::env::temp_dir().join(format!("meshmove-mpi-{}-{name}", std::process::id()));
        ok(&deform(3, "two_region.msh", &dir, "again.vtu", &[] as &[&str]));
        assert_eq!(moved(&dir.join("again.vtu")), moved(&dir.join("ranks3.vtu")), "{name}: a second run on 3 ranks");
    }
}

/// Sub-stepping that reaches its limit (eight sub-steps, each keeping 0.78 of every cell's area,
/// for a cylinder moved 2 D: three quarters of the motion are accepted): status 4 and the same
/// last valid mesh as serially.
#[test]
fn a_step_past_the_sub_step_limit_leaves_the_serial_last_valid_mesh() {
    if !have_mpirun() {
        return;
    }
    let dir = tmp("limit");
    let case = channel_case("biharmonic")
        .replace("steps = 2", "steps = 1\nmax_substeps = 8\nmin_volume_ratio = 0.78")
        .replace("translation = [0.5, 0.0]", "translation = [2.0, 0.0]");
    std::fs::write(dir.join("case.toml"), case).unwrap();
    let no: [&str; 0] = [];
    let serial = deform(0, "channel.msh", &dir, "serial.vtu", &no);
    let stderr = String::from_utf8_lossy(&serial.stderr);
    assert_eq!(serial.status.code(), Some(4), "{stderr}");
    assert!(stderr.contains("(75.0% of the motion)"), "{stderr}");
    let reference = moved(&dir.join("serial.last-valid.vtu"));
    let original = original_points(&dir.join("serial.last-valid.vtu"));
    for ranks in [1, 3] {
        let o = deform(ranks, "channel.msh", &dir, &format!("ranks{ranks}.vtu"), &no);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(4), "{stderr}");
        assert_eq!(stderr.matches("meshmove: error:").count(), 1, "{stderr}");
        assert!(stderr.contains("(75.0% of the motion)"), "{stderr}");
        assert!(!dir.join(format!("ranks{ranks}.vtu")).exists());
        let last = moved(&dir.join(format!("ranks{ranks}.last-valid.vtu")));
        let d = relative_difference(&last, &reference, &original);
        assert!(d < 1e-10, "on {ranks} ranks the last valid mesh differs from serial by {d:e}");
    }
}

/// `-o OUT.pvtu`: each rank's piece OUT_<rank>.vtu holds its owned cells; read back, the pieces
/// give every vertex (by `global_id`) the serial command's moved point, and the index names them.
#[test]
fn a_pvtu_output_is_one_piece_per_rank_giving_the_serial_points() {
    if !have_mpirun() {
        return;
    }
    let dir = tmp("pvtu");
    std::fs::write(dir.join("case.toml"), channel_case("biharmonic")).unwrap();
    let no: [&str; 0] = [];
    ok(&deform(0, "channel.msh", &dir, "serial.vtu", &no));
    let serial = read_vtu(&dir.join("serial.vtu")).unwrap();
    let reference = &serial.mesh.coords;
    let original = original_points(&dir.join("serial.vtu"));
    let ranks = 3;
    ok(&deform(ranks, "channel.msh", &dir, "out.pvtu", &no));
    let index = std::fs::read_to_string(dir.join("out.pvtu")).unwrap();
    let (mut cells, mut seen) = (0, vec![false; reference.len() / 2]);
    let mut points = reference.clone();
    for r in 0..ranks {
        assert!(index.contains(&format!("<Piece Source=\"out_{r}.vtu\"/>")), "{index}");
        let piece = read_vtu(&dir.join(format!("out_{r}.vtu"))).unwrap();
        let gids = &piece.point_data.iter().find(|p| p.0 == "global_id").unwrap().1;
        for (v, g) in gids.iter().enumerate() {
            let g = *g as usize;
            points[2 * g..2 * g + 2].copy_from_slice(&piece.mesh.coords[2 * v..2 * v + 2]);
            seen[g] = true;
        }
        cells += piece.mesh.num_cells();
        assert!(piece.cell_data.iter().any(|c| c.0 == "area_ratio"));
    }
    assert_eq!(cells, serial.mesh.num_cells(), "each cell in one piece");
    assert!(seen.iter().all(|&s| s), "every vertex in a piece");
    let d = relative_difference(&points, reference, &original);
    assert!(d < 1e-10, "the pieces differ from serial by {d:e}");
}

/// A last step whose result inverts cells (the cylinder moved 2.5 D in one step; in two from the
/// original mesh): written anyway with status 3, the same mesh as serially.
#[test]
fn an_inverted_last_step_is_written_as_serially() {
    if !have_mpirun() {
        return;
    }
    for (name, reference, steps) in [("inverted", "incremental", 1), ("inverted-original", "original", 2)] {
        let dir = tmp(name);
        let case = channel_case("biharmonic")
            .replace("translation = [0.5, 0.0]", "translation = [2.5, 0.0]")
            .replace("steps = 2", &format!("steps = {steps}"));
        std::fs::write(dir.join("case.toml"), format!("reference = \"{reference}\"\n{case}")).unwrap();
        let no: [&str; 0] = [];
        let serial = deform(0, "channel.msh", &dir, "serial.vtu", &no);
        assert_eq!(serial.status.code(), Some(3), "{}", String::from_utf8_lossy(&serial.stderr));
        let inverted =
            |s: &[u8]| String::from_utf8_lossy(s).lines().find(|l| l.starts_with("inverted cells")).map(String::from);
        let original = original_points(&dir.join("serial.vtu"));
        for ranks in [1, 3] {
            let o = deform(ranks, "channel.msh", &dir, &format!("ranks{ranks}.vtu"), &no);
            assert_eq!(o.status.code(), Some(3), "{}", String::from_utf8_lossy(&o.stderr));
            assert_eq!(inverted(&o.stdout), inverted(&serial.stdout));
            let d = relative_difference(
                &moved(&dir.join(format!("ranks{ranks}.vtu"))),
                &moved(&dir.join("serial.vtu")),
                &original,
            );
            assert!(d < 1e-10, "{name} on {ranks} ranks: differs from serial by {d:e}");
        }
    }
}
