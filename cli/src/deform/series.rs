//! Motions of `meshmove deform` that are not one linear ramp: a patch's rigid motion given by its
//! totals at the end of each step (a table, or a periodic formula), and a displacement field
//! given by its totals (a file per step, or one file times a periodic formula). Each step's
//! increment, from the totals before and after it, is one `advance` of the solver.

use meshmove::{Motion, RigidMotion};
use std::borrow::Cow;

/// The periodic profile of a `[[motion]]` with `period`: the fraction of its amplitude it has
/// moved by at the end of step `k`, sin(2πk/P + φ) − sin φ, zero at k = 0 so that the mesh as read
/// is the body at phase φ.
pub fn periodic(k: usize, period: f64, phase: f64) -> f64 {
    (std::f64::consts::TAU * k as f64 / period + phase).sin() - phase.sin()
}

/// A patch moved rigidly about a fixed axis through `center`: its translation and angle (radians)
/// from the mesh as read, at the end of each step.
pub struct RigidTrack {
    pub patch: i32,
    /// The rotation's unit axis (z in 2D).
    pub axis: [f64; 3],
    pub center: [f64; 3],
    pub totals: Vec<([f64; 3], f64)>,
}

impl RigidTrack {
    /// The motion of step `i` (0-based), from the body where step `i` − 1 left it: the change of
    /// translation and angle, about the centre carried along by the translation so far.
    fn increment(&self, i: usize) -> RigidMotion {
        let (t0, a0) = if i == 0 { ([0.0; 3], 0.0) } else { self.totals[i - 1] };
        let (t1, a1) = self.totals[i];
        RigidMotion {
            translation: [0, 1, 2].map(|c| t1[c] - t0[c]),
            rotation: self.axis.map(|x| x * (a1 - a0)),
            center: [0, 1, 2].map(|c| self.center[c] + t0[c]),
        }
    }
}

/// A displacement field (`dim` values per vertex) from the mesh as read, at the end of each step.
pub enum FieldTrack {
    /// One field times a factor per step.
    Scaled { field: Vec<f64>, factors: Vec<f64> },
    /// One field per step.
    PerStep(Vec<Vec<f64>>),
}

impl FieldTrack {
    /// The total displacement at the end of step `k` (1-based; 0 is the mesh as read).
    fn total(&self, k: usize) -> Cow<'_, [f64]> {
        match (self, k) {
            (FieldTrack::Scaled { field, .. }, 0) => Cow::Owned(vec![0.0; field.len()]),
            (FieldTrack::Scaled { field, factors }, k) => {
                Cow::Owned(field.iter().map(|d| d * factors[k - 1]).collect())
            }
            (FieldTrack::PerStep(fields), 0) => Cow::Owned(vec![0.0; fields[0].len()]),
            (FieldTrack::PerStep(fields), k) => Cow::Borrowed(&fields[k - 1]),
        }
    }
}

/// The motions of a case that are given step by step, beside the ramped ones.
#[derive(Default)]
pub struct Series {
    pub rigid: Vec<RigidTrack>,
    pub fields: Vec<FieldTrack>,
}

impl Series {
    /// The increment of step `i` (0-based) of `steps`: an equal part of the ramped motion `ramped`,
    /// and each track's change over the step.
    pub fn increment(&self, ramped: &Motion, i: usize, steps: usize) -> Motion {
        let mut m = ramped.increment(i, steps);
        m.rigid.extend(self.rigid.iter().map(|t| (t.patch, t.increment(i))));
        for f in &self.fields {
            let (before, after) = (f.total(i), f.total(i + 1));
            for ((d, a), b) in m.displacement.iter_mut().zip(after.iter()).zip(before.iter()) {
                *d += a - b;
            }
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn periodic_profile_starts_at_zero_and_returns_after_a_period() {
        let phase = 30f64.to_radians();
        assert_eq!(periodic(0, 20.0, phase), 0.0);
        assert!(periodic(20, 20.0, phase).abs() < 1e-15);
        // A quarter period from phase 0 is the amplitude; half a period from 30° is −2 sin 30°.
        assert!((periodic(5, 20.0, 0.0) - 1.0).abs() < 1e-15);
        assert!((periodic(10, 20.0, phase) + 1.0).abs() < 1e-15);
    }

    #[test]
    fn rigid_increments_compose_to_each_total() {
        // A turn about z through (1, 0, 0) and a translation, tabulated: applying the increments
        // one after another puts a point where each step's total puts it.
        let axis = [0.0, 0.0, 1.0];
        let totals = vec![([0.1, 0.0, 0.0], 0.2), ([0.3, -0.1, 0.0], -0.1), ([0.0, 0.2, 0.5], 0.7)];
        let track = RigidTrack { patch: 1, axis, center: [1.0, 0.0, 0.0], totals: totals.clone() };
        let x0 = [2.0, 0.5, 0.25];
        let mut x = x0;
        for (i, &(t, a)) in totals.iter().enumerate() {
            let d = track.increment(i).displacement(&x);
            x = [0, 1, 2].map(|c| x[c] + d[c]);
            let total = RigidMotion { translation: t, rotation: axis.map(|w| w * a), center: [1.0, 0.0, 0.0] };
            let want = total.apply(&x0);
            assert!((0..3).all(|c| (x[c] - want[c]).abs() < 1e-14), "step {}: {x:?} {want:?}", i + 1);
        }
    }

    #[test]
    fn field_increments_add_up_to_the_totals() {
        let ramped = Motion::from_displacement(vec![0.0; 4]);
        let series = Series {
            rigid: vec![],
            fields: vec![
                FieldTrack::Scaled { field: vec![1.0, 2.0, 0.0, 0.0], factors: vec![0.5, -1.0] },
                FieldTrack::PerStep(vec![vec![0.0, 0.0, 3.0, 0.0], vec![0.0, 0.0, 1.0, 4.0]]),
            ],
        };
        let first = series.increment(&ramped, 0, 2).displacement;
        let second = series.increment(&ramped, 1, 2).displacement;
        assert_eq!(first, vec![0.5, 1.0, 3.0, 0.0]);
        assert_eq!(second, vec![-1.5, -3.0, -2.0, 4.0]);
    }
}
