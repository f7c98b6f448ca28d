//! `meshmove_mesh`: a validated triangle mesh with patches and regions.

use super::error::CError;
use super::handles::{self, check_out, count, get, hand_out, path, slice, Handle, Slot};
use super::status::meshmove_status;
use super::types::bounded;
use crate::cases::meshes;
use crate::{Mesh, MeshError};
use glam::DVec2;
use std::ffi::c_char;

/// An immutable triangle mesh (vertices, cells, boundary and interface patches, regions).
/// Create with `meshmove_mesh_create`, `meshmove_mesh_create_case` or `meshmove_mesh_read_msh`;
/// free with `meshmove_mesh_free`. A solver keeps its own copy: the mesh may be freed after
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

/// `meshmove_mesh_create_case("free_surface", h)`: the bottom, y = −1.
pub const MESHMOVE_FS_BOTTOM: i32 = 1;
/// `"free_surface"`: the right side x = 1 (same y as the left side's vertices).
pub const MESHMOVE_FS_RIGHT: i32 = 2;
/// `"free_surface"`: the top y = 0, the free surface.
pub const MESHMOVE_FS_TOP: i32 = 3;
/// `"free_surface"`: the left side x = 0.
pub const MESHMOVE_FS_LEFT: i32 = 4;
/// `"two_region_interface"`: the bottom, y = −1.
pub const MESHMOVE_IF_BOTTOM: i32 = 1;
/// `"two_region_interface"`: both right sides, x = 1.
pub const MESHMOVE_IF_RIGHT: i32 = 2;
/// `"two_region_interface"`: the interface y = 0 (interior edges between regions 0 and 1).
pub const MESHMOVE_IF_INTERFACE: i32 = 3;
/// `"two_region_interface"`: both left sides, x = 0.
pub const MESHMOVE_IF_LEFT: i32 = 4;
/// `"two_region_interface"`: the top, y = +1.
pub const MESHMOVE_IF_TOP: i32 = 5;
/// `"cylinder_channel"`: the four channel walls of `[0,8]×[−1,1]`.
pub const MESHMOVE_CH_WALL: i32 = 1;
/// `"cylinder_channel"`: the cylinder of diameter 1 about (2, 0).
pub const MESHMOVE_CH_CYLINDER: i32 = 2;

/// Validates and creates a mesh (at most `MESHMOVE_MAX_VERTICES` vertices,
/// `MESHMOVE_MAX_CELLS` cells and `MESHMOVE_MAX_VERTICES` tagged edges).
///
/// `coords`: `2 num_vertices` doubles (x0, y0, x1, y1, ...). `cells`: `3 num_cells` vertex
/// indices in `index_base` (0 for C, 1 for Fortran), either orientation. `tagged_edges`:
/// `2 num_tagged` vertex indices and `tagged_patches`: `num_tagged` patch ids; boundary edges not
/// tagged are on patch 0, a tagged interior edge is an internal interface. `regions`: NULL or one
/// id per cell. The arrays are copied. On failure `*out` is NULL and the status says why
/// (`MESHMOVE_STATUS_INVALID_MESH` names the offending cell, edge or vertex).
///
/// # Safety
/// Each non-NULL array must hold the number of elements stated; `out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn meshmove_mesh_create(
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
    ffi_body!(meshmove_mesh_create, {
        check_out(out, "out")?;
        let nv = bounded(num_vertices, "num_vertices", 0, crate::limits::MAX_VERTICES)?;
        let nc = bounded(num_cells, "num_cells", 0, crate::limits::MAX_CELLS)?;
        let nt = bounded(num_tagged, "num_tagged", 0, crate::limits::MAX_VERTICES)?;
        let base = handles::index_base(index_base)?;
        let xy = slice(coords, 2 * nv, "coords")?;
        let cv = slice(cells, 3 * nc, "cells")?;
        let te = slice(tagged_edges, 2 * nt, "tagged_edges")?;
        let tp = slice(tagged_patches, nt, "tagged_patches")?;
        let reg = if regions.is_null() { None } else { Some(slice(regions, nc, "regions")?) };
        let xy: Vec<[f64; 2]> = xy.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
        let tris: Vec<[i32; 3]> = cv.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let tagged: Vec<([i32; 2], i32)> = te.chunks_exact(2).zip(tp).map(|(e, &p)| ([e[0], e[1]], p)).collect();
        let mesh = Mesh::new(&xy, &tris, base, &tagged, reg).map_err(|e| in_base(e, index_base))?;
        hand_out(mesh, out)
    })
}

