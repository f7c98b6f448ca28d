//! The `.vtu` reader: one piece of cells; ascii, inline base64 or appended arrays, zlib or not.

use super::VtuData;
use crate::geometry::CellType;
use crate::io::{io_err, line_of, IoError};
use crate::mesh::MeshData;
use base64::Engine as _;
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::io::Read as _;
use std::path::Path;

/// Reads a `.vtu` file: one piece of cells (see the module documentation for the encodings).
pub fn read_vtu(path: &Path) -> Result<VtuData, IoError> {
    let bytes = std::fs::read(path).map_err(io_err(path))?;
    parse_vtu(&bytes)
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Section {
    None,
    PointData,
    CellData,
    Points,
    Cells,
    FieldData,
}

impl Section {
    fn tag(self) -> &'static str {
        match self {
            Section::None => "<Piece>",
            Section::PointData => "<PointData>",
            Section::CellData => "<CellData>",
            Section::Points => "<Points>",
            Section::Cells => "<Cells>",
            Section::FieldData => "<FieldData>",
        }
    }
}

struct Array {
    section: Section,
    ty: String,
    name: Option<String>,
    comps: usize,
    format: String,
    /// `offset` of an appended array.
    offset: Option<usize>,
    /// Offset of the `<DataArray` tag and of its text.
    at: usize,
    text_at: usize,
    text: String,
}

impl Array {
    fn label(&self) -> String {
        match &self.name {
            Some(s) => format!("DataArray `{s}` in {}", self.section.tag()),
            None => format!("DataArray in {}", self.section.tag()),
        }
    }
}

/// The data of `<AppendedData>`: from after its `_` to `end` (the end of the file for raw data,
/// the closing tag for base64).
struct Appended {
    start: usize,
    end: usize,
    base64: bool,
}

struct Ctx<'a> {
    b: &'a [u8],
    header64: bool,
    big_endian: bool,
    /// Compressed by `vtkZLibDataCompressor`.
    zlib: bool,
    appended: Option<Appended>,
    /// The `offset`s of the appended arrays, ascending (where each base64 run ends).
    offsets: Vec<usize>,
}

/// Where something is in the file: the text at a byte offset (reported by line), or binary data
/// at a byte offset (reported by offset).
#[derive(Clone, Copy)]
enum Pos {
    Text(usize),
    Byte(usize),
}

impl Ctx<'_> {
    fn err(&self, at: usize, message: String) -> IoError {
        IoError::Parse { line: line_of(self.b, at), offset: Some(at), message }
    }

    fn err_pos(&self, pos: Pos, message: String) -> IoError {
        match pos {
            Pos::Text(at) => self.err(at, message),
            Pos::Byte(at) => IoError::Parse { line: 0, offset: Some(at), message },
        }
    }

    /// Size of the header integers.
    fn hsize(&self) -> usize {
        if self.header64 {
            8
        } else {
            4
        }
    }

    /// A header integer (`hsize` bytes in the file's byte order).
    fn uint(&self, b: &[u8]) -> u64 {
        let mut a = [0u8; 8];
        a[..b.len()].copy_from_slice(b);
        if self.big_endian {
            a[..b.len()].reverse();
        }
        u64::from_le_bytes(a)
    }
}

fn attr(e: &BytesStart, name: &str, ctx: &Ctx, at: usize) -> Result<Option<String>, IoError> {
    match e.try_get_attribute(name) {
        Ok(Some(a)) => a
            .unescape_value()
            .map(|v| Some(v.into_owned()))
            .map_err(|x| ctx.err(at, format!("attribute `{name}` of <{}>: {x}", tag_name(e)))),
        Ok(None) => Ok(None),
        Err(x) => Err(ctx.err(at, format!("attributes of <{}>: {x}", tag_name(e)))),
    }
}

fn tag_name(e: &BytesStart) -> String {
    String::from_utf8_lossy(e.name().as_ref()).into_owned()
}

fn req_usize(e: &BytesStart, name: &str, ctx: &Ctx, at: usize) -> Result<usize, IoError> {
    let v =
        attr(e, name, ctx, at)?.ok_or_else(|| ctx.err(at, format!("<{}> has no attribute `{name}`", tag_name(e))))?;
    v.trim().parse().map_err(|_| ctx.err(at, format!("attribute `{name}` of <{}> is `{v}`, not a count", tag_name(e))))
}

