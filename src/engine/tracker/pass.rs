//! The graph tracker's passes over every place (issue 16): at 10,000 places the steady frame
//! is a handful of passes over columns of 10,000 values, so their number and how many places
//! each instruction handles, not the arithmetic, set its time.
//!
//! - [`intersect`]: `c_j = T(max(pred_j, b), e_j)` with the clamped support and exclusion, one
//!   loop per column written, each without a branch per place, so that the compiler applies it
//!   to two places at once; every column is read once and written once, as in one fused loop;
//! - [`normalise`]: `π'` from `c` in a loop of the same kind, then one scan for the two highest
//!   `π'` (the necessities' complements) and the places hot for the revision;
//! - [`Necessity`]: the necessity column is one value everywhere but at the most possible
//!   place, so only the entries that change are written;
//! - [`decide`]: the decision from those results, without passing over the columns again.
//!
//! Each computes the same operations on the same values as the `logic` functions the tracker
//! used before (`PlaceDistribution::normalise`, `decide`); the tests compare them bit for bit.
//! The columns hold degrees in `[0, 1]`: clamped inputs, and t-norms of them, so never NaN.

use crate::logic::decision::decide_from;
use crate::logic::{
    Decision, DecisionParams, Disoriented, Normalisation, PlaceDistribution, TNorm,
};

/// The evidence's columns, each of the map's length.
pub(super) struct Evidence<'a> {
    pub possibility: &'a [f64],
    pub support: &'a [f64],
    pub exclusion: &'a [f64],
}

/// The columns the intersection writes, each of the map's length.
pub(super) struct Written<'a> {
    pub support: &'a mut [f64],
    pub exclusion: &'a mut [f64],
    pub raw: &'a mut [f64],
    pub evid: &'a mut [f64],
}

/// `e_j = clamp(v_j)^w`, `c_j = T(max(pred_j, b), e_j)`, the clamped support and exclusion of
/// every place; returns `(max_j c_j, max_j α_j)`. The maxima are taken with `>` in lanes, so
/// that no place waits for the one before: the same values as `f64::max` in order (no NaN
/// here), but a maximum of 0 may carry either sign of zero — the caller recomputes the height in
/// order when it is 0, and the support's maximum is read only by comparisons.
pub(super) fn intersect(
    t: TNorm,
    b: f64,
    w: f64,
    pred: &[f64],
    ev: &Evidence,
    out: Written,
) -> (f64, f64) {
    match (t, w == 1.0) {
        (TNorm::Min, true) => run(|x, e| TNorm::Min.apply(x, e), |v| v, b, pred, ev, out),
        (TNorm::Product, true) => run(|x, e| TNorm::Product.apply(x, e), |v| v, b, pred, ev, out),
        (TNorm::Lukasiewicz, true) => run(
            |x, e| TNorm::Lukasiewicz.apply(x, e),
            |v| v,
            b,
            pred,
            ev,
            out,
        ),
        // `powf(1)` is exact, so only a weight below 1 takes the power.
        (t, false) => run(|x, e| t.apply(x, e), |v: f64| v.powf(w), b, pred, ev, out),
    }
}

/// [`crate::logic::clamp_degree`] as two selects (NaN fails `x >= 0`; `−0` passes it and stays `−0`, as
/// `clamp` leaves it), which the compiler can apply to several places at once.
#[inline(always)]
fn clamp01(x: f64) -> f64 {
    let x = if x >= 0.0 { x } else { 0.0 };
    if x <= 1.0 {
        x
    } else {
        1.0
    }
}

/// Lanes of the running maxima in [`intersect`].
const LANES: usize = 4;

