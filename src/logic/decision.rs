//! The decision drawn from a [`PlaceDistribution`]: a chosen place, or a typed *disoriented*
//! outcome with its reason — never a silent guess, never NaN (DESIGN §3).
//!
//! Let `b` be the place of highest necessity (ties: higher support, then lower index), `θ` the
//! threshold and `m` the margin. Then, in this order:
//! 1. `N_b ≥ θ` and `N_b − Inc > m` → [`Decision::Place`] `b`;
//! 2. `Inc ≥ θ` → [`Disoriented::Inconsistent`]: strong evidence for places that exclude each
//!    other drowns everything below `Inc`;
//! 3. `N_b ≥ θ` (so it failed only the margin over `Inc`) → [`Disoriented::TooClose`];
//! 4. no place has support `≥ θ` → [`Disoriented::NothingAboveThreshold`];
//! 5. otherwise → [`Disoriented::TooClose`]: a runner-up remains too possible.
//!
//! **Ties are exact up to [`TIE_TOLERANCE`].** The degrees compared with `θ` and `m` are
//! computed (`N = 1 − (1 − α)`, `N − Inc`), so a value that equals a stated threshold on paper
//! can land one rounding step below it: `1 − (1 − 0.1) = 0.09999999999999998`. Every comparison
//! above therefore reads "reaches `θ`" as `x ≥ θ − 10⁻⁹` and "exceeds `m`" as `x > m + 10⁻⁹`.
//! Degrees are sums of at most a few roundings of numbers in `[0, 1]` (errors near 10⁻¹⁶), and
//! thresholds are written with a few decimals, so no two degrees a rule file can tell apart are
//! merged by it.
//!
//! The runner-up reported is the place other than `b` with the highest normalised possibility;
//! with a single place, cases 3 and 5 report [`Disoriented::Inconsistent`] instead, since there is
//! no other place to be close to.

use super::possibility::{Peaks, PlaceDistribution};
use serde::{Deserialize, Serialize};

/// How far below a threshold (or above a margin) a computed degree may fall and still count as
/// meeting it (see the module docs).
pub const TIE_TOLERANCE: f64 = 1e-9;

/// `x ≥ θ`, up to the rounding of `x` ([`TIE_TOLERANCE`]).
#[inline]
pub fn reaches(x: f64, threshold: f64) -> bool {
    x >= threshold - TIE_TOLERANCE
}

/// `x > m`, where an `x` within [`TIE_TOLERANCE`] of `m` is a tie and does not exceed it.
#[inline]
pub fn exceeds(x: f64, margin: f64) -> bool {
    x > margin + TIE_TOLERANCE
}

/// Threshold and margin of the decision (from the rule file's `logic` block).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DecisionParams {
    /// Necessity a place needs.
    pub threshold: f64,
    /// How far the necessity must exceed the inconsistency.
    pub margin: f64,
}

/// Why no place was chosen.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum Disoriented {
    /// No place is supported up to the threshold.
    NothingAboveThreshold {
        /// The best place all the same.
        best: usize,
        /// Its support.
        support: f64,
    },
    /// The best place does not stand out enough from the runner-up.
    TooClose {
        /// The best place.
        best: usize,
        /// The place that stays too possible.
        runner_up: usize,
        /// The best place's necessity.
        necessity: f64,
    },
    /// The evidence contradicts itself too much.
    Inconsistent {
        /// `Inc`.
        inconsistency: f64,
    },
    /// The map has no places at all.
    NoPlaces,
}

/// The outcome of one step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
pub enum Decision {
    /// A place was chosen.
    Place {
        /// Its index in the map.
        place: usize,
        /// Its necessity.
        necessity: f64,
    },
    /// No place was chosen.
    Disoriented(Disoriented),
}

impl Decision {
    /// The chosen place, if any.
    pub fn place(&self) -> Option<usize> {
        match *self {
            Decision::Place { place, .. } => Some(place),
            Decision::Disoriented(_) => None,
        }
    }
}

