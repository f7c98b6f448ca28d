//! Tests of every cell type through both formats: quads and mixed 2D meshes, 3D solids, and the
//! files VTK and Gmsh write (`tests/data/gen_vtk_fixtures.py`, `tests/data/gen_fixtures.sh`).

use super::tests::{data, tmp};
use super::vtu::signed_measure;
use super::*;
use crate::geometry::CellType;
use crate::mesh::fixtures::quads as structured_quads;
use crate::mesh::MeshData;
use std::f64::consts::PI;

/// A mesh of `cells` (type, corners, region) on the points `coords` (`dim` values each).
fn mesh_of(dim: usize, coords: &[f64], cells: &[(CellType, &[u32], i32)]) -> MeshData {
    let mut d = MeshData::new(dim);
    coords.chunks_exact(dim).for_each(|p| {
        d.push_vertex(p);
    });
    cells.iter().for_each(|&(t, v, r)| d.push_cell(t, v, r));
    d
}

/// Coordinates with full 53-bit mantissas (an affine map of positive scale: orientations kept).
fn scramble(d: &mut MeshData) {
    d.coords.iter_mut().for_each(|x| *x = (*x + 0.1) * PI / 3.0);
}

fn assert_bitwise(a: &MeshData, b: &MeshData) {
    assert_eq!(a, b);
    let bits = |d: &MeshData| d.coords.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(a), bits(b));
}

/// Writes `d` as .msh 2.2 and reads it back.
fn through_msh(d: &MeshData, name: &str) -> MeshData {
    let path = tmp(name);
    write_msh22_data(d, &path).unwrap();
    let (back, names, tags) = read_msh_data(&path).unwrap();
    assert!(names.is_empty());
    assert_eq!(tags, (1..=d.num_vertices()).collect::<Vec<_>>());
    back
}

/// Writes `d` as .vtu (its regions as the cell field `region`) and reads it back.
fn through_vtu(d: &MeshData, name: &str) -> MeshData {
    let path = tmp(name);
    let cell_data = match d.regions.is_empty() {
        true => vec![],
        false => vec![("region", CellField::I32(&d.regions))],
    };
    write_vtu(&path, d, &[], &cell_data).unwrap();
    read_vtu(&path).unwrap().mesh
}

/// 3 × 2 quads on [0, 1.5] × [−1, 0.25], every other one split into two triangles (region 5),
/// the quads in region 0.
fn mixed_2d() -> MeshData {
    let q = structured_quads(3, 2, [0.0, 1.5, -1.0, 0.25]);
    let mut d = MeshData { cell_types: Vec::new(), cell_offsets: vec![0], cell_vertices: Vec::new(), ..q.clone() };
    for c in 0..q.num_cells() {
        let &[a, b, e, f] = q.cell(c) else { unreachable!() };
        if c % 2 == 0 {
            d.push_cell(CellType::Triangle, &[a, b, e], 5);
            d.push_cell(CellType::Triangle, &[a, e, f], 5);
        } else {
            d.push_cell(CellType::Quad, &[a, b, e, f], 0);
        }
    }
    d
}

#[test]
fn quad_and_mixed_2d_meshes_round_trip() {
    let mut quads = structured_quads(3, 2, [0.0, 1.5, -1.0, 0.25]);
    scramble(&mut quads);
    quads.regions = (0..quads.num_cells() as i32).map(|c| c % 3 - 1).collect();
    let mut mixed = mixed_2d();
    scramble(&mut mixed);
    assert_eq!(mixed.num_cells(), 9);
    for (d, name) in [(&quads, "quads"), (&mixed, "mixed")] {
        assert_bitwise(&through_msh(d, &format!("{name}.msh")), d);
        assert_bitwise(&through_vtu(d, &format!("{name}.vtu")), d);
    }
    // A mesh without regions keeps none.
    let plain = structured_quads(2, 2, [0.0, 1.0, 0.0, 1.0]);
    assert_eq!(through_msh(&plain, "plain.msh"), plain);
    assert_eq!(through_vtu(&plain, "plain.vtu"), plain);
}

