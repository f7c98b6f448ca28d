//! The geometry of cells: everything that knows the dimension and the cell type lives here.
//!
//! A cell's corners are gathered into [`CellPoints`]; its element quantities (signed measure,
//! corner Jacobians, the stiffness ∫∇φ_i·∇φ_j, the lumped mass ∫φ_i, angles) come from the
//! module of its family: `simplex` (P1 triangles and tetrahedra) and `tensor` (Q1 quads and
//! hexahedra); wedges and pyramids are averaged decompositions into tetrahedra (`decomposed`).
//! Rotations in D dimensions are in `rotation`; closest points on boundary simplices in
//! `closest`.

mod cell_type;
pub(crate) mod closest;
mod decomposed;
mod face;
mod general;
mod hex_kernel;
mod cell_quality;
pub(crate) mod rotation;
mod simplex;
mod tensor;

pub use cell_type::{CellType, MAX_CORNERS};
pub(crate) use face::face_area_vector;
pub(crate) use general::GeneralPoints;
pub(crate) use hex_kernel::Lanes;

/// Up to `MAX_CORNERS` values, one per corner of a cell.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Corners<T> {
    v: [T; MAX_CORNERS],
    n: u8,
}

impl<T: Copy + Default> Corners<T> {
    /// The values `f(k)` of the `n` corners.
    #[inline]
    pub(crate) fn from_fn(n: usize, mut f: impl FnMut(usize) -> T) -> Corners<T> {
        let mut v = [T::default(); MAX_CORNERS];
        for (k, x) in v[..n].iter_mut().enumerate() {
            *x = f(k);
        }
        Corners { v, n: n as u8 }
    }
}

impl<T> std::ops::Deref for Corners<T> {
    type Target = [T];
    #[inline]
    fn deref(&self) -> &[T] {
        &self.v[..self.n as usize]
    }
}

/// The corners of one cell, padded to 3 coordinates (z = 0 in 2D).
#[derive(Clone, Copy, Debug)]
pub struct CellPoints {
    pub(crate) ty: CellType,
    pub(crate) p: [[f64; 3]; MAX_CORNERS],
}

impl CellPoints {
    /// Gathers the corners `verts` of a cell of type `ty` from interleaved `coords` of `dim`
    /// values per vertex.
    #[inline]
    pub fn gather(ty: CellType, verts: &[u32], coords: &[f64], dim: usize) -> CellPoints {
        let mut p = [[0.0; 3]; MAX_CORNERS];
        // Each point's values by name where the dimension is 3 or 2: a copy of a length known
        // only at run time is a call to `memcpy` per corner.
        for (k, &v) in verts.iter().enumerate() {
            let x = &coords[v as usize * dim..v as usize * dim + dim];
            match *x {
                [a, b, c] => p[k] = [a, b, c],
                [a, b] => p[k] = [a, b, 0.0],
                _ => p[k][..dim].copy_from_slice(x),
            }
        }
        CellPoints { ty, p }
    }

    /// Signed area (2D) or volume (3D): positive for a cell in its type's orientation.
    pub fn signed_measure(&self) -> f64 {
        match self.ty {
            CellType::Triangle => simplex::triangle_area(&self.p),
            CellType::Quad => tensor::quad_area(&self.p),
            CellType::Tetra => simplex::tet_volume(&self.p),
            CellType::Hexahedron => cell_quality::volume(&self.p),
            _ => tensor::volume_by_faces(self.ty, &self.p),
        }
    }

    /// The smallest corner Jacobian determinant (for a simplex its one Jacobian, twice the area
    /// or six times the volume): the cell is inverted when it is ≤ 0.
    pub(crate) fn min_corner_jacobian(&self) -> f64 {
        match self.ty {
            CellType::Triangle => 2.0 * simplex::triangle_area(&self.p),
            CellType::Tetra => 6.0 * simplex::tet_volume(&self.p),
            CellType::Hexahedron => cell_quality::min_corner_jacobian(&self.p),
            _ => tensor::min_corner_jacobian(self.ty, &self.p),
        }
    }

    /// [`CellPoints::min_corner_jacobian`] given the cell's signed measure `m`: a simplex's one
    /// Jacobian is its measure times 2 (triangle) or 6 (tetrahedron), the same value without a
    /// second evaluation.
    pub(crate) fn min_corner_jacobian_with_measure(&self, m: f64) -> f64 {
        match self.ty {
            CellType::Triangle => 2.0 * m,
            CellType::Tetra => 6.0 * m,
            _ => self.min_corner_jacobian(),
        }
    }

    /// True when the cell is inverted: a corner Jacobian ≤ 0, or a signed measure ≤ 0 (a wedge or
    /// hexahedron can fold between its corners, through a twisted face, with every corner
    /// positive), or NaN.
    pub(crate) fn is_inverted(&self) -> bool {
        match self.ty {
            CellType::Triangle | CellType::Tetra => not_positive(self.min_corner_jacobian()),
            _ => not_positive(self.min_corner_jacobian()) || not_positive(self.signed_measure()),
        }
    }

