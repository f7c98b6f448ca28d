//! One solve's report as the probes print it (included by path).

use meshmove::Solution;

/// The iterations (the polish's among them), residual, convergence, inverted cells and smallest
/// volume ratio of `sol`.
pub fn solve_line(sol: &Solution) -> String {
    format!(
        "{} iterations (polish {}), residual {:.2e}, converged {}, inverted {}, min volume {:.4}",
        sol.report.cycles,
        sol.report.polish_cycles,
        sol.report.rel_residual,
        sol.report.converged,
        sol.quality.inverted,
        sol.quality.min_area_ratio
    )
}
