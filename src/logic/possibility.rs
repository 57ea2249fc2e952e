//! The possibility distribution over mutually exclusive places, built from per-place supports
//! (DESIGN §3).
//!
//! Each place `k` has a support `α_k` (the degree derived for `at_place(P_k)`) and an exclusion
//! `β_k` (the degree derived for `!at_place(P_k)`). In possibilistic logic `(at_place(P_j), α_j)`
//! means `N(at_place(P_j)) ≥ α_j`; since places exclude each other, it rules out every world
//! `k ≠ j` to degree `α_j`, and `(¬at_place(P_k), β_k)` rules out world `k` to degree `β_k`. The
//! least specific distribution compatible with all of them is
//!
//! ```text
//! π_k  = min( min_{j≠k} (1 − α_j), 1 − β_k )
//! h    = max_k π_k                     (height)
//! Inc  = 1 − h                         (inconsistency degree of the base)
//! π'_k = 1 if π_k = h, else π_k        (min-based normalisation)
//! π'_k = π_k / h                       (product-based normalisation; all 1 when h = 0)
//! Π_k  = π'_k
//! N_k  = 1 − max_{j≠k} π'_j
//! ```
//!
//! Every quantity is computed in `O(n)` with two running extremes, into buffers allocated once.
//!
//! Beyond single places, [`PlaceDistribution::update`] is three steps that the engine can
//! interleave with more evidence: [`PlaceDistribution::fill_raw`] (the formula above),
//! then any of
//! - [`PlaceDistribution::constrain`]: a weighted head over a set of places, `(S, α)`, lowers each
//!   world outside `S` to `1 − α`; a negated one, `(¬S, β)`, each world inside `S` to `1 − β`;
//! - [`PlaceDistribution::fuse`]: the unnormalised distribution of another evidence group,
//!   combined world by world by min or product ([`Fusion`]);
//! - [`PlaceDistribution::condition`]: the region `A` is known from outside, so every world
//!   outside `A` becomes impossible; the normalisation that follows is then min-based
//!   (`π(k | A) = 1` where `π_k = Π(A)`, else `π_k`) or product-based (`π_k / Π(A)`)
//!   conditioning, and `Inc = 1 − Π(A)` says how far the evidence disagrees with the region;
//!
//! and finally [`PlaceDistribution::finish`] (height, Inc, normalisation, N).

use super::ops::{Fusion, Normalisation};
use super::sets::PlaceSet;
use serde::{Deserialize, Serialize};

/// Supports, possibilities and necessities of `n` mutually exclusive places.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlaceDistribution {
    /// `α_k`: support for `at_place(P_k)`.
    pub support: Vec<f64>,
    /// `β_k`: support for `!at_place(P_k)`.
    pub exclusion: Vec<f64>,
    /// `π_k` before normalisation.
    pub possibility_raw: Vec<f64>,
    /// `Π_k = π'_k`, after normalisation.
    pub possibility: Vec<f64>,
    /// `N_k`.
    pub necessity: Vec<f64>,
    /// `h = max π`.
    pub height: f64,
    /// `Inc = 1 − h`.
    pub inconsistency: f64,
}

/// Index and value of the largest and the index-excluding second largest entries.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Top2 {
    pub(crate) best: usize,
    pub(crate) first: f64,
    pub(crate) second: f64,
}

impl Top2 {
    /// Nothing seen yet.
    pub(crate) const EMPTY: Top2 = Top2 {
        best: usize::MAX,
        first: f64::NEG_INFINITY,
        second: f64::NEG_INFINITY,
    };

    /// Over `values`, with `f` mapping each entry; ties keep the lowest index as `best`.
    fn max_of(values: &[f64], f: impl Fn(f64) -> f64) -> Top2 {
        let mut t = Top2::EMPTY;
        for (k, &v) in values.iter().enumerate() {
            t.push(k, f(v));
        }
        t
    }

    /// Entry `k` of value `v`; entries pushed in ascending `k` keep the lowest index on ties.
    #[inline]
    pub(crate) fn push(&mut self, k: usize, v: f64) {
        if v > self.first {
            self.second = self.first;
            self.first = v;
            self.best = k;
        } else if v > self.second {
            self.second = v;
        }
    }

