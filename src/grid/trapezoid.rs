//! Trapezoidal fuzzy sets `⟨θ, Δ, α, h, b⟩` of paper 000 (Buschka, Saffiotti,
//! Wasik, Fig. 2) on the real line and on the circle of headings, and the
//! paper's intersection rule for angle sets (Fig. 4).
//!
//! This module is pure arithmetic: no grid, no allocation. Everything else in
//! [`crate::grid`] measures distances and angles with these sets. What it adds to the crate's
//! one trapezoid ([`crate::core::trapezoid::Trapezoid`], which gives the shape and the
//! membership: [`Trapezoid::shape`]) is a centre of its own, the circle of headings and the
//! intersection of angle sets.
//!
//! # Conventions
//!
//! * `core` (Δ) is the *full* width of the top; `slope` (α) is the horizontal
//!   width of each flank, over which the membership falls linearly from `height`
//!   to zero (α = 0 gives a rectangle). The paper names α "the slope"; storing
//!   the flank width instead of a gradient keeps the rectangle case finite.
//! * The bias `b` is a uniform floor: `μ(x) = max(b, h · f(x))`
//!   ([`BiasRule::Floor`], [`Trapezoid::BIAS_RULE`]; the rule engine's
//!   similarities, [`crate::logic::Similarity`], read it the other way, see
//!   [`crate::core::trapezoid`]). It
//!   is the possibility that the reading is an outlier ("the actual value is
//!   somewhere else").
//! * Angles are radians; every angular distance is taken the short way round,
//!   so sets wrap around 2π.
//!
//! # Complexity
//!
//! Every operation is O(1).
//!
//! # Example
//!
//! ```
//! use lplace::grid::Trapezoid;
//! let a = Trapezoid::new(0.0, 0.2, 0.2, 1.0, 0.1);
//! let b = Trapezoid::new(0.25, 0.2, 0.2, 1.0, 0.1);
//! let c = a.intersect_angle(&b);
//! assert!((c.shape.bias - 0.01).abs() < 1e-6); // b_C = b_A · b_B
//! assert!(c.center > 0.0 && c.center < 0.25);
//! ```

use crate::core::angle::wrap_pi_f32 as wrap_pi;
use crate::core::trapezoid::{BiasRule, Trapezoid as CoreTrapezoid};
use serde::{Deserialize, Serialize};
use std::f32::consts::PI;

const TAU: f32 = 2.0 * PI;

/// A trapezoidal fuzzy set `⟨center, core, slope, height, bias⟩`: the crate's one trapezoid
/// ([`CoreTrapezoid`], floor bias) placed at a centre of its own.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(from = "TrapezoidWire", into = "TrapezoidWire")]
pub struct Trapezoid {
    /// θ: centre of the core.
    pub center: f32,
    /// `⟨Δ, α, h, b⟩` around θ, the bias a floor ([`Trapezoid::BIAS_RULE`]).
    pub shape: CoreTrapezoid<f32>,
}

/// The serialized fields of a [`Trapezoid`]: flat, as before the shape was its own type.
#[derive(Serialize, Deserialize)]
struct TrapezoidWire {
    center: f32,
    core: f32,
    slope: f32,
    height: f32,
    bias: f32,
}

impl From<TrapezoidWire> for Trapezoid {
    fn from(w: TrapezoidWire) -> Self {
        Trapezoid::raw(w.center, w.core, w.slope, w.height, w.bias)
    }
}

impl From<Trapezoid> for TrapezoidWire {
    fn from(t: Trapezoid) -> Self {
        TrapezoidWire {
            center: t.center,
            core: t.shape.core,
            slope: t.shape.slope,
            height: t.shape.height,
            bias: t.shape.bias,
        }
    }
}