fn opt_usize(e: &BytesStart, name: &str, ctx: &Ctx, at: usize) -> Result<Option<usize>, IoError> {
    match attr(e, name, ctx, at)? {
        None => Ok(None),
        Some(_) => req_usize(e, name, ctx, at).map(Some),
    }
}

/// Parses the contents of a `.vtu` file.
pub fn parse_vtu(bytes: &[u8]) -> Result<VtuData, IoError> {
    // The XML runs up to the end of the <AppendedData> tag: raw data after it is not text.
    let xml_end = match bytes.windows(13).position(|w| w == b"<AppendedData") {
        Some(p) => bytes[p..].iter().position(|&c| c == b'>').map_or(bytes.len(), |q| p + q + 1),
        None => bytes.len(),
    };
    let text = std::str::from_utf8(&bytes[..xml_end]).map_err(|e| IoError::Parse {
        line: line_of(bytes, e.valid_up_to()),
        offset: Some(e.valid_up_to()),
        message: "the XML of the file is not UTF-8 text".into(),
    })?;
    let mut ctx =
        Ctx { b: bytes, header64: false, big_endian: false, zlib: false, appended: None, offsets: Vec::new() };
    let mut reader = Reader::from_str(text);
    let mut counts: Option<(usize, usize)> = None;
    let mut section = Section::None;
    let mut arrays: Vec<Array> = Vec::new();
    // The DataArray being read, and how deep inside it the reader is (<InformationKey>, ...).
    let mut array: Option<Array> = None;
    let mut nested = 0usize;
    let mut seen_file = false;
    let mut seen_points = false;
    let mut piece_end = None;
    loop {
        let at = reader.buffer_position() as usize;
        let ev = reader.read_event().map_err(|e| ctx.err(at, format!("malformed XML: {e}")))?;
        match ev {
            Event::Start(_) | Event::Empty(_) if array.is_some() => {
                nested += usize::from(matches!(ev, Event::Start(_)));
            }
            Event::Start(ref e) | Event::Empty(ref e) => {
                let empty = matches!(ev, Event::Empty(_));
                match e.name().as_ref() {
                    b"VTKFile" => {
                        seen_file = true;
                        let ty = attr(e, "type", &ctx, at)?;
                        if ty.as_deref() != Some("UnstructuredGrid") {
                            return Err(IoError::Unsupported(format!(
                                "VTKFile type {ty:?}; only UnstructuredGrid is read"
                            )));
                        }
                        match attr(e, "compressor", &ctx, at)?.as_deref() {
                            None | Some("") => {}
                            Some("vtkZLibDataCompressor") => ctx.zlib = true,
                            Some(c) => {
                                return Err(IoError::Unsupported(format!(
                                    "data compressed by {c}; only vtkZLibDataCompressor is read"
                                )))
                            }
                        }
                        ctx.big_endian = attr(e, "byte_order", &ctx, at)?.as_deref() == Some("BigEndian");
                        ctx.header64 = attr(e, "header_type", &ctx, at)?.as_deref() == Some("UInt64");
                    }
                    b"Piece" => {
                        if counts.is_some() {
                            return Err(IoError::Unsupported("more than one <Piece>".into()));
                        }
                        counts =
                            Some((req_usize(e, "NumberOfPoints", &ctx, at)?, req_usize(e, "NumberOfCells", &ctx, at)?));
                    }
                    b"PointData" if !empty => section = Section::PointData,
                    b"CellData" if !empty => section = Section::CellData,
                    b"Points" if !empty => section = Section::Points,
                    b"Cells" if !empty => section = Section::Cells,
                    b"FieldData" if !empty => section = Section::FieldData,
                    b"Points" => seen_points = true,
                    b"DataArray" => {
                        if counts.is_none() && section != Section::FieldData {
                            return Err(ctx.err(at, "<DataArray> outside a <Piece>".into()));
                        }
                        let a = Array {
                            section,
                            ty: attr(e, "type", &ctx, at)?
                                .ok_or_else(|| ctx.err(at, "<DataArray> has no attribute `type`".into()))?,
                            name: attr(e, "Name", &ctx, at)?,
                            comps: opt_usize(e, "NumberOfComponents", &ctx, at)?.unwrap_or(1),
                            format: attr(e, "format", &ctx, at)?
                                .ok_or_else(|| ctx.err(at, "<DataArray> has no attribute `format`".into()))?,
                            offset: opt_usize(e, "offset", &ctx, at)?,
                            at,
                            text_at: reader.buffer_position() as usize,
                            text: String::new(),
                        };
                        if empty {
                            arrays.push(a);
                        } else {
                            array = Some(a);
                            nested = 0;
                        }
                    }
                    b"AppendedData" => ctx.appended = Some(appended_data(e, &ctx, at, xml_end)?),
                    _ => {}
                }
            }
            Event::Text(t) => {
                if let Some(a) = array.as_mut().filter(|_| nested == 0) {
                    if a.text.is_empty() {
                        a.text_at = at;
                    }
                    a.text.push_str(&String::from_utf8_lossy(&t));
                }
            }
            Event::End(e) => match e.name().as_ref() {
                _ if nested > 0 => nested -= 1,
                b"DataArray" => arrays.extend(array.take()),
                b"PointData" | b"CellData" | b"Points" | b"Cells" | b"FieldData" => section = Section::None,
                b"Piece" => piece_end = Some(at),
                _ => {}
            },
            Event::Eof => break,
            _ => {}
        }
    }
    if !seen_file {
        return Err(ctx.err(0, "no <VTKFile> element".into()));
    }
    let Some((n, m)) = counts else {
        return Err(ctx.err(bytes.len(), "no <Piece> element in <UnstructuredGrid>".into()));
    };
    ctx.offsets = arrays.iter().filter(|a| a.format == "appended").filter_map(|a| a.offset).collect();
    ctx.offsets.sort_unstable();

    let mut out = VtuData { mesh: MeshData::new(2), ..VtuData::default() };
    let mut points = None;
    let mut cells_arrays: Vec<(String, Vec<f64>, usize)> = Vec::new();
    let mut field_data: Vec<(String, Vec<f64>)> = Vec::new();
    let mut region_array = None;
    for a in &arrays {
        let cell_array =
            matches!(a.name.as_deref(), Some("connectivity" | "offsets" | "types" | "faces" | "faceoffsets"));
        match a.section {
            Section::None => continue,
            Section::Cells if !cell_array => continue,
            _ => {}
        }
        let label = a.label();
        if a.comps == 0 {
            return Err(ctx.err(a.at, format!("{label}: NumberOfComponents is 0")));
        }
        let values = decode(a, &label, &ctx)?;
        let tuples = match a.section {
            Section::Points | Section::PointData => Some(n),
            Section::CellData => Some(m),
            _ => None,
        };
        if let Some(t) = tuples {
            if values.len() != t * a.comps {
                return Err(ctx.err(
                    a.at,
                    format!(
                        "{label}: expected {} values ({t} tuples × {} components), found {}",
                        t * a.comps,
                        a.comps,
                        values.len()
                    ),
                ));
            }
        }
        match a.section {
            Section::Points => {
                if a.comps != 3 {
                    return Err(ctx.err(a.at, format!("{label}: NumberOfComponents is {}, 3 expected", a.comps)));
                }
                seen_points = true;
                points = Some(values);
            }
            Section::FieldData => {
                if let Some(name) = &a.name {
                    field_data.push((name.clone(), values));
                }
            }
            Section::PointData | Section::CellData => {
                let name = a.name.clone().ok_or_else(|| ctx.err(a.at, format!("{label}: no attribute `Name`")))?;
                if a.section == Section::CellData && name == "region" {
                    region_array = Some(regions(&values, a, &label, &ctx)?);
                }
                if a.section == Section::CellData && PATCH_ARRAYS.contains(&name.as_str()) {
                    check_ids(&values, a, &label, &ctx)?;
                }
                let list = if a.section == Section::PointData { &mut out.point_data } else { &mut out.cell_data };
                list.push((name, values, a.comps));
            }
            _ => cells_arrays.push((a.name.clone().unwrap_or_default(), values, a.at)),
        }
    }
    let end = piece_end.unwrap_or(bytes.len());
    if !seen_points {
        return Err(ctx.err(end, "<Piece> has no <Points> element".into()));
    }
    let points = points.unwrap_or_default();
    if points.len() != 3 * n {
        return Err(ctx.err(end, format!("<Points> holds {} points, NumberOfPoints is {n}", points.len() / 3)));
    }
    let kinds = build_cells(&mut out.mesh, &cells_arrays, n, m, &ctx, end)?;
    split_faces(&mut out, &kinds, region_array, &field_data);
    let dim = out.mesh.dim;
    if dim == 2 {
        crate::io::check_planar(points.chunks_exact(3).map(|p| [p[0], p[1], p[2]]))?;
    }
    out.mesh.coords = points.chunks_exact(3).flat_map(|p| p[..dim].iter().copied()).collect();
    Ok(out)
}

