//! Meshes as finite-volume codes store them (OpenFOAM's polyMesh, code_saturne): faces with
//! their vertices, the cell on each side of a face, a patch per boundary face. Each cell's faces
//! are gathered (the owner's as given, the neighbour's reversed) and the cell is recognised as a
//! tetrahedron, hexahedron, wedge or pyramid where its faces make one, in a corner order that
//! depends on its vertices only (below), else kept as a polyhedron (so is a cell of a fixed type
//! with a concave corner, which that type's element would refuse); in 2D, where the faces are
//! segments, as a triangle, quad or polygon.

use super::{polyhedra, Mesh, MeshData, MeshError};
use crate::geometry::{CellPoints, CellType};

/// A mesh given by its faces, in the layout of OpenFOAM's polyMesh and of code_saturne: 0-based
/// arrays. A face's vertices run round it so that its right-hand normal (in 2D, where faces are
/// segments, the normal (Δy, −Δx)) points out of its owner cell, into its neighbour.
///
/// ```
/// use meshmove::FaceMeshData;
/// // The unit square as two triangles, faces (edges) with owner and neighbour.
/// let faces = FaceMeshData {
///     dim: 2,
///     coords: vec![0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0],
///     face_offsets: vec![0, 2, 4, 6, 8, 10],
///     face_vertices: vec![0, 2, 0, 1, 1, 2, 2, 3, 3, 0],
///     owner: vec![1, 0, 0, 1, 1],
///     neighbour: vec![0, -1, -1, -1, -1],
///     patch: vec![-1, 1, 2, 3, 4],
///     regions: Vec::new(),
/// };
/// let mesh = faces.to_mesh().unwrap();
/// assert_eq!((mesh.num_cells(), mesh.patch_vertices(2)), (2, vec![1, 2]));
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaceMeshData {
    /// 2 or 3.
    pub dim: usize,
    /// `dim` values per vertex: x0, y0, (z0,) x1, ...
    pub coords: Vec<f64>,
    /// Face `f`'s vertices are `face_vertices[face_offsets[f]..face_offsets[f + 1]]`; starts at 0.
    pub face_offsets: Vec<u32>,
    /// The vertices of every face: in 3D a loop of at least 3, in 2D a segment.
    pub face_vertices: Vec<u32>,
    /// The cell each face's normal points out of. Cells are numbered 0 to the largest owner or
    /// neighbour; every cell must own or neighbour a face.
    pub owner: Vec<i64>,
    /// The cell each face's normal points into, or −1 (any negative value) on the boundary.
    pub neighbour: Vec<i64>,
    /// The patch of each face: ≥ 0 on every boundary face; on an interior face −1 (any negative
    /// value) or a patch id that tags it (an interface between regions).
    pub patch: Vec<i32>,
    /// Region of each cell; empty means every cell is in region 0.
    pub regions: Vec<i32>,
}

impl FaceMeshData {
    /// Number of faces.
    pub fn num_faces(&self) -> usize {
        self.owner.len()
    }

    /// The vertices of face `f`.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.face_vertices[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }

    /// The same mesh as cells ([`MeshData`]): each cell recognised as a tetrahedron, hexahedron,
    /// wedge or pyramid (a triangle or quad in 2D) where its faces make one, its corners in an
    /// order that depends on its vertex numbers only (corner 0 is its lowest vertex; see
    /// docs/DESIGN.md §2), else a polyhedron (polygon). Errors name the face or cell at fault:
    /// arrays of different lengths, a face of too few vertices, a vertex, owner or neighbour out
    /// of range, a boundary face without a patch, a cell whose faces do not close it.
    pub fn to_data(&self) -> Result<MeshData, MeshError> {
        self.cells(false)
    }

    /// One rank's part of a partitioned mesh as cells: as [`to_data`](Self::to_data), where a
    /// face between a cell of the part and a cell of another rank has that side negative (its
    /// owner or its neighbour) and a negative patch. Such a face is not a boundary face and is
    /// not tagged; the distributed mesh fetches the cell beyond it.
    pub fn to_part_data(&self) -> Result<MeshData, MeshError> {
        self.cells(true)
    }

