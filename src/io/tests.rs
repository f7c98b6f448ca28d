//! Tests of the mesh file readers and writers, on Gmsh-made fixtures in `tests/data/`.

use super::*;
use crate::mesh::Mesh;
use glam::DVec2;
use std::path::PathBuf;

pub(super) fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

pub(super) fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("meshmove-io-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn edges_of(m: &Mesh, patch: i32) -> usize {
    m.patch_edges().iter().filter(|e| e.patch == patch).count()
}

/// Same topology, patches and regions; coordinates within `tol` (0: bitwise).
fn assert_same(a: &MshMesh, b: &MshMesh, tol: f64) {
    let (ma, mb) = (&a.mesh, &b.mesh);
    assert_eq!(ma.num_vertices(), mb.num_vertices());
    assert_eq!(ma.tris(), mb.tris());
    assert_eq!(ma.regions(), mb.regions());
    assert_eq!(ma.patch_edges(), mb.patch_edges());
    assert_eq!(a.node_tags, b.node_tags);
    assert_eq!(a.physical_names, b.physical_names);
    for (p, q) in ma.points_2d().iter().zip(mb.points_2d()) {
        if tol == 0.0 {
            assert_eq!((p.x.to_bits(), p.y.to_bits()), (q.x.to_bits(), q.y.to_bits()));
        } else {
            assert!((*p - q).abs().max_element() <= tol, "{p} vs {q}");
        }
    }
}

#[test]
fn gmsh_fixtures_22_41_ascii_binary_agree() {
    let files = ["square_hole_22.msh", "square_hole_22_bin.msh", "square_hole_41.msh", "square_hole_41_bin.msh"];
    let meshes: Vec<MshMesh> = files.iter().map(|f| read_msh(&data(f)).unwrap()).collect();
    let m0 = &meshes[0];
    assert_eq!(m0.mesh.num_vertices(), 36);
    assert_eq!(m0.mesh.num_cells(), 48);
    assert_eq!(m0.mesh.patch_ids(), vec![1, 2, 3]);
    // Each square side and each quarter circle is meshed with 2 segments at lc = 0.25.
    assert_eq!(edges_of(&m0.mesh, 1), 8);
    assert_eq!(edges_of(&m0.mesh, 2), 8);
    assert_eq!(edges_of(&m0.mesh, 3), 8);
    assert!(m0.mesh.regions().iter().all(|&r| r == 7));
    assert_eq!(
        m0.physical_names,
        vec![
            (1, 1, "wall".to_string()),
            (1, 2, "inout".to_string()),
            (1, 3, "hole".to_string()),
            (2, 7, "fluid".to_string()),
        ]
    );
    // The hole: patch 3 vertices at distance 0.2 from (0.5, 0.5).
    for v in m0.mesh.patch_vertices(3) {
        let d = (m0.mesh.points_2d()[v as usize] - DVec2::new(0.5, 0.5)).length();
        assert!((d - 0.2).abs() < 1e-12, "{d}");
    }
    // Gmsh writes ASCII with %.16g, so ASCII and binary agree to rounding only.
    assert_same(&meshes[0], &meshes[2], 0.0);
    assert_same(&meshes[1], &meshes[3], 0.0);
    assert_same(&meshes[0], &meshes[1], 1e-15);
}

