//! The named sets of places (rooms, regions) in each step — their heads applied to the raw
//! distribution, their Π and N read after it (when the step's room or region degrees are first
//! asked for) — in time that grows with the sets' sizes rather than with `sets × places`
//! (issue 16: a 10,000-place map has 2,500 rooms).
//!
//! `Π(S) = max_{k ∈ S} π_k` reads the members only. `N(S) = 1 − max_{k ∉ S} π_k` reads the
//! `K` highest places of the step (`K` one more than the largest small set): the first of them
//! outside `S` is the highest place outside `S`. Sets larger than [`SMALL`] are scanned whole.
//! Both select a maximum, so the results are exactly [`PlaceSet::possibility`] and
//! [`PlaceSet::necessity`] (NaNs ignored, as `f64::max` does there). `degrees` allocates its
//! result and the top places; `constrain_heads` allocates nothing.

use super::compile::SetHead;
use super::RoomDegrees;
use crate::logic::{clamp_degree, PlaceDistribution, PlaceSet};

/// Largest set whose necessity is read from the top places.
const SMALL: usize = 32;

/// The named sets with their members listed.
#[derive(Debug, Clone)]
pub(super) struct NamedSets {
    sets: Vec<PlaceSet>,
    members: Vec<Vec<usize>>,
    /// How many of the highest places `N` of a small set may read: one more than the largest.
    k: usize,
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
        NamedSets { sets, members, k }
    }

    /// Support (from the registers `regs[support[i]]`), Π and N of each set under `dist`
    /// (normalised).
    pub(super) fn degrees(
        &self,
        dist: &PlaceDistribution,
        regs: &[f64],
        support: &[u32],
    ) -> RoomDegrees {
        let pi = &dist.possibility;
        let top = self.top(pi);
        let n = self.sets.len();
        let mut out = RoomDegrees {
            support: Vec::with_capacity(n),
            possibility: Vec::with_capacity(n),
            necessity: Vec::with_capacity(n),
        };
        for (i, (set, members)) in self.sets.iter().zip(&self.members).enumerate() {
            let reg = support.get(i).copied().unwrap_or(u32::MAX);
            let s = clamp_degree(regs.get(reg as usize).copied().unwrap_or(0.0));
            let p = members
                .iter()
                .filter_map(|&k| pi.get(k).copied())
                .fold(0.0, f64::max);
            let n = if members.len() <= SMALL {
                // The member list, not the set's flag per place: one small array per set.
                let outside = top.iter().find(|&&(_, k)| !members.contains(&k));
                1.0 - outside.map_or(0.0, |&(v, _)| v)
            } else {
                set.necessity(pi)
            };
            out.support.push(s);
            out.possibility.push(p);
            out.necessity.push(n);
        }
        out
    }

    /// The `k` highest places, highest first (ties in any order: only the values are read);
    /// NaN places are left out, as `f64::max` leaves them out of a maximum.
    fn top(&self, pi: &[f64]) -> Vec<(f64, usize)> {
        let mut top = Vec::with_capacity(self.k + 1);
        if self.k == 0 {
            return top;
        }
        for (j, &v) in pi.iter().enumerate() {
            if v.is_nan() || (top.len() == self.k && top[self.k - 1].0 >= v) {
                continue;
            }
            let at = top.partition_point(|&(w, _)| w >= v);
            top.insert(at, (v, j));
            top.truncate(self.k);
        }
        top
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