    /// The cells of [`to_data`](Self::to_data), or of [`to_part_data`](Self::to_part_data)
    /// when `part`.
    fn cells(&self, part: bool) -> Result<MeshData, MeshError> {
        let nf = self.check(part)?;
        let dim = self.dim;
        let nc = (0..nf).map(|f| self.owner[f].max(self.neighbour[f]) + 1).max().unwrap_or(0) as usize;
        // Every cell has at least 3 faces and a face at most 2 cells.
        if nc > 2 * nf {
            let problem = format!("cells numbered up to {} with {nf} faces: some cells have no face", nc - 1);
            return Err(MeshError::FaceArrays { problem });
        }
        // Each cell's faces, outward: (face, reversed).
        let mut count = vec![0u32; nc + 1];
        for f in 0..nf {
            if self.owner[f] >= 0 {
                count[self.owner[f] as usize + 1] += 1;
            }
            if self.neighbour[f] >= 0 {
                count[self.neighbour[f] as usize + 1] += 1;
            }
        }
        (0..nc).for_each(|c| count[c + 1] += count[c]);
        let mut next = count.clone();
        let mut sides = vec![(0u32, false); count[nc] as usize];
        for f in 0..nf {
            if self.owner[f] >= 0 {
                let o = self.owner[f] as usize;
                sides[next[o] as usize] = (f as u32, false);
                next[o] += 1;
            }
            if self.neighbour[f] >= 0 {
                let n = self.neighbour[f] as usize;
                sides[next[n] as usize] = (f as u32, true);
                next[n] += 1;
            }
        }
        let mut d = MeshData::new(dim);
        d.coords = self.coords.clone();
        let mut loops: Vec<Vec<u32>> = Vec::new();
        for c in 0..nc {
            let mine = &sides[count[c] as usize..count[c + 1] as usize];
            if mine.is_empty() {
                return Err(MeshError::FaceBasedCell {
                    cell: c,
                    problem: "no face has it as owner or neighbour".into(),
                });
            }
            let region = self.regions.get(c).copied().unwrap_or(0);
            loops.clear();
            loops.extend(mine.iter().map(|&(f, rev)| {
                let mut v = self.face(f as usize).to_vec();
                if rev {
                    v.reverse();
                }
                v
            }));
            if dim == 2 {
                let corners = polygon(c, &loops)?;
                let ty = match corners.len() {
                    3 => CellType::Triangle,
                    4 => CellType::Quad,
                    _ => CellType::Polygon,
                };
                d.push_cell(ty, &corners, region);
                continue;
            }
            let faces: Vec<&[u32]> = loops.iter().map(|v| v.as_slice()).collect();
            polyhedra::closed(c, faces.iter().copied())?;
            match recognise(&faces).filter(|(ty, corners)| convex(*ty, corners, &self.coords)) {
                Some((ty, corners)) => d.push_cell(ty, &corners, region),
                None => d.push_polyhedron(&faces, region),
            }
        }
        if !self.regions.is_empty() && self.regions.len() != nc {
            return Err(MeshError::RegionCount { regions: self.regions.len(), cells: nc });
        }
        for f in 0..nf {
            if self.patch[f] >= 0 && self.owner[f] < 0 {
                // A tagged face of the part whose owner is another rank's: outward from the part.
                let v: Vec<u32> = self.face(f).iter().rev().copied().collect();
                d.push_face(&v, self.patch[f]);
            } else if self.patch[f] >= 0 || (self.neighbour[f] < 0 && !part) {
                d.push_face(self.face(f), self.patch[f]);
            }
        }
        Ok(d)
    }

    /// The mesh ([`FaceMeshData::to_data`], then [`Mesh::from_data`]'s checks).
    pub fn to_mesh(&self) -> Result<Mesh, MeshError> {
        Mesh::from_data(&self.to_data()?)
    }