#[test]
fn gmsh_two_regions_interface_and_unnamed_curve() {
    // 4.1 written with -save_all: the top curves have no physical group (patch 0), points
    // (type 15) are in the file; the 2.2 binary omits them. Both read to the same mesh.
    let a = read_msh(&data("two_regions_41.msh")).unwrap();
    let b = read_msh(&data("two_regions_22_bin.msh")).unwrap();
    assert_same(&a, &b, 1e-15);
    let m = &a.mesh;
    assert_eq!((m.num_vertices(), m.num_cells()), (56, 86));
    assert_eq!(m.patch_ids(), vec![0, 4, 5, 9]);
    let interface: Vec<_> = m.patch_edges().into_iter().filter(|e| e.patch == 9).collect();
    assert_eq!(interface.len(), 4);
    assert!(interface.iter().all(|e| e.interior));
    assert!(m.patch_vertices(9).iter().all(|&v| m.point(v as usize)[0] == 1.0));
    assert!(m.patch_vertices(0).iter().all(|&v| m.point(v as usize)[1] == 1.0));
    assert_eq!(edges_of(m, 4), 8);
    assert_eq!(edges_of(m, 0), 8);
    for (c, &r) in m.tris().iter().zip(m.regions()) {
        let cx = c.iter().map(|&v| m.point(v as usize)[0]).sum::<f64>() / 3.0;
        assert_eq!(r, if cx < 1.0 { 1 } else { 2 });
    }
    // Node tags: the Gmsh tags of the kept nodes, distinct.
    let mut t = a.node_tags.clone();
    t.sort_unstable();
    t.dedup();
    assert_eq!(t.len(), 56);
}

#[test]
fn write_msh22_round_trip_is_exact() {
    let src = read_msh(&data("two_regions_41.msh")).unwrap().mesh;
    // Coordinates with full 53-bit mantissas, and one tiny and one huge offset.
    let coords: Vec<DVec2> = src
        .points_2d()
        .iter()
        .enumerate()
        .map(|(i, p)| *p * std::f64::consts::PI + DVec2::splat(1e-300 * i as f64))
        .collect();
    let mesh = src.with_coords(coords.iter().flat_map(|p| [p.x, p.y]).collect());
    let path = tmp("round.msh");
    write_msh22(&mesh, &path).unwrap();
    let back = read_msh(&path).unwrap();
    assert_eq!(back.node_tags, (1..=mesh.num_vertices()).collect::<Vec<_>>());
    let bm = &back.mesh;
    for (p, q) in mesh.points_2d().iter().zip(bm.points_2d()) {
        assert_eq!((p.x.to_bits(), p.y.to_bits()), (q.x.to_bits(), q.y.to_bits()));
    }
    assert_eq!(bm.tris(), mesh.tris());
    assert_eq!(bm.regions(), mesh.regions());
    assert_eq!(bm.patch_edges(), mesh.patch_edges());
}

fn sample_fields(n: usize, m: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<i32>) {
    let s: Vec<f64> = (0..n).map(|i| (i as f64 + 0.1).sqrt() * 1e-7).collect();
    let v: Vec<f64> = (0..n).flat_map(|i| [(i as f64).sin(), -(i as f64 / 3.0)]).collect();
    let f: Vec<f64> = (0..m).map(|c| 1.0 / (c as f64 + 3.0)).collect();
    let k: Vec<i32> = (0..m).map(|c| c as i32 * 7 - 40).collect();
    (s, v, f, k)
}

const ENCODINGS: [VtuEncoding; 3] = [VtuEncoding::Binary, VtuEncoding::Compressed, VtuEncoding::Ascii];

