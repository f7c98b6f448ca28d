//! `meshmove deform MESH --config CASE.toml -o OUT.vtu`: the user's own mesh and case. MESH is a
//! `.msh`, a `.vtu` or an OpenFOAM polyMesh (or case) directory, whose moved mesh is written as a
//! polyMesh directory at OUT unless OUT ends in `.vtu` (`output`).
//!
//! The case file (TOML): every key, its default and an example of each feature are in
//! docs/CASE-FORMAT.md, whose examples tests/case_format.rs runs.
//!
//! Exit status: 0 on a valid result; 1 on a bad mesh or case file (nothing written); 2 on usage
//! errors (clap); 3 when the result has inverted cells (the .vtu is still written); 4 when a step
//! failed (not converged, sub-stepping limit reached, tangled reference): the last valid mesh is
//! written to `OUT.last-valid.vtu` beside the requested output; 5 when Ctrl-C stopped the run: the
//! last valid mesh is written there too (a second Ctrl-C exits at once, with 130).

mod carried;
mod output;
#[cfg(feature = "mpi")]
mod pieces;
#[cfg(feature = "mpi")]
mod ranks;
mod series;

use carried::{Carried, WallShape};
use indicatif::{ProgressBar, ProgressStyle};
use meshmove::io::{read_msh, read_polymesh, read_vtu, VtuEncoding};
use meshmove::solver::{ReferenceMode, StepReport};
use meshmove::{
    BoundaryConditions, InterfaceVariant, Kind, Link, Mesh, Method, Motion, Options, Progress, RigidMotion,
};
use meshmove_cases::report::run_series_with;
use meshmove_cases::setups::CaseSetup;
use output::{step_path, PolyMeshSource};
use serde::Deserialize;
use series::{periodic, FieldTrack, RigidTrack, Series};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

#[derive(clap::Args)]
pub struct Args {
    /// The mesh: Gmsh .msh (2.2 or 4.1; physical groups are patches), .vtu, or an OpenFOAM
    /// polyMesh directory (or a case directory with constant/polyMesh; its patches by name).
    mesh: PathBuf,
    /// The case file (TOML).
    #[arg(long)]
    config: PathBuf,
    /// Also draw the deformed mesh to this PNG file (title, inverted cells, min area ratio).
    #[arg(long, value_name = "FILE")]
    png: Option<PathBuf>,
    /// Where to write the deformed mesh: a .vtu file; for a polyMesh, a polyMesh directory
    /// (the input's files with the moved points; the input directory itself to move it in
    /// place) unless the name ends in .vtu; under mpirun also a .pvtu index, each rank writing
    /// its piece beside it (OUT_0.vtu, OUT_1.vtu, …).
    #[arg(short, long)]
    output: PathBuf,
    /// Also write the deformed mesh to this .vtu file.
    #[arg(long, value_name = "FILE")]
    vtu: Option<PathBuf>,
    /// Also write one JSON object per sub-step (JSON lines) to this file.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Also write the mesh after every K-th step (and the last) to OUT_NNNN.vtu beside OUT.vtu,
    /// NNNN the step.
    #[arg(long, value_name = "K")]
    every: Option<std::num::NonZeroUsize>,
    /// How the .vtu files are encoded.
    #[arg(long, value_enum, default_value_t = Encoding::Binary)]
    encoding: Encoding,
}

/// `--encoding`: [`VtuEncoding`]'s variants.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
enum Encoding {
    /// Appended raw binary: the fastest to write and read.
    Binary,
    /// Appended binary compressed by zlib: smaller, slower to write.
    Compressed,
    /// Text.
    Ascii,
}

impl Encoding {
    fn vtu(self) -> VtuEncoding {
        match self {
            Encoding::Binary => VtuEncoding::Binary,
            Encoding::Compressed => VtuEncoding::Compressed,
            Encoding::Ascii => VtuEncoding::Ascii,
        }
    }
}

/// `steps = N` or `steps = "auto"` (one step, split automatically as needed).
#[derive(Deserialize, Debug)]
#[serde(untagged)]
enum StepsSpec {
    Count(usize),
    Word(String),
}

#[derive(Deserialize, Debug, Clone)]
#[serde(untagged)]
enum PatchRef {
    Id(i32),
    Name(String),
}