/// The data of the `<AppendedData>` tag `e` (at `at`, ending at `xml_end`).
fn appended_data(e: &BytesStart, ctx: &Ctx, at: usize, xml_end: usize) -> Result<Appended, IoError> {
    let base64 = match attr(e, "encoding", ctx, at)?.as_deref() {
        Some("raw") => false,
        Some("base64") => true,
        other => {
            let msg = format!("attribute `encoding` of <AppendedData> is {other:?}; raw or base64 expected");
            return Err(ctx.err(at, msg));
        }
    };
    // Whitespace, then `_`, then the data.
    let b = ctx.b;
    let p = xml_end + b[xml_end..].iter().take_while(|c| c.is_ascii_whitespace()).count();
    if b.get(p) != Some(&b'_') {
        return Err(ctx.err(p, "<AppendedData>: expected `_` before its data".into()));
    }
    let end = match base64 {
        true => b.windows(15).rposition(|w| w == b"</AppendedData>").unwrap_or(b.len()),
        false => b.len(),
    };
    Ok(Appended { start: p + 1, end: end.max(p + 1), base64 })
}

/// The regions of the cell array `region` (one integer per cell of the file, faces included).
fn regions(values: &[f64], a: &Array, label: &str, ctx: &Ctx) -> Result<Vec<i32>, IoError> {
    check_ids(values, a, label, ctx)?;
    Ok(values.iter().map(|&x| x as i32).collect())
}

