//! Hand-worked possibilistic cases for `lplace::logic` (DESIGN §3): the inconsistency degree of
//! small weighted bases over mutually exclusive places, min- versus product-based normalisation,
//! each outcome of the threshold decision, the drowning effect, the residuated and Kleene–Dienes
//! implications, the two readings of `->`, and the trapezoidal similarity.
//!
//! Every expected number is worked out by hand in the comments next to it, from the textbook
//! definitions (π(w) = min over the formulas that world w falsifies of 1 − weight; h = max π;
//! Inc = 1 − h; N(A) = 1 − Π(¬A)), never copied from the code's output. Comparisons use a 1e-12
//! tolerance because decimal weights such as 0.3 are not exact in binary.

use lplace::logic::{
    clamp_degree, decide, Decision, DecisionParams, Disoriented, Implication, LogicConfig,
    Normalisation, PlaceDistribution, Similarity, TNorm,
};

const EPS: f64 = 1e-12;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < EPS
}

fn assert_all_close(got: &[f64], want: &[f64], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: length");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(close(*g, *w), "{what}[{k}]: got {g}, want {w}");
    }
}

/// A distribution with the given supports `α` (for `at_place`) and exclusions `β` (for
/// `!at_place`).
fn dist(alpha: &[f64], beta: &[f64], norm: Normalisation) -> PlaceDistribution {
    let mut d = PlaceDistribution::new(alpha.len());
    d.support.copy_from_slice(alpha);
    d.exclusion.copy_from_slice(beta);
    d.update(norm);
    d
}

fn params(threshold: f64, margin: f64) -> DecisionParams {
    DecisionParams { threshold, margin }
}

/// Necessity of `at_place(P_k)` under the *unnormalised* distribution: 1 − max_{j≠k} π_j.
/// Textbook possibilistic entailment degree of the base, before any normalisation.
fn raw_necessity(d: &PlaceDistribution, k: usize) -> f64 {
    let others = d
        .possibility_raw
        .iter()
        .enumerate()
        .filter(|&(j, _)| j != k)
        .map(|(_, &p)| p)
        .fold(0.0, f64::max);
    1.0 - others
}

// ---------------------------------------------------------------------------------------------
// Inconsistency degree of a weighted base
// ---------------------------------------------------------------------------------------------

/// Base {(at_place(P0), 0.8), (at_place(P1), 0.6), (¬at_place(P2), 0.3)} over three exclusive
/// places. World w = "the robot is at P_w".
///
/// - w = 0 falsifies only at_place(P1):                     π_0 = 1 − 0.6 = 0.4
/// - w = 1 falsifies only at_place(P0):                     π_1 = 1 − 0.8 = 0.2
/// - w = 2 falsifies P0 (0.2), P1 (0.4) and ¬P2 (0.7):      π_2 = min(0.2, 0.4, 0.7) = 0.2
///
/// h = max(0.4, 0.2, 0.2) = 0.4, Inc = 1 − 0.4 = 0.6.
#[test]
fn inconsistency_of_a_small_weighted_base() {
    let d = dist(&[0.8, 0.6, 0.0], &[0.0, 0.0, 0.3], Normalisation::Min);
    assert_all_close(&d.possibility_raw, &[0.4, 0.2, 0.2], "π");
    assert!(close(d.height, 0.4), "h = {}", d.height);
    assert!(close(d.inconsistency, 0.6), "Inc = {}", d.inconsistency);
}

/// A consistent base has Inc = 0: {(at_place(P0), 0.7), (¬at_place(P1), 0.4)} over three places.
///
/// - w = 0 satisfies both formulas:                         π_0 = 1
/// - w = 1 falsifies P0 (0.3) and ¬P1 (0.6):                π_1 = 0.3
/// - w = 2 falsifies P0:                                    π_2 = 0.3
///
/// h = 1, Inc = 0; both normalisations leave π unchanged, so N_0 = 1 − 0.3 = 0.7 and
/// N_1 = N_2 = 1 − π_0 = 0 either way.
#[test]
fn consistent_base_has_zero_inconsistency() {
    for norm in [Normalisation::Min, Normalisation::Product] {
        let d = dist(&[0.7, 0.0, 0.0], &[0.0, 0.4, 0.0], norm);
        assert_all_close(&d.possibility_raw, &[1.0, 0.3, 0.3], "π");
        assert_eq!(d.height, 1.0);
        assert_eq!(d.inconsistency, 0.0);
        assert_all_close(&d.possibility, &[1.0, 0.3, 0.3], "π'");
        assert_all_close(&d.necessity, &[0.7, 0.0, 0.0], "N");
    }
}

