//! The largest amplitude of a one-step motion that a method moves without inverting a cell.
//!
//! Every method solves a linear system on the reference mesh whose right-hand side is linear in
//! the prescribed displacement, so one step from the original mesh by the motion scaled by t
//! gives exactly t times the displacement of the unscaled motion (the relative tolerance scales
//! with it). One solve therefore gives the mesh at every amplitude: X(t) = X⁰ + t d. The largest
//! valid t is found on that line by a scan and a bisection of the inversion test, without further
//! solves.

use super::setups::CaseSetup;
use meshmove::mesh::quality::inverted_cells;
use meshmove::solver::{Options, Solver};
use meshmove::Method;
use meshmove::{Error, Result};
use std::time::Instant;

/// What [`largest_valid_amplitude`] finds.
#[derive(Clone, Debug, PartialEq)]
pub struct AmplitudeLimit {
    /// The largest amplitude found valid (no inverted cell), within `resolution` of the first
    /// inverted one; `a_max` when no amplitude up to it inverts a cell.
    pub largest_valid: f64,
    /// The smallest amplitude found with an inverted cell (`largest_valid` + at most
    /// `resolution`), if any up to `a_max`.
    pub first_inverted: Option<f64>,
    /// The solve's iterations (the larger component's).
    pub cycles: usize,
    /// Wall time: the solve and the search.
    pub seconds: f64,
}

/// The largest amplitude of `setup`'s motion, whose amplitude is `amplitude` (e.g. A of the
/// free surface), that `method` moves in one step from the original mesh without inverting a
/// cell: one solve, then amplitudes `step`, 2 `step`, … up to `a_max` are checked until one
/// inverts a cell, and the interval before it is bisected down to `resolution`. The motion must
/// be a displacement or rigid translations (a rotation is not linear in its angle).
pub fn largest_valid_amplitude(
    setup: &CaseSetup,
    amplitude: f64,
    method: Method,
    opts: &Options,
    (step, a_max, resolution): (f64, f64, f64),
) -> Result<AmplitudeLimit> {
    if setup.motion.rigid.iter().any(|(_, m)| m.rotation != [0.0; 3]) {
        return Err(Error::InvalidArgument("largest_valid_amplitude: a rotation is not linear in its angle".into()));
    }
    if !(amplitude > 0.0 && step > 0.0 && a_max >= step && resolution > 0.0) {
        return Err(Error::InvalidArgument(
            "largest_valid_amplitude: positive amplitude, step, a_max, resolution".into(),
        ));
    }
    let t0 = Instant::now();
    let mesh = &setup.mesh;
    let solver = Solver::new(mesh, &setup.bcs, Options { method, ..opts.clone() })?;
    let sol = solver.solve(&setup.motion)?;
    if !sol.report.converged {
        return Err(Error::NotConverged(format!(
            "{} {method:?}: relative residual {:e}",
            setup.name, sol.report.rel_residual
        )));
    }
    let x0 = mesh.coords();
    let valid = |a: f64| {
        let t = a / amplitude;
        let x: Vec<f64> = x0.iter().zip(&sol.displacement).map(|(x, d)| x + t * d).collect();
        inverted_cells(mesh, &x).is_empty()
    };
    let (mut good, mut bad) = (0.0, None);
    let mut k = 1;
    while k as f64 * step <= a_max + 1e-12 {
        let a = (k as f64 * step).min(a_max);
        if valid(a) {
            good = a;
        } else {
            bad = Some(a);
            break;
        }
        k += 1;
    }
    if let Some(mut b) = bad {
        while b - good > resolution {
            let m = 0.5 * (good + b);
            if valid(m) {
                good = m;
            } else {
                b = m;
            }
        }
        bad = Some(b);
    }
    Ok(AmplitudeLimit {
        largest_valid: good,
        first_inverted: bad,
        cycles: sol.report.cycles,
        seconds: t0.elapsed().as_secs_f64(),
    })
}
