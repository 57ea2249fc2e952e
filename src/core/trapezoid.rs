//! Paper 000's trapezoidal fuzzy set ⟨θ, Δ, α, h, b⟩ (Buschka, Saffiotti & Wasik, Fig. 2): the
//! one statement of its shape and of how its bias enters, which both trapezoid types of the
//! crate — the rule engine's `logic::Trapezoid` (f64, degrees or metres, the centre
//! given per comparison) and the grid's `grid::Trapezoid` (f32, radians, with the
//! paper's angle-set intersection) — evaluate through.
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
//! flank. The crate uses both readings, each named by a [`BiasRule`]:
//!
//! * [`BiasRule::Floor`], `μ = max(b, h·f)`: the bias is a floor under the trapezoid (the grid:
//!   an outlier keeps `b`; the paper's intersection of angle sets, `b_C = b_A·b_B`, treats the
//!   bias as a separate uniform part in the same way).
//! * [`BiasRule::Lifted`], `μ = b + (h − b)·f`: the trapezoid stands on the bias, as Fig. 2 draws
//!   it (the rule engine's similarities).
//!
//! They agree on the core and outside the support and differ only on the flank (core 2, slope 2,
//! h 1, b 0.1 at distance 2: 0.50 against 0.55). Depends on nothing.
//!
//! # Complexity
//!
//! O(1).

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
    pub fn apply_f64(self, f: f64, h: f64, b: f64) -> f64 {
        match self {
            BiasRule::Floor => (h * f).max(b),
            BiasRule::Lifted => b + (h - b) * f,
        }
    }

    /// [`BiasRule::apply_f64`] in single precision (the grid's).
    #[inline(always)]
    pub fn apply_f32(self, f: f32, h: f32, b: f32) -> f32 {
        match self {
            BiasRule::Floor => (h * f).max(b),
            BiasRule::Lifted => b + (h - b) * f,
        }
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
        assert!((BiasRule::Floor.apply_f64(fm, 1.0, 0.1) - 0.5).abs() < 1e-12);
        assert!((BiasRule::Lifted.apply_f64(fm, 1.0, 0.1) - 0.55).abs() < 1e-12);
        assert!((BiasRule::Lifted.apply_f32(fm as f32, 1.0, 0.1) - 0.55).abs() < 1e-6);
        // Core (h) and outside the support (b): both readings give the paper's values.
        for rule in [BiasRule::Floor, BiasRule::Lifted] {
            assert_eq!(rule.apply_f64(f(0.7, 2.0, 2.0), 0.9, 0.1), 0.9);
            assert_eq!(rule.apply_f64(f(3.5, 2.0, 2.0), 0.9, 0.1), 0.1);
        }
    }

    #[test]
    fn both_stay_between_bias_and_height_and_floor_is_below_lifted() {
        for hi in 0..=10 {
            for bi in 0..=hi {
                for fi in 0..=20 {
                    let (h, b, fv) = (hi as f64 / 10.0, bi as f64 / 10.0, fi as f64 / 20.0);
                    let lo = BiasRule::Floor.apply_f64(fv, h, b);
                    let up = BiasRule::Lifted.apply_f64(fv, h, b);
                    assert!(lo >= b - 1e-12 && lo <= h + 1e-12, "{h} {b} {fv}");
                    assert!(up >= b - 1e-12 && up <= h + 1e-12, "{h} {b} {fv}");
                    assert!(lo <= up + 1e-12, "{h} {b} {fv}: {lo} > {up}");
                }
            }
        }
    }
}