/// With no evidence at all every place is fully possible and nothing is necessary.
#[test]
fn no_evidence_is_total_ignorance() {
    let d = PlaceDistribution::new(4);
    assert_all_close(&d.possibility, &[1.0; 4], "Π");
    assert_all_close(&d.necessity, &[0.0; 4], "N");
    assert_eq!(d.inconsistency, 0.0);
}

/// A one-place map: the only world is the robot's, so N_0 = 1 − max(∅) = 1 whatever the
/// exclusion; an exclusion of 0.25 only lowers π_0 to 0.75, so Inc = 0.25.
/// An empty map: h = max(∅) = 0, Inc = 1.
#[test]
fn one_place_and_no_place() {
    let d = dist(&[0.0], &[0.25], Normalisation::Min);
    assert!(close(d.possibility_raw[0], 0.75));
    assert!(close(d.inconsistency, 0.25));
    assert_eq!(d.necessity[0], 1.0);
    let d = dist(&[], &[], Normalisation::Product);
    assert_eq!(d.height, 0.0);
    assert_eq!(d.inconsistency, 1.0);
    assert_eq!(
        decide(&d, params(0.5, 0.0)),
        Decision::Disoriented(Disoriented::NoPlaces)
    );
}

// ---------------------------------------------------------------------------------------------
// Min- versus product-based normalisation
// ---------------------------------------------------------------------------------------------

/// Same base as `inconsistency_of_a_small_weighted_base`: π = (0.4, 0.2, 0.2), h = 0.4.
///
/// Min-based:     π' = (1, 0.2, 0.2)            (only the worlds at height are raised to 1)
///                N_0 = 1 − max(0.2, 0.2) = 0.8, N_1 = N_2 = 1 − 1 = 0
/// Product-based: π' = (0.4, 0.2, 0.2) / 0.4 = (1, 0.5, 0.5)
///                N_0 = 1 − 0.5 = 0.5,          N_1 = N_2 = 0
#[test]
fn min_and_product_normalisation_differ() {
    let alpha = [0.8, 0.6, 0.0];
    let beta = [0.0, 0.0, 0.3];
    let m = dist(&alpha, &beta, Normalisation::Min);
    assert_all_close(&m.possibility, &[1.0, 0.2, 0.2], "min π'");
    assert_all_close(&m.necessity, &[0.8, 0.0, 0.0], "min N");
    let p = dist(&alpha, &beta, Normalisation::Product);
    assert_all_close(&p.possibility, &[1.0, 0.5, 0.5], "product π'");
    assert_all_close(&p.necessity, &[0.5, 0.0, 0.0], "product N");
    // Normalisation never changes π, h or Inc.
    assert_eq!(m.possibility_raw, p.possibility_raw);
    assert_eq!(m.inconsistency, p.inconsistency);
}

/// Two places tie at the height: α = (0.7, 0.7, 0.1) over three places.
///
/// π_0 = 1 − max(0.7, 0.1) = 0.3, π_1 = 0.3, π_2 = 1 − 0.7 = 0.3 → h = 0.3, Inc = 0.7.
/// All three worlds sit at the height, so both normalisations give π' = (1, 1, 1) and N = 0.
#[test]
fn ties_at_the_height_leave_nothing_necessary() {
    for norm in [Normalisation::Min, Normalisation::Product] {
        let d = dist(&[0.7, 0.7, 0.1], &[0.0; 3], norm);
        assert_all_close(&d.possibility_raw, &[0.3, 0.3, 0.3], "π");
        assert!(close(d.inconsistency, 0.7));
        assert_all_close(&d.possibility, &[1.0, 1.0, 1.0], "π'");
        assert_all_close(&d.necessity, &[0.0, 0.0, 0.0], "N");
    }
}