    /// Checks the arrays' lengths and ranges; returns the number of faces. In a `part` a face
    /// may have one side negative, and then needs no patch.
    fn check(&self, part: bool) -> Result<usize, MeshError> {
        let dim = self.dim;
        if dim != 2 && dim != 3 {
            return Err(MeshError::Dimension { dim });
        }
        if self.coords.len() % dim != 0 {
            return Err(MeshError::CoordinateCount { values: self.coords.len(), dim });
        }
        let nv = self.coords.len() / dim;
        let nf = self.owner.len();
        let off = &self.face_offsets;
        if off.len() != nf + 1 || off[0] != 0 || off[nf] as usize != self.face_vertices.len() {
            return Err(MeshError::FaceOffsets { faces: nf, offsets: off.len(), vertices: self.face_vertices.len() });
        }
        for (name, len) in [("neighbour", self.neighbour.len()), ("patch", self.patch.len())] {
            if len != nf {
                let problem = format!("{nf} owners (faces) and {len} {name} values");
                return Err(MeshError::FaceArrays { problem });
            }
        }
        if nf == 0 {
            return Err(MeshError::Empty);
        }
        let cells_max = i64::from(u32::MAX) - 1;
        for f in 0..nf {
            if off[f + 1] < off[f] {
                return Err(MeshError::FaceOffsets {
                    faces: nf,
                    offsets: off.len(),
                    vertices: self.face_vertices.len(),
                });
            }
            let v = self.face(f);
            if if dim == 2 { v.len() != 2 } else { v.len() < 3 } {
                return Err(MeshError::FaceSize { face: f, count: v.len(), dim });
            }
            if let Some(&bad) = v.iter().find(|&&v| v as usize >= nv) {
                return Err(MeshError::FaceIndexOutOfRange {
                    face: f,
                    what: "vertex",
                    index: bad.into(),
                    end: nv as i64,
                });
            }
            let (o, n) = (self.owner[f], self.neighbour[f]);
            // In a part, a face whose owner is another rank's cell has its neighbour here.
            let elsewhere = part && o < 0 && (0..cells_max).contains(&n);
            if !(0..cells_max).contains(&o) && !elsewhere {
                return Err(MeshError::FaceIndexOutOfRange { face: f, what: "owner", index: o, end: cells_max });
            }
            if n >= cells_max || (n == o && n >= 0) {
                let end = if n == o { o } else { cells_max };
                return Err(MeshError::FaceIndexOutOfRange { face: f, what: "neighbour", index: n, end });
            }
            if n < 0 && self.patch[f] < 0 && !part {
                return Err(MeshError::BoundaryFaceWithoutPatch { face: f, patch: self.patch[f] });
            }
        }
        Ok(nf)
    }
}

impl Mesh {
    /// A mesh from faces with owner and neighbour cells, as finite-volume codes store it: see
    /// [`FaceMeshData`].
    pub fn from_faces(faces: &FaceMeshData) -> Result<Mesh, MeshError> {
        faces.to_mesh()
    }
}

/// The corners of a 2D cell whose outward sides (each with the cell on its left) are `sides`:
/// one loop, counter-clockwise, from its lowest vertex.
fn polygon(cell: usize, sides: &[Vec<u32>]) -> Result<Vec<u32>, MeshError> {
    let mut sorted: Vec<(u32, u32)> = sides.iter().map(|s| (s[0], s[1])).collect();
    sorted.sort_unstable();
    if let Some(w) = sorted.windows(2).find(|w| w[0].0 == w[1].0) {
        let problem = format!("two of its sides start at vertex {} (its faces are not one loop round it)", w[0].0);
        return Err(MeshError::FaceBasedCell { cell, problem });
    }
    if let Some(&(from, to)) = sorted.iter().find(|s| sorted.binary_search_by_key(&s.1, |t| t.0).is_err()) {
        return Err(MeshError::OpenCell { cell, from, to, twice: false });
    }
    let start = sorted[0].0;
    let mut corners = vec![start];
    let mut at = sorted[0].1;
    while at != start && corners.len() < sorted.len() {
        corners.push(at);
        // Every side's end starts exactly one side (checked above).
        let k = sorted.partition_point(|s| s.0 < at);
        at = sorted[k].1;
    }
    if corners.len() != sorted.len() || at != start {
        let problem = format!("its {} sides make more than one loop", sorted.len());
        return Err(MeshError::FaceBasedCell { cell, problem });
    }
    Ok(corners)
}

