//! A step's initial guess extrapolated in time from the last accepted steps' increments
//! (docs/DESIGN.md §5, "The start of a time step").
//!
//! On a smooth motion each step's prescribed values are about a multiple c of the last step's,
//! and its displacement about c times that step's displacement per unit of motion, a response
//! that drifts slowly as the reference mesh moves. The guess scales each of the last accepted
//! increments to this step's prescribed values (the least-squares multiple over the prescribed
//! unknowns, taken only where the values are that multiple to within `CONSISTENT_WITHIN`) and
//! extrapolates the scaled responses linearly in the step number: 2 r₁ − r₂ from the last two,
//! r₁ alone after the first step or where the older one does not fit. The solve overwrites the
//! guess's prescribed values with the step's own.

use std::collections::VecDeque;
use std::sync::Arc;

use crate::bc::P;
use crate::multigrid::level::Level;

/// Largest misfit, relative to the prescribed values' norm, of a step's prescribed values
/// against a multiple of a past step's for that step's response to enter the guess.
const CONSISTENT_WITHIN: f64 = 0.1;

/// How many past increments the guess extrapolates from (linear extrapolation in time; the
/// quadratic one from three, measured against it, is in docs/perf-history.md).
const KEPT: usize = 2;

/// A step's values at the finest level's prescribed unknowns, by the unknown's index in a
/// per-vertex array (vertex · dim + component), in increasing index. Which unknowns are
/// prescribed can change from one step to the next (a slip wall's frames follow the moved
/// mesh), so steps are compared by index, not by position in the list.
#[derive(Clone, Debug)]
pub(crate) struct Prescribed {
    at: Vec<(usize, f64)>,
}

/// One accepted step: its prescribed values and its displacement (`dim` per vertex), shared,
/// so the copy a call keeps to restore on failure copies neither.
#[derive(Clone, Debug)]
struct Increment {
    prescribed: Arc<Prescribed>,
    displacement: Arc<Vec<f64>>,
}

/// The last accepted steps' increments, the most recent first; empty after the reference was
/// set from outside a step.
#[derive(Clone, Debug, Default)]
pub(crate) struct Increments {
    past: VecDeque<Increment>,
}

impl Increments {
    /// Forgets every past increment (the reference was set from outside a step).
    pub(crate) fn clear(&mut self) {
        self.past.clear();
    }

    /// Keeps an accepted step's values at the prescribed unknowns (`prescribed_values`) and its
    /// `displacement` (`dim` per vertex, on the mesh the step started from), dropping the oldest
    /// beyond `KEPT`.
    pub(crate) fn push(&mut self, prescribed: Prescribed, displacement: Vec<f64>) {
        if self.past.len() >= KEPT {
            self.past.pop_back();
        }
        self.past.push_front(Increment { prescribed: Arc::new(prescribed), displacement: Arc::new(displacement) });
    }

    /// The initial guess of a step whose values at the prescribed unknowns are `now`, or None
    /// when the last step's values are no multiple of these.
    pub(crate) fn guess(&self, now: &Prescribed) -> Option<Vec<f64>> {
        // The scaled responses of the past increments that fit, up to the first that does not.
        let fits: Vec<(f64, &[f64])> = self
            .past
            .iter()
            .map_while(|p| multiple(now, &p.prescribed).map(|a| (a, p.displacement.as_slice())))
            .collect();
        let weights = EXTRAPOLATION.get(fits.len().checked_sub(1)?)?;
        let mut guess = vec![0.0; fits[0].1.len()];
        for ((a, d), w) in fits.iter().zip(weights.iter()) {
            for (g, x) in guess.iter_mut().zip(d.iter()) {
                *g += w * a * x;
            }
        }
        guess.iter().all(|g| g.is_finite()).then_some(guess)
    }
}

/// The weights of the extrapolation to the next step from the last `KEPT` steps' scaled
/// responses: from one, that response; from two, the straight line through them.
const EXTRAPOLATION: [&[f64]; KEPT] = [&[1.0], &[2.0, -1.0]];