/// Total inconsistency on two places, α = (1, 1): π_0 = 1 − 1 = 0, π_1 = 0, h = 0, Inc = 1.
/// Product-based normalisation cannot divide by h = 0; the documented convention is π' = 1
/// everywhere, so N = 0, and no NaN.
#[test]
fn total_inconsistency_has_no_nan() {
    for norm in [Normalisation::Min, Normalisation::Product] {
        let d = dist(&[1.0, 1.0], &[0.0, 0.0], norm);
        assert_eq!(d.height, 0.0);
        assert_eq!(d.inconsistency, 1.0);
        assert_all_close(&d.possibility, &[1.0, 1.0], "π'");
        assert_all_close(&d.necessity, &[0.0, 0.0], "N");
        assert_eq!(
            decide(&d, params(0.5, 0.0)),
            Decision::Disoriented(Disoriented::Inconsistent { inconsistency: 1.0 })
        );
    }
}

// ---------------------------------------------------------------------------------------------
// The decision
// ---------------------------------------------------------------------------------------------

/// The brief's base with threshold 0.5, margin 0 and min-based normalisation:
/// N_0 = 0.8 ≥ 0.5 and N_0 − Inc = 0.8 − 0.6 = 0.2 > 0 → P0 is chosen with necessity 0.8.
#[test]
fn decision_chooses_when_necessity_clears_threshold_and_inconsistency() {
    let d = dist(&[0.8, 0.6, 0.0], &[0.0, 0.0, 0.3], Normalisation::Min);
    match decide(&d, params(0.5, 0.0)) {
        Decision::Place { place, necessity } => {
            assert_eq!(place, 0);
            assert!(close(necessity, 0.8), "N = {necessity}");
        }
        other => panic!("expected P0 to be chosen, got {other:?}"),
    }
}

/// Weak evidence: α = (0.3, 0.2, 0.1), threshold 0.5, margin 0, min-based.
///
/// π_0 = 1 − max(0.2, 0.1) = 0.8, π_1 = 1 − max(0.3, 0.1) = 0.7, π_2 = 1 − 0.3 = 0.7;
/// h = 0.8, Inc = 0.2; π' = (1, 0.7, 0.7); N = (0.3, 0, 0).
/// Step 1: N_0 = 0.3 < 0.5. Step 2: Inc = 0.2 < 0.5. Step 3: N_0 < 0.5. Step 4: every support
/// is < 0.5 → NothingAboveThreshold, best = P0 with support 0.3.
#[test]
fn decision_nothing_above_threshold() {
    let d = dist(&[0.3, 0.2, 0.1], &[0.0; 3], Normalisation::Min);
    assert_all_close(&d.necessity, &[0.3, 0.0, 0.0], "N");
    assert!(close(d.inconsistency, 0.2));
    match decide(&d, params(0.5, 0.0)) {
        Decision::Disoriented(Disoriented::NothingAboveThreshold { best, support }) => {
            assert_eq!(best, 0);
            assert!(close(support, 0.3));
        }
        other => panic!("expected NothingAboveThreshold, got {other:?}"),
    }
}

/// Failing only the margin over Inc (step 3): α = (0.7, 0.3), threshold 0.5, margin 0.5.
///
/// π_0 = 1 − 0.3 = 0.7, π_1 = 1 − 0.7 = 0.3; h = 0.7, Inc = 0.3; π' = (1, 0.3); N_0 = 0.7.
/// Step 1: 0.7 ≥ 0.5 but 0.7 − 0.3 = 0.4 ≤ 0.5. Step 2: Inc = 0.3 < 0.5. Step 3: N_0 ≥ 0.5 →
/// TooClose with best P0, runner-up P1 (the only other place), necessity 0.7.
#[test]
fn decision_too_close_by_margin() {
    let d = dist(&[0.7, 0.3], &[0.0; 2], Normalisation::Min);
    match decide(&d, params(0.5, 0.5)) {
        Decision::Disoriented(Disoriented::TooClose {
            best,
            runner_up,
            necessity,
        }) => {
            assert_eq!((best, runner_up), (0, 1));
            assert!(close(necessity, 0.7));
        }
        other => panic!("expected TooClose, got {other:?}"),
    }
}

