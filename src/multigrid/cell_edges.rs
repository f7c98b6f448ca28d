//! The cells' edges of a level as a graph over its unknowns: where the line finder
//! (`multigrid::lines`; docs/DESIGN.md §5, "Wall layers") tests whether a line may start.
//!
//! K's graph holds every pair of a cell's corners, so a quadrilateral's or a hexahedron's face
//! and body diagonals too. A diagonal is longer than every edge, and in cells of a modest aspect
//! ratio (a structured mesh's 2.8:1 cells at a wall) the body diagonal is already 16 times the
//! short edge in d², the finder's anisotropy over K's graph. Over the edges an unknown's weakest
//! coupling is its longest edge, and only a cell's own stretching makes it anisotropic. On
//! simplices the two graphs are the same.

use crate::bc::Dofs;
use crate::sparse::CsrMatrix;
use crate::Mesh;

/// A graph over a level's unknowns: each unknown's neighbours, ascending, itself not among them.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Graph {
    /// Unknown i's neighbours are `neighbours[start[i]..start[i + 1]]`.
    start: Vec<usize>,
    neighbours: Vec<u32>,
}

impl Graph {
    /// The edges of `mesh`'s cells (`CellType::edges`, a general cell's faces' sides) over its
    /// unknowns `dofs`, as a part of `k`'s graph (the level's stiffness, whose pattern holds
    /// every pair of a cell's corners). Two unknowns of one edge that are one unknown (linked
    /// vertices) are no edge.
    pub(crate) fn cell_edges(mesh: &Mesh, dofs: &Dofs, k: &CsrMatrix) -> Graph {
        let mut on = vec![false; k.cols.len()];
        let mut mark = |a: u32, b: u32| {
            if a == b {
                return;
            }
            if let (Some(p), Some(q)) = (k.find(a as usize, b as usize), k.find(b as usize, a as usize)) {
                on[p] = true;
                on[q] = true;
            }
        };
        for c in 0..mesh.num_cells() {
            if mesh.cell_type(c).is_general() {
                let d = dofs.general_cell_dofs(mesh, c);
                for [i, j] in mesh.general_points(mesh.coords(), c).edges() {
                    mark(d[i], d[j]);
                }
            } else {
                let d = dofs.cell_dofs(mesh, c);
                for &[i, j] in mesh.cell_type(c).edges() {
                    mark(d[i as usize], d[j as usize]);
                }
            }
        }
        Graph::of_entries(k, |p| on[p])
    }

    /// The graph of `k`'s off-diagonal entries p (in `k.cols`' order) that `keep(p)` holds.
    pub(crate) fn of_entries(k: &CsrMatrix, keep: impl Fn(usize) -> bool) -> Graph {
        let mut g = Graph { start: Vec::with_capacity(k.nrows + 1), neighbours: Vec::new() };
        g.start.push(0);
        for i in 0..k.nrows {
            let first = k.row_ptr[i] as usize;
            let (cols, _) = k.row(i);
            g.neighbours.extend(cols.iter().enumerate().filter(|&(e, &j)| j as usize != i && keep(first + e)).map(|(_, &j)| j));
            g.start.push(g.neighbours.len());
        }
        g
    }

    /// The number of unknowns.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// The neighbours of unknown i, ascending.
    pub(crate) fn neighbours(&self, i: usize) -> &[u32] {
        &self.neighbours[self.start[i]..self.start[i + 1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::operator::{LevelOperator, Method};
    use crate::CellType;

    /// Two hexahedra side by side along x (corners 0–11: the x = 0, 1, 2 planes' squares).
    fn two_hexahedra(h: f64) -> Mesh {
        let mut data = crate::MeshData::new(3);
        for x in 0..3 {
            for [y, z] in [[0.0, 0.0], [1.0, 0.0], [1.0, h], [0.0, h]] {
                data.push_vertex(&[x as f64, y, z]);
            }
        }
        for c in [[0u32, 4, 5, 1, 3, 7, 6, 2], [4, 8, 9, 5, 7, 11, 10, 6]] {
            data.push_cell(CellType::Hexahedron, &c, 0);
        }
        Mesh::from_data(&data).expect("two hexahedra")
    }

    #[test]
    fn a_hexahedron_s_diagonals_are_no_edges() {
        let mesh = two_hexahedra(0.3);
        let dofs = Dofs::build(&mesh, &[], &[]);
        let op = LevelOperator::new(Method::Laplacian, &mesh, &dofs);
        let g = Graph::cell_edges(&mesh, &dofs, &op.k);
        assert_eq!(g.len(), 12);
        // Corner 0: its three edges; K couples it with all 7 others of its cell.
        assert_eq!(g.neighbours(0), &[1, 3, 4]);
        assert_eq!(op.k.row(0).0.len(), 8);
        // Corner 4 is on both cells: its edges to 0 and 8 along x, to 5 and 7 in the shared face.
        assert_eq!(g.neighbours(4), &[0, 5, 7, 8]);
        let edges: usize = (0..g.len()).map(|i| g.neighbours(i).len()).sum();
        assert_eq!(edges, 2 * 20);
    }

    #[test]
    fn a_matrix_s_graph_leaves_the_diagonal_out() {
        let k = CsrMatrix::from_triplets(3, 3, vec![(0, 0, 2.0), (0, 1, -1.0), (1, 0, -1.0), (1, 1, 2.0), (1, 2, -1.0), (2, 1, -1.0), (2, 2, 2.0)]);
        let g = Graph::of_entries(&k, |_| true);
        assert_eq!((g.neighbours(0), g.neighbours(1), g.neighbours(2)), (&[1u32][..], &[0u32, 2][..], &[1u32][..]));
    }
}
