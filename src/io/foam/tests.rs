use super::*;
use crate::geometry::CellType;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/foam");

fn files(dir: &str) -> Vec<Vec<u8>> {
    ["points", "faces", "owner", "neighbour", "boundary"]
        .iter()
        .map(|f| std::fs::read(format!("{DATA}/{dir}/{f}")).unwrap())
        .collect()
}

/// Parses the five files, `edit` applied to file `which` first.
fn parse_edited(dir: &str, which: usize, edit: impl Fn(&[u8]) -> Vec<u8>) -> Result<Parsed, IoError> {
    let mut f = files(dir);
    f[which] = edit(&f[which]);
    parse_polymesh([&f[0], &f[1], &f[2], &f[3], &f[4]], ["points", "faces", "owner", "neighbour", "boundary"])
}

fn replace(bytes: &[u8], from: &str, to: &str) -> Vec<u8> {
    let at = bytes.windows(from.len()).position(|w| w == from.as_bytes()).expect("the text to replace");
    [&bytes[..at], to.as_bytes(), &bytes[at + from.len()..]].concat()
}

fn message(e: IoError) -> String {
    e.to_string()
}

#[test]
fn ascii_and_binary_read_the_same_mesh() {
    let a = read_polymesh(Path::new(&format!("{DATA}/sphere_ascii"))).unwrap();
    let b = read_polymesh(Path::new(&format!("{DATA}/sphere_binary"))).unwrap();
    assert_eq!((a.faces.coords.len(), a.faces.num_faces()), (3 * 444, 904));
    assert_eq!(a.faces.neighbour.iter().filter(|&&n| n >= 0).count(), 672);
    assert_eq!(a.patch_names, vec![(1, "outer".to_string()), (2, "ball".to_string())]);
    assert_eq!(a.faces.patch.iter().filter(|&&p| p == 2).count(), 64);
    // The ASCII file holds 17 digits: the same bits as the binary one.
    assert_eq!(a.faces, b.faces);
    assert_eq!(a.patch_names, b.patch_names);
    assert!(!a.format.binary && b.format.binary);
    assert_eq!((b.format.label_bytes, b.format.scalar_bytes, b.format.location.as_str()), (4, 8, "constant/polyMesh"));
    let mesh = a.to_mesh().unwrap();
    assert_eq!((mesh.num_vertices(), mesh.num_cells()), (444, 243));
    // checkMesh counts 188 hexahedra; 8 of them have a concave corner (snapped to the ball) and
    // are polyhedra here.
    let count = |t: CellType| (0..mesh.num_cells()).filter(|&c| mesh.cell_type(c) == t).count();
    assert_eq!(count(CellType::Hexahedron), 180);
    assert!(count(CellType::Polyhedron) >= 24, "{} polyhedra", count(CellType::Polyhedron));
    assert_eq!(mesh.coords(), &a.faces.coords[..]);
}

#[test]
fn points_written_read_back_to_the_same_bits() {
    for (dir, binary) in [("sphere_ascii", false), ("sphere_binary", true)] {
        let m = read_polymesh(Path::new(&format!("{DATA}/{dir}"))).unwrap();
        let moved: Vec<f64> = m.faces.coords.iter().enumerate().map(|(i, x)| x + 1e-3 * (i as f64).sin()).collect();
        let mut f = files(dir);
        f[0] = format_points(&moved, &m.format).unwrap();
        let (back, names, format) =
            parse_polymesh([&f[0], &f[1], &f[2], &f[3], &f[4]], ["points", "faces", "owner", "neighbour", "boundary"])
                .unwrap();
        assert_eq!(back.coords, moved);
        assert_eq!((names, format.binary), (m.patch_names.clone(), binary));
    }
}