/// A runner-up that stays too possible (step 5), and the same base decided differently by the two
/// normalisations: α = (0.6, 0.3, 0), threshold 0.5, margin 0.
///
/// π_0 = 1 − 0.3 = 0.7, π_1 = 1 − 0.6 = 0.4, π_2 = 0.4; h = 0.7, Inc = 0.3.
/// Min-based:     π' = (1, 0.4, 0.4), N_0 = 0.6 ≥ 0.5 and 0.6 − 0.3 > 0 → P0 chosen.
/// Product-based: π' = (1, 4/7, 4/7), N_0 = 3/7 ≈ 0.43 < 0.5; Inc < 0.5; yet α_0 = 0.6 ≥ 0.5, so
/// it is not "nothing above threshold" → TooClose; the runner-up is P1 (Π_1 = Π_2 = 4/7, tie
/// broken by the higher support 0.3 > 0).
#[test]
fn decision_too_close_runner_up_and_normalisation_matters() {
    let alpha = [0.6, 0.3, 0.0];
    let m = dist(&alpha, &[0.0; 3], Normalisation::Min);
    assert_all_close(&m.necessity, &[0.6, 0.0, 0.0], "min N");
    assert_eq!(decide(&m, params(0.5, 0.0)).place(), Some(0));

    let p = dist(&alpha, &[0.0; 3], Normalisation::Product);
    assert_all_close(&p.possibility, &[1.0, 4.0 / 7.0, 4.0 / 7.0], "product π'");
    assert_all_close(&p.necessity, &[3.0 / 7.0, 0.0, 0.0], "product N");
    match decide(&p, params(0.5, 0.0)) {
        Decision::Disoriented(Disoriented::TooClose {
            best,
            runner_up,
            necessity,
        }) => {
            assert_eq!((best, runner_up), (0, 1));
            assert!(close(necessity, 3.0 / 7.0));
        }
        other => panic!("expected TooClose, got {other:?}"),
    }
}

/// Inconsistent evidence (step 2).
///
/// (a) α = (0.8, 0.8, 0): π = (0.2, 0.2, 0.2), h = 0.2, Inc = 0.8; all π' = 1, N = 0.
///     Step 1 fails (N = 0); Inc = 0.8 ≥ 0.5 → Inconsistent{0.8}.
/// (b) The brief's base (Inc = 0.6, N_0 = 0.8) with margin 0.3: 0.8 − 0.6 = 0.2 ≤ 0.3, and
///     Inc = 0.6 ≥ 0.5 → Inconsistent{0.6}.
#[test]
fn decision_inconsistent() {
    let d = dist(&[0.8, 0.8, 0.0], &[0.0; 3], Normalisation::Min);
    match decide(&d, params(0.5, 0.0)) {
        Decision::Disoriented(Disoriented::Inconsistent { inconsistency }) => {
            assert!(close(inconsistency, 0.8));
        }
        other => panic!("expected Inconsistent, got {other:?}"),
    }
    let d = dist(&[0.8, 0.6, 0.0], &[0.0, 0.0, 0.3], Normalisation::Min);
    match decide(&d, params(0.5, 0.3)) {
        Decision::Disoriented(Disoriented::Inconsistent { inconsistency }) => {
            assert!(close(inconsistency, 0.6));
        }
        other => panic!("expected Inconsistent, got {other:?}"),
    }
}

