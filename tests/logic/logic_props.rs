//! Property tests for `lplace::logic` (DESIGN §3): the t-norm and t-conorm axioms for every
//! `TNorm`, conorm duality, the residuation adjunction, the place distribution against an
//! independent brute-force enumeration over possible worlds, range and NaN safety, the decision's
//! contract, order independence, and `clamp_degree`; and weighted formulas over *sets* of places,
//! min/product fusion of two bases and conditioning on a region, with Π and N of sets, again
//! against enumeration.
//!
//! The expected values come from the textbook definitions, implemented here without reference to
//! the crate: a weighted base is a list of formulas `(at_place(P_j), α)` / `(¬at_place(P_k), β)`
//! (several may speak about the same place), a world is "the robot is at place w", and
//! π(w) = min over the formulas w falsifies of (1 − weight). Height, inconsistency, both
//! normalisations, Π and N are then computed by enumerating worlds. Floating point forces a 1e-12
//! tolerance wherever two algebraically equal expressions are evaluated in a different order.

use lplace::logic::{
    clamp_degree, decide, Decision, DecisionParams, Disoriented, Fusion, Normalisation,
    PlaceDistribution, PlaceSet, Similarity, TNorm,
};
use proptest::prelude::*;

const EPS: f64 = 1e-12;

/// The decision's tie tolerance, as documented in `logic::decision` (10⁻⁹).
const TIE: f64 = 1e-9;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= EPS
}

/// Degrees in [0, 1], biased towards the endpoints and a coarse grid so that ties, zeros and ones
/// (where most edge cases live) show up often.
fn degree() -> impl Strategy<Value = f64> {
    prop_oneof![
        1 => Just(0.0),
        1 => Just(1.0),
        3 => (0u32..=10).prop_map(|k| f64::from(k) / 10.0),
        5 => 0.0..=1.0f64,
    ]
}

fn tnorm() -> impl Strategy<Value = TNorm> {
    prop::sample::select(TNorm::ALL.to_vec())
}

fn normalisation() -> impl Strategy<Value = Normalisation> {
    prop::sample::select(vec![Normalisation::Min, Normalisation::Product])
}

// ---------------------------------------------------------------------------------------------
// Brute-force possibilistic reference
// ---------------------------------------------------------------------------------------------

/// A weighted formula about mutually exclusive places.
#[derive(Debug, Clone, Copy)]
enum Formula {
    /// `(at_place(P_j), weight)`.
    At(usize, f64),
    /// `(¬at_place(P_k), weight)`.
    NotAt(usize, f64),
}

impl Formula {
    /// Whether the world "the robot is at place `w`" satisfies the formula.
    fn holds_in(self, w: usize) -> bool {
        match self {
            Formula::At(j, _) => w == j,
            Formula::NotAt(k, _) => w != k,
        }
    }

    fn weight(self) -> f64 {
        match self {
            Formula::At(_, a) | Formula::NotAt(_, a) => a,
        }
    }
}

/// What the textbook semantics says about a base over `n` places.
#[derive(Debug)]
struct Reference {
    pi: Vec<f64>,
    height: f64,
    inconsistency: f64,
    /// Normalised π'.
    pi_norm: Vec<f64>,
    /// Π({i}) under π'.
    poss: Vec<f64>,
    /// N({i}) = 1 − Π(worlds ∖ {i}) under π'.
    nec: Vec<f64>,
}

/// Π(A) = max_{w ∈ A} π(w), with Π(∅) = 0.
fn possibility_of(pi: &[f64], a: impl Fn(usize) -> bool) -> f64 {
    (0..pi.len())
        .filter(|&w| a(w))
        .map(|w| pi[w])
        .fold(0.0, f64::max)
}