/// False for a recognised cell that its type's element would refuse although its volume is
/// positive: a corner of non-positive Jacobian, as a snapped hexahedron's concave corner (mesh
/// generators such as snappyHexMesh make them and finite-volume codes accept them). Such a cell
/// is kept as a polyhedron, whose element is valid while its sub-tetrahedra are. A cell of
/// negative volume keeps its type: the mesh's orientation is checked as a whole afterwards.
fn convex(ty: CellType, corners: &[u32], coords: &[f64]) -> bool {
    let p = CellPoints::gather(ty, corners, coords, 3);
    p.signed_measure() <= 0.0 || !p.is_inverted()
}

/// The type and corners of a closed cell of outward `faces` that is a tetrahedron, hexahedron,
/// wedge or pyramid, or None. Corner 0 is a fixed choice among the cell's vertices and the rest
/// follow from the faces (so the order depends on the vertex numbers only, not on the order of
/// the faces or of their vertices):
///
/// - tetrahedron: 0 the lowest vertex, 3 the highest, 1 and 2 from the face opposite 3;
/// - pyramid: 0 the lowest vertex of the quad, 4 the apex;
/// - wedge: 0 the lowest vertex, 0–1–2 its triangle, 3–5 across the quads;
/// - hexahedron: 0 the lowest vertex, 4 the highest of its three neighbours along edges,
///   0–1–2–3 the face at 0 without 4.
///
/// A hexahedral grid numbered along x, then y, then z, with VTK's corner order in each cell,
/// gets back exactly that order. The result is checked against the type's faces.
fn recognise(faces: &[&[u32]]) -> Option<(CellType, Vec<u32>)> {
    let mut verts: Vec<u32> = faces.iter().flat_map(|f| f.iter().copied()).collect();
    verts.sort_unstable();
    verts.dedup();
    let tris = faces.iter().filter(|f| f.len() == 3).count();
    let quads = faces.iter().filter(|f| f.len() == 4).count();
    let low = verts[0];
    // The outward loop of a face containing `v`, rotated to start at `v`.
    let from = |f: &[u32], v: u32| -> Option<Vec<u32>> {
        let k = f.iter().position(|&x| x == v)?;
        Some((0..f.len()).map(|i| f[(k + i) % f.len()]).collect())
    };
    // The vertex after `v` along an edge that is not in `not`.
    let across = |v: u32, not: &[u32]| -> Option<u32> {
        faces.iter().find_map(|f| {
            let l = from(f, v)?;
            [l[1], l[l.len() - 1]].into_iter().find(|w| !not.contains(w))
        })
    };
    let (ty, corners) = match (faces.len(), tris, quads, verts.len()) {
        (4, 4, 0, 4) => {
            let high = verts[3];
            let base = faces.iter().find(|f| !f.contains(&high))?;
            let l = from(base, low)?;
            (CellType::Tetra, vec![low, l[2], l[1], high])
        }
        (5, 4, 1, 5) => {
            let base = faces.iter().find(|f| f.len() == 4)?;
            let b0 = *base.iter().min()?;
            let l = from(base, b0)?;
            let apex = *verts.iter().find(|v| !base.contains(v))?;
            (CellType::Pyramid, vec![b0, l[3], l[2], l[1], apex])
        }
        (5, 2, 3, 6) => {
            let base = faces.iter().find(|f| f.len() == 3 && f.contains(&low))?;
            let l = from(base, low)?;
            let top: Option<Vec<u32>> = l.iter().map(|&v| across(v, &l)).collect();
            let mut c = l.clone();
            c.extend(top?);
            (CellType::Wedge, c)
        }
        (6, 0, 6, 8) => {
            let mut near: Vec<u32> = faces.iter().filter_map(|f| from(f, low)).flat_map(|l| [l[1], l[3]]).collect();
            near.sort_unstable();
            near.dedup();
            let up = *near.last()?;
            let base = faces.iter().find(|f| f.contains(&low) && !f.contains(&up))?;
            let l = from(base, low)?;
            let bottom = [low, l[3], l[2], l[1]];
            let top: Option<Vec<u32>> = bottom.iter().map(|&v| across(v, &bottom)).collect();
            let mut c = bottom.to_vec();
            c.extend(top?);
            (CellType::Hexahedron, c)
        }
        _ => return None,
    };
    same_faces(ty, &corners, faces).then_some((ty, corners))
}

