//! Running a case with one method and measuring the result against the ORIGINAL mesh
//! (docs/DESIGN.md §7's quality measures).

use super::setups::CaseSetup;
use glam::{DVec2, DVec3};
use meshmove::mesh::quality::{quality, signed_measures};
use meshmove::mesh::Mesh;
use meshmove::solver::{Options, Solver, StepReport};
use meshmove::Result;
use meshmove::{Method, Motion};
use std::collections::HashMap;
use std::time::Instant;

/// Lower-case method name as in `results.csv`.
pub fn method_name(m: Method) -> &'static str {
    match m {
        Method::Biharmonic => "biharmonic",
        Method::Laplacian => "laplacian",
        Method::Spring => "spring",
    }
}

/// The three methods, in the CSV's order.
pub const METHODS: [Method; 3] = [Method::Biharmonic, Method::Laplacian, Method::Spring];

/// Measures along the moved patch of a deformed mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchMeasures {
    /// (max − min)/mean of h/h₀ over the cells touching the patch by an edge (h: the cell's height
    /// over that edge, deformed; h₀ the same in the original mesh). In 3D: by a face, h the cell's
    /// volume over the face's area.
    pub spacing_variation: f64,
    /// Smallest and largest deformed/original area (volume) ratio of those cells.
    pub area_ratio: (f64, f64),
    /// Interfaces: mean h/h₀ of the first cells above (region `upper`) over that below.
    pub spacing_ratio_across: Option<f64>,
}

/// One row of `results.csv`, plus what the tests and RESULTS.md use besides.
#[derive(Clone, Debug)]
pub struct CaseResult {
    pub case: String,
    /// The mesh's dimension, 2 or 3.
    pub dim: usize,
    pub method: Method,
    pub steps: usize,
    /// Cells with a non-positive corner Jacobian.
    pub inverted: usize,
    /// Cells of non-positive area (volume).
    pub negative_volume_cells: usize,
    /// Smallest deformed/original area (volume) ratio.
    pub min_area_ratio: f64,
    /// Smallest deformed/original ratio of a cell's smallest corner Jacobian.
    pub min_corner_jacobian_ratio: f64,
    pub min_angle_deg: f64,
    pub patch: PatchMeasures,
    /// W-cycles (CG iterations in the default mode) summed over the accepted steps and each
    /// step's result (one with inverted cells too), max over components.
    pub cycles: usize,
    /// Wall time of the whole case: hierarchy, every step.
    pub seconds: f64,
    /// Interface cases: largest y of a vertex of the upper region.
    pub max_y_upper: Option<f64>,
    /// First step (1-based) after which the mesh had an inverted cell, if any.
    pub first_inverted_step: Option<usize>,
    /// A step that failed, or whose result inverted cells while steps remained, with the
    /// message (the run stops there).
    pub failure: Option<String>,
    /// Final positions of every vertex (on a failure, the last mesh reached, which may be the
    /// inverted result that stopped the run).
    pub coords: Vec<f64>,
    /// The last valid mesh of the run (the final one when the run succeeded).
    pub last_valid: Vec<f64>,
    /// Reports of each sub-step.
    pub reports: Vec<StepReport>,
}

impl CaseResult {
    /// Displacement from the original mesh.
    pub fn displacement(&self, original: &Mesh) -> Vec<f64> {
        self.coords.iter().zip(original.coords()).map(|(a, b)| a - b).collect()
    }

    /// The CSV header of [`CaseResult::csv_row`].
    /// `inverted`: cells with a non-positive corner Jacobian; `negative_volume_cells`: cells of
    /// non-positive volume (area in 2D); `min_volume_ratio`: the smallest volume (area) ratio;
    /// `min_corner_jacobian_ratio`: the smallest ratio of a cell's smallest corner Jacobian
    /// (docs/DESIGN.md §7).
    pub const CSV_HEADER: &'static str = "case,method,steps,inverted,negative_volume_cells,min_volume_ratio,\
         min_corner_jacobian_ratio,min_angle_deg,spacing_variation,cycles,seconds,max_y_upper,dim";