#[test]
fn vtu_round_trip_is_exact() {
    let mesh = read_msh(&data("square_hole_41_bin.msh")).unwrap().mesh;
    let (n, m) = (mesh.num_vertices(), mesh.num_cells());
    let (s, v, f, k) = sample_fields(n, m);
    let mut written = mesh.to_data();
    written.coords.iter_mut().for_each(|x| *x /= 3.0);
    let mut sizes = Vec::new();
    for enc in ENCODINGS {
        let path = tmp(&format!("rt_{enc:?}.vtu"));
        write_vtu_as(
            &path,
            &written,
            &[("s", PointField::Scalar(&s)), ("v <&>", PointField::Vector(&v, 2))],
            &[("f", CellField::F64(&f)), ("region", CellField::I32(&k))],
            enc,
        )
        .unwrap();
        let bytes = std::fs::read(&path).unwrap();
        sizes.push(bytes.len());
        let has = |t: &str| bytes.windows(t.len()).any(|w| w == t.as_bytes());
        assert_eq!(has("<AppendedData encoding=\"raw\">"), enc != VtuEncoding::Ascii, "{enc:?}");
        assert_eq!(has("compressor=\"vtkZLibDataCompressor\""), enc == VtuEncoding::Compressed, "{enc:?}");
        assert_eq!(has("format=\"ascii\""), enc == VtuEncoding::Ascii, "{enc:?}");
        let d = read_vtu(&path).unwrap();
        assert_eq!(d.mesh.num_vertices(), n);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&d.mesh.coords), bits(&written.coords), "{enc:?}");
        assert_eq!(d.mesh.cell_vertices, written.cell_vertices);
        assert_eq!(d.mesh.face_vertices, written.face_vertices);
        assert_eq!(d.mesh.face_patch, written.face_patch);
        assert_eq!(d.mesh.regions, k);
        assert_eq!(d.point_data.len(), 2);
        assert_eq!((d.point_data[0].0.as_str(), d.point_data[0].2), ("s", 1));
        assert!(d.point_data[0].1.iter().zip(&s).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!((d.point_data[1].0.as_str(), d.point_data[1].2), ("v <&>", 3));
        for (i, p) in v.chunks_exact(2).enumerate() {
            assert_eq!(&d.point_data[1].1[3 * i..3 * i + 3], &[p[0], p[1], 0.0]);
        }
        assert_eq!((d.cell_data[0].0.as_str(), d.cell_data[0].2), ("f", 1));
        assert!(d.cell_data[0].1.iter().zip(&f).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(d.cell_data[1].1, k.iter().map(|&x| x as f64).collect::<Vec<_>>());
        let back = d.to_mesh().unwrap();
        assert_eq!(back.regions(), &k[..]);
        assert_eq!(back.tris(), mesh.tris());
    }
    // Binary holds 8 bytes a float where text holds about 20; zlib shrinks the integer arrays.
    assert!(sizes[0] < sizes[2] && sizes[1] < sizes[0], "binary, compressed, ascii: {sizes:?} bytes");
}

/// The layout VTK reads: after `_`, each array's UInt64 byte count and its little-endian bytes,
/// one after another at the offsets the XML gives.
#[test]
fn appended_binary_layout() {
    let d = crate::mesh::MeshData {
        dim: 2,
        coords: vec![0.0, 0.0, 1.0, 0.0, 0.0, 1.0],
        cell_types: vec![crate::geometry::CellType::Triangle],
        cell_offsets: vec![0, 3],
        cell_vertices: vec![0, 1, 2],
        ..crate::mesh::MeshData::new(2)
    };
    let path = tmp("layout.vtu");
    write_vtu(&path, &d, &[("s", PointField::Scalar(&[1.5, -2.0, 0.25]))], &[]).unwrap();
    let b = std::fs::read(&path).unwrap();
    let text = String::from_utf8_lossy(&b);
    let offsets: Vec<usize> = text
        .match_indices("offset=\"")
        .map(|(i, m)| text[i + m.len()..].split('"').next().unwrap().parse().unwrap())
        .collect();
    // s (3 floats), points (9 floats), connectivity (3 Int64), offsets (1 Int64), types (1 byte).
    assert_eq!(offsets, vec![0, 8 + 24, 8 + 24 + 8 + 72, 8 + 24 + 8 + 72 + 8 + 24, 8 + 24 + 8 + 72 + 8 + 24 + 8 + 8]);
    let start = b.windows(2).position(|w| w == b"\n_").unwrap() + 2;
    let word = |at: usize| u64::from_le_bytes(b[start + at..start + at + 8].try_into().unwrap());
    assert_eq!(word(0), 24);
    assert_eq!(f64::from_bits(word(16)), -2.0);
    assert_eq!(word(32), 72);
    assert_eq!(f64::from_bits(word(32 + 8 + 24)), 1.0);
    assert_eq!(word(offsets[3] + 8), 3);
    assert_eq!(word(offsets[4]), 1);
    assert_eq!(b[start + offsets[4] + 8], 5);
    assert!(b.ends_with(b"\n</AppendedData>\n</VTKFile>\n"));
}