/// A unit cube (hexahedron), a pyramid on its top, a wedge on its x = 1 side and a tetrahedron
/// on its x = 0 side, regions 1 to 4: the mesh of `gen_vtk_fixtures.py`.
fn solids() -> MeshData {
    #[rustfmt::skip]
    let coords = [
        0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.,
        0., 0., 1., 1., 0., 1., 1., 1., 1., 0., 1., 1.,
        0.5, 0.5, 1.5, 2., 0., 0., 2., 1., 0., -1., 0., 0.,
    ];
    mesh_of(
        3,
        &coords,
        &[
            (CellType::Hexahedron, &[0, 1, 2, 3, 4, 5, 6, 7], 1),
            (CellType::Pyramid, &[4, 5, 6, 7, 8], 2),
            (CellType::Wedge, &[1, 9, 5, 2, 10, 6], 3),
            (CellType::Tetra, &[0, 4, 3, 11], 4),
        ],
    )
}

fn assert_positive_volumes(d: &MeshData) {
    for c in 0..d.num_cells() {
        assert!(signed_measure(d, c) > 0.0, "cell {c} ({}) has volume {}", d.cell_types[c], signed_measure(d, c));
    }
}

#[test]
fn solids_round_trip() {
    let mut d = solids();
    assert_positive_volumes(&d);
    let volumes: Vec<f64> = (0..4).map(|c| signed_measure(&d, c)).collect();
    assert!(volumes.iter().zip([1.0, 1.0 / 6.0, 0.5, 1.0 / 6.0]).all(|(a, b)| (a - b).abs() < 1e-15), "{volumes:?}");
    d.push_face(&[0, 3, 2, 1], 1);
    d.push_face(&[4, 5, 8], 2);
    d.push_face(&[9, 10, 6, 5], 3);
    d.push_face(&[0, 11, 4], 3);
    scramble(&mut d);
    assert_positive_volumes(&d);
    assert_bitwise(&through_msh(&d, "solids.msh"), &d);
    assert_bitwise(&through_vtu(&d, "solids.vtu"), &d);
    // The wedge is written as a Gmsh prism: its two triangles reversed.
    let text = std::fs::read_to_string(tmp("solids.msh")).unwrap();
    assert!(text.contains("\n7 6 2 3 3 2 6 10 3 7 11\n"), "{text}");
    assert!(text.contains("\n1 3 2 1 1 1 4 3 2\n") && text.contains("\n2 2 2 2 2 5 6 9\n"), "{text}");
    // The core builds the 3D mesh of mixed solids.
    let m = parse_msh(text.as_bytes()).unwrap().mesh;
    assert_eq!((m.dim(), m.num_cells()), (3, d.num_cells()));
}

#[test]
fn deformed_solids_fields() {
    let d = solids();
    let n = d.num_vertices();
    // Stretched by 2 in z: every volume doubles; then the pyramid's apex pushed through its base.
    let mut disp: Vec<f64> = d.coords.chunks_exact(3).flat_map(|p| [0.0, 0.0, p[2]]).collect();
    let path = tmp("solids_def.vtu");
    write_deformed_data(&path, &d, &disp).unwrap();
    let back = read_vtu(&path).unwrap();
    let get = |v: &VtuData, name: &str| v.cell_data.iter().find(|x| x.0 == name).unwrap().1.clone();
    assert!(get(&back, "volume_ratio").iter().all(|&r| (r - 2.0).abs() < 1e-12));
    assert_eq!(get(&back, "inverted"), vec![0.0; 4]);
    assert_eq!(get(&back, "region"), vec![1.0, 2.0, 3.0, 4.0]);
    // Smallest face corner angles: the cube stretched in z stays right-angled; the others less.
    let angles = get(&back, "min_angle");
    assert!((angles[0] - 90.0).abs() < 1e-9 && angles[1..].iter().all(|&a| a > 0.0 && a < 90.0), "{angles:?}");
    assert_eq!(back.mesh.regions, vec![1, 2, 3, 4]);
    assert_eq!(back.point_data[0].1, disp);
    disp[3 * 8 + 2] = -2.0;
    write_deformed_data(&path, &d, &disp).unwrap();
    let back = read_vtu(&path).unwrap();
    assert_eq!(get(&back, "inverted"), vec![0.0, 1.0, 0.0, 0.0]);
    assert_eq!(get(&back, "min_angle")[1], 0.0);
    assert!(matches!(write_deformed_data(&path, &d, &disp[..3 * n - 1]), Err(IoError::InvalidArgument(_))));
}

