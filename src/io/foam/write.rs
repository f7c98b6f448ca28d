//! A polyMesh's `points` written back: ASCII (shortest round-trip numbers, so the file reads back
//! to the same bits) or binary of the format read, gzip-compressed when it was.

use super::FoamFormat;
use crate::io::{io_err, IoError};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The contents of a `points` file of `coords` (x, y, z of each point) in `format` (not
/// compressed).
pub fn format_points(coords: &[f64], format: &FoamFormat) -> Result<Vec<u8>, IoError> {
    if coords.len() % 3 != 0 {
        return Err(IoError::InvalidArgument(format!("{} coordinates are not whole 3D points", coords.len())));
    }
    if ![4, 8].contains(&format.scalar_bytes) || ![4, 8].contains(&format.label_bytes) {
        return Err(IoError::InvalidArgument(format!(
            "labels of {} and scalars of {} bytes; 4 or 8 expected",
            format.label_bytes, format.scalar_bytes
        )));
    }
    let n = coords.len() / 3;
    let mut head = String::from("FoamFile\n{\n    version     2.0;\n");
    let _ = writeln!(head, "    format      {};", if format.binary { "binary" } else { "ascii" });
    head.push_str("    class       vectorField;\n");
    if format.binary {
        let _ = writeln!(
            head,
            "    arch        \"LSB;label={};scalar={}\";",
            8 * format.label_bytes,
            8 * format.scalar_bytes
        );
    }
    let _ = write!(head, "    location    \"{}\";\n    object      points;\n}}\n\n{n}\n(", format.location);
    let mut out = head.into_bytes();
    if format.binary {
        out.reserve(n * 3 * format.scalar_bytes + 3);
        for &x in coords {
            if format.scalar_bytes == 4 {
                out.extend_from_slice(&(x as f32).to_le_bytes());
            } else {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        out.extend_from_slice(b")\n");
    } else {
        let mut s = String::with_capacity(n * 60);
        s.push('\n');
        for p in coords.chunks_exact(3) {
            let _ = writeln!(s, "({:?} {:?} {:?})", p[0], p[1], p[2]);
        }
        s.push_str(")\n");
        out.extend_from_slice(s.as_bytes());
    }
    Ok(out)
}

/// Writes `coords` as the `points` of the polyMesh directory `dir` (`points.gz` when
/// `format.compressed`), through a temporary file renamed over the old one, so that a failed
/// write leaves the old points. Returns the path written.
pub fn write_points(dir: &Path, coords: &[f64], format: &FoamFormat) -> Result<PathBuf, IoError> {
    let mut bytes = format_points(coords, format)?;
    let name = if format.compressed { "points.gz" } else { "points" };
    let path = dir.join(name);
    let tmp = dir.join(format!(".{name}.meshmove-tmp"));
    if format.compressed {
        let mut z = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(&bytes).and_then(|_| z.finish()).map(|b| bytes = b).map_err(io_err(&path))?;
    }
    std::fs::write(&tmp, &bytes).map_err(io_err(&tmp))?;
    std::fs::rename(&tmp, &path).map_err(io_err(&path))?;
    Ok(path)
}

/// Writes the polyMesh of `source` with `coords` as its points into the directory `out`: every
/// other file of `source` copied as it is (none when `out` is `source`), then
/// [`write_points`]. `out` is created if missing.
pub fn write_polymesh(source: &Path, out: &Path, coords: &[f64], format: &FoamFormat) -> Result<PathBuf, IoError> {
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let same = match (source.canonicalize(), out.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if !same {
        for entry in std::fs::read_dir(source).map_err(io_err(source))? {
            let entry = entry.map_err(io_err(source))?;
            let name = entry.file_name();
            let is_points = name == "points" || name == "points.gz";
            if entry.file_type().map_err(io_err(&entry.path()))?.is_file() && !is_points {
                let to = out.join(&name);
                std::fs::copy(entry.path(), &to).map_err(io_err(&to))?;
            }
        }
    }
    write_points(out, coords, format)
}