/// The cell arrays that give the patch ids of the faces (and, without an array `region`, the
/// regions of the cells), in order of preference: Gmsh's physical tags as meshio writes them,
/// our own name, VTK's and ParaView's.
pub(super) const PATCH_ARRAYS: [&str; 3] = ["gmsh:physical", "patch", "CellEntityIds"];

/// An id array: one component, every value an i32.
fn check_ids(values: &[f64], a: &Array, label: &str, ctx: &Ctx) -> Result<(), IoError> {
    if a.comps != 1 {
        return Err(ctx.err(a.at, format!("{label}: NumberOfComponents is {}; ids have 1", a.comps)));
    }
    match values.iter().position(|&x| x.fract() != 0.0 || x.abs() > i32::MAX as f64) {
        Some(c) => Err(ctx.err(a.at, format!("{label}: the value of cell {c} is {}, not an i32", values[c]))),
        None => Ok(()),
    }
}

/// What a cell of the file is in the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// A cell of the mesh's dimension.
    Cell,
    /// A cell of one dimension less: a patch face.
    Face,
    /// A vertex or, in 3D, an edge: not part of the mesh.
    Skipped,
}

/// Moves the file's cells of dimension D − 1 (`kinds`) from `out.mesh`'s cells to its patch
/// faces, their patch ids from the first of [`PATCH_ARRAYS`] present (0 without one); the cells'
/// regions from the array `region`, else from that same array (as Gmsh's physical groups tag
/// volumes and surfaces alike); keeps the cell arrays' values of the cells only; and takes the
/// patch names from the field data: an integer array whose first value is a patch id and whose
/// second, where present, is the dimension D − 1 (as meshio writes Gmsh's physical names).
fn split_faces(
    out: &mut VtuData,
    kinds: &[(Kind, Option<CellType>)],
    region: Option<Vec<i32>>,
    field_data: &[(String, Vec<f64>)],
) {
    let ids: Option<Vec<i32>> = PATCH_ARRAYS
        .iter()
        .find_map(|p| out.cell_data.iter().find(|(n, _, _)| n == p))
        .map(|(_, v, _)| v.iter().map(|&x| x as i32).collect());
    let dim = out.mesh.dim;
    let all = std::mem::replace(&mut out.mesh, MeshData::new(dim));
    let mesh = &mut out.mesh;
    // Polyhedra are 3D, so cells of a 3D mesh: their face lists stay in cell order.
    mesh.polyhedron_faces = all.polyhedron_faces.clone();
    let regions = region.or_else(|| ids.clone());
    let mut cells = 0;
    for (c, &(kind, ty)) in kinds.iter().enumerate() {
        let vertices = &all.cell_vertices[all.cell_offsets[c] as usize..all.cell_offsets[c + 1] as usize];
        match (kind, ty) {
            (Kind::Cell, Some(ty)) => {
                let region = regions.as_ref().map_or(0, |r| r[c]);
                mesh.push_cell(ty, vertices, region);
                cells += 1;
            }
            (Kind::Face, _) => mesh.push_face(vertices, ids.as_ref().map_or(0, |p| p[c])),
            _ => {}
        }
    }
    if cells < kinds.len() {
        for (_, values, comps) in &mut out.cell_data {
            let k = *comps;
            *values = values
                .chunks_exact(k)
                .zip(kinds)
                .filter(|(_, k)| k.0 == Kind::Cell)
                .flat_map(|(t, _)| t.iter().copied())
                .collect();
        }
    }
    let face_dim = (mesh.dim - 1) as f64;
    for (name, v) in field_data {
        let is_id = |x: f64| x.fract() == 0.0 && x.abs() <= i32::MAX as f64;
        let patch = match v[..] {
            [id] if is_id(id) => Some(id),
            [id, d] if is_id(id) && d == face_dim => Some(id),
            _ => None,
        };
        if let Some(id) = patch {
            out.patch_names.push((id as i32, name.clone()));
        }
    }
}

