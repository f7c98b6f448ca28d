//! The wall-layer meshes on distributed slabs (docs/PERFORMANCE.md, "the paper's cases on 1–4
//! ranks"): run under `mpirun -np N`, it solves the boundary-layer cylinder (2D, its hybrid
//! variant, the 3D extrusion) and the wall-layered airfoil with the biharmonic and the Laplacian to 1e-12 and 1e-14 on slabs
//! across x and prints, per solve, the distributed iterations beside the serial cycles and the
//! largest difference from the serial displacement relative to the motion. Arguments: the mesh
//! names to run (all without one), `tol=T` (repeatable; 1e-12 and 1e-14 without one) and
//! `method=biharmonic` or `method=laplacian` (both without one).
#[path = "../../tests/slabs/mod.rs"]
mod slabs;

use meshmove::distributed::mpi::traits::*;
use meshmove::distributed::{DistSolveParams, DistributedMesh, DistributedSolver};
use meshmove::{Method, Motion, Options, Solver};
use meshmove_cases::setups::{case, CaseSetup, Scale};
use meshmove_cases::setups3d::case3d;
use meshmove_cases::viscous::{airfoil_2d, boundary_conditions, motion, AirfoilParams, BodyMotion};

fn main() {
    let universe = meshmove::distributed::mpi::initialize().expect("MPI initialises once");
    let world = universe.world();
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<String> = args.iter().filter(|a| !a.contains('=')).cloned().collect();
    let tols: Vec<f64> = args.iter().filter_map(|a| a.strip_prefix("tol=")?.parse().ok()).collect();
    let tols = if tols.is_empty() { vec![1e-12, 1e-14] } else { tols };
    let methods: Vec<Method> = match args.iter().find_map(|a| a.strip_prefix("method=")) {
        Some("biharmonic") => vec![Method::Biharmonic],
        Some("laplacian") => vec![Method::Laplacian],
        _ => vec![Method::Biharmonic, Method::Laplacian],
    };
    let all = ["boundary_layer_cylinder", "boundary_layer_cylinder_hybrid", "boundary_layer_cylinder_3d", "airfoil"];
    for name in all.iter().filter(|n| names.is_empty() || names.iter().any(|m| m == *n)) {
        let setup = case(name, Scale::Quick).or_else(|| case3d(name, Scale::Quick)).unwrap_or_else(airfoil);
        let d = setup.mesh.to_data();
        let (dim, nv) = (d.dim, d.num_vertices());
        let owner = slabs::slabs_across_x(&d, size);
        let p = slabs::part(&d, &owner, rank, true);
        let dm = DistributedMesh::new(&world, &p.data, &p.gids, &p.ghost).expect("the distributed mesh");
        let given = &setup.motion.displacement;
        let local: Vec<f64> = p.global.iter().flat_map(|&v| given[v * dim..(v + 1) * dim].to_vec()).collect();
        let motion = Motion { displacement: local, rigid: setup.motion.rigid.clone() };
        for &method in &methods {
            for &tol in &tols {
                let mut reference = vec![0.0; nv * dim];
                let mut cycles = [0.0];
                if rank == 0 {
                    let mut o = Options { method, threads: 1, ..Default::default() };
                    o.solve.tol = tol;
                    o.solve.max_cycles = 1000;
                    let s =
                        Solver::new(&setup.mesh, &setup.bcs, o).expect("serial").solve(&setup.motion).expect("solve");
                    reference = s.displacement;
                    cycles = [s.report.cycles as f64];
                }
                let root = world.process_at_rank(0);
                root.broadcast_into(&mut reference[..]);
                root.broadcast_into(&mut cycles[..]);
                let scale = reference.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let params = DistSolveParams { tol, ..Default::default() };
                let solver = DistributedSolver::new(&dm, &setup.bcs, method, params).expect("solver");
                let sol = match solver.solve(&motion) {
                    Ok(sol) => sol,
                    Err(e) => {
                        if rank == 0 {
                            println!("{name} ({nv} vertices) {method:?} to {tol:e} on {size} ranks: {e}");
                        }
                        continue;
                    }
                };
                let worst = slabs::largest_difference(&p.global, &sol.displacement, &reference, dim);
                let mut all = vec![0.0; size];
                world.all_gather_into(&worst, &mut all[..]);
                let worst = all.iter().fold(0.0f64, |m, &x| m.max(x));
                if rank == 0 {
                    println!(
                        "{name} ({nv} vertices) {method:?} to {tol:e} on {size} ranks: iterations {:?} (serial {}), \
                         apart {:.1e} of the motion, levels {:?}, transfers {:?}",
                        sol.iterations,
                        cycles[0],
                        worst / scale,
                        sol.level_rows,
                        sol.level_transfers
                    );
                }
            }
        }
    }
}

/// The smallest wall-layered airfoil (first height 1e-5 chord) pitched about its quarter chord.
fn airfoil() -> CaseSetup {
    let v = airfoil_2d(&AirfoilParams::new(64)).expect("the airfoil");
    let (bcs, motion) = (boundary_conditions(&v), motion(&v, BodyMotion::Pitch));
    CaseSetup {
        name: "airfoil".into(),
        mesh: v.mesh,
        bcs,
        motion,
        ..case("cylinder_channel", Scale::Quick).expect("a case")
    }
}
