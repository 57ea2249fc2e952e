//! The similarity of a measured value with the value a place expects: paper 000's trapezoid
//! ⟨θ, Δ, α, h, b⟩ ([`crate::core::trapezoid::Trapezoid`], the crate's one) with the centre θ
//! supplied per comparison, the bias lifting the trapezoid ([`BiasRule::Lifted`]).
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
//! makes a crisp interval. The bias `b` is the possibility that the reading is an outlier: a
//! value far from the expectation keeps possibility `b`, not 0 (the grid's angle sets read the
//! bias as a floor instead, see [`crate::core::trapezoid`]). What this type adds to the
//! trapezoid is where the distance `|x − θ|` comes from: with a `period` (360 for degrees) it is
//! taken around the circle.
//!
//! A place may expect a *range* of values rather than one (`lo .. hi`): then the distance is to
//! the nearest point of the range, `max(0, |x − θ| − w)` with θ its middle and `w` its half
//! width — the same as a trapezoid whose core is widened by the range
//! ([`Similarity::degree_within`]).

use crate::core::trapezoid::{BiasRule, Trapezoid};
use serde::{Deserialize, Serialize};

/// A trapezoidal similarity; the centre θ is supplied per comparison. Serialized as the flat
/// `core, slope, height, bias, period` of a rule file's `similarity … = trapezoid(…)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(from = "SimilarityWire", into = "SimilarityWire")]
pub struct Similarity {
    /// The trapezoid, in the measured value's unit; its rule is [`Similarity::BIAS_RULE`].
    pub shape: Trapezoid<f64>,
    /// Period for circular quantities (360 for degrees); `None` for linear ones.
    pub period: Option<f64>,
}

/// The serialized fields of a [`Similarity`].
#[derive(Serialize, Deserialize)]
struct SimilarityWire {
    core: f64,
    slope: f64,
    height: f64,
    bias: f64,
    period: Option<f64>,
}

impl From<SimilarityWire> for Similarity {
    fn from(w: SimilarityWire) -> Self {
        Similarity::new(w.core, w.slope, w.height, w.bias, w.period)
    }
}

impl From<Similarity> for SimilarityWire {
    fn from(s: Similarity) -> Self {
        SimilarityWire {
            core: s.shape.core,
            slope: s.shape.slope,
            height: s.shape.height,
            bias: s.shape.bias,
            period: s.period,
        }
    }
}

impl Default for Similarity {
    /// A crisp point with slopes of 1: core 0, slope 1, height 1, bias 0, linear.
    fn default() -> Self {
        Similarity::new(0.0, 1.0, 1.0, 0.0, None)
    }
}

impl Similarity {
    /// How the bias enters: `μ = b + (h − b)·f`.
    pub const BIAS_RULE: BiasRule = BiasRule::Lifted;

    /// The similarity of core Δ, slope α, height h, bias b (in the measured value's unit), over
    /// a circle of `period` when given. Values are taken as given: the rule checker vouches
    /// for them.
    pub fn new(core: f64, slope: f64, height: f64, bias: f64, period: Option<f64>) -> Similarity {
        Similarity {
            shape: Trapezoid {
                core,
                slope,
                height,
                bias,
                rule: Self::BIAS_RULE,
            },
            period,
        }
    }

    /// `μ(x)` for a trapezoid centred on `centre`. NaN or infinite inputs give the bias: a value
    /// that could not be measured is as possible as an outlier, no more.
    #[inline]
    pub fn degree(&self, x: f64, centre: f64) -> f64 {
        self.degree_within(x, centre, 0.0)
    }

    /// `μ(x)` against the range of half width `half` around `centre`: the distance is taken to
    /// the range's nearest point (`half = 0` is [`Similarity::degree`]). A negative or NaN `half`
    /// counts as 0. NaN or infinite inputs give the bias.
    #[inline]
    pub fn degree_within(&self, x: f64, centre: f64, half: f64) -> f64 {
        let mut d = (x - centre).abs();
        if !d.is_finite() {
            return self.shape.bias;
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
        self.shape.degree_at(d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_worked_points() {
        // core 2 (±1), slope 2, height 1, bias 0.1: at distance 2 we are half way down the slope,
        // f = 0.5, μ = 0.1 + 0.9·0.5 = 0.55; at distance 3 and beyond, μ = b = 0.1.
        let t = Similarity::new(2.0, 2.0, 1.0, 0.1, None);
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
        let t = Similarity::new(1.0, 2.0, 1.0, 0.0, None);
        let wide = Similarity::new(3.0, 2.0, 1.0, 0.0, None);
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
        let t = Similarity::new(20.0, 10.0, 1.0, 0.0, Some(360.0));
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