/// The maximum of `xs` with `>` in [`LANES`] lanes (place `k` in lane `k mod LANES`, the places
/// after the last full group of lanes in lane 0): see [`intersect`] for the sign of a maximum of 0.
#[inline(always)]
fn lane_max(xs: &[f64]) -> f64 {
    let mut top = [0.0f64; LANES];
    let mut chunks = xs.chunks_exact(LANES);
    for c in &mut chunks {
        for l in 0..LANES {
            top[l] = if c[l] > top[l] { c[l] } else { top[l] };
        }
    }
    for &x in chunks.remainder() {
        top[0] = if x > top[0] { x } else { top[0] };
    }
    top.iter().fold(0.0, |x, &y| if y > x { y } else { x })
}

/// The passes of [`intersect`]: one loop per column written, each simple enough for the
/// compiler to apply to two places at once on baseline x86-64 (one fused loop over eight
/// columns was compiled place by place). Every column is still read once and written once.
#[inline(always)]
fn run(
    tn: impl Fn(f64, f64) -> f64,
    power: impl Fn(f64) -> f64,
    b: f64,
    pred: &[f64],
    ev: &Evidence,
    out: Written,
) -> (f64, f64) {
    // The caller gives columns of one length; were one shorter, the loops would stop there.
    for (o, &a) in out.support.iter_mut().zip(ev.support) {
        *o = clamp01(a);
    }
    for (o, &z) in out.exclusion.iter_mut().zip(ev.exclusion) {
        *o = clamp01(z);
    }
    for (o, &v) in out.evid.iter_mut().zip(ev.possibility) {
        *o = power(clamp01(v));
    }
    for ((c, &p), &e) in out.raw.iter_mut().zip(pred).zip(&*out.evid) {
        *c = tn(p.max(b), e);
    }
    (lane_max(out.raw), lane_max(out.support))
}

/// `m_i ← T(m_i, floor)` for every anchor; returns the highest result (with `>` in lanes: the
/// value of the highest, a 0 of either sign).
pub(super) fn revise(anchor: &mut [f64], t: TNorm, floor: f64) -> f64 {
    match t {
        TNorm::Min => scale(anchor, |m| TNorm::Min.apply(m, floor)),
        TNorm::Product => scale(anchor, |m| TNorm::Product.apply(m, floor)),
        TNorm::Lukasiewicz => scale(anchor, |m| TNorm::Lukasiewicz.apply(m, floor)),
    }
}

#[inline(always)]
fn scale(anchor: &mut [f64], f: impl Fn(f64) -> f64) -> f64 {
    let mut top = [0.0f64; LANES];
    let mut chunks = anchor.chunks_exact_mut(LANES);
    for c in &mut chunks {
        for l in 0..LANES {
            c[l] = f(c[l]);
            top[l] = if c[l] > top[l] { c[l] } else { top[l] };
        }
    }
    for m in chunks.into_remainder() {
        *m = f(*m);
        top[0] = if *m > top[0] { *m } else { top[0] };
    }
    top.iter().fold(0.0, |x, &y| if y > x { y } else { x })
}

/// The most possible place and the two highest `π'` (`PlaceDistribution::normalise`'s search:
/// the first place of the highest value; the second is the highest of the others).
#[derive(Debug, Clone, Copy)]
pub(super) struct Top {
    pub best: usize,
    pub first: f64,
    pub second: f64,
}

impl Top {
    /// `1 − max(0, max_{j≠k} π'_j)` for every `k` but `best`, and for `best`.
    pub fn complements(&self) -> (f64, f64) {
        (1.0 - self.first.max(0.0), 1.0 - self.second.max(0.0))
    }
}

/// What the normalisation lists the revision's hot places with: its floor, `e_j`, and the list
/// (see [`normalise`]).
pub(super) struct Hot<'a> {
    pub floor: f64,
    pub evid: &'a [f64],
    pub list: &'a mut [(u32, f64)],
}

