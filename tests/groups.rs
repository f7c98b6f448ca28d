//! The components of a displacement solved as one system (one group, one set of CG scalars over
//! all blocks: what a coupling condition such as a slip wall needs) give the same solution as
//! the components solved one by one, which is what the methods' decoupled operators allow.

use meshmove::multigrid::solve::{solve, SolveParams};
use meshmove::{BoundaryConditions, CellType, Kind, Mesh, MeshData, Method, Motion, Options, Solver};

fn mixed_mesh(n: usize) -> Mesh {
    let mut d = MeshData::new(2);
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..=n {
        for i in 0..=n {
            d.push_vertex(&[i as f64 / n as f64, j as f64 / n as f64]);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if (i + j) % 3 == 0 {
                d.push_cell(CellType::Triangle, &[q[0], q[1], q[2]], 0);
                d.push_cell(CellType::Triangle, &[q[0], q[2], q[3]], 0);
            } else {
                d.push_cell(CellType::Quad, &q, 0);
            }
        }
    }
    for k in 0..n {
        d.push_face(&[id(k, n), id(k + 1, n)], 3);
    }
    Mesh::from_data(&d).unwrap()
}

#[test]
fn one_group_equals_separate_components() {
    let mesh = mixed_mesh(24);
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(0, Kind::Fixed).set_kinds(3, Kind::Clamped);
    let mut motion = Motion::zero(&mesh);
    for v in mesh.patch_vertices(3) {
        let x = mesh.point(v as usize)[0];
        motion.displacement[2 * v as usize] = 0.05 * (3.0 * x).sin();
        motion.displacement[2 * v as usize + 1] = 0.1 * (6.0 * x).cos();
    }
    for method in [Method::Biharmonic, Method::Laplacian] {
        let opts = Options { method, ..Default::default() };
        let solver = Solver::new(&mesh, &bcs, opts).unwrap();
        let h = solver.hierarchy();
        let lev = h.fine();
        let n = lev.n();
        let vals = motion.vertex_values(&mesh);
        // Right-hand sides of both components, one block each.
        let mut b = vec![0.0; 2 * n];
        for c in 0..2 {
            let dp: Vec<f64> = (0..n)
                .map(|d| if lev.flags()[c][d] & 1 != 0 { vals[lev.dofs().dof_vertex[d] as usize * 2 + c] } else { 0.0 })
                .collect();
            let mut s = vec![0.0; n];
            lev.op().rhs(&lev.flags()[c], &dp, None, &mut b[c * n..(c + 1) * n], &mut s);
        }
        let p = SolveParams { tol: 1e-11, ..Default::default() };
        let mut joint = vec![0.0f64; 2 * n];
        let rj = solve(h, 0..2, &p, &b, &mut joint, 1.0);
        assert!(rj.converged, "{method:?}: joint solve did not converge");
        let mut sep = vec![0.0f64; 2 * n];
        for c in 0..2 {
            let r = solve(h, c..c + 1, &p, &b[c * n..(c + 1) * n], &mut sep[c * n..(c + 1) * n], 1.0);
            assert!(r.converged);
        }
        let scale = sep.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let err = joint.iter().zip(&sep).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(scale > 1e-3 && err < 1e-9 * scale, "{method:?}: joint vs separate {err:e} (scale {scale:e})");
    }
}
