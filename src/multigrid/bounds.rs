//! The biharmonic levels' λmax estimates, cheaper on a moved mesh whose level changed little.
//!
//! The Chebyshev smoother is tuned to the estimate after `POWER_ITERATIONS` power iterations
//! from a fixed start, which lies below λmax(D⁻¹A) by an amount that depends on the level's
//! spectrum. A full estimate also keeps, per component, how the iteration converged (the ratio
//! of its estimates after `SHAPE.1` and `SHAPE.0` iterations, the shape, and the ratio of the
//! full estimate to the one after `FEW`); every estimate from the fixed start (full or rescaled,
//! below) keeps the unit iterate its last iteration started from and the Jacobi diagonal it was
//! made with.
//!
//! On a moved mesh whose diagonal differs from the kept one by at most `DRIFT` (relatively) at
//! every free unknown, the cells changed little everywhere: one iteration from the kept iterate
//! on the moved operator stands for the estimate it was kept from (times its rescaling and
//! `MARGIN`), as that iterate is the fixed start's after that estimate's count and the norm of
//! its product follows the operator's change along it. What it does not follow is a top mode
//! the motion made elsewhere (compressed cells), so it is raised by the largest drift d:
//! e·(1 + d), λmax(D⁻¹A) changing no more than the diagonal does where A's rows change with
//! it. The smoother loses far more to an estimate below λmax than to one above it, except
//! where the raise alone lifts the padded estimate to the l1 bound 1: the smoother then runs
//! on the bound's interval, which costs iterations (docs/perf-history.md, "The kept step's
//! bounds raised by the drift"), and the component takes the estimate from the fixed start
//! below. Past that drift, or without a kept iterate, the iteration runs `SHAPE.1` iterations
//! from the fixed start; when the shape is within `SHAPE_TOLERANCE` of the calibration's, the spectrum's
//! top kept its form, and the estimate after `FEW` iterations times the calibration's ratio (and
//! `MARGIN`) stands for the full one. Otherwise (cells squashed into a local top mode that a
//! spread start needs more iterations to find) the iteration continues to the full estimate,
//! bitwise the one a new level gets, and calibrates the component again.

use super::group::{padded, raised_on_lines, run_side_by_side, GroupOp, PowerIteration, POWER_ITERATIONS};
use super::level::Level;
use std::sync::Arc;

/// The largest relative change of a free unknown's Jacobi diagonal since the last estimate from
/// the fixed start under which a component's estimate is one iteration from the kept iterate,
/// raised by that change (docs/perf-history.md, "The kept step's bounds raised by the drift").
const DRIFT: f64 = 0.30;

/// The power iterations of a rescaled estimate.
const FEW: usize = 8;

/// The iterations whose estimates' ratio is the convergence's shape.
const SHAPE: (usize, usize) = (3, 5);

/// The largest relative change of the shape under which a component keeps its calibration.
const SHAPE_TOLERANCE: f64 = 0.005;

/// The cheaper estimates' margin. The smoother loses far more to an estimate below the full one
/// than to one above it (docs/perf-history.md, "bounds rescaled").
const MARGIN: f64 = 1.05;

/// What a component's last full estimate leaves for the cheaper ones after it.
#[derive(Clone, Default)]
struct Component {
    /// The unit iterate the last estimate from the fixed start (full or rescaled) started its
    /// last iteration from (empty: none kept).
    start: Arc<[f64]>,
    /// The inverse Jacobi diagonal that estimate was made with.
    inv_d: Arc<[f64]>,
    /// That estimate over its last product's norm (1 for a full estimate, the rescaling ratio
    /// for a rescaled one).
    scale: f64,
    /// The estimate after `SHAPE.1` iterations over the one after `SHAPE.0` (unpadded).
    shape: f64,
    /// The full estimate over the one after `FEW` iterations (unpadded; zero: none, the next
    /// estimate past the drift is full).
    ratio: f64,
}

/// What a level's last full estimates leave for the cheaper ones after them, per component
/// (empty, or a component's empty start: its next estimate is full).
#[derive(Clone, Default)]
pub(crate) struct Calibration(Vec<Component>);

/// The largest relative change of the Jacobi diagonal from `before` to `now` (inverse
/// diagonals, as the levels keep them) over the unknowns free at either; infinite where the
/// free unknowns differ.
pub(crate) fn largest_drift(before: &[f64], now: &[f64]) -> f64 {
    if before.len() != now.len() {
        return f64::INFINITY;
    }
    before.iter().zip(now).fold(0.0, |m: f64, (&b, &n)| match (b > 0.0, n > 0.0) {
        (true, true) => m.max((b / n - 1.0).abs()),
        (false, false) => m,
        _ => f64::INFINITY,
    })
}