fn reference(n: usize, base: &[Formula], norm: Normalisation) -> Reference {
    // π(w) = min over the formulas falsified by w of (1 − weight); 1 if none is falsified.
    let pi: Vec<f64> = (0..n)
        .map(|w| {
            base.iter()
                .filter(|f| !f.holds_in(w))
                .map(|f| 1.0 - f.weight())
                .fold(1.0, f64::min)
        })
        .collect();
    let height = possibility_of(&pi, |_| true);
    let inconsistency = 1.0 - height;
    let pi_norm: Vec<f64> = pi
        .iter()
        .map(|&p| match norm {
            // Min-based: the worlds at the height become fully possible, the rest keep π.
            Normalisation::Min => {
                if p == height {
                    1.0
                } else {
                    p
                }
            }
            // Product-based: rescale by h. With h = 0 every world is equally impossible; the
            // documented convention is the uniform distribution 1 (what min-based also gives).
            Normalisation::Product => {
                if height == 0.0 {
                    1.0
                } else {
                    p / height
                }
            }
        })
        .collect();
    let poss = (0..n)
        .map(|i| possibility_of(&pi_norm, |w| w == i))
        .collect();
    let nec = (0..n)
        .map(|i| 1.0 - possibility_of(&pi_norm, |w| w != i))
        .collect();
    Reference {
        pi,
        height,
        inconsistency,
        pi_norm,
        poss,
        nec,
    }
}

/// Feeds a base to the crate the way the engine does: a place's support is the max over the
/// weights of the formulas concluding `at_place` for it (alternative derivations combine by max),
/// likewise its exclusion; 0 when nothing concludes it.
fn distribution(n: usize, base: &[Formula], norm: Normalisation) -> PlaceDistribution {
    let mut d = PlaceDistribution::new(n);
    for f in base {
        match *f {
            Formula::At(j, a) => d.support[j] = d.support[j].max(a),
            Formula::NotAt(k, b) => d.exclusion[k] = d.exclusion[k].max(b),
        }
    }
    d.update(norm);
    d
}

/// A place count in `0..max_n` and a base of up to 12 formulas about those places.
fn base(max_n: usize) -> impl Strategy<Value = (usize, Vec<Formula>)> {
    (0..max_n).prop_flat_map(|n| {
        let formulas = if n == 0 {
            Just(Vec::new()).boxed()
        } else {
            prop::collection::vec(
                (any::<bool>(), 0..n, degree()).prop_map(|(pos, k, w)| {
                    if pos {
                        Formula::At(k, w)
                    } else {
                        Formula::NotAt(k, w)
                    }
                }),
                0..12,
            )
            .boxed()
        };
        (Just(n), formulas)
    })
}

fn assert_close_vec(got: &[f64], want: &[f64], what: &str) -> Result<(), TestCaseError> {
    prop_assert_eq!(got.len(), want.len(), "{}: length", what);
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        prop_assert!(close(*g, *w), "{}[{}]: got {}, want {}", what, k, g, w);
    }
    Ok(())
}

fn in_unit(x: f64) -> bool {
    (0.0..=1.0).contains(&x)
}