/// With product-based normalisation a necessity can reach the threshold yet not exceed Inc:
/// α = (0.6, 0.5): π_0 = 0.5, π_1 = 0.4, h = 0.5, Inc = 0.5; π' = (1, 0.8), N_0 = 0.2.
/// Threshold 0.2: N_0 ≥ 0.2 but N_0 − Inc = −0.3 ≤ 0, so P0 must not be chosen; Inc ≥ 0.2 →
/// Inconsistent{0.5}.
#[test]
fn decision_refuses_a_necessity_below_inconsistency() {
    let d = dist(&[0.6, 0.5], &[0.0; 2], Normalisation::Product);
    assert_all_close(&d.necessity, &[0.2, 0.0], "N");
    assert!(close(d.inconsistency, 0.5));
    match decide(&d, params(0.2, 0.0)) {
        Decision::Disoriented(Disoriented::Inconsistent { inconsistency }) => {
            assert!(close(inconsistency, 0.5));
        }
        other => panic!("expected Inconsistent, got {other:?}"),
    }
}

/// The best place is the one of highest necessity. α = (0, 0, 0, 0.05), β = (0.9, 0, 0.9, 0):
/// π_0 = min(1 − 0.05, 1 − 0.9) = 0.1, π_1 = 1 − 0.05 = 0.95, π_2 = 0.1, π_3 = 1 − 0 = 1;
/// h = 1, Inc = 0, π' = π; N_3 = 1 − 0.95 = 0.05, N_0 = N_1 = N_2 = 1 − 1 = 0.
/// Threshold 0.01: N_3 ≥ 0.01 and 0.05 − 0 > 0 → P3 chosen.
#[test]
fn decision_best_is_highest_necessity() {
    let d = dist(
        &[0.0, 0.0, 0.0, 0.05],
        &[0.9, 0.0, 0.9, 0.0],
        Normalisation::Min,
    );
    assert_all_close(&d.possibility, &[0.1, 0.95, 0.1, 1.0], "π'");
    assert_all_close(&d.necessity, &[0.0, 0.0, 0.0, 0.05], "N");
    assert_eq!(decide(&d, params(0.01, 0.0)).place(), Some(3));
}

/// A place can be chosen with no support at all, by eliminating every other place:
/// α = 0, β = (0, 0.9, 0.9): π = (1, 0.1, 0.1), h = 1, Inc = 0, N_0 = 0.9 → P0 chosen.
#[test]
fn decision_by_elimination() {
    let d = dist(&[0.0; 3], &[0.0, 0.9, 0.9], Normalisation::Min);
    match decide(&d, params(0.5, 0.0)) {
        Decision::Place { place, necessity } => {
            assert_eq!(place, 0);
            assert!(close(necessity, 0.9));
        }
        other => panic!("expected P0, got {other:?}"),
    }
}