    pub fn csv_row(&self) -> String {
        format!(
            "{},{},{},{},{},{:.6},{:.6},{:.4},{:.6},{},{:.4},{},{}",
            self.case,
            method_name(self.method),
            self.steps,
            self.inverted,
            self.negative_volume_cells,
            self.min_area_ratio,
            self.min_corner_jacobian_ratio,
            self.min_angle_deg,
            self.patch.spacing_variation,
            self.cycles,
            self.seconds,
            self.max_y_upper.map(|y| format!("{y:.6}")).unwrap_or_default(),
            self.dim
        )
    }
}

/// The cells touching `patch` (of a 2D mesh) by an edge, with that edge: (cell, a, b).
pub fn patch_cells(mesh: &Mesh, patch: i32) -> Vec<(usize, u32, u32)> {
    let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for c in 0..mesh.num_cells() {
        let t = mesh.cell(c);
        for k in 0..t.len() {
            let (a, b) = (t[k], t[(k + 1) % t.len()]);
            by_edge.entry((a.min(b), a.max(b))).or_default().push(c);
        }
    }
    let mut out = Vec::new();
    for e in mesh.patch_faces().filter(|e| e.patch == patch) {
        let [a, b] = [e.vertices[0], e.vertices[1]];
        for &c in by_edge.get(&(a.min(b), a.max(b))).map(|v| v.as_slice()).unwrap_or(&[]) {
            out.push((c, a, b));
        }
    }
    out
}

/// Twice the cell's signed area over the length of its edge (a, b): a triangle's height over
/// the edge, twice a quad's (only ratios of these are reported).
fn height(area: f64, a: DVec2, b: DVec2) -> f64 {
    2.0 * area / (b - a).length()
}

/// Vertex `v` of 2D positions `x`.
fn xy(x: &[f64], v: usize) -> DVec2 {
    DVec2::new(x[2 * v], x[2 * v + 1])
}

/// The measures of [`PatchMeasures`] for `original` moved to `deformed`.
pub fn patch_measures(original: &Mesh, deformed: &[f64], patch: i32, upper: Option<i32>) -> PatchMeasures {
    if original.dim() == 3 {
        return patch_measures_3d(original, deformed, patch, upper);
    }
    let a0 = signed_measures(original, original.coords());
    let a1 = signed_measures(original, deformed);
    let x0 = original.coords();
    let cells = patch_cells(original, patch).into_iter().map(|(c, a, b)| {
        let (a, b) = (a as usize, b as usize);
        let r = height(a1[c], xy(deformed, a), xy(deformed, b)) / height(a0[c], xy(x0, a), xy(x0, b));
        (c, r, a1[c] / a0[c])
    });
    measures(cells, original.regions(), upper)
}

/// The measures from each cell on the patch: (cell, its height ratio over the patch, its
/// area or volume ratio).
fn measures(cells: impl Iterator<Item = (usize, f64, f64)>, regions: &[i32], upper: Option<i32>) -> PatchMeasures {
    let (mut lo, mut hi, mut sum, mut n) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0usize);
    let (mut rlo, mut rhi) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut up, mut nup, mut down, mut ndown) = (0.0, 0usize, 0.0, 0usize);
    for (c, r, ar) in cells {
        lo = lo.min(r);
        hi = hi.max(r);
        sum += r;
        n += 1;
        rlo = rlo.min(ar);
        rhi = rhi.max(ar);
        if let Some(u) = upper {
            if regions[c] == u {
                up += r;
                nup += 1;
            } else {
                down += r;
                ndown += 1;
            }
        }
    }
    let mean = sum / n.max(1) as f64;
    PatchMeasures {
        spacing_variation: if n == 0 { 0.0 } else { (hi - lo) / mean },
        area_ratio: (rlo, rhi),
        spacing_ratio_across: (nup > 0 && ndown > 0).then(|| (up / nup as f64) / (down / ndown as f64)),
    }
}