proptest! {
    // No regression files: the failing input is printed, and the tree stays clean.
    #![proptest_config(ProptestConfig {
        cases: 512,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    // -----------------------------------------------------------------------------------------
    // t-norms
    // -----------------------------------------------------------------------------------------

    #[test]
    fn tnorm_commutative(t in tnorm(), a in degree(), b in degree()) {
        prop_assert_eq!(t.apply(a, b), t.apply(b, a));
    }

    #[test]
    fn tnorm_associative(t in tnorm(), a in degree(), b in degree(), c in degree()) {
        let l = t.apply(t.apply(a, b), c);
        let r = t.apply(a, t.apply(b, c));
        prop_assert!(close(l, r), "{:?}: T(T(a,b),c) = {} ≠ T(a,T(b,c)) = {}", t, l, r);
    }

    #[test]
    fn tnorm_monotone(t in tnorm(), a in degree(), a2 in degree(), b in degree()) {
        let (lo, hi) = if a <= a2 { (a, a2) } else { (a2, a) };
        prop_assert!(t.apply(lo, b) <= t.apply(hi, b) + EPS);
        prop_assert!(t.apply(b, lo) <= t.apply(b, hi) + EPS);
    }

    #[test]
    fn tnorm_identity_and_annihilator(t in tnorm(), a in degree()) {
        prop_assert!(close(t.apply(a, 1.0), a), "{:?}: T({}, 1) = {}", t, a, t.apply(a, 1.0));
        prop_assert!(close(t.apply(1.0, a), a));
        prop_assert_eq!(t.apply(a, 0.0), 0.0);
        prop_assert_eq!(t.apply(0.0, a), 0.0);
    }

    /// Every t-norm lies below min (the largest t-norm) and stays in [0, 1].
    #[test]
    fn tnorm_bounded_by_min(t in tnorm(), a in degree(), b in degree()) {
        let v = t.apply(a, b);
        prop_assert!(in_unit(v));
        prop_assert!(v <= a.min(b) + EPS);
    }

    /// DESIGN §3: paper 003's `max` of dissimilarities δ is our `min` of confidences 1 − δ.
    #[test]
    fn paper_max_of_dissimilarities_is_min_of_confidences(da in degree(), db in degree()) {
        prop_assert_eq!(TNorm::Min.apply(1.0 - da, 1.0 - db), 1.0 - da.max(db));
    }

    // -----------------------------------------------------------------------------------------
    // t-conorms
    // -----------------------------------------------------------------------------------------

    #[test]
    fn conorm_is_dual(t in tnorm(), a in degree(), b in degree()) {
        let s = t.conorm(a, b);
        let dual = 1.0 - t.apply(1.0 - a, 1.0 - b);
        prop_assert!(
            close(s, dual),
            "{:?}: S({}, {}) = {} but 1 − T(1−a, 1−b) = {}", t, a, b, s, dual
        );
    }

    #[test]
    fn conorm_axioms(t in tnorm(), a in degree(), a2 in degree(), b in degree(), c in degree()) {
        prop_assert_eq!(t.conorm(a, b), t.conorm(b, a));
        let l = t.conorm(t.conorm(a, b), c);
        let r = t.conorm(a, t.conorm(b, c));
        prop_assert!(close(l, r), "{:?}: not associative: {} vs {}", t, l, r);
        let (lo, hi) = if a <= a2 { (a, a2) } else { (a2, a) };
        prop_assert!(t.conorm(lo, b) <= t.conorm(hi, b) + EPS);
        prop_assert!(close(t.conorm(a, 0.0), a), "{:?}: S({}, 0) = {}", t, a, t.conorm(a, 0.0));
        prop_assert!(close(t.conorm(a, 1.0), 1.0));
        let s = t.conorm(a, b);
        prop_assert!(in_unit(s) && s + EPS >= a.max(b));
    }

    // -----------------------------------------------------------------------------------------
    // Residua
    // -----------------------------------------------------------------------------------------

    /// The adjunction `T(a, z) ≤ b ⇔ z ≤ R(a, b)`, made tolerance-aware: away from the boundary by
    /// more than ε it must hold exactly in both directions, and the supremum is attained
    /// (`T(a, R(a, b)) ≤ b`, up to rounding) since all three t-norms are continuous.
    #[test]
    fn residuation_adjunction(t in tnorm(), a in degree(), b in degree(), z in degree()) {
        const E: f64 = 1e-9;
        let r = t.residuum(a, b);
        prop_assert!(in_unit(r), "{:?}: R({}, {}) = {}", t, a, b, r);
        let tz = t.apply(a, z);
        if z <= r - E {
            prop_assert!(
                tz <= b + EPS,
                "{:?}: z = {} ≤ R = {} but T(a, z) = {} > b = {}", t, z, r, tz, b
            );
        }
        if z >= r + E {
            prop_assert!(
                tz > b,
                "{:?}: z = {} > R = {} but T(a, z) = {} ≤ b = {}", t, z, r, tz, b
            );
        }
        let at_r = t.apply(a, r);
        prop_assert!(at_r <= b + EPS, "{:?}: T(a, R(a, b)) = {} > b = {}", t, at_r, b);
        // … and it is the supremum: just above R the t-norm already exceeds b.
        if r + E <= 1.0 {
            prop_assert!(
                t.apply(a, r + E) > b,
                "{:?}: T(a, R + ε) ≤ b: R({}, {}) = {} too small", t, a, b, r
            );
        }
    }

    /// `R(a, b) = 1` iff `a ≤ b`. The "only if" half is checked where `a` exceeds `b` by more
    /// than rounding can hide (`1 − a + b` rounds to 1 when `a − b` is below half an ulp of 1).
    #[test]
    fn residuum_is_one_iff_a_le_b(t in tnorm(), a in degree(), b in degree()) {
        let r = t.residuum(a, b);
        if a <= b {
            prop_assert_eq!(r, 1.0);
        } else if a - b > 1e-9 {
            prop_assert!(r < 1.0, "{:?}: R({}, {}) = 1 although a > b", t, a, b);
        }
    }

    /// The residuum is antitone in its first and monotone in its second argument.
    #[test]
    fn residuum_monotonicity(
        t in tnorm(),
        a in degree(),
        a2 in degree(),
        b in degree(),
        b2 in degree(),
    ) {
        let (alo, ahi) = if a <= a2 { (a, a2) } else { (a2, a) };
        let (blo, bhi) = if b <= b2 { (b, b2) } else { (b2, b) };
        prop_assert!(t.residuum(ahi, b) <= t.residuum(alo, b) + EPS);
        prop_assert!(t.residuum(a, blo) <= t.residuum(a, bhi) + EPS);
    }

    // -----------------------------------------------------------------------------------------
    // The place distribution against brute-force enumeration over worlds
    // -----------------------------------------------------------------------------------------

    #[test]
    fn distribution_matches_brute_force((n, formulas) in base(8), norm in normalisation()) {
        let d = distribution(n, &formulas, norm);
        let r = reference(n, &formulas, norm);
        assert_close_vec(&d.possibility_raw, &r.pi, "π")?;
        prop_assert!(close(d.height, r.height), "h: got {}, want {}", d.height, r.height);
        prop_assert!(close(d.inconsistency, r.inconsistency),
            "Inc: got {}, want {}", d.inconsistency, r.inconsistency);
        assert_close_vec(&d.possibility, &r.pi_norm, "π'")?;
        assert_close_vec(&d.possibility, &r.poss, "Π")?;
        assert_close_vec(&d.necessity, &r.nec, "N")?;
    }

    /// Every quantity stays in [0, 1], nothing is NaN, a normalised distribution reaches 1
    /// somewhere, and N ≤ Π for every place of a map with at least two places.
    #[test]
    fn distribution_in_range((n, formulas) in base(10), norm in normalisation()) {
        let d = distribution(n, &formulas, norm);
        for v in d.possibility_raw.iter().chain(&d.possibility).chain(&d.necessity)
            .chain([&d.height, &d.inconsistency])
        {
            prop_assert!(in_unit(*v), "out of range or NaN: {} in {:?}", v, d);
        }
        prop_assert!(close(d.height + d.inconsistency, 1.0));
        if n > 0 {
            prop_assert!(d.possibility.contains(&1.0), "not normalised: {:?}", d);
        }
        if n >= 2 {
            for k in 0..n {
                prop_assert!(d.necessity[k] <= d.possibility[k] + EPS);
            }
        }
    }

    /// Permuting the places permutes π, Π and N and leaves h and Inc alone; the decision keeps
    /// its kind, and when the best place is unique it is the same place under its new index.
    #[test]
    fn order_independence(
        (n, formulas, perm) in base(8).prop_flat_map(|(n, f)| {
            (Just(n), Just(f), Just((0..n).collect::<Vec<_>>()).prop_shuffle())
        }),
        norm in normalisation(),
        threshold in degree(),
    ) {
        // Place k is renamed perm[k].
        let renamed: Vec<Formula> = formulas
            .iter()
            .map(|f| match *f {
                Formula::At(j, a) => Formula::At(perm[j], a),
                Formula::NotAt(k, b) => Formula::NotAt(perm[k], b),
            })
            .collect();
        let d = distribution(n, &formulas, norm);
        let e = distribution(n, &renamed, norm);
        prop_assert_eq!(d.height, e.height);
        prop_assert_eq!(d.inconsistency, e.inconsistency);
        for (k, &pk) in perm.iter().enumerate() {
            prop_assert_eq!(d.possibility_raw[k], e.possibility_raw[pk]);
            prop_assert_eq!(d.possibility[k], e.possibility[pk]);
            prop_assert_eq!(d.necessity[k], e.necessity[pk]);
        }
        let p = DecisionParams { threshold, margin: 0.0 };
        let (x, y) = (decide(&d, p), decide(&e, p));
        prop_assert_eq!(std::mem::discriminant(&x), std::mem::discriminant(&y));
        if let (
            Decision::Place { place: a, necessity: na },
            Decision::Place { place: b, necessity: nb },
        ) = (x, y)
        {
            prop_assert_eq!(na, nb);
            let unique = d.necessity.iter().filter(|&&v| v == na).count() == 1;
            if unique {
                prop_assert_eq!(perm[a], b);
            }
        }
    }

    // -----------------------------------------------------------------------------------------
    // The decision
    // -----------------------------------------------------------------------------------------

    /// `decide` never panics, and its outcome agrees with the documented procedure: a place is
    /// chosen exactly when the best necessity reaches the threshold and exceeds Inc by more than
    /// the margin; the chosen place has the highest necessity; each disoriented reason holds.
    /// "Reaches" and "exceeds" are up to the documented tie tolerance `TIE`, written out here.
    #[test]
    fn decision_contract(
        (n, formulas) in base(10),
        norm in normalisation(),
        threshold in degree(),
        margin in prop_oneof![Just(0.0), 0.0..=0.5f64],
    ) {
        let d = distribution(n, &formulas, norm);
        let p = DecisionParams { threshold, margin };
        let outcome = decide(&d, p);
        let inc = d.inconsistency;
        let max_n = d.necessity.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let reaches = |x: f64| x >= threshold - TIE;
        let should_choose = n > 0 && reaches(max_n) && max_n - inc > margin + TIE;
        prop_assert_eq!(outcome.place().is_some(), should_choose, "{:?} for {:?}", outcome, d);
        match outcome {
            Decision::Place { place, necessity } => {
                prop_assert!(place < n);
                prop_assert_eq!(necessity, d.necessity[place]);
                prop_assert!(reaches(necessity));
                prop_assert!(necessity - inc > margin + TIE);
                prop_assert_eq!(necessity, max_n);
            }
            Decision::Disoriented(Disoriented::NoPlaces) => prop_assert_eq!(n, 0),
            Decision::Disoriented(Disoriented::Inconsistent { inconsistency }) => {
                prop_assert_eq!(inconsistency, inc);
                // Either the conflict is strong, or a lone place failed only the margin over Inc
                // (decision.rs: with one place there is no runner-up to be too close to).
                prop_assert!(reaches(inc) || (n == 1 && max_n - inc <= margin + TIE));
            }
            Decision::Disoriented(Disoriented::NothingAboveThreshold { best, support }) => {
                prop_assert!(best < n);
                prop_assert_eq!(support, d.support[best]);
                prop_assert!(d.support.iter().all(|&s| !reaches(s)));
                prop_assert!(!reaches(max_n));
            }
            Decision::Disoriented(Disoriented::TooClose { best, runner_up, necessity }) => {
                prop_assert!(best < n && runner_up < n);
                prop_assert_eq!(necessity, max_n);
                prop_assert_eq!(necessity, d.necessity[best]);
                prop_assert!(!reaches(inc));
                // The runner-up is another place, the most possible of the others.
                if n >= 2 {
                    prop_assert_ne!(best, runner_up);
                    let best_other = (0..n)
                        .filter(|&k| k != best)
                        .map(|k| d.possibility[k])
                        .fold(f64::NEG_INFINITY, f64::max);
                    prop_assert_eq!(d.possibility[runner_up], best_other);
                }
            }
        }
    }

    // -----------------------------------------------------------------------------------------
    // clamp_degree and Similarity
    // -----------------------------------------------------------------------------------------

    #[test]
    fn clamp_degree_lands_in_unit_interval(
        x in prop_oneof![
            Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY),
            Just(f64::MAX), Just(f64::MIN), Just(-0.0),
            any::<f64>(), -10.0..10.0f64,
        ],
    ) {
        let c = clamp_degree(x);
        prop_assert!(in_unit(c), "clamp_degree({}) = {}", x, c);
        if in_unit(x) {
            prop_assert_eq!(c, x);
        } else if x > 1.0 {
            prop_assert_eq!(c, 1.0);
        } else {
            // Below 0, −∞ or NaN: no support.
            prop_assert_eq!(c, 0.0);
        }
    }

    /// μ stays between the bias and the height, is symmetric about the centre, does not increase
    /// with distance, and equals the bias for any non-finite reading.
    #[test]
    fn trapezoid_shape(
        core in 0.0..20.0f64,
        slope in prop_oneof![Just(0.0), 0.0..20.0f64],
        h in degree(),
        bias_frac in degree(),
        centre in -100.0..100.0f64,
        d1 in 0.0..60.0f64,
        d2 in 0.0..60.0f64,
    ) {
        let t = Similarity::new(core, slope, h, h * bias_frac, None);
        let (near, far) = if d1 <= d2 { (d1, d2) } else { (d2, d1) };
        let mu = |x: f64| t.degree(x, centre);
        for x in [centre + near, centre - near, centre + far] {
            let m = mu(x);
            prop_assert!(
                m >= t.shape.bias - EPS && m <= h + EPS,
                "μ({}) = {} outside [{}, {}]", x, m, t.shape.bias, h
            );
        }
        prop_assert!((mu(centre + near) - mu(centre - near)).abs() <= 1e-9);
        // Distances measured from centre 0 so that no rounding blurs their order.
        prop_assert!(t.degree(far, 0.0) <= t.degree(near, 0.0) + EPS);
        // b + (h − b)·1 need not round back to exactly h.
        prop_assert!(close(t.degree(centre, centre), h));
        prop_assert_eq!(t.degree(f64::NAN, centre), t.shape.bias);
        prop_assert_eq!(t.degree(f64::INFINITY, centre), t.shape.bias);
    }

    /// A circular trapezoid (period 360) cannot tell x from x + 360·k, and its value depends only
    /// on the distance around the circle.
    #[test]
    fn trapezoid_circular_wraps(
        core in 0.0..90.0f64,
        slope in 0.0..90.0f64,
        centre in 0.0..360.0f64,
        x in 0.0..360.0f64,
        turns in -3i32..=3,
    ) {
        let t = Similarity::new(core, slope, 1.0, 0.0, Some(360.0));
        let a = t.degree(x, centre);
        let b = t.degree(x + 360.0 * f64::from(turns), centre);
        prop_assert!(
            (a - b).abs() <= 1e-9,
            "μ({}) = {} but μ({} + 360·{}) = {}", x, a, x, turns, b
        );
        // Same value as the linear trapezoid at the circular distance.
        let lin = Similarity { period: None, ..t };
        let raw = (x - centre).abs();
        let circ = raw.min(360.0 - raw);
        prop_assert!((a - lin.degree(circ, 0.0)).abs() <= 1e-9);
    }
}

