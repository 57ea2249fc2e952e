//! Degrees and the possibilistic semantics of DESIGN §3: the fuzzy connectives a rule file may
//! choose ([`ops`]), the similarity that compares a measured value with a place's expectation
//! through paper 000's trapezoid ([`similarity`]), the possibility distribution over mutually exclusive places and
//! its necessities ([`possibility`]), sets of places and their Π and N ([`sets`]), and the
//! decision drawn from it ([`decision`]).
//!
//! This module depends on nothing but `core` (the trapezoid): it is plain arithmetic on `f64` degrees in
//! `[0, 1]`, where 1 means "fully supported". Paper 003 writes several percept degrees as
//! dissimilarities δ (0 = perfect match); lplace stores `1 − δ`, so the paper's `max` of
//! dissimilarities is our `min` of confidences.

pub mod decision;
pub mod ops;
pub mod possibility;
pub mod sets;
pub mod similarity;

pub use decision::{decide, Decision, DecisionParams, Disoriented, TIE_TOLERANCE};
pub use ops::{Fusion, Implication, LogicConfig, Normalisation, TNorm};
pub use possibility::PlaceDistribution;
pub use sets::PlaceSet;
pub use similarity::Similarity;

/// Clamps a degree into `[0, 1]`, mapping NaN to 0 (no support).
///
/// The engine calls this on every degree that comes from outside, so that a bad sensor value can
/// lower support but never produce NaN downstream.
///
/// Two comparisons, which a pass over every place's registers pays for twice per place: NaN
/// fails both (`NaN > 1` keeps it, `NaN >= 0` does not), and `−0` passes through as
/// `f64::clamp` passes it.
#[inline]
pub fn clamp_degree(x: f64) -> f64 {
    let below_one = if x > 1.0 { 1.0 } else { x };
    if below_one >= 0.0 {
        below_one
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::clamp_degree;

    #[test]
    fn clamping_is_nan_to_zero_then_the_standard_clamp_bit_for_bit() {
        let mut rng = crate::core::rng::SplitMix64::new(5);
        let special = [
            f64::NAN,
            -f64::NAN,
            0.0,
            -0.0,
            1.0,
            -1.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            1.0 + f64::EPSILON,
            1.0 - f64::EPSILON / 2.0,
            5e-324,
        ];
        let mut xs = special.to_vec();
        for _ in 0..10_000 {
            xs.push(f64::from_bits(rng.next_u64()));
            xs.push(rng.uniform(-0.5, 1.5));
        }
        for x in xs {
            let want = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
            assert_eq!(clamp_degree(x).to_bits(), want.to_bits(), "{x:e}");
        }
    }
}