/// A mesh error in the caller's numbering: cells, vertices and tagged edges counted from `base`
/// (the mesh's own messages count from 0).
fn in_base(e: MeshError, base: i32) -> CError {
    let n = |i: &usize| *i as i64 + i64::from(base);
    let msg = match &e {
        MeshError::NonFiniteCoordinate { vertex, x, y } => {
            format!("vertex {} has a non-finite coordinate ({x}, {y})", n(vertex))
        }
        MeshError::IndexOutOfRange { cell, index, base, end } => {
            format!("cell {} refers to vertex index {index}, outside {base}..{end}", n(cell))
        }
        MeshError::RepeatedVertex { cell, vertex } => format!("cell {} repeats vertex {}", n(cell), n(vertex)),
        MeshError::UnusedVertex { vertex } => format!("vertex {} is not used by any cell", n(vertex)),
        MeshError::DegenerateCell { cell, area } => format!("cell {} has zero area ({area:e})", n(cell)),
        MeshError::NonManifoldEdge { a, b, cells } => {
            format!("edge ({}, {}) is shared by {cells} cells; at most two may share an edge", n(a), n(b))
        }
        MeshError::TaggedIndexOutOfRange { edge, index, base, end } => {
            format!("tagged edge {} refers to vertex index {index}, outside {base}..{end}", n(edge))
        }
        MeshError::TaggedEdgeNotAnEdge { edge, a, b } => {
            format!("tagged edge {} ({}, {}) is not an edge of any cell", n(edge), n(a), n(b))
        }
        MeshError::TaggedEdgeTwice { edge, a, b, first, second } => {
            format!("tagged edge {} ({}, {}) is tagged twice, with patches {first} and {second}", n(edge), n(a), n(b))
        }
        _ => return e.into(),
    };
    CError::new(meshmove_status::InvalidMesh, format!("invalid mesh: {msg} (numbered from {base}, as given)"))
}

/// Creates one of the paper's test meshes with edge length about `h`: `"free_surface"`
/// (`[0,1]×[−1,0]`, patches `MESHMOVE_FS_*`, 0 < h ≤ 1/2), `"two_region_interface"`
/// (`[0,1]×[−1,1]`, regions 0 and 1, patches `MESHMOVE_IF_*`, 0 < h ≤ 1/2) or
/// `"cylinder_channel"` (`[0,8]×[−1,1]` minus a cylinder, patches `MESHMOVE_CH_*`, 0 < h ≤ 1/4).
/// h below 1/1024 is refused (the mesh would not fit in memory comfortably).
///
/// # Safety
/// `name` must be NULL or a NUL-terminated string; `out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn meshmove_mesh_create_case(
    name: *const c_char,
    h: f64,
    out: *mut *mut meshmove_mesh,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_create_case, {
        check_out(out, "out")?;
        let name = path(name, "name")?;
        let hmax = match name {
            "free_surface" | "two_region_interface" => 0.5,
            "cylinder_channel" => 0.25,
            _ => {
                return Err(CError::arg(format!(
                    "unknown case \"{name}\" (free_surface, two_region_interface, cylinder_channel)"
                )))
            }
        };
        if !(h >= 1.0 / 1024.0 && h <= hmax) {
            return Err(CError::arg(format!("h is {h}; case \"{name}\" needs 1/1024 <= h <= {hmax}")));
        }
        let mesh = match name {
            "free_surface" => meshes::free_surface(h),
            "two_region_interface" => meshes::two_region_interface(h),
            _ => meshes::cylinder_channel(h),
        };
        hand_out(mesh, out)
    })
}

