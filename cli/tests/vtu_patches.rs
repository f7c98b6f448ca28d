//! A `.vtu` carries patches as its boundary cells: meshio's default export of a Gmsh mesh (the
//! unit cube minus a sphere: tetrahedra, boundary triangles, cell data `gmsh:physical`) reads as
//! the same mesh, faces and patches as the `.msh` it came from, and `meshmove deform` moves it to
//! bitwise the same coordinates with the walls sliding and the sphere clamped and moved.

use meshmove::io::{parse_vtu, read_msh, read_vtu, write_vtu};
use std::path::{Path, PathBuf};
use std::process::Command;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data").join(name)
}

#[test]
fn meshio_export_reads_as_the_msh_with_its_patches() {
    let msh = read_msh(&data("box_sphere.msh")).unwrap();
    let vtu = read_vtu(&data("box_sphere.vtu")).unwrap();
    let (a, b) = (&msh.data, &vtu.mesh);
    assert_eq!((b.dim, b.num_vertices(), b.num_cells(), b.num_faces()), (3, 510, 1739, 830));
    assert_eq!(
        a.coords.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        b.coords.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
    assert_eq!((&a.cell_types, &a.cell_offsets, &a.cell_vertices), (&b.cell_types, &b.cell_offsets, &b.cell_vertices));
    assert_eq!((&a.face_offsets, &a.face_vertices, &a.face_patch), (&b.face_offsets, &b.face_vertices, &b.face_patch));
    // The tetrahedra's region is their physical tag, as from the .msh.
    assert!(b.regions.iter().all(|&r| r == 10) && a.regions == b.regions);
    // 6 × 118 wall triangles on patch 1, 122 on the sphere (patch 2).
    assert_eq!(b.face_patch.iter().filter(|&&p| p == 1).count(), 708);
    assert_eq!(b.face_patch.iter().filter(|&&p| p == 2).count(), 122);
    // The cell arrays keep the tetrahedra's values only.
    let (_, phys, _) = vtu.cell_data.iter().find(|f| f.0 == "gmsh:physical").unwrap();
    assert_eq!(phys.len(), 1739);
    let mesh = vtu.to_mesh().unwrap();
    let mut ids = mesh.patch_ids();
    ids.sort_unstable();
    assert_eq!(ids, vec![1, 2]);
}

#[test]
fn deform_of_the_vtu_equals_deform_of_the_msh_bitwise() {
    let dir = std::env::temp_dir().join(format!("meshmove-vtu-patches-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let case = dir.join("case.toml");
    std::fs::write(
        &case,
        "steps = 2\n\n[[patch]]\npatch = 1\nkind = \"slip\"\n\n[[patch]]\npatch = 2\nkind = \"clamped\"\n\n\
         [[motion]]\npatch = 2\ntranslation = [0.08, 0.0, 0.04]\nrotation_deg = 20\naxis = [0, 0, 1]\n\
         center = [0.5, 0.5, 0.5]\n",
    )
    .unwrap();
    let mut moved = Vec::new();
    for mesh in ["box_sphere.msh", "box_sphere.vtu"] {
        let out = dir.join(format!("{mesh}.out.vtu"));
        let run = Command::new(env!("CARGO_BIN_EXE_meshmove"))
            .arg("deform")
            .arg(data(mesh))
            .arg("--config")
            .arg(&case)
            .arg("-o")
            .arg(&out)
            .output()
            .expect("meshmove runs");
        assert!(run.status.success(), "{mesh}: {}", String::from_utf8_lossy(&run.stderr));
        moved.push(read_vtu(&out).unwrap());
    }
    let bits = |d: &meshmove::io::VtuData| d.mesh.coords.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&moved[0]), bits(&moved[1]));
    // The sphere moved: its centre vertex-free, so check a sphere vertex's displacement.
    let m = &moved[1].mesh;
    let (_, disp, _) = moved[1].point_data.iter().find(|f| f.0 == "displacement").unwrap();
    let v = m.face(m.face_patch.iter().position(|&p| p == 2).unwrap())[0] as usize;
    assert!(disp[3 * v].abs() + disp[3 * v + 1].abs() > 0.01, "{:?}", &disp[3 * v..3 * v + 3]);
    // The output carries the patches back: written faces with their ids.
    assert_eq!(m.num_faces(), 830);
    assert_eq!(m.face_patch.iter().filter(|&&p| p == 2).count(), 122);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn written_patches_and_field_data_names_read_back() {
    let vtu = read_vtu(&data("box_sphere.vtu")).unwrap();
    let path = std::env::temp_dir().join(format!("meshmove-vtu-roundtrip-{}.vtu", std::process::id()));
    write_vtu(&path, &vtu.mesh, &[], &[]).unwrap();
    let back = read_vtu(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    assert_eq!(back.mesh, vtu.mesh);
    // A 2D piece: two triangles, three boundary lines with CellEntityIds, names as field data
    // (id and dimension 1); a vertex cell is skipped.
    let xml = r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">
<UnstructuredGrid>
<FieldData>
<DataArray type="Int32" Name="inlet" NumberOfTuples="2" format="ascii">4 1</DataArray>
<DataArray type="Int32" Name="bulk" NumberOfTuples="2" format="ascii">7 2</DataArray>
</FieldData>
<Piece NumberOfPoints="4" NumberOfCells="6">
<CellData>
<DataArray type="Int32" Name="CellEntityIds" format="ascii">7 7 4 5 5 0</DataArray>
</CellData>
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 1 1 0 0 1 0</DataArray></Points>
<Cells>
<DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 0 2 3 0 1 1 2 2 3 3</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">3 6 8 10 12 13</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">5 5 3 3 3 1</DataArray>
</Cells>
</Piece>
</UnstructuredGrid>
</VTKFile>
"#;
    let d = parse_vtu(xml.as_bytes()).unwrap();
    assert_eq!((d.mesh.dim, d.mesh.num_cells(), d.mesh.num_faces()), (2, 2, 3));
    assert_eq!(d.mesh.face_patch, vec![4, 5, 5]);
    assert_eq!(d.mesh.regions, vec![7, 7]);
    assert_eq!(d.patch_names, vec![(4, "inlet".to_string())]);
    assert_eq!(d.cell_data[0].1, vec![7.0, 7.0]);
}