/// Gmsh's reference prism (positive volume in Gmsh's convention), a triangle face on it, a line
/// and a point (ignored in 3D).
const PRISM22: &str = "$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
6
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 1 0 1
6 0 1 1
$EndNodes
$Elements
4
1 15 2 0 1 1
2 1 2 9 9 1 2
3 2 2 7 7 1 2 3
4 6 2 3 3 1 2 3 4 5 6
$EndElements
";

#[test]
fn gmsh_prism_is_a_positive_vtk_wedge() {
    let (d, _, tags) = parse_msh_data(PRISM22.as_bytes()).unwrap();
    assert_eq!(d.dim, 3);
    assert_eq!(tags, vec![1, 2, 3, 4, 5, 6]);
    assert_eq!(d.cell_types, vec![CellType::Wedge]);
    assert_eq!(d.cell(0), &[0, 2, 1, 3, 5, 4]);
    assert_eq!(d.regions, vec![3]);
    assert_eq!((d.face(0), d.face_patch.as_slice()), (&[0, 1, 2][..], &[7][..]));
    assert_eq!(d.num_faces(), 1);
    assert_eq!(signed_measure(&d, 0), 0.5);
    // Written back in Gmsh's order.
    let path = tmp("prism.msh");
    write_msh22_data(&d, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\n1 2 2 7 7 1 2 3\n2 6 2 3 3 1 2 3 4 5 6\n"), "{text}");
}

#[test]
fn gmsh_41_box_of_tetrahedra() {
    let (d, names, tags) = read_msh_data(&data("box_tets_41.msh")).unwrap();
    assert_eq!(d.dim, 3);
    assert_eq!(tags.len(), d.num_vertices());
    assert!(d.num_cells() > 20 && d.cell_types.iter().all(|&t| t == CellType::Tetra));
    assert!(d.regions.iter().all(|&r| r == 10) && d.regions.len() == d.num_cells());
    assert_eq!(names, vec![(2, 1, "bottom".to_string()), (2, 2, "top".to_string()), (3, 10, "solid".to_string())]);
    assert_positive_volumes(&d);
    let volume: f64 = (0..d.num_cells()).map(|c| signed_measure(&d, c)).sum();
    assert!((volume - 1.0).abs() < 1e-12, "{volume}");
    assert_patches(&d, &[(1, 0.0), (2, 1.0)]);
    let m = read_msh(&data("box_tets_41.msh")).unwrap().mesh;
    assert_eq!((m.dim(), m.num_cells()), (3, d.num_cells()));
    assert_eq!(m.patch_ids(), vec![0, 1, 2]);
}

/// Tagged faces on patches `(patch, z)` only, each lying in its plane z and covering the unit
/// square there.
fn assert_patches(d: &MeshData, planes: &[(i32, f64)]) {
    for &(patch, z) in planes {
        let faces: Vec<usize> = (0..d.num_faces()).filter(|&f| d.face_patch[f] == patch).collect();
        assert!(faces.iter().all(|&f| d.face(f).iter().all(|&v| d.point(v as usize)[2] == z)), "patch {patch}");
        let area: f64 = faces
            .iter()
            .map(|&f| {
                let v = d.face(f);
                let p = |k: usize| d.point(v[k] as usize);
                (1..v.len() - 1)
                    .map(|k| {
                        let (a, b, c) = (p(0), p(k), p(k + 1));
                        0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs()
                    })
                    .sum::<f64>()
            })
            .sum();
        assert!((area - 1.0).abs() < 1e-12, "patch {patch}: area {area}");
    }
    let count: usize = planes.iter().map(|&(p, _)| d.face_patch.iter().filter(|&&q| q == p).count()).sum();
    assert_eq!(count, d.num_faces());
}

#[test]
fn gmsh_prism_layers_41_binary_and_22() {
    let (a, names, _) = read_msh_data(&data("slab_prisms_41_bin.msh")).unwrap();
    let (b, _, _) = read_msh_data(&data("slab_prisms_22.msh")).unwrap();
    assert_eq!(names, vec![(2, 1, "bottom".to_string()), (2, 2, "top".to_string()), (3, 7, "slab".to_string())]);
    for d in [&a, &b] {
        assert!(d.cell_types.iter().all(|&t| t == CellType::Wedge) && d.num_cells() >= 8);
        assert!(d.regions.iter().all(|&r| r == 7));
        assert_positive_volumes(d);
        let volume: f64 = (0..d.num_cells()).map(|c| signed_measure(d, c)).sum();
        assert!((volume - 0.5).abs() < 1e-12, "{volume}");
        assert_patches(d, &[(1, 0.0), (2, 0.5)]);
        assert!((0..d.num_faces()).all(|f| d.face(f).len() == 3));
    }
    assert_eq!(
        (&a.cell_types, &a.cell_vertices, &a.face_vertices, &a.face_patch),
        (&b.cell_types, &b.cell_vertices, &b.face_vertices, &b.face_patch)
    );
    assert!(a.coords.iter().zip(&b.coords).all(|(x, y)| (x - y).abs() <= 1e-15));
}

/// The mesh of `gen_vtk_fixtures.py`'s `quad`: 2 × 2 unit quads, regions 1 to 4.
fn vtk_quads() -> MeshData {
    let coords: Vec<f64> = (0..9).flat_map(|v| [(v % 3) as f64, (v / 3) as f64]).collect();
    let q = |i: u32, j: u32| [3 * j + i, 3 * j + i + 1, 3 * j + i + 4, 3 * j + i + 3];
    let (a, b, c, e) = (q(0, 0), q(1, 0), q(0, 1), q(1, 1));
    let quad = CellType::Quad;
    mesh_of(2, &coords, &[(quad, &a, 1), (quad, &b, 2), (quad, &c, 3), (quad, &e, 4)])
}

#[test]
fn vtk_written_files_read() {
    for (file, mesh, field, comps) in [
        ("quad_appended.vtu", vtk_quads(), "u", 2),
        ("quad_binary.vtu", vtk_quads(), "u", 2),
        ("mixed3d_appended.vtu", solids(), "displacement", 3),
        ("mixed3d_binary.vtu", solids(), "displacement", 3),
        ("mixed3d_raw.vtu", solids(), "displacement", 3),
        ("mixed3d_base64.vtu", solids(), "displacement", 3),
    ] {
        let d = read_vtu(&data(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(d.mesh, mesh, "{file}");
        let n = mesh.num_vertices();
        let values: Vec<f64> = (0..n).flat_map(|i| (0..comps).map(move |k| 0.5 * i as f64 + 0.25 * k as f64)).collect();
        assert_eq!(d.point_data, vec![(field.to_string(), values, comps)], "{file}");
        assert_eq!(d.cell_data, vec![("region".to_string(), vec![1.0, 2.0, 3.0, 4.0], 1)], "{file}");
    }
}

fn replace_bytes(b: &[u8], from: &str, to: &str) -> Vec<u8> {
    let at = b.windows(from.len()).position(|w| w == from.as_bytes()).unwrap_or_else(|| panic!("no `{from}`"));
    [&b[..at], to.as_bytes(), &b[at + from.len()..]].concat()
}

#[test]
fn vtu_compressed_and_appended_errors() {
    let file = std::fs::read(data("mixed3d_appended.vtu")).unwrap();
    // A byte of the first array's zlib stream (after its 4-integer UInt32 header) changed.
    let tag = file.windows(13).position(|w| w == b"<AppendedData").unwrap();
    let start = tag + file[tag..].iter().position(|&c| c == b'_').unwrap() + 1;
    let mut bad = file.clone();
    bad[start + 16 + 5] ^= 0x55;
    match parse_vtu(&bad) {
        Err(IoError::Parse { line: 0, offset: Some(o), message }) => {
            assert_eq!(o, start);
            assert!(
                message.contains("DataArray `displacement` in <PointData>") && message.contains("block 0"),
                "{message}"
            )
        }
        other => panic!("{other:?}"),
    }
    let lz4 = replace_bytes(&file, "vtkZLibDataCompressor", "vtkLZ4DataCompressor");
    assert!(matches!(parse_vtu(&lz4), Err(IoError::Unsupported(m)) if m.contains("vtkLZ4DataCompressor")));
    let no_offset = replace_bytes(&file, "offset=\"0\"", "");
    match parse_vtu(&no_offset) {
        Err(IoError::Parse { line: 5, message, .. }) => {
            assert!(message.contains("`displacement`") && message.contains("offset"), "{message}")
        }
        other => panic!("{other:?}"),
    }
    let encoding = replace_bytes(&file, "encoding=\"raw\"", "encoding=\"hex\"");
    assert!(matches!(parse_vtu(&encoding), Err(IoError::Parse { message, .. }) if message.contains("`encoding`")));
    // Cut inside the appended data.
    match parse_vtu(&file[..start + 300]) {
        Err(IoError::Parse { line: 0, message, .. }) => assert!(message.contains("DataArray"), "{message}"),
        other => panic!("{other:?}"),
    }
}

/// A small .vtu whose connectivity, offsets and types are `cells`.
fn cells_vtu(points: usize, conn: &str, offsets: &str, types: &str) -> String {
    let xyz: String = (0..points).map(|i| format!("{} {} {} ", i % 2, i / 2 % 2, i / 4)).collect();
    format!(
        r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">
<UnstructuredGrid><Piece NumberOfPoints="{points}" NumberOfCells="{}">
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">{xyz}</DataArray></Points>
<Cells><DataArray type="Int64" Name="connectivity" format="ascii">{conn}</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">{offsets}</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">{types}</DataArray></Cells>
</Piece></UnstructuredGrid></VTKFile>"#,
        types.split_whitespace().count()
    )
}

#[test]
fn vtu_cell_errors() {
    let ok = cells_vtu(4, "0 1 3 2", "4", "9");
    assert_eq!(parse_vtu(ok.as_bytes()).unwrap().mesh.cell_types, vec![CellType::Quad]);
    let polygon = cells_vtu(4, "0 1 3 2", "4", "7");
    assert_eq!(parse_vtu(polygon.as_bytes()).unwrap().mesh.cell_types, vec![CellType::Polygon]);
    let pixel = cells_vtu(4, "0 1 3 2", "4", "8");
    assert!(matches!(parse_vtu(pixel.as_bytes()), Err(IoError::Unsupported(m)) if m.contains("VTK cell type 8")));
    // A polyhedron needs its faces.
    let polyhedron = cells_vtu(8, "0 1 2 3 4 5 6 7", "8", "42");
    assert!(
        matches!(parse_vtu(polyhedron.as_bytes()), Err(IoError::Parse { message, .. }) if message.contains("faceoffsets"))
    );
    let (line, msg) = match parse_vtu(cells_vtu(4, "0 1 3 2", "3", "9").as_bytes()) {
        Err(IoError::Parse { line, message, .. }) => (line, message),
        other => panic!("{other:?}"),
    };
    assert_eq!(line, 5);
    assert!(msg.contains("`offsets`") && msg.contains("expected 4") && msg.contains("quad"), "{msg}");
    let short = cells_vtu(4, "0 1 3", "4", "9");
    assert!(
        matches!(parse_vtu(short.as_bytes()), Err(IoError::Parse { message, .. }) if message.contains("`connectivity`"))
    );
    // A triangle among tetrahedra is a face (on patch 0: no id array).
    let mixed = parse_vtu(cells_vtu(8, "0 1 2 4 1 2 3", "4 7", "10 5").as_bytes()).unwrap();
    assert_eq!(
        (mixed.mesh.num_cells(), mixed.mesh.face_vertices.clone(), mixed.mesh.face_patch),
        (1, vec![1, 2, 3], vec![0])
    );
    // 3D points of 2D cells off a plane are not planar; of a 3D cell they are kept.
    let tilted = cells_vtu(8, "0 1 3 5", "4", "9");
    assert!(matches!(parse_vtu(tilted.as_bytes()), Err(IoError::Unsupported(m)) if m.contains("not planar")));
    let tet = parse_vtu(cells_vtu(8, "0 1 2 4", "4", "10").as_bytes()).unwrap();
    assert_eq!((tet.mesh.dim, tet.mesh.coords.len()), (3, 24));
}

/// The base64 of `raw` compressed as one zlib block with a UInt32 header, the header and the
/// data encoded as one run or as two (what meshio and VTK write).
fn zlib_base64(raw: &[u8], runs: usize) -> String {
    use base64::Engine as _;
    use std::io::Write as _;
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    z.write_all(raw).unwrap();
    let packed = z.finish().unwrap();
    let n = raw.len() as u32;
    let header: Vec<u8> = [1, n, n, packed.len() as u32].iter().flat_map(|x| x.to_le_bytes()).collect();
    let b64 = base64::engine::general_purpose::STANDARD;
    match runs {
        1 => b64.encode([header, packed].concat()),
        _ => b64.encode(header) + &b64.encode(packed),
    }
}

#[test]
fn vtu_inline_zlib_one_or_two_runs() {
    let pts: Vec<u8> = [0.0f64, 0.0, 0.0, 1.0, 0.0, 0.0, 0.1, 0.7, 0.0].iter().flat_map(|x| x.to_le_bytes()).collect();
    let conn: Vec<u8> = [0i32, 1, 2].iter().flat_map(|x| x.to_le_bytes()).collect();
    for runs in [1, 2] {
        let xml = format!(
            r#"<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian" header_type="UInt32" compressor="vtkZLibDataCompressor">
<UnstructuredGrid><Piece NumberOfPoints="3" NumberOfCells="1">
<Points><DataArray type="Float32" Name="x" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0.1 0.7 0</DataArray>
</Points><PointData><DataArray type="Float64" Name="p" NumberOfComponents="3" format="binary">{}</DataArray></PointData>
<Cells><DataArray type="Int32" Name="connectivity" format="binary">
  {}
</DataArray><DataArray type="Int64" Name="offsets" format="ascii">3</DataArray>
<DataArray type="UInt8" Name="types" format="binary">{}</DataArray></Cells>
</Piece></UnstructuredGrid></VTKFile>"#,
            zlib_base64(&pts, runs),
            zlib_base64(&conn, runs),
            zlib_base64(&[5], runs),
        );
        let d = parse_vtu(xml.as_bytes()).unwrap_or_else(|e| panic!("{runs} runs: {e}"));
        assert_eq!(d.mesh.cell_vertices, vec![0, 1, 2]);
        assert_eq!(d.mesh.cell_types, vec![CellType::Triangle]);
        assert_eq!(d.point_data[0].1, vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.1, 0.7, 0.0]);
    }
}

#[test]
fn writers_reject_inconsistent_data() {
    let mut d = structured_quads(1, 1, [0.0, 1.0, 0.0, 1.0]);
    d.push_face(&[0, 1, 2], 9);
    let path = tmp("bad.msh");
    assert!(matches!(write_msh22_data(&d, &path), Err(IoError::InvalidArgument(m)) if m.contains("3 vertices")));
    let mut d = structured_quads(1, 1, [0.0, 1.0, 0.0, 1.0]);
    d.cell_types[0] = CellType::Triangle;
    assert!(matches!(write_vtu(&path, &d, &[], &[]), Err(IoError::InvalidArgument(m)) if m.contains("cell 0")));
    let d = structured_quads(1, 1, [0.0, 1.0, 0.0, 1.0]);
    let v = [0.0; 8];
    assert!(matches!(
        write_vtu(&path, &d, &[("v", PointField::Vector(&v, 3))], &[]),
        Err(IoError::InvalidArgument(m)) if m.contains("`v`")
    ));
}
