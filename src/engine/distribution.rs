//! The place distribution of a step without evidence groups or a known region, from the tape's
//! registers in two passes over the places (issue 16: at 10,000 places each pass over every
//! place costs more than the few places a frame's gates evaluate).
//!
//! The first pass reads each place's support and exclusion (the exclusion from a table of the
//! distinct exclusion registers, `Exclusions`), keeps the extremes of the supports and writes
//! the place's own bound `t_k = min(1 − β_k, c)`, `c` the lowest cap of the set heads
//! (`at_place(P) -> in_room(R)` at every place gives one head per room); the few members of that
//! lowest head get their own caps after it (see `named_sets::constrain_heads`: a place's cap is
//! the lowest among the heads that leave it out). The second pass is
//! [`PlaceDistribution::finish_bounded`]: `π`, the height, `π'`, `N`, and the extremes the
//! decision reads. On a large map both go by exclusion class instead (`classes`): the first
//! reads only the supports, the second copies each class's `β`, `π` and `π'` and computes the
//! few places with a bound of their own. Every column holds the bits of the separate passes
//! (`fill_raw`, the heads, `finish`), and the decision is `decide`'s: `min` and `max` are exact
//! and order-free on these degrees, which are never NaN nor `−0`. Allocates nothing.

mod classes;

use super::compile::SetHead;
use crate::logic::possibility::{higher, lower, Peaks, Top2};
use crate::logic::{clamp_degree, Normalisation, PlaceDistribution};

/// The member places of each set head, listed once at load time (a head's `PlaceSet` is a flag
/// per place: walking it for a handful of members would read every place).
#[derive(Debug, Clone)]
pub(super) struct HeadMembers {
    start: Vec<u32>,
    places: Vec<u32>,
}

impl HeadMembers {
    pub(super) fn new(heads: &[SetHead]) -> HeadMembers {
        let mut start = Vec::with_capacity(heads.len() + 1);
        let mut places = Vec::new();
        start.push(0);
        for h in heads {
            places.extend(h.members.indices().map(|k| k as u32));
            start.push(places.len() as u32);
        }
        HeadMembers { start, places }
    }

    fn of(&self, h: usize) -> &[u32] {
        let (Some(&s), Some(&e)) = (self.start.get(h), self.start.get(h + 1)) else {
            return &[];
        };
        self.places.get(s as usize..e as usize).unwrap_or(&[])
    }
}

/// What a step reads the distribution from.
pub(super) struct Inputs<'a> {
    pub regs: &'a [f64],
    pub support: &'a [u32],
    pub heads: &'a [SetHead],
    pub members: &'a HeadMembers,
}

/// The places' exclusion registers, each distinct one listed once, with its degree and the
/// bound it gives in the current step: negative evidence is often one register per wall
/// configuration, shared by thousands of places, so the first pass looks each place's up in a
/// table of a few entries rather than clamping a register of its own.
#[derive(Debug, Clone)]
pub(super) struct Exclusions {
    regs: Vec<u32>,
    of_place: Vec<u32>,
    degree: Vec<f64>,
    bound: Vec<f64>,
    /// The places of each distinct register, for the pass by class (`classes`).
    classes: classes::Classes,
}

impl Exclusions {
    /// From each place's exclusion register.
    pub(super) fn new(exclusion: &[u32]) -> Exclusions {
        let mut index = std::collections::HashMap::new();
        let mut regs = Vec::new();
        let of_place = exclusion
            .iter()
            .map(|&r| {
                *index.entry(r).or_insert_with(|| {
                    regs.push(r);
                    regs.len() as u32 - 1
                })
            })
            .collect::<Vec<u32>>();
        let m = regs.len();
        Exclusions {
            classes: classes::Classes::new(&of_place, m),
            regs,
            of_place,
            degree: vec![0.0; m],
            bound: vec![1.0; m],
        }
    }

    /// Each distinct register's degree and bound `min(1 − β, c0)`; their maximum, which is the
    /// maximum over the places, since every entry is some place's.
    fn read(&mut self, regs: &[f64], c0: f64) -> f64 {
        let mut t_max = f64::NEG_INFINITY;
        let cols = self.degree.iter_mut().zip(&mut self.bound);
        for ((e, t), &r) in cols.zip(&self.regs) {
            *e = read(regs, r);
            *t = lower(1.0 - *e, c0);
            t_max = higher(t_max, *t);
        }
        t_max
    }
}