/// Fills `mesh`'s dimension and the corner lists (`cell_offsets`, `cell_vertices`) of every cell of
/// the file from the arrays `connectivity`, `offsets` and `types`, and returns what each cell is
/// with its type: the mesh's dimension D is the largest of its cells', cells of dimension D − 1
/// are faces (VTK lines in 2D; triangles and quads in 3D), lower ones are skipped.
fn build_cells(
    mesh: &mut MeshData,
    arrays: &[(String, Vec<f64>, usize)],
    n: usize,
    m: usize,
    ctx: &Ctx,
    end: usize,
) -> Result<Vec<(Kind, Option<CellType>)>, IoError> {
    let get = |name: &str| {
        arrays
            .iter()
            .find(|(k, _, _)| k == name)
            .map(|(_, v, at)| (v, *at))
            .ok_or_else(|| ctx.err(end, format!("<Cells> has no DataArray `{name}`")))
    };
    let (conn, conn_at) = get("connectivity")?;
    let (offsets, off_at) = get("offsets")?;
    let (types, types_at) = get("types")?;
    for (name, v, at) in [("offsets", offsets, off_at), ("types", types, types_at)] {
        if v.len() != m {
            return Err(ctx.err(
                at,
                format!("DataArray `{name}` in <Cells>: expected {m} values (NumberOfCells), found {}", v.len()),
            ));
        }
    }
    mesh.cell_offsets = Vec::with_capacity(m + 1);
    mesh.cell_offsets.push(0);
    let mut prev = 0usize;
    let mut shapes = Vec::with_capacity(m);
    for (c, (&t, &o)) in types.iter().zip(offsets).enumerate() {
        let ty = Some(t).filter(|t| t.fract() == 0.0).map(|t| t as i64);
        // (dimension, corners, cell type): VTK's vertex and line, then the cell types.
        // A polygon's or polyhedron's corners are as many as its offsets give (at least 3, 4).
        let general = |ty: CellType, least: usize| {
            let given = o - prev as f64;
            let n = if given >= least as f64 && given.fract() == 0.0 { given as usize } else { least };
            (ty.dim(), n, Some(ty))
        };
        let shape = match ty {
            Some(1) => Some((0, 1, None)),
            Some(3) => Some((1, 2, None)),
            Some(7) => Some(general(CellType::Polygon, 3)),
            Some(42) => Some(general(CellType::Polyhedron, 4)),
            Some(t) => CellType::from_vtk(t).map(|ty| (ty.dim(), ty.num_corners(), Some(ty))),
            None => None,
        };
        let (_, corners, ty) = shape.ok_or_else(|| {
            IoError::Unsupported(format!(
                "cell {c} has VTK cell type {t}; the types read are vertex (1), line (3), triangle (5), \
                 polygon (7), quad (9), tetra (10), hexahedron (12), wedge (13), pyramid (14) and polyhedron (42)"
            ))
        })?;
        shapes.push(shape.expect("checked above"));
        let want = prev + corners;
        if o != want as f64 {
            return Err(ctx.err(
                off_at,
                format!(
                    "DataArray `offsets` in <Cells>: offset of cell {c} is {o}, expected {want} (a {} of {corners} \
                     corners after offset {prev})",
                    ty.map_or_else(|| format!("VTK type {t}"), |ty| ty.to_string())
                ),
            ));
        }
        mesh.cell_offsets
            .push(u32::try_from(want).map_err(|_| {
                IoError::Unsupported(format!("{want} corners in <Cells>: more than 2^32 are not read"))
            })?);
        prev = want;
    }
    if conn.len() != prev {
        return Err(ctx.err(
            conn_at,
            format!(
                "DataArray `connectivity` in <Cells>: expected {prev} values (the last offset), found {}",
                conn.len()
            ),
        ));
    }
    mesh.cell_vertices = Vec::with_capacity(prev);
    for (k, &v) in conn.iter().enumerate() {
        if !(v >= 0.0 && v < n as f64 && v.fract() == 0.0) {
            let c = mesh.cell_offsets.partition_point(|&o| o as usize <= k) - 1;
            return Err(ctx.err(
                conn_at,
                format!("DataArray `connectivity` in <Cells>: cell {c} refers to point {v}, outside 0..{n}"),
            ));
        }
        mesh.cell_vertices.push(v as u32);
    }
    mesh.dim = if shapes.iter().any(|s| s.0 == 3) { 3 } else { 2 };
    polyhedra(mesh, arrays, &shapes, n, ctx, end)?;
    let kinds = shapes
        .iter()
        .map(|&(d, _, ty)| {
            let kind = match mesh.dim - d {
                0 => Kind::Cell,
                1 => Kind::Face,
                _ => Kind::Skipped,
            };
            (kind, ty)
        })
        .collect();
    Ok(kinds)
}

