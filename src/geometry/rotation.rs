//! Rotations in 2 and 3 dimensions, given as a rotation vector ω: in 3D the axis times the angle
//! (radians, right-handed), in 2D the angle alone, stored as ω = (0, 0, θ) (a rotation about z).

use super::{cross, dot3};
use glam::DVec2;

/// How many values give a rotation in `dim` dimensions: the angle in 2D, the rotation vector
/// (axis × angle) in 3D.
pub(crate) fn value_count(dim: usize) -> usize {
    if dim == 2 {
        1
    } else {
        3
    }
}

/// The rotation vector of the first [`value_count`]`(dim)` values of `v`.
pub(crate) fn from_values(v: &[f64], dim: usize) -> [f64; 3] {
    if dim == 2 {
        [0.0, 0.0, v[0]]
    } else {
        [v[0], v[1], v[2]]
    }
}

/// The rotation angle: the rotation vector's length in 3D, the signed angle in 2D.
pub(crate) fn angle(omega: &[f64; 3], dim: usize) -> f64 {
    if dim == 2 {
        omega[2]
    } else {
        dot3(omega, omega).sqrt()
    }
}

/// R r for the rotation vector `omega` (`dim` = 2: only ω_z is read).
pub(crate) fn rotate(omega: &[f64; 3], dim: usize, r: &[f64; 3]) -> [f64; 3] {
    if dim == 2 {
        let q = DVec2::from_angle(omega[2]).rotate(DVec2::new(r[0], r[1]));
        return [q.x, q.y, 0.0];
    }
    let theta = dot3(omega, omega).sqrt();
    if theta == 0.0 {
        return *r;
    }
    let k = omega.map(|w| w / theta);
    let (s, c) = theta.sin_cos();
    let kxr = cross(&k, r);
    let kr = dot3(&k, r) * (1.0 - c);
    [0, 1, 2].map(|i| r[i] * c + kxr[i] * s + k[i] * kr)
}

/// The rotation vector of "first `a`, then `b`". In 2D, and in 3D about one axis, the angles add
/// (a turn past 360° keeps its angle, so a sum of increments ramps as a whole); otherwise the
/// product of the two rotations, as a rotation vector of angle in [0, π].
pub(crate) fn compose(a: &[f64; 3], b: &[f64; 3], dim: usize) -> [f64; 3] {
    if dim == 2 || cross(a, b) == [0.0; 3] {
        return [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
    }
    let quat = |w: &[f64; 3]| {
        let t = dot3(w, w).sqrt();
        let s = if t == 0.0 { 0.0 } else { (0.5 * t).sin() / t };
        ((0.5 * t).cos(), w.map(|x| x * s))
    };
    let ((wa, va), (wb, vb)) = (quat(a), quat(b));
    // q = q_b q_a.
    let w = wb * wa - dot3(&vb, &va);
    let c = cross(&vb, &va);
    let mut v = [0, 1, 2].map(|i| wb * va[i] + wa * vb[i] + c[i]);
    let mut w = w;
    if w < 0.0 {
        w = -w;
        v = v.map(|x| -x);
    }
    let n = dot3(&v, &v).sqrt();
    if n == 0.0 {
        return [0.0; 3];
    }
    let theta = 2.0 * n.atan2(w);
    v.map(|x| x / n * theta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_turns() {
        let z = [0.0, 0.0, std::f64::consts::FRAC_PI_2];
        let r = rotate(&z, 3, &[1.0, 0.0, 0.0]);
        assert!((r[0]).abs() < 1e-15 && (r[1] - 1.0).abs() < 1e-15);
        let r2 = rotate(&z, 2, &[1.0, 0.0, 0.0]);
        assert!((r2[1] - 1.0).abs() < 1e-15);
        // x then y quarter turns: the composition rotates like the two in sequence.
        let x = [std::f64::consts::FRAC_PI_2, 0.0, 0.0];
        let y = [0.0, std::f64::consts::FRAC_PI_2, 0.0];
        let xy = compose(&x, &y, 3);
        let p = [0.3, -0.7, 1.1];
        let seq = rotate(&y, 3, &rotate(&x, 3, &p));
        let one = rotate(&xy, 3, &p);
        for i in 0..3 {
            assert!((seq[i] - one[i]).abs() < 1e-14);
        }
    }
}
