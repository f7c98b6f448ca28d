//! Where `deform` writes a moved mesh: a `.vtu` file, or, for a mesh read from an OpenFOAM
//! polyMesh, a polyMesh directory (the source's files with the moved `points`, in the format
//! they were read in).

use meshmove::io::{write_deformed_as, write_polymesh, FoamFormat, VtuEncoding};
use meshmove::Mesh;
use std::path::{Path, PathBuf};

/// The polyMesh a mesh was read from: its directory and how its points were stored.
pub struct PolyMeshSource {
    pub dir: PathBuf,
    pub format: FoamFormat,
}

/// True when `path` names a `.vtu` file.
fn is_vtu(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("vtu"))
}

/// Writes `mesh` moved by `disp`: to a polyMesh directory at `path` when the mesh came from a
/// polyMesh and `path` is not a `.vtu` (the source directory itself included: then only its
/// points are replaced), else to the `.vtu` file `path`.
pub fn write(
    path: &Path,
    mesh: &Mesh,
    disp: &[f64],
    encoding: VtuEncoding,
    foam: Option<&PolyMeshSource>,
) -> Result<(), String> {
    let result = match foam {
        Some(src) if !is_vtu(path) => {
            let coords: Vec<f64> = mesh.coords().iter().zip(disp).map(|(x, d)| x + d).collect();
            write_polymesh(&src.dir, path, &coords, &src.format).map(|_| ())
        }
        _ => write_deformed_as(path, &mesh.to_data(), disp, encoding),
    };
    result.map_err(|e| format!("{}: {e}", path.display()))
}

/// Where `--every` writes the mesh after step `step` of `steps`: OUT_NNNN.vtu beside OUT.vtu (or
/// the polyMesh directory OUT_NNNN beside OUT), the step in as many digits as the last one has
/// (at least 4), so that the files sort in order and ParaView opens them as one series.
pub fn step_path(output: &Path, step: usize, steps: usize, foam: bool) -> PathBuf {
    let stem = output.file_stem().and_then(|s| s.to_str()).unwrap_or("out");
    let width = steps.to_string().len().max(4);
    let ext = if foam && !is_vtu(output) { "" } else { ".vtu" };
    output.with_file_name(format!("{stem}_{step:0width$}{ext}"))
}
