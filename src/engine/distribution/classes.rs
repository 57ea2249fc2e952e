//! The second pass of [`super::fill`] by exclusion class (issue 16): a place's bound `t_k`,
//! hence `π_k` and `π'_k`, is a function of its exclusion register alone but at a few places,
//! and at 10,000 places 4 registers (one per wall configuration) serve every place. So `π` and
//! `π'` are computed once per class and copied to the columns, and only the places with a bound
//! of their own — the members of the lowest set head and of the negated heads, and the most
//! supported place, whose complement of the other supports differs — are computed one by one.
//! The extremes of `π'` come from each class's first two places and those places, pushed in
//! place order: the same highest, the same first place of it, and the same highest of the
//! others as a push of every place. Every column, the height and the extremes are those of the
//! pass over every place (`min` and `max` are exact and order-free on these degrees, which are
//! never NaN nor `−0`). Allocates nothing: every buffer is sized at load time, and a step with
//! more classes or more places of their own than they hold takes the pass over every place, as
//! does a map with fewer than 8 places per class and place of its own (the office's 8 places,
//! one register each), where the tables cost more than the places.

use super::{read, Exclusions, HeadScratch, Inputs};
use crate::logic::possibility::{higher, lower, Peaks, Top2};
use crate::logic::{Normalisation, PlaceDistribution};

/// At most this many distinct exclusion registers: beyond, the tables are no smaller than the
/// columns.
const CLASSES: usize = 64;
/// At most this many places with a bound of their own per step.
const OWN: usize = 256;

/// Unset entry of [`Classes::own`].
const NONE: f64 = f64::NAN;

/// The places of each exclusion class and the scratch of a step by class.
#[derive(Debug, Clone)]
pub(in crate::engine) struct Classes {
    /// Class `c`'s places, ascending: `places[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    places: Vec<u32>,
    /// Per class, its first two places without a bound of their own (`u32::MAX`: none).
    first: Vec<[u32; 2]>,
    /// Per class, `(β, π, π')` in this step: a table of [`CLASSES`] entries (the first
    /// `first.len()` used), so that a class index taken modulo its length needs no bounds check
    /// in the pass over the places.
    values: Box<[[f64; 3]; CLASSES]>,
    /// Per place, its own bound `t_k` in this step, or NaN.
    own: Vec<f64>,
    /// The places with an own bound (ascending once listed).
    listed: Vec<u32>,
    /// The places whose `π'` the extremes are taken from, with it.
    candidates: Vec<(u32, f64)>,
}

impl Classes {
    /// From each place's class (`Exclusions::of_place`) and the number of classes; empty (never
    /// used) beyond [`CLASSES`].
    pub(super) fn new(of_place: &[u32], classes: usize) -> Classes {
        let (m, n) = if classes <= CLASSES {
            (classes, of_place.len())
        } else {
            (0, 0)
        };
        let mut start = vec![0u32; m + 1];
        for &c in of_place.iter().take(n) {
            if let Some(s) = start.get_mut(c as usize + 1) {
                *s += 1;
            }
        }
        for c in 0..m {
            start[c + 1] += start[c];
        }
        let mut next = start.clone();
        let mut places = vec![0u32; n];
        for (k, &c) in of_place.iter().enumerate().take(n) {
            if let Some(at) = next.get_mut(c as usize) {
                if let Some(slot) = places.get_mut(*at as usize) {
                    *slot = k as u32;
                }
                *at += 1;
            }
        }
        Classes {
            start,
            places,
            first: vec![[u32::MAX; 2]; m],
            values: Box::new([[0.0; 3]; CLASSES]),
            own: vec![NONE; n],
            listed: Vec::with_capacity(OWN),
            candidates: Vec::with_capacity(2 * m + OWN),
        }
    }

    fn of(&self, c: usize) -> &[u32] {
        let (Some(&s), Some(&e)) = (self.start.get(c), self.start.get(c + 1)) else {
            return &[];
        };
        self.places.get(s as usize..e as usize).unwrap_or(&[])
    }

    /// Gives place `k` the bound `t` (listing it the first time).
    fn set_own(&mut self, k: usize, t: f64) {
        if let Some(o) = self.own.get_mut(k) {
            if o.is_nan() {
                self.listed.push(k as u32);
            }
            *o = t;
        }
    }
}

/// [`super::fill`]'s work after `sort_heads`, by class; `None`, touching nothing, when the step
/// does not fit the tables (see the module docs).
pub(super) fn fill(
    dist: &mut PlaceDistribution,
    inp: &Inputs<'_>,
    scratch: &HeadScratch,
    ex: &mut Exclusions,
    normalisation: Normalisation,
) -> Option<Peaks> {
    let n = dist.len();
    let (c0, h0) = scratch.plain.first().copied().unwrap_or((1.0, usize::MAX));
    let negated = scratch
        .negated
        .iter()
        .map(|&(_, h)| inp.members.of(h).len());
    let own_max = inp.members.of(h0).len() + negated.sum::<usize>() + 1;
    let (cl, m) = (&ex.classes, ex.degree.len());
    // On a small map (the office's 8 places) the tables and the places of their own are no
    // fewer than the places: the pass over every place costs less there.
    let small = n < 8 * (m + own_max);
    if small || cl.own.len() != n || cl.first.len() != m || own_max > OWN {
        return None;
    }
    let sup = supports(dist, inp);
    ex.read(inp.regs, c0);
    own_bounds(ex, inp, scratch, h0, sup.best);
    let t_max = first_places(ex);
    let (all, but_best) = sup.complements();
    let t_b = ex.classes.own.get(sup.best).copied().unwrap_or(NONE);
    // As `PlaceDistribution::finish_bounded` computes it.
    let h = all.min(t_max).max(0.0).max(but_best.min(t_b));
    dist.height = h;
    dist.inconsistency = 1.0 - h;
    let o = (sup.best, all, but_best);
    // One pass per case, as `finish_bounded`.
    let pos = if h <= 0.0 {
        class_pass(dist, ex, o, |_| 1.0)
    } else {
        match normalisation {
            Normalisation::Min => class_pass(dist, ex, o, |r| if r >= h { 1.0 } else { r }),
            Normalisation::Product => class_pass(dist, ex, o, |r| lower(r / h, 1.0)),
        }
    };
    dist.fill_necessity(pos);
    Some(Peaks {
        support: sup,
        possibility: pos,
    })
}

