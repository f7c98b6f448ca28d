//! `meshmove_mesh`: a validated mesh (vertices, cells of any type as CSR lists, tagged faces,
//! regions) built from the caller's plain arrays.
//!
//! The C layer checks every size, offset and index of the arrays, builds a 0-based
//! [`MeshData`] and hands it to [`Mesh::from_data`], which validates the geometry. The mesh is
//! read back through [`Mesh::to_data`], so nothing here depends on the dimension or cell types
//! the core handles.

use super::error::CError;
use super::handles::{self, check_out, count, get, hand_out, slice, slice_mut, Handle, Slot};
use super::points;
use super::status::meshmove_status;
use super::types::{self, bounded};
use crate::geometry::CellType;
use crate::mesh::MeshData;
use crate::solver::memory;
use crate::{limits, Mesh, MeshError};
use std::ffi::c_char;

/// An immutable mesh (vertices, cells, boundary and interface patches, regions). Create with
/// `meshmove_mesh_create`, `meshmove_mesh_create_triangles` or `meshmove_mesh_read_msh`; free
/// with `meshmove_mesh_free`. A solver keeps its own copy: the mesh may be freed after
/// `meshmove_solver_create`.
pub struct meshmove_mesh(Slot<Mesh>);

impl Handle for meshmove_mesh {
    type Payload = Mesh;
    const NAME: &'static str = "meshmove_mesh";
    fn slot(&self) -> &Slot<Mesh> {
        &self.0
    }
    fn from_slot(slot: Slot<Mesh>) -> Self {
        meshmove_mesh(slot)
    }
}

/// A CSR list as the caller gave it: `offsets` (None: derived) and the vertex indices.
struct Csr<'a> {
    offsets: Option<&'a [i32]>,
    vertices: &'a [i32],
}

/// The arrays of a mesh as the caller gave them, their lengths checked, in the caller's numbering.
struct Arrays<'a> {
    dim: usize,
    coords: &'a [f64],
    cell_types: &'a [i32],
    cells: Csr<'a>,
    faces: Csr<'a>,
    face_patch: &'a [i32],
    regions: Option<&'a [i32]>,
    base: i32,
}

/// The number of vertices of a `dim`-dimensional mesh: at most `MESHMOVE_MAX_VERTICES`, and
/// `dim × vertices` must fit an `int32_t` length.
fn vertex_count(n: i32, dim: usize) -> Result<usize, CError> {
    let max = limits::MAX_VERTICES.min(i32::MAX as usize / dim);
    bounded(n, &format!("num_vertices (a {dim}D mesh)"), 0, max)
}

/// How many vertices a tagged face of a `dim`-dimensional mesh may have: those of the cells'
/// sides (segments in 2D, triangles and quads in 3D), from the cell types' tables.
fn face_sizes(dim: usize) -> Vec<usize> {
    let mut sizes: Vec<usize> =
        CellType::ALL.iter().filter(|t| t.dim() == dim).flat_map(|t| t.faces().iter().map(|f| f.len())).collect();
    sizes.sort_unstable();
    sizes.dedup();
    sizes
}

/// Item `i` (0-based) in the caller's numbering.
fn named(i: usize, base: i32) -> i64 {
    i as i64 + i64::from(base)
}

/// Checks caller-given offsets of `n` items into `total` vertex indices: `n + 1` positions from
/// 0 to `total`, never decreasing, each item's count accepted by `item_ok` (which names the
/// problem). Returns them as the Rust mesh stores them.
fn checked_offsets(
    off: &[i32],
    total: usize,
    what: &str,
    total_what: &str,
    item_ok: impl Fn(usize, usize) -> Result<(), CError>,
) -> Result<Vec<u32>, CError> {
    if off[0] != 0 {
        return Err(CError::arg(format!("`{what}[0]` is {}; offsets start at 0 (whatever the index base)", off[0])));
    }
    for (i, w) in off.windows(2).enumerate() {
        if w[1] < w[0] {
            return Err(CError::arg(format!("`{what}` decreases at entry {} ({} after {})", i + 1, w[1], w[0])));
        }
        item_ok(i, (w[1] - w[0]) as usize)?;
    }
    let last = off[off.len() - 1];
    if last as usize != total {
        return Err(CError::arg(format!("`{what}[{}]` is {last}; it must be {total_what}, {total}", off.len() - 1)));
    }
    Ok(off.iter().map(|&o| o as u32).collect())
}

/// Offsets from a count per item, checked against the length the caller stated.
fn derived_offsets(counts: impl Iterator<Item = usize>, total: usize, explain: &str) -> Result<Vec<u32>, CError> {
    let mut off = vec![0u32];
    let mut at = 0usize;
    for n in counts {
        at += n;
        off.push(at.min(u32::MAX as usize) as u32);
    }
    if at != total {
        return Err(CError::arg(format!("{explain}: {at} vertex indices are needed, {total} were given")));
    }
    Ok(off)
}