/// The cells touching `patch` (of a 3D mesh) by a face, with that face's vertices: (cell, face).
pub fn patch_cells_3d(mesh: &Mesh, patch: i32) -> Vec<(usize, Vec<u32>)> {
    let key = |v: &[u32]| {
        let mut k = v.to_vec();
        k.sort_unstable();
        k
    };
    let on_patch: HashMap<Vec<u32>, Vec<u32>> =
        mesh.patch_faces().filter(|f| f.patch == patch).map(|f| (key(f.vertices), f.vertices.to_vec())).collect();
    // Only a face whose every vertex lies on the patch can be one of its faces: the rest are
    // passed over before their key is made.
    let mut on = vec![false; mesh.num_vertices()];
    on_patch.values().flatten().for_each(|&v| on[v as usize] = true);
    let mut out = Vec::new();
    for c in 0..mesh.num_cells() {
        let cell = mesh.cell(c);
        for f in mesh.cell_type(c).faces() {
            if !f.iter().all(|&k| on[cell[k as usize] as usize]) {
                continue;
            }
            let v: Vec<u32> = f.iter().map(|&k| cell[k as usize]).collect();
            if let Some(face) = on_patch.get(&key(&v)) {
                out.push((c, face.clone()));
            }
        }
    }
    out
}

/// The area of the (planar or warped) polygon `face` at positions `x` (3 per vertex): the length
/// of its vector area.
fn face_area(x: &[f64], face: &[u32]) -> f64 {
    let p = |k: usize| {
        let v = face[k % face.len()] as usize;
        DVec3::new(x[3 * v], x[3 * v + 1], x[3 * v + 2])
    };
    (0..face.len()).map(|k| p(k).cross(p(k + 1))).sum::<DVec3>().length() / 2.0
}

/// [`patch_measures`] in 3D: a cell's height over its patch face is its volume over the face's
/// area.
fn patch_measures_3d(original: &Mesh, deformed: &[f64], patch: i32, upper: Option<i32>) -> PatchMeasures {
    let v0 = signed_measures(original, original.coords());
    let v1 = signed_measures(original, deformed);
    let x0 = original.coords();
    let cells = patch_cells_3d(original, patch).into_iter().map(|(c, face)| {
        let r = (v1[c] / face_area(deformed, &face)) / (v0[c] / face_area(x0, &face));
        (c, r, v1[c] / v0[c])
    });
    measures(cells, original.regions(), upper)
}

/// Runs `setup` with `method` and `opts` (its method is overridden): `steps` solves, the reference
/// re-evaluated after each, then measures the final mesh against the original one. A step that
/// fails, or whose result inverts cells while steps remain, ends the run; it is reported in
/// `failure`.
pub fn run_case(setup: &CaseSetup, method: Method, opts: &Options) -> Result<CaseResult> {
    run_case_with(setup, method, opts, |_, _| {})
}

/// [`run_case`], calling `on_step(step, reports)` after each step with its sub-step reports.
pub fn run_case_with(
    setup: &CaseSetup,
    method: Method,
    opts: &Options,
    mut on_step: impl FnMut(usize, &[StepReport]),
) -> Result<CaseResult> {
    let ramp = |i| setup.motion.increment(i, setup.steps);
    run_series_with(setup, method, opts, ramp, |step, reports, _| on_step(step, reports))
}

