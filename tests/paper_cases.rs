//! The paper's findings (DESIGN §7) as numbers, at the stated set-ups (`Scale::Paper`). Each
//! assertion names DESIGN's "expected here" value; where ours differs, the comment says what we
//! get and why (docs/RESULTS.md has the full table). No case is tuned to pass.

use glam::DVec2;
use meshmove::bc::P;
use meshmove::cases::report::{patch_measures, run_case, CaseResult};
use meshmove::cases::setups::{case, interface_case, CaseSetup, Scale};
use meshmove::mesh::quality::quality;
use meshmove::{InterfaceVariant, Kind, Method, Options, Solver};

fn run(name: &str, method: Method) -> (CaseSetup, CaseResult) {
    let s = case(name, Scale::Paper).unwrap();
    let r = run_case(&s, method, &Options::default()).unwrap();
    assert!(r.failure.is_none(), "{name} {method:?}: {:?}", r.failure);
    (s, r)
}

fn near(x: f64, want: f64, tol: f64) -> bool {
    (x - want).abs() <= tol
}

#[test]
fn free_surface_a01_both_valid_biharmonic_keeps_top_spacing() {
    let (_, b) = run("free_surface_a0.1", Method::Biharmonic);
    let (_, l) = run("free_surface_a0.1", Method::Laplacian);
    assert_eq!((b.inverted, l.inverted), (0, 0));
    // Expected: h/h0 variation ≈ 0.2 (biharmonic) vs ≈ 1.2 (Laplacian). Ours: 0.213 vs 1.233.
    assert!(near(b.patch.spacing_variation, 0.2, 0.05), "{}", b.patch.spacing_variation);
    assert!(near(l.patch.spacing_variation, 1.2, 0.1), "{}", l.patch.spacing_variation);
}

#[test]
fn free_surface_a025_one_step_laplacian_and_spring_tangle() {
    let (_, b) = run("free_surface_a0.25", Method::Biharmonic);
    let (_, l) = run("free_surface_a0.25", Method::Laplacian);
    let (_, s) = run("free_surface_a0.25", Method::Spring);
    // Expected ≈ 30 inverted for Laplacian and SPRING, 0 biharmonic. Ours: 35, 28, 0.
    assert_eq!(b.inverted, 0);
    assert!((20..=45).contains(&l.inverted), "laplacian {}", l.inverted);
    assert!((20..=45).contains(&s.inverted), "spring {}", s.inverted);
}

#[test]
fn free_surface_ten_steps_all_valid_with_the_quality_gap() {
    let (_, b) = run("free_surface_a0.25_10steps", Method::Biharmonic);
    let (_, l) = run("free_surface_a0.25_10steps", Method::Laplacian);
    // † The paper's "Laplacian inverts on the last step" does not hold (nor did it for DESIGN's
    // independent implementation): all valid.
    assert_eq!((b.inverted, l.inverted), (0, 0));
    // Expected min area ratio Laplacian ≈ 0.16, biharmonic ≈ 0.68. Ours: 0.206 and 0.680 (the
    // Laplacian's minimum sits in one cell and depends on the mesh; the gap is the finding).
    assert!(near(b.min_area_ratio, 0.68, 0.05), "{}", b.min_area_ratio);
    assert!(near(l.min_area_ratio, 0.16, 0.06), "{}", l.min_area_ratio);
    // Expected h/h0 variation ≈ 2.4 vs ≈ 0.3. Ours: 2.403 and 0.356.
    assert!(near(l.patch.spacing_variation, 2.4, 0.2), "{}", l.patch.spacing_variation);
    assert!(near(b.patch.spacing_variation, 0.3, 0.1), "{}", b.patch.spacing_variation);
}

#[test]
fn rising_interface_spacing_across_and_variants_agree() {
    let (s, b) = run("rising_interface_0.5", Method::Biharmonic);
    let (_, l) = run("rising_interface_0.5", Method::Laplacian);
    assert_eq!((b.inverted, l.inverted), (0, 0));
    // Expected spacing ratio across the interface: Laplacian 1/3, biharmonic ≈ 0.96. Ours:
    // 0.33333 and 0.966.
    let lr = l.patch.spacing_ratio_across.unwrap();
    let br = b.patch.spacing_ratio_across.unwrap();
    assert!(near(lr, 1.0 / 3.0, 1e-6), "{lr}");
    assert!(near(br, 0.96, 0.02), "{br}");
    // Variant B (continuous) gives the same mesh as variant A (separate): expected to 1e-12.
    let sb = interface_case("rising_interface_0.5_B", 1.0 / 32.0, InterfaceVariant::Continuous, |_| 0.5, 1);
    let mut o = Options::default();
    o.solve.tol = 1e-13;
    let ra = run_case(&s, Method::Biharmonic, &o).unwrap();
    let rb = run_case(&sb, Method::Biharmonic, &o).unwrap();
    let diff = ra.coords.iter().zip(&rb.coords).map(|(a, b)| (*a - *b).length()).fold(0.0, f64::max);
    assert!(diff < 1e-10, "variants differ by {diff:e}");
}