/// The polyhedra's face lists from the arrays `faces` (each polyhedron's number of faces, then
/// each face's vertex count and vertices) and `faceoffsets` (where each cell's list ends, −1
/// for a cell that is not a polyhedron) into `mesh.polyhedron_faces`, checked.
fn polyhedra(
    mesh: &mut MeshData,
    arrays: &[(String, Vec<f64>, usize)],
    shapes: &[(usize, usize, Option<CellType>)],
    n: usize,
    ctx: &Ctx,
    end: usize,
) -> Result<(), IoError> {
    let get = |name: &str| arrays.iter().find(|(k, _, _)| k == name).map(|(_, v, at)| (v, *at));
    let any = shapes.iter().any(|s| s.2 == Some(CellType::Polyhedron));
    let (Some((faces, faces_at)), Some((ends, ends_at))) = (get("faces"), get("faceoffsets")) else {
        if any {
            return Err(
                ctx.err(end, "<Cells> has polyhedra (type 42) but no DataArray `faces` or `faceoffsets`".into())
            );
        }
        return Ok(());
    };
    if ends.len() != shapes.len() {
        let msg = format!("DataArray `faceoffsets` in <Cells>: expected {} values, found {}", shapes.len(), ends.len());
        return Err(ctx.err(ends_at, msg));
    }
    let mut at = 0usize;
    for (c, s) in shapes.iter().enumerate() {
        if s.2 != Some(CellType::Polyhedron) {
            continue;
        }
        let e = ends[c];
        if !(e.fract() == 0.0 && e >= at as f64 && e <= faces.len() as f64) {
            let msg = format!("DataArray `faceoffsets` in <Cells>: cell {c}'s list ends at {e}, after {at}");
            return Err(ctx.err(ends_at, msg));
        }
        let list = &faces[at..e as usize];
        if let Some(v) = list.iter().find(|&&v| !(v >= 0.0 && v.fract() == 0.0 && v < u32::MAX as f64)) {
            return Err(ctx.err(faces_at, format!("DataArray `faces` in <Cells>: cell {c}'s list holds {v}")));
        }
        let list: Vec<u32> = list.iter().map(|&v| v as u32).collect();
        match crate::mesh::polyhedron_list_end(&list, 0, n) {
            Ok(e) if e == list.len() => {}
            Ok(_) => {
                return Err(ctx.err(faces_at, format!("DataArray `faces` in <Cells>: cell {c}'s list is too long")))
            }
            Err(p) => return Err(ctx.err(faces_at, format!("DataArray `faces` in <Cells>: cell {c}: {p}"))),
        }
        mesh.polyhedron_faces.extend(list);
        at = e as usize;
    }
    if at != faces.len() {
        return Err(ctx.err(faces_at, "DataArray `faces` in <Cells>: values follow the last polyhedron's list".into()));
    }
    Ok(())
}