    /// `1 − max(0, max_{j≠k} v_j)` for every `k` but `best`, and for `best` (an empty max read
    /// as 0): the complement a place's "all the others" takes, computed once per pass.
    #[inline]
    pub(crate) fn complements(&self) -> (f64, f64) {
        (1.0 - self.first.max(0.0), 1.0 - self.second.max(0.0))
    }
}

/// The extremes [`PlaceDistribution::finish_bounded`] saw while writing the columns: enough to
/// answer the decision's searches over every place without another pass.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Peaks {
    /// Of `support`.
    pub(crate) support: Top2,
    /// Of `possibility` (`π'`).
    pub(crate) possibility: Top2,
}

impl Peaks {
    /// The place of highest necessity, ties to the higher support, then to the lower index
    /// (what `decide` searches for). Every necessity is `1 − max π'` but the most possible
    /// place's, `1 − second π'`, which is at least as high: that place when it is higher, else
    /// all are equal and the support decides — the first place of highest support.
    pub(crate) fn most_necessary(&self) -> usize {
        let (all, but_best) = self.possibility.complements();
        if but_best > all {
            self.possibility.best
        } else {
            self.support.best
        }
    }

    /// The highest support, or 0 (`max(0, max_k α_k)`).
    pub(crate) fn max_support(&self) -> f64 {
        self.support.first.max(0.0)
    }
}

impl PlaceDistribution {
    /// A distribution over `n` places with no evidence yet (all supports 0).
    pub fn new(n: usize) -> Self {
        let mut d = PlaceDistribution {
            support: vec![0.0; n],
            exclusion: vec![0.0; n],
            possibility_raw: vec![1.0; n],
            possibility: vec![1.0; n],
            necessity: vec![0.0; n],
            height: 1.0,
            inconsistency: 0.0,
        };
        d.update(Normalisation::Min);
        d
    }

    /// Number of places.
    pub fn len(&self) -> usize {
        self.support.len()
    }

    /// True when there are no places.
    pub fn is_empty(&self) -> bool {
        self.support.is_empty()
    }

    /// Recomputes π, h, Inc, Π and N from `support` and `exclusion`, without allocating.
    ///
    /// With no places at all the height is 0 and the inconsistency 1: nothing is possible.
    pub fn update(&mut self, normalisation: Normalisation) {
        self.fill_raw();
        self.finish(normalisation);
    }

    /// Fills `possibility_raw` from `support` and `exclusion` (the module's formula for `π_k`).
    pub fn fill_raw(&mut self) {
        let n = self.support.len();
        // min_{j≠k}(1 − α_j) = 1 − max_{j≠k} α_j; an empty min is 1.
        let sup = Top2::max_of(&self.support, |a| a);
        let (all, but_best) = sup.complements();
        for k in 0..n {
            let others = if k == sup.best { but_best } else { all };
            let beta = self.exclusion.get(k).copied().unwrap_or(0.0);
            self.possibility_raw[k] = others.min(1.0 - beta);
        }
    }

    /// The weighted head `(S, degree)` (or `(¬S, degree)` when `negated`): every world that
    /// falsifies it is lowered to at most `1 − degree`.
    pub fn constrain(&mut self, set: &PlaceSet, degree: f64, negated: bool) {
        let cap = 1.0 - degree;
        for (k, p) in self.possibility_raw.iter_mut().enumerate() {
            if set.contains(k) == negated {
                *p = p.min(cap);
            }
        }
    }

    /// Combines `possibility_raw` world by world with another group's unnormalised
    /// distribution `other` (missing entries read as 1, which changes nothing).
    pub fn fuse(&mut self, other: &[f64], fusion: Fusion) {
        for (k, p) in self.possibility_raw.iter_mut().enumerate() {
            *p = fusion.apply(*p, other.get(k).copied().unwrap_or(1.0));
        }
    }

    /// Conditions on the region `known`: every world outside it becomes impossible. The
    /// normalisation in [`Self::finish`] then makes this min- or product-based conditioning.
    pub fn condition(&mut self, known: &PlaceSet) {
        for (k, p) in self.possibility_raw.iter_mut().enumerate() {
            if !known.contains(k) {
                *p = 0.0;
            }
        }
    }

    /// Computes the height, `Inc`, `Π` and `N` from `possibility_raw`.
    pub fn finish(&mut self, normalisation: Normalisation) {
        let h = self.possibility_raw.iter().copied().fold(0.0, f64::max);
        self.height = h;
        self.inconsistency = 1.0 - h;
        self.normalise(normalisation);
    }