/// Vertex indices in `base` to 0-based ones, each checked against `nv`; `err(item, index)` is the
/// error for an index out of range in item `item` (0-based).
fn vertex_indices(
    offsets: &[u32],
    vertices: &[i32],
    nv: usize,
    base: i32,
    err: impl Fn(usize, i64) -> MeshError,
) -> Result<Vec<u32>, MeshError> {
    let mut out = Vec::with_capacity(vertices.len());
    for (item, w) in offsets.windows(2).enumerate() {
        for &v in &vertices[w[0] as usize..w[1] as usize] {
            let i = i64::from(v) - i64::from(base);
            if i < 0 || i >= nv as i64 {
                return Err(err(item, i64::from(v)));
            }
            out.push(i as u32);
        }
    }
    Ok(out)
}

/// Checks every size, offset, type and index of `a` and builds the 0-based [`MeshData`].
fn mesh_data(a: &Arrays) -> Result<MeshData, CError> {
    let (dim, base) = (a.dim, a.base);
    let nv = a.coords.len() / dim;
    let types: Vec<CellType> =
        a.cell_types.iter().enumerate().map(|(c, &t)| types::cell_type(t, named(c, base))).collect::<Result<_, _>>()?;
    let ncv = a.cells.vertices.len();
    let cell_offsets = match a.cells.offsets {
        Some(off) => checked_offsets(off, ncv, "cell_offsets", "num_cell_vertices", |c, n| {
            let t = types[c];
            if n == t.num_corners() {
                return Ok(());
            }
            Err(CError::arg(format!(
                "`cell_offsets` give cell {} {n} vertices; it is a {t} (type {}), which has {}",
                named(c, base),
                t.vtk_id(),
                t.num_corners()
            )))
        })?,
        None => derived_offsets(
            types.iter().map(|t| t.num_corners()),
            ncv,
            "num_cell_vertices does not match the cell types (cell_offsets is NULL: every cell has the corners of its \
             type)",
        )?,
    };
    let nfv = a.faces.vertices.len();
    let sizes = face_sizes(dim);
    let face_offsets = match a.faces.offsets {
        Some(off) => checked_offsets(off, nfv, "face_offsets", "num_face_vertices", |f, n| {
            if sizes.contains(&n) {
                return Ok(());
            }
            Err(CError::arg(format!(
                "`face_offsets` give face {} {n} vertices; a face of a {dim}D mesh has {sizes:?}",
                named(f, base),
            )))
        })?,
        None => {
            // Every face the same size, which the counts tell: the face size of this dimension's
            // cells (triangles or quadrilaterals in 3D) whose multiple num_face_vertices is.
            let nf = a.face_patch.len();
            let k = sizes.iter().copied().find(|&k| k * nf == nfv).or(sizes.first().copied()).unwrap_or(0);
            derived_offsets(
                std::iter::repeat_n(k, nf),
                nfv,
                &format!(
                    "num_face_vertices ({nfv}) does not match num_faces ({nf}): with face_offsets NULL every face has \
                     {} vertices in {dim}D",
                    sizes.iter().map(usize::to_string).collect::<Vec<_>>().join(" or ")
                ),
            )?
        }
    };
    let (b, end) = (i64::from(base), i64::from(base) + nv as i64);
    let cell_vertices = vertex_indices(&cell_offsets, a.cells.vertices, nv, base, |cell, index| {
        MeshError::IndexOutOfRange { cell, index, base: b, end }
    })
    .map_err(|e| in_base(e, base))?;
    let face_vertices = vertex_indices(&face_offsets, a.faces.vertices, nv, base, |edge, index| {
        MeshError::TaggedIndexOutOfRange { edge, index, base: b, end }
    })
    .map_err(|e| in_base(e, base))?;
    Ok(MeshData {
        dim,
        coords: a.coords.to_vec(),
        cell_types: types,
        cell_offsets,
        cell_vertices,
        regions: a.regions.map(<[i32]>::to_vec).unwrap_or_default(),
        face_offsets,
        face_vertices,
        face_patch: a.face_patch.to_vec(),
        polyhedron_faces: Vec::new(),
    })
}

/// Builds the mesh of `a` and hands it out in `*out`.
///
/// # Safety
/// `out` must have passed `check_out`.
unsafe fn create(a: &Arrays, out: *mut *mut meshmove_mesh) -> Result<(), CError> {
    let (nv, nc) = (a.coords.len() / a.dim, a.cell_types.len());
    let need = memory::mesh_bytes(a.dim, nv, nc, a.cells.vertices.len(), a.face_patch.len());
    memory::check_available(need, 0, "the mesh")?;
    let data = mesh_data(a)?;
    let mesh = Mesh::from_data(&data).map_err(|e| in_base(e, a.base))?;
    // SAFETY: `out` passed `check_out` (this function's contract).
    unsafe { hand_out(mesh, out) }
}