/// Reads a Gmsh `.msh` file (2.2 or 4.1, ASCII or binary): triangles become cells with their
/// physical tag as region, lines tagged edges with their physical tag as patch.
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string; `out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn meshmove_mesh_read_msh(path: *const c_char, out: *mut *mut meshmove_mesh) -> meshmove_status {
    ffi_body!(meshmove_mesh_read_msh, {
        check_out(out, "out")?;
        let p = handles::path(path, "path")?;
        let m = crate::io::read_msh(std::path::Path::new(p))?;
        hand_out(m.mesh, out)
    })
}

/// Frees a mesh. NULL is accepted and does nothing; a freed or foreign handle is reported
/// (`MESHMOVE_STATUS_INVALID_HANDLE`) and nothing is freed.
///
/// # Safety
/// `mesh` must be NULL or a pointer received from meshmove (checked against the live handles).
#[no_mangle]
pub unsafe extern "C" fn meshmove_mesh_free(mesh: *mut meshmove_mesh) -> meshmove_status {
    ffi_body!(meshmove_mesh_free, { handles::free(mesh, "mesh") })
}

/// Number of vertices and cells of a mesh (either pointer may be NULL).
///
/// # Safety
/// Non-NULL pointers must be writable.
#[no_mangle]
pub unsafe extern "C" fn meshmove_mesh_sizes(
    mesh: *const meshmove_mesh,
    num_vertices: *mut i32,
    num_cells: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_sizes, {
        let m = get(mesh, "mesh")?;
        if !num_vertices.is_null() {
            handles::write_out(num_vertices, m.num_vertices() as i32, "num_vertices")?;
        }
        if !num_cells.is_null() {
            handles::write_out(num_cells, m.num_cells() as i32, "num_cells")?;
        }
        Ok(())
    })
}

/// Copies the coordinates (x0, y0, x1, y1, ...) into `coords`, `len` = 2 × vertices.
///
/// # Safety
/// `coords` must hold `len` doubles.
#[no_mangle]
pub unsafe extern "C" fn meshmove_mesh_get_coords(
    mesh: *const meshmove_mesh,
    len: i32,
    coords: *mut f64,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_get_coords, {
        let m = get(mesh, "mesh")?;
        handles::check_xy_out(coords, len, m.num_vertices(), "coords")?;
        handles::write_xy(coords, m.coords());
        Ok(())
    })
}

/// Copies the cells (3 vertex indices each, counter-clockwise, in `index_base`) into `cells`,
/// `len` = 3 × cells.
///
/// # Safety
/// `cells` must hold `len` integers.
#[no_mangle]
pub unsafe extern "C" fn meshmove_mesh_get_cells(
    mesh: *const meshmove_mesh,
    index_base: i32,
    len: i32,
    cells: *mut i32,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_get_cells, {
        let m = get(mesh, "mesh")?;
        let b = handles::index_base(index_base)? as i32;
        let n = count(len, "len")?;
        if n != 3 * m.num_cells() {
            return Err(CError::arg(format!(
                "len is {n}; the mesh has {} cells, so {} are needed",
                m.num_cells(),
                3 * m.num_cells()
            )));
        }
        let out = handles::slice_mut(cells, n, "cells")?;
        for (o, c) in out.chunks_exact_mut(3).zip(m.cells()) {
            for k in 0..3 {
                o[k] = c[k] as i32 + b;
            }
        }
        Ok(())
    })
}

/// Copies the region id of every cell into `regions`, `len` = cells.
///
/// # Safety
/// `regions` must hold `len` integers.
#[no_mangle]
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
        handles::slice_mut(regions, n, "regions")?.copy_from_slice(m.regions());
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
        let b = handles::index_base(index_base)? as i32;
        let cap = handles::count(capacity, "capacity")?;
        if count.is_null() {
            return Err(CError::null("count"));
        }
        let v = m.patch_vertices(patch);
        handles::write_out(count, v.len() as i32, "count")?;
        if cap < v.len() {
            return Err(CError::new(
                meshmove_status::BufferTooSmall,
                format!("patch {patch} has {} vertices; capacity is {cap}", v.len()),
            ));
        }
        let out = handles::slice_mut(vertices, v.len(), "vertices")?;
        for (o, &x) in out.iter_mut().zip(&v) {
            *o = x as i32 + b;
        }
        Ok(())
    })
}

/// Writes the mesh moved by `displacement` (`len` = 2 × vertices; NULL with `len` 0 for none)
/// as a VTK `.vtu` file with point data `displacement` and cell data `region`, `area_ratio`,
/// `inverted` and `min_angle`.
///
/// # Safety
/// `path` must be a NUL-terminated string; `displacement` must hold `len` doubles.
#[no_mangle]
pub unsafe extern "C" fn meshmove_mesh_write_vtu(
    mesh: *const meshmove_mesh,
    path: *const c_char,
    len: i32,
    displacement: *const f64,
) -> meshmove_status {
    ffi_body!(meshmove_mesh_write_vtu, {
        let m = get(mesh, "mesh")?;
        let p = handles::path(path, "path")?;
        write_vtu(&m, p, len, displacement)
    })
}

pub(crate) unsafe fn write_vtu(m: &Mesh, p: &str, len: i32, displacement: *const f64) -> Result<(), CError> {
    let d = if len == 0 && displacement.is_null() {
        vec![DVec2::ZERO; m.num_vertices()]
    } else {
        handles::read_xy(displacement, len, m.num_vertices(), "displacement")?
    };
    handles::finite_xy(&d, "displacement")?;
    let d: Vec<f64> = d.iter().flat_map(|v| v.to_array()).collect();
    crate::io::write_deformed(std::path::Path::new(p), m, &d)?;
    Ok(())
}
