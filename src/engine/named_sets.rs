//! The named sets of places (rooms, regions) in each step — their heads applied to the raw
//! distribution, their Π and N read after it — in time that grows with the sets' sizes rather
//! than with `sets × places` (issue 16: a 10,000-place map has 2,500 rooms).
//!
//! `Π(S) = max_{k ∈ S} π_k` reads the members only. `N(S) = 1 − max_{k ∉ S} π_k` reads the
//! `K` highest places of the step (`K` one more than the largest small set): the first of them
//! outside `S` is the highest place outside `S`. Sets larger than [`SMALL`] are scanned whole.
//! Both select a maximum, so the results are exactly [`PlaceSet::possibility`] and
//! [`PlaceSet::necessity`] (NaNs ignored, as `f64::max` does there). `update` allocates nothing.

use super::compile::SetHead;
use crate::logic::{clamp_degree, PlaceDistribution, PlaceSet};

/// Largest set whose necessity is read from the top places.
const SMALL: usize = 32;

/// The named sets with their members listed, and a buffer for the top places.
#[derive(Debug, Clone)]
pub(super) struct NamedSets {
    sets: Vec<PlaceSet>,
    members: Vec<Vec<usize>>,
    /// The `k` highest `(π, place)` of the step, highest first.
    top: Vec<(f64, usize)>,
    k: usize,
}

/// Support (from the rules), Π and N of each named set, in its declaration order.
#[derive(Debug)]
pub(super) struct Targets<'a> {
    pub support: &'a mut [f64],
    pub possibility: &'a mut [f64],
    pub necessity: &'a mut [f64],
}

impl NamedSets {
    pub(super) fn new(sets: Vec<PlaceSet>) -> NamedSets {
        let members: Vec<Vec<usize>> = sets.iter().map(|s| s.indices().collect()).collect();
        let k = members
            .iter()
            .map(Vec::len)
            .filter(|&m| m <= SMALL)
            .max()
            .map_or(0, |m| m + 1);
        NamedSets {
            sets,
            members,
            top: Vec::with_capacity(k + 1),
            k,
        }
    }

    /// Fills `out` from `dist` (normalised) and the support registers `regs[support[i]]`.
    pub(super) fn update(
        &mut self,
        dist: &PlaceDistribution,
        regs: &[f64],
        support: &[u32],
        out: Targets<'_>,
    ) {
        let pi = &dist.possibility;
        self.fill_top(pi);
        let sets = self.sets.iter().zip(&self.members).enumerate();
        for (i, (set, members)) in sets {
            let reg = support.get(i).copied().unwrap_or(u32::MAX);
            let s = clamp_degree(regs.get(reg as usize).copied().unwrap_or(0.0));
            let p = members
                .iter()
                .filter_map(|&k| pi.get(k).copied())
                .fold(0.0, f64::max);
            let n = if members.len() <= SMALL {
                let outside = self.top.iter().find(|&&(_, k)| !set.contains(k));
                1.0 - outside.map_or(0.0, |&(v, _)| v)
            } else {
                set.necessity(pi)
            };
            if let (Some(a), Some(b), Some(c)) = (
                out.support.get_mut(i),
                out.possibility.get_mut(i),
                out.necessity.get_mut(i),
            ) {
                (*a, *b, *c) = (s, p, n);
            }
        }
    }

    /// The `k` highest places, highest first (ties in any order: only the values are read);
    /// NaN places are left out, as `f64::max` leaves them out of a maximum.
    fn fill_top(&mut self, pi: &[f64]) {
        self.top.clear();
        if self.k == 0 {
            return;
        }
        for (j, &v) in pi.iter().enumerate() {
            if v.is_nan() || (self.top.len() == self.k && self.top[self.k - 1].0 >= v) {
                continue;
            }
            let at = self.top.partition_point(|&(w, _)| w >= v);
            self.top.insert(at, (v, j));
            self.top.truncate(self.k);
        }
    }
}

/// Applies the weighted set heads of `heads` (those of evidence group `group`; all when `None`) to
/// `dist.possibility_raw`: a head `(S, d)` caps every place outside `S` at `1 − d`, a negated
/// one every place inside — what [`PlaceDistribution::constrain`] does head by head, in time
/// `O(n + Σ|S|)` instead of `O(n × heads)`.
///
/// A head of degree 0 caps at 1, which changes nothing (`possibility_raw` is in `[0, 1]`, built
/// from clamped degrees), so it is skipped. For the others, place `k`'s cap from the plain heads
/// is the lowest cap among those not containing `k`: the heads are sorted by cap (`scratch`,
/// sized at construction, so nothing is allocated) and walked until one leaves `k` out — as many
/// steps as the heads that contain `k`, plus one. `min` is exact and order-free, so the result
/// is that of applying the heads one by one.
pub(super) fn constrain_heads(
    dist: &mut PlaceDistribution,
    heads: &[SetHead],
    group: Option<usize>,
    read: impl Fn(u32) -> f64,
    scratch: &mut Vec<(f64, usize)>,
) {
    scratch.clear();
    for (h, head) in heads.iter().enumerate() {
        let degree = read(head.reg);
        if group.is_some_and(|g| head.group != g) || degree <= 0.0 {
            continue;
        }
        let cap = 1.0 - degree;
        if head.negated {
            for k in head.members.indices() {
                if let Some(p) = dist.possibility_raw.get_mut(k) {
                    *p = p.min(cap);
                }
            }
        } else {
            scratch.push((cap, h));
        }
    }
    if scratch.is_empty() {
        return;
    }
    scratch.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    for (k, p) in dist.possibility_raw.iter_mut().enumerate() {
        let outside = scratch
            .iter()
            .find(|&&(_, h)| heads.get(h).is_some_and(|x| !x.members.contains(k)));
        if let Some(&(cap, _)) = outside {
            *p = p.min(cap);
        }
    }
}