/// Validates and creates a mesh of any dimension and cell types from plain arrays (copied).
///
/// - `dim`: 2 or 3. `coords`: `dim × num_vertices` doubles, interleaved (x0, y0, (z0,) x1, ...);
///   at most `MESHMOVE_MAX_VERTICES` vertices (in 3D, `INT32_MAX / 3`).
/// - Cells (at most `MESHMOVE_MAX_CELLS`): `cell_types` gives each cell's `meshmove_cell_type`
///   (VTK's ids); cell c's corners, in VTK's local order for its type, are
///   `cell_connectivity[cell_offsets[c] .. cell_offsets[c + 1]]`. `cell_offsets` holds
///   `num_cells + 1` positions starting at 0 (whatever the index base) and ending at
///   `num_cell_vertices`, the length of `cell_connectivity`; NULL when every cell's corner count
///   follows from its type (it always does: the offsets are then derived).
/// - Tagged faces (at most `MESHMOVE_MAX_VERTICES`): face f's vertices are
///   `face_connectivity[face_offsets[f] .. face_offsets[f + 1]]` (2 in 2D, 3 or 4 in 3D), its
///   patch `face_patch[f]`. `face_offsets`: `num_faces + 1` positions from 0 to
///   `num_face_vertices`, or NULL when every face has as many vertices: segments in 2D; in 3D
///   quadrilaterals when `num_face_vertices` = 4 × `num_faces` (hexahedral meshes), triangles
///   when it is 3 × `num_faces`, any other count `MESHMOVE_STATUS_INVALID_ARGUMENT` (mixed
///   faces need `face_offsets`). Boundary faces not tagged are on patch 0; a tagged interior face is an internal
///   interface.
/// - `cell_region`: NULL, or one region id per cell. `index_base`: the first vertex index, 0 (C)
///   or 1 (Fortran).
///
/// Every size, offset, type and index is checked (`MESHMOVE_STATUS_INVALID_ARGUMENT` names the
/// array and entry; an index out of range is `MESHMOVE_STATUS_INVALID_MESH`, naming the raw index
/// and the base), then the geometry (`MESHMOVE_STATUS_INVALID_MESH` names the offending cell,
/// face or vertex, numbered from `index_base`). A dimension or cell type the library does not
/// handle yet is `MESHMOVE_STATUS_UNSUPPORTED`. On failure `*out` is NULL.
///
/// # Safety
/// Each non-NULL array must hold the number of elements stated; `out` must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_create(
    dim: i32,
    num_vertices: i32,
    coords: *const f64,
    num_cells: i32,
    cell_offsets: *const i32,
    num_cell_vertices: i32,
    cell_connectivity: *const i32,
    cell_types: *const i32,
    num_faces: i32,
    face_offsets: *const i32,
    num_face_vertices: i32,
    face_connectivity: *const i32,
    face_patch: *const i32,
    cell_region: *const i32,
    index_base: i32,
    out: *mut *mut meshmove_mesh,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_create, {
        // SAFETY: the caller guarantees `out` is NULL (refused) or writable.
        unsafe { check_out(out, "out") }?;
        let dim = bounded(dim, "dim", 2, 3)?;
        let nv = vertex_count(num_vertices, dim)?;
        let nc = bounded(num_cells, "num_cells", 0, limits::MAX_CELLS)?;
        let nf = bounded(num_faces, "num_faces", 0, limits::MAX_VERTICES)?;
        let ncv = count(num_cell_vertices, "num_cell_vertices")?;
        let nfv = count(num_face_vertices, "num_face_vertices")?;
        let base = handles::index_base(index_base)?;
        let optional = |p: *const i32| (!p.is_null()).then_some(p);
        // SAFETY: the caller guarantees that each non-NULL array holds the number of elements
        // stated by the counts (checked non-negative and bounded above); NULL is refused where
        // an array is required and its length is not 0.
        let a = unsafe {
            Arrays {
                dim,
                coords: slice(coords, dim * nv, "coords")?,
                cell_types: slice(cell_types, nc, "cell_types")?,
                cells: Csr {
                    offsets: optional(cell_offsets).map(|p| slice(p, nc + 1, "cell_offsets")).transpose()?,
                    vertices: slice(cell_connectivity, ncv, "cell_connectivity")?,
                },
                faces: Csr {
                    offsets: optional(face_offsets).map(|p| slice(p, nf + 1, "face_offsets")).transpose()?,
                    vertices: slice(face_connectivity, nfv, "face_connectivity")?,
                },
                face_patch: slice(face_patch, nf, "face_patch")?,
                regions: optional(cell_region).map(|p| slice(p, nc, "cell_region")).transpose()?,
                base,
            }
        };
        // SAFETY: `out` passed `check_out`.
        unsafe { create(&a, out) }
    })
}

