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
#[inline]
pub fn clamp_degree(x: f64) -> f64 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(0.0, 1.0)
    }
}
