//! The cell types, in VTK's numbering, and their reference tables: corners, edges and faces in
//! the local numbering of VTK (and of most FV codes' cell-to-vertex lists).

/// A cell type. The discriminant is VTK's cell type id.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum CellType {
    /// Three corners, counter-clockwise (2D).
    Triangle = 5,
    /// Four corners, counter-clockwise (2D), bilinear.
    Quad = 9,
    /// Four corners; corner 3 on the side where (1 − 0) × (2 − 0) points (3D).
    Tetra = 10,
    /// Eight corners: 0–3 the bottom face counter-clockwise seen from the top 4–7 (3D).
    Hexahedron = 12,
    /// Six corners: triangle 0–1–2, whose right-hand normal points away from triangle 3–4–5 (3D).
    Wedge = 13,
    /// Five corners: quad 0–1–2–3, whose right-hand normal points to the apex 4 (3D).
    Pyramid = 14,
    /// A polygon of three or more corners, counter-clockwise (2D): a general cell whose element
    /// is a fan of triangles around its corners' average (docs/DESIGN.md §2).
    Polygon = 7,
    /// A polyhedron given by its faces (3D): its corners are its distinct vertices, its faces are
    /// listed per cell (`MeshData::polyhedron_faces`); a general cell whose element is a set of
    /// tetrahedra through its face centres and its centre (docs/DESIGN.md §2).
    Polyhedron = 42,
}

/// The most corners a cell of any type has (a hexahedron's).
pub const MAX_CORNERS: usize = 8;

impl CellType {
    /// Every cell type of a fixed corner count (and fixed tables), in VTK id order.
    pub const ALL: [CellType; 6] =
        [CellType::Triangle, CellType::Quad, CellType::Tetra, CellType::Hexahedron, CellType::Wedge, CellType::Pyramid];

    /// The general cell types: their corners and faces are listed per cell.
    pub const GENERAL: [CellType; 2] = [CellType::Polygon, CellType::Polyhedron];

    /// The fixed type of a VTK cell type id, or None for a type meshmove does not handle or a
    /// general type (see [`CellType::general_from_vtk`]).
    pub fn from_vtk(id: i64) -> Option<CellType> {
        CellType::ALL.into_iter().find(|t| *t as i64 == id)
    }

    /// The type of a VTK cell type id, the general types (polygon 7, polyhedron 42) included.
    pub fn general_from_vtk(id: i64) -> Option<CellType> {
        CellType::ALL.into_iter().chain(CellType::GENERAL).find(|t| *t as i64 == id)
    }

    /// True for a polygon or a polyhedron: a cell whose corner count and faces are its own, not
    /// its type's.
    pub fn is_general(self) -> bool {
        matches!(self, CellType::Polygon | CellType::Polyhedron)
    }

    /// VTK's id of this type.
    pub fn vtk_id(self) -> u8 {
        self as u8
    }

    /// The dimension of the space this cell fills.
    pub fn dim(self) -> usize {
        match self {
            CellType::Triangle | CellType::Quad | CellType::Polygon => 2,
            _ => 3,
        }
    }

    /// Number of corners (vertices); 0 for the general types, whose cells have their own.
    pub fn num_corners(self) -> usize {
        match self {
            CellType::Polygon | CellType::Polyhedron => 0,
            CellType::Triangle => 3,
            CellType::Quad | CellType::Tetra => 4,
            CellType::Pyramid => 5,
            CellType::Wedge => 6,
            CellType::Hexahedron => 8,
        }
    }

