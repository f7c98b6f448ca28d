//! The slip-wall solve agrees with a dense direct solve of the same constrained discrete system
//! (docs/DESIGN.md §4 "Slip walls"): the componentwise matrices assembled here from K, V and the
//! flags, the unknowns written in a basis of each slip unknown's tangents, the normal parts
//! prescribed. 2D (an annulus with a curved slip wall, on several multigrid levels; a slanted
//! channel through the whole solver) and 3D (a duct whose slip walls meet at edges).

mod common;
mod slip_meshes;

use meshmove::bc::{P, Z};
use meshmove::multigrid::solve::{solve, SolveParams};
use meshmove::{BoundaryConditions, CoarseLevels, Kind, Link, Mesh, Method, Motion, Options, Solver};

const ALL_METHODS: [Method; 3] = [Method::Biharmonic, Method::Laplacian, Method::Spring];

/// The componentwise operator of component c as a dense n × n matrix (rows of P unknowns zero):
/// biharmonic Σ_{k without Z} K_ik K_kj / V_k, Laplacian and spring K_ij.
fn component_matrix(s: &Solver, c: usize) -> Vec<Vec<f64>> {
    let lev = s.hierarchy().fine();
    let n = lev.n();
    let k = lev.op().k.to_dense();
    let flags = &lev.flags()[c];
    let mut a = vec![vec![0.0; n]; n];
    for i in (0..n).filter(|&i| flags[i] & P == 0) {
        if lev.op().method == Method::Biharmonic {
            for kk in (0..n).filter(|&kk| flags[kk] & Z == 0 && k[i][kk] != 0.0) {
                let w = k[i][kk] * lev.op().inv_v[kk];
                for j in 0..n {
                    a[i][j] += w * k[kk][j];
                }
            }
        } else {
            a[i].copy_from_slice(&k[i]);
        }
    }
    a
}