/// VTK itself reads what we write, in every encoding, to the same points, cells and fields.
/// Runs only where Python's `vtk` module (python3-vtk9) is installed; skips otherwise.
#[test]
fn vtk_reads_written_files() {
    let python = ["python3", "/usr/bin/python3"]
        .into_iter()
        .find(|p| std::process::Command::new(p).args(["-c", "import vtk"]).output().is_ok_and(|o| o.status.success()));
    let Some(python) = python else {
        eprintln!("skipped: no Python with the vtk module");
        return;
    };
    let mesh = read_msh(&data("square_hole_41_bin.msh")).unwrap().mesh;
    let disp: Vec<f64> = mesh.coords().iter().map(|x| 0.01 * x).collect();
    let script = "import sys, vtk\n\
        r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update()\n\
        g = r.GetOutput(); p = g.GetPoint(g.GetNumberOfPoints() - 1)\n\
        d = g.GetPointData().GetArray('displacement').GetTuple3(g.GetNumberOfPoints() - 1)\n\
        print(g.GetNumberOfPoints(), g.GetNumberOfCells(), g.GetCellType(0), g.GetCellType(g.GetNumberOfCells() - 1),\n\
              repr(p[0]), repr(d[0]), int(g.GetCellData().GetArray('patch').GetTuple1(g.GetNumberOfCells() - 1)))\n";
    let n = mesh.num_vertices();
    let last = mesh.point(n - 1);
    let data = mesh.to_data();
    for enc in ENCODINGS {
        let path = tmp(&format!("vtk_{enc:?}.vtu"));
        write_deformed_as(&path, &data, &disp, enc).unwrap();
        let out = std::process::Command::new(python).args(["-c", script]).arg(&path).output().unwrap();
        assert!(out.status.success(), "{enc:?}: {}", String::from_utf8_lossy(&out.stderr));
        let got = String::from_utf8_lossy(&out.stdout);
        let (cells, faces) = (mesh.num_cells(), data.num_faces());
        let x = last[0] + disp[2 * (n - 1)];
        let want = format!("{n} {} 5 3 {x:?} {:?} {}\n", cells + faces, disp[2 * (n - 1)], data.face_patch[faces - 1]);
        assert_eq!(got, want, "{enc:?}");
    }
}

#[test]
fn write_deformed_fields() {
    let mesh = read_msh(&data("square_hole_22.msh")).unwrap().mesh;
    let n = mesh.num_vertices();
    // Stretch x by 2 (area ratio 2), then flip one vertex far across to invert some cells.
    let mut disp: Vec<f64> = mesh.points_2d().iter().flat_map(|p| [p.x, 0.0]).collect();
    let path = tmp("def.vtu");
    write_deformed(&path, &mesh, &disp).unwrap();
    let d = read_vtu(&path).unwrap();
    let get = |name: &str| d.cell_data.iter().find(|x| x.0 == name).unwrap().1.clone();
    assert!(get("area_ratio").iter().all(|&r| (r - 2.0).abs() < 1e-12));
    assert!(get("inverted").iter().all(|&r| r == 0.0));
    assert!(get("region").iter().all(|&r| r == 7.0));
    assert!(get("min_angle").iter().all(|&a| a > 0.0 && a < 60.0));
    for (p, (q, u)) in d.mesh.coords.chunks_exact(2).zip(mesh.points_2d().iter().zip(disp.chunks_exact(2))) {
        assert_eq!(p[0], q.x + u[0]);
    }
    let v = mesh.tris()[0][0] as usize;
    disp[2 * v..2 * v + 2].copy_from_slice(&[5.0, 5.0]);
    write_deformed(&path, &mesh, &disp).unwrap();
    let d = read_vtu(&path).unwrap();
    let inv = d.cell_data.iter().find(|x| x.0 == "inverted").unwrap();
    assert!(inv.1.contains(&1.0));
    assert_eq!(d.point_data[0].1.len(), 3 * n);
    assert!(matches!(write_deformed(&path, &mesh, &disp[1..]), Err(IoError::InvalidArgument(_))));
}

// ---- malformed input --------------------------------------------------------------------------

