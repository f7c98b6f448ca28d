//! The `.vtu` writer: appended raw binary (the default), zlib-compressed appended binary, or
//! ASCII with shortest round-trip floats; every encoding reads back to the same bits.

use super::{CellField, PointField};
use crate::geometry::{CellGeometry, CellPoints, GeneralPoints};
use crate::io::{check_data, io_err, IoError};
use crate::mesh::faces_in;
use crate::mesh::{Mesh, MeshData};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

/// How the arrays of a written `.vtu` are encoded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum VtuEncoding {
    /// Raw little-endian bytes after the XML, in one `<AppendedData encoding="raw">` block: the
    /// fastest to write and read, and what VTK and ParaView read natively.
    #[default]
    Binary,
    /// As `Binary`, each array compressed by zlib (`vtkZLibDataCompressor`) in blocks of 32 KiB:
    /// smaller files, slower to write.
    Compressed,
    /// Text (`format="ascii"`), floats in their shortest round-trip form: larger and slower, for
    /// reading by eye.
    Ascii,
}

/// The uncompressed size of a zlib block of [`VtuEncoding::Compressed`] (VTK's own default).
const ZLIB_BLOCK: usize = 1 << 15;

/// Writes the points, cells and tagged faces of `mesh` with the given named fields, in appended
/// raw binary: [`write_vtu_as`] with [`VtuEncoding::Binary`].
pub fn write_vtu(
    path: &Path,
    mesh: &MeshData,
    point_data: &[(&str, PointField)],
    cell_data: &[(&str, CellField)],
) -> Result<(), IoError> {
    write_vtu_as(path, mesh, point_data, cell_data, VtuEncoding::default())
}

/// Writes the points, cells and tagged faces of `mesh` with the given named fields, encoded as
/// `encoding` says. 2D points are written with z = 0. The faces follow the cells as VTK cells of
/// one dimension less (lines in 2D, triangles and quads in 3D) with an Int32 cell array `patch`
/// (the faces' patch ids, the cells' regions), which [`read_vtu`](super::read_vtu) reads back as
/// the patches; the caller's cell fields hold the cells' values, and the faces' are written as
/// NaN (`F64`) or 0 (`I32`). Regions are read back from a cell field `region` where the caller
/// passes one.
pub fn write_vtu_as(
    path: &Path,
    mesh: &MeshData,
    point_data: &[(&str, PointField)],
    cell_data: &[(&str, CellField)],
    encoding: VtuEncoding,
) -> Result<(), IoError> {
    vtu_contents(mesh, &mesh.coords, point_data, cell_data, encoding)?.write_to(path)
}