#[test]
fn gzip_compressed_files_are_read_and_written_compressed() {
    let dir = std::env::temp_dir().join(format!("meshmove-foam-gz-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (name, bytes) in ["points", "faces", "owner", "neighbour", "boundary"].iter().zip(files("sphere_binary")) {
        let mut z = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        std::io::Write::write_all(&mut z, &bytes).unwrap();
        std::fs::write(dir.join(format!("{name}.gz")), z.finish().unwrap()).unwrap();
    }
    let m = read_polymesh(&dir).unwrap();
    assert!(m.format.compressed && m.format.binary);
    let moved: Vec<f64> = m.faces.coords.iter().map(|x| 2.0 * x).collect();
    assert_eq!(write_points(&dir, &moved, &m.format).unwrap(), dir.join("points.gz"));
    assert_eq!(read_polymesh(&dir).unwrap().faces.coords, moved);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_case_directory_leads_to_its_polymesh() {
    let case = std::env::temp_dir().join(format!("meshmove-foam-case-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&case);
    let src = PathBuf::from(format!("{DATA}/sphere_ascii"));
    let m = read_polymesh(&src).unwrap();
    let out = case.join("constant/polyMesh");
    write_polymesh(&src, &out, &m.faces.coords, &m.format).unwrap();
    assert_eq!(polymesh_dir(&case), Some(out.clone()));
    let back = read_polymesh(&case).unwrap();
    assert_eq!((back.faces, back.dir), (m.faces, out));
    std::fs::remove_dir_all(&case).unwrap();
    let e = read_polymesh(&case).unwrap_err();
    assert!(message(e).contains("neither a polyMesh directory"));
}

#[test]
fn malformed_files_are_clear_errors() {
    type Edit = Box<dyn Fn(&[u8]) -> Vec<u8>>;
    let cases: Vec<(usize, Edit, &str)> = vec![
        // Truncated: the last points are missing.
        (
            0,
            Box::new(|b: &[u8]| b[..b.len() / 2].to_vec()),
            "line 236: points: `)` expected to close point 215 (three coordinates), found the end of the file",
        ),
        (0, Box::new(|b: &[u8]| replace(b, "444\n(", "445\n(")), "point 444"),
        (0, Box::new(|b: &[u8]| replace(b, "FoamFile", "FoamFil")), "the `FoamFile` header expected first"),
        (0, Box::new(|b: &[u8]| replace(b, "ascii;", "text;")), "format `text`: `ascii` or `binary` expected"),
        (
            1,
            Box::new(|b: &[u8]| replace(b, "6(1 6 153", "6(1 6 444")),
            "faces: face 0: a vertex outside the 444 points",
        ),
        (
            2,
            Box::new(|b: &[u8]| replace(b, "904\n(\n0\n", "904\n(\n999\n")),
            "owner: face 0: cell 999 outside the 243 cells",
        ),
        (2, Box::new(|b: &[u8]| replace(b, "904\n(\n0\n", "903\n(\n")), "owner: 903 owners for the 904 faces"),
        (
            3,
            Box::new(|b: &[u8]| replace(b, "672\n(\n", "672\n(\nx")),
            "line 21: neighbour: entry 0 of the neighbours expected (an integer), found `x1`",
        ),
        (
            4,
            Box::new(|b: &[u8]| replace(b, "startFace       840", "startFace       841")),
            "patch `ball`: faces 841..841+64",
        ),
        (
            4,
            Box::new(|b: &[u8]| replace(b, "nFaces          64", "nFaces          63")),
            "face 903 has no neighbour and is in no patch",
        ),
        (
            4,
            Box::new(|b: &[u8]| replace(b, "nFaces          64;", "")),
            "patch `ball`: `startFace` and `nFaces` expected",
        ),
    ];
    for (which, edit, want) in cases {
        let e = message(parse_edited("sphere_ascii", which, edit).unwrap_err());
        assert!(e.contains(want), "`{e}` does not say `{want}`");
    }
    // Binary: a truncated list, a label size the arch does not allow.
    let e = message(parse_edited("sphere_binary", 0, |b| b[..b.len() - 100].to_vec()).unwrap_err());
    assert!(e.contains("points: 10656 bytes of binary data expected"), "{e}");
    let e = message(parse_edited("sphere_binary", 2, |b| replace(b, "label=32", "label=16")).unwrap_err());
    assert!(e.contains("arch `LSB;label=16;scalar=64`: 32 or 64 bits expected"), "{e}");
    let e = message(parse_edited("sphere_binary", 2, |b| replace(b, "LSB", "MSB")).unwrap_err());
    assert!(e.contains("big-endian"), "{e}");
}

#[test]
fn sixty_four_bit_labels_and_a_face_list_in_ascii_compact_form_read_alike() {
    // The owners as 64-bit binary labels, the faces as an ASCII faceCompactList.
    let m = read_polymesh(Path::new(&format!("{DATA}/sphere_ascii"))).unwrap();
    let f = files("sphere_ascii");
    let d = &m.faces;
    let mut owner = b"FoamFile { format binary; class labelList; arch \"LSB;label=64;scalar=64\"; }\n".to_vec();
    owner.extend(format!("{}\n(", d.owner.len()).bytes());
    d.owner.iter().for_each(|o| owner.extend(o.to_le_bytes()));
    owner.extend(b")\n");
    let list = |v: &[u32]| format!("{}({})", v.len(), v.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(" "));
    let faces = format!(
        "FoamFile {{ format ascii; class faceCompactList; }}\n{}\n{}\n",
        list(&d.face_offsets),
        list(&d.face_vertices)
    );
    let (back, _, _) = parse_polymesh(
        [&f[0], faces.as_bytes(), &owner, &f[3], &f[4]],
        ["points", "faces", "owner", "neighbour", "boundary"],
    )
    .unwrap();
    assert_eq!(&back, d);
}