/// Reads every place's support into `dist` and returns their extremes.
fn supports(dist: &mut PlaceDistribution, inp: &Inputs<'_>) -> Top2 {
    let mut sup = Top2::EMPTY;
    for (k, (s, &r)) in dist.support.iter_mut().zip(inp.support).enumerate() {
        *s = read(inp.regs, r);
        sup.push(k, *s);
    }
    sup
}

/// The places with a bound of their own, as the pass over every place bounds them: the lowest
/// head's members `min(1 − β_k, cap_k)`, then the negated heads' caps, then the most supported
/// place `b` (its class's bound, if nothing else).
fn own_bounds(ex: &mut Exclusions, inp: &Inputs<'_>, scratch: &HeadScratch, h0: usize, b: usize) {
    let cl = &mut ex.classes;
    for &k in &cl.listed {
        if let Some(o) = cl.own.get_mut(k as usize) {
            *o = NONE;
        }
    }
    cl.listed.clear();
    let class = |k: usize| ex.of_place.get(k).map_or(usize::MAX, |&c| c as usize);
    let bound = |k: usize| ex.bound.get(class(k)).copied().unwrap_or(1.0);
    for &k in inp.members.of(h0) {
        let k = k as usize;
        let cap = scratch.cap_outside(inp.heads, k);
        let e = ex.degree.get(class(k)).copied().unwrap_or(0.0);
        cl.set_own(k, lower(1.0 - e, cap));
    }
    for &(cap, h) in &scratch.negated {
        for &k in inp.members.of(h) {
            let k = k as usize;
            let t = cl.own.get(k).copied().unwrap_or(NONE);
            let t = if t.is_nan() { bound(k) } else { t };
            cl.set_own(k, t.min(cap));
        }
    }
    if cl.own.get(b).is_some_and(|t| t.is_nan()) {
        cl.set_own(b, bound(b));
    }
    cl.listed.sort_unstable();
}

/// Each class's first two places without a bound of their own; returns `max_k t_k`: the bounds
/// of the classes that keep a place, and the own bounds.
fn first_places(ex: &mut Exclusions) -> f64 {
    let cl = &mut ex.classes;
    let mut t_max = f64::NEG_INFINITY;
    for (c, &t) in ex.bound.iter().enumerate() {
        let mut found = [u32::MAX; 2];
        let mut seen = 0;
        for &k in cl.of(c) {
            if cl.own.get(k as usize).is_some_and(|o| o.is_nan()) {
                found[seen] = k;
                seen += 1;
                if seen == 2 {
                    break;
                }
            }
        }
        if seen > 0 {
            t_max = higher(t_max, t);
        }
        if let Some(f) = cl.first.get_mut(c) {
            *f = found;
        }
    }
    let own = cl.listed.iter().map(|&k| cl.own.get(k as usize));
    own.flatten().fold(t_max, |m, &t| higher(m, t))
}

/// `β`, `π` and `π' = norm(π)` of every place from its class's values, then of the places with
/// a bound of their own; returns the extremes of `π'`. `o` is `(b, o, o_b)`: the complement of
/// the other supports, `o_b` at the most supported place `b`, `o` elsewhere.
#[inline]
fn class_pass(
    dist: &mut PlaceDistribution,
    ex: &mut Exclusions,
    (b, all, but_best): (usize, f64, f64),
    norm: impl Fn(f64) -> f64,
) -> Top2 {
    let cl = &mut ex.classes;
    for (v, (&e, &t)) in cl.values.iter_mut().zip(ex.degree.iter().zip(&ex.bound)) {
        let r = lower(all, t);
        *v = [e, r, norm(r)];
    }
    let cols = dist.exclusion.iter_mut().zip(&mut dist.possibility_raw);
    for ((e, r), (p, &c)) in cols.zip(dist.possibility.iter_mut().zip(&ex.of_place)) {
        // Every class index is below the number of classes, at most `CLASSES`.
        let [ve, vr, vp] = cl.values[c as usize % CLASSES];
        (*e, *r, *p) = (ve, vr, vp);
    }
    cl.candidates.clear();
    for (f, v) in cl.first.iter().zip(cl.values.iter()) {
        let places = f.iter().filter(|&&k| k != u32::MAX);
        cl.candidates.extend(places.map(|&k| (k, v[2])));
    }
    for &k in &cl.listed {
        let k = k as usize;
        let t = cl.own.get(k).copied().unwrap_or(NONE);
        let r = lower(if k == b { but_best } else { all }, t);
        if let (Some(raw), Some(p)) = (dist.possibility_raw.get_mut(k), dist.possibility.get_mut(k))
        {
            (*raw, *p) = (r, norm(r));
            cl.candidates.push((k as u32, *p));
        }
    }
    cl.candidates.sort_unstable_by_key(|&(k, _)| k);
    let mut pos = Top2::EMPTY;
    for &(k, p) in &cl.candidates {
        pos.push(k as usize, p);
    }
    pos
}