    /// `Π(S)` under the normalised distribution.
    pub fn set_possibility(&self, set: &PlaceSet) -> f64 {
        set.possibility(&self.possibility)
    }

    /// `N(S)` under the normalised distribution.
    pub fn set_necessity(&self, set: &PlaceSet) -> f64 {
        set.necessity(&self.possibility)
    }

    /// Computes `Π = π'` and `N` from `possibility_raw` (whatever filled it: [`Self::update`], or a
    /// tracker that intersected it with a carried belief), normalising by the height of
    /// `possibility_raw` itself. Leaves `height` and `inconsistency` to the caller.
    pub fn normalise(&mut self, normalisation: Normalisation) {
        let h = self.possibility_raw.iter().copied().fold(0.0, f64::max);
        let pairs = self.possibility.iter_mut().zip(&self.possibility_raw);
        // One loop per case, so that each is a plain pass over the columns.
        if h <= 0.0 {
            // Nothing is possible: total ignorance rather than 0/0.
            pairs.for_each(|(p, _)| *p = 1.0);
        } else {
            match normalisation {
                Normalisation::Min => {
                    pairs.for_each(|(p, &raw)| *p = if raw >= h { 1.0 } else { raw })
                }
                Normalisation::Product => pairs.for_each(|(p, &raw)| *p = (raw / h).min(1.0)),
            }
        }
        let pos = Top2::max_of(&self.possibility, |p| p);
        self.fill_necessity(pos);
    }

    /// `N` from the extremes of `π'`: `1 − max π'` everywhere but at the most possible place.
    pub(crate) fn fill_necessity(&mut self, pos: Top2) {
        // An empty max is 0: a lone place is certain.
        let (all, but_best) = pos.complements();
        self.necessity.fill(all);
        if let Some(nk) = self.necessity.get_mut(pos.best) {
            *nk = but_best;
        }
    }

    /// [`Self::fill_raw`] and [`Self::finish`] in one pass over the places, for a caller that
    /// has already written `support` and `exclusion`, and in `possibility_raw` each place's
    /// bound from its own evidence, `t_k = min(1 − β_k, caps of the set heads on k)`; `sup`
    /// holds the extremes of `support` (pushed in place order) and `t_max = max_k t_k`.
    ///
    /// `π_k = min(o_k, t_k)` with `o_k` the complement of the other supports, which is one
    /// value `o` for every place but the most supported one `b`, whose `o_b ≥ o`. So the
    /// height `max_k π_k` is `max(min(o, t_max), min(o_b, t_b))` (`min(o_b, t_b)` covers the
    /// term `min(o, t_b)` it bounds), known before the pass that writes `π`, `π'` and their
    /// extremes. `min` and `max` are exact and the degrees are never NaN nor `−0` here (clamped
    /// supports, `1 − x` of degrees in `[0, 1]`), so every column holds the bits the separate
    /// passes write.
    pub(crate) fn finish_bounded(
        &mut self,
        sup: Top2,
        t_max: f64,
        normalisation: Normalisation,
    ) -> Peaks {
        let (all, but_best) = sup.complements();
        let mut h = all.min(t_max).max(0.0);
        if let Some(&t) = self.possibility_raw.get(sup.best) {
            h = h.max(but_best.min(t));
        }
        self.height = h;
        self.inconsistency = 1.0 - h;
        let (raw, pi) = (&mut self.possibility_raw, &mut self.possibility);
        let o = (sup.best, all, but_best);
        // One loop per case, so that each is a plain pass over the columns.
        let pos = if h <= 0.0 {
            bounded_pass(raw, pi, o, |_| 1.0)
        } else {
            match normalisation {
                Normalisation::Min => bounded_pass(raw, pi, o, |r| if r >= h { 1.0 } else { r }),
                Normalisation::Product => bounded_pass(raw, pi, o, |r| lower(r / h, 1.0)),
            }
        };
        self.fill_necessity(pos);
        Peaks {
            support: sup,
            possibility: pos,
        }
    }
}

/// `min(a, b)` of operands that are never NaN (nor `−0` beside `+0`): the value `f64::min`
/// gives, without the NaN handling it pays on every call in a pass over the places.
#[inline]
pub(crate) fn lower(a: f64, b: f64) -> f64 {
    if b < a {
        b
    } else {
        a
    }
}

