//! OpenFOAM's `polyMesh` read, as a [`FaceMeshData`], and its points written back.
//!
//! A polyMesh directory (`constant/polyMesh` of a case) holds the mesh as faces: `points`
//! (`vectorField`), `faces` (`faceList`, or `faceCompactList` as binary files hold them), `owner`
//! and `neighbour` (`labelList`: the cell on each side of a face; `neighbour` lists the interior
//! faces only, which come first) and `boundary` (the patches: name, `startFace`, `nFaces`). Each
//! file has a `FoamFile` header: `format ascii` or `binary`, and `arch "LSB;label=32;scalar=64"`
//! (labels of 32 or 64 bits, scalars of 32 or 64 bits; big-endian data is `Unsupported`). A
//! file may be gzip-compressed (`points.gz`, …) as OpenFOAM writes it with `writeCompression on`.
//!
//! Patch `i` of `boundary` (0-based, in file order) is patch id `i + 1`, and its name is the
//! patch's: case files name patches of a polyMesh as they name Gmsh physical groups. Every
//! other file of the directory (`cellZones`, `pointLevel`, …) is left as it is.
//!
//! The writer writes `points` only, in the format it was read in (ASCII with shortest
//! round-trip numbers, or binary of the same sizes; compressed when it was), so OpenFOAM reads
//! the moved mesh with its faces, cells and patches unchanged.
//!
//! Our own parser: the format is small, and the crates that read it are tied to one variant
//! (ASCII only) or do not say which file and line is wrong, which the reader's errors must.

mod lists;
mod tokens;
mod write;

pub use write::{format_points, write_points, write_polymesh};

use super::{io_err, IoError};
use crate::mesh::{FaceMeshData, Mesh};
use std::io::Read;
use std::path::{Path, PathBuf};
use tokens::Cursor;

/// How a polyMesh's points were stored: the writer writes them back the same way.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FoamFormat {
    /// `format binary` (else ASCII).
    pub binary: bool,
    /// Bytes of a label in binary files: 4 or 8.
    pub label_bytes: usize,
    /// Bytes of a scalar in binary files: 4 or 8.
    pub scalar_bytes: usize,
    /// The points file was gzip-compressed (`points.gz`).
    pub compressed: bool,
    /// The `location` of the points file's header (`constant/polyMesh` as OpenFOAM writes it).
    pub location: String,
}

impl Default for FoamFormat {
    fn default() -> Self {
        FoamFormat {
            binary: false,
            label_bytes: 4,
            scalar_bytes: 8,
            compressed: false,
            location: "constant/polyMesh".into(),
        }
    }
}

/// A polyMesh as read: the faces, the patch names and the points file's format.
#[derive(Clone, Debug, PartialEq)]
pub struct FoamMesh {
    /// The mesh (3D), faces as OpenFOAM orders them; boundary patch `i` of the file has id
    /// `i + 1`, interior faces −1.
    pub faces: FaceMeshData,
    /// `(patch id, name)` of every patch of `boundary`, in file order (empty patches included).
    pub patch_names: Vec<(i32, String)>,
    /// How the points were stored.
    pub format: FoamFormat,
    /// The polyMesh directory read.
    pub dir: PathBuf,
}

impl FoamMesh {
    /// The mesh ([`FaceMeshData::to_mesh`]): cells recognised as tetrahedra, hexahedra, wedges
    /// and pyramids where they are one, else polyhedra; vertices in the order of `points`.
    pub fn to_mesh(&self) -> Result<Mesh, IoError> {
        Ok(self.faces.to_mesh()?)
    }
}

/// The polyMesh directory of `path`: `path` itself when it holds `points` (or `points.gz`), else
/// `path/constant/polyMesh` (a case directory).
pub fn polymesh_dir(path: &Path) -> Option<PathBuf> {
    let holds = |d: &Path| d.join("points").is_file() || d.join("points.gz").is_file();
    if holds(path) {
        return Some(path.to_path_buf());
    }
    let d = path.join("constant").join("polyMesh");
    holds(&d).then_some(d)
}

/// Reads the polyMesh at `path` (a polyMesh directory or a case directory; see
/// [`polymesh_dir`]).
pub fn read_polymesh(path: &Path) -> Result<FoamMesh, IoError> {
    let dir = polymesh_dir(path).ok_or_else(|| {
        IoError::InvalidArgument(format!(
            "{}: neither a polyMesh directory (with `points`, `faces`, `owner`, `neighbour`, `boundary`) nor a \
             case directory with constant/polyMesh",
            path.display()
        ))
    })?;
    let mut files = Vec::with_capacity(5);
    let mut compressed = false;
    for name in ["points", "faces", "owner", "neighbour", "boundary"] {
        let (bytes, gz) = read_file(&dir, name)?;
        compressed |= gz && name == "points";
        files.push(bytes);
    }
    let label = |name: &str| dir.join(name).display().to_string();
    let names = ["points", "faces", "owner", "neighbour", "boundary"].map(label);
    let (faces, patch_names, mut format) = parse_polymesh(
        [&files[0], &files[1], &files[2], &files[3], &files[4]],
        [&names[0], &names[1], &names[2], &names[3], &names[4]],
    )?;
    format.compressed = compressed;
    Ok(FoamMesh { faces, patch_names, format, dir })
}