/// The padded warm estimate from `e` (one product from a kept iterate, times its scale and
/// `MARGIN`) on a diagonal `drift` away from that iterate's: e·(1 + drift), padded; None where
/// the raise alone lifts it to the l1 bound (the unraised estimate below it), so the estimate
/// from the fixed start is due.
fn raised(e: f64, drift: f64) -> Option<f64> {
    let up = padded(Some(e * (1.0 + drift)));
    (up < 1.0 || padded(Some(e)) >= 1.0).then_some(up)
}

/// The λmax estimates of a biharmonic level's components `own` (each component's smoother
/// separately, no slip coupling), with `previous` the calibration of its last estimates (None
/// on a new level). Returns the estimates in `own`'s order and the calibration to keep.
/// Components smoothed along lines always get the full estimate, as the smoother there is the
/// most sensitive to its interval (docs/perf-history.md, "bounds by Lanczos").
pub(crate) fn biharmonic_estimates(level: &Level, own: &[usize], previous: Option<&Calibration>) -> (Vec<f64>, Calibration) {
    let ops: Vec<GroupOp> = own.iter().map(|&c| GroupOp::new(level, c..c + 1, false)).collect();
    let lines: Vec<bool> = ops.iter().map(|op| op.lines(0).is_some()).collect();
    let kept: Vec<Option<&Component>> =
        own.iter().zip(&lines).map(|(&c, &lines)| previous.and_then(|p| p.0.get(c)).filter(|_| !lines)).collect();
    let mut estimates: Vec<Option<(f64, Component)>> = vec![None; own.len()];
    // One iteration from each kept iterate whose diagonal drifted little.
    let mut warm: Vec<(usize, f64, PowerIteration)> = (0..own.len())
        .filter_map(|i| {
            let k = kept[i].filter(|k| k.start.len() == level.n())?;
            let drift = largest_drift(&k.inv_d, &level.inv_d[own[i]]);
            (drift <= DRIFT).then(|| (i, drift, PowerIteration::from_start(&ops[i], k.start.to_vec())))
        })
        .collect();
    let mut runs: Vec<(GroupOp, &mut PowerIteration)> = warm.iter_mut().map(|(i, _, p)| (ops[*i], p)).collect();
    run_side_by_side(level, &mut runs, 1);
    for (i, drift, power) in &warm {
        let k = kept[*i].expect("a warm start is a kept one");
        if let Some(e) = power.after(1).and_then(|e| raised(e * k.scale * MARGIN, *drift)) {
            estimates[*i] = Some((e, k.clone()));
        }
    }
    // The others from the fixed start: the shape after `SHAPE.1` iterations, the rescaled
    // estimate after `FEW` where the calibration holds, else the full one.
    let mut cold: Vec<(usize, PowerIteration)> =
        (0..own.len()).filter(|&i| estimates[i].is_none()).map(|i| (i, PowerIteration::new(&ops[i]))).collect();
    let mut runs: Vec<(GroupOp, &mut PowerIteration)> = cold.iter_mut().map(|(i, p)| (ops[*i], p)).collect();
    run_side_by_side(level, &mut runs, SHAPE.1);
    let shapes: Vec<f64> = runs
        .iter()
        .map(|(_, power)| match (power.after(SHAPE.0), power.after(SHAPE.1)) {
            (Some(a), Some(b)) if a > 0.0 => b / a,
            _ => 0.0,
        })
        .collect();
    run_side_by_side(level, &mut runs, FEW);
    drop(runs);
    for ((i, power), &shape) in cold.iter().zip(&shapes) {
        let calibrated = kept[*i].filter(|k| k.ratio > 0.0 && (shape - k.shape).abs() <= SHAPE_TOLERANCE * k.shape);
        if let (Some(k), Some(e), Some(x)) = (calibrated, power.after(FEW), power.last_start()) {
            let warm = Component { start: x.into(), inv_d: level.inv_d[own[*i]].as_slice().into(), scale: k.ratio, ..k.clone() };
            estimates[*i] = Some((padded(Some(e * k.ratio * MARGIN)), warm));
        }
    }
    let mut runs: Vec<(GroupOp, &mut PowerIteration)> =
        cold.iter_mut().filter(|(i, _)| estimates[*i].is_none()).map(|(i, p)| (ops[*i], p)).collect();
    run_side_by_side(level, &mut runs, POWER_ITERATIONS);
    drop(runs);
    for ((i, power), &shape) in cold.iter().zip(&shapes) {
        if estimates[*i].is_some() {
            continue;
        }
        let full = power.after(POWER_ITERATIONS);
        let ratio = match (full, power.after(FEW)) {
            (Some(f), Some(e)) if e > 0.0 && shape > 0.0 => f / e,
            _ => 0.0,
        };
        let (start, inv_d) = match power.last_start() {
            Some(x) if full.is_some() && !lines[*i] => (x.into(), level.inv_d[own[*i]].as_slice().into()),
            _ => Default::default(),
        };
        estimates[*i] = Some((raised_on_lines(&ops[*i], padded(full)), Component { start, inv_d, scale: 1.0, shape, ratio }));
    }
    let mut cal = vec![Component::default(); level.flags.len()];
    let mut out = Vec::with_capacity(own.len());
    for (&c, e) in own.iter().zip(estimates) {
        let (e, k) = e.expect("every component estimated");
        cal[c] = k;
        out.push(e);
    }
    (out, Calibration(cal))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bc::Kind;
    use crate::geometry::CellType;
    use crate::mesh::fixtures::rect;
    use crate::mesh::{Mesh, MeshData};
    use crate::multigrid::group::estimate_lambda_max;
    use crate::multigrid::hierarchy::{Hierarchy, HierarchyParams};
    use crate::{BoundaryConditions, Method};

    /// Every level's λmax estimates, component by component.
    fn lambdas(h: &Hierarchy) -> Vec<Vec<f64>> {
        h.levels.iter().map(|l| l.lambda_max.clone()).collect()
    }

    fn bits(v: &[Vec<f64>]) -> Vec<Vec<u64>> {
        v.iter().map(|l| l.iter().map(|x| x.to_bits()).collect()).collect()
    }

    /// The unit square of `n`×`n` cells as a free surface (bottom fixed, top clamped, the sides
    /// clamping x only, so the components have their own flags), with a coarsest size below
    /// 2D's default that keeps three levels on a small mesh.
    fn free_surface(n: usize) -> (Mesh, BoundaryConditions, HierarchyParams) {
        let mesh = rect(n, n, [0.0, 1.0, 0.0, 1.0]);
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(1, Kind::Fixed).set_kinds(3, Kind::Clamped);
        for p in [2, 4] {
            bcs.set_kind(p, 0, Kind::Clamped).unwrap().set_kind(p, 1, Kind::Free).unwrap();
        }
        let mut params = HierarchyParams::default();
        params.coarsen.coarsest_unknowns = Some(40);
        (mesh, bcs, params)
    }

    /// A turned and shifted level keeps its diagonal and is estimated from one iteration of its
    /// kept iterate (the margin over the full estimate, which the motion leaves alone); a
    /// squashed finest level is estimated from the fixed start, not below a new hierarchy's; a restore
    /// estimates bitwise as before the failed move.
    #[test]
    fn warm_only_where_the_diagonal_stayed() {
        let (mesh, bcs, params) = free_surface(24);
        let mut h = Hierarchy::build(&mesh, Vec::new(), &bcs, Method::Biharmonic, &params).unwrap();
        assert!(h.levels.len() >= 3, "{} levels", h.levels.len());
        let built = lambdas(&h);
        assert_ne!(h.levels[0].flags[0], h.levels[0].flags[1], "the components have their own flags");

        let (c, s) = (0.03f64.cos(), 0.03f64.sin());
        let turned: Vec<f64> =
            mesh.coords().chunks(2).flat_map(|p| [c * p[0] - s * p[1] + 0.25, s * p[0] + c * p[1] - 0.5]).collect();
        assert!(h.move_to(turned.clone()).unwrap());
        let warm = lambdas(&h);
        // A rigid motion keeps the coarse levels below the first (`multigrid::lag`).
        assert!(h.phases().coarse_kept);
        for (l, (bl, wl)) in built.iter().zip(&warm).enumerate() {
            for (b, w) in bl.iter().zip(wl) {
                let want = if l < 2 { (b * MARGIN).min(1.0) } else { *b };
                assert!((w - want).abs() <= 1e-6 * want, "level {l}: warm {w}, built {b}");
            }
        }

        let squashed: Vec<f64> = turned.chunks(2).flat_map(|p| [p[0], p[1] * (0.3 + 0.7 * p[1].abs())]).collect();
        let carried = h.carried();
        assert!(h.move_to(squashed.clone()).unwrap());
        let moved = lambdas(&h);
        let fresh = lambdas(&Hierarchy::build(&mesh.with_coords(squashed), Vec::new(), &bcs, Method::Biharmonic, &params).unwrap());
        for (m, f) in moved[0].iter().zip(&fresh[0]) {
            assert!(m.to_bits() == f.to_bits() || (*m >= *f && *m <= f * MARGIN * MARGIN), "squashed: {m} against a new level's {f}");
        }

        assert!(h.restore(turned, carried).unwrap());
        assert_eq!(bits(&lambdas(&h)), bits(&warm), "a restore estimates as before");
    }

    /// A calibration whose diagonal the level kept gives one iteration from its iterate times
    /// its scale and the margin (on the same level, the full estimate's last product again); one whose
    /// diagonal moved past `DRIFT` somewhere, without a rescaling ratio, gives the full estimate,
    /// bitwise, and calibrates again.
    #[test]
    fn the_diagonal_chooses_the_warm_or_the_full_estimate() {
        let mesh = rect(16, 16, [0.0, 1.0, 0.0, 1.0]);
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(1, Kind::Fixed).set_kinds(3, Kind::Clamped);
        let h = Hierarchy::build(&mesh, Vec::new(), &bcs, Method::Biharmonic, &HierarchyParams::default()).unwrap();
        let level = &h.levels[0];
        let op = GroupOp::new(level, 0..1, false);
        let mut power = PowerIteration::new(&op);
        power.run(&op, POWER_ITERATIONS);
        let full = power.after(POWER_ITERATIONS).unwrap();
        let (e, cal) = biharmonic_estimates(level, &[0], None);
        assert_eq!(e[0].to_bits(), padded(Some(full)).to_bits());
        let k = &cal.0[0];
        assert_eq!(k.start.len(), level.n());
        // A rescaled estimate's iterate (scale 0.5), so the padded estimate stays below the cap.
        let half = Calibration(vec![Component { scale: 0.5, ..k.clone() }]);
        let (e, _) = biharmonic_estimates(level, &[0], Some(&half));
        let want = padded(Some(full * 0.5 * MARGIN));
        assert!((e[0] - want).abs() <= 1e-12 && want < 0.9, "{} against {want}", e[0]);
        // One unknown's diagonal 20% away: the warm estimate raised by 1.2, unless the raise
        // alone takes it to the l1 bound (then the full estimate, here with no rescaling).
        let i = k.inv_d.iter().position(|&d| d > 0.0).unwrap();
        let mut inv_d = k.inv_d.to_vec();
        inv_d[i] *= 1.2;
        let near = Calibration(vec![Component { inv_d: inv_d.clone().into(), scale: 0.5, ratio: 0.0, ..k.clone() }]);
        let (e, _) = biharmonic_estimates(level, &[0], Some(&near));
        let want = padded(Some(full * 0.5 * MARGIN * 1.2));
        assert!((e[0] - want).abs() <= 1e-12 && want < 1.0, "{} against {want}", e[0]);
        let scale = 0.95 / (1.1 * full * MARGIN);
        let lifted = Calibration(vec![Component { inv_d: inv_d.clone().into(), scale, ratio: 0.0, ..k.clone() }]);
        let (e, _) = biharmonic_estimates(level, &[0], Some(&lifted));
        assert_eq!(e[0].to_bits(), estimate_lambda_max(&op).to_bits(), "the raise alone reaches the bound");
        let capped = Calibration(vec![Component { inv_d: inv_d.into(), scale: 2.0 / full, ratio: 0.0, ..k.clone() }]);
        assert_eq!(biharmonic_estimates(level, &[0], Some(&capped)).0, [1.0], "at the bound unraised: warm");
        // One unknown's diagonal past `DRIFT`: the full estimate.
        let mut inv_d = k.inv_d.to_vec();
        inv_d[i] *= 1.0 + 1.2 * DRIFT;
        let moved = Calibration(vec![Component { inv_d: inv_d.into(), ratio: 0.0, ..k.clone() }]);
        let (e, cal) = biharmonic_estimates(level, &[0], Some(&moved));
        assert_eq!(e[0].to_bits(), estimate_lambda_max(&op).to_bits());
        assert_eq!(&*cal.0[0].inv_d, level.inv_d[0].as_slice(), "calibrated again");
        assert!((largest_drift(&[1.0, 0.0, 0.5], &[1.0 / 1.1, 0.0, 0.5]) - 0.1).abs() < 1e-12);
        assert_eq!(largest_drift(&[1.0, 0.0], &[1.0, 0.5]), f64::INFINITY);
    }

    /// The n³ hexahedra of the unit cube graded towards z = 0 (the cells there half as high as
    /// at z = 1, too little for lines), its boundary left untagged (fixed).
    fn graded_hex_box(n: usize) -> Mesh {
        let mut d = MeshData::new(3);
        let at = |i: usize| i as f64 / n as f64;
        for k in 0..=n {
            for j in 0..=n {
                for i in 0..=n {
                    d.push_vertex(&[at(i), at(j), 0.5 * at(k) * (1.0 + at(k))]);
                }
            }
        }
        let id = |i: usize, j: usize, k: usize| ((k * (n + 1) + j) * (n + 1) + i) as u32;
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let c = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
                        .map(|(a, b, e)| id(i + a, j + b, k + e));
                    d.push_cell(CellType::Hexahedron, &c, 0);
                }
            }
        }
        Mesh::from_data(&d).unwrap()
    }

    /// On a graded hexahedral box whose cells near the graded wall are compressed (the largest
    /// diagonal drift between 12% and `DRIFT`), the moved level's estimate is one product
    /// from the kept iterate raised by the drift, and it lies above the level's fresh estimate
    /// by less than the raise and the margin.
    #[test]
    fn the_raised_warm_estimate_errs_high_on_a_compressed_graded_box() {
        let mesh = graded_hex_box(8);
        let bcs = BoundaryConditions::new();
        let params = HierarchyParams::default();
        let mut h = Hierarchy::build(&mesh, Vec::new(), &bcs, Method::Biharmonic, &params).unwrap();
        let (_, cal) = biharmonic_estimates(&h.levels[0], &[0], None);
        let squeezed: Vec<f64> =
            mesh.coords().chunks(3).flat_map(|p| [p[0], p[1], p[2] * (1.0 - 0.1 * (1.0 - p[2]) * p[0])]).collect();
        assert!(h.move_to(squeezed).unwrap());
        let level = &h.levels[0];
        let drift = largest_drift(&cal.0[0].inv_d, &level.inv_d[0]);
        assert!(drift > 0.12 && drift <= DRIFT, "drift {drift}");
        let op = GroupOp::new(level, 0..1, false);
        let fresh = estimate_lambda_max(&op);
        let (warm, _) = biharmonic_estimates(level, &[0], Some(&cal));
        assert_eq!(warm[0].to_bits(), level.lambda_max[0].to_bits(), "the hierarchy's own estimate");
        let mut power = PowerIteration::from_start(&op, cal.0[0].start.to_vec());
        power.run(&op, 1);
        let e = power.after(1).unwrap() * MARGIN;
        assert_eq!(warm[0].to_bits(), padded(Some(e * (1.0 + drift))).to_bits(), "the warm estimate, raised");
        assert!(warm[0] >= fresh && warm[0] <= fresh * (1.0 + drift) * MARGIN, "warm {} against fresh {fresh}", warm[0]);
    }

    /// Without a kept iterate, a calibration whose shape the iteration keeps gives the 8th
    /// estimate times its ratio and the margin; one whose shape it leaves gives the full
    /// estimate, bitwise.
    #[test]
    fn the_shape_chooses_the_rescaled_or_the_full_estimate() {
        let mesh = rect(16, 16, [0.0, 1.0, 0.0, 1.0]);
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(1, Kind::Fixed).set_kinds(3, Kind::Clamped);
        let h = Hierarchy::build(&mesh, Vec::new(), &bcs, Method::Biharmonic, &HierarchyParams::default()).unwrap();
        let level = &h.levels[0];
        let (_, cal) = biharmonic_estimates(level, &[0], None);
        let k = &cal.0[0];
        assert!(k.shape > 0.0 && k.ratio > 0.0, "calibrated: shape {} ratio {}", k.shape, k.ratio);
        let op = GroupOp::new(level, 0..1, false);
        let mut power = PowerIteration::new(&op);
        power.run(&op, FEW);
        let e8 = power.after(FEW).unwrap();
        let kept = Calibration(vec![Component { shape: k.shape, ratio: 0.25, ..Default::default() }]);
        let (e, _) = biharmonic_estimates(level, &[0], Some(&kept));
        assert_eq!(e[0].to_bits(), padded(Some(e8 * 0.25 * MARGIN)).to_bits());
        assert!(e[0] < 0.5, "{}", e[0]);
        let left = Calibration(vec![Component { shape: k.shape * (1.0 + 2.0 * SHAPE_TOLERANCE), ratio: 0.25, ..Default::default() }]);
        let (e, cal) = biharmonic_estimates(level, &[0], Some(&left));
        assert_eq!(e[0].to_bits(), estimate_lambda_max(&op).to_bits());
        assert_eq!(cal.0[0].ratio.to_bits(), k.ratio.to_bits(), "calibrated again");
    }

    /// The components' power iterations side by side give each component's own run bitwise, on
    /// every level and at one and three threads: the full estimates and the kept iterates of a
    /// new level, and a rescaled component (a calibration whose shape holds) beside a full one;
    /// `LevelOperator::applies` is each block's `apply` bitwise, on the biharmonic's two passes
    /// and a one-pass operator.
    #[test]
    fn side_by_side_is_each_component_alone_bitwise() {
        let (mesh, bcs, params) = free_surface(20);
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let h = Hierarchy::build(&mesh, Vec::new(), &bcs, Method::Biharmonic, &params).unwrap();
                assert!(h.levels.len() >= 3, "{} levels", h.levels.len());
                for level in &h.levels {
                    let (e, cal) = biharmonic_estimates(level, &[0, 1], None);
                    for (c, ec) in e.iter().enumerate() {
                        let op = GroupOp::new(level, c..c + 1, false);
                        assert_eq!(ec.to_bits(), estimate_lambda_max(&op).to_bits(), "component {c}");
                        let mut power = PowerIteration::new(&op);
                        power.run(&op, POWER_ITERATIONS);
                        let own: Vec<u64> = power.last_start().unwrap().iter().map(|x| x.to_bits()).collect();
                        let kept: Vec<u64> = cal.0[c].start.iter().map(|x| x.to_bits()).collect();
                        assert_eq!(own, kept, "component {c}'s kept iterate");
                    }
                    // Component 0 rescaled after `FEW` iterations, component 1 run to the full count.
                    let mixed = Calibration(vec![
                        Component { shape: cal.0[0].shape, ratio: 0.25, ..Default::default() },
                        Component::default(),
                    ]);
                    let (m, _) = biharmonic_estimates(level, &[0, 1], Some(&mixed));
                    let op = GroupOp::new(level, 0..1, false);
                    let mut power = PowerIteration::new(&op);
                    power.run(&op, FEW);
                    assert_eq!(m[0].to_bits(), padded(Some(power.after(FEW).unwrap() * 0.25 * MARGIN)).to_bits());
                    assert_eq!(m[1].to_bits(), e[1].to_bits());
                }
                // `applies` against `apply`, three blocks, both kinds of operator.
                let lap = Hierarchy::build(&mesh, Vec::new(), &bcs, Method::Laplacian, &params).unwrap();
                for level in [&h.levels[0], &h.levels[1], &lap.levels[0]] {
                    let n = level.n();
                    assert!(level.flags[0] != level.flags[1], "the components have their own flags");
                    let flags = [&level.flags[0][..], &level.flags[1][..], &level.flags[0][..]];
                    let xs: Vec<Vec<f64>> =
                        (0..3).map(|b| (0..n).map(|i| ((i * 7919 + b * 31) % 1009) as f64 / 1009.0 - 0.5).collect()).collect();
                    let x: Vec<&[f64]> = xs.iter().map(|x| x.as_slice()).collect();
                    let (mut ys, mut ss) = (vec![vec![0.0; n]; 3], vec![vec![0.0; n]; 3]);
                    {
                        let mut y: Vec<&mut [f64]> = ys.iter_mut().map(|y| y.as_mut_slice()).collect();
                        let mut s: Vec<&mut [f64]> = ss.iter_mut().map(|s| s.as_mut_slice()).collect();
                        level.op.applies(&flags, &x, &mut y, &mut s);
                    }
                    for b in 0..3 {
                        let (mut y, mut s) = (vec![0.0; n], vec![0.0; n]);
                        level.op.apply(flags[b], x[b], &mut y, &mut s);
                        let same = y.iter().zip(&ys[b]).all(|(a, c)| a.to_bits() == c.to_bits());
                        assert!(same, "block {b} of {n} rows");
                        assert!(y.iter().any(|&v| v != 0.0));
                    }
                }
            });
        }
    }
}
