//! Paper 000's trapezoidal fuzzy set ⟨θ, Δ, α, h, b⟩ (Buschka, Saffiotti & Wasik, Fig. 2): the
//! one [`Trapezoid`] of the crate — its shape `f`, its membership `μ` and how the bias enters —
//! in single or double precision ([`Real`]). Its users only say where the distance comes from:
//! the rule engine's `logic::Similarity` (f64, degrees or metres, the centre given per
//! comparison, circular with a period, ranges) and the grid's `grid::Trapezoid` (f32, radians, a
//! centre of its own, the paper's angle-set intersection).
//!
//! The paper: "the top of the trapezoid (core) identifies those values which are fully
//! possible … the base (support) the area where we could still possibly have meaningful values
//! … we include a small uniform bias b, representing the degree of possibility that the actual
//! angle is 'somewhere else'". With `d` the distance of a value from θ,
//!
//! ```text
//!   f(d) = 1                         d ≤ Δ/2          (the core)
//!        = 1 − (d − Δ/2)/α           Δ/2 < d < Δ/2 + α (the flank; α is its run)
//!        = 0                         otherwise        (outside the support)
//! ```
//!
//! The text fixes `μ = h` on the core and `μ = b` outside the support, not how the bias meets the
//! flank. The crate uses both readings, each an explicit [`BiasRule`] of the trapezoid:
//!
//! * [`BiasRule::Floor`], `μ = max(b, h·f)`: the bias is a floor under the trapezoid (the grid:
//!   an outlier keeps `b`; the paper's intersection of angle sets, `b_C = b_A·b_B`, treats the
//!   bias as a separate uniform part in the same way).
//! * [`BiasRule::Lifted`], `μ = b + (h − b)·f`: the trapezoid stands on the bias, as Fig. 2 draws
//!   it (the rule engine's similarities).
//!
//! They agree on the core and outside the support and differ only on the flank (core 2, slope 2,
//! h 1, b 0.1 at distance 2: 0.50 against 0.55). Each rule also keeps the one way its users have
//! always rounded the flank's end, so that results stay bit for bit what they were: `Floor` ends
//! the flank at the support's edge (`f = 0` from `d ≥ Δ/2 + α` on), `Lifted` clamps it
//! (`f = max(0, 1 − (d − Δ/2)/α)`). The two differ only where `Δ/2 + α` and `d − Δ/2` round
//! differently, by a few ulps of `f`. A NaN distance gives `f = 0`, hence `μ = b`, under both.
//! Depends on nothing.
//!
//! # Complexity
//!
//! O(1).

use std::ops::{Add, Div, Mul, Sub};

/// The two precisions a [`Trapezoid`] is evaluated in (`f32` in the grid, `f64` in the rule
/// engine); sealed, since the shape's rounding is stated for these two only.
pub trait Real:
    Copy
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + sealed::Sealed
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// ½.
    const HALF: Self;
    /// The larger of two values; a NaN loses (`f32::max` / `f64::max`).
    fn max(self, other: Self) -> Self;
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

impl Real for f32 {
    const ZERO: f32 = 0.0;
    const ONE: f32 = 1.0;
    const HALF: f32 = 0.5;
    #[inline(always)]
    fn max(self, other: f32) -> f32 {
        f32::max(self, other)
    }
}

impl Real for f64 {
    const ZERO: f64 = 0.0;
    const ONE: f64 = 1.0;
    const HALF: f64 = 0.5;
    #[inline(always)]
    fn max(self, other: f64) -> f64 {
        f64::max(self, other)
    }
}

/// How the bias `b` combines with the trapezoid part `f ∈ [0, 1]` of height `h` (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BiasRule {
    /// `μ = max(b, h·f)`: a uniform floor under the trapezoid.
    Floor,
    /// `μ = b + (h − b)·f`: the trapezoid standing on the bias.
    Lifted,
}

impl BiasRule {
    /// `μ` for the trapezoid part `f` (the flank value, 1 on the core, 0 outside the support).
    #[inline(always)]
    pub fn apply<F: Real>(self, f: F, h: F, b: F) -> F {
        match self {
            BiasRule::Floor => (h * f).max(b),
            BiasRule::Lifted => b + (h - b) * f,
        }
    }
}

/// Paper 000's trapezoid `⟨Δ, α, h, b⟩` around a centre its user measures distances from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trapezoid<F> {
    /// Δ: full width of the core (the fully possible values).
    pub core: F,
    /// α: run of each flank (membership falls from `h` to the bias over it); 0 = crisp edges.
    pub slope: F,
    /// h: height, in `[0, 1]`.
    pub height: F,
    /// b: the possibility that the reading is an outlier, in `[0, 1]`.
    pub bias: F,
    /// How the bias enters.
    pub rule: BiasRule,
}

