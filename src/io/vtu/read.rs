//! The `.vtu` reader: one piece of triangles, ascii or inline base64 arrays.

use super::VtuData;
use crate::io::{io_err, line_of, IoError};
use base64::Engine as _;
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::path::Path;

/// Reads a `.vtu` file: one piece of triangles (see the module documentation for the encodings).
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
}

impl Section {
    fn tag(self) -> &'static str {
        match self {
            Section::None => "<Piece>",
            Section::PointData => "<PointData>",
            Section::CellData => "<CellData>",
            Section::Points => "<Points>",
            Section::Cells => "<Cells>",
        }
    }
}

struct Array {
    ty: String,
    name: Option<String>,
    comps: usize,
    format: String,
    /// Offset of the `<DataArray` tag and of its text.
    at: usize,
    text_at: usize,
    text: String,
}

struct Ctx<'a> {
    b: &'a [u8],
    header64: bool,
    big_endian: bool,
}

impl Ctx<'_> {
    fn err(&self, at: usize, message: String) -> IoError {
        IoError::Parse { line: line_of(self.b, at), offset: Some(at), message }
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

/// Parses the contents of a `.vtu` file.
pub fn parse_vtu(bytes: &[u8]) -> Result<VtuData, IoError> {
    let text = std::str::from_utf8(bytes).map_err(|e| IoError::Parse {
        line: line_of(bytes, e.valid_up_to()),
        offset: Some(e.valid_up_to()),
        message: "the file is not UTF-8 text (appended raw data is not supported)".into(),
    })?;
    let mut ctx = Ctx { b: bytes, header64: false, big_endian: false };
    let mut reader = Reader::from_str(text);
    let mut out = VtuData::default();
    let mut counts: Option<(usize, usize)> = None;
    let mut section = Section::None;
    let mut array: Option<Array> = None;
    let mut seen_file = false;
    let mut seen_points = false;
    let mut cells_arrays: Vec<(String, Vec<f64>, usize)> = Vec::new();
    let mut piece_end = None;
    loop {
        let at = reader.buffer_position() as usize;
        let ev = reader.read_event().map_err(|e| ctx.err(at, format!("malformed XML: {e}")))?;
        match ev {
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
                        if let Some(c) = attr(e, "compressor", &ctx, at)? {
                            return Err(IoError::Unsupported(format!("compressed data ({c})")));
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
                    b"Points" => seen_points = true,
                    b"DataArray" => {
                        if counts.is_none() {
                            return Err(ctx.err(at, "<DataArray> outside a <Piece>".into()));
                        }
                        let a = Array {
                            ty: attr(e, "type", &ctx, at)?
                                .ok_or_else(|| ctx.err(at, "<DataArray> has no attribute `type`".into()))?,
                            name: attr(e, "Name", &ctx, at)?,
                            comps: match attr(e, "NumberOfComponents", &ctx, at)? {
                                None => 1,
                                Some(_) => req_usize(e, "NumberOfComponents", &ctx, at)?,
                            },
                            format: attr(e, "format", &ctx, at)?
                                .ok_or_else(|| ctx.err(at, "<DataArray> has no attribute `format`".into()))?,
                            at,
                            text_at: reader.buffer_position() as usize,
                            text: String::new(),
                        };
                        if empty {
                            finish_array(a, section, counts, &ctx, &mut out, &mut cells_arrays)?;
                            if section == Section::Points {
                                seen_points = true;
                            }
                        } else {
                            array = Some(a);
                        }
                    }
                    b"AppendedData" => return Err(IoError::Unsupported("<AppendedData>".into())),
                    _ => {}
                }
            }
            Event::Text(t) => {
                if let Some(a) = array.as_mut() {
                    if a.text.is_empty() {
                        a.text_at = at;
                    }
                    a.text.push_str(&String::from_utf8_lossy(&t));
                }
            }
            Event::End(e) => match e.name().as_ref() {
                b"DataArray" => {
                    if let Some(a) = array.take() {
                        finish_array(a, section, counts, &ctx, &mut out, &mut cells_arrays)?;
                        if section == Section::Points {
                            seen_points = true;
                        }
                    }
                }
                b"PointData" | b"CellData" | b"Points" | b"Cells" => section = Section::None,
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
    let end = piece_end.unwrap_or(bytes.len());
    if !seen_points {
        return Err(ctx.err(end, "<Piece> has no <Points> element".into()));
    }
    if out.points.len() != n {
        return Err(ctx.err(end, format!("<Points> holds {} points, NumberOfPoints is {n}", out.points.len())));
    }
    out.cells = build_cells(&cells_arrays, n, m, &ctx, end)?;
    Ok(out)
}

fn build_cells(
    arrays: &[(String, Vec<f64>, usize)],
    n: usize,
    m: usize,
    ctx: &Ctx,
    end: usize,
) -> Result<Vec<[u32; 3]>, IoError> {
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
    if let Some((c, &t)) = types.iter().enumerate().find(|(_, &t)| t != 5.0) {
        return Err(IoError::Unsupported(format!("cell {c} has VTK cell type {t}; only triangles (5) are read")));
    }
    for (c, &o) in offsets.iter().enumerate() {
        if o != (3 * (c + 1)) as f64 {
            return Err(ctx.err(
                off_at,
                format!(
                    "DataArray `offsets` in <Cells>: offset of cell {c} is {o}, expected {} for triangles",
                    3 * (c + 1)
                ),
            ));
        }
    }
    if conn.len() != 3 * m {
        return Err(ctx.err(
            conn_at,
            format!(
                "DataArray `connectivity` in <Cells>: expected {} values (3 per triangle), found {}",
                3 * m,
                conn.len()
            ),
        ));
    }
    let mut cells = Vec::with_capacity(m);
    for (c, t) in conn.chunks_exact(3).enumerate() {
        let mut cell = [0u32; 3];
        for (k, &v) in t.iter().enumerate() {
            if !(v >= 0.0 && v < n as f64 && v.fract() == 0.0) {
                return Err(ctx.err(
                    conn_at,
                    format!("DataArray `connectivity` in <Cells>: cell {c} refers to point {v}, outside 0..{n}"),
                ));
            }
            cell[k] = v as u32;
        }
        cells.push(cell);
    }
    Ok(cells)
}

fn finish_array(
    a: Array,
    section: Section,
    counts: Option<(usize, usize)>,
    ctx: &Ctx,
    out: &mut VtuData,
    cells_arrays: &mut Vec<(String, Vec<f64>, usize)>,
) -> Result<(), IoError> {
    let (n, m) = counts.unwrap_or((0, 0));
    let label = match &a.name {
        Some(s) => format!("DataArray `{s}` in {}", section.tag()),
        None => format!("DataArray in {}", section.tag()),
    };
    if a.comps == 0 {
        return Err(ctx.err(a.at, format!("{label}: NumberOfComponents is 0")));
    }
    let values = decode(&a, &label, ctx)?;
    let tuples = match section {
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
    match section {
        Section::Points => {
            if a.comps != 3 {
                return Err(ctx.err(a.at, format!("{label}: NumberOfComponents is {}, 3 expected", a.comps)));
            }
            crate::io::check_planar(values.chunks_exact(3).map(|p| [p[0], p[1], p[2]]))?;
            out.points = values.chunks_exact(3).map(|p| [p[0], p[1]]).collect();
        }
        Section::PointData | Section::CellData => {
            let name = a.name.ok_or_else(|| ctx.err(a.at, format!("{label}: no attribute `Name`")))?;
            let list = if section == Section::PointData { &mut out.point_data } else { &mut out.cell_data };
            list.push((name, values, a.comps));
        }
        Section::Cells => {
            if let Some(name) = a.name {
                cells_arrays.push((name, values, a.at));
            }
        }
        Section::None => {}
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
        "binary" => decode_base64(a, label, ctx),
        "appended" => Err(IoError::Unsupported(format!("{label}: format=\"appended\""))),
        f => Err(ctx.err(a.at, format!("{label}: attribute `format` is `{f}`; ascii, binary or appended expected"))),
    }
}

fn decode_base64(a: &Array, label: &str, ctx: &Ctx) -> Result<Vec<f64>, IoError> {
    let b64 = base64::engine::general_purpose::STANDARD;
    let text: String = a.text.chars().filter(|c| !c.is_ascii_whitespace()).collect();
    let hsize: usize = if ctx.header64 { 8 } else { 4 };
    let bad = |e: base64::DecodeError| ctx.err(a.text_at, format!("{label}: bad base64: {e}"));
    // VTK encodes the header and the data either together or as two base64 runs; a separate
    // header run ends in padding.
    let hchars = hsize.div_ceil(3) * 4;
    let raw = if text.len() >= hchars && text[..hchars].ends_with('=') {
        let mut h = b64.decode(&text[..hchars]).map_err(bad)?;
        h.extend(b64.decode(&text[hchars..]).map_err(bad)?);
        h
    } else {
        b64.decode(&text).map_err(bad)?
    };
    if raw.len() < hsize {
        return Err(ctx.err(a.text_at, format!("{label}: binary data shorter than its header")));
    }
    let hdr = &raw[..hsize];
    let nbytes = match (hsize, ctx.big_endian) {
        (8, false) => u64::from_le_bytes(hdr.try_into().unwrap()),
        (8, true) => u64::from_be_bytes(hdr.try_into().unwrap()),
        (_, false) => u32::from_le_bytes(hdr.try_into().unwrap()) as u64,
        (_, true) => u32::from_be_bytes(hdr.try_into().unwrap()) as u64,
    } as usize;
    let data = &raw[hsize..];
    if data.len() < nbytes {
        return Err(ctx.err(a.text_at, format!("{label}: header announces {nbytes} bytes, {} present", data.len())));
    }
    let data = &data[..nbytes];
    let size = match a.ty.as_str() {
        "Int8" | "UInt8" => 1,
        "Int16" | "UInt16" => 2,
        "Int32" | "UInt32" | "Float32" => 4,
        "Int64" | "UInt64" | "Float64" => 8,
        t => {
            return Err(ctx.err(a.at, format!("{label}: unknown type `{t}`")));
        }
    };
    if nbytes % size != 0 {
        return Err(ctx.err(a.text_at, format!("{label}: {nbytes} bytes is not a whole number of {} values", a.ty)));
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
