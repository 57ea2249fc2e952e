//! Angle wrapping: one convention, the half-open interval (−π, π] (degrees: (−180, 180]).
//!
//! A heading difference of exactly half a turn is reported as +π, never −π, so that two
//! components computing the same angle agree to the bit.

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
    fn non_finite_is_nan() {
        assert!(wrap_pi(f64::INFINITY).is_nan());
        assert!(wrap_pi(f64::NAN).is_nan());
        assert!(wrap_180(f64::NEG_INFINITY).is_nan());
    }
}