/// `π'` of every place from `raw` and its height `h` (the value of `max raw`; its sign at 0 does
/// not matter), as `PlaceDistribution::normalise` computes it, with the two highest `π'` found in
/// the same pass. With `hot` also lists the places whose agreement `min(π'_j, e_j)` exceeds
/// `floor` (into `list`, returning how many; see `Tracker::revise`).
pub(super) fn normalise(
    raw: &[f64],
    h: f64,
    norm: Normalisation,
    poss: &mut [f64],
    hot: Option<Hot>,
) -> (Top, usize) {
    if h <= 0.0 {
        // Nothing is possible: total ignorance rather than 0/0.
        return scan(raw, poss, hot, |_| 1.0);
    }
    match norm {
        Normalisation::Min => scan(raw, poss, hot, |r| if r >= h { 1.0 } else { r }),
        // `r / 1 = r` exactly: no division when the height is 1.
        Normalisation::Product if h == 1.0 => scan(raw, poss, hot, |r| r.min(1.0)),
        Normalisation::Product => scan(raw, poss, hot, |r| (r / h).min(1.0)),
    }
}

#[inline(always)]
fn scan(raw: &[f64], poss: &mut [f64], hot: Option<Hot>, f: impl Fn(f64) -> f64) -> (Top, usize) {
    let mut t = Top {
        best: usize::MAX,
        first: f64::NEG_INFINITY,
        second: f64::NEG_INFINITY,
    };
    let mut found = 0;
    let mut n = poss.len().min(raw.len());
    if let Some(h) = &hot {
        n = n.min(h.evid.len());
    }
    // `π'` first, in a loop of its own that the compiler applies to two places at once (the
    // division of the product normalisation is the costliest operation of the pass), then the
    // searches.
    for (p, &r) in poss[..n].iter_mut().zip(&raw[..n]) {
        *p = f(r);
    }
    let each = |t: &mut Top, k: usize, v: f64| {
        if v > t.first {
            (t.second, t.first, t.best) = (t.first, v, k);
        } else if v > t.second {
            t.second = v;
        }
    };
    // By blocks of places: a place changes the two highest only if it exceeds the second, and
    // is hot only if its agreement exceeds the floor, so a block whose highest value does
    // neither is skipped after one branch-free look at it (most are: `π'` has a few distinct
    // values in a steady frame).
    let mut k0 = 0;
    let poss = &poss[..n];
    match hot {
        None => {
            for block in poss.chunks(BLOCK) {
                if highest(block) > t.second {
                    for (k, &p) in block.iter().enumerate() {
                        each(&mut t, k0 + k, p);
                    }
                }
                k0 += block.len();
            }
        }
        Some(Hot { floor, evid, list }) => {
            // `min` as a select: neither is NaN, and only a `g` above `floor ≥ 0` is kept, so
            // the sign a zero would take does not matter.
            let agree = |p: f64, e: f64| if e < p { e } else { p };
            for (block, ev) in poss.chunks(BLOCK).zip(evid.chunks(BLOCK)) {
                if highest(block) > t.second {
                    for (k, &p) in block.iter().enumerate() {
                        each(&mut t, k0 + k, p);
                    }
                }
                let any = block
                    .iter()
                    .zip(ev)
                    .fold(false, |x, (&p, &e)| x | (agree(p, e) > floor));
                if any {
                    for (k, (&p, &e)) in block.iter().zip(ev).enumerate() {
                        let g = agree(p, e);
                        if g > floor {
                            if let Some(slot) = list.get_mut(found) {
                                (*slot, found) = (((k0 + k) as u32, g), found + 1);
                            }
                        }
                    }
                }
                k0 += block.len();
            }
        }
    }
    (t, found)
}

/// Places per block in [`scan`].
const BLOCK: usize = 16;

/// The highest of `xs`, or −∞, with `>` selects (no branch per place): only compared.
#[inline(always)]
fn highest(xs: &[f64]) -> f64 {
    xs.iter()
        .fold(f64::NEG_INFINITY, |x, &y| if y > x { y } else { x })
}

/// What the necessity column holds: `all` (its bits) everywhere but at `at`. `None` when
/// unknown (a new distribution).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Necessity(Option<(u64, usize)>);