const GOOD22: &str = "$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
10 0 0 0
20 1 0 0
30 1 1 0
40 0 1 0
$EndNodes
$Elements
3
1 1 2 5 5 10 20
2 2 2 1 1 10 20 30
3 2 2 1 1 10 30 40
$EndElements
";

fn parse_err(text: &str) -> (usize, String) {
    match parse_msh(text.as_bytes()) {
        Err(IoError::Parse { line, message, .. }) => (line, message),
        other => panic!("expected a Parse error, got {other:?}"),
    }
}

#[test]
fn hand_written_22_reads() {
    let m = parse_msh(GOOD22.as_bytes()).unwrap();
    assert_eq!(m.node_tags, vec![10, 20, 30, 40]);
    assert_eq!(m.mesh.patch_ids(), vec![0, 5]);
    assert_eq!(edges_of(&m.mesh, 5), 1);
    assert_eq!(m.mesh.regions(), &[1, 1]);
}

/// Node tags far above the node count (looked up in the hash map beside the table of small
/// tags) read the same mesh, and a repeated one is still an error.
#[test]
fn sparse_node_tags_read_the_same_mesh() {
    let sparse = GOOD22
        .replace("20 1 0 0", "9000000000 1 0 0")
        .replace("30 1 1 0", "2000 1 1 0")
        .replace("5 5 10 20", "5 5 10 9000000000")
        .replace("1 1 10 20 30", "1 1 10 9000000000 2000")
        .replace("1 1 10 30 40", "1 1 10 2000 40");
    let (a, b) = (parse_msh(GOOD22.as_bytes()).unwrap(), parse_msh(sparse.as_bytes()).unwrap());
    assert_eq!(b.node_tags, vec![10, 9000000000, 2000, 40]);
    assert_eq!(a.data, b.data);
    let (line, msg) = parse_err(&sparse.replace("2000 1 1 0", "9000000000 1 1 0"));
    assert_eq!(line, 8, "{msg}");
    assert!(msg.contains("9000000000 appears twice"), "{msg}");
}

#[test]
fn truncated_nodes() {
    let t = GOOD22.replace("40 0 1 0\n", "");
    let (line, msg) = parse_err(&t);
    assert_eq!(line, 9, "{msg}");
    assert!(msg.contains("$Nodes") && msg.contains("$EndNodes"), "{msg}");
    // Cut off inside $Nodes, at the end of the file.
    let t = &GOOD22[..GOOD22.find("30 1 1 0").unwrap()];
    let (line, msg) = parse_err(t);
    assert_eq!(line, 7, "{msg}");
    assert!(msg.contains("end of file") && msg.contains("$Nodes"), "{msg}");
}

#[test]
fn non_number() {
    let (line, msg) = parse_err(&GOOD22.replace("20 1 0 0", "20 1 x0 0"));
    assert_eq!(line, 7);
    assert!(msg.contains("`x0`") && msg.contains("$Nodes"), "{msg}");
    let (line, msg) = parse_err(&GOOD22.replace("3 2 2 1 1 10 30 40", "3 2 2 1 1 10 30 4.5"));
    assert_eq!(line, 15);
    assert!(msg.contains("$Elements"), "{msg}");
}

#[test]
fn missing_end_elements() {
    let (line, msg) = parse_err(&GOOD22.replace("$EndElements\n", ""));
    assert_eq!(line, 15);
    assert!(msg.contains("$EndElements") && msg.contains("end of file"), "{msg}");
    let t = GOOD22.replace("$EndElements\n", "$NodeData\n$EndNodeData\n");
    let (line, msg) = parse_err(&t);
    assert_eq!(line, 16);
    assert!(msg.contains("`$NodeData`"), "{msg}");
}