impl<F: Real> Trapezoid<F> {
    /// The trapezoid part's shape `f` at a distance `d ≥ 0` from the centre: 1 on the core,
    /// falling to 0 over the flank (ended as the [`BiasRule`] ends it, see the module docs), 0
    /// outside the support and for a NaN `d`.
    #[inline(always)]
    pub fn shape(&self, d: F) -> F {
        let half = F::HALF * self.core;
        if d <= half {
            F::ONE
        } else if self.slope > F::ZERO {
            match self.rule {
                BiasRule::Floor if d < half + self.slope => F::ONE - (d - half) / self.slope,
                BiasRule::Floor => F::ZERO,
                BiasRule::Lifted => (F::ONE - (d - half) / self.slope).max(F::ZERO),
            }
        } else {
            F::ZERO // also a NaN slope, as a crisp edge
        }
    }

    /// `μ` at a distance `d ≥ 0` from the centre: [`Trapezoid::shape`] with the bias entering by
    /// the trapezoid's [`BiasRule`]. A NaN distance gives the bias.
    #[inline(always)]
    pub fn degree_at(&self, d: F) -> F {
        self.rule.apply(self.shape(d), self.height, self.bias)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's f(d) written out independently, for the hand-worked values below.
    fn f(d: f64, core: f64, slope: f64) -> f64 {
        let half = core / 2.0;
        if d <= half {
            1.0
        } else if d >= half + slope {
            0.0
        } else {
            (half + slope - d) / slope
        }
    }

    #[test]
    fn the_two_readings_on_the_papers_shape() {
        // ⟨θ = 0, Δ = 2, α = 2, h = 1, b = 0.1⟩ at d = 2: half way down the flank, f = 0.5.
        let fm = f(2.0, 2.0, 2.0);
        assert_eq!(fm, 0.5);
        assert!((BiasRule::Floor.apply(fm, 1.0, 0.1) - 0.5).abs() < 1e-12);
        assert!((BiasRule::Lifted.apply(fm, 1.0, 0.1) - 0.55).abs() < 1e-12);
        assert!((BiasRule::Lifted.apply(fm as f32, 1.0, 0.1) - 0.55).abs() < 1e-6);
        // Core (h) and outside the support (b): both readings give the paper's values.
        for rule in [BiasRule::Floor, BiasRule::Lifted] {
            assert_eq!(rule.apply(f(0.7, 2.0, 2.0), 0.9, 0.1), 0.9);
            assert_eq!(rule.apply(f(3.5, 2.0, 2.0), 0.9, 0.1), 0.1);
        }
    }

    #[test]
    fn the_type_gives_the_papers_values_in_both_precisions_under_both_rules() {
        for rule in [BiasRule::Floor, BiasRule::Lifted] {
            let t = Trapezoid {
                core: 2.0,
                slope: 2.0,
                height: 0.9,
                bias: 0.1,
                rule,
            };
            let t32 = Trapezoid {
                core: 2.0f32,
                slope: 2.0,
                height: 0.9,
                bias: 0.1,
                rule,
            };
            for d in [0.0, 0.7, 1.0, 1.5, 2.0, 2.5, 2.999, 3.0, 3.5, 100.0] {
                let want = rule.apply(f(d, 2.0, 2.0), 0.9, 0.1);
                assert!((t.degree_at(d) - want).abs() < 1e-12, "{rule:?} {d}");
                assert!(
                    (f64::from(t32.degree_at(d as f32)) - want).abs() < 1e-6,
                    "{rule:?} {d}"
                );
            }
            // Unmeasurable: the bias, as for an outlier.
            assert_eq!(t.degree_at(f64::NAN), 0.1);
            assert_eq!(t32.degree_at(f32::NAN), 0.1);
            // A crisp trapezoid (α = 0): h on the core, b off it.
            let crisp = Trapezoid { slope: 0.0, ..t };
            assert_eq!(crisp.degree_at(1.0), 0.9);
            assert_eq!(crisp.degree_at(1.0 + 1e-9), 0.1);
        }
        // The flank under each rule at the paper's Fig. 2 point (core 2, slope 2, h 1, b 0.1, d 2).
        let floor = Trapezoid {
            core: 2.0f64,
            slope: 2.0,
            height: 1.0,
            bias: 0.1,
            rule: BiasRule::Floor,
        };
        let lifted = Trapezoid {
            rule: BiasRule::Lifted,
            ..floor
        };
        assert!((floor.degree_at(2.0) - 0.5).abs() < 1e-12);
        assert!((lifted.degree_at(2.0) - 0.55).abs() < 1e-12);
    }

    #[test]
    fn both_stay_between_bias_and_height_and_floor_is_below_lifted() {
        for hi in 0..=10 {
            for bi in 0..=hi {
                for fi in 0..=20 {
                    let (h, b, fv) = (hi as f64 / 10.0, bi as f64 / 10.0, fi as f64 / 20.0);
                    let lo = BiasRule::Floor.apply(fv, h, b);
                    let up = BiasRule::Lifted.apply(fv, h, b);
                    assert!(lo >= b - 1e-12 && lo <= h + 1e-12, "{h} {b} {fv}");
                    assert!(up >= b - 1e-12 && up <= h + 1e-12, "{h} {b} {fv}");
                    assert!(lo <= up + 1e-12, "{h} {b} {fv}: {lo} > {up}");
                }
            }
        }
    }
}
