//! Checks on a caller's mesh, each returning the named error of docs/DESIGN.md §2, and the
//! construction of the validated mesh (orientation normalised, patch faces derived).

use super::topology::{cell_faces, patch_faces, CellsView};
use super::{Csr, IndexBase, Mesh, MeshData, MeshError, PolyhedronFaces};
use crate::geometry::{CellGeometry, CellPoints, CellType, GeneralPoints};

/// Converts caller indices to 0-based vertices; on failure, the position and the raw index.
pub(crate) fn indices<I: Copy + TryInto<i64>, const N: usize>(
    raw: &[I; N],
    base: IndexBase,
    n: usize,
) -> Result<[u32; N], (usize, i64)> {
    let mut out = [0u32; N];
    for (k, &i) in raw.iter().enumerate() {
        out[k] = index(i, base, n).map_err(|raw| (k, raw))?;
    }
    Ok(out)
}

/// Converts one caller index to a 0-based vertex, or the raw index when out of range.
pub(crate) fn index<I: Copy + TryInto<i64>>(i: I, base: IndexBase, n: usize) -> Result<u32, i64> {
    let raw: i64 = i.try_into().unwrap_or(i64::MIN);
    let v = raw.checked_sub(base as i64).unwrap_or(-1);
    if v < 0 || v >= n as i64 {
        Err(raw)
    } else {
        Ok(v as u32)
    }
}

/// The error of a cell corner index outside the vertex range.
pub(crate) fn out_of_range(cell: usize, index: i64, base: IndexBase, n: usize) -> MeshError {
    let b = base as i64;
    MeshError::IndexOutOfRange { cell, index, base: b, end: n as i64 + b }
}

/// Validates `d` and builds the mesh (see `Mesh::from_data`).
pub(super) fn mesh(d: &MeshData) -> Result<Mesh, MeshError> {
    let dim = d.dim;
    if !CellType::ALL.iter().any(|t| t.dim() == dim) {
        return Err(MeshError::Dimension { dim });
    }
    if d.coords.len() % dim != 0 {
        return Err(MeshError::CoordinateCount { values: d.coords.len(), dim });
    }
    let n = d.coords.len() / dim;
    if n == 0 || d.cell_types.is_empty() {
        return Err(MeshError::Empty);
    }
    if n >= u32::MAX as usize {
        return Err(MeshError::TooLarge { vertices: n, max: u32::MAX as usize - 1 });
    }
    if let Some(i) = d.coords.iter().position(|x| !x.is_finite()) {
        return Err(MeshError::NonFiniteCoordinate { vertex: i / dim, component: i % dim, value: d.coords[i] });
    }
    let cells = cells(d, n)?;
    let nc = d.cell_types.len();
    let regions = match d.regions.len() {
        0 => vec![0; nc],
        r if r == nc => d.regions.clone(),
        r => return Err(MeshError::RegionCount { regions: r, cells: nc }),
    };
    all_used(&cells, n)?;
    let mut polyhedra = super::polyhedra::faces(d, &cells)?;
    let mut cells = cells;
    orient(&d.coords, dim, &d.cell_types, &mut cells, &mut polyhedra)?;
    distinct(&cells)?;
    let view = CellsView { num_vertices: n, types: &d.cell_types, cells: &cells, polyhedra: &polyhedra };
    let faces = cell_faces(view)?;
    let tagged = tagged_faces(d, n)?;
    let (pf, patch, interior) = patch_faces(view, &faces, &tagged)?;
    let mut mesh = Mesh::from_parts(dim, d.coords.clone(), d.cell_types.clone(), cells, regions, pf, patch, interior);
    mesh.polyhedra = polyhedra;
    Ok(mesh)
}

/// The cells as CSR, every count, type and index checked.
fn cells(d: &MeshData, n: usize) -> Result<Csr, MeshError> {
    let nc = d.cell_types.len();
    let off = &d.cell_offsets;
    if off.len() != nc + 1 || off[0] != 0 || off[nc] as usize != d.cell_vertices.len() {
        return Err(MeshError::CellOffsets { cells: nc, offsets: off.len(), vertices: d.cell_vertices.len() });
    }
    let mut out = Csr::new();
    for (c, &ty) in d.cell_types.iter().enumerate() {
        if ty.dim() != d.dim {
            return Err(MeshError::CellTypeNotInDimension { cell: c, cell_type: ty, dim: d.dim });
        }
        let least = match ty {
            CellType::Polygon => 3,
            CellType::Polyhedron => 4,
            _ => ty.num_corners(),
        };
        let fits = |n: usize| if ty.is_general() { n >= least } else { n == least };
        if off[c + 1] < off[c] || !fits((off[c + 1] - off[c]) as usize) {
            return Err(MeshError::CornerCount { cell: c, cell_type: ty, count: off[c + 1] as i64 - off[c] as i64 });
        }
        let t = &d.cell_vertices[off[c] as usize..off[c + 1] as usize];
        for (k, &v) in t.iter().enumerate() {
            if v as usize >= n {
                return Err(out_of_range(c, v as i64, IndexBase::Zero, n));
            }
            if t[..k].contains(&v) {
                return Err(MeshError::RepeatedVertex { cell: c, vertex: v as usize });
            }
        }
        out.push(t);
    }
    Ok(out)
}

/// Every vertex must belong to a cell: a lone vertex has no equation to move it.
fn all_used(cells: &Csr, n: usize) -> Result<(), MeshError> {
    let mut used = vec![false; n];
    cells.items().iter().for_each(|&v| used[v as usize] = true);
    match used.iter().position(|u| !u) {
        Some(vertex) => Err(MeshError::UnusedVertex { vertex }),
        None => Ok(()),
    }
}