/// Values of a DataArray as f64 (exact for every integer type up to 2^53).
fn decode(a: &Array, label: &str, ctx: &Ctx) -> Result<Vec<f64>, IoError> {
    match a.format.as_str() {
        "ascii" => {
            let mut v = Vec::new();
            let base = a.text_at;
            let bytes = a.text.as_bytes();
            let mut i = 0;
            while i < bytes.len() {
                while i < bytes.len() && bytes[i].is_ascii_whitespace() {
                    i += 1;
                }
                let s = i;
                while i < bytes.len() && !bytes[i].is_ascii_whitespace() {
                    i += 1;
                }
                if s == i {
                    break;
                }
                let tok = &a.text[s..i];
                let x: f64 = tok.parse().map_err(|_| {
                    ctx.err(base + s, format!("{label}: expected a number of type {}, found `{tok}`", a.ty))
                })?;
                v.push(x);
            }
            Ok(v)
        }
        "binary" => {
            let pos = Pos::Text(a.text_at);
            let raw = unbase64(&a.text, label, ctx, pos)?;
            typed(&payload(&raw, label, ctx, pos)?, a, label, ctx, pos)
        }
        "appended" => {
            let app = ctx.appended.as_ref().ok_or_else(|| {
                ctx.err(a.at, format!("{label}: format=\"appended\" but the file has no <AppendedData>"))
            })?;
            let off =
                a.offset.ok_or_else(|| ctx.err(a.at, format!("{label}: format=\"appended\" without `offset`")))?;
            let start = app.start.saturating_add(off);
            if start > app.end {
                return Err(ctx.err(a.at, format!("{label}: offset {off} is past the end of <AppendedData>")));
            }
            if app.base64 {
                // This array's run ends where the next one starts.
                let end = ctx.offsets.iter().find(|&&o| o > off).map_or(app.end, |&o| (app.start + o).min(app.end));
                let text = String::from_utf8_lossy(&ctx.b[start..end]);
                let pos = Pos::Text(start);
                let raw = unbase64(&text, label, ctx, pos)?;
                typed(&payload(&raw, label, ctx, pos)?, a, label, ctx, pos)
            } else {
                let pos = Pos::Byte(start);
                typed(&payload(&ctx.b[start..], label, ctx, pos)?, a, label, ctx, pos)
            }
        }
        f => Err(ctx.err(a.at, format!("{label}: attribute `format` is `{f}`; ascii, binary or appended expected"))),
    }
}

/// The bytes of base64 `text` (whitespace ignored) holding a header and its data. VTK encodes
/// the two either together or as two runs, the header's first; a header run whose length is
/// not a multiple of 3 bytes ends in padding, and one that is encodes as the joint run does.
fn unbase64(text: &str, label: &str, ctx: &Ctx, pos: Pos) -> Result<Vec<u8>, IoError> {
    let b64 = base64::engine::general_purpose::STANDARD;
    let text: String = text.chars().filter(|c| !c.is_ascii_whitespace()).collect();
    let bad = |e: base64::DecodeError| ctx.err_pos(pos, format!("{label}: bad base64: {e}"));
    let short = || ctx.err_pos(pos, format!("{label}: binary data shorter than its header"));
    let h = ctx.hsize();
    let header_bytes = if ctx.zlib {
        // [blocks, block size, last block size, compressed sizes...]: the first 4h characters
        // are the first 3h bytes in either layout.
        let first = b64.decode(text.get(..4 * h).ok_or_else(short)?).map_err(bad)?;
        let blocks = usize::try_from(ctx.uint(&first[..h])).unwrap_or(usize::MAX);
        if blocks > text.len() {
            return Err(ctx.err_pos(pos, format!("{label}: the header announces {blocks} compressed blocks")));
        }
        (3 + blocks) * h
    } else {
        h
    };
    let hchars = header_bytes.div_ceil(3) * 4;
    match text.get(..hchars) {
        Some(head) if head.ends_with('=') => {
            let mut raw = b64.decode(head).map_err(bad)?;
            raw.extend(b64.decode(&text[hchars..]).map_err(bad)?);
            Ok(raw)
        }
        _ => b64.decode(&text).map_err(bad),
    }
}