#[test]
fn raised_to_075_biharmonic_overshoots_and_folds() {
    let (_, b) = run("rising_interface_0.75", Method::Biharmonic);
    let (_, l) = run("rising_interface_0.75", Method::Laplacian);
    // Expected max Y ≈ 1.028 with ≈ 800 inverted cells at the top (the method's known limit).
    // Ours: 1.0278, 756 inverted.
    let y = b.max_y_upper.unwrap();
    assert!(near(y, 1.028, 0.003), "{y}");
    assert!((600..=1000).contains(&b.inverted), "{}", b.inverted);
    // The second-order method stays within its boundary values.
    assert!(l.max_y_upper.unwrap() <= 1.0 + 1e-12);
    assert_eq!(l.inverted, 0);
}

#[test]
fn deforming_interface_both_variants() {
    for (name, bih_lo, bih_hi) in [("deforming_interface_A", 0.4, 0.55), ("deforming_interface_B", 0.35, 0.5)] {
        let (_, b) = run(name, Method::Biharmonic);
        let (_, l) = run(name, Method::Laplacian);
        let (_, s) = run(name, Method::Spring);
        // Expected: biharmonic valid, min area ratio ≈ 0.4–0.5. Ours: A 0.506, B 0.384.
        assert_eq!(b.inverted, 0, "{name}");
        assert!((bih_lo..=bih_hi).contains(&b.min_area_ratio), "{name}: {}", b.min_area_ratio);
        // † Laplacian valid but min area ratio ≈ 0.04. Ours: 0 inverted, 0.064.
        assert_eq!(l.inverted, 0, "{name}");
        assert!(l.min_area_ratio > 0.0 && l.min_area_ratio < 0.1, "{name}: {}", l.min_area_ratio);
        // SPRING inverts from step ≈ 11. Ours: from step 9 (A) and 10 (B), 15 cells at the end.
        assert!(s.inverted > 0, "{name}");
        let k = s.first_inverted_step.unwrap();
        assert!((8..=12).contains(&k), "{name}: spring first inverted at step {k}");
    }
}

#[test]
fn cylinder_in_channel() {
    let (_, b) = run("cylinder_channel", Method::Biharmonic);
    let (_, l) = run("cylinder_channel", Method::Laplacian);
    assert_eq!(b.inverted, 0);
    // Expected ≈ 200 inverted for the Laplacian. Ours at h = 1/12: 86. The count grows with the
    // mesh (h = 1/8: 36, 1/16: 163, 1/24: 352; examples/channel_probe.rs): the tangled area is
    // the same, DESIGN does not state its mesh size. The finding (Laplacian inverts right of the
    // cylinder, biharmonic does not) holds at every size.
    assert!((60..=120).contains(&l.inverted), "{}", l.inverted);
    // Expected wall-cell area ratio 0.87–1.13. Ours at h = 1/12: 0.795–1.221, tending to it as
    // the mesh is refined (1/16: 0.844–1.164, 1/24: 0.883–1.115).
    let (lo, hi) = b.patch.area_ratio;
    assert!(lo > 0.75 && hi < 1.25, "{lo}..{hi}");
}