/// [`run_case_with`] with step `i`'s (0-based) increment given by `increment(i)` instead of an
/// equal part of `setup.motion` (which is only checked), and `on_step(step, reports, coords)`
/// also given the positions after the step.
pub fn run_series_with(
    setup: &CaseSetup,
    method: Method,
    opts: &Options,
    mut increment: impl FnMut(usize) -> Motion,
    mut on_step: impl FnMut(usize, &[StepReport], &[f64]),
) -> Result<CaseResult> {
    let t0 = Instant::now();
    let opts = Options { method, ..opts.clone() };
    let original = &setup.mesh;
    let mut solver = Solver::new(original, &setup.bcs, opts)?;
    solver.check_motion(&setup.motion)?;
    let mut coords = original.coords().to_vec();
    let mut reports = Vec::new();
    let mut first_inverted_step = None;
    let mut failure = None;
    let mut last_valid = coords.clone();
    let mut cycles = 0;
    // The last call's quality against the positions it started from.
    let mut whole = None;
    for i in 0..setup.steps {
        let result = solver.advance(&increment(i));
        // `advance` numbers its sub-steps as one step of a whole motion: renumber as step i + 1.
        let steps: Vec<StepReport> = solver
            .step_reports()
            .iter()
            .map(|r| StepReport { step: i + 1, fraction: (i as f64 + r.fraction) / setup.steps as f64, ..r.clone() })
            .collect();
        on_step(i + 1, &steps, solver.current_coords());
        // The call's cycles: its accepted sub-steps and its result (a result with inverted
        // cells is returned but not accepted).
        cycles += match &result {
            Ok(sol) => sol.report.cycles,
            Err(_) => steps.iter().filter(|r| r.accepted).map(|r| r.cycles).sum(),
        };
        reports.extend(steps);
        let sol = match result {
            Ok(s) => s,
            Err(e) => {
                failure = Some(format!("step {}: {e}", i + 1));
                coords = solver.last_valid_coords().to_vec();
                last_valid = coords.clone();
                break;
            }
        };
        coords = solver.last_valid_coords().to_vec();
        whole = (sol.quality.inverted == 0).then_some(sol.quality);
        last_valid = if sol.quality.inverted > 0 { solver.current_coords().to_vec() } else { coords.clone() };
        if sol.quality.inverted > 0 {
            first_inverted_step.get_or_insert(i + 1);
            if i + 1 < setup.steps {
                failure = Some(format!(
                    "step {}: {} inverted cells; the later steps cannot start from a tangled mesh",
                    i + 1,
                    sol.quality.inverted
                ));
                break;
            }
        }
    }
    // A run of one call from the original mesh, accepted whole: the call's own quality check is
    // the result's against the original, made once.
    let q = match &whole {
        Some(q) if setup.steps == 1 && failure.is_none() => *q,
        _ => quality(original, &coords),
    };
    let patch = patch_measures(original, &coords, setup.moved_patch, setup.upper_region);
    let max_y_upper = setup.upper_region.map(|u| {
        let mut m = f64::NEG_INFINITY;
        for c in 0..original.num_cells() {
            if original.regions()[c] == u {
                for &v in original.cell(c) {
                    m = m.max(coords[original.dim() * v as usize + 1]);
                }
            }
        }
        m
    });
    Ok(CaseResult {
        case: setup.name.clone(),
        dim: original.dim(),
        method,
        steps: setup.steps,
        inverted: q.inverted,
        negative_volume_cells: q.non_positive_measure,
        min_area_ratio: q.min_area_ratio,
        min_corner_jacobian_ratio: q.min_corner_jacobian_ratio,
        min_angle_deg: q.min_angle_deg,
        patch,
        cycles,
        seconds: t0.elapsed().as_secs_f64(),
        max_y_upper,
        first_inverted_step,
        failure,
        coords,
        last_valid,
        reports,
    })
}