/// The data bytes of one array from `src`, its header and data (and maybe more after them):
/// uncompressed, or inflated block by block.
fn payload(src: &[u8], label: &str, ctx: &Ctx, pos: Pos) -> Result<Vec<u8>, IoError> {
    let h = ctx.hsize();
    let int = |i: usize| -> Result<usize, IoError> {
        let b = src
            .get(i * h..(i + 1) * h)
            .ok_or_else(|| ctx.err_pos(pos, format!("{label}: binary data shorter than its header")))?;
        Ok(usize::try_from(ctx.uint(b)).unwrap_or(usize::MAX))
    };
    if !ctx.zlib {
        let nbytes = int(0)?;
        let data = &src[h..];
        if data.len() < nbytes {
            return Err(ctx.err_pos(pos, format!("{label}: header announces {nbytes} bytes, {} present", data.len())));
        }
        return Ok(data[..nbytes].to_vec());
    }
    let (blocks, size, last) = (int(0)?, int(1)?, int(2)?);
    if blocks > src.len() {
        return Err(ctx.err_pos(pos, format!("{label}: the header announces {blocks} compressed blocks")));
    }
    let mut at = (3 + blocks) * h;
    let mut out = Vec::new();
    for k in 0..blocks {
        let csize = int(3 + k)?;
        let want = if k + 1 == blocks && last != 0 { last } else { size };
        let block = src.get(at..at.saturating_add(csize)).ok_or_else(|| {
            ctx.err_pos(pos, format!("{label}: compressed block {k} of {csize} bytes runs past the data"))
        })?;
        let before = out.len();
        flate2::read::ZlibDecoder::new(block)
            .take(want as u64 + 1)
            .read_to_end(&mut out)
            .map_err(|e| ctx.err_pos(pos, format!("{label}: compressed block {k}: {e}")))?;
        if out.len() - before != want {
            return Err(ctx.err_pos(
                pos,
                format!(
                    "{label}: compressed block {k} inflates to {} bytes, the header says {want}",
                    out.len() - before
                ),
            ));
        }
        at += csize;
    }
    Ok(out)
}

/// The values of `data`, of `a`'s type in the file's byte order.
fn typed(data: &[u8], a: &Array, label: &str, ctx: &Ctx, pos: Pos) -> Result<Vec<f64>, IoError> {
    let size = match a.ty.as_str() {
        "Int8" | "UInt8" => 1,
        "Int16" | "UInt16" => 2,
        "Int32" | "UInt32" | "Float32" => 4,
        "Int64" | "UInt64" | "Float64" => 8,
        t => {
            return Err(ctx.err(a.at, format!("{label}: unknown type `{t}`")));
        }
    };
    if data.len() % size != 0 {
        return Err(ctx.err_pos(pos, format!("{label}: {} bytes is not a whole number of {} values", data.len(), a.ty)));
    }
    let be = ctx.big_endian;
    Ok(data
        .chunks_exact(size)
        .map(|c| {
            let mut b = [0u8; 8];
            b[..size].copy_from_slice(c);
            if be {
                b[..size].reverse();
            }
            match a.ty.as_str() {
                "Int8" => b[0] as i8 as f64,
                "UInt8" => b[0] as f64,
                "Int16" => i16::from_le_bytes([b[0], b[1]]) as f64,
                "UInt16" => u16::from_le_bytes([b[0], b[1]]) as f64,
                "Int32" => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                "UInt32" => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                "Float32" => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                "Int64" => i64::from_le_bytes(b) as f64,
                "UInt64" => u64::from_le_bytes(b) as f64,
                _ => f64::from_le_bytes(b),
            }
        })
        .collect())
}