/// Scratch for the heads of positive degree, `(cap, head)`, sized at load time.
#[derive(Debug, Clone, Default)]
pub(super) struct HeadScratch {
    plain: Vec<(f64, usize)>,
    negated: Vec<(f64, usize)>,
}

impl HeadScratch {
    pub(super) fn new(heads: usize) -> HeadScratch {
        HeadScratch {
            plain: Vec::with_capacity(heads),
            negated: Vec::with_capacity(heads),
        }
    }

    /// The cap of place `k`, a member of the lowest plain head: the lowest cap among the other
    /// plain heads that leave it out (1 when none does).
    pub(super) fn cap_outside(&self, heads: &[SetHead], k: usize) -> f64 {
        let outside = self
            .plain
            .iter()
            .skip(1)
            .find(|&&(_, h)| heads.get(h).is_some_and(|x| !x.members.contains(k)));
        outside.map_or(1.0, |&(c, _)| c)
    }
}

fn read(regs: &[f64], r: u32) -> f64 {
    clamp_degree(regs.get(r as usize).copied().unwrap_or(0.0))
}

/// Fills `dist` from the registers (see the module docs) and returns the extremes the decision
/// reads; `None`, touching nothing, when the register lists are not one per place (the
/// separate passes then run).
pub(super) fn fill(
    dist: &mut PlaceDistribution,
    inp: &Inputs<'_>,
    scratch: &mut HeadScratch,
    ex: &mut Exclusions,
    normalisation: Normalisation,
) -> Option<Peaks> {
    let n = dist.len();
    let cols_ok = [dist.exclusion.len(), dist.possibility_raw.len()];
    if inp.support.len() != n || ex.of_place.len() != n || cols_ok != [n, n] {
        return None;
    }
    sort_heads(inp, scratch);
    if let Some(peaks) = classes::fill(dist, inp, scratch, ex, normalisation) {
        return Some(peaks);
    }
    let (c0, h0) = scratch.plain.first().copied().unwrap_or((1.0, usize::MAX));
    let mut sup = Top2::EMPTY;
    let mut t_max = ex.read(inp.regs, c0);
    let cols = dist.support.iter_mut().zip(&mut dist.exclusion);
    let cols = cols.zip(&mut dist.possibility_raw);
    let regs = inp.support.iter().zip(&ex.of_place);
    for (k, (((s, e), t), (&rs, &j))) in cols.zip(regs).enumerate() {
        *s = read(inp.regs, rs);
        sup.push(k, *s);
        // Every index is a table entry (made from these places); the defaults are never read.
        *e = ex.degree.get(j as usize).copied().unwrap_or(0.0);
        *t = ex.bound.get(j as usize).copied().unwrap_or(1.0);
    }
    // The lowest head's members: the lowest cap among the heads that leave them out (at least
    // `c0`, so `t_max` only rises).
    for &k in inp.members.of(h0) {
        let k = k as usize;
        let cap = scratch.cap_outside(inp.heads, k);
        if let (Some(t), Some(&e)) = (dist.possibility_raw.get_mut(k), dist.exclusion.get(k)) {
            *t = lower(1.0 - e, cap);
            t_max = higher(t_max, *t);
        }
    }
    if !scratch.negated.is_empty() {
        for &(cap, h) in &scratch.negated {
            for &k in inp.members.of(h) {
                if let Some(t) = dist.possibility_raw.get_mut(k as usize) {
                    *t = t.min(cap);
                }
            }
        }
        // Lowered bounds: the maximum is read again.
        t_max = dist
            .possibility_raw
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
    }
    Some(dist.finish_bounded(sup, t_max, normalisation))
}