/// Validates and creates a mesh from its faces, as finite-volume codes store it (OpenFOAM's
/// polyMesh, code_saturne): the arrays are copied.
///
/// - `dim`, `num_vertices`, `coords`: as `meshmove_mesh_create`.
/// - Faces (at most `MESHMOVE_MAX_VERTICES`): face f's vertices are
///   `face_connectivity[face_offsets[f] .. face_offsets[f + 1]]` (`num_faces + 1` positions from
///   0 to `num_face_vertices`): in 3D a loop of at least 3 whose right-hand normal points out of
///   its owner cell `face_owner[f]` into its neighbour `face_neighbour[f]`; in 2D a segment
///   whose normal (dy, -dx) does. A neighbour below `index_base` (-1 in C, 0 or -1 in Fortran)
///   marks a boundary face. `face_patch[f]`: the patch of a boundary face (>= 0); on an interior
///   face -1, or a patch id that tags it as an interface.
/// - Cells are numbered from `index_base` to `num_cells` (at most `MESHMOVE_MAX_CELLS`); each
///   must own or neighbour a face. `cell_region`: NULL, or one region id per cell.
///
/// Each cell is recognised as a tetrahedron, hexahedron, wedge or pyramid (triangle or quad in
/// 2D) where its faces make one, else kept as a polyhedron (polygon); see docs/DESIGN.md §2 for
/// its corner order. Sizes and indices are checked (`MESHMOVE_STATUS_INVALID_ARGUMENT` names the
/// array), then the faces and the geometry (`MESHMOVE_STATUS_INVALID_MESH` names the face or
/// cell: a face of too few vertices, an owner or neighbour out of range, a boundary face
/// without a patch, a cell whose faces do not close it). On failure `*out` is NULL.
///
/// # Safety
/// Each non-NULL array must hold the number of elements stated; `out` must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_create_from_faces(
    dim: i32,
    num_vertices: i32,
    coords: *const f64,
    num_faces: i32,
    face_offsets: *const i32,
    num_face_vertices: i32,
    face_connectivity: *const i32,
    face_owner: *const i32,
    face_neighbour: *const i32,
    face_patch: *const i32,
    num_cells: i32,
    cell_region: *const i32,
    index_base: i32,
    out: *mut *mut meshmove_mesh,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_create_from_faces, {
        // SAFETY: the caller guarantees `out` is NULL (refused) or writable.
        unsafe { check_out(out, "out") }?;
        // SAFETY: the caller's contract for every array.
        let data = unsafe {
            faces_to_cells(
                dim,
                num_vertices,
                coords,
                num_faces,
                face_offsets,
                num_face_vertices,
                face_connectivity,
                face_owner,
                face_neighbour,
                face_patch,
                num_cells,
                cell_region,
                index_base,
                false,
            )
        }?;
        // The faces as given (checked by `faces_to_cells`).
        let nf = usize::try_from(num_faces).unwrap_or(0);
        let need = memory::mesh_bytes(data.dim, data.num_vertices(), data.num_cells(), data.cell_vertices.len(), nf);
        memory::check_available(need, 0, "the mesh")?;
        let base = handles::index_base(index_base)?;
        let mesh = Mesh::from_data(&data).map_err(|e| in_base(e, base))?;
        // SAFETY: `out` passed `check_out`.
        unsafe { hand_out(mesh, out) }
    })
}

/// The cells of a mesh given by its faces (`meshmove_mesh_create_from_faces`'s arrays,
/// checked and converted); in a `part` of a partitioned mesh a face may have its owner or its
/// neighbour on another rank (below `index_base`, with a patch below 0).
///
/// # Safety
/// As `meshmove_mesh_create_from_faces`.
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn faces_to_cells(
    dim: i32,
    num_vertices: i32,
    coords: *const f64,
    num_faces: i32,
    face_offsets: *const i32,
    num_face_vertices: i32,
    face_connectivity: *const i32,
    face_owner: *const i32,
    face_neighbour: *const i32,
    face_patch: *const i32,
    num_cells: i32,
    cell_region: *const i32,
    index_base: i32,
    part: bool,
) -> Result<MeshData, CError> {
    let dim = bounded(dim, "dim", 2, 3)?;
    let nv = vertex_count(num_vertices, dim)?;
    let nf = bounded(num_faces, "num_faces", 0, limits::MAX_VERTICES)?;
    let nc = bounded(num_cells, "num_cells", 0, limits::MAX_CELLS)?;
    let nfv = count(num_face_vertices, "num_face_vertices")?;
    let base = handles::index_base(index_base)?;
    // SAFETY: the caller guarantees that each non-NULL array holds the number of elements
    // stated by the counts (checked non-negative and bounded above); NULL is refused where
    // an array is required and its length is not 0.
    let (coords, offsets, vertices, owner, neighbour, patch, regions) = unsafe {
        (
            slice(coords, dim * nv, "coords")?,
            slice(face_offsets, nf + 1, "face_offsets")?,
            slice(face_connectivity, nfv, "face_connectivity")?,
            slice(face_owner, nf, "face_owner")?,
            slice(face_neighbour, nf, "face_neighbour")?,
            slice(face_patch, nf, "face_patch")?,
            (!cell_region.is_null()).then(|| slice(cell_region, nc, "cell_region")).transpose()?,
        )
    };
    let face_offsets = checked_offsets(offsets, nfv, "face_offsets", "num_face_vertices", |_, _| Ok(()))?;
    let b = base as i64;
    let vertex = |f: usize, v: i32| {
        let i = i64::from(v) - b;
        u32::try_from(i).ok().filter(|&i| (i as usize) < nv).ok_or(MeshError::FaceIndexOutOfRange {
            face: f,
            what: "vertex",
            index: i64::from(v),
            end: nv as i64 + b,
        })
    };
    let mut face_vertices = Vec::with_capacity(nfv);
    for f in 0..nf {
        for &v in &vertices[face_offsets[f] as usize..face_offsets[f + 1] as usize] {
            face_vertices.push(vertex(f, v).map_err(|e| in_base(e, base))?);
        }
    }
    let cell = |f: usize, c: i32, what: &'static str| {
        let i = i64::from(c) - b;
        if i >= nc as i64 || (what == "owner" && i < 0 && !part) {
            return Err(in_base(
                MeshError::FaceIndexOutOfRange { face: f, what, index: c.into(), end: nc as i64 + b },
                base,
            ));
        }
        Ok(i.max(-1))
    };
    let mut faces = crate::FaceMeshData {
        dim,
        coords: coords.to_vec(),
        face_offsets,
        face_vertices,
        patch: patch.to_vec(),
        regions: regions.map(<[i32]>::to_vec).unwrap_or_default(),
        ..Default::default()
    };
    for f in 0..nf {
        faces.owner.push(cell(f, owner[f], "owner")?);
        faces.neighbour.push(cell(f, neighbour[f], "neighbour")?);
    }
    let data = if part { faces.to_part_data() } else { faces.to_data() }.map_err(|e| in_base(e, base))?;
    if data.num_cells() != nc {
        let msg = format!("cell {} has no face (num_cells is {nc})", named(data.num_cells(), base));
        return Err(CError::new(meshmove_status::InvalidMesh, format!("invalid mesh: {msg}")));
    }
    Ok(data)
}

