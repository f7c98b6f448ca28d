//! The bench's slip-wall comparison: the cylinder in a channel moved 1.5 D, its walls FIXED or
//! SLIP (docs/DESIGN.md §4 "Slip walls"), refined while under `--max-vertices`: CG iterations and
//! solve time of each method with each wall, and their ratio, on the default coarse levels (kept
//! unknowns) and on coarse meshes. The channel lies along x (`straight`: walls normal to the axes,
//! whose slip vertices prescribe components and leave them apart) and turned by 30° (`turned`:
//! the slip frames couple the components). Writes `DIR/slip.csv`.

use meshmove::{CoarseLevels, Kind, Mesh, Method, Options, RigidMotion, SolveParams, Solver};
use meshmove_cases::setups::cylinder_channel_far;
use std::fmt::Write as _;
use std::path::Path;

pub const HEADER: &str =
    "walls,coarse_levels,method,vertices,levels,fixed_iterations,slip_iterations,fixed_solve_s,slip_solve_s";

/// Runs the comparison up to `max_vertices`, to the relative residual `tol`; returns the table.
pub fn run(out: &Path, max_vertices: usize, tol: f64) -> Result<String, String> {
    let mut csv = format!("{HEADER}\n");
    let mut table = String::from(
        "slip walls: cylinder channel moved 1.5 D, walls FIXED vs SLIP\n\
         walls    coarse  method        vertices lev  it FIXED  it SLIP  ratio   solve_s FIXED  SLIP\n",
    );
    let setups = [Kind::Fixed, Kind::Slip].map(|k| cylinder_channel_far(1.0 / 12.0, k));
    let mut meshes = vec![setups[0].mesh.clone()];
    while meshes.last().map_or(0, |m| 4 * m.num_vertices()) <= max_vertices {
        let next = meshes.last().expect("one").refined().map_err(|e| e.to_string())?;
        meshes.push(next);
    }
    let routes = [("kept", CoarseLevels::Auto), ("meshes", CoarseLevels::Remeshed)];
    let turn = RigidMotion::planar([0.0, 0.0], 30f64.to_radians(), [0.0, 0.0]);
    for (walls, mesh) in meshes.iter().flat_map(|m| [("straight", m.clone()), ("turned", turned(m, &turn))]) {
        let mesh = &mesh;
        for ((route, coarse_levels), method) in
            routes.into_iter().flat_map(|r| [Method::Biharmonic, Method::Laplacian, Method::Spring].map(|m| (r, m)))
        {
            let mut its = [0usize; 2];
            let mut secs = [0.0f64; 2];
            let mut levels = 0;
            for (k, s) in setups.iter().enumerate() {
                let mut opts =
                    Options { method, solve: SolveParams { tol, ..Default::default() }, ..Default::default() };
                opts.hierarchy.coarse_levels = coarse_levels;
                let solver = Solver::new(mesh, &s.bcs, opts).map_err(|e| format!("slip bench: {e}"))?;
                let mut along = s.motion.rigid[0].1;
                if walls == "turned" {
                    along.translation = turn.apply(&along.translation[..2]);
                }
                let motion = meshmove::Motion::zero(mesh).with_rigid(s.moved_patch, along);
                let sol = solver.solve(&motion).map_err(|e| format!("slip bench, {method:?}: {e}"))?;
                its[k] = sol.report.cycles;
                secs[k] = sol.report.seconds;
                levels = solver.num_levels();
            }
            let name = format!("{method:?}").to_lowercase();
            let nv = mesh.num_vertices();
            let _ = writeln!(
                csv,
                "{walls},{route},{name},{nv},{levels},{},{},{:.4},{:.4}",
                its[0], its[1], secs[0], secs[1]
            );
            let _ = writeln!(
                table,
                "{walls:<8} {route:<7} {name:<13} {nv:>8} {levels:>3} {:>9} {:>8} {:>6.2} {:>12.4} {:>6.4}",
                its[0],
                its[1],
                its[1] as f64 / its[0].max(1) as f64,
                secs[0],
                secs[1]
            );
        }
    }
    let path = out.join("slip.csv");
    std::fs::write(&path, csv).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(table)
}

/// `mesh` (2D) with its vertices moved by `turn`.
fn turned(mesh: &Mesh, turn: &RigidMotion) -> Mesh {
    mesh.with_coords(mesh.coords().chunks(2).flat_map(|p| turn.apply(p)[..2].to_vec()).collect())
}