    /// [`CellPoints::is_inverted`] given the cell's signed measure `m` (a simplex has one
    /// Jacobian, proportional to its measure: no second evaluation).
    pub(crate) fn inverted_with_measure(&self, m: f64) -> bool {
        match self.ty {
            CellType::Triangle | CellType::Tetra => not_positive(m),
            _ => not_positive(m) || not_positive(self.min_corner_jacobian()),
        }
    }

    /// The squared length of the cell's longest edge (the scale of degeneracy tests).
    pub(crate) fn longest_edge_squared(&self) -> f64 {
        self.ty.edges().iter().map(|e| dist2(&self.p[e[0] as usize], &self.p[e[1] as usize])).fold(0.0, f64::max)
    }

    /// The cell's smallest angle, in degrees: in 2D between two edges at a corner (0 for an
    /// inverted corner), in 3D the smallest dihedral angle (between two faces at an edge), which
    /// reads like the 2D angle and, unlike an edge angle, shows a sliver tetrahedron.
    pub fn min_angle_deg(&self) -> f64 {
        match self.ty {
            CellType::Triangle => simplex::triangle_min_angle_deg(&self.p),
            CellType::Quad => tensor::min_corner_angle_deg(self.ty, &self.p),
            CellType::Hexahedron => cell_quality::min_dihedral_deg(&self.p),
            CellType::Tetra => cell_quality::tet_min_dihedral_deg(&self.p),
            _ => tensor::min_dihedral_deg(self.ty, &self.p),
        }
    }

    /// The local stiffness K_ij = ∫∇φ_i·∇φ_j for the pairs of `self.ty.couplings()`, in that
    /// order (the diagonal follows from the rows' zero sums and is not returned).
    pub(crate) fn stiffness(&self, k: &mut [f64]) {
        match self.ty {
            CellType::Triangle => simplex::triangle_stiffness(&self.p, k),
            CellType::Quad => tensor::quad_stiffness(&self.p, k),
            CellType::Tetra => simplex::tet_stiffness(&self.p, k),
            CellType::Hexahedron => hex_kernel::stiffness_and_mass(&self.p, k, &mut [0.0; 8]),
            t => decomposed::element(t, &self.p, Some(k), None),
        }
    }

    /// `stiffness` and `lumped_mass` together (bitwise each), sharing the quadrature points
    /// where the cell has them; inlined, so a pass run inside `Lanes::run` runs the hexahedron's
    /// kernel on those lanes (the same values on any).
    #[inline(always)]
    pub(crate) fn stiffness_and_mass(&self, k: &mut [f64], m: &mut [f64]) {
        match self.ty {
            CellType::Hexahedron => hex_kernel::stiffness_and_mass(&self.p, k, m),
            CellType::Wedge | CellType::Pyramid => decomposed::element(self.ty, &self.p, Some(k), Some(m)),
            _ => {
                self.stiffness(k);
                self.lumped_mass(m);
            }
        }
    }

    /// The lumped mass ∫φ_i of every corner.
    pub(crate) fn lumped_mass(&self, m: &mut [f64]) {
        match self.ty {
            CellType::Triangle => simplex::triangle_lumped_mass(&self.p, m),
            CellType::Quad => tensor::quad_lumped_mass(&self.p, m),
            CellType::Tetra => simplex::tet_lumped_mass(&self.p, m),
            CellType::Hexahedron => hex_kernel::lumped_mass(&self.p, m),
            t => decomposed::element(t, &self.p, None, Some(m)),
        }
    }
}

/// One cell of any type: the fixed types' corners, or a general cell's corners and faces.
pub(crate) enum CellGeometry {
    /// A cell of a fixed type.
    Fixed(CellPoints),
    /// A polygon or a polyhedron.
    General(GeneralPoints),
}