/// Validates and creates a 2D triangle mesh: `meshmove_mesh_create` for the common case.
///
/// `coords`: `2 num_vertices` doubles (x0, y0, x1, y1, ...). `cells`: `3 num_cells` vertex
/// indices in `index_base` (0 for C, 1 for Fortran), either orientation. `tagged_edges`:
/// `2 num_tagged` vertex indices and `tagged_patches`: `num_tagged` patch ids; boundary edges not
/// tagged are on patch 0, a tagged interior edge is an internal interface. `regions`: NULL or one
/// id per cell. The arrays are copied; the checks and statuses are those of
/// `meshmove_mesh_create`.
///
/// # Safety
/// Each non-NULL array must hold the number of elements stated; `out` must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_create_triangles(
    num_vertices: i32,
    coords: *const f64,
    num_cells: i32,
    cells: *const i32,
    index_base: i32,
    num_tagged: i32,
    tagged_edges: *const i32,
    tagged_patches: *const i32,
    regions: *const i32,
    out: *mut *mut meshmove_mesh,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_create_triangles, {
        // SAFETY: the caller guarantees `out` is NULL (refused) or writable.
        unsafe { check_out(out, "out") }?;
        let nv = vertex_count(num_vertices, 2)?;
        let nc = bounded(num_cells, "num_cells", 0, limits::MAX_CELLS)?;
        let nt = bounded(num_tagged, "num_tagged", 0, limits::MAX_VERTICES)?;
        let base = handles::index_base(index_base)?;
        // SAFETY: the caller guarantees that each non-NULL array holds the number of elements
        // stated (the counts are bounded, so 3 × cells and 2 × vertices fit); NULL is refused
        // where an array is required and its length is not 0.
        let (coords, cells, tagged_edges, tagged_patches, regions) = unsafe {
            (
                slice(coords, 2 * nv, "coords")?,
                slice(cells, 3 * nc, "cells")?,
                slice(tagged_edges, 2 * nt, "tagged_edges")?,
                slice(tagged_patches, nt, "tagged_patches")?,
                if regions.is_null() { None } else { Some(slice(regions, nc, "regions")?) },
            )
        };
        // Every pointer is checked before anything the counts size is allocated.
        memory::check_available(memory::mesh_bytes(2, nv, nc, 3 * nc, nt), 0, "the mesh")?;
        let triangles = vec![CellType::Triangle.vtk_id() as i32; nc];
        let a = Arrays {
            dim: 2,
            coords,
            cell_types: &triangles,
            cells: Csr { offsets: None, vertices: cells },
            faces: Csr { offsets: None, vertices: tagged_edges },
            face_patch: tagged_patches,
            regions,
            base,
        };
        // SAFETY: `out` passed `check_out`.
        unsafe { create(&a, out) }
    })
}

/// Vertices in the caller's numbering, as a list.
fn listed(v: &[u32], base: i32) -> String {
    let v: Vec<i64> = v.iter().map(|&v| named(v as usize, base)).collect();
    format!("{v:?}")
}