/// The heads of positive degree into `scratch`, `(1 − degree, head)`: the plain ones sorted by
/// cap, the negated ones in head order. A head of degree 0 caps at 1, which changes nothing.
fn sort_heads(inp: &Inputs<'_>, scratch: &mut HeadScratch) {
    scratch.plain.clear();
    scratch.negated.clear();
    for (h, head) in inp.heads.iter().enumerate() {
        let degree = read(inp.regs, head.reg);
        if degree <= 0.0 {
            continue;
        }
        let list = if head.negated {
            &mut scratch.negated
        } else {
            &mut scratch.plain
        };
        list.push((1.0 - degree, h));
    }
    scratch.plain.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::rng::SplitMix64;
    use crate::engine::compile::GroundAtom;
    use crate::logic::PlaceSet;

    /// A register value: levels (ties), NaN, `−0` and values outside `[0, 1]`.
    fn value(rng: &mut SplitMix64) -> f64 {
        match rng.below(10) {
            0 => f64::NAN,
            1 => -0.0,
            2 => [1.5, -0.3, f64::INFINITY][rng.below(3)],
            3 | 4 => 0.0,
            5 => 1.0,
            6 => 0.5,
            _ => rng.unit(),
        }
    }

    fn head(rng: &mut SplitMix64, n: usize, reg: u32) -> SetHead {
        let size = 1 + rng.below(n.min(6));
        SetHead {
            atom: GroundAtom {
                name: "in_room".to_string(),
                args: Vec::new(),
            },
            members: PlaceSet::from_indices(n, (0..size).map(|_| rng.below(n))),
            negated: rng.chance(0.3),
            group: 0,
            reg,
        }
    }

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    /// The pass by class (`classes`) against the pass over every place, which a table of
    /// classes too large to use forces: every column, the height and the extremes, bit for bit.
    #[test]
    fn the_pass_by_class_is_the_pass_over_every_place() {
        let mut rng = SplitMix64::new(23);
        let mut by_classes = 0;
        for case in 0..3000 {
            let n = 1 + rng.below(300);
            let regs: Vec<f64> = (0..3 * n + 8).map(|_| value(&mut rng)).collect();
            let reg = |rng: &mut SplitMix64| rng.below(regs.len() + 2) as u32;
            let support: Vec<u32> = (0..n).map(|_| reg(&mut rng)).collect();
            // A few distinct exclusion registers, as per wall configuration.
            let shared: Vec<u32> = (0..1 + rng.below(4)).map(|_| reg(&mut rng)).collect();
            let exclusion: Vec<u32> = (0..n)
                .map(|_| match rng.chance(0.99) {
                    true => shared[rng.below(shared.len())],
                    false => reg(&mut rng),
                })
                .collect();
            let heads: Vec<SetHead> = (0..rng.below(5))
                .map(|_| {
                    let r = reg(&mut rng);
                    head(&mut rng, n, r)
                })
                .collect();
            let members = HeadMembers::new(&heads);
            let inp = Inputs {
                regs: &regs,
                support: &support,
                heads: &heads,
                members: &members,
            };
            let norm = [Normalisation::Min, Normalisation::Product][rng.below(2)];
            let mut by_class = Exclusions::new(&exclusion);
            let mut every = Exclusions::new(&exclusion);
            every.classes = classes::Classes::new(&every.of_place, usize::MAX);
            let (mut a, mut b) = (PlaceDistribution::new(n), PlaceDistribution::new(n));
            let mut s = HeadScratch::new(heads.len());
            sort_heads(&inp, &mut s);
            let Some(pa) = classes::fill(&mut a, &inp, &s, &mut by_class, norm) else {
                continue;
            };
            by_classes += 1;
            let pb = fill(&mut b, &inp, &mut s, &mut every, norm).expect("fits");
            let at = format!("case {case}");
            assert_eq!(bits(&a.support), bits(&b.support), "{at}");
            assert_eq!(bits(&a.exclusion), bits(&b.exclusion), "{at}");
            assert_eq!(bits(&a.possibility_raw), bits(&b.possibility_raw), "{at}");
            assert_eq!(bits(&a.possibility), bits(&b.possibility), "{at}");
            assert_eq!(bits(&a.necessity), bits(&b.necessity), "{at}");
            assert_eq!(a.height.to_bits(), b.height.to_bits(), "{at}");
            let top = |t: &Top2| (t.best, t.first.to_bits(), t.second.to_bits());
            assert_eq!(top(&pa.possibility), top(&pb.possibility), "{at}");
            assert_eq!(top(&pa.support), top(&pb.support), "{at}");
        }
        assert!(by_classes > 1500, "only {by_classes} steps by class");
    }
}
