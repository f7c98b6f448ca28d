//! OpenFOAM's lists as the polyMesh files hold them: `N ( … )` in ASCII, `N (raw bytes)` in
//! binary (little-endian labels and scalars of the header's sizes), `N {value}` for a list of one
//! repeated label; points as a `vectorField`, faces as a `faceList` (`k(a b c …)` per face) or a
//! `faceCompactList` (the offsets, then every face's vertices).

use super::tokens::{Cursor, Header};
use crate::io::IoError;

/// The size `N` of a list and, after it, its opening bracket. The size is at most the bytes left
/// in the file (every entry takes at least one), so that a wrong size cannot allocate beyond
/// what the file holds.
fn open(c: &mut Cursor, what: &str) -> Result<usize, IoError> {
    let left = c.bytes.len() - c.pos;
    let n = c.label(&format!("the size of {what}"), left)?;
    c.expect(b'(', &format!("to open {what} of {n} entries"))?;
    Ok(n)
}

/// The binary data of `n` items of `size` bytes, up to the closing bracket.
fn raw_items<'a>(c: &mut Cursor<'a>, n: usize, size: usize, what: &str) -> Result<&'a [u8], IoError> {
    let bytes = n.checked_mul(size).ok_or_else(|| c.error(format!("{what}: {n} entries are too many")))?;
    let data = c.raw(bytes, what)?;
    c.expect(b')', &format!("to close {what} of {n} entries"))?;
    Ok(data)
}

/// A little-endian label of 4 or 8 bytes.
fn label_le(b: &[u8]) -> i64 {
    match b.len() {
        4 => i64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        _ => i64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
    }
}

/// A little-endian scalar of 4 or 8 bytes.
fn scalar_le(b: &[u8]) -> f64 {
    match b.len() {
        4 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        _ => f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
    }
}

/// A list of labels (`labelList`), as signed integers: `owner`, `neighbour`, the parts of a
/// `faceCompactList`.
pub(super) fn labels(c: &mut Cursor, h: &Header, what: &str) -> Result<Vec<i64>, IoError> {
    let left = c.bytes.len() - c.pos;
    let n = c.label(&format!("the size of {what}"), left)?;
    if c.peek() == Some(b'{') {
        c.expect(b'{', "")?;
        let v = c.signed(&format!("the value of {what}"))?;
        c.expect(b'}', &format!("to close the uniform {what}"))?;
        return Ok(vec![v; n]);
    }
    c.expect(b'(', &format!("to open {what} of {n} entries"))?;
    if h.binary {
        let data = raw_items(c, n, h.label_bytes, what)?;
        return Ok(data.chunks_exact(h.label_bytes).map(label_le).collect());
    }
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        out.push(c.signed(&format!("entry {i} of {what}"))?);
    }
    c.expect(b')', &format!("to close {what} of {n} entries"))?;
    Ok(out)
}

/// The points (`vectorField`): x, y, z of each.
pub(super) fn points(c: &mut Cursor, h: &Header) -> Result<Vec<f64>, IoError> {
    let n = open(c, "the points")?;
    if h.binary {
        let data = raw_items(c, n, 3 * h.scalar_bytes, "the points")?;
        let out: Vec<f64> = data.chunks_exact(h.scalar_bytes).map(scalar_le).collect();
        if let Some(i) = out.iter().position(|x| !x.is_finite()) {
            return Err(c.error(format!("point {}: a coordinate is not finite", i / 3)));
        }
        return Ok(out);
    }
    let mut out = Vec::with_capacity(3 * n);
    for i in 0..n {
        let what = format!("point {i}");
        c.expect(b'(', &format!("to open {what}"))?;
        for _ in 0..3 {
            out.push(c.scalar(&format!("a coordinate of {what}"))?);
        }
        c.expect(b')', &format!("to close {what} (three coordinates)"))?;
    }
    c.expect(b')', &format!("to close the points ({n} of them)"))?;
    Ok(out)
}

/// The faces as CSR (offsets from 0, vertex indices), from a `faceList` or `faceCompactList`.
pub(super) fn faces(c: &mut Cursor, h: &Header) -> Result<(Vec<i64>, Vec<i64>), IoError> {
    if h.class == "faceCompactList" {
        let at = c.pos;
        let offsets = labels(c, h, "the face offsets")?;
        let vertices = labels(c, h, "the face vertices")?;
        if offsets.first().is_some_and(|&o| o != 0) || offsets.last().is_some_and(|&o| o != vertices.len() as i64) {
            return Err(c.error_at(
                at,
                format!(
                    "the face offsets run from {:?} to {:?}; from 0 to the {} face vertices expected",
                    offsets.first(),
                    offsets.last(),
                    vertices.len()
                ),
            ));
        }
        if let Some(f) = offsets.windows(2).position(|w| w[1] < w[0]) {
            return Err(c.error_at(at, format!("face {f}: its offsets decrease")));
        }
        return Ok((offsets, vertices));
    }
    let n = open(c, "the faces")?;
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0);
    let mut vertices = Vec::new();
    for f in 0..n {
        vertices.extend(labels(c, h, &format!("face {f}"))?);
        offsets.push(vertices.len() as i64);
    }
    c.expect(b')', &format!("to close the faces ({n} of them)"))?;
    Ok((offsets, vertices))
}

/// A patch of the `boundary` file: its name, first face and number of faces.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Patch {
    pub name: String,
    pub start: usize,
    pub count: usize,
}

/// The patches of the `boundary` file (`polyBoundaryMesh`): `N ( name { … nFaces n; startFace
/// s; … } … )`; the other entries of each patch are skipped.
pub(super) fn patches(c: &mut Cursor) -> Result<Vec<Patch>, IoError> {
    let n = open(c, "the patches")?;
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let name = c.token(&format!("the name of patch {i}"))?.trim_matches('"').to_string();
        let at = c.pos;
        c.expect(b'{', &format!("to open patch `{name}`"))?;
        let (mut start, mut count) = (None, None);
        while c.peek() != Some(b'}') {
            let key = c.token(&format!("an entry of patch `{name}`"))?;
            let slot = match key {
                "startFace" => &mut start,
                "nFaces" => &mut count,
                _ => {
                    c.skip_entry()?;
                    continue;
                }
            };
            *slot = Some(c.label(&format!("`{key}` of patch `{name}`"), u32::MAX as usize)?);
            c.expect(b';', &format!("after `{key}` of patch `{name}`"))?;
        }
        c.expect(b'}', &format!("to close patch `{name}`"))?;
        match (start, count) {
            (Some(start), Some(count)) => out.push(Patch { name, start, count }),
            _ => return Err(c.error_at(at, format!("patch `{name}`: `startFace` and `nFaces` expected"))),
        }
    }
    c.expect(b')', &format!("to close the patches ({n} of them)"))?;
    Ok(out)
}