// ---------------------------------------------------------------------------------------------
// Sets of places, fusion and conditioning against brute-force enumeration
// ---------------------------------------------------------------------------------------------

/// A weighted formula about a set of places: `(S, w)` or `(¬S, w)`, with `S` given as the
/// membership of each world.
#[derive(Debug, Clone)]
struct SetFormula {
    members: Vec<bool>,
    negated: bool,
    weight: f64,
}

impl SetFormula {
    fn holds_in(&self, w: usize) -> bool {
        self.members[w] != self.negated
    }
}

/// π(w) = min over the set formulas `w` falsifies of (1 − weight), by enumeration.
fn set_reference(n: usize, base: &[SetFormula]) -> Vec<f64> {
    (0..n)
        .map(|w| {
            base.iter()
                .filter(|f| !f.holds_in(w))
                .map(|f| 1.0 - f.weight)
                .fold(1.0, f64::min)
        })
        .collect()
}

/// The crate's route: no singleton evidence, then one `constrain` per formula.
fn set_distribution(n: usize, base: &[SetFormula]) -> PlaceDistribution {
    let mut d = PlaceDistribution::new(n);
    d.fill_raw();
    for f in base {
        let set = PlaceSet::from_indices(n, (0..n).filter(|&k| f.members[k]));
        d.constrain(&set, f.weight, f.negated);
    }
    d
}