/// A mesh error in the caller's numbering: cells, vertices and faces counted from `base` (the
/// mesh's own messages count from 0). A dimension the core rejects is one it does not handle:
/// `MESHMOVE_STATUS_UNSUPPORTED` (the C layer has already checked that it is 2 or 3).
fn in_base(e: MeshError, base: i32) -> CError {
    let n = |i: &usize| named(*i, base);
    let msg = match &e {
        MeshError::Dimension { dim } => {
            return CError::unsupported(format!("a {dim}D mesh: this version of meshmove does not handle it yet"))
        }
        MeshError::CellTypeNotInDimension { cell, cell_type, dim } => {
            format!("cell {} is a {cell_type}, which is not a cell of a {dim}D mesh", n(cell))
        }
        MeshError::NonFiniteCoordinate { vertex, component, value } => {
            format!("vertex {} has a non-finite coordinate: component {component} is {value}", n(vertex))
        }
        MeshError::IndexOutOfRange { cell, index, base, end } => {
            format!("cell {} refers to vertex index {index}, outside {base}..{end}", n(cell))
        }
        MeshError::RepeatedVertex { cell, vertex } => format!("cell {} repeats vertex {}", n(cell), n(vertex)),
        MeshError::UnusedVertex { vertex } => format!("vertex {} is not used by any cell", n(vertex)),
        MeshError::DegenerateCell { cell, measure } => {
            format!("cell {} has zero area or volume ({measure:e})", n(cell))
        }
        MeshError::MeasureOutOfRange { cell, longest_edge, largest } => format!(
            "cell {}'s area or volume overflows or underflows double precision (longest edge {longest_edge:e}, \
             coordinates up to {largest:e}): express the mesh in units where cells are between about 1e-90 and 1e90 \
             long",
            n(cell)
        ),
        MeshError::NonManifoldFace { face, cells } => {
            format!("face {} is shared by {cells} cells; at most two may share a face", listed(face, base))
        }
        MeshError::TaggedIndexOutOfRange { edge, index, base, end } => {
            format!("tagged face {} refers to vertex index {index}, outside {base}..{end}", n(edge))
        }
        MeshError::TaggedFaceNotAFace { face, vertices } => {
            format!("tagged face {} {} is not a face of any cell", n(face), listed(vertices, base))
        }
        MeshError::TaggedFaceTwice { face, vertices, first, second } => {
            format!(
                "tagged face {} {} is tagged twice, with patches {first} and {second}",
                n(face),
                listed(vertices, base)
            )
        }
        MeshError::FaceSize { face, count, .. } => format!("face {} has {count} vertices", n(face)),
        MeshError::FaceIndexOutOfRange { face, what, index, end } => {
            format!("face {}'s {what} is {index}, outside {base}..{end}", n(face))
        }
        MeshError::BoundaryFaceWithoutPatch { face, patch } => {
            format!("face {} is a boundary face (no neighbour) without a patch (patch id {patch})", n(face))
        }
        MeshError::OpenCell { cell, from, to, .. } => format!(
            "the faces of cell {} do not close it at its side {} -> {}",
            n(cell),
            n(&(*from as usize)),
            n(&(*to as usize))
        ),
        MeshError::FaceBasedCell { cell, problem } => format!("cell {}: {problem}", n(cell)),
        MeshError::Overlap { first, second, face } => format!(
            "cells {} and {} lie on the same side of their shared face {}: the mesh overlaps itself",
            n(first),
            n(second),
            listed(face, base)
        ),
        _ => return e.into(),
    };
    CError::new(meshmove_status::InvalidMesh, format!("invalid mesh: {msg} (numbered from {base}, as given)"))
}

/// Reads a Gmsh `.msh` file (2.2 or 4.1, ASCII or binary), 2D or 3D: the elements of the mesh's
/// dimension become cells with their physical tag as region, those one dimension lower tagged
/// faces with their physical tag as patch (Gmsh's prisms become VTK wedges).
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string; `out` must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_read_msh(path: *const c_char, out: *mut *mut meshmove_mesh) -> meshmove_status {
    ffi_body!(meshmove_mesh_read_msh, {
        // SAFETY: the caller guarantees `out` is NULL (refused) or writable.
        unsafe { check_out(out, "out") }?;
        // SAFETY: the caller guarantees `path` is NULL (refused) or a NUL-terminated string.
        let p = unsafe { handles::path(path, "path") }?;
        let m = crate::io::read_msh(std::path::Path::new(p))?;
        // SAFETY: `out` passed `check_out`.
        unsafe { hand_out(m.mesh, out) }
    })
}

/// Frees a mesh. NULL is accepted and does nothing; a freed or foreign handle is reported
/// (`MESHMOVE_STATUS_INVALID_HANDLE`) and nothing is freed.
///
/// # Safety
/// `mesh` must be NULL or a pointer received from meshmove (checked against the live handles).
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_free(mesh: *mut meshmove_mesh) -> meshmove_status {
    ffi_body!(meshmove_mesh_free, { handles::free(mesh, "mesh") })
}

/// Writes counts to optional outputs (NULL: skipped): every pointer is checked before any is
/// written.
///
/// # Safety
/// Each non-NULL pointer must be valid for writing one `int32_t`.
pub(crate) unsafe fn write_counts(outs: &[(*mut i32, usize, &str)]) -> Result<(), CError> {
    for &(p, _, what) in outs {
        if !p.is_null() {
            handles::check_aligned(p, what)?;
        }
    }
    for &(p, v, what) in outs {
        // SAFETY: NULL or aligned and writable (this function's contract); counts are bounded by
        // the `MESHMOVE_MAX_*` limits, so they fit.
        unsafe { handles::write_opt(p, v.min(i32::MAX as usize) as i32, what) }?;
    }
    Ok(())
}