/// The exact discrete solution (Jacobi-preconditioned CG on the same operator, to 1e-11): an
/// independent check of what the multigrid should have reached.
fn reference_solve(s: &CaseSetup, method: Method) -> Vec<DVec2> {
    let solver = Solver::new(&s.mesh, &s.bcs, Options { method, ..Default::default() }).unwrap();
    let lev = &solver.hierarchy().levels[0];
    let n = lev.n();
    let vals = s.motion.vertex_values(&s.mesh);
    let mut disp = vec![DVec2::ZERO; s.mesh.num_vertices()];
    for c in 0..2 {
        let flags = &lev.flags[c];
        let dp: Vec<f64> =
            (0..n).map(|d| if flags[d] & P != 0 { vals[lev.dofs.dof_vertex[d] as usize][c] } else { 0.0 }).collect();
        // The rigid-motion flux source of a CLAMPED patch (DESIGN §4), as the solver builds it.
        let g = (method == Method::Biharmonic).then(|| {
            let mut g = vec![0.0; n];
            let (patch, m) = s.motion.rigid[0];
            assert_eq!(s.bcs.kind(patch, c), Kind::Clamped);
            let x = lev.mesh.coords();
            let l: Vec<f64> = lev.dofs.dof_vertex.iter().map(|&v| m.displacement(x[v as usize])[c]).collect();
            for v in lev.mesh.patch_vertices(patch) {
                let d = lev.dofs.vertex_dof[v as usize] as usize;
                let (cols, vs) = lev.op.k.row(d);
                g[d] = cols.iter().zip(vs).map(|(&j, &a)| a * l[j as usize]).sum();
            }
            g
        });
        let (mut b, mut sc) = (vec![0.0; n], vec![0.0; n]);
        lev.op.rhs(flags, &dp, g.as_deref(), &mut b, &mut sc);
        let dinv = lev.op.inv_l1_diag(flags);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut x = vec![0.0; n];
        let mut r = b.clone();
        let mut z: Vec<f64> = r.iter().zip(&dinv).map(|(a, d)| a * d).collect();
        let mut p = z.clone();
        let mut rz = dot(&r, &z);
        let bn = dot(&b, &b).sqrt();
        let mut ap = vec![0.0; n];
        for _ in 0..200_000 {
            if dot(&r, &r).sqrt() <= 1e-11 * bn {
                break;
            }
            lev.op.apply(flags, &p, &mut ap, &mut sc);
            let alpha = rz / dot(&p, &ap);
            x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
            r.iter_mut().zip(&ap).for_each(|(r, a)| *r -= alpha * a);
            z.iter_mut().zip(r.iter().zip(&dinv)).for_each(|(z, (r, d))| *z = r * d);
            let rz1 = dot(&r, &z);
            let beta = rz1 / rz;
            rz = rz1;
            p.iter_mut().zip(&z).for_each(|(p, z)| *p = z + beta * *p);
        }
        assert!(dot(&r, &r).sqrt() <= 1e-9 * bn, "reference CG did not converge");
        for (v, &d) in lev.dofs.vertex_dof.iter().enumerate() {
            disp[v][c] = x[d as usize] + dp[d as usize];
        }
    }
    s.mesh.coords().iter().zip(&disp).map(|(a, b)| *a + *b).collect()
}

#[test]
fn boundary_layer_cylinder() {
    let s = case("boundary_layer_cylinder", Scale::Paper).unwrap();
    // Expected: Laplacian ≈ 1000 inverted. Ours: 1738 (multigrid converges; a direct solve
    // agrees to 7e-8).
    let l = run_case(&s, Method::Laplacian, &Options::default()).unwrap();
    assert!(l.reports[0].converged);
    assert!(l.inverted > 500, "{}", l.inverted);
    // Expected: SPRING and biharmonic valid, wall-layer area ratio ≈ 0.9–1.1. The exact discrete
    // solutions are (ours: 0 inverted, wall-layer area ratio 0.998–1.002 for both)...
    for m in [Method::Spring, Method::Biharmonic] {
        let moved = reference_solve(&s, m);
        assert_eq!(quality(&s.mesh, &moved).inverted, 0, "{m:?} exact solution");
        let (lo, hi) = patch_measures(&s.mesh, &moved, s.moved_patch, None).area_ratio;
        assert!(lo > 0.9 && hi < 1.1, "{m:?}: {lo}..{hi}");
    }
    // ...but OUR MULTIGRID DOES NOT REACH THEM on this mesh: with the wall layer's 0.005-high
    // cells (aspect ratio ≈ 8) the coarse levels do not represent the layer, and CG + W-cycle
    // stalls (biharmonic relative residual ≈ 6e-4, SPRING ≈ 8e-2 after 500 cycles), leaving a
    // tangled mesh. This is a solver limitation, recorded here so that a fix shows up.
    for m in [Method::Spring, Method::Biharmonic] {
        let r = run_case(&s, m, &Options::default()).unwrap();
        assert!(!r.reports[0].converged, "{m:?} now converges: update this test and RESULTS.md");
        assert!(r.inverted > 0, "{m:?}");
    }
}
