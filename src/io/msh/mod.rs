//! Gmsh `.msh` reader (versions 2.2 and 4.1, ASCII and binary) and ASCII 2.2 writer.
//!
//! Our own parser rather than the `mshio` crate: `mshio` reads only MSH 4.1 (we need 2.2, which
//! many solvers' pipelines still write), is built on nom 5, and its errors carry no line number.
//! One small parser for both versions gives one error style: `Parse` with the 1-based line (0 and
//! a byte offset inside binary data) and a message naming the section and what was expected.
//!
//! What is read: `$MeshFormat`, `$PhysicalNames`, `$Entities` (4.1), `$Nodes`, `$Elements`; other
//! sections are skipped. Triangles (type 2) become cells with their physical tag as region (0 if
//! none), lines (type 1) tagged edges with their physical tag as patch (0 if none; in 4.1 the
//! first physical tag of the line's curve entity), points (type 15) are ignored, any other type
//! is `Unsupported`. z must be one value for every node a triangle uses (else `Unsupported`: the
//! mesh is not planar) and is dropped. Nodes no triangle uses are dropped and the rest renumbered in
//! file order; `MshMesh::node_tags` keeps each vertex's Gmsh tag. Binary files of either byte
//! order are read (the order is the one that makes the file's check integer equal 1).

mod parser;
mod sections;

use super::{io_err, IoError};
use crate::mesh::Mesh;
use parser::Parser;
use std::fmt::Write as _;
use std::path::Path;

/// A mesh read from a Gmsh file.
#[derive(Clone, Debug)]
pub struct MshMesh {
    pub mesh: Mesh,
    /// `(dimension, physical tag, name)` from `$PhysicalNames`, in file order.
    pub physical_names: Vec<(i32, i32, String)>,
    /// Gmsh node tag of each vertex of `mesh`.
    pub node_tags: Vec<usize>,
}

/// Reads a Gmsh `.msh` file (2.2 or 4.1, ASCII or binary).
pub fn read_msh(path: &Path) -> Result<MshMesh, IoError> {
    let bytes = std::fs::read(path).map_err(io_err(path))?;
    parse_msh(&bytes)
}

/// Parses the contents of a Gmsh `.msh` file (2.2 or 4.1, ASCII or binary).
pub fn parse_msh(bytes: &[u8]) -> Result<MshMesh, IoError> {
    Parser::new(bytes).run()
}

/// Writes `mesh` as an ASCII MSH 2.2 file: every patch edge as a line element whose physical
/// (and elementary) tag is its patch id, every cell as a triangle whose physical tag is its
/// region. Coordinates are written with shortest round-trip formatting, so `read_msh` gives the
/// same coordinates bit for bit.
pub fn write_msh22(mesh: &Mesh, path: &Path) -> Result<(), IoError> {
    let mut s = String::with_capacity(64 * (mesh.num_vertices() + mesh.num_cells()));
    s.push_str("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n");
    let _ = writeln!(s, "{}", mesh.num_vertices());
    for i in 0..mesh.num_vertices() {
        let p = mesh.point(i);
        let _ = writeln!(s, "{} {:?} {:?} 0", i + 1, p[0], p[1]);
    }
    s.push_str("$EndNodes\n$Elements\n");
    let _ = writeln!(s, "{}", mesh.num_patch_faces() + mesh.num_cells());
    let mut id = 0usize;
    for e in mesh.patch_faces() {
        id += 1;
        let [a, b] = [e.vertices[0], e.vertices[1]];
        let _ = writeln!(s, "{id} 1 2 {} {} {} {}", e.patch, e.patch, a + 1, b + 1);
    }
    for (k, r) in mesh.regions().iter().enumerate() {
        let c = mesh.cell(k);
        id += 1;
        let _ = writeln!(s, "{id} 2 2 {r} {r} {} {} {}", c[0] + 1, c[1] + 1, c[2] + 1);
    }
    s.push_str("$EndElements\n");
    std::fs::write(path, s).map_err(io_err(path))
}