#[derive(Deserialize, Debug)]
#[serde(untagged)]
enum KindSpec {
    Both(String),
    PerComponent(Vec<String>),
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct PatchCfg {
    patch: PatchRef,
    kind: KindSpec,
    /// A slip patch's analytic wall: sphere (circle), cylinder or plane (line).
    shape: Option<String>,
    center: Option<Vec<f64>>,
    radius: Option<f64>,
    axis: Option<Vec<f64>>,
    point: Option<Vec<f64>>,
    normal: Option<Vec<f64>>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct LinkCfg {
    a: PatchRef,
    b: PatchRef,
    offset: Vec<f64>,
    tol: Option<f64>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct InterfaceCfg {
    patch: PatchRef,
    variant: String,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct MotionCfg {
    patch: Option<PatchRef>,
    translation: Option<Vec<f64>>,
    rotation_deg: Option<f64>,
    axis: Option<Vec<f64>>,
    center: Option<Vec<f64>>,
    file: Option<PathBuf>,
    /// A periodic rigid motion or `file`: steps per period (the amplitudes are `translation`,
    /// `rotation_deg` or the file's displacement).
    period: Option<f64>,
    phase_deg: Option<f64>,
    /// Tables: the totals at the end of each step.
    translations: Option<Vec<Vec<f64>>>,
    rotations_deg: Option<Vec<f64>>,
    files: Option<Vec<PathBuf>>,
}

impl MotionCfg {
    /// The number of rows of this motion's tables, if it has any (all the same, else an error).
    fn rows(&self, what: &str) -> Result<Option<usize>, String> {
        let lens = [
            ("translations", self.translations.as_ref().map(Vec::len)),
            ("rotations_deg", self.rotations_deg.as_ref().map(Vec::len)),
            ("files", self.files.as_ref().map(Vec::len)),
        ];
        let mut given = lens.iter().filter_map(|(k, l)| l.map(|l| (k, l)));
        let Some((_, n)) = given.next() else { return Ok(None) };
        if let Some((k, l)) = given.find(|(_, l)| *l != n) {
            return Err(format!("{what}: `{k}` has {l} rows, the other table {n}"));
        }
        if n == 0 {
            return Err(format!("{what}: a table of no rows"));
        }
        Ok(Some(n))
    }
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Config {
    method: Option<String>,
    tolerance: Option<f64>,
    threads: Option<usize>,
    steps: Option<StepsSpec>,
    max_substeps: Option<usize>,
    min_volume_ratio: Option<f64>,
    reference: Option<String>,
    #[serde(default)]
    patch: Vec<PatchCfg>,
    #[serde(default)]
    link: Vec<LinkCfg>,
    #[serde(default)]
    interface: Vec<InterfaceCfg>,
    #[serde(default)]
    motion: Vec<MotionCfg>,
}

struct Patches {
    ids: Vec<i32>,
    names: Vec<(i32, String)>,
}

/// Sub-steps per step of `steps = "auto"`.
const AUTO_SUBSTEPS: usize = 1024;

impl Patches {
    /// `name (id)` for a named patch, the id otherwise.
    fn name(&self, id: i32) -> String {
        match self.names.iter().find(|(i, _)| *i == id) {
            Some((_, n)) => format!("`{n}` ({id})"),
            None => id.to_string(),
        }
    }

    fn resolve(&self, p: &PatchRef, what: &str) -> Result<i32, String> {
        let id = match p {
            PatchRef::Id(i) => *i,
            PatchRef::Name(n) => match self.names.iter().find(|(_, m)| m == n) {
                Some((i, _)) => *i,
                None => {
                    let known: Vec<&str> = self.names.iter().map(|(_, n)| n.as_str()).collect();
                    return Err(format!("{what}: no patch named `{n}` in the mesh (named patches: {known:?})"));
                }
            },
        };
        if self.ids.binary_search(&id).is_err() {
            return Err(format!("{what}: patch {id} is not in the mesh (patches: {:?})", self.ids));
        }
        Ok(id)
    }
}

fn kind(s: &str, what: &str) -> Result<Kind, String> {
    match s.to_ascii_lowercase().as_str() {
        "fixed" => Ok(Kind::Fixed),
        "clamped" => Ok(Kind::Clamped),
        "free" => Ok(Kind::Free),
        "slip" => Ok(Kind::Slip),
        _ => Err(format!("{what}: kind `{s}` is not one of fixed, clamped, free, slip")),
    }
}

/// A vector of the case file as 3 values: it must have `dim` components (the mesh's).
fn vector(v: &[f64], dim: usize, what: &str, key: &str) -> Result<[f64; 3], String> {
    if v.len() != dim {
        return Err(format!("{what}: `{key}` has {} components; the mesh is {dim}D: expected {dim}", v.len()));
    }
    let mut out = [0.0; 3];
    out[..dim].copy_from_slice(v);
    Ok(out)
}

/// The analytic wall of a `[[patch]]` entry, if it gives a `shape`: its keys checked against the
/// shape (each required one given, finite, a positive radius, a non-zero axis or normal; no key
/// of another shape).
fn slip_shape(p: &PatchCfg, dim: usize, what: &str) -> Result<Option<WallShape>, String> {
    let given = [("center", p.center.is_some()), ("radius", p.radius.is_some()), ("axis", p.axis.is_some())]
        .into_iter()
        .chain([("point", p.point.is_some()), ("normal", p.normal.is_some())]);
    let Some(shape) = p.shape.as_deref().map(str::to_ascii_lowercase) else {
        return match given.into_iter().find(|(_, g)| *g) {
            Some((key, _)) => Err(format!("{what}: `{key}` belongs to a `shape`, and none is given")),
            None => Ok(None),
        };
    };
    let (kind, keys): (&str, &[&str]) = match (shape.as_str(), dim) {
        ("sphere" | "circle", _) => ("sphere", &["center", "radius"]),
        ("cylinder", 3) => ("cylinder", &["center", "radius", "axis"]),
        ("plane" | "line", _) => ("plane", &["point", "normal"]),
        ("cylinder", _) => return Err(format!("{what}: shape `cylinder` is for 3D meshes (a 2D wall is a circle)")),
        (s, _) => return Err(format!("{what}: shape `{s}` is not one of sphere (circle), cylinder, plane (line)")),
    };
    for (key, is) in given {
        if is != keys.contains(&key) {
            let why = if is { "is not a key of" } else { "is required by" };
            return Err(format!("{what}: `{key}` {why} shape `{shape}`"));
        }
    }
    // A given key's vector, finite; a direction's also non-zero.
    let point = |v: &Option<Vec<f64>>, key: &str| {
        let x = vector(v.as_deref().unwrap_or_default(), dim, what, key)?;
        x.iter().all(|c| c.is_finite()).then_some(x).ok_or_else(|| format!("{what}: `{key}` is not finite"))
    };
    let direction = |v: &Option<Vec<f64>>, key: &str| {
        let x = point(v, key)?;
        x.iter().any(|&c| c != 0.0).then_some(x).ok_or_else(|| format!("{what}: `{key}` is zero"))
    };
    let radius = || match p.radius {
        Some(r) if r.is_finite() && r > 0.0 => Ok(r),
        r => Err(format!("{what}: `radius` must be a positive number, got {r:?}")),
    };
    Ok(Some(match kind {
        "sphere" => WallShape::Sphere { center: point(&p.center, "center")?, radius: radius()? },
        "cylinder" => WallShape::Cylinder {
            center: point(&p.center, "center")?,
            axis: direction(&p.axis, "axis")?,
            radius: radius()?,
        },
        _ => WallShape::Plane { point: point(&p.point, "point")?, normal: direction(&p.normal, "normal")? },
    }))
}

/// What `read_mesh` returns: the mesh, the names of its patches, the polyMesh it came from.
type MeshRead = (Mesh, Vec<(i32, String)>, Option<PolyMeshSource>);

/// The mesh and the names of its patches (Gmsh physical groups of dimension `dim - 1`; a
/// `.vtu`'s field data; a polyMesh's patches), and for a polyMesh (a directory) where it came
/// from.
fn read_mesh(path: &Path) -> Result<MeshRead, String> {
    if path.is_dir() {
        let m = read_polymesh(path).map_err(|e| format!("mesh {}: {e}", path.display()))?;
        let mesh = m.to_mesh().map_err(|e| format!("mesh {}: {e}", path.display()))?;
        return Ok((mesh, m.patch_names, Some(PolyMeshSource { dir: m.dir, format: m.format })));
    }
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    match ext.as_str() {
        "msh" => {
            let m = read_msh(path).map_err(|e| format!("mesh {}: {e}", path.display()))?;
            let pd = m.mesh.dim() as i32 - 1;
            let names = m.physical_names.iter().filter(|(d, _, _)| *d == pd).map(|(_, t, n)| (*t, n.clone())).collect();
            Ok((m.mesh, names, None))
        }
        "vtu" => {
            let d = read_vtu(path).map_err(|e| format!("mesh {}: {e}", path.display()))?;
            let m = d.to_mesh().map_err(|e| format!("mesh {}: {e}", path.display()))?;
            Ok((m, d.patch_names, None))
        }
        _ => Err(format!("mesh {}: unknown extension (expected .msh, .vtu or a polyMesh directory)", path.display())),
    }
}

/// A displacement per vertex (`dim` components, the rest 0) from a .vtu (point data
/// `displacement`) or a CSV `vertex,dx,dy` (2D) or `vertex,dx,dy,dz` (3D).
fn read_displacement(path: &Path, nv: usize, dim: usize) -> Result<Vec<Option<[f64; 3]>>, String> {
    let what = format!("displacement file {}", path.display());
    let mut out = vec![None; nv];
    if path.extension().and_then(|e| e.to_str()) == Some("vtu") {
        let d = read_vtu(path).map_err(|e| format!("{what}: {e}"))?;
        let (_, v, k) = d
            .point_data
            .iter()
            .find(|(n, _, _)| n == "displacement")
            .ok_or_else(|| format!("{what}: no point data `displacement`"))?;
        if *k < dim || v.len() != nv * k {
            return Err(format!(
                "{what}: `displacement` has {} values of {k} components; the mesh has {nv} vertices",
                v.len()
            ));
        }
        for (i, o) in out.iter_mut().enumerate() {
            let mut d = [0.0; 3];
            d[..dim].copy_from_slice(&v[i * k..i * k + dim]);
            *o = Some(d);
        }
        return Ok(out);
    }
    let text = std::fs::read_to_string(path).map_err(|e| format!("{what}: {e}"))?;
    for (ln, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') || (ln == 0 && line.starts_with(|c: char| c.is_alphabetic())) {
            continue;
        }
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let fields = ["vertex,dx,dy", "vertex,dx,dy,dz"][dim - 2];
        let bad = || format!("{what}: line {}: expected `{fields}`, got `{line}`", ln + 1);
        if f.len() != 1 + dim {
            return Err(bad());
        }
        let v: usize = f[0].parse().map_err(|_| bad())?;
        let mut d = [0.0f64; 3];
        for c in 0..dim {
            d[c] = f[1 + c].parse().map_err(|_| bad())?;
        }
        if v >= nv || d.iter().any(|x| !x.is_finite()) {
            return Err(format!("{what}: line {}: vertex {v} (the mesh has {nv}) or a non-finite value", ln + 1));
        }
        out[v] = Some(d);
    }
    Ok(out)
}

/// A case read: its set-up, options and step-by-step motions, the polyMesh it came from, and
/// its conditions' walls, links and interfaces as data (what `deform` under mpirun sends the
/// ranks beside the kinds).
type Built = (CaseSetup, Options, Series, Option<PolyMeshSource>, Carried);

fn build(args: &Args) -> Result<Built, String> {
    let text = std::fs::read_to_string(&args.config).map_err(|e| format!("config {}: {e}", args.config.display()))?;
    let cfg: Config = toml::from_str(&text).map_err(|e| format!("config {}: {e}", args.config.display()))?;
    let base = args.config.parent().unwrap_or(Path::new("."));
    let (mesh, names, foam) = read_mesh(&args.mesh)?;
    let dim = mesh.dim();
    if dim != 2 && dim != 3 {
        return Err(format!("mesh {}: a {dim}D mesh; `deform` moves 2D and 3D meshes", args.mesh.display()));
    }
    let patches = Patches { ids: mesh.patch_ids(), names };
    let method = match cfg.method.as_deref().unwrap_or("biharmonic").to_ascii_lowercase().as_str() {
        "biharmonic" => Method::Biharmonic,
        "laplacian" => Method::Laplacian,
        "spring" => Method::Spring,
        m => return Err(format!("config: method `{m}` is not one of biharmonic, laplacian, spring")),
    };
    let mut opts = Options { method, ..Default::default() };
    if let Some(t) = cfg.tolerance {
        if !(t > 0.0 && t.is_finite()) {
            return Err(format!("config: tolerance must be positive, got {t}"));
        }
        opts.solve.tol = t;
    }
    opts.threads = cfg.threads.unwrap_or(0);
    let rows = series_steps(&cfg)?;
    let (steps, auto) = match (&cfg.steps, rows) {
        (None, Some(n)) => (n, false),
        (None, None) => (1, false),
        (Some(StepsSpec::Count(n)), Some(rows)) if *n != rows => {
            return Err(format!("config: steps = {n}, but the tables of [[motion]] have {rows} rows (one a step)"))
        }
        (Some(StepsSpec::Count(n)), _) => (*n, false),
        (Some(StepsSpec::Word(w)), rows) if w == "auto" => {
            if rows.is_some() || cfg.motion.iter().any(|m| m.period.is_some()) {
                return Err("config: steps = \"auto\" is one step; a table or `period` needs steps = N".into());
            }
            (1, true)
        }
        (Some(StepsSpec::Word(w)), _) => return Err(format!("config: steps = \"{w}\" is not a count or \"auto\"")),
    };
    if cfg.steps.is_none() && rows.is_none() && cfg.motion.iter().any(|m| m.period.is_some()) {
        return Err("config: a motion with `period` needs `steps = N` (the steps of the whole run)".into());
    }
    if steps == 0 || steps > meshmove::solver::MAX_STEPS {
        return Err(format!("config: steps must be 1 to {}", meshmove::solver::MAX_STEPS));
    }
    opts.max_substeps = cfg.max_substeps.unwrap_or(if auto { AUTO_SUBSTEPS } else { 0 });
    if let Some(r) = cfg.min_volume_ratio {
        opts.min_volume_ratio = r;
    }
    opts.reference = match cfg.reference.as_deref().map(str::to_ascii_lowercase).as_deref() {
        None | Some("incremental") => ReferenceMode::Incremental,
        Some("original") => ReferenceMode::Original,
        Some(r) => return Err(format!("config: reference `{r}` is not incremental or original")),
    };
    let mut bcs = BoundaryConditions::new();
    let mut carried = Carried::default();
    let mut listed: Vec<(i32, usize)> = Vec::new();
    for (i, p) in cfg.patch.iter().enumerate() {
        let what = format!("config: [[patch]] {}", i + 1);
        let id = patches.resolve(&p.patch, &what)?;
        if let Some((_, first)) = listed.iter().find(|(q, _)| *q == id) {
            return Err(format!("{what}: patch {} is already given a kind by [[patch]] {first}", patches.name(id)));
        }
        listed.push((id, i + 1));
        match &p.kind {
            KindSpec::Both(k) => {
                bcs.set_kinds(id, kind(k, &what)?);
            }
            KindSpec::PerComponent(ks) => {
                if ks.len() != dim {
                    return Err(format!(
                        "{what}: `kind` has {} components; the mesh is {dim}D: expected {dim}",
                        ks.len()
                    ));
                }
                for (c, k) in ks.iter().enumerate() {
                    bcs.set_kind(id, c, kind(k, &what)?).map_err(|e| e.to_string())?;
                }
            }
        }
    }
    for (i, p) in cfg.patch.iter().enumerate() {
        let what = format!("config: [[patch]] {}", i + 1);
        if let Some(surface) = slip_shape(p, dim, &what)? {
            let id = patches.resolve(&p.patch, &what)?;
            if !bcs.is_slip(id) {
                return Err(format!("{what}: `shape` is for a patch of kind \"slip\""));
            }
            carried.walls.push((id, surface));
        }
    }
    for (i, l) in cfg.link.iter().enumerate() {
        let what = format!("config: [[link]] {}", i + 1);
        let (a, b) = (patches.resolve(&l.a, &what)?, patches.resolve(&l.b, &what)?);
        let offset = vector(&l.offset, dim, &what, "offset")?;
        carried.links.push(Link::ByOffset { a, b, offset, tol: l.tol.unwrap_or(1e-9) });
    }
    for (i, f) in cfg.interface.iter().enumerate() {
        let what = format!("config: [[interface]] {}", i + 1);
        let id = patches.resolve(&f.patch, &what)?;
        let v = match f.variant.to_ascii_lowercase().as_str() {
            "separate" | "a" => InterfaceVariant::Separate,
            "continuous" | "b" => InterfaceVariant::Continuous,
            v => return Err(format!("{what}: variant `{v}` is not separate (A) or continuous (B)")),
        };
        carried.interfaces.push((id, v));
    }
    carried.apply(&mut bcs);
    let mut motion = Motion::zero(&mesh);
    let mut series = Series::default();
    let mut moved_patch = 0;
    let mut moved: Vec<(i32, usize)> = Vec::new();
    for (i, m) in cfg.motion.iter().enumerate() {
        let what = format!("config: [[motion]] {}", i + 1);
        let patch = m.patch.as_ref().map(|p| patches.resolve(p, &what)).transpose()?;
        if let Some(p) = patch {
            if let Some((_, first)) = moved.iter().find(|(q, _)| *q == p) {
                return Err(format!("{what}: patch {} is already moved by [[motion]] {first}", patches.name(p)));
            }
            moved.push((p, i + 1));
        }
        if let Some(p) = patch {
            if moved_patch == 0 {
                moved_patch = p;
            }
        }
        let rigid = m.translation.is_some() || m.rotation_deg.is_some();
        let table = m.translations.is_some() || m.rotations_deg.is_some();
        let forms = [rigid, table, m.file.is_some(), m.files.is_some()];
        match forms.iter().filter(|&&f| f).count() {
            0 => {
                return Err(format!(
                    "{what}: give `translation`/`rotation_deg`, `translations`/`rotations_deg`, a displacement `file` or `files`"
                ))
            }
            1 => {}
            _ => {
                return Err(format!(
                    "{what}: give one of a rigid motion, a table of rigid motions, `file` and `files`, not several"
                ))
            }
        }
        if m.phase_deg.is_some() && m.period.is_none() {
            return Err(format!("{what}: `phase_deg` without `period`"));
        }
        let profile = match m.period {
            None => None,
            Some(_) if table || m.files.is_some() => {
                return Err(format!("{what}: `period` is for a rigid motion or a `file`, not a table"))
            }
            Some(p) if !(p > 0.0 && p.is_finite()) => {
                return Err(format!("{what}: `period` (steps per period) must be a positive number, got {p}"))
            }
            Some(p) => {
                let phase = m.phase_deg.unwrap_or(0.0).to_radians();
                if !phase.is_finite() {
                    return Err(format!("{what}: `phase_deg` is not finite"));
                }
                Some((1..=steps).map(|k| periodic(k, p, phase)).collect::<Vec<f64>>())
            }
        };
        if m.axis.is_some() && (m.file.is_some() || m.files.is_some()) {
            return Err(format!("{what}: `axis` belongs to a rigid motion, not to a displacement file"));
        }
        let file_field = |f: &Path| file_field(&base.join(f), patch, &mesh, &bcs, &patches, &what);
        if rigid || table {
            let p = patch.ok_or_else(|| format!("{what}: a rigid motion needs `patch`"))?;
            match (table, profile) {
                (false, None) => motion = motion.with_rigid(p, rigid_motion(m, dim, &what)?),
                (false, Some(factors)) => {
                    let r = rigid_motion(m, dim, &what)?;
                    let axis = rotation_axis(m, dim, &what, "rotation_deg", m.rotation_deg.is_some())?;
                    let angle = m.rotation_deg.unwrap_or(0.0).to_radians();
                    let totals = factors.iter().map(|&f| (r.translation.map(|t| t * f), angle * f)).collect();
                    series.rigid.push(RigidTrack { patch: p, axis, center: r.center, totals });
                }
                (true, _) => series.rigid.push(rigid_table(m, p, dim, steps, &what)?),
            }
        } else if let Some(f) = &m.file {
            let d = file_field(f)?;
            match profile {
                Some(factors) => {
                    let field = d.iter().flat_map(|v| v.unwrap_or_default()[..dim].to_vec()).collect();
                    series.fields.push(FieldTrack::Scaled { field, factors });
                }
                None => {
                    for (v, dv) in d.iter().enumerate() {
                        if let Some(dv) = dv {
                            motion.displacement[dim * v..dim * (v + 1)].copy_from_slice(&dv[..dim]);
                        }
                    }
                }
            }
        } else if let Some(files) = &m.files {
            let fields = files
                .iter()
                .map(|f| Ok(file_field(f)?.iter().flat_map(|v| v.unwrap_or_default()[..dim].to_vec()).collect()))
                .collect::<Result<Vec<Vec<f64>>, String>>()?;
            series.fields.push(FieldTrack::PerStep(fields));
        }
    }
    bcs.check(&mesh).map_err(|e| format!("config: {e}"))?;
    let name = args.mesh.file_stem().and_then(|s| s.to_str()).unwrap_or("mesh").to_string();
    Ok((CaseSetup { name, mesh, bcs, motion, steps, moved_patch, upper_region: None }, opts, series, foam, carried))
}

/// The number of steps the tables of the case's motions give (each table a row per step), if
/// any has one.
fn series_steps(cfg: &Config) -> Result<Option<usize>, String> {
    let mut rows: Option<(usize, usize)> = None;
    for (i, m) in cfg.motion.iter().enumerate() {
        let what = format!("config: [[motion]] {}", i + 1);
        match (m.rows(&what)?, rows) {
            (Some(n), Some((r, first))) if n != r => {
                return Err(format!("{what}: a table of {n} rows; [[motion]] {first}'s has {r}"))
            }
            (Some(n), None) => rows = Some((n, i + 1)),
            _ => {}
        }
    }
    Ok(rows.map(|(n, _)| n))
}

/// The displacement of a `[[motion]]`'s file `path` at each vertex it gives, only on `patch`'s
/// vertices when the motion names a patch; an error when it moves a component that is free there.
fn file_field(
    path: &Path,
    patch: Option<i32>,
    mesh: &Mesh,
    bcs: &BoundaryConditions,
    patches: &Patches,
    what: &str,
) -> Result<Vec<Option<[f64; 3]>>, String> {
    let dim = mesh.dim();
    let mut d = read_displacement(path, mesh.num_vertices(), dim)?;
    if let Some(p) = patch {
        for c in 0..dim {
            let moves = mesh.patch_vertices(p).iter().any(|&v| d[v as usize].is_some_and(|d| d[c] != 0.0));
            if moves && bcs.kind(p, c) == Kind::Free {
                return Err(format!(
                    "{what}: the file moves patch {} in {}, which is FREE there: make it fixed or clamped",
                    patches.name(p),
                    ["x", "y", "z"][c]
                ));
            }
        }
        let only = mesh.patch_vertices(p);
        for (v, dv) in d.iter_mut().enumerate() {
            if only.binary_search(&(v as u32)).is_err() {
                *dv = None;
            }
        }
    }
    Ok(d)
}

/// The rotation axis of a `[[motion]]` (unit; z in 2D): `axis` in 3D, required when the motion
/// rotates (`key` is given) and only then; an error in 2D.
fn rotation_axis(m: &MotionCfg, dim: usize, what: &str, key: &str, rotates: bool) -> Result<[f64; 3], String> {
    if dim == 2 {
        if m.axis.is_some() {
            return Err(format!("{what}: `axis` is for 3D meshes; a 2D rotation is about z"));
        }
        return Ok([0.0, 0.0, 1.0]);
    }
    match (&m.axis, rotates) {
        (None, false) => Ok([0.0, 0.0, 1.0]),
        (None, true) => Err(format!("{what}: a 3D rotation needs `axis = [ax, ay, az]` with `{key}`")),
        (Some(_), false) => Err(format!("{what}: `axis` without `{key}`")),
        (Some(a), true) => {
            let a = vector(a, 3, what, "axis")?;
            let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            if !(n > 0.0 && n.is_finite()) {
                return Err(format!("{what}: `axis` must be a non-zero finite vector"));
            }
            Ok(a.map(|x| x / n))
        }
    }
}

/// The rigid motion of a `[[motion]]` with `translations` and/or `rotations_deg`: the totals at
/// the end of each of the `steps` steps, about `axis` through `center`.
fn rigid_table(m: &MotionCfg, patch: i32, dim: usize, steps: usize, what: &str) -> Result<RigidTrack, String> {
    let axis = rotation_axis(m, dim, what, "rotations_deg", m.rotations_deg.is_some())?;
    let center = m.center.as_deref().map(|c| vector(c, dim, what, "center")).transpose()?.unwrap_or([0.0; 3]);
    let translations = match &m.translations {
        Some(rows) => rows
            .iter()
            .enumerate()
            .map(|(k, t)| vector(t, dim, what, &format!("translations[{k}]")))
            .collect::<Result<Vec<_>, _>>()?,
        None => vec![[0.0; 3]; steps],
    };
    let angles: Vec<f64> = match &m.rotations_deg {
        Some(a) => a.iter().map(|x| x.to_radians()).collect(),
        None => vec![0.0; steps],
    };
    let finite = translations.iter().flatten().chain(&angles).chain(&center).all(|x| x.is_finite());
    if !finite {
        return Err(format!("{what}: a value of `translations`, `rotations_deg` or `center` is not finite"));
    }
    Ok(RigidTrack { patch, axis, center, totals: translations.into_iter().zip(angles).collect() })
}

/// The rigid motion of a `[[motion]]`: in 2D `rotation_deg` about z; in 3D `rotation_deg` about
/// `axis` (normalised), both through `center`.
fn rigid_motion(m: &MotionCfg, dim: usize, what: &str) -> Result<RigidMotion, String> {
    let translation = m.translation.as_deref().map(|t| vector(t, dim, what, "translation")).transpose()?;
    let center = m.center.as_deref().map(|c| vector(c, dim, what, "center")).transpose()?;
    let (translation, center) = (translation.unwrap_or([0.0; 3]), center.unwrap_or([0.0; 3]));
    let angle = m.rotation_deg.unwrap_or(0.0).to_radians();
    let axis = rotation_axis(m, dim, what, "rotation_deg", m.rotation_deg.is_some())?;
    Ok(RigidMotion { translation, rotation: axis.map(|a| a * angle), center })
}

/// Set by Ctrl-C: the solver's progress hook then cancels the step under way.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Ctrl-C cancels the run at the next sub-step (the last valid mesh is then written); a second
/// one exits at once.
fn on_ctrl_c(opts: &mut Options) {
    let set = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });
    if set.is_ok() {
        opts.progress = Some(Progress::new(|_, _| !INTERRUPTED.load(Ordering::SeqCst)));
    }
}

pub fn run(args: Args) -> Result<ExitCode, String> {
    #[cfg(feature = "mpi")]
    if crate::distributed::launched() {
        return ranks::run(&args);
    }
    let (setup, mut opts, series, foam, _) = build(&args)?;
    let encoding = args.encoding.vtu();
    let write = |path: &Path, disp: &[f64]| output::write(path, &setup.mesh, disp, encoding, foam.as_ref());
    let mut step_file_error = None;
    on_ctrl_c(&mut opts);
    let bar = step_bar(setup.steps);
    let increment = |i| series.increment(&setup.motion, i, setup.steps);
    let r = run_series_with(&setup, opts.method, &opts, increment, |step, reps, coords| {
        if args.every.is_some_and(|k| step % k.get() == 0 || step == setup.steps) {
            let path = step_path(&args.output, step, setup.steps, foam.is_some());
            let disp: Vec<f64> = coords.iter().zip(setup.mesh.coords()).map(|(a, b)| a - b).collect();
            if let Err(e) = write(&path, &disp) {
                step_file_error.get_or_insert(e);
            }
        }
        reps.iter().for_each(|rep| print_line(&bar, rep.line()));
        bar.inc(1);
    })
    .map_err(|e| e.to_string())?;
    bar.finish_and_clear();
    if let Some(e) = step_file_error {
        return Err(e);
    }
    if let Some(path) = &args.report {
        write_report(path, r.reports.iter().map(|x| json_line(x, None)))?;
    }
    let (done, substeps) = progress(&r.reports);
    let how = format!(
        "{:?}, {} step(s) in {substeps} sub-step(s), {} cycles, {:.3} s, converged",
        opts.method, r.steps, r.cycles, r.seconds,
    );
    finish(&args, &setup, &r, (&how, done), write)
}

/// The progress bar of a run of `steps` steps (hidden below 5 steps).
fn step_bar(steps: usize) -> ProgressBar {
    let bar = if steps >= 5 { ProgressBar::new(steps as u64) } else { ProgressBar::hidden() };
    bar.set_style(
        ProgressStyle::with_template("{bar:40} step {pos}/{len} {elapsed}").unwrap_or(ProgressStyle::default_bar()),
    );
    bar
}

/// Prints a sub-step's report line above the progress bar (to stderr when it is hidden).
fn print_line(bar: &ProgressBar, line: String) {
    if bar.is_hidden() {
        eprintln!("{line}");
    } else {
        bar.println(line);
    }
}

/// The fraction of the motion the accepted sub-steps of `reports` reached, and how many they are.
fn progress(reports: &[StepReport]) -> (f64, usize) {
    let accepted = reports.iter().filter(|x| x.accepted);
    (accepted.clone().map(|x| x.fraction).fold(0.0, f64::max), accepted.count())
}

/// Writes the JSON lines of `--report` to `path`.
fn write_report(path: &Path, lines: impl Iterator<Item = String>) -> Result<(), String> {
    let text: String = lines.map(|l| l + "\n").collect();
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Writes a run's result and prints its summary (`how`: how it was solved; `done`: the fraction
/// of the motion its last valid mesh reached): the exit status of the run.
fn finish(
    args: &Args,
    setup: &CaseSetup,
    r: &meshmove_cases::report::CaseResult,
    (how, done): (&str, f64),
    write: impl Fn(&Path, &[f64]) -> Result<(), String>,
) -> Result<ExitCode, String> {
    let encoding = args.encoding.vtu();
    let original = setup.mesh.coords();
    if let Some(f) = &r.failure {
        let partial = args.output.with_extension("last-valid.vtu");
        let disp: Vec<f64> = r.last_valid.iter().zip(original).map(|(a, b)| a - b).collect();
        write(&partial, &disp)?;
        eprintln!("meshmove: error: {f}");
        eprintln!(
            "meshmove: the last valid mesh ({:.1}% of the motion) is written to {}; {} is not written",
            100.0 * done,
            partial.display(),
            args.output.display()
        );
        return Ok(ExitCode::from(if INTERRUPTED.load(Ordering::SeqCst) { 5 } else { 4 }));
    }
    let disp = r.displacement(&setup.mesh);
    write(&args.output, &disp)?;
    if let Some(vtu) = &args.vtu {
        output::write(vtu, &setup.mesh, &disp, encoding, None)?;
    }
    println!(
        "mesh            {} ({} vertices, {} cells)",
        args.mesh.display(),
        setup.mesh.num_vertices(),
        setup.mesh.num_cells()
    );
    println!("method          {how}");
    let measure = if setup.mesh.dim() == 2 { "area" } else { "volume" };
    println!(
        "inverted cells  {} (a corner Jacobian or volume <= 0), {} of non-positive {measure}",
        r.inverted, r.negative_volume_cells
    );
    println!("min {measure} ratio {:.4}", r.min_area_ratio);
    println!("min corner Jacobian ratio {:.4}", r.min_corner_jacobian_ratio);
    println!("min angle       {:.2} deg", r.min_angle_deg);
    let offwall = r.reports.iter().filter(|x| x.accepted).map(|x| x.max_slip_offwall).fold(0.0, f64::max);
    if setup.mesh.patch_ids().iter().any(|&p| setup.bcs.is_slip(p)) {
        println!("slip walls      largest distance of a slipped vertex from its wall {offwall:.2e}");
    }
    if setup.moved_patch != 0 {
        // The run's own measures of the moved patch (a case of `deform` has no upper region).
        let pm = &r.patch;
        println!(
            "moved patch {}   spacing variation {:.4}, first-cell {} ratio {:.4}..{:.4}",
            setup.moved_patch,
            pm.spacing_variation,
            if setup.mesh.dim() == 2 { "area" } else { "volume" },
            pm.area_ratio.0,
            pm.area_ratio.1
        );
    }
    println!("wrote           {}", args.output.display());
    if let Some(vtu) = &args.vtu {
        println!("wrote           {}", vtu.display());
    }
    if let Some(png) = &args.png {
        case_png(png, setup, &r.coords, r.method, r.steps)?;
    }
    if r.inverted > 0 {
        eprintln!(
            "meshmove: error: the deformed mesh has {} inverted cells (written anyway to {})",
            r.inverted,
            args.output.display()
        );
        return Ok(ExitCode::from(3));
    }
    Ok(ExitCode::SUCCESS)
}

/// One sub-step as a JSON object (non-finite numbers as null); under mpirun with the rank whose
/// owned cells hold the smallest volume ratio (`worst_rank`).
fn json_line(r: &StepReport, worst_rank: Option<usize>) -> String {
    let num = |x: f64| if x.is_finite() { format!("{x:?}") } else { "null".into() };
    format!(
        "{{\"step\":{},\"substep\":{},\"fraction\":{},\"cycles\":{},\"rel_residual\":{},\"converged\":{},\"rebuilt\":{},\"inverted\":{},\"min_volume_ratio\":{},\"min_angle_deg\":{},\"seconds\":{},\"solve_seconds\":{},\"quality_seconds\":{},\"reference_seconds\":{},\"accepted\":{},\"max_slip_offwall\":{}{}}}",
        r.step,
        r.substep,
        num(r.fraction),
        r.cycles,
        num(r.rel_residual),
        r.converged,
        r.rebuilt,
        r.inverted,
        num(r.min_volume_ratio),
        num(r.min_angle_deg),
        num(r.seconds),
        num(r.solve_seconds),
        num(r.quality_seconds),
        num(r.reference_seconds),
        r.accepted,
        num(r.max_slip_offwall),
        worst_rank.map(|w| format!(",\"worst_rank\":{w}")).unwrap_or_default()
    )
}

/// The picture `meshmove deform --png FILE` writes: the whole deformed mesh (3D: its section
/// through the moved patch, [`crate::plot3d::section_png`]), titled with the case's name, the
/// method and the step count, its moved patch drawn blue.
fn case_png(
    path: &Path,
    setup: &meshmove_cases::setups::CaseSetup,
    coords: &[f64],
    method: meshmove::Method,
    steps: usize,
) -> Result<(), String> {
    let title = format!("{}: {method:?}, {steps} step(s)", setup.name).to_lowercase();
    if setup.mesh.dim() == 3 {
        let axis = crate::plot3d::section_axis(&setup.mesh, &setup.motion);
        return crate::plot3d::section_png(path, (&setup.mesh, coords), (title, &[]), (axis, setup.moved_patch), 800)
            .map_err(|e| format!("{}: {e}", path.display()));
    }
    let (highlight, extra) = match setup.moved_patch {
        0 => (Vec::new(), Vec::new()),
        p => (crate::plot::patch_edges(&setup.mesh, p), vec![format!("blue: the moved patch ({p})")]),
    };
    crate::plot::deformed_png(path, (&setup.mesh, coords), (title, &extra), &highlight, (None, None), 800)
        .map_err(|e| format!("{}: {e}", path.display()))
}