/// The sizes of a mesh (any pointer may be NULL): its dimension, vertices, cells, the length of
/// its cell connectivity (what `meshmove_mesh_get_cells` returns), and its faces and their
/// connectivity's length (every boundary and interface face, those on patch 0 included: what
/// `meshmove_mesh_get_faces` returns).
///
/// # Safety
/// Non-NULL pointers must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_sizes(
    mesh: *const meshmove_mesh,
    dim: *mut i32,
    num_vertices: *mut i32,
    num_cells: *mut i32,
    num_cell_vertices: *mut i32,
    num_faces: *mut i32,
    num_face_vertices: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_sizes, {
        let m = get(mesh, "mesh")?;
        // SAFETY: the caller guarantees non-NULL pointers are writable.
        unsafe {
            write_counts(&[
                (dim, points::dim_of(&m), "dim"),
                (num_vertices, m.num_vertices(), "num_vertices"),
                (num_cells, m.num_cells(), "num_cells"),
                (num_cell_vertices, m.num_cell_corners(), "num_cell_vertices"),
                (num_faces, m.num_patch_faces(), "num_faces"),
                (num_face_vertices, m.num_patch_face_vertices(), "num_face_vertices"),
            ])
        }
    })
}

/// Copies the coordinates (x0, y0, (z0,) x1, ...) into `coords`, `len` = dim × vertices.
///
/// # Safety
/// `coords` must hold `len` doubles.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_get_coords(
    mesh: *const meshmove_mesh,
    len: i32,
    coords: *mut f64,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_get_coords, {
        let m = get(mesh, "mesh")?;
        // SAFETY: the caller guarantees `coords` holds `len` doubles; `write` after `check_out`.
        unsafe {
            points::check_out(coords, len, points::dim_of(&m), m.num_vertices(), "coords")?;
            points::write(coords, m.coords());
        }
        Ok(())
    })
}

/// An optional output array: NULL with `len` 0 skips it, otherwise `len` must be `want`.
///
/// # Safety
/// A non-NULL `p` must hold `len` writable elements.
pub(super) unsafe fn out_array<'a>(
    p: *mut i32,
    len: i32,
    want: usize,
    what: &str,
    of: &str,
) -> Result<Option<&'a mut [i32]>, CError> {
    let n = count(len, &format!("{what} length"))?;
    if p.is_null() && n == 0 {
        return Ok(None);
    }
    if n != want {
        return Err(CError::arg(format!("`{what}` has length {n}; {of}, so {want} are needed (or NULL with 0)")));
    }
    // SAFETY: `p` holds `len` = `n` writable elements (this function's contract).
    Ok(Some(unsafe { slice_mut(p, n, what) }?))
}

/// `meshmove_mesh_get_cells` (`faces` false) and `_get_faces`: copies the cells' (faces') CSR list,
/// vertex indices plus `index_base`, and one value per cell (face: its type, its patch) into the
/// caller's optional arrays, every length checked before anything is written.
///
/// # Safety
/// Each non-NULL pointer of `outs` must hold its stated number of writable `int32_t`.
unsafe fn get_lists(
    mesh: *const meshmove_mesh,
    index_base: i32,
    faces: bool,
    outs: [(i32, *mut i32); 3],
) -> Result<(), CError> {
    let m = get(mesh, "mesh")?;
    let base = handles::index_base(index_base)?;
    // The items (cells or patch faces), their vertex count together, and each one's vertices and
    // value (its VTK type, or its patch).
    let (n, corners, what, last) = if faces {
        (m.num_patch_faces(), m.num_patch_face_vertices(), "faces", "patches")
    } else {
        (m.num_cells(), m.num_cell_corners(), "cells", "types")
    };
    let item = |i: usize| if faces { m.patch_face(i).vertices } else { m.cell(i) };
    let value = |i: usize| if faces { m.patch_face(i).patch } else { i32::from(m.cell_type(i).vtk_id()) };
    let of = format!("the mesh has {n} {what} and {corners} vertex indices in them");
    let mut arrays = Vec::with_capacity(3);
    for ((len, p), (want, name)) in outs.into_iter().zip([(n + 1, "offsets"), (corners, "connectivity"), (n, last)]) {
        // SAFETY: the caller guarantees a non-NULL `p` holds `len` writable elements.
        arrays.push(unsafe { out_array(p, len, want, name, &of) }?);
    }
    let [offsets, connectivity, values] = <[_; 3]>::try_from(arrays).expect("three arrays");
    if let Some(o) = offsets {
        o[0] = 0;
        for i in 0..n {
            o[i + 1] = o[i] + item(i).len() as i32;
        }
    }
    if let Some(c) = connectivity {
        for (c, &v) in c.iter_mut().zip((0..n).flat_map(item)) {
            *c = v as i32 + base;
        }
    }
    if let Some(t) = values {
        for (i, t) in t.iter_mut().enumerate() {
            *t = value(i);
        }
    }
    Ok(())
}

/// Copies the cells as `meshmove_mesh_create` takes them: `offsets` (`num_offsets` = cells + 1,
/// from 0), `connectivity` (`num_connectivity` = the connectivity length of
/// `meshmove_mesh_sizes`; vertex indices in `index_base`, every cell oriented like the first) and
/// `types` (`num_types` = cells, `meshmove_cell_type` values). Any of the three may be NULL with
/// its length 0 to skip it.
///
/// # Safety
/// Each non-NULL array must hold its stated number of `int32_t`.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_get_cells(
    mesh: *const meshmove_mesh,
    index_base: i32,
    num_offsets: i32,
    offsets: *mut i32,
    num_connectivity: i32,
    connectivity: *mut i32,
    num_types: i32,
    types: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_get_cells, {
        let outs = [(num_offsets, offsets), (num_connectivity, connectivity), (num_types, types)];
        // SAFETY: the caller guarantees each non-NULL array holds its stated length.
        unsafe { get_lists(mesh, index_base, false, outs) }
    })
}