#[test]
fn wrong_node_count() {
    let (line, msg) = parse_err(&GOOD22.replace("$Nodes\n4\n", "$Nodes\n3\n"));
    assert_eq!(line, 9);
    assert!(msg.contains("$EndNodes") && msg.contains("`40`"), "{msg}");
    // 4.1: header total disagrees with the blocks.
    let t41 = std::fs::read_to_string(data("square_hole_41.msh")).unwrap();
    let t = t41.replacen("$Nodes\n17 36 1 36", "$Nodes\n17 37 1 36", 1);
    let (line, msg) = parse_err(&t);
    assert!(msg.contains("announces 37 nodes"), "{msg}");
    let end_nodes = t.lines().position(|l| l == "$EndNodes").unwrap() + 1;
    assert_eq!(line, end_nodes - 1);
}

#[test]
fn unknown_and_unsupported_version() {
    let (line, msg) = parse_err(&GOOD22.replace("2.2 0 8", "2.x 0 8"));
    assert_eq!(line, 2);
    assert!(msg.contains("$MeshFormat") && msg.contains("`2.x`"), "{msg}");
    let (line, _) = parse_err(&GOOD22.replace("2.2 0 8", "7.3 0 8"));
    assert_eq!(line, 2);
    assert!(matches!(
        parse_msh(GOOD22.replace("2.2 0 8", "3.0 0 8").as_bytes()),
        Err(IoError::Unsupported(m)) if m.contains("3.0")
    ));
}

#[test]
fn element_with_missing_node() {
    let (line, msg) = parse_err(&GOOD22.replace("2 2 2 1 1 10 20 30", "2 2 2 1 1 10 20 31"));
    assert_eq!(line, 14);
    assert!(msg.contains("node 31") && msg.contains("$Elements"), "{msg}");
    // 4.1 ASCII from Gmsh, one node tag of the last element changed.
    let t41 = std::fs::read_to_string(data("square_hole_41.msh")).unwrap();
    let mut lines: Vec<String> = t41.lines().map(String::from).collect();
    let end = lines.iter().position(|l| l == "$EndElements").unwrap();
    lines[end - 1] = lines[end - 1].replacen(' ', " 999 ", 1);
    let (line, msg) = parse_err(&(lines.join("\n") + "\n"));
    assert_eq!(line, end);
    assert!(msg.contains("node 999"), "{msg}");
}

#[test]
fn unsupported_element_and_truncated_binary() {
    let t = GOOD22.replace("3 2 2 1 1 10 30 40", "3 9 2 1 1 10 20 30 40 20 30");
    assert!(matches!(
        parse_msh(t.as_bytes()),
        Err(IoError::Unsupported(m)) if m.contains("type 9") && m.contains("6-node triangle") && m.contains("line 15")
    ));
    let b = std::fs::read(data("square_hole_41_bin.msh")).unwrap();
    let cut = b.windows(9).position(|w| w == b"$Elements").unwrap() + 40;
    match parse_msh(&b[..cut]) {
        Err(IoError::Parse { line: 0, offset: Some(o), message }) => {
            assert!(o <= cut && message.contains("$Elements"), "{message}")
        }
        other => panic!("{other:?}"),
    }
    let no_tri = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n0 1 0 1\n1\n0 0 0\n$EndNodes\n$Elements\n1 1 1 1\n0 1 15 1\n1 1\n$EndElements\n";
    assert!(matches!(parse_msh(no_tri.as_bytes()), Err(IoError::Unsupported(_))));
}

/// A small ASCII .vtu, for tests that edit its text.
fn vtu_text() -> String {
    let mesh = parse_msh(GOOD22.as_bytes()).unwrap().mesh;
    let path = tmp("small.vtu");
    let s = [1.5, 2.5, 3.5, 4.5];
    write_vtu_as(&path, &mesh.to_data(), &[("s", PointField::Scalar(&s))], &[], VtuEncoding::Ascii).unwrap();
    std::fs::read_to_string(path).unwrap()
}

fn vtu_err(text: &str) -> (usize, String) {
    match parse_vtu(text.as_bytes()) {
        Err(IoError::Parse { line, message, .. }) => (line, message),
        other => panic!("expected a Parse error, got {other:?}"),
    }
}