/// The constrained system solved directly: returns (g, w) with g the prescribed part (P values
/// and slip normal parts, `dim` blocks of n) and w the free part, x = g + w.
fn direct(s: &Solver, vals: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let lev = s.hierarchy().fine();
    let (n, dim) = (lev.n(), lev.dim());
    let frames = &lev.slip_frames().expect("slip frames");
    let val = |d: usize, c: usize| vals[lev.dofs().dof_vertex[d] as usize * dim + c];
    let mut g = vec![0.0; dim * n];
    let mut basis: Vec<(usize, [f64; 3])> = Vec::new();
    for d in 0..n {
        let prescribed: Vec<bool> = (0..dim).map(|c| lev.flags()[c][d] & P != 0).collect();
        for c in (0..dim).filter(|&c| prescribed[c]) {
            g[c * n + d] = val(d, c);
        }
        match frames.dofs.binary_search(&(d as u32)) {
            Ok(k) => {
                let mut v = [0.0; 3];
                (0..dim).for_each(|c| v[c] = val(d, c));
                for e in frames.directions(k) {
                    let a: f64 = (0..3).map(|c| e[c] * v[c]).sum();
                    (0..dim).for_each(|c| g[c * n + d] += a * e[c]);
                }
                basis.extend(frames.tangents(k, &prescribed).into_iter().map(|t| (d, t)));
            }
            Err(_) => {
                for c in (0..dim).filter(|&c| !prescribed[c]) {
                    let mut e = [0.0; 3];
                    e[c] = 1.0;
                    basis.push((d, e));
                }
            }
        }
    }
    let mats: Vec<Vec<Vec<f64>>> = (0..dim).map(|c| component_matrix(s, c)).collect();
    // Tᵀ A T and −Tᵀ A g.
    let m = basis.len();
    let mut a = vec![0.0; m * m];
    let mut b = vec![0.0; m];
    for (p, &(i, ti)) in basis.iter().enumerate() {
        for c in 0..dim {
            if ti[c] == 0.0 {
                continue;
            }
            let row = &mats[c][i];
            b[p] -= ti[c] * (0..n).map(|j| row[j] * g[c * n + j]).sum::<f64>();
            for (q, &(j, tj)) in basis.iter().enumerate() {
                a[p * m + q] += ti[c] * row[j] * tj[c];
            }
        }
    }
    for i in 0..m {
        for j in 0..i {
            let v = 0.5 * (a[i * m + j] + a[j * m + i]);
            a[i * m + j] = v;
            a[j * m + i] = v;
        }
    }
    meshmove::dense::Cholesky::new(m, &a).expect("the constrained system is SPD").solve(&mut b);
    let mut w = vec![0.0; dim * n];
    for (&(i, t), y) in basis.iter().zip(&b) {
        (0..dim).for_each(|c| w[c * n + i] += t[c] * y);
    }
    (g, w)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// An annulus, the outer circle slip and given a displacement with a normal part, the inner one
/// rotated: the multigrid solve of the constrained system (several levels, inherited frames)
/// equals the direct one. The wall normals of a regular polygon are radial.
#[test]
fn annulus_multigrid_matches_direct() {
    let mesh = common::annulus(10, 48, 1.0, 3.0, 1.1);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(common::INNER, Kind::Clamped).set_kinds(common::OUTER, Kind::Slip);
    let mut field = vec![0.0; 2 * mesh.num_vertices()];
    for v in 0..mesh.num_vertices() {
        let x = mesh.point(v);
        let a = x[1].atan2(x[0]);
        field[2 * v] = 0.05 * (3.0 * a).cos();
        field[2 * v + 1] = 0.03 * (2.0 * a).sin();
    }
    let motion = Motion::from_displacement(field);
    // Both routes to coarse levels, the kept unknowns coarsened down to a few dozen.
    let routes = [(CoarseLevels::LeastSquares, 40), (CoarseLevels::Remeshed, 150)];
    for ((route, coarsest), method) in routes.into_iter().flat_map(|r| ALL_METHODS.map(|m| (r, m))) {
        let mut o = Options { method, ..Default::default() };
        (o.hierarchy.coarse_levels, o.hierarchy.coarsen.coarsest_unknowns) = (route, Some(coarsest));
        let s = Solver::new(&mesh, &bcs, o).unwrap();
        assert!(s.num_levels() >= 3, "{route:?} {method:?}: {} levels", s.num_levels());
        let h = s.hierarchy();
        let lev = h.fine();
        let frames = &lev.slip_frames().unwrap();
        // The four vertices on the axes have axis normals (their components prescribed), the
        // others frames; the hierarchy is coupled.
        assert_eq!((frames.dofs.len(), frames.axes.len()), (44, 4));
        assert_eq!(h.groups().len(), 1);
        for (k, &d) in frames.dofs.iter().enumerate() {
            let x = mesh.point(lev.dofs().dof_vertex[d as usize] as usize);
            let e = frames.directions(k)[0];
            let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
            assert!((e[0] * x[1] - e[1] * x[0]).abs() < 1e-14 * r, "normal not radial");
        }
        let vals = motion.vertex_values(&mesh);
        let (g, want) = direct(&s, &vals);
        // b = Π (−A g), assembled from the operator itself.
        let n = lev.n();
        let mut b = vec![0.0; 2 * n];
        let mut sc = vec![0.0; n];
        for c in 0..2 {
            lev.op().rhs(&lev.flags()[c], &g[c * n..(c + 1) * n], None, &mut b[c * n..(c + 1) * n], &mut sc);
        }
        frames.project(n, &mut b);
        let mut w = vec![0.0; 2 * n];
        let rep = solve(h, 0..2, &SolveParams { tol: 1e-13, ..Default::default() }, &b, &mut w, 1.0);
        assert!(rep.converged, "{route:?} {method:?}: {rep:?}");
        let err = max_diff(&w, &want);
        println!(
            "annulus {route:?} {method:?}: {} iterations, |w| {:.3e}, error {err:.2e}",
            rep.cycles,
            max_abs(&want)
        );
        assert!(max_abs(&want) > 1e-3 && err < 1e-10 * max_abs(&want), "{route:?} {method:?}: error {err:e}");
    }
}

/// The whole solver on a slanted channel (flat slip walls given a displacement with a normal
/// part, periodic ends) equals the direct solve.
#[test]
fn slanted_channel_solver_matches_direct() {
    use slip_meshes::*;
    let angle = 0.5f64;
    let (s, c) = angle.sin_cos();
    let mesh = channel(24, 8, 3.0, [[9, 12], [3, 5]], 0.3, angle);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BOTTOM, Kind::Slip).set_kinds(TOP, Kind::Slip).set_kinds(BODY, Kind::Clamped);
    bcs.set_kinds(LEFT, Kind::Free).set_kinds(RIGHT, Kind::Free);
    bcs.add_link(Link::ByOffset { a: LEFT, b: RIGHT, offset: [3.0 * c, 3.0 * s, 0.0], tol: 1e-9 });
    let mut field = vec![0.0; 2 * mesh.num_vertices()];
    for v in 0..mesh.num_vertices() {
        let x = mesh.point(v);
        let along = (c * x[0] + s * x[1]) * std::f64::consts::TAU / 3.0;
        field[2 * v] = 0.02 * along.sin();
        field[2 * v + 1] = 0.03 * along.cos();
    }
    // (No rigid motion: its flux source is not part of this direct assembly.)
    let motion = Motion::from_displacement(field);
    for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
        let mut o = Options { method, ..Default::default() };
        o.solve.tol = 1e-13;
        let solver = Solver::new(&mesh, &bcs, o).unwrap();
        let sol = solver.solve(&motion).unwrap();
        let lev = solver.hierarchy().fine();
        let n = lev.n();
        let (g, w) = direct(&solver, &motion.vertex_values(&mesh));
        let want: Vec<f64> = g.iter().zip(&w).map(|(a, b)| a + b).collect();
        let got: Vec<f64> = (0..2)
            .flat_map(|cc| lev.dofs().dof_vertex.iter().map(move |&v| (v, cc)))
            .map(|(v, cc)| sol.displacement[v as usize * 2 + cc])
            .collect();
        assert_eq!(got.len(), 2 * n);
        let err = max_diff(&got, &want);
        println!("channel {method:?}: {} iterations, error {err:.2e}", sol.report.cycles);
        assert!(err < 1e-10 * max_abs(&want), "{method:?}: error {err:e}");
    }
}

