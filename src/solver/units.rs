//! The solve independent of the units: a system whose prescribed displacements are far from 1
//! is solved scaled by a power of two and scaled back.
//!
//! The conjugate-gradient scalars are products of two displacements and the operator (pᵀAp,
//! rᵀz): displacements of 1e154 overflow them and displacements of 1e-170 underflow them to
//! zero, although both are representable and the answer is only the normal one scaled. The
//! system is linear, so it is solved for the displacements times 2^k, with 2^k bringing the
//! largest prescribed displacement near 1. Multiplying by a power of two is exact (it changes
//! only the exponent), so a scaled solve gives the unscaled one's digits wherever the unscaled
//! one neither overflows nor underflows. Inside [`SAFE`] nothing is scaled: the usual calls do
//! no extra passes and their results stay bitwise as they are.

/// Largest prescribed displacements in 2^-SAFE..2^SAFE are solved as they are. Their squares
/// times an operator entry and a sum over the unknowns stay far inside the range of `f64`
/// (about 2^±1022).
const SAFE: i32 = 200;

/// The power of two the system of largest prescribed displacement `largest` is multiplied by:
/// 1 inside the safe range (or for no motion, or a non-finite one, which is refused elsewhere),
/// otherwise the power nearest to 1/`largest`.
pub(super) fn factor(largest: f64) -> f64 {
    if largest == 0.0 || !largest.is_finite() {
        return 1.0;
    }
    let e = exponent(largest);
    if (-SAFE..=SAFE).contains(&e) {
        return 1.0;
    }
    // 2^-e is kept normal: a subnormal `largest` is brought to about 2^-74 at least, the
    // largest finite one to below 4, both well inside the safe range.
    power_of_two((-e).clamp(-1022, 1000))
}

/// The binary exponent of a finite, non-zero `x`: 2^e ≤ |x| < 2^(e+1) (for subnormals, about).
fn exponent(x: f64) -> i32 {
    let bits = ((x.to_bits() >> 52) & 0x7ff) as i32;
    if bits == 0 {
        // Subnormal: below 2^-1022.
        -1023 - (x.abs().to_bits().leading_zeros() as i32 - 12)
    } else {
        bits - 1023
    }
}

/// 2^k for k in -1022..=1023, exact.
fn power_of_two(k: i32) -> f64 {
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// Multiplies every value by `f` (a power of two: exact).
pub(super) fn scale(values: &mut [f64], f: f64) {
    values.iter_mut().for_each(|v| *v *= f);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn usual_sizes_are_left_alone_and_extreme_ones_brought_near_one() {
        for x in [1e-60, 1e-3, 1.0, 0.1, 7.5e59, 0.0] {
            assert_eq!(factor(x), 1.0, "{x}");
        }
        for x in [1e-170, 1e154, 1e300, -1e300, 1e-300, 5e-324, f64::MAX] {
            let f = factor(x);
            let y = x.abs() * f;
            assert!(y >= 2f64.powi(-80) && y < 4.0, "{x} × {f} = {y}");
            assert_eq!(f.to_bits() & ((1 << 52) - 1), 0, "{f} is a power of two");
        }
        assert_eq!(exponent(1.0), 0);
        assert_eq!(exponent(0.75), -1);
        assert_eq!(exponent(f64::MIN_POSITIVE), -1022);
        assert_eq!(power_of_two(-3), 0.125);
    }
}