/// Copies the faces on patches (every boundary face, on patch 0 when it was not tagged, and every
/// tagged interior face) as `meshmove_mesh_create` takes them: `offsets` (`num_offsets` =
/// faces + 1, from 0), `connectivity` (vertex indices in `index_base`; boundary faces oriented
/// with the mesh on their left in 2D) and `patches` (`num_patches` = faces). Any of the three may
/// be NULL with its length 0 to skip it.
///
/// # Safety
/// Each non-NULL array must hold its stated number of `int32_t`.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_get_faces(
    mesh: *const meshmove_mesh,
    index_base: i32,
    num_offsets: i32,
    offsets: *mut i32,
    num_connectivity: i32,
    connectivity: *mut i32,
    num_patches: i32,
    patches: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_get_faces, {
        let outs = [(num_offsets, offsets), (num_connectivity, connectivity), (num_patches, patches)];
        // SAFETY: the caller guarantees each non-NULL array holds its stated length.
        unsafe { get_lists(mesh, index_base, true, outs) }
    })
}

/// Copies the region id of every cell into `regions`, `len` = cells.
///
/// # Safety
/// `regions` must hold `len` integers.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_get_regions(
    mesh: *const meshmove_mesh,
    len: i32,
    regions: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_get_regions, {
        let m = get(mesh, "mesh")?;
        let n = count(len, "len")?;
        if n != m.num_cells() {
            return Err(CError::arg(format!("len is {n}; the mesh has {} cells", m.num_cells())));
        }
        // SAFETY: the caller guarantees `regions` holds `len` = `n` integers.
        unsafe { slice_mut(regions, n, "regions") }?.copy_from_slice(m.regions());
        Ok(())
    })
}

/// The sorted vertices (in `index_base`) lying on `patch`. `*count` receives how many there are;
/// if `capacity` is smaller (e.g. 0 with `vertices` NULL, to ask the size), nothing is copied
/// and `MESHMOVE_STATUS_BUFFER_TOO_SMALL` is returned. A patch not in the mesh has 0 vertices.
///
/// # Safety
/// `vertices` must hold `capacity` integers; `count` must be writable.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_patch_vertices(
    mesh: *const meshmove_mesh,
    patch: i32,
    index_base: i32,
    capacity: i32,
    vertices: *mut i32,
    count: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_patch_vertices, {
        let m = get(mesh, "mesh")?;
        let b = handles::index_base(index_base)?;
        let cap = handles::count(capacity, "capacity")?;
        if count.is_null() {
            return Err(CError::null("count"));
        }
        let v = m.patch_vertices(patch);
        // SAFETY: `count` is not NULL; the caller guarantees it is writable.
        unsafe { handles::write_out(count, v.len() as i32, "count") }?;
        if cap < v.len() {
            return Err(CError::new(
                meshmove_status::BufferTooSmall,
                format!("patch {patch} has {} vertices; capacity is {cap}", v.len()),
            ));
        }
        // SAFETY: the caller guarantees `vertices` holds `capacity` >= `v.len()` integers.
        let out = unsafe { slice_mut(vertices, v.len(), "vertices") }?;
        for (o, &x) in out.iter_mut().zip(&v) {
            *o = x as i32 + b;
        }
        Ok(())
    })
}

/// Writes the mesh moved by `displacement` (`len` = dim × vertices; NULL with `len` 0 for none)
/// as a VTK `.vtu` file with point data `displacement` and cell data `region`, `area_ratio`,
/// `inverted` and `min_angle`.
///
/// # Safety
/// `path` must be a NUL-terminated string; `displacement` must hold `len` doubles.
#[no_mangle]
#[must_use]
pub unsafe extern "C" fn meshmove_mesh_write_vtu(
    mesh: *const meshmove_mesh,
    path: *const c_char,
    len: i32,
    displacement: *const f64,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_write_vtu, {
        let m = get(mesh, "mesh")?;
        // SAFETY: the caller guarantees `path` is a NUL-terminated string and `displacement`
        // holds `len` doubles.
        unsafe { write_vtu(&m, path, len, displacement) }
    })
}

/// `meshmove_mesh_write_vtu` and `meshmove_solver_write_vtu`: `m` moved by `displacement`.
///
/// # Safety
/// `path` must be NULL (refused) or a NUL-terminated string; a non-NULL `displacement` must hold
/// `len` doubles.
pub(crate) unsafe fn write_vtu(
    m: &Mesh,
    path: *const c_char,
    len: i32,
    displacement: *const f64,
) -> Result<(), CError> {
    // SAFETY: this function's contract.
    let p = unsafe { handles::path(path, "path") }?;
    let d = if len == 0 && displacement.is_null() {
        points::zeros(m.dim(), m.num_vertices())
    } else {
        // SAFETY: `displacement` holds `len` doubles (this function's contract).
        unsafe { points::read(displacement, len, points::dim_of(m), m.num_vertices(), "displacement") }?
    };
    points::finite_in(&d, m.dim(), "displacement")?;
    crate::io::write_deformed(std::path::Path::new(p), m, &d)?;
    Ok(())
}
