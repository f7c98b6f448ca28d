//! The polish of a tangled result. A solve stopped at the caller's tolerance leaves an error in
//! the displacement; in the thinnest cells of wall layers (the wing's trailing edge,
//! docs/PERFORMANCE.md) that error can be larger than the cell, and the moved mesh inverts
//! cells the exact solution keeps valid. Before such a result is reported tangled, the solver
//! solves on from it to a tolerance ten times tighter, checks the mesh again, and so on for up
//! to three decades; a motion that truly tangles stays tangled and is reported so. A stage
//! that unfolds no cell ends the polish: the tolerance's error shrinks tenfold a stage, so the
//! cells it folded unfold with it, while the cells a motion folds (the Laplacian's across wall
//! layers) stay folded at any tolerance. Counts of iterations and of inverted cells bound the
//! polish, never a time, so the result does not depend on the machine.

use crate::multigrid::solve::{Report, SolveParams};

/// Each stage of the polish asks for this fraction of the tolerance of the stage before.
const TIGHTER: f64 = 0.1;

/// The most stages: the last asks for a thousandth of the caller's tolerance.
const STAGES: usize = 3;

/// The tightest tolerance a polish asks for, near what double precision reaches: the
/// biharmonic on the wing's wall layers still reaches it (docs/perf-history.md, "The polish of
/// a tangled result"), while rounding in the products of cells 10⁻⁵ thick bounds how far below
/// it any solve can go.
const FLOOR: f64 = 1e-13;

/// The stages of one polish after a converged first solve.
pub(crate) struct Polish {
    /// The caller's parameters.
    p: SolveParams,
    /// The first solve's cycles: the polish runs at most as many in all.
    first: usize,
    /// The stages run so far.
    stage: usize,
    /// The last stage's tolerance.
    tol: f64,
    /// The inverted cells of the last result that moved (the first solve's, then the last
    /// stage's that ran cycles).
    inverted: usize,
    /// The polish's cycles when `inverted` was counted.
    spent: usize,
}

impl Polish {
    /// The polish of a first solve with `p` that reported `first` and left `inverted` cells
    /// inverted, or None when it did not converge (a result above its tolerance is not polished
    /// but reported as it is).
    pub(crate) fn after(p: &SolveParams, first: &Report, inverted: usize) -> Option<Polish> {
        first.converged.then_some(Polish { p: *p, first: first.cycles, stage: 0, tol: p.tol, inverted, spent: 0 })
    }

    /// The parameters of the next stage, given the report so far (the first solve and the
    /// stages run) and the cells its result leaves inverted, or None when no stage can gain:
    /// all were run, the last one that ran cycles unfolded no cell (the tangle is the
    /// motion's; a stage whose tolerance the result already met moved nothing and says
    /// nothing), the next would ask for less than the floor (by more than rounding), or no
    /// cycles are left (at most the first solve's count in all, and `p.max_cycles` with it).
    pub(crate) fn next(&mut self, so_far: &Report, inverted: usize) -> Option<SolveParams> {
        let tol = self.tol * TIGHTER;
        let left = self.p.max_cycles.saturating_sub(so_far.cycles);
        let max_cycles = left.min(self.first.saturating_sub(so_far.polish_cycles));
        if so_far.polish_cycles > self.spent {
            if inverted >= self.inverted {
                return None;
            }
            (self.inverted, self.spent) = (inverted, so_far.polish_cycles);
        }
        if self.stage == STAGES || tol * (1.0 + 1e-9) < FLOOR || max_cycles == 0 {
            return None;
        }
        self.stage += 1;
        self.tol = tol;
        Some(SolveParams { tol, max_cycles, ..self.p })
    }
}

/// The report of the solve so far and one more stage of its polish: cycles, history and seconds
/// added, the stage's residual and correction, converged (the caller checked the stage against
/// its criterion), and the stage's cycles counted among the polish's.
pub(crate) fn chain(so_far: Report, stage: Report) -> Report {
    let polish_cycles = so_far.polish_cycles + stage.cycles;
    Report { converged: true, polish_cycles, ..Report::chain(so_far, stage) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn converged(cycles: usize) -> Report {
        Report { cycles, converged: true, ..Default::default() }
    }

    #[test]
    fn each_stage_asks_a_tenth_down_to_a_thousandth_or_the_floor() {
        let tols = |p: SolveParams| {
            let first = converged(9);
            let mut polish = Polish::after(&p, &first, 10).unwrap();
            let mut so_far = first;
            let mut tols = Vec::new();
            while let Some(q) = polish.next(&so_far, 10 - tols.len()) {
                tols.push(q.tol);
                so_far = chain(so_far, converged(1));
            }
            tols
        };
        let close =
            |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x / y - 1.0).abs() < 1e-12);
        let p = SolveParams::default();
        assert!(close(&tols(p), &[1e-9, 1e-10, 1e-11]), "{:?}", tols(p));
        let tight = SolveParams { tol: 1e-12, ..p };
        assert!(close(&tols(tight), &[FLOOR]), "{:?}", tols(tight));
        assert!(tols(SolveParams { tol: FLOOR, ..p }).is_empty());
    }

    #[test]
    fn the_polish_runs_within_the_cycles_left() {
        let p = SolveParams { max_cycles: 12, ..Default::default() };
        let mut polish = Polish::after(&p, &converged(9), 1).unwrap();
        assert_eq!(polish.next(&converged(9), 1).unwrap().max_cycles, 3);
        let mut polish = Polish::after(&SolveParams::default(), &converged(9), 2).unwrap();
        let spent = Report { polish_cycles: 7, ..converged(16) };
        assert_eq!(polish.next(&spent, 1).unwrap().max_cycles, 2);
        assert!(Polish::after(&p, &Report { converged: false, ..converged(5) }, 1).is_none());
    }

    #[test]
    fn a_stage_that_unfolds_no_cell_ends_the_polish() {
        let p = SolveParams::default();
        let first = converged(9);
        let mut polish = Polish::after(&p, &first, 93).unwrap();
        assert!(polish.next(&first, 93).is_some());
        assert!(polish.next(&chain(first.clone(), converged(1)), 93).is_none());
        let mut polish = Polish::after(&p, &first, 5).unwrap();
        assert!(polish.next(&first, 5).is_some());
        let so_far = chain(first.clone(), converged(1));
        assert!(polish.next(&so_far, 2).is_some());
        assert!(polish.next(&chain(so_far, converged(1)), 3).is_none());
    }

    #[test]
    fn a_stage_that_ran_no_cycles_does_not_end_the_polish() {
        let first = converged(9);
        let mut polish = Polish::after(&SolveParams::default(), &first, 4).unwrap();
        assert!(polish.next(&first, 4).is_some());
        let idle = chain(first, converged(0));
        assert!(polish.next(&idle, 4).is_some());
        assert!(polish.next(&chain(idle, converged(2)), 4).is_none());
    }

    #[test]
    fn the_chained_report_counts_the_polish_apart() {
        let first = Report { history: vec![(1.0, 1e-9)], ..converged(9) };
        let stage = Report { rel_residual: 1e-12, history: vec![(0.1, 1e-12)], ..converged(4) };
        let r = chain(first, stage);
        assert_eq!((r.cycles, r.polish_cycles, r.rel_residual), (13, 4, 1e-12));
        assert_eq!(r.history.len(), 2);
        assert!(r.converged);
    }
}