impl Necessity {
    /// Writes `N` for `top` into `nec`: `1 − first` everywhere but at the most possible place,
    /// which gets `1 − second`. Only the entries that differ from the last column are written.
    pub fn write(&mut self, nec: &mut [f64], top: &Top) {
        let (all, but_best) = top.complements();
        match self.0 {
            Some((bits, at)) if bits == all.to_bits() => {
                if let Some(x) = nec.get_mut(at) {
                    *x = all;
                }
            }
            _ => nec.fill(all),
        }
        if let Some(x) = nec.get_mut(top.best) {
            *x = but_best;
        }
        self.0 = Some((all.to_bits(), top.best));
    }

    /// Forgets what the column holds (it was written elsewhere).
    pub fn forget(&mut self) {
        self.0 = None;
    }
}

/// `logic::decide` on `d`, whose possibility and necessity [`normalise`] and [`Necessity`]
/// wrote from `top`, and whose supports' highest is `max_support`: the place of highest
/// necessity is `top.best` unless every necessity is the same, then the first place of the
/// highest support; the runner-up is searched only when the decision reports it.
pub(super) fn decide(
    d: &PlaceDistribution,
    top: &Top,
    max_support: f64,
    p: DecisionParams,
) -> Decision {
    let n = d.len();
    if n == 0 {
        return Decision::Disoriented(Disoriented::NoPlaces);
    }
    let (all, but_best) = top.complements();
    let best = if but_best > all && top.best < n {
        top.best
    } else {
        d.support
            .iter()
            .position(|&s| s == max_support)
            .unwrap_or(0)
    };
    decide_from(d, p, best, || max_support)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::rng::SplitMix64;
    use crate::logic::{clamp_degree, decide as logic_decide};

    /// A value from a few levels, so that ties are common; `wild` adds NaN and values outside
    /// `[0, 1]` (what the intersection clamps).
    fn level(rng: &mut SplitMix64, wild: bool) -> f64 {
        match rng.below(if wild { 9 } else { 6 }) {
            0 => 0.0,
            1 => 1.0,
            2 => 0.5,
            3 | 4 => rng.unit(),
            5 => 0.1 * rng.below(4) as f64,
            6 => f64::NAN,
            7 => [-0.5, -0.0, f64::NEG_INFINITY][rng.below(3)],
            _ => [1.5, f64::INFINITY][rng.below(2)],
        }
    }

    #[test]
    fn the_two_selects_clamp_as_clamp_degree() {
        let odd = [
            f64::NAN,
            -f64::NAN,
            -0.0,
            0.0,
            1.0,
            -1e-300,
            1.0 + f64::EPSILON,
        ];
        let more = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.3,
            -7.0,
            7.0,
            f64::MIN_POSITIVE,
        ];
        for x in odd.into_iter().chain(more) {
            assert_eq!(clamp01(x).to_bits(), clamp_degree(x).to_bits(), "{x}");
        }
    }

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    #[test]
    fn the_intersection_is_the_formulas_place_by_place() {
        let mut rng = SplitMix64::new(5);
        for case in 0..3000 {
            let n = rng.below(23);
            let col = |rng: &mut SplitMix64, wild| (0..n).map(|_| level(rng, wild)).collect();
            let (pos, sup, exc): (Vec<f64>, Vec<f64>, Vec<f64>) = (
                col(&mut rng, true),
                col(&mut rng, true),
                col(&mut rng, true),
            );
            let pred: Vec<f64> = col(&mut rng, false);
            let t = TNorm::ALL[rng.below(3)];
            let b = [0.0, 0.1, 0.3][rng.below(3)];
            let w = [1.0, 1.0, 0.4][rng.below(3)];
            let mut got = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
            let [s, x, r, e] = got.each_mut();
            let ev = Evidence {
                possibility: &pos,
                support: &sup,
                exclusion: &exc,
            };
            let out = Written {
                support: s,
                exclusion: x,
                raw: r,
                evid: e,
            };
            let (h, m) = intersect(t, b, w, &pred, &ev, out);
            let e: Vec<f64> = pos.iter().map(|&v| clamp_degree(v).powf(w)).collect();
            let c: Vec<f64> = (0..n).map(|j| t.apply(pred[j].max(b), e[j])).collect();
            let a: Vec<f64> = sup.iter().map(|&v| clamp_degree(v)).collect();
            let z: Vec<f64> = exc.iter().map(|&v| clamp_degree(v)).collect();
            assert_eq!(bits(&got[0]), bits(&a), "case {case}");
            assert_eq!(bits(&got[1]), bits(&z), "case {case}");
            assert_eq!(bits(&got[2]), bits(&c), "case {case}");
            assert_eq!(bits(&got[3]), bits(&e), "case {case}");
            // Equal values; a zero's sign is left open (see `intersect`).
            assert_eq!(h, c.iter().copied().fold(0.0, f64::max), "case {case}");
            assert_eq!(m, a.iter().copied().fold(0.0, f64::max), "case {case}");
        }
    }

    #[test]
    fn normalising_and_deciding_are_logics_bit_for_bit() {
        let mut rng = SplitMix64::new(9);
        // One distribution per size, reused across cases, so that the necessity column is
        // patched from what earlier cases left in it.
        let mut kept: Vec<(PlaceDistribution, Necessity)> = (0..60)
            .map(|n| (PlaceDistribution::new(n), Necessity::default()))
            .collect();
        for case in 0..20000 {
            let n = rng.below(60);
            let norm = [Normalisation::Min, Normalisation::Product][rng.below(2)];
            let mut want = PlaceDistribution::new(n);
            let flat = rng.chance(0.2).then(|| level(&mut rng, false));
            for k in 0..n {
                want.possibility_raw[k] = flat.unwrap_or_else(|| level(&mut rng, false));
                want.support[k] = if rng.chance(0.3) {
                    level(&mut rng, false)
                } else {
                    0.0
                };
            }
            let h = want.possibility_raw.iter().copied().fold(0.0, f64::max);
            (want.height, want.inconsistency) = (h, 1.0 - h);
            let (got, nec) = &mut kept[n];
            got.possibility_raw.clone_from(&want.possibility_raw);
            got.support.clone_from(&want.support);
            (got.height, got.inconsistency) = (h, 1.0 - h);
            want.normalise(norm);
            let floor = [0.3, 0.7, 1.0][rng.below(3)];
            let evid: Vec<f64> = (0..n).map(|_| level(&mut rng, false)).collect();
            let mut list = vec![(0, 0.0); n];
            let hot = (floor < 1.0).then_some(Hot {
                floor,
                evid: &evid,
                list: &mut list,
            });
            let (top, found) = normalise(&got.possibility_raw, h, norm, &mut got.possibility, hot);
            nec.write(&mut got.necessity, &top);
            assert_eq!(
                bits(&got.possibility),
                bits(&want.possibility),
                "case {case}"
            );
            assert_eq!(bits(&got.necessity), bits(&want.necessity), "case {case}");
            let hot_want: Vec<(u32, f64)> = (0..n)
                .map(|j| (j as u32, want.possibility[j].min(evid[j])))
                .filter(|&(_, g)| floor < 1.0 && g > floor)
                .collect();
            assert_eq!(list[..found], hot_want[..], "case {case}");
            let params = DecisionParams {
                threshold: [0.0, 0.3, 0.5, 0.9][rng.below(4)],
                margin: [0.0, 0.1, 0.4][rng.below(3)],
            };
            let max_support = got.support.iter().copied().fold(0.0, f64::max);
            assert_eq!(
                decide(got, &top, max_support, params),
                logic_decide(&want, params),
                "case {case}: {want:?}"
            );
        }
    }
}