/// The module documents TooClose's runner-up as "the place other than b". On a one-place map
/// there is no other place, yet step 3 is reachable with a positive margin:
/// β_0 = 0.6 → π_0 = 0.4, h = 0.4, Inc = 0.6; N_0 = 1 (lone place). Threshold 0.9, margin 0.5:
/// step 1: 1 − 0.6 = 0.4 ≤ 0.5 fails; step 2: Inc = 0.6 < 0.9; step 3: N_0 = 1 ≥ 0.9 → TooClose,
/// whose runner-up can only be P0 itself. Whatever the outcome, it must not name the best place as
/// its own runner-up (a place cannot be "too close" to itself); the failure mode here is a
/// margin failure, i.e. inconsistency.
#[test]
fn decision_one_place_never_too_close_to_itself() {
    let d = dist(&[0.0], &[0.6], Normalisation::Min);
    assert_eq!(d.necessity[0], 1.0);
    assert!(close(d.inconsistency, 0.6));
    let outcome = decide(&d, params(0.9, 0.5));
    assert_eq!(
        outcome.place(),
        None,
        "1 − 0.6 = 0.4 does not clear margin 0.5"
    );
    if let Decision::Disoriented(Disoriented::TooClose {
        best, runner_up, ..
    }) = outcome
    {
        assert_ne!(
            best, runner_up,
            "TooClose names P{best} as its own runner-up: {outcome:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// The drowning effect
// ---------------------------------------------------------------------------------------------

/// A conclusion whose weight does not exceed Inc is trivial: the base entails even ⊥ at degree
/// Inc. Brief's base: π = (0.4, 0.2, 0.2), Inc = 0.6.
///
/// - Unnormalised: N(⊥) = 1 − max π = 0.6 = Inc;
///   N(at_place(P1)) = 1 − max(π_0, π_2) = 1 − 0.4 = 0.6 ≤ Inc → trivial (no better than ⊥);
///   N(at_place(P0)) = 1 − max(π_1, π_2) = 0.8 > Inc → a genuine conclusion.
/// - After normalisation P1 keeps nothing: N_1 = 0, and no threshold lets the decision pick it.
#[test]
fn drowning_effect_makes_weak_conclusions_trivial() {
    let d = dist(&[0.8, 0.6, 0.0], &[0.0, 0.0, 0.3], Normalisation::Min);
    assert!(close(raw_necessity(&d, 1), 0.6));
    assert!(raw_necessity(&d, 1) <= d.inconsistency + EPS);
    assert!(close(raw_necessity(&d, 0), 0.8));
    assert!(raw_necessity(&d, 0) > d.inconsistency);
    assert!(close(d.necessity[1], 0.0));
    for t in [0.0, 0.1, 0.3, 0.6, 0.9] {
        assert_ne!(decide(&d, params(t, 0.0)).place(), Some(1), "threshold {t}");
    }
}

/// A drowned formula has no effect: {(P0, 0.7), (P1, 0.7), (¬P2, 0.2)} over three places.
///
/// Without ¬P2: π = (0.3, 0.3, min(0.3, 0.3)) = (0.3, 0.3, 0.3), Inc = 0.7.
/// With ¬P2 (weight 0.2 ≤ 0.7): π_2 = min(0.3, 0.3, 1 − 0.2 = 0.8) = 0.3, unchanged, so Π, N and
/// the decision (Inconsistent{0.7}) are identical: N(¬P2) = 1 − Π_2 = 1 − 1 = 0.
#[test]
fn drowned_formula_changes_nothing() {
    let with = dist(&[0.7, 0.7, 0.0], &[0.0, 0.0, 0.2], Normalisation::Min);
    let without = dist(&[0.7, 0.7, 0.0], &[0.0, 0.0, 0.0], Normalisation::Min);
    assert_all_close(&with.possibility_raw, &[0.3, 0.3, 0.3], "π");
    assert_eq!(with.possibility, without.possibility);
    assert_eq!(with.necessity, without.necessity);
    assert!(close(1.0 - with.possibility[2], 0.0));
    let p = params(0.5, 0.0);
    assert_eq!(decide(&with, p), decide(&without, p));
    assert!(matches!(
        decide(&with, p),
        Decision::Disoriented(Disoriented::Inconsistent { .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// Connectives
// ---------------------------------------------------------------------------------------------

/// T(0.6, 0.7): min 0.6, product 0.42, Łukasiewicz 0.6 + 0.7 − 1 = 0.3.
/// S(0.6, 0.7): max 0.7, probabilistic sum 0.6 + 0.7 − 0.42 = 0.88, bounded min(1, 1.3) = 1.
/// Łukasiewicz T(0.3, 0.4) = max(0, −0.3) = 0.
#[test]
fn tnorm_and_conorm_hand_points() {
    assert!(close(TNorm::Min.apply(0.6, 0.7), 0.6));
    assert!(close(TNorm::Product.apply(0.6, 0.7), 0.42));
    assert!(close(TNorm::Lukasiewicz.apply(0.6, 0.7), 0.3));
    assert_eq!(TNorm::Lukasiewicz.apply(0.3, 0.4), 0.0);
    assert!(close(TNorm::Min.conorm(0.6, 0.7), 0.7));
    assert!(close(TNorm::Product.conorm(0.6, 0.7), 0.88));
    assert!(close(TNorm::Lukasiewicz.conorm(0.6, 0.7), 1.0));
}

/// Residua R(a, b) = sup{z : T(a, z) ≤ b}:
/// - Gödel:       R(0.7, 0.4) = 0.4 (a > b → b);     R(0.4, 0.7) = 1;  R(1, 0) = 0
/// - Goguen:      R(0.8, 0.4) = 0.4/0.8 = 0.5;       R(0.5, 0.2) = 0.4; R(0.3, 0.9) = 1
/// - Łukasiewicz: R(0.7, 0.4) = 1 − 0.7 + 0.4 = 0.7; R(0.9, 0.1) = 0.2; R(0.2, 0.3) = 1
///
/// and R(a, a) = 1 for all three.
#[test]
fn residuated_implications_hand_points() {
    let g = TNorm::Min;
    assert!(close(g.residuum(0.7, 0.4), 0.4));
    assert_eq!(g.residuum(0.4, 0.7), 1.0);
    assert_eq!(g.residuum(1.0, 0.0), 0.0);
    let p = TNorm::Product;
    assert!(close(p.residuum(0.8, 0.4), 0.5));
    assert!(close(p.residuum(0.5, 0.2), 0.4));
    assert_eq!(p.residuum(0.3, 0.9), 1.0);
    assert_eq!(p.residuum(0.6, 0.0), 0.0);
    let l = TNorm::Lukasiewicz;
    assert!(close(l.residuum(0.7, 0.4), 0.7));
    assert!(close(l.residuum(0.9, 0.1), 0.2));
    assert_eq!(l.residuum(0.2, 0.3), 1.0);
    assert_eq!(l.residuum(1.0, 0.0), 0.0);
    for t in TNorm::ALL {
        assert_eq!(t.residuum(0.37, 0.37), 1.0, "{t:?}");
    }
    // Under the default (residuum) reading, a nested `->` is the t-norm's residuum.
    let cfg = LogicConfig {
        tnorm: TNorm::Product,
        ..LogicConfig::default()
    };
    assert!(close(cfg.implies(0.8, 0.4), 0.5));
}

/// Kleene–Dienes max(1 − a, b), the nested `->` under min-MP, whatever the t-norm:
/// KD(0.7, 0.4) = max(0.3, 0.4) = 0.4; KD(0.2, 0.5) = max(0.8, 0.5) = 0.8 — not 1 although
/// a ≤ b, unlike every residuum; KD(1, 0.3) = 0.3; KD(0, 0) = 1.
#[test]
fn kleene_dienes_via_min_mp() {
    for tnorm in TNorm::ALL {
        let cfg = LogicConfig {
            tnorm,
            implication: Implication::MinMp,
            ..LogicConfig::default()
        };
        assert!(close(cfg.implies(0.7, 0.4), 0.4), "{tnorm:?}");
        assert!(close(cfg.implies(0.2, 0.5), 0.8), "{tnorm:?}");
        assert!(close(cfg.implies(1.0, 0.3), 0.3), "{tnorm:?}");
        assert_eq!(cfg.implies(0.0, 0.0), 1.0, "{tnorm:?}");
    }
}

/// The two readings of `->` on one rule, antecedent 0.8, weight 0.6 (DESIGN §3):
/// - residuum, product:     0.8 · 0.6 = 0.48
/// - residuum, Łukasiewicz: max(0, 0.8 + 0.6 − 1) = 0.4
/// - residuum, min:         min(0.8, 0.6) = 0.6
/// - min-MP (any t-norm):   min(0.8, 0.6) = 0.6
#[test]
fn two_readings_of_the_arrow() {
    let with = |tnorm, implication| LogicConfig {
        tnorm,
        implication,
        ..LogicConfig::default()
    };
    let r = Implication::Residuum;
    assert!(close(with(TNorm::Product, r).detach(0.8, 0.6), 0.48));
    assert!(close(with(TNorm::Lukasiewicz, r).detach(0.8, 0.6), 0.4));
    assert!(close(with(TNorm::Min, r).detach(0.8, 0.6), 0.6));
    for tnorm in TNorm::ALL {
        assert!(close(with(tnorm, Implication::MinMp).detach(0.8, 0.6), 0.6));
    }
    // The default reading is the residuum of min.
    assert!(close(LogicConfig::default().detach(0.8, 0.6), 0.6));
}

/// `clamp_degree` at hand-picked points: NaN → 0 (no support), ±∞ → 1 / 0, out of range clamps.
#[test]
fn clamp_degree_hand_points() {
    assert_eq!(clamp_degree(f64::NAN), 0.0);
    assert_eq!(clamp_degree(f64::INFINITY), 1.0);
    assert_eq!(clamp_degree(f64::NEG_INFINITY), 0.0);
    assert_eq!(clamp_degree(1.5), 1.0);
    assert_eq!(clamp_degree(-0.2), 0.0);
    assert_eq!(clamp_degree(0.35), 0.35);
}

// ---------------------------------------------------------------------------------------------
// Trapezoid
// ---------------------------------------------------------------------------------------------

/// Linear trapezoid centred on 50, core Δ = 4 (±2), slope α = 2, height 0.9, bias 0.2:
/// μ(x) = 0.2 + 0.7 · f(|x − 50|), f(d) = 1 for d ≤ 2, else max(0, 1 − (d − 2)/2).
/// - x = 50, 52, 48:   f = 1              → 0.9
/// - x = 53, 47:       f = 1 − 1/2 = 0.5  → 0.2 + 0.35 = 0.55
/// - x = 53.5:         f = 1 − 1.5/2 = 0.25 → 0.2 + 0.175 = 0.375
/// - x = 54, 1000, −1e9: f = 0            → 0.2 (the bias: an outlier stays possible)
/// - x = NaN:                              → 0.2
#[test]
fn trapezoid_linear_hand_points() {
    let t = Similarity::new(4.0, 2.0, 0.9, 0.2, None);
    for (x, want) in [
        (50.0, 0.9),
        (52.0, 0.9),
        (48.0, 0.9),
        (53.0, 0.55),
        (47.0, 0.55),
        (53.5, 0.375),
        (54.0, 0.2),
        (1000.0, 0.2),
        (-1e9, 0.2),
        (f64::NAN, 0.2),
        (f64::INFINITY, 0.2),
    ] {
        let got = t.degree(x, 50.0);
        assert!(close(got, want), "μ({x}) = {got}, want {want}");
    }
}

/// Crisp interval (slope 0), core 10, height 1, bias 0: μ = 1 for |x − c| ≤ 5, else 0.
#[test]
fn trapezoid_crisp_hand_points() {
    let t = Similarity::new(10.0, 0.0, 1.0, 0.0, None);
    assert_eq!(t.degree(5.0, 0.0), 1.0);
    assert_eq!(t.degree(-5.0, 0.0), 1.0);
    assert_eq!(t.degree(5.5, 0.0), 0.0);
}

/// Circular trapezoid, period 360, centre 350°, core 30 (±15), slope 30, height 1, bias 0.1:
/// μ = 0.1 + 0.9 · f(d), d the distance around the circle.
/// - x = 10°:    |10 − 350| = 340, around the circle 20 → f = 1 − 5/30 = 5/6 → 0.1 + 0.75 = 0.85
/// - x = 20°:    d = 30 → f = 1 − 15/30 = 0.5 → 0.55
/// - x = 5°:     d = 15 → f = 1 → 1
/// - x = 170°:   d = 180 → f = 0 → 0.1
/// - x = −10°:   same angle as 350° → d = 0 → 1;  x = 1070° = 350° + 720° → 1
/// - x = 300°:   d = 50 → f = 1 − 35/30 < 0 → 0 → 0.1
#[test]
fn trapezoid_circular_hand_points() {
    let t = Similarity::new(30.0, 30.0, 1.0, 0.1, Some(360.0));
    for (x, want) in [
        (10.0, 0.85),
        (20.0, 0.55),
        (5.0, 1.0),
        (170.0, 0.1),
        (-10.0, 1.0),
        (1070.0, 1.0),
        (300.0, 0.1),
        (335.0, 1.0),
    ] {
        let got = t.degree(x, 350.0);
        assert!(close(got, want), "μ({x}°) = {got}, want {want}");
    }
}