/// Orients the mesh as a whole: a mesh given entirely in the negative orientation is flipped, a
/// cell of zero measure is an error, and so is a cell whose orientation disagrees with the
/// rest's (flipping cells one by one would accept a tangled mesh). The reported cell is the
/// first one of the smaller group (the first negative one on a tie). After orienting, every
/// corner of every cell must have a positive Jacobian (a non-convex quad is refused).
fn orient(
    coords: &[f64],
    dim: usize,
    types: &[CellType],
    cells: &mut Csr,
    polyhedra: &mut PolyhedronFaces,
) -> Result<(), MeshError> {
    let geometry = |cells: &Csr, polyhedra: &PolyhedronFaces, c: usize| {
        let ty = types[c];
        if ty.is_general() {
            CellGeometry::General(GeneralPoints::gather(cells.get(c), polyhedra.of(c), coords, dim))
        } else {
            CellGeometry::Fixed(CellPoints::gather(ty, cells.get(c), coords, dim))
        }
    };
    let mut negative = Vec::with_capacity(types.len());
    for c in 0..types.len() {
        let g = geometry(cells, polyhedra, c);
        let m = g.signed_measure();
        // Relative test: the measure against the longest edge's, so the check is scale-free.
        let edge2 = g.longest_edge_squared();
        let scale = edge2.powf(0.5 * dim as f64);
        // Cells too large or too small for their measure to be a normal `f64` (finite
        // coordinates can still overflow a product of them): said so, not taken as degenerate.
        if edge2 > 0.0 && (!scale.is_normal() || !m.is_finite()) {
            let largest = cells.get(c).iter().flat_map(|&v| &coords[v as usize * dim..(v as usize + 1) * dim]);
            let largest = largest.fold(0.0f64, |a, x| a.max(x.abs()));
            return Err(MeshError::MeasureOutOfRange { cell: c, longest_edge: edge2.sqrt(), largest });
        }
        if m.abs() <= 1e-14 * scale || !m.is_finite() {
            return Err(MeshError::DegenerateCell { cell: c, measure: m });
        }
        negative.push(m < 0.0);
    }
    let neg = negative.iter().filter(|&&x| x).count();
    let pos = types.len() - neg;
    if neg > 0 && pos > 0 {
        let minority = neg <= pos;
        let cell = negative.iter().position(|&x| x == minority).expect("both orientations present");
        return Err(MeshError::InconsistentOrientation { cell, negative: neg, positive: pos });
    }
    for (c, &ty) in types.iter().enumerate() {
        if neg > 0 {
            let cell = cells.get_mut(c);
            match ty {
                // A polygon's loop runs the other way round from the same first corner.
                CellType::Polygon => cell[1..].reverse(),
                CellType::Polyhedron => polyhedra.reverse(c),
                _ => {
                    let old = cell.to_vec();
                    for (k, &f) in ty.flipped().iter().enumerate() {
                        cell[k] = old[f as usize];
                    }
                }
            }
        }
        let g = geometry(cells, polyhedra, c);
        if g.min_corner_jacobian() <= 0.0 {
            return Err(MeshError::InvertedCorner { cell: c, cell_type: ty });
        }
    }
    Ok(())
}

/// Two cells with the same vertex set are an error (the second one names the pair).
fn distinct(cells: &Csr) -> Result<(), MeshError> {
    // Cells of more than 8 corners (general cells) compare among themselves.
    let mut large: Vec<(Vec<u32>, u32)> = (0..cells.len())
        .filter(|&c| cells.get(c).len() > 8)
        .map(|c| {
            let mut k = cells.get(c).to_vec();
            k.sort_unstable();
            (k, c as u32)
        })
        .collect();
    large.sort_unstable();
    if let Some(w) = large.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(MeshError::RepeatedCell { first: w[0].1 as usize, second: w[1].1 as usize });
    }
    let mut keys: Vec<([u32; 8], u32)> = (0..cells.len())
        .filter(|&c| cells.get(c).len() <= 8)
        .map(|c| {
            let mut k = [u32::MAX; 8];
            let t = cells.get(c);
            k[..t.len()].copy_from_slice(t);
            k.sort_unstable();
            (k, c as u32)
        })
        .collect();
    keys.sort_unstable();
    match keys.windows(2).find(|w| w[0].0 == w[1].0) {
        Some(w) => Err(MeshError::RepeatedCell { first: w[0].1 as usize, second: w[1].1 as usize }),
        None => Ok(()),
    }
}

/// The tagged faces, their offsets and indices checked.
fn tagged_faces(d: &MeshData, n: usize) -> Result<Vec<(Vec<u32>, i32)>, MeshError> {
    let nf = d.face_patch.len();
    let off = &d.face_offsets;
    if nf == 0 && (off.is_empty() || off == &[0]) && d.face_vertices.is_empty() {
        return Ok(Vec::new());
    }
    if off.len() != nf + 1 || off[0] != 0 || off[nf] as usize != d.face_vertices.len() {
        return Err(MeshError::FaceOffsets { faces: nf, offsets: off.len(), vertices: d.face_vertices.len() });
    }
    (0..nf)
        .map(|f| {
            if off[f + 1] < off[f] {
                return Err(MeshError::FaceOffsets { faces: nf, offsets: off.len(), vertices: d.face_vertices.len() });
            }
            let v = &d.face_vertices[off[f] as usize..off[f + 1] as usize];
            if let Some(&bad) = v.iter().find(|&&v| v as usize >= n) {
                return Err(MeshError::TaggedIndexOutOfRange { edge: f, index: bad as i64, base: 0, end: n as i64 });
            }
            Ok((v.to_vec(), d.face_patch[f]))
        })
        .collect()
}