/// The place `k ≠ skip` of highest `key[k]`, ties to the higher support, then to the lower
/// index; `start` when none beats it. The best pair is carried in locals rather than read back
/// by index at every comparison: one pass over the two columns, the same comparisons.
fn highest(key: &[f64], support: &[f64], start: usize, skip: usize) -> usize {
    let (Some(&k0), Some(&s0)) = (key.get(start), support.get(start)) else {
        return start;
    };
    let (mut best, mut bk, mut bs) = (start, k0, s0);
    for (k, (&kk, &sk)) in key.iter().zip(support).enumerate() {
        if k != skip && (kk > bk || (kk == bk && sk > bs)) {
            (best, bk, bs) = (k, kk, sk);
        }
    }
    best
}

/// Decides from an up-to-date distribution, as the module docs describe.
pub fn decide(d: &PlaceDistribution, p: DecisionParams) -> Decision {
    if d.is_empty() {
        return Decision::Disoriented(Disoriented::NoPlaces);
    }
    let best = highest(&d.necessity, &d.support, 0, usize::MAX);
    decide_from(d, p, best, || d.support.iter().copied().fold(0.0, f64::max))
}

/// [`decide`] for a distribution whose columns were written by
/// [`PlaceDistribution::finish_bounded`], which saw the extremes its searches look for.
pub(crate) fn decide_with_peaks(
    d: &PlaceDistribution,
    p: DecisionParams,
    peaks: Peaks,
) -> Decision {
    if d.is_empty() {
        return Decision::Disoriented(Disoriented::NoPlaces);
    }
    decide_from(d, p, peaks.most_necessary(), || peaks.max_support())
}

/// The decision, given the place of highest necessity `best` (ties: higher support, then lower
/// index) and the highest support (only compared with the threshold), over `n ≥ 1` places. The
/// cascade every decision shares; its callers differ in how they found `best`.
pub(crate) fn decide_from(
    d: &PlaceDistribution,
    p: DecisionParams,
    best: usize,
    max_support: impl FnOnce() -> f64,
) -> Decision {
    let n = d.len();
    let nb = d.necessity.get(best).copied().unwrap_or(0.0);
    let inc = d.inconsistency;
    if reaches(nb, p.threshold) && exceeds(nb - inc, p.margin) {
        return Decision::Place {
            place: best,
            necessity: nb,
        };
    }
    if reaches(inc, p.threshold) {
        return Decision::Disoriented(Disoriented::Inconsistent { inconsistency: inc });
    }
    if !reaches(nb, p.threshold) && !reaches(max_support(), p.threshold) {
        return Decision::Disoriented(Disoriented::NothingAboveThreshold {
            best,
            support: d.support.get(best).copied().unwrap_or(0.0),
        });
    }
    if n == 1 {
        // A lone place has nobody to be too close to: what held it back is the inconsistency.
        return Decision::Disoriented(Disoriented::Inconsistent { inconsistency: inc });
    }
    let runner_up = highest(&d.possibility, &d.support, usize::from(best == 0), best);
    Decision::Disoriented(Disoriented::TooClose {
        best,
        runner_up,
        necessity: nb,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::rng::SplitMix64;

    /// A value from a few levels (so that ties are common), now and then NaN.
    fn level(rng: &mut SplitMix64) -> f64 {
        match rng.below(6) {
            0 => f64::NAN,
            k => 0.25 * (k - 1) as f64,
        }
    }

    /// The search by index, as `decide` read it: `k` beats `b` on `key`, then on support.
    fn by_index(key: &[f64], sup: &[f64], start: usize, skip: usize) -> usize {
        let better = |a: usize, b: usize| key[a] > key[b] || (key[a] == key[b] && sup[a] > sup[b]);
        let mut best = start;
        for k in 0..key.len() {
            if k != skip && better(k, best) {
                best = k;
            }
        }
        best
    }

    #[test]
    fn the_one_pass_search_picks_what_the_search_by_index_picks() {
        let mut rng = SplitMix64::new(7);
        for _ in 0..2000 {
            let n = 1 + rng.below(12);
            let key: Vec<f64> = (0..n).map(|_| level(&mut rng)).collect();
            let sup: Vec<f64> = (0..n).map(|_| level(&mut rng)).collect();
            let (start, skip) = (rng.below(n), rng.below(n + 1));
            let want = by_index(&key, &sup, start, skip);
            assert_eq!(highest(&key, &sup, start, skip), want, "{key:?} {sup:?}");
        }
    }
}