/// Normalises by enumeration (the textbook definitions of `reference` above).
fn normalise_reference(pi: &[f64], norm: Normalisation) -> Vec<f64> {
    let h = possibility_of(pi, |_| true);
    pi.iter()
        .map(|&p| match norm {
            _ if h == 0.0 => 1.0,
            Normalisation::Min => {
                if p == h {
                    1.0
                } else {
                    p
                }
            }
            Normalisation::Product => p / h,
        })
        .collect()
}

fn set_base(n: usize) -> impl Strategy<Value = Vec<SetFormula>> {
    prop::collection::vec(
        (
            prop::collection::vec(any::<bool>(), n),
            any::<bool>(),
            degree(),
        )
            .prop_map(|(members, negated, weight)| SetFormula {
                members,
                negated,
                weight,
            }),
        0..8,
    )
}

/// Places, two bases, a query set and a known region (membership per place).
type SetsCase = (
    usize,
    Vec<SetFormula>,
    Vec<SetFormula>,
    Vec<bool>,
    Vec<bool>,
);

/// Membership of a world in a set, written independently of `PlaceSet`.
type Membership<'a> = Box<dyn Fn(usize) -> bool + 'a>;

fn sets_case() -> impl Strategy<Value = SetsCase> {
    (1usize..7).prop_flat_map(|n| {
        (
            Just(n),
            set_base(n),
            set_base(n),
            prop::collection::vec(any::<bool>(), n),
            prop::collection::vec(any::<bool>(), n),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 512,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Set heads, both fusions, conditioning on a region, and Π / N of any set (and of its
    /// complement, of intersections and unions), each against enumeration over the worlds.
    #[test]
    fn sets_fusion_conditioning_match_brute_force(
        (n, base1, base2, query, known) in sets_case(),
        norm in normalisation(),
        product in any::<bool>(),
        conditioned in any::<bool>(),
    ) {
        let fusion = if product { Fusion::Product } else { Fusion::Min };
        // Reference: each group's π by enumeration, fused world by world, then restricted.
        let (p1, p2) = (set_reference(n, &base1), set_reference(n, &base2));
        let mut pi: Vec<f64> = p1.iter().zip(&p2).map(|(a, b)| match fusion {
            Fusion::Min => a.min(*b),
            Fusion::Product => a * b,
        }).collect();
        if conditioned {
            for (w, p) in pi.iter_mut().enumerate() {
                if !known[w] {
                    *p = 0.0;
                }
            }
        }
        let pi_norm = normalise_reference(&pi, norm);
        let height = possibility_of(&pi, |_| true);

        // The crate.
        let mut d = set_distribution(n, &base1);
        let g2 = set_distribution(n, &base2);
        d.fuse(&g2.possibility_raw, fusion);
        let known_set = PlaceSet::from_indices(n, (0..n).filter(|&k| known[k]));
        if conditioned {
            d.condition(&known_set);
        }
        d.finish(norm);
        assert_close_vec(&d.possibility_raw, &pi, "π")?;
        prop_assert!(close(d.inconsistency, 1.0 - height));
        assert_close_vec(&d.possibility, &pi_norm, "π'")?;

        let s = PlaceSet::from_indices(n, (0..n).filter(|&k| query[k]));
        let poss = |a: &dyn Fn(usize) -> bool| possibility_of(&pi_norm, a);
        let cases: [(PlaceSet, Membership); 4] = [
            (s.clone(), Box::new(|w| query[w])),
            (s.complement(), Box::new(|w| !query[w])),
            (s.intersection(&known_set), Box::new(|w| query[w] && known[w])),
            (s.union(&known_set), Box::new(|w| query[w] || known[w])),
        ];
        for (set, member) in &cases {
            let want_pi = poss(&|w| member(w));
            let want_n = 1.0 - poss(&|w| !member(w));
            prop_assert!(close(d.set_possibility(set), want_pi), "Π: got {}, want {}", d.set_possibility(set), want_pi);
            prop_assert!(close(d.set_necessity(set), want_n), "N: got {}, want {}", d.set_necessity(set), want_n);
        }
    }
}