/// `max(a, b)` of operands that are never NaN (nor `−0` beside `+0`), as [`lower`].
#[inline]
pub(crate) fn higher(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// `π_k = min(o_k, t_k)` into `raw` (which holds `t`), `π'_k = norm(π_k)` into `pi`, and the
/// extremes of `π'`; `o_k` is `o.2` at place `o.0`, `o.1` elsewhere.
#[inline]
fn bounded_pass(
    raw: &mut [f64],
    pi: &mut [f64],
    (b, all, but_best): (usize, f64, f64),
    norm: impl Fn(f64) -> f64,
) -> Top2 {
    let mut pos = Top2::EMPTY;
    for (k, (t, p)) in raw.iter_mut().zip(pi).enumerate() {
        let r = lower(if k == b { but_best } else { all }, *t);
        *t = r;
        *p = norm(r);
        pos.push(k, *p);
    }
    pos
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dist(alpha: &[f64], beta: &[f64], norm: Normalisation) -> PlaceDistribution {
        let mut d = PlaceDistribution::new(alpha.len());
        d.support.copy_from_slice(alpha);
        d.exclusion.copy_from_slice(beta);
        d.update(norm);
        d
    }

    #[test]
    fn two_supported_places_hand_worked() {
        // α = (0.8, 0.5, 0): π_0 = min(1−0.5, 1−0) = 0.5, π_1 = 1−0.8 = 0.2, π_2 = 0.2.
        // h = 0.5, Inc = 0.5. Min-based: π' = (1, 0.2, 0.2) → N_0 = 0.8, N_1 = N_2 = 0.
        let d = dist(&[0.8, 0.5, 0.0], &[0.0; 3], Normalisation::Min);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert!(close(d.possibility_raw[0], 0.5) && close(d.possibility_raw[1], 0.2));
        assert!(close(d.inconsistency, 0.5));
        assert!(close(d.necessity[0], 0.8) && close(d.necessity[1], 0.0));
        // Product-based: π' = (1, 0.4, 0.4) → N_0 = 0.6.
        let d = dist(&[0.8, 0.5, 0.0], &[0.0; 3], Normalisation::Product);
        assert!(close(d.necessity[0], 0.6));
    }

    #[test]
    fn lone_place_and_no_place() {
        let d = dist(&[0.0], &[0.3], Normalisation::Min);
        // π_0 = min(1 (empty min), 0.7) = 0.7 → normalised to 1; N_0 = 1 − max(∅) = 1.
        assert_eq!(d.necessity[0], 1.0);
        let d = dist(&[], &[], Normalisation::Min);
        assert_eq!(d.inconsistency, 1.0);
    }

    /// `π'` and `N` as the module's formulas read, place by place.
    fn by_definition(raw: &[f64], norm: Normalisation) -> (Vec<f64>, Vec<f64>) {
        let h = raw.iter().copied().fold(0.0, f64::max);
        let pi: Vec<f64> = raw
            .iter()
            .map(|&r| match norm {
                _ if h <= 0.0 => 1.0,
                Normalisation::Min if r >= h => 1.0,
                Normalisation::Min => r,
                Normalisation::Product => (r / h).min(1.0),
            })
            .collect();
        let nec = (0..pi.len())
            .map(|k| {
                let others = pi.iter().enumerate().filter(|&(j, _)| j != k);
                1.0 - others.map(|(_, &p)| p).fold(0.0, f64::max)
            })
            .collect();
        (pi, nec)
    }

    #[test]
    fn normalising_gives_the_formulas_place_by_place() {
        let mut rng = crate::core::rng::SplitMix64::new(11);
        for case in 0..2000 {
            let n = rng.below(8);
            let norm = [Normalisation::Min, Normalisation::Product][rng.below(2)];
            let mut d = PlaceDistribution::new(n);
            for r in &mut d.possibility_raw {
                *r = match rng.below(5) {
                    0 => f64::NAN,
                    1 => 0.0,
                    2 => 0.5,
                    _ => rng.unit(),
                };
            }
            d.normalise(norm);
            let (pi, nec) = by_definition(&d.possibility_raw, norm);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&d.possibility), bits(&pi), "case {case}");
            assert_eq!(bits(&d.necessity), bits(&nec), "case {case}");
        }
    }
}