#[test]
fn vtu_missing_points() {
    let t = vtu_text();
    let a = t.find("<Points>").unwrap();
    let b = t.find("</Points>").unwrap() + "</Points>\n".len();
    let cut = format!("{}{}", &t[..a], &t[b..]);
    let (line, msg) = vtu_err(&cut);
    assert!(msg.contains("<Points>"), "{msg}");
    let piece_end = cut.lines().position(|l| l == "</Piece>").unwrap() + 1;
    assert_eq!(line, piece_end);
}

#[test]
fn vtu_too_few_values() {
    let t = vtu_text().replace("1.5 2.5 3.5 4.5", "1.5 2.5 3.5");
    let (line, msg) = vtu_err(&t);
    let at = t.lines().position(|l| l.contains("Name=\"s\"")).unwrap() + 1;
    assert_eq!(line, at);
    assert!(msg.contains("`s`") && msg.contains("expected 4") && msg.contains("found 3"), "{msg}");
    let t = vtu_text().replace("1.5 2.5 3.5 4.5", "1.5 2.5 zz 4.5");
    let (line, msg) = vtu_err(&t);
    assert_eq!(line, at + 1);
    assert!(msg.contains("`zz`"), "{msg}");
    let t = vtu_text().replace(" NumberOfPoints=\"4\"", "");
    let (_, msg) = vtu_err(&t);
    assert!(msg.contains("NumberOfPoints") && msg.contains("<Piece>"), "{msg}");
}

#[test]
fn vtu_inline_base64_binary() {
    // The points of a triangle, Float64, base64 with a UInt32 header, encoded in one run.
    let pts: Vec<f64> = vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.1, 0.7, 0.0];
    let mut raw = ((pts.len() * 8) as u32).to_le_bytes().to_vec();
    pts.iter().for_each(|x| raw.extend(x.to_le_bytes()));
    use base64::Engine as _;
    let enc = base64::engine::general_purpose::STANDARD.encode(&raw);
    let xml = format!(
        r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
<UnstructuredGrid><Piece NumberOfPoints="3" NumberOfCells="1">
<Points><DataArray type="Float64" NumberOfComponents="3" format="binary">{enc}</DataArray></Points>
<Cells><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">3</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">5</DataArray></Cells>
</Piece></UnstructuredGrid></VTKFile>"#
    );
    let d = parse_vtu(xml.as_bytes()).unwrap();
    assert_eq!(d.mesh.coords, vec![0.0, 0.0, 1.0, 0.0, 0.1, 0.7]);
    assert_eq!(d.mesh.cell_vertices, vec![0, 1, 2]);
    assert_eq!(d.to_mesh().unwrap().num_cells(), 1);
}

#[test]
fn mesh_off_the_xy_plane_is_not_planar() {
    // The unit square stood up in the xz plane: x and y alone would give cells of zero area.
    let xz = GOOD22.replace("30 1 1 0", "30 1 0 1").replace("40 0 1 0", "40 0 0 1");
    match parse_msh(xz.as_bytes()) {
        Err(IoError::Unsupported(m)) => assert!(m.contains("not planar"), "{m}"),
        other => panic!("expected a not-planar error, got {other:?}"),
    }
    // One z for every node is a plane: read, z dropped.
    let raised = GOOD22.replace(" 0\n", " 2.5\n");
    assert!(raised.contains("10 0 0 2.5"));
    assert_eq!(parse_msh(raised.as_bytes()).unwrap().mesh.points_2d()[2], DVec2::new(1.0, 1.0));
    // The same check for .vtu points.
    let t = vtu_text();
    let a = t.find("<Points>").unwrap();
    let b = a + t[a..].find("</Points>").unwrap();
    let mut points = t[a..b].to_string();
    // The last point's z, written as `0.0`, becomes 1.
    let last_zero = points.rfind(" 0.0 ").unwrap();
    points.replace_range(last_zero..last_zero + 5, " 1.0 ");
    let tilted = format!("{}{}{}", &t[..a], points, &t[b..]);
    match parse_vtu(tilted.as_bytes()) {
        Err(IoError::Unsupported(m)) => assert!(m.contains("not planar"), "{m}"),
        other => panic!("expected a not-planar error, got {other:?}"),
    }
}