/// The bytes of `dir/name`, else of `dir/name.gz` inflated; and whether it was compressed.
fn read_file(dir: &Path, name: &str) -> Result<(Vec<u8>, bool), IoError> {
    let plain = dir.join(name);
    if plain.is_file() || !dir.join(format!("{name}.gz")).is_file() {
        return Ok((std::fs::read(&plain).map_err(io_err(&plain))?, false));
    }
    let gz = dir.join(format!("{name}.gz"));
    let file = std::fs::File::open(&gz).map_err(io_err(&gz))?;
    let mut out = Vec::new();
    flate2::read::MultiGzDecoder::new(file).read_to_end(&mut out).map_err(io_err(&gz))?;
    Ok((out, true))
}

/// What [`parse_polymesh`] returns: the faces, the patch names and the points' format.
type Parsed = (FaceMeshData, Vec<(i32, String)>, FoamFormat);

/// Parses the five files (points, faces, owner, neighbour, boundary; `names` for errors) into a
/// [`FaceMeshData`] with its patch names, checking that they fit together.
pub(crate) fn parse_polymesh(files: [&[u8]; 5], names: [&str; 5]) -> Result<Parsed, IoError> {
    let [points, faces, owner, neighbour, boundary] = files;
    let mut c = Cursor::new(points, names[0]);
    let h = c.header()?;
    let coords = lists::points(&mut c, &h)?;
    let format = FoamFormat {
        binary: h.binary,
        label_bytes: h.label_bytes,
        scalar_bytes: h.scalar_bytes,
        compressed: false,
        location: if h.location.is_empty() { FoamFormat::default().location } else { h.location.clone() },
    };
    let nv = coords.len() / 3;

    let mut c = Cursor::new(faces, names[1]);
    let h = c.header()?;
    let (offsets, vertices) = lists::faces(&mut c, &h)?;
    let nf = offsets.len().saturating_sub(1);
    let bad =
        |file: &str, message: String| IoError::Parse { line: 0, offset: None, message: format!("{file}: {message}") };
    let face_vertices = vertices
        .iter()
        .map(|&v| u32::try_from(v).ok().filter(|&v| (v as usize) < nv))
        .collect::<Option<Vec<u32>>>()
        .ok_or_else(|| {
            let f = offsets
                .windows(2)
                .position(|w| (w[0]..w[1]).any(|k| vertices[k as usize] < 0 || vertices[k as usize] as usize >= nv));
            bad(names[1], format!("face {}: a vertex outside the {nv} points", f.unwrap_or(0)))
        })?;
    let face_offsets = offsets
        .iter()
        .map(|&o| u32::try_from(o).ok())
        .collect::<Option<Vec<u32>>>()
        .ok_or_else(|| bad(names[1], "more face vertices than 32-bit offsets hold".into()))?;

    let mut c = Cursor::new(owner, names[2]);
    let h = c.header()?;
    let cells = count_of(&h.note, "nCells");
    let owner = lists::labels(&mut c, &h, "the owners")?;
    let mut c = Cursor::new(neighbour, names[3]);
    let hn = c.header()?;
    let mut neighbour = lists::labels(&mut c, &hn, "the neighbours")?;
    if owner.len() != nf {
        return Err(bad(names[2], format!("{} owners for the {nf} faces of {}", owner.len(), names[1])));
    }
    if neighbour.len() > nf {
        return Err(bad(names[3], format!("{} neighbours for the {nf} faces of {}", neighbour.len(), names[1])));
    }
    let interior = neighbour.len();
    neighbour.resize(nf, -1);
    if let Some(nc) = cells {
        for (file, list) in [(names[2], &owner[..]), (names[3], &neighbour[..interior])] {
            if let Some(f) = list.iter().position(|&x| x < 0 || x >= nc) {
                return Err(bad(file, format!("face {f}: cell {} outside the {nc} cells (nCells)", list[f])));
            }
        }
    }
    if let Some(f) = owner.iter().position(|&x| x < 0) {
        return Err(bad(names[2], format!("face {f}: owner {} is negative", owner[f])));
    }

    let mut c = Cursor::new(boundary, names[4]);
    c.header()?;
    let patches = lists::patches(&mut c)?;
    let mut patch = vec![-1i32; nf];
    let mut patch_names = Vec::with_capacity(patches.len());
    for (i, p) in patches.iter().enumerate() {
        let id = i32::try_from(i + 1).map_err(|_| bad(names[4], "too many patches".into()))?;
        let end = p.start.checked_add(p.count).filter(|&e| e <= nf);
        let Some(end) = end else {
            return Err(bad(
                names[4],
                format!("patch `{}`: faces {}..{}+{} outside the {nf} faces", p.name, p.start, p.start, p.count),
            ));
        };
        if let Some(f) = (p.start..end).find(|&f| patch[f] >= 0) {
            return Err(bad(names[4], format!("patch `{}`: face {f} is in an earlier patch too", p.name)));
        }
        patch[p.start..end].fill(id);
        patch_names.push((id, p.name.clone()));
    }
    if let Some(f) = (0..nf).find(|&f| neighbour[f] < 0 && patch[f] < 0) {
        return Err(bad(names[4], format!("face {f} has no neighbour and is in no patch")));
    }
    let faces =
        FaceMeshData { dim: 3, coords, face_offsets, face_vertices, owner, neighbour, patch, regions: Vec::new() };
    Ok((faces, patch_names, format))
}

/// The count `key` of a header note such as `nPoints:444  nCells:243 …`.
fn count_of(note: &str, key: &str) -> Option<i64> {
    note.split_whitespace().find_map(|w| w.strip_prefix(key)?.strip_prefix(':')?.parse().ok())
}

#[cfg(test)]
mod tests;