impl Trapezoid {
    /// Builds a set, clamping widths to ≥ 0 and height/bias to [0, 1]
    /// (non-finite widths become 0, non-finite height/bias become 0).
    pub fn new(center: f32, core: f32, slope: f32, height: f32, bias: f32) -> Self {
        let nn = |v: f32| if v.is_finite() { v.max(0.0) } else { 0.0 };
        let unit = |v: f32| {
            if v.is_finite() {
                v.clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        Trapezoid::raw(
            if center.is_finite() { center } else { 0.0 },
            nn(core),
            nn(slope),
            unit(height),
            unit(bias),
        )
    }

    /// The set with exactly these values, unchecked (callers that computed them in range).
    #[inline(always)]
    pub const fn raw(center: f32, core: f32, slope: f32, height: f32, bias: f32) -> Self {
        Trapezoid {
            center,
            shape: CoreTrapezoid {
                core,
                slope,
                height,
                bias,
                rule: Self::BIAS_RULE,
            },
        }
    }

    /// Total ignorance about an angle: every heading fully possible.
    pub fn full_circle() -> Self {
        Trapezoid::raw(0.0, TAU, 0.0, 1.0, 1.0)
    }

    /// How the bias enters: `μ = max(b, h·f)`.
    pub const BIAS_RULE: BiasRule = BiasRule::Floor;

    /// Membership of a value on the real line (ranges). NaN gives the bias.
    #[inline]
    pub fn linear(&self, x: f32) -> f32 {
        self.shape.degree_at((x - self.center).abs())
    }

    /// Membership of an angle, measured the short way round the circle.
    #[inline]
    pub fn angular(&self, phi: f32) -> f32 {
        self.shape.degree_at(wrap_pi(phi - self.center).abs())
    }

    /// True when the set covers every heading at full height.
    pub fn is_full_circle(&self) -> bool {
        self.shape.core >= TAU
    }

    /// Half width of the level-`t` cut of the trapezoid part (t ≤ height);
    /// infinite when the cut covers the whole circle.
    #[inline]
    fn half_width_at(&self, t: f32) -> f32 {
        let w = 0.5 * self.shape.core
            + if self.shape.height > 0.0 {
                self.shape.slope * (1.0 - t / self.shape.height)
            } else {
                0.0
            };
        if w >= PI {
            f32::INFINITY
        } else {
            w
        }
    }

    /// Highest level at which the trapezoid parts of two angle sets overlap,
    /// `sup_φ min(h_A·ramp_A(φ), h_B·ramp_B(φ))`, with the short-way centre
    /// distance; 0 when their supports are disjoint.
    pub fn overlap_level(&self, other: &Trapezoid) -> f32 {
        let d = wrap_pi(other.center - self.center).abs();
        Self::overlap_level_at(self, other, d)
    }

    fn overlap_level_at(a: &Trapezoid, b: &Trapezoid, d: f32) -> f32 {
        let hmin = a.shape.height.min(b.shape.height);
        if hmin <= 0.0 {
            return 0.0;
        }
        let wa = a.half_width_at(0.0);
        let wb = b.half_width_at(0.0);
        if wa.is_infinite() || wb.is_infinite() {
            // One support covers the circle: the level is limited by where the
            // narrower set's cut still meets the wide one. For the circle-wide
            // set, the cut at level t covers the circle while its own half
            // width at t stays ≥ π.
            let lvl = |s: &Trapezoid| -> f32 {
                if s.half_width_at(s.shape.height).is_infinite() || s.shape.slope <= 0.0 {
                    s.shape.height
                } else {
                    // Solve Δ/2 + α(1 - t/h) = π for t.
                    (s.shape.height * (1.0 - (PI - 0.5 * s.shape.core) / s.shape.slope))
                        .clamp(0.0, s.shape.height)
                }
            };
            let la = if wa.is_infinite() {
                lvl(a)
            } else {
                a.shape.height
            };
            let lb = if wb.is_infinite() {
                lvl(b)
            } else {
                b.shape.height
            };
            // The other set's own height bounds the level too.
            return la.min(lb).min(hmin).max(0.0);
        }
        let reach = wa + wb - d;
        if reach < 0.0 {
            return 0.0;
        }
        let rate = a.shape.slope / a.shape.height + b.shape.slope / b.shape.height;
        let cores = 0.5 * (a.shape.core + b.shape.core) - d;
        if cores >= 0.0 {
            hmin
        } else if rate > 0.0 {
            (reach / rate).min(hmin).max(0.0)
        } else {
            0.0
        }
    }

    /// Possibility that the two angle sets describe the same heading,
    /// `sup_φ min(μ_A(φ), μ_B(φ))`, bias included.
    pub fn consistency(&self, other: &Trapezoid) -> f32 {
        let t = self.overlap_level(other);
        let bb = self.shape.bias.min(other.shape.bias);
        t.max(bb)
            .max(self.shape.bias.min(other.shape.height))
            .max(self.shape.height.min(other.shape.bias))
    }

    /// [`Trapezoid::intersect_angle`] and [`Trapezoid::consistency`] at once,
    /// sharing their common work (the grid calls both for every cell).
    pub fn intersect_with_consistency(&self, other: &Trapezoid) -> (Trapezoid, f32) {
        let d = wrap_pi(other.center - self.center);
        let t = Self::overlap_level_at(self, other, d.abs());
        let c = t
            .max(self.shape.bias.min(other.shape.bias))
            .max(self.shape.bias.min(other.shape.height))
            .max(self.shape.height.min(other.shape.bias));
        (self.intersect_at(other, d, t), c)
    }

    /// Paper 000's intersection of two angle sets (Fig. 4).
    ///
    /// * If the trapezoid parts overlap, the result is the inner trapezoidal
    ///   envelope of `min(A, B)`: height `t*` (the highest level where both cuts
    ///   meet), core = the meeting of the cuts at `t*`, support = the meeting of
    ///   the supports, and the *steeper* of the two resulting flanks on both
    ///   sides so that the symmetric trapezoid stays under `min(A, B)` (which is
    ///   concave on its support). Bias `b_C = b_A · b_B`.
    /// * If they do not overlap, the result is the outer trapezoidal envelope of
    ///   `max(A, B)` along the short arc joining them: its core spans both cores,
    ///   its flanks reach both supports (the *wider* flank on both sides), height
    ///   `max(h_A, h_B)`, and bias `1 − (1 − b_A)(1 − b_B)` — the paper only says
    ///   the bias must grow; the probabilistic sum is our reading of that.
    pub fn intersect_angle(&self, other: &Trapezoid) -> Trapezoid {
        let d = wrap_pi(other.center - self.center); // B sits at d in A's frame
        let t = Self::overlap_level_at(self, other, d.abs());
        self.intersect_at(other, d, t)
    }

    fn intersect_at(&self, other: &Trapezoid, d: f32, t: f32) -> Trapezoid {
        let a = self;
        let b = other;
        if t > 0.0 {
            let bias = a.shape.bias * b.shape.bias;
            let (ca_lo, ca_hi) = interval(0.0, a.half_width_at(t));
            let (cb_lo, cb_hi) = interval(d, b.half_width_at(t));
            let (sa_lo, sa_hi) = interval(0.0, a.half_width_at(0.0));
            let (sb_lo, sb_hi) = interval(d, b.half_width_at(0.0));
            let (core_lo, core_hi) = (ca_lo.max(cb_lo), ca_hi.min(cb_hi));
            let (sup_lo, sup_hi) = (sa_lo.max(sb_lo), sa_hi.min(sb_hi));
            if !(core_hi - core_lo).is_finite() {
                // Both cuts cover the circle: so does the intersection.
                return Trapezoid::new(
                    if a.is_full_circle() {
                        b.center
                    } else {
                        a.center
                    },
                    TAU,
                    0.0,
                    t,
                    bias,
                );
            }
            let core_hi = core_hi.max(core_lo); // rounding at a single point
            let flank = (core_lo - sup_lo).min(sup_hi - core_hi).max(0.0);
            let flank = if flank.is_finite() { flank } else { TAU };
            let center = wrap_pi(a.center + 0.5 * (core_lo + core_hi));
            Trapezoid::new(
                center,
                (core_hi - core_lo).min(TAU),
                flank.min(TAU),
                t,
                bias,
            )
        } else {
            let bias = 1.0 - (1.0 - a.shape.bias) * (1.0 - b.shape.bias);
            let wa = 0.5 * a.shape.core;
            let wb = 0.5 * b.shape.core;
            let core_lo = (-wa).min(d - wb);
            let core_hi = wa.max(d + wb);
            let sup_lo = (-wa - a.shape.slope).min(d - wb - b.shape.slope);
            let sup_hi = (wa + a.shape.slope).max(d + wb + b.shape.slope);
            let flank = (core_lo - sup_lo).max(sup_hi - core_hi).max(0.0);
            let center = wrap_pi(a.center + 0.5 * (core_lo + core_hi));
            Trapezoid::new(
                center,
                (core_hi - core_lo).min(TAU),
                flank.min(TAU),
                a.shape.height.max(b.shape.height),
                bias,
            )
        }
    }
}

#[inline]
fn interval(c: f32, half: f32) -> (f32, f32) {
    (c - half, c + half)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn membership_shape() {
        // core [0.9, 1.1], flanks to 0.8 / 1.2, bias 0.1.
        let t = Trapezoid::new(1.0, 0.2, 0.1, 1.0, 0.1);
        assert_eq!(t.linear(1.05), 1.0);
        assert!((t.linear(1.15) - 0.5).abs() < 1e-5);
        assert_eq!(t.linear(5.0), 0.1);
        assert_eq!(t.linear(f32::NAN), 0.1);
    }

    #[test]
    fn angular_wraps() {
        let t = Trapezoid::new(PI - 0.05, 0.2, 0.0, 1.0, 0.0);
        assert_eq!(t.angular(-PI + 0.02), 1.0); // 0.07 rad away across ±π
        assert_eq!(t.angular(0.0), 0.0);
    }

    #[test]
    fn intersection_across_pi_stays_there() {
        let a = Trapezoid::new(PI - 0.1, 0.2, 0.1, 1.0, 0.2);
        let b = Trapezoid::new(-PI + 0.1, 0.2, 0.1, 1.0, 0.5);
        // Cores [π-0.2, π] and [-π, -π+0.2] touch at π: core collapses to π.
        let c = a.intersect_angle(&b);
        assert!(wrap_pi(c.center - PI).abs() < 1e-5, "{c:?}");
        assert!((c.shape.height - 1.0).abs() < 1e-6);
        assert!((c.shape.bias - 0.1).abs() < 1e-6);
    }

    #[test]
    fn full_circle_is_neutral() {
        let a = Trapezoid::full_circle();
        let b = Trapezoid::new(3.0, 0.4, 0.2, 1.0, 0.3);
        let c = a.intersect_angle(&b);
        assert!((c.center - 3.0).abs() < 1e-5, "{c:?}");
        assert!((c.shape.core - 0.4).abs() < 1e-5);
        assert!((c.shape.slope - 0.2).abs() < 1e-5);
        assert!((c.shape.bias - 0.3).abs() < 1e-6);
        assert!((a.consistency(&b) - 1.0).abs() < 1e-6);
    }
}
