//! The trapezoidal fuzzy set ⟨θ, Δ, α, h, b⟩ of paper 000 (centre, core width, slope, height,
//! bias), used to compare a measured value with the value a place expects.
//!
//! ```text
//!   h ┤      ┌────Δ────┐
//!     │     /           \
//!     │    /             \
//!   b ┤───┘               └───      μ(x) = b + (h − b) · f(|x − θ|)
//!     └───┴──┴────θ────┴──┴──       f(d) = 1                        if d ≤ Δ/2
//!          α               α             = max(0, 1 − (d − Δ/2)/α)  otherwise
//! ```
//!
//! `α` is the horizontal run of each slope (the support is `Δ/2 + α` either side of θ); `α = 0`
//! makes a crisp interval. The bias enters by [`BiasRule::Lifted`] ([`Trapezoid::BIAS_RULE`]);
//! the grid's angle sets use the floor reading (see [`crate::core::trapezoid`]). The bias `b` is the possibility that the reading is an outlier: a value
//! far from the expectation keeps possibility `b`, not 0. With a `period` (360 for degrees), the
//! distance `|x − θ|` is taken around the circle.
//!
//! A place may expect a *range* of values rather than one (`lo .. hi`): then the distance is to
//! the nearest point of the range, `max(0, |x − θ| − w)` with θ its middle and `w` its half
//! width — the same as a trapezoid whose core is widened by the range ([`Trapezoid::degree_within`]).

use crate::core::trapezoid::BiasRule;
use serde::{Deserialize, Serialize};

/// Shape of a trapezoidal similarity; the centre θ is supplied per comparison.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Trapezoid {
    /// Δ: width of the core (fully possible values), in the measured value's unit.
    pub core: f64,
    /// α: run of each slope, same unit. 0 = crisp edges.
    pub slope: f64,
    /// h: height, in `[0, 1]` (default 1).
    pub height: f64,
    /// b: bias, in `[0, h]` (default 0).
    pub bias: f64,
    /// Period for circular quantities (360 for degrees); `None` for linear ones.
    pub period: Option<f64>,
}

impl Default for Trapezoid {
    fn default() -> Self {
        Trapezoid {
            core: 0.0,
            slope: 1.0,
            height: 1.0,
            bias: 0.0,
            period: None,
        }
    }
}

impl Trapezoid {
    /// How the bias enters: `μ = b + (h − b)·f`.
    pub const BIAS_RULE: BiasRule = BiasRule::Lifted;

    /// `μ(x)` for a trapezoid centred on `centre`. NaN or infinite inputs give the bias: a value
    /// that could not be measured is as possible as an outlier, no more.
    #[inline]
    pub fn degree(&self, x: f64, centre: f64) -> f64 {
        self.degree_within(x, centre, 0.0)
    }

    /// `μ(x)` against the range of half width `half` around `centre`: the distance is taken to
    /// the range's nearest point (`half = 0` is [`Trapezoid::degree`]). A negative or NaN `half`
    /// counts as 0. NaN or infinite inputs give the bias.
    #[inline]
    pub fn degree_within(&self, x: f64, centre: f64, half: f64) -> f64 {
        let mut d = (x - centre).abs();
        if !d.is_finite() {
            return self.bias;
        }
        if let Some(p) = self.period {
            if p > 0.0 {
                // fmod returns d itself below p: skip the library call in the usual case.
                if d >= p {
                    d %= p;
                }
                d = d.min(p - d);
            }
        }
        if half > 0.0 {
            d = (d - half).max(0.0);
        }
        let half = 0.5 * self.core;
        let f = if d <= half {
            1.0
        } else if self.slope > 0.0 {
            (1.0 - (d - half) / self.slope).max(0.0)
        } else {
            0.0
        };
        Self::BIAS_RULE.apply_f64(f, self.height, self.bias)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked_points() {
        // core 2 (±1), slope 2, height 1, bias 0.1: at distance 2 we are half way down the slope,
        // f = 0.5, μ = 0.1 + 0.9·0.5 = 0.55; at distance 3 and beyond, μ = b = 0.1.
        let t = Trapezoid {
            core: 2.0,
            slope: 2.0,
            height: 1.0,
            bias: 0.1,
            period: None,
        };
        assert_eq!(t.degree(10.0, 10.0), 1.0);
        assert_eq!(t.degree(11.0, 10.0), 1.0);
        assert!((t.degree(12.0, 10.0) - 0.55).abs() < 1e-12);
        assert!((t.degree(7.0, 10.0) - 0.1).abs() < 1e-12);
        assert!((t.degree(f64::NAN, 10.0) - 0.1).abs() < 1e-12);
    }

    #[test]
    fn a_range_widens_the_core_by_its_width() {
        // Range 2 .. 4 (θ = 3, w = 1), core 1 (±0.5), slope 2, bias 0: inside the range and up
        // to 0.5 beyond it μ = 1; at 5.5 we are 1.5 past the range, 1 into the slope: μ = 0.5;
        // the same as a single value with core 1 + 2·1 = 3.
        let t = Trapezoid {
            core: 1.0,
            slope: 2.0,
            height: 1.0,
            bias: 0.0,
            period: None,
        };
        let wide = Trapezoid { core: 3.0, ..t };
        for x in [2.0, 3.7, 4.5, 0.5, 5.5, 7.0, 9.0] {
            assert_eq!(t.degree_within(x, 3.0, 1.0), wide.degree(x, 3.0), "x = {x}");
        }
        assert_eq!(t.degree_within(3.7, 3.0, 1.0), 1.0);
        assert!((t.degree_within(5.5, 3.0, 1.0) - 0.5).abs() < 1e-12);
        assert_eq!(t.degree_within(9.0, 3.0, 1.0), 0.0);
        // A NaN half width is a single value.
        assert_eq!(t.degree_within(4.0, 3.0, f64::NAN), t.degree(4.0, 3.0));
    }

    #[test]
    fn circular_distance_wraps() {
        // 355° and 5° are 10° apart on the circle: inside a core of width 20.
        let t = Trapezoid {
            core: 20.0,
            slope: 10.0,
            height: 1.0,
            bias: 0.0,
            period: Some(360.0),
        };
        assert_eq!(t.degree(355.0, 5.0), 1.0);
        // 180° away: beyond the support (10 + 10): bias 0.
        assert_eq!(t.degree(185.0, 5.0), 0.0);
        // -20 vs 5 = 25° apart: f = 1 − (25 − 10)/10 = −0.5 → 0.
        assert_eq!(t.degree(-20.0, 5.0), 0.0);
        // 17° apart: f = 1 − 7/10 = 0.3.
        assert!((t.degree(-12.0, 5.0) - 0.3).abs() < 1e-12);
        // A turn or more apart: 725° vs 5° is 720° = 0° on the circle; 365° vs 5° exactly one
        // period (d = p); 1102° vs 5° is 1097° = 17° (after three turns): f = 0.3 again.
        assert_eq!(t.degree(725.0, 5.0), 1.0);
        assert_eq!(t.degree(365.0, 5.0), 1.0);
        assert!((t.degree(1102.0, 5.0) - 0.3).abs() < 1e-9);
        assert!((t.degree(-1092.0, 5.0) - 0.3).abs() < 1e-9);
    }
}