/// The values of `vals` (`dim` per vertex) at the finest level's prescribed unknowns.
pub(crate) fn prescribed_values(lev: &Level, vals: &[f64]) -> Prescribed {
    let dim = lev.dim();
    let mut at = Vec::new();
    for (c, flags) in lev.flags.iter().enumerate() {
        for d in (0..flags.len()).filter(|&d| flags[d] & P != 0) {
            let i = lev.dofs.vertices_of(d)[0] as usize * dim + c;
            at.push((i, vals[i]));
        }
    }
    at.sort_unstable_by_key(|&(i, _)| i);
    Prescribed { at }
}

/// The least-squares multiple α of `past` nearest to `now` over the unknowns prescribed now (a
/// value not prescribed in the past step counts as zero there), when `now` is that multiple to
/// within `CONSISTENT_WITHIN` of its norm.
fn multiple(now: &Prescribed, past: &Prescribed) -> Option<f64> {
    let (mut vv, mut vp, mut pp) = (0.0, 0.0, 0.0);
    let mut then = past.at.iter().peekable();
    for &(i, v) in &now.at {
        while then.next_if(|&&(j, _)| j < i).is_some() {}
        let p = then.next_if(|&&(j, _)| j == i).map_or(0.0, |&(_, p)| p);
        vv += v * v;
        vp += v * p;
        pp += p * p;
    }
    if !(pp > 0.0 && vv > 0.0) {
        return None;
    }
    let alpha = vp / pp;
    // |v − α p|² = |v|² − (v·p)²/|p|².
    let misfit = (vv - vp * alpha).max(0.0);
    (misfit <= CONSISTENT_WITHIN * CONSISTENT_WITHIN * vv).then_some(alpha)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values prescribed at the unknowns 0, 1, ….
    fn at(values: &[f64]) -> Prescribed {
        Prescribed { at: values.iter().copied().enumerate().collect() }
    }

    /// Responses that drift linearly with the step are extrapolated exactly, each scaled to the
    /// step's prescribed values; an older increment that does not fit is left out.
    #[test]
    fn extrapolates_scaled_responses() {
        let mut inc = Increments::default();
        assert_eq!(inc.guess(&at(&[1.0, 2.0])), None);
        // Unit responses r(k) = [1 + k, 3 − k] over prescribed values c_k (1, 2): c = 2, then −1.
        inc.push(at(&[2.0, 4.0]), vec![2.0 * 1.0, 2.0 * 3.0]);
        assert_eq!(inc.guess(&at(&[1.0, 2.0])), Some(vec![1.0, 3.0]));
        inc.push(at(&[-1.0, -2.0]), vec![-2.0, -2.0]);
        // Step 2 at c = 3: 3 (2 r(1) − r(0)) = 3 r(2) = [9, 3].
        assert_eq!(inc.guess(&at(&[3.0, 6.0])), Some(vec![9.0, 3.0]));
        // Values no multiple of the last step's: no guess.
        assert_eq!(inc.guess(&at(&[1.0, -2.0])), None);
        // An older increment whose values do not fit is left out: the last one's response alone.
        inc.push(at(&[1.0, 2.0]), vec![3.0, 1.0]);
        inc.push(at(&[1.0, 0.0]), vec![5.0, 7.0]);
        assert_eq!(inc.guess(&at(&[2.0, 0.0])), Some(vec![10.0, 14.0]));
        inc.clear();
        assert_eq!(inc.guess(&at(&[2.0, 0.0])), None);
    }

    /// Steps whose prescribed unknowns differ (a slip wall's frames moved) are compared at the
    /// unknowns prescribed now, a value not prescribed then counting as zero.
    #[test]
    fn compares_steps_by_the_unknowns_prescribed_now() {
        let mut inc = Increments::default();
        inc.push(Prescribed { at: vec![(0, 2.0), (3, 4.0), (5, 0.0)] }, vec![4.0, 6.0]);
        let now = Prescribed { at: vec![(0, 1.0), (2, 0.0), (3, 2.0)] };
        assert_eq!(inc.guess(&now), Some(vec![2.0, 3.0]));
        let off = Prescribed { at: vec![(0, 1.0), (2, 1.0), (3, 2.0)] };
        assert_eq!(inc.guess(&off), None);
    }
}