/// 3D: a duct with four slip walls given a displacement with normal parts, its walls normal to
/// the axes (each component solved apart) and turned by 20° about the duct's axis (edges with
/// two constrained directions, the components coupled); the solver equals the direct solve.
#[test]
fn duct_solver_matches_direct() {
    use slip_meshes::*;
    let straight = duct([6, 4, 4], 2.0, [[2, 4], [1, 3], [1, 3]], 0.25);
    for mesh in [turned_about_x(&straight, 20f64.to_radians()), straight] {
        duct_against_direct(&mesh);
    }
}

fn duct_against_direct(mesh: &Mesh) {
    use slip_meshes::*;
    let mesh = mesh.clone();
    let mut bcs = BoundaryConditions::new();
    for p in [BOTTOM, TOP, FRONT, BACK] {
        bcs.set_kinds(p, Kind::Slip);
    }
    bcs.set_kinds(BODY, Kind::Clamped).set_kinds(LEFT, Kind::Fixed).set_kinds(RIGHT, Kind::Free);
    let mut field = vec![0.0; 3 * mesh.num_vertices()];
    for v in 0..mesh.num_vertices() {
        let x = mesh.point(v);
        field[3 * v] = 0.02 * (2.0 * x[1]).sin();
        field[3 * v + 1] = 0.03 * (1.5 * x[0]).cos() * x[2];
        field[3 * v + 2] = 0.02 * (x[0] + x[1]).sin();
    }
    let motion = Motion::from_displacement(field);
    for method in [Method::Biharmonic, Method::Laplacian, Method::Spring] {
        let mut o = Options { method, ..Default::default() };
        o.solve.tol = 1e-13;
        let solver = Solver::new(&mesh, &bcs, o).unwrap();
        let frames = &solver.hierarchy().fine().slip_frames().expect("slip frames");
        let coupled = (0..frames.dofs.len()).any(|k| frames.directions(k).len() == 2);
        let apart = frames.axes.iter().any(|&(_, mask)| mask.count_ones() == 2);
        assert!(coupled != apart && coupled == (solver.hierarchy().groups().len() == 1));
        let sol = solver.solve(&motion).unwrap();
        let lev = solver.hierarchy().fine();
        let (g, w) = direct(&solver, &motion.vertex_values(&mesh));
        let want: Vec<f64> = g.iter().zip(&w).map(|(a, b)| a + b).collect();
        let got: Vec<f64> = (0..3)
            .flat_map(|cc| lev.dofs().dof_vertex.iter().map(move |&v| (v, cc)))
            .map(|(v, cc)| sol.displacement[v as usize * 3 + cc])
            .collect();
        let err = max_diff(&got, &want);
        println!("duct (coupled {coupled}) {method:?}: {} iterations, error {err:.2e}", sol.report.cycles);
        assert!(err < 1e-10 * max_abs(&want), "{method:?}: error {err:e}");
    }
}