    /// Lower-case name, for messages.
    pub fn name(self) -> &'static str {
        match self {
            CellType::Triangle => "triangle",
            CellType::Quad => "quad",
            CellType::Tetra => "tetrahedron",
            CellType::Hexahedron => "hexahedron",
            CellType::Wedge => "wedge",
            CellType::Pyramid => "pyramid",
            CellType::Polygon => "polygon",
            CellType::Polyhedron => "polyhedron",
        }
    }

    /// The cell's edges as pairs of local corners: the springs of the spring analogy and the
    /// couplings of the stiffness pattern's edge graph (never face or body diagonals). Empty for
    /// the general types: their edges are their faces' sides.
    pub fn edges(self) -> &'static [[u8; 2]] {
        match self {
            CellType::Polygon | CellType::Polyhedron => &[],
            CellType::Triangle => &[[0, 1], [1, 2], [2, 0]],
            CellType::Quad => &[[0, 1], [1, 2], [2, 3], [3, 0]],
            CellType::Tetra => &[[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]],
            CellType::Hexahedron => {
                &[[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4], [0, 4], [1, 5], [2, 6], [3, 7]]
            }
            CellType::Wedge => &[[0, 1], [1, 2], [2, 0], [3, 4], [4, 5], [5, 3], [0, 3], [1, 4], [2, 5]],
            CellType::Pyramid => &[[0, 1], [1, 2], [2, 3], [3, 0], [0, 4], [1, 4], [2, 4], [3, 4]],
        }
    }

    /// The cell's faces (its sides: segments in 2D, triangles and quads in 3D) as local corners,
    /// each ordered so that its right-hand normal points out of the cell (in 2D: the cell lies
    /// on the left of the segment). Empty for the general types: their faces are their own.
    pub fn faces(self) -> &'static [&'static [u8]] {
        match self {
            CellType::Polygon | CellType::Polyhedron => &[],
            CellType::Triangle => &[&[0, 1], &[1, 2], &[2, 0]],
            CellType::Quad => &[&[0, 1], &[1, 2], &[2, 3], &[3, 0]],
            CellType::Tetra => &[&[0, 1, 3], &[1, 2, 3], &[2, 0, 3], &[0, 2, 1]],
            CellType::Hexahedron => {
                &[&[0, 3, 2, 1], &[4, 5, 6, 7], &[0, 1, 5, 4], &[1, 2, 6, 5], &[2, 3, 7, 6], &[3, 0, 4, 7]]
            }
            CellType::Wedge => &[&[0, 1, 2], &[3, 5, 4], &[0, 3, 4, 1], &[1, 4, 5, 2], &[2, 5, 3, 0]],
            CellType::Pyramid => &[&[0, 3, 2, 1], &[0, 1, 4], &[1, 2, 4], &[2, 3, 4], &[3, 0, 4]],
        }
    }
}

impl std::fmt::Display for CellType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every edge of a type is an edge of exactly two of its faces in 3D (one in 2D), and every
    /// face runs along edges of the cell: the tables agree with each other.
    #[test]
    fn edges_and_faces_agree() {
        for t in CellType::ALL {
            let faces = t.faces();
            for e in t.edges() {
                let on = |f: &&[u8]| {
                    (0..f.len()).any(|k| {
                        let (a, b) = (f[k], f[(k + 1) % f.len()]);
                        (a, b) == (e[0], e[1]) || (a, b) == (e[1], e[0])
                    })
                };
                let count = faces.iter().filter(|f| on(f)).count();
                assert_eq!(count, if t.dim() == 2 { 1 } else { 2 }, "{t} edge {e:?}");
            }
            // Each face side is traversed once in each direction over the closed surface.
            if t.dim() == 3 {
                let mut sides: Vec<(u8, u8)> =
                    faces.iter().flat_map(|f| (0..f.len()).map(move |k| (f[k], f[(k + 1) % f.len()]))).collect();
                sides.sort_unstable();
                for &(a, b) in &sides {
                    assert!(sides.binary_search(&(b, a)).is_ok(), "{t}: side {a}-{b} has no reverse");
                }
                assert_eq!(sides.len(), 2 * t.edges().len());
            }
            assert_eq!(CellType::from_vtk(t.vtk_id() as i64), Some(t));
        }
    }
}