/// True when the faces of `ty` on `corners` are `faces` (each the same loop, from any start).
fn same_faces(ty: CellType, corners: &[u32], faces: &[&[u32]]) -> bool {
    let key = |f: &[u32]| -> Vec<u32> {
        let k = (0..f.len()).min_by_key(|&i| f[i]).unwrap_or(0);
        (0..f.len()).map(|i| f[(k + i) % f.len()]).collect()
    };
    let mut want: Vec<Vec<u32>> =
        ty.faces().iter().map(|f| key(&f.iter().map(|&k| corners[k as usize]).collect::<Vec<_>>())).collect();
    let mut have: Vec<Vec<u32>> = faces.iter().map(|f| key(f)).collect();
    want.sort_unstable();
    have.sort_unstable();
    want == have
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube's six outward faces on corners in VTK order `c`.
    fn cube_faces(c: [u32; 8]) -> Vec<Vec<u32>> {
        CellType::Hexahedron.faces().iter().map(|f| f.iter().map(|&k| c[k as usize]).collect()).collect()
    }

    #[test]
    fn a_hexahedron_is_recognised_in_grid_order() {
        let c = [0, 1, 3, 2, 4, 5, 7, 6];
        let mut faces = cube_faces(c);
        faces.rotate_left(2);
        faces[0].rotate_left(1);
        let refs: Vec<&[u32]> = faces.iter().map(|f| f.as_slice()).collect();
        assert_eq!(recognise(&refs), Some((CellType::Hexahedron, c.to_vec())));
        // The same cube with its faces reversed is its mirror image: 1 and 3 swap (and 5 and 7).
        let rev: Vec<Vec<u32>> = faces.iter().map(|f| f.iter().rev().copied().collect()).collect();
        let refs: Vec<&[u32]> = rev.iter().map(|f| f.as_slice()).collect();
        assert_eq!(recognise(&refs), Some((CellType::Hexahedron, vec![0, 2, 3, 1, 4, 6, 7, 5])));
        // Six quads on eight vertices that do not make a cube: two faces swapped for others.
        let mut odd = cube_faces(c);
        odd[0] = vec![0, 2, 7, 1];
        let refs: Vec<&[u32]> = odd.iter().map(|f| f.as_slice()).collect();
        assert_eq!(recognise(&refs), None);
    }

    #[test]
    fn tetrahedra_wedges_and_pyramids_are_recognised() {
        for (ty, c) in [
            (CellType::Tetra, vec![3u32, 9, 5, 7]),
            (CellType::Wedge, vec![2, 6, 4, 8, 3, 5]),
            (CellType::Pyramid, vec![1, 8, 3, 6, 0]),
        ] {
            let faces: Vec<Vec<u32>> = ty.faces().iter().map(|f| f.iter().map(|&k| c[k as usize]).collect()).collect();
            let refs: Vec<&[u32]> = faces.iter().map(|f| f.as_slice()).collect();
            let (got, corners) = recognise(&refs).unwrap();
            assert_eq!(got, ty);
            assert!(same_faces(ty, &corners, &refs));
            let mut sorted = corners.clone();
            sorted.sort_unstable();
            let mut given = c.clone();
            given.sort_unstable();
            assert_eq!(sorted, given);
        }
    }
}