impl CellGeometry {
    /// Signed area (2D) or volume (3D).
    pub(crate) fn signed_measure(&self) -> f64 {
        match self {
            CellGeometry::Fixed(g) => g.signed_measure(),
            CellGeometry::General(g) => g.signed_measure(),
        }
    }
    /// The smallest corner (fixed types) or sub-simplex (general cells) Jacobian.
    pub(crate) fn min_corner_jacobian(&self) -> f64 {
        match self {
            CellGeometry::Fixed(g) => g.min_corner_jacobian(),
            CellGeometry::General(g) => g.min_corner_jacobian(),
        }
    }
    /// [`CellGeometry::min_corner_jacobian`] given the cell's signed measure `m`.
    pub(crate) fn min_corner_jacobian_with_measure(&self, m: f64) -> f64 {
        match self {
            CellGeometry::Fixed(g) => g.min_corner_jacobian_with_measure(m),
            CellGeometry::General(g) => g.min_corner_jacobian(),
        }
    }
    /// True when the cell is inverted (see [`CellPoints::is_inverted`]; a general cell: a
    /// sub-simplex not positive).
    pub(crate) fn is_inverted(&self) -> bool {
        match self {
            CellGeometry::Fixed(g) => g.is_inverted(),
            CellGeometry::General(g) => g.is_inverted(),
        }
    }
    /// The squared length of the longest edge.
    pub(crate) fn longest_edge_squared(&self) -> f64 {
        match self {
            CellGeometry::Fixed(g) => g.longest_edge_squared(),
            CellGeometry::General(g) => g.longest_edge_squared(),
        }
    }
    /// [`CellGeometry::is_inverted`] given the cell's signed measure `m`.
    pub(crate) fn inverted_with_measure(&self, m: f64) -> bool {
        match self {
            CellGeometry::Fixed(g) => g.inverted_with_measure(m),
            CellGeometry::General(g) => g.is_inverted(),
        }
    }
    /// The smallest angle, degrees (see [`CellPoints::min_angle_deg`]).
    pub(crate) fn min_angle_deg(&self) -> f64 {
        match self {
            CellGeometry::Fixed(g) => g.min_angle_deg(),
            CellGeometry::General(g) => g.min_angle_deg(),
        }
    }
}

impl CellType {
    /// The pairs of corners the stiffness couples: a simplex's edges (in `edges()` order), a
    /// tensor cell's every pair (its basis functions overlap across face diagonals too); empty
    /// for the general types, which couple every pair of their own corners.
    pub(crate) fn couplings(self) -> &'static [[u8; 2]] {
        match self {
            CellType::Triangle | CellType::Tetra => self.edges(),
            CellType::Quad => &[[0, 1], [1, 2], [2, 3], [3, 0], [0, 2], [1, 3]],
            CellType::Hexahedron => &ALL_PAIRS_8,
            CellType::Wedge => &ALL_PAIRS_6,
            CellType::Pyramid => &ALL_PAIRS_5,
            CellType::Polygon | CellType::Polyhedron => &[],
        }
    }

    /// The corner order of the same cell in the opposite orientation (empty for the general
    /// types: a polygon's loop or a polyhedron's faces are reversed instead).
    pub fn flipped(self) -> &'static [u8] {
        match self {
            CellType::Triangle => &[0, 2, 1],
            CellType::Quad => &[0, 3, 2, 1],
            CellType::Tetra => &[0, 2, 1, 3],
            CellType::Hexahedron => &[0, 3, 2, 1, 4, 7, 6, 5],
            CellType::Wedge => &[0, 2, 1, 3, 5, 4],
            CellType::Pyramid => &[0, 3, 2, 1, 4],
            CellType::Polygon | CellType::Polyhedron => &[],
        }
    }
}

/// Every pair of `N` corners, (0,1), (0,2), …, (1,2), …, in that order (`M` = N (N − 1) / 2).
const fn all_pairs<const N: usize, const M: usize>() -> [[u8; 2]; M] {
    let mut out = [[0u8; 2]; M];
    let (mut i, mut k) = (0, 0);
    while i < N {
        let mut j = i + 1;
        while j < N {
            out[k] = [i as u8, j as u8];
            k += 1;
            j += 1;
        }
        i += 1;
    }
    out
}

static ALL_PAIRS_5: [[u8; 2]; 10] = all_pairs::<5, 10>();
static ALL_PAIRS_6: [[u8; 2]; 15] = all_pairs::<6, 15>();
static ALL_PAIRS_8: [[u8; 2]; 28] = all_pairs::<8, 28>();

/// Not above zero, or NaN.
fn not_positive(x: f64) -> bool {
    x.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
}

/// A point of 2 or 3 coordinates as three, z = 0 in 2D: the form the closest-point and face
/// kernels take in any dimension.
#[inline]
pub(crate) fn padded(x: &[f64]) -> [f64; 3] {
    [x[0], x[1], x.get(2).copied().unwrap_or(0.0)]
}

/// |a − b|², the same sum as `DVec2::distance_squared` in 2D (z terms are zero).
#[inline]
pub(crate) fn dist2(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    if d[2] == 0.0 {
        d[0] * d[0] + d[1] * d[1]
    } else {
        d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
    }
}

/// a − b.
#[inline]
pub(crate) fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a × b.
#[inline]
pub(crate) fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// a · b.
#[inline]
pub(crate) fn dot3(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// (b − a) ⟂· (c − a) = twice the signed area of triangle (a, b, c) in the xy plane.
#[inline]
pub(crate) fn twice_area2(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> f64 {
    let (u, v) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
    u[0] * v[1] - u[1] * v[0]
}
