//! Gmsh `.msh` reader (versions 2.2 and 4.1, ASCII and binary) and ASCII 2.2 writer.
//!
//! Our own parser rather than the `mshio` crate: `mshio` reads only MSH 4.1 (we need 2.2, which
//! many solvers' pipelines still write), is built on nom 5, and its errors carry no line number.
//! One small parser for both versions gives one error style: `Parse` with the 1-based line (0 and
//! a byte offset inside binary data) and a message naming the section and what was expected.
//!
//! What is read: `$MeshFormat`, `$PhysicalNames`, `$Entities` (4.1), `$Nodes`, `$Elements`; other
//! sections are skipped. The element types read are lines (1), triangles (2), quadrangles (3),
//! tetrahedra (4), hexahedra (5), prisms (6), pyramids (7) and points (15); any other type is
//! `Unsupported`. The mesh's dimension is that of its highest-dimensional elements: elements of
//! that dimension become cells with their physical tag as region (0 if none), elements one
//! dimension lower (lines in 2D, triangles and quadrangles in 3D) tagged faces with their
//! physical tag as patch (0 if none; in 4.1 the first physical tag of the element's entity), and
//! lower ones (points, lines in 3D) are ignored. Corners are in VTK's order
//! ([`CellType`](crate::geometry::CellType)): Gmsh's order for every type but the prism, whose
//! two triangles are reversed (Gmsh's first triangle faces the second, VTK's wedge's faces away).
//! In 2D, z must be one value for every node a cell uses (else `Unsupported`: the mesh is not
//! planar) and is dropped. Nodes no cell uses are dropped and the rest renumbered in file order;
//! the node tags returned keep each vertex's Gmsh tag. Binary files of either byte order are
//! read (the order is the one that makes the file's check integer equal 1).

mod parser;
mod sections;

use super::{check_data, io_err, IoError};
use crate::geometry::CellType;
use crate::mesh::{Mesh, MeshData};
use parser::Parser;
use std::fmt::Write as _;
use std::path::Path;

/// A mesh read from a Gmsh file.
#[derive(Clone, Debug)]
pub struct MshMesh {
    /// The validated mesh of `data` ([`Mesh::from_data`]).
    pub mesh: Mesh,
    /// The cells, tagged faces and coordinates as read.
    pub data: MeshData,
    /// `(dimension, physical tag, name)` from `$PhysicalNames`, in file order.
    pub physical_names: Vec<(i32, i32, String)>,
    /// Gmsh node tag of each vertex of `mesh`.
    pub node_tags: Vec<usize>,
}

/// What [`parse_msh_data`] returns: the mesh as plain arrays, the `(dimension, physical tag, name)`
/// of `$PhysicalNames` in file order, and the Gmsh node tag of each vertex.
pub type MshParts = (MeshData, Vec<(i32, i32, String)>, Vec<usize>);

/// Reads a Gmsh `.msh` file (2.2 or 4.1, ASCII or binary) and builds its mesh.
pub fn read_msh(path: &Path) -> Result<MshMesh, IoError> {
    let bytes = std::fs::read(path).map_err(io_err(path))?;
    parse_msh(&bytes)
}

/// Parses the contents of a Gmsh `.msh` file (2.2 or 4.1, ASCII or binary) and builds its mesh:
/// [`parse_msh_data`] and [`Mesh::from_data`].
pub fn parse_msh(bytes: &[u8]) -> Result<MshMesh, IoError> {
    let (data, physical_names, node_tags) = parse_msh_data(bytes)?;
    let mesh = Mesh::from_data(&data)?;
    Ok(MshMesh { mesh, data, physical_names, node_tags })
}

/// Reads a Gmsh `.msh` file into plain arrays, without building a [`Mesh`].
pub fn read_msh_data(path: &Path) -> Result<MshParts, IoError> {
    let bytes = std::fs::read(path).map_err(io_err(path))?;
    parse_msh_data(&bytes)
}

/// Parses the contents of a Gmsh `.msh` file into plain arrays, without building a [`Mesh`]
/// (nothing beyond the file's own consistency is checked).
pub fn parse_msh_data(bytes: &[u8]) -> Result<MshParts, IoError> {
    Parser::new(bytes).run()
}

/// Writes `mesh` as an ASCII MSH 2.2 file: [`write_msh22_data`] of [`Mesh::to_data`] (every
/// patch edge a line element, every cell a triangle).
pub fn write_msh22(mesh: &Mesh, path: &Path) -> Result<(), IoError> {
    write_msh22_data(&mesh.to_data(), path)
}