/// The exact discrete displacement of one solve, by Jacobi-preconditioned conjugate gradients on
/// the finest operator alone (no multigrid), to a relative residual of `tol`: an independent
/// check of what the multigrid should reach. Slow (O(N^1.5) and worse); for tests and diagnosis.
pub fn reference_displacement(
    mesh: &Mesh,
    bcs: &meshmove::BoundaryConditions,
    motion: &meshmove::Motion,
    method: Method,
    tol: f64,
) -> Result<Vec<f64>> {
    use meshmove::bc::P;
    let solver = Solver::new(mesh, bcs, Options { method, ..Default::default() })?;
    let lev = &solver.hierarchy().levels[0];
    let n = lev.n();
    let vals = motion.vertex_values(mesh);
    let dim = mesh.dim();
    let mut disp = vec![0.0; mesh.coords().len()];
    for c in 0..dim {
        let flags = &lev.flags()[c];
        let dp: Vec<f64> = (0..n)
            .map(|d| if flags[d] & P != 0 { vals[lev.dofs().dof_vertex[d] as usize * dim + c] } else { 0.0 })
            .collect();
        // The rigid-motion flux source of a CLAMPED patch (docs/DESIGN.md §4): the solver's own.
        let g = meshmove::solver::rigid_flux(solver.hierarchy(), bcs, motion, c);
        let (mut b, mut sc) = (vec![0.0; n], vec![0.0; n]);
        lev.op().rhs(flags, &dp, g.as_deref(), &mut b, &mut sc);
        let dinv = lev.op().inv_l1_diag(flags);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut x = vec![0.0; n];
        let mut r = b.clone();
        let mut z: Vec<f64> = r.iter().zip(&dinv).map(|(a, d)| a * d).collect();
        let mut p = z.clone();
        let mut rz = dot(&r, &z);
        let bn = dot(&b, &b).sqrt();
        let mut ap = vec![0.0; n];
        for _ in 0..50 * n + 1000 {
            if dot(&r, &r).sqrt() <= tol * bn {
                break;
            }
            lev.op().apply(flags, &p, &mut ap, &mut sc);
            let alpha = rz / dot(&p, &ap);
            x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
            r.iter_mut().zip(&ap).for_each(|(r, a)| *r -= alpha * a);
            z.iter_mut().zip(r.iter().zip(&dinv)).for_each(|(z, (r, d))| *z = r * d);
            let rz1 = dot(&r, &z);
            let beta = rz1 / rz;
            rz = rz1;
            p.iter_mut().zip(&z).for_each(|(p, z)| *p = z + beta * *p);
        }
        let rel = dot(&r, &r).sqrt() / bn.max(f64::MIN_POSITIVE);
        if bn > 0.0 && rel > 10.0 * tol {
            return Err(meshmove::Error::Diverged(format!("reference CG reached only {rel:e}")));
        }
        for (v, &d) in lev.dofs().vertex_dof.iter().enumerate() {
            disp[v * dim + c] = x[d as usize] + dp[d as usize];
        }
    }
    Ok(disp)
}

/// [`run_case`] with every step solved by [`reference_displacement`] (the mesh re-referenced
/// after each step as the solver does). Returns the final positions and the first step after
/// which a cell was inverted; like the solver, it stops after that step (nothing can be solved
/// on a tangled mesh).
pub fn run_case_reference(setup: &CaseSetup, method: Method, tol: f64) -> Result<(Vec<f64>, Option<usize>)> {
    let original = &setup.mesh;
    let mut current = original.clone();
    for i in 0..setup.steps {
        let d = reference_displacement(&current, &setup.bcs, &setup.motion.increment(i, setup.steps), method, tol)?;
        let moved: Vec<f64> = current.coords().iter().zip(&d).map(|(x, d)| x + d).collect();
        if quality(original, &moved).inverted > 0 {
            return Ok((moved, Some(i + 1)));
        }
        current = current.with_coords(moved);
    }
    Ok((current.coords().to_vec(), None))
}

/// The CPU seconds of every thread of the process so far (Linux: the first field of each
/// thread's schedstat, in nanoseconds; 0 where it does not tell). A loaded machine stretches
/// wall seconds, not these.
pub fn thread_cpu_seconds() -> f64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else { return 0.0 };
    let ns: u64 = tasks
        .flatten()
        .filter_map(|t| std::fs::read_to_string(t.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next().and_then(|v| v.parse::<u64>().ok()))
        .sum();
    ns as f64 * 1e-9
}
