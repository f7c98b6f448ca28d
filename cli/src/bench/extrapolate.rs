//! How long a capped stationary iteration (the Jacobi mover, the paper-faithful W-cycle) would
//! have needed to reach the tolerance, from its residual history: the table prints it beside the
//! measured lower bound, so a row stopped by its cap never reads as a finished solve.

/// Estimated seconds to `tol`, given the (step, relative residual) history of a run that took
/// `seconds` and ended at the history's last step: its rate per step over the second half of the
/// history, assumed to hold to the end. `seconds` when it got there; infinite when it was not
/// converging.
pub fn seconds_to_tol(hist: &[(usize, f64)], seconds: f64, tol: f64) -> f64 {
    let Some(&(s2, r2)) = hist.last() else { return f64::INFINITY };
    if r2 <= tol {
        return seconds;
    }
    let (s1, r1) = hist[hist.len() / 2];
    if s2 <= s1 || r1 <= 0.0 {
        return f64::INFINITY;
    }
    let rate = (r2 / r1).powf(1.0 / (s2 - s1) as f64);
    if rate < 1.0 {
        let more = (tol / r2).ln() / rate.ln();
        seconds * (s2 as f64 + more) / s2 as f64
    } else {
        f64::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::seconds_to_tol;

    #[test]
    fn a_geometric_history_extrapolates_exactly() {
        // Residual 0.5^k after k steps, 1 s per 10 steps: 1e-8 needs log2(1e8) ≈ 26.6 steps.
        let hist: Vec<(usize, f64)> = (0..=10).map(|k| (k, 0.5f64.powi(k as i32))).collect();
        let est = seconds_to_tol(&hist, 1.0, 1e-8);
        assert!((est - 1e8f64.log2() / 10.0).abs() < 1e-12, "{est}");
    }

    #[test]
    fn converged_stalled_and_empty_histories() {
        assert_eq!(seconds_to_tol(&[(0, 1.0), (5, 1e-9)], 2.0, 1e-8), 2.0);
        assert_eq!(seconds_to_tol(&[(0, 1.0), (5, 1.0), (10, 1.0)], 2.0, 1e-8), f64::INFINITY);
        assert_eq!(seconds_to_tol(&[], 0.0, 1e-8), f64::INFINITY);
        assert_eq!(seconds_to_tol(&[(0, 1.0)], 0.0, 1e-8), f64::INFINITY);
    }
}
