//! `meshmove_mesh_polyhedron_sizes` and `_get_polyhedron_faces`: the faces of the polyhedral
//! cells of a snappyHexMesh mesh (tests/data/foam) created through
//! `meshmove_mesh_create_from_faces`, in both index bases, are those of the Rust mesh; wrong
//! lengths are refused before anything is written.

use meshmove::capi::*;
use meshmove::io::read_polymesh;
use meshmove::CellType;
use std::path::Path;
use std::ptr::null_mut;

#[path = "common/faces_c.rs"]
mod faces_c;
use faces_c::create_from_faces;

fn polymesh() -> meshmove::FaceMeshData {
    read_polymesh(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/foam/sphere_ascii")).unwrap().faces
}

fn create(f: &meshmove::FaceMeshData) -> *mut meshmove_mesh {
    let nc = f.owner.iter().chain(&f.neighbour).max().unwrap() + 1;
    let (s, m) = create_from_faces(f, 0, nc as i32);
    assert_eq!(s, meshmove_status::Ok);
    m
}

#[test]
fn polyhedron_faces_through_the_c_abi() {
    let f = polymesh();
    let rust = f.to_mesh().unwrap();
    let m = create(&f);
    let (mut nf, mut nfv) = (-1, -1);
    assert_eq!(unsafe { meshmove_mesh_polyhedron_sizes(m, &mut nf, &mut nfv) }, meshmove_status::Ok);
    let nc = rust.num_cells();
    let polyhedra: Vec<usize> = (0..nc).filter(|&c| rust.cell_type(c) == CellType::Polyhedron).collect();
    let want: Vec<Vec<u32>> = polyhedra.iter().flat_map(|&c| rust.polyhedron_faces(c).map(<[u32]>::to_vec)).collect();
    assert!(polyhedra.len() >= 24);
    assert_eq!((nf as usize, nfv as usize), (want.len(), want.iter().map(Vec::len).sum()));
    for base in [0, 1] {
        let (mut cells, mut offsets, mut conn) = (vec![-7; nc + 1], vec![-7; want.len() + 1], vec![-7; nfv as usize]);
        let s = unsafe {
            meshmove_mesh_get_polyhedron_faces(
                m,
                base,
                cells.len() as i32,
                cells.as_mut_ptr(),
                offsets.len() as i32,
                offsets.as_mut_ptr(),
                conn.len() as i32,
                conn.as_mut_ptr(),
            )
        };
        assert_eq!(s, meshmove_status::Ok);
        for c in 0..nc {
            let k = (cells[c + 1] - cells[c]) as usize;
            assert_eq!(k, if polyhedra.contains(&c) { rust.polyhedron_faces(c).len() } else { 0 }, "cell {c}");
        }
        let got: Vec<Vec<u32>> = offsets
            .windows(2)
            .map(|w| conn[w[0] as usize..w[1] as usize].iter().map(|&v| (v - base) as u32).collect())
            .collect();
        assert_eq!(got, want);
    }
    // A wrong length: refused, nothing written.
    let mut cells = vec![-7; nc];
    let s = unsafe {
        meshmove_mesh_get_polyhedron_faces(m, 0, nc as i32, cells.as_mut_ptr(), 0, null_mut(), 0, null_mut())
    };
    assert_eq!(s, meshmove_status::InvalidArgument);
    assert!(cells.iter().all(|&x| x == -7));
    assert_eq!(unsafe { meshmove_mesh_free(m) }, meshmove_status::Ok);
}