/// The contents of the file [`write_vtu_as`] writes, with the points at `points` (the mesh's
/// coordinates, or the same number of moved ones).
fn vtu_contents(
    mesh: &MeshData,
    points: &[f64],
    point_data: &[(&str, PointField)],
    cell_data: &[(&str, CellField)],
    encoding: VtuEncoding,
) -> Result<Writer, IoError> {
    check_data(mesh, "write_vtu")?;
    debug_assert_eq!(points.len(), mesh.coords.len());
    let (n, m) = (mesh.num_vertices(), mesh.num_cells());
    let nf = mesh.num_faces();
    for (name, f) in point_data {
        let (len, comps) = match *f {
            PointField::Scalar(v) => (v.len(), 1),
            PointField::Vector(v, k) => (v.len(), k),
        };
        if comps == 0 || len != n * comps {
            return Err(IoError::InvalidArgument(format!(
                "write_vtu: point field `{name}` has {len} values of {comps} components for {n} vertices"
            )));
        }
    }
    for (name, f) in cell_data {
        let len = match f {
            CellField::F64(v) => v.len(),
            CellField::I32(v) => v.len(),
        };
        if len != m {
            return Err(IoError::InvalidArgument(format!(
                "write_vtu: cell field `{name}` has {len} values for {m} cells"
            )));
        }
    }
    let face_vtk = |f: usize| match (mesh.dim, mesh.face(f).len()) {
        (2, _) => 3u8,
        (_, 3) => 5,
        (_, 4) => 9,
        _ => 7,
    };
    let mut w = Writer::new(encoding, 80 * n + 40 * m);
    w.xml.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"");
    if encoding == VtuEncoding::Compressed {
        w.xml.push_str(" compressor=\"vtkZLibDataCompressor\"");
    }
    w.xml.push_str(">\n<UnstructuredGrid>\n");
    let _ = writeln!(w.xml, "<Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{}\">", m + nf);
    w.xml.push_str("<PointData>\n");
    for (name, f) in point_data {
        match *f {
            PointField::Scalar(v) => w.array(Some(name), 1, Values::F64(v)),
            PointField::Vector(v, k) => w.array(Some(name), k.max(3 * usize::from(k == 2)), Values::F64(&tuples(v, k))),
        }
    }
    w.xml.push_str("</PointData>\n<CellData>\n");
    for (name, f) in cell_data {
        match f {
            CellField::F64(v) => {
                let all: Vec<f64> = v.iter().copied().chain(std::iter::repeat_n(f64::NAN, nf)).collect();
                w.array(Some(name), 1, Values::F64(&all));
            }
            CellField::I32(v) => {
                let all: Vec<i32> = v.iter().copied().chain(std::iter::repeat_n(0, nf)).collect();
                w.array(Some(name), 1, Values::I32(&all));
            }
        }
    }
    if nf > 0 {
        let regions = (0..m).map(|c| mesh.regions.get(c).copied().unwrap_or(0));
        let patch: Vec<i32> = regions.chain(mesh.face_patch.iter().copied()).collect();
        w.array(Some("patch"), 1, Values::I32(&patch));
    }
    w.xml.push_str("</CellData>\n<Points>\n");
    w.array(None, 3, Values::F64(&tuples(points, mesh.dim)));
    w.xml.push_str("</Points>\n<Cells>\n");
    let conn: Vec<i64> = mesh.cell_vertices.iter().chain(&mesh.face_vertices).map(|&v| i64::from(v)).collect();
    w.array(Some("connectivity"), 1, Values::I64(&conn));
    let end = mesh.cell_vertices.len() as i64;
    let cell_ends = mesh.cell_offsets.get(1..).unwrap_or_default().iter().map(|&o| i64::from(o));
    let face_ends = mesh.face_offsets.get(1..).unwrap_or_default().iter().map(|&o| end + i64::from(o));
    w.array(Some("offsets"), 1, Values::I64(&cell_ends.chain(face_ends).collect::<Vec<_>>()));
    let types: Vec<u8> = mesh.cell_types.iter().map(|t| t.vtk_id()).chain((0..nf).map(face_vtk)).collect();
    w.array(Some("types"), 1, Values::U8(&types));
    if !mesh.polyhedron_faces.is_empty() {
        // VTK's polyhedra: every polyhedron's face list, one after another, in `faces`, and
        // where each cell's list ends in `faceoffsets` (−1 for a cell that is not a polyhedron).
        let spans = mesh.polyhedron_spans(n).map_err(|p| IoError::InvalidArgument(format!("write_vtu: {p}")))?;
        let ends: Vec<i64> =
            spans.iter().map(|s| s.as_ref().map_or(-1, |r| r.end as i64)).chain((0..nf).map(|_| -1)).collect();
        let faces: Vec<i64> = mesh.polyhedron_faces.iter().map(|&v| i64::from(v)).collect();
        w.array(Some("faces"), 1, Values::I64(&faces));
        w.array(Some("faceoffsets"), 1, Values::I64(&ends));
    }
    w.xml.push_str("</Cells>\n</Piece>\n</UnstructuredGrid>\n");
    Ok(w)
}

/// Tuples of `comps` values as VTK stores them: pairs as (x, y, 0), other sizes as they are.
fn tuples(values: &[f64], comps: usize) -> std::borrow::Cow<'_, [f64]> {
    if comps != 2 {
        return std::borrow::Cow::Borrowed(values);
    }
    std::borrow::Cow::Owned(values.chunks_exact(2).flat_map(|p| [p[0], p[1], 0.0]).collect())
}

