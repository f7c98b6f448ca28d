//! Multi-step motion (docs/DESIGN.md §3 last paragraph): the boundary reaches its target, the reference
//! is re-evaluated each step with the coarse topology kept, and single cycles converge.

#[path = "../../tests/common/mod.rs"]
mod common;
use common::*;
use glam::DVec2;
use meshmove::{BoundaryConditions, CoarseLevels, Kind, Method, Mode, Motion, Options, Solver};
use meshmove_cases::meshes::{FS_LEFT, FS_RIGHT, FS_TOP};
use meshmove_cases::setups::free_surface_case;

#[test]
fn rigid_rotation_in_steps_lands_exactly() {
    let mesh = annulus(12, 48, 0.5, 3.0, 1.25);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(INNER, Kind::Clamped).set_kinds(OUTER, Kind::Fixed);
    let mut s = Solver::new(&mesh, &bcs, Options::default()).unwrap();
    let rot = planar(DVec2::new(0.2, 0.1), 1.0, DVec2::ZERO);
    let reports = s.move_in_steps(&Motion::zero(&mesh).with_rigid(INNER, rot), 8).unwrap();
    assert_eq!(reports.len(), 8);
    assert!(reports.iter().all(|r| r.converged));
    let (start, end) = (mesh.points_2d(), s.mesh().points_2d());
    for v in mesh.patch_vertices(INNER) {
        let x0 = start[v as usize];
        let want = x0 + rigid_at(&rot, x0);
        assert!((end[v as usize] - want).length() < 1e-12, "vertex {v}");
    }
    let q = meshmove::mesh::quality(&mesh, s.mesh().coords());
    assert_eq!(q.inverted, 0);
}

fn free_surface_setup() -> (meshmove::Mesh, BoundaryConditions, Motion) {
    let c = free_surface_case("steps", 1.0 / 24.0, 0.25, 10);
    (c.mesh, c.bcs, c.motion)
}

/// The options of `method` on coarse meshes (the route whose levels have cells to compare).
fn remeshed(method: Method) -> Options {
    let mut o = Options { method, ..Default::default() };
    o.hierarchy.coarse_levels = CoarseLevels::Remeshed;
    o
}

#[test]
fn ten_steps_reach_the_target_surface() {
    let (mesh, bcs, motion) = free_surface_setup();
    for method in [Method::Biharmonic, Method::Laplacian] {
        let mut s = Solver::new(&mesh, &bcs, remeshed(method)).unwrap();
        let topology = |s: &Solver| -> Vec<Vec<Vec<u32>>> {
            s.hierarchy()
                .levels
                .iter()
                .map(|l| (0..l.mesh().num_cells()).map(|c| l.mesh().cell(c).to_vec()).collect())
                .collect()
        };
        let before = topology(&s);
        s.move_in_steps(&motion, 10).unwrap();
        // The coarse meshes followed the fine one: same cells, moved vertices.
        assert_eq!(before, topology(&s), "{method:?}: hierarchy rebuilt");
        assert_ne!(
            s.hierarchy().levels[1].mesh().coords(),
            Solver::new(&mesh, &bcs, remeshed(Method::Biharmonic)).unwrap().hierarchy().levels[1].mesh().coords()
        );
        let (start, end, d) = (mesh.points_2d(), s.mesh().points_2d(), to_vec2(&motion.displacement));
        for v in mesh.patch_vertices(FS_TOP) {
            let (x0, x1) = (start[v as usize], end[v as usize]);
            assert!((x1 - (x0 + d[v as usize])).length() < 1e-12);
        }
        // Periodic sides stay matched: each left vertex has its partner at the same height.
        let left = mesh.patch_vertices(FS_LEFT);
        let right = mesh.patch_vertices(FS_RIGHT);
        let mut yl: Vec<f64> = left.iter().map(|&v| s.mesh().point(v as usize)[1]).collect();
        let mut yr: Vec<f64> = right.iter().map(|&v| s.mesh().point(v as usize)[1]).collect();
        yl.sort_by(f64::total_cmp);
        yr.sort_by(f64::total_cmp);
        assert_eq!(yl, yr);
        assert_eq!(meshmove::mesh::quality(&mesh, s.mesh().coords()).inverted, 0, "{method:?}");
    }
}

#[test]
fn repeated_single_cycles_converge_to_the_solve() {
    let (mesh, bcs, motion) = free_surface_setup();
    for mode in [Mode::Default, Mode::PaperFaithful] {
        let mut o = Options::default();
        o.solve.mode = mode;
        o.solve.tol = 1e-12;
        // The stationary iteration reaches 1e-12 only after about 600 cycles.
        o.solve.max_cycles = 3000;
        let s = Solver::new(&mesh, &bcs, o).unwrap();
        let exact = s.solve(&motion).unwrap().displacement;
        let mut d = vec![0.0; 2 * mesh.num_vertices()];
        let cycles = if mode == Mode::Default { 40 } else { 600 };
        let mut first = 0.0;
        for k in 0..cycles {
            let r = s.cycle(&motion, &mut d).unwrap();
            if k == 0 {
                first = r.rel_residual;
            }
        }
        let err = to_vec2(&d).iter().zip(&to_vec2(&exact)).map(|(a, b)| (*a - *b).length()).fold(0.0, f64::max);
        assert!(err < 1e-7, "{mode:?}: error {err:e} after {cycles} cycles (first residual {first:e})");
    }
}

#[test]
fn prolongation_is_exact_for_linear_fields_on_every_level() {
    let (mesh, bcs, _) = free_surface_setup();
    for mut opts in [Options::default(), remeshed(Method::Biharmonic)] {
        // A coarsest size below 2D's default keeps three levels on this small mesh.
        opts.hierarchy.coarsen.coarsest_unknowns = Some(40);
        let s = Solver::new(&mesh, &bcs, opts).unwrap();
        let h = s.hierarchy();
        assert!(h.levels.len() >= 3, "{} levels", h.levels.len());
        // Independent of x, so consistent with the merged periodic unknowns.
        let lin = |p: &[f64]| -1.7 * p[1] + 0.2;
        for l in 0..h.levels.len() - 1 {
            let (fine, coarse) = (&h.levels[l], &h.levels[l + 1]);
            let xc: Vec<f64> = coarse.unknown_points().chunks_exact(2).map(lin).collect();
            let mut xf = vec![0.0; fine.n()];
            fine.prolong().unwrap().mul_vec(&xc, &mut xf);
            for (d, p) in fine.unknown_points().chunks_exact(2).enumerate() {
                assert!((xf[d] - lin(p)).abs() < 1e-12, "level {l} unknown {d}");
            }
        }
    }
}