/// Writes `data` as an ASCII MSH 2.2 file: every tagged face as an element (a line in 2D, a
/// triangle or quadrangle in 3D, by its number of vertices) whose physical (and elementary) tag
/// is its patch id, then every cell as the element of its type (prisms in Gmsh's order) whose
/// physical tag is its region (0 without regions). Nodes are numbered from 1 in vertex order, with
/// z = 0 in 2D. Coordinates are written with shortest round-trip formatting, so
/// [`read_msh_data`] gives the same `MeshData` bit for bit when every vertex is a cell's.
pub fn write_msh22_data(data: &MeshData, path: &Path) -> Result<(), IoError> {
    check_data(data, "write_msh22")?;
    // Gmsh's elements have fixed node counts: no polygon or polyhedron.
    if let Some(c) = data.cell_types.iter().position(|t| t.is_general()) {
        let t = data.cell_types[c];
        return Err(IoError::InvalidArgument(format!("write_msh22: cell {c} is a {t}, which Gmsh has no element for")));
    }
    let dim = data.dim;
    let (n, m) = (data.num_vertices(), data.num_cells());
    let mut s = String::with_capacity(64 * (n + m));
    s.push_str("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n");
    let _ = writeln!(s, "{n}");
    for (i, p) in data.coords.chunks_exact(dim).enumerate() {
        let _ = write!(s, "{}", i + 1);
        p.iter().for_each(|x| {
            let _ = write!(s, " {x:?}");
        });
        s.push_str(if dim == 2 { " 0\n" } else { "\n" });
    }
    s.push_str("$EndNodes\n$Elements\n");
    let _ = writeln!(s, "{}", data.num_faces() + m);
    let mut id = 0usize;
    let mut element = |ty: GmshType, tag: i32, corners: &[u32]| {
        id += 1;
        let _ = write!(s, "{id} {} 2 {tag} {tag}", ty.id);
        ty.vtk_order().iter().for_each(|&k| {
            let _ = write!(s, " {}", corners[k] + 1);
        });
        s.push('\n');
    };
    for f in 0..data.num_faces() {
        let face = data.face(f);
        let ty = GmshType::of_face(face.len(), dim).ok_or_else(|| {
            IoError::InvalidArgument(format!(
                "write_msh22: tagged face {f} has {} vertices; a face of a {dim}D mesh has {}",
                face.len(),
                if dim == 2 { "2" } else { "3 or 4" }
            ))
        })?;
        element(ty, data.face_patch[f], face);
    }
    for c in 0..m {
        let region = data.regions.get(c).copied().unwrap_or(0);
        element(GmshType::of_cell(data.cell_types[c]), region, data.cell(c));
    }
    s.push_str("$EndElements\n");
    std::fs::write(path, s).map_err(io_err(path))
}

/// A Gmsh element type that is read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct GmshType {
    /// Gmsh's id.
    id: i32,
    pub(super) nodes: usize,
    /// 0 for points, 1 for lines, ...
    pub(super) dim: usize,
    /// The VTK type of a triangle, a quadrangle or a solid.
    pub(super) cell: Option<CellType>,
    pub(super) name: &'static str,
}

const GMSH_TYPES: [GmshType; 8] = [
    GmshType { id: 1, nodes: 2, dim: 1, cell: None, name: "line" },
    GmshType { id: 2, nodes: 3, dim: 2, cell: Some(CellType::Triangle), name: "triangle" },
    GmshType { id: 3, nodes: 4, dim: 2, cell: Some(CellType::Quad), name: "quadrangle" },
    GmshType { id: 4, nodes: 4, dim: 3, cell: Some(CellType::Tetra), name: "tetrahedron" },
    GmshType { id: 5, nodes: 8, dim: 3, cell: Some(CellType::Hexahedron), name: "hexahedron" },
    GmshType { id: 6, nodes: 6, dim: 3, cell: Some(CellType::Wedge), name: "prism" },
    GmshType { id: 7, nodes: 5, dim: 3, cell: Some(CellType::Pyramid), name: "pyramid" },
    GmshType { id: 15, nodes: 1, dim: 0, cell: None, name: "point" },
];

impl GmshType {
    pub(super) fn from_id(id: i32) -> Option<GmshType> {
        GMSH_TYPES.into_iter().find(|t| t.id == id)
    }

    fn of_cell(t: CellType) -> GmshType {
        GMSH_TYPES.into_iter().find(|g| g.cell == Some(t) && g.dim == t.dim()).expect("every cell type has a Gmsh type")
    }

    /// The element of a tagged face of `vertices` vertices in a `dim`-dimensional mesh.
    fn of_face(vertices: usize, dim: usize) -> Option<GmshType> {
        GMSH_TYPES.into_iter().find(|g| g.dim + 1 == dim && g.nodes == vertices)
    }

    /// `vtk_order()[k]`: the Gmsh node that is VTK corner `k`. The prism's two triangles are
    /// reversed (corners 1 and 2, 4 and 5 swapped); the permutation is its own inverse, so it
    /// also gives the Gmsh node `k` of VTK's corners.
    pub(super) fn vtk_order(self) -> &'static [usize] {
        const IDENTITY: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
        match self.cell {
            Some(CellType::Wedge) => &[0, 2, 1, 3, 5, 4],
            _ => &IDENTITY[..self.nodes],
        }
    }
}