/// The values of one array, of the VTK type each variant names.
enum Values<'a> {
    F64(&'a [f64]),
    I32(&'a [i32]),
    I64(&'a [i64]),
    U8(&'a [u8]),
}

impl Values<'_> {
    fn vtk_type(&self) -> &'static str {
        match self {
            Values::F64(_) => "Float64",
            Values::I32(_) => "Int32",
            Values::I64(_) => "Int64",
            Values::U8(_) => "UInt8",
        }
    }

    /// The number of bytes of the values.
    fn byte_len(&self) -> usize {
        match self {
            Values::F64(v) => 8 * v.len(),
            Values::I32(v) => 4 * v.len(),
            Values::I64(v) => 8 * v.len(),
            Values::U8(v) => v.len(),
        }
    }

    /// Appends the values to `out` as little-endian bytes.
    fn append_le(&self, out: &mut Vec<u8>) {
        fn le<const N: usize, T: Copy>(out: &mut Vec<u8>, v: &[T], f: impl Fn(T) -> [u8; N]) {
            out.reserve(N * v.len());
            v.iter().for_each(|&x| out.extend_from_slice(&f(x)));
        }
        match self {
            Values::F64(v) => le(out, v, f64::to_le_bytes),
            Values::I32(v) => le(out, v, i32::to_le_bytes),
            Values::I64(v) => le(out, v, i64::to_le_bytes),
            Values::U8(v) => out.extend_from_slice(v),
        }
    }

    /// The values as text, separated by spaces; floats in their shortest round-trip form (`{:?}`
    /// is Rust's), so reading back gives the same bits.
    fn push_text(&self, s: &mut String) {
        match self {
            Values::F64(v) => v.iter().for_each(|x| {
                let _ = write!(s, "{x:?} ");
            }),
            Values::I32(v) => push_ints(s, v),
            Values::I64(v) => push_ints(s, v),
            Values::U8(v) => push_ints(s, v),
        }
    }
}

fn push_ints<T: std::fmt::Display>(s: &mut String, v: &[T]) {
    v.iter().for_each(|x| {
        let _ = write!(s, "{x} ");
    });
}

/// The XML of a file being written and, for the binary encodings, its appended data.
struct Writer {
    encoding: VtuEncoding,
    xml: String,
    appended: Vec<u8>,
}

impl Writer {
    fn new(encoding: VtuEncoding, ascii_guess: usize) -> Writer {
        let capacity = if encoding == VtuEncoding::Ascii { ascii_guess } else { 4096 };
        Writer { encoding, xml: String::with_capacity(capacity), appended: Vec::new() }
    }

    /// One `<DataArray>`: inline text, or its offset here and its header and bytes appended.
    fn array(&mut self, name: Option<&str>, comps: usize, values: Values) {
        let _ = write!(self.xml, "<DataArray type=\"{}\"", values.vtk_type());
        if let Some(name) = name {
            let _ = write!(self.xml, " Name=\"{}\"", quick_xml::escape::escape(name));
        }
        if comps != 1 {
            let _ = write!(self.xml, " NumberOfComponents=\"{comps}\"");
        }
        if self.encoding == VtuEncoding::Ascii {
            self.xml.push_str(" format=\"ascii\">\n");
            values.push_text(&mut self.xml);
            self.xml.push_str("\n</DataArray>\n");
            return;
        }
        let _ = writeln!(self.xml, " format=\"appended\" offset=\"{}\"/>", self.appended.len());
        if self.encoding == VtuEncoding::Compressed {
            let mut data = Vec::new();
            values.append_le(&mut data);
            self.push_compressed(&data);
        } else {
            self.appended.extend_from_slice(&(values.byte_len() as u64).to_le_bytes());
            values.append_le(&mut self.appended);
        }
    }

    /// `data` as VTK's compressed form: the header (block count, block size, size of the last
    /// block, each block's compressed size) then the blocks, each a zlib stream. Level 1: the
    /// smaller files of higher levels cost several times the time, and speed is what a file
    /// written every time step needs.
    fn push_compressed(&mut self, data: &[u8]) {
        let blocks: Vec<Vec<u8>> = data
            .chunks(ZLIB_BLOCK)
            .map(|b| {
                let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::fast());
                // Writing to and finishing into a Vec cannot fail.
                let _ = z.write_all(b);
                z.finish().unwrap_or_default()
            })
            .collect();
        let last = data.len() % ZLIB_BLOCK;
        let header = [blocks.len(), ZLIB_BLOCK, last].into_iter().chain(blocks.iter().map(Vec::len));
        header.for_each(|x| self.appended.extend_from_slice(&(x as u64).to_le_bytes()));
        blocks.iter().for_each(|b| self.appended.extend_from_slice(b));
    }

    /// Writes the whole file to `path`: the XML, then the appended data, if any (each written
    /// from where it is held, not joined into one buffer first).
    fn write_to(mut self, path: &Path) -> Result<(), IoError> {
        let parts: [&[u8]; 3] = if self.encoding == VtuEncoding::Ascii {
            self.xml.push_str("</VTKFile>\n");
            [self.xml.as_bytes(), &[], &[]]
        } else {
            self.xml.push_str("<AppendedData encoding=\"raw\">\n_");
            [self.xml.as_bytes(), &self.appended, b"\n</AppendedData>\n</VTKFile>\n"]
        };
        let mut file = std::fs::File::create(path).map_err(io_err(path))?;
        parts.iter().try_for_each(|p| file.write_all(p)).map_err(io_err(path))
    }
}

