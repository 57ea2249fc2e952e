//! Angle wrapping: one convention, the half-open interval (−π, π] (degrees: (−180, 180]).
//!
//! A heading difference of exactly half a turn is reported as +π, never −π, so that two
//! components computing the same angle agree to the bit. [`wrap_pi_f32`] is the single-precision
//! form the grid's inner loops use: most of its inputs are differences of wrapped angles, so it
//! tries two compares before any division.

use std::f64::consts::{PI, TAU};

/// `a` (radians) wrapped into (−π, π]. Non-finite input gives NaN.
#[inline]
pub fn wrap_pi(a: f64) -> f64 {
    let w = (a + PI).rem_euclid(TAU) - PI;
    // rem_euclid maps an odd multiple of π to −π; the convention is (−π, π].
    if w <= -PI {
        w + TAU
    } else {
        w
    }
}

/// `a` (degrees) wrapped into (−180, 180]. Non-finite input gives NaN.
#[inline]
pub fn wrap_180(a: f64) -> f64 {
    let w = (a + 180.0).rem_euclid(360.0) - 180.0;
    if w <= -180.0 {
        w + 360.0
    } else {
        w
    }
}

/// `a` (radians, `f32`) wrapped into (−π, π]. Non-finite input is returned unchanged so the
/// caller's validation sees it.
#[inline]
pub fn wrap_pi_f32(a: f32) -> f32 {
    use std::f32::consts::PI;
    const TAU: f32 = 2.0 * PI;
    // Most inputs are differences of wrapped angles: two compares beat fmod.
    if a > -PI && a <= PI {
        return a;
    }
    if a > PI && a <= 3.0 * PI {
        return a - TAU;
    }
    if a <= -PI && a > -3.0 * PI {
        return a + TAU;
    }
    if !a.is_finite() {
        return a;
    }
    let mut r = a % TAU; // in (-2π, 2π)
    if r > PI {
        r -= TAU;
    } else if r <= -PI {
        r += TAU;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_turns_land_on_plus_pi() {
        assert_eq!(wrap_pi(PI), PI);
        assert_eq!(wrap_pi(-PI), PI);
        assert_eq!(wrap_pi(3.0 * PI), PI);
        assert_eq!(wrap_180(-180.0), 180.0);
        assert_eq!(wrap_180(540.0), 180.0);
    }

    #[test]
    fn results_are_in_range_and_equivalent() {
        // Brute force over a grid of angles several turns wide: the result is in (−π, π] and
        // differs from the input by a whole number of turns.
        for i in -4000..=4000 {
            let a = i as f64 * 0.00731;
            let w = wrap_pi(a);
            assert!(w > -PI && w <= PI, "{a} -> {w}");
            let turns = (a - w) / TAU;
            assert!((turns - turns.round()).abs() < 1e-9, "{a} -> {w}");
            let d = a.to_degrees();
            let wd = wrap_180(d);
            assert!(wd > -180.0 && wd <= 180.0, "{d} -> {wd}");
            let turns = (d - wd) / 360.0;
            assert!((turns - turns.round()).abs() < 1e-9, "{d} -> {wd}");
        }
    }

    #[test]
    fn f32_form_is_in_range_and_equivalent() {
        use std::f32::consts::{PI, TAU};
        for k in -20..20 {
            let a = k as f32 * 0.77;
            let w = wrap_pi_f32(a);
            assert!(w > -PI - 1e-6 && w <= PI + 1e-6, "{a} -> {w}");
            assert!(((a - w) / TAU - ((a - w) / TAU).round()).abs() < 1e-4);
        }
        assert_eq!(wrap_pi_f32(PI), PI);
        assert_eq!(wrap_pi_f32(-PI), PI);
        assert!(wrap_pi_f32(f32::NAN).is_nan());
        assert_eq!(wrap_pi_f32(f32::INFINITY), f32::INFINITY);
    }

    #[test]
    fn non_finite_is_nan() {
        assert!(wrap_pi(f64::INFINITY).is_nan());
        assert!(wrap_pi(f64::NAN).is_nan());
        assert!(wrap_180(f64::NEG_INFINITY).is_nan());
    }
}
