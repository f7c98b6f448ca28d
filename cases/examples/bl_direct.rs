//! Diagnosis (RESULTS.md): the boundary-layer cylinder solved by a dense direct solve of the same
//! discrete system, to tell whether a tangle is the method's or the multigrid's (which stalls).
use meshmove::bc::P;
use meshmove::dense::Cholesky;
use meshmove::mesh::quality;
use meshmove::{Kind, Method, Options, Solver};
use meshmove_cases::setups::*;
fn main() {
    let s = case("boundary_layer_cylinder", Scale::Paper).unwrap();
    for method in [Method::Spring, Method::Biharmonic, Method::Laplacian] {
        let solver = Solver::new(&s.mesh, &s.bcs, Options { method, ..Default::default() }).unwrap();
        let lev = &solver.hierarchy().levels[0];
        let n = lev.n();
        let vals = s.motion.vertex_values(&s.mesh);
        let dim = s.mesh.dim();
        let mut disp = vec![0.0; s.mesh.coords().len()];
        for c in 0..dim {
            let flags = &lev.flags()[c];
            let dp: Vec<f64> = (0..n)
                .map(|d| if flags[d] & P != 0 { vals[lev.dofs().dof_vertex[d] as usize * dim + c] } else { 0.0 })
                .collect();
            let mut g = None;
            if method == Method::Biharmonic {
                let mut gv = vec![0.0; n];
                let (patch, m) = s.motion.rigid[0];
                assert_eq!(s.bcs.kind(patch, c), Kind::Clamped);
                let l: Vec<f64> =
                    lev.dofs().dof_vertex.iter().map(|&v| m.displacement(lev.mesh().point(v as usize))[c]).collect();
                for v in lev.mesh().patch_vertices(patch) {
                    let d = lev.dofs().vertex_dof[v as usize] as usize;
                    let (cols, vs) = lev.op().k.row(d);
                    gv[d] = cols.iter().zip(vs).map(|(&j, &a)| a * l[j as usize]).sum();
                }
                g = Some(gv);
            }
            let (mut b, mut sc) = (vec![0.0; n], vec![0.0; n]);
            lev.op().rhs(flags, &dp, g.as_deref(), &mut b, &mut sc);
            let free: Vec<usize> = (0..n).filter(|&d| flags[d] & P == 0).collect();
            let m = free.len();
            let mut a = vec![0.0; m * m];
            let (mut e, mut y) = (vec![0.0; n], vec![0.0; n]);
            for (j, &dj) in free.iter().enumerate() {
                e[dj] = 1.0;
                lev.op().apply(flags, &e, &mut y, &mut sc);
                e[dj] = 0.0;
                for (i, &di) in free.iter().enumerate() {
                    a[i * m + j] = y[di];
                }
            }
            for i in 0..m {
                for j in 0..i {
                    let v = 0.5 * (a[i * m + j] + a[j * m + i]);
                    a[i * m + j] = v;
                    a[j * m + i] = v;
                }
            }
            let ch = Cholesky::new(m, &a).expect("SPD");
            let mut x: Vec<f64> = free.iter().map(|&d| b[d]).collect();
            ch.solve(&mut x);
            let mut full = dp.clone();
            for (i, &d) in free.iter().enumerate() {
                full[d] += x[i];
            }
            for (v, &d) in lev.dofs().vertex_dof.iter().enumerate() {
                disp[v * dim + c] = full[d as usize];
            }
        }
        let moved: Vec<f64> = s.mesh.coords().iter().zip(&disp).map(|(a, b)| *a + *b).collect();
        let q = quality(&s.mesh, &moved);
        let pm = meshmove_cases::report::patch_measures(&s.mesh, &moved, s.moved_patch, None);
        let mg = solver.solve(&s.motion).unwrap();
        let err = mg
            .displacement
            .chunks_exact(dim)
            .zip(disp.chunks_exact(dim))
            .map(|(a, b)| a.iter().zip(b).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt())
            .fold(0.0, f64::max);
        println!("{method:?} direct: inverted {} min_area_ratio {:.4} wall area {:?} spacing var {:.4}; multigrid max error {err:.3e} (rel res {:e}, {} cycles)",
            q.inverted, q.min_area_ratio, pm.area_ratio, pm.spacing_variation, mg.report.rel_residual, mg.report.cycles);
    }
}