/// Writes `reference` moved by `displacement` (`dim` values per vertex), with point data
/// `displacement` and cell data `region` (Int32), `area_ratio` in 2D or `volume_ratio` in 3D
/// (deformed over reference signed measure), `inverted` (1 where a corner Jacobian of the
/// deformed cell is not positive) and `min_angle` (degrees: the smallest angle between two edges
/// at a corner; 0 for inverted cells).
pub fn write_deformed(path: &Path, reference: &Mesh, displacement: &[f64]) -> Result<(), IoError> {
    write_deformed_data(path, &reference.to_data(), displacement)
}

/// [`write_deformed`] of a mesh given as plain arrays (any cell types, 2D or 3D).
pub fn write_deformed_data(path: &Path, data: &MeshData, displacement: &[f64]) -> Result<(), IoError> {
    write_deformed_as(path, data, displacement, VtuEncoding::default())
}

/// [`write_deformed_data`] in the given encoding.
pub fn write_deformed_as(
    path: &Path,
    data: &MeshData,
    displacement: &[f64],
    encoding: VtuEncoding,
) -> Result<(), IoError> {
    write_deformed_with(path, data, displacement, &[], encoding)
}

/// [`write_deformed_as`] with more point data after `displacement` (a distributed mesh's piece:
/// its vertices' global ids).
pub fn write_deformed_with(
    path: &Path,
    data: &MeshData,
    displacement: &[f64],
    more_point_data: &[(&str, PointField)],
    encoding: VtuEncoding,
) -> Result<(), IoError> {
    check_data(data, "write_deformed")?;
    let (dim, n) = (data.dim, data.num_vertices());
    if displacement.len() != dim * n {
        return Err(IoError::InvalidArgument(format!(
            "write_deformed: {} displacement values for a mesh of {n} vertices in {dim}D ({} expected)",
            displacement.len(),
            dim * n
        )));
    }
    let moved: Vec<f64> = data.coords.iter().zip(displacement).map(|(x, d)| x + d).collect();
    let m = data.num_cells();
    let spans = data.polyhedron_spans(n).map_err(|p| IoError::InvalidArgument(format!("write_deformed: {p}")))?;
    let cell_points = |coords: &[f64], c: usize| cell_geometry(data, coords, &spans, c);
    let (mut ratio, mut inverted, mut min_angle) =
        (Vec::with_capacity(m), Vec::with_capacity(m), Vec::with_capacity(m));
    for c in 0..m {
        let (p0, p1) = (cell_points(&data.coords, c), cell_points(&moved, c));
        let a1 = p1.signed_measure();
        ratio.push(a1 / p0.signed_measure());
        let bad = p1.inverted_with_measure(a1);
        inverted.push(i32::from(bad));
        min_angle.push(if bad { 0.0 } else { p1.min_angle_deg() });
    }
    let regions = if data.regions.is_empty() { vec![0; m] } else { data.regions.clone() };
    let contents = vtu_contents(
        data,
        &moved,
        &[&[("displacement", PointField::Vector(displacement, dim))], more_point_data].concat(),
        &[
            ("region", CellField::I32(&regions)),
            (if dim == 2 { "area_ratio" } else { "volume_ratio" }, CellField::F64(&ratio)),
            ("inverted", CellField::I32(&inverted)),
            ("min_angle", CellField::F64(&min_angle)),
        ],
        encoding,
    )?;
    contents.write_to(path)
}

/// Signed area (2D) or volume (3D) of cell `c` (the geometry module's).
#[cfg(test)]
pub(crate) fn signed_measure(d: &MeshData, c: usize) -> f64 {
    cell_points(d, &d.coords, c).signed_measure()
}

/// Cell `c` of `d`'s topology at positions `coords`.
fn cell_points(d: &MeshData, coords: &[f64], c: usize) -> CellPoints {
    CellPoints::gather(d.cell_types[c], d.cell(c), coords, d.dim)
}

/// Cell `c` of `d`'s topology, of any type, at positions `coords`; `spans` are `d`'s polyhedron
/// spans.
fn cell_geometry(d: &MeshData, coords: &[f64], spans: &[Option<std::ops::Range<usize>>], c: usize) -> CellGeometry {
    if d.cell_types[c].is_general() {
        let list = spans[c].clone().map_or(&[][..], |r| &d.polyhedron_faces[r]);
        CellGeometry::General(GeneralPoints::gather(d.cell(c), faces_in(list), coords, d.dim))
    } else {
        CellGeometry::Fixed(cell_points(d, coords, c))
    }
}
