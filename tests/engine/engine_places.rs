//! Golden tests of the possibilistic layer over sets of places (issue 19): exact threshold ties,
//! heads over rooms and regions as weighted disjunctions, Π and N of sets and their Boolean
//! combinations, product fusion of evidence groups, conditioning on a known region, the
//! diagnostics for negated derived heads and zero weights, the parenthesised body, and
//! `explain --atom` / `eval --query` / the stream's `region` field.
//!
//! Every expected number is worked out in the comments from the textbook definitions (Dubois,
//! Lang, Prade: `(φ, α)` means `N(φ) ≥ α`; π(w) = min over the formulas w falsifies of 1 − α),
//! not read off the program.

use crate::support::lplace;
use lplace::engine::Engine;
use lplace::logic::{
    decide, Decision, DecisionParams, Disoriented, Fusion, Normalisation, PlaceDistribution,
    PlaceSet,
};
use lplace::syntax::ast::{Formula, RuleItem};
use lplace::syntax::diagnostic::{DiagnosticKind, NeverFiresReason, SourceFile};
use lplace::syntax::parse_rules;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-12
}

// ---------------------------------------------------------------------------------------------
// 1. Ties at every two-decimal threshold
// ---------------------------------------------------------------------------------------------

/// One place supported to exactly the threshold θ: π = (1, 1 − θ, 1 − θ), N(P1) = 1 − (1 − θ) = θ
/// on paper, Inc = 0, so P1 must be chosen at every θ = 0.01 … 0.99 (margin 0). In floating
/// point `1 − (1 − 0.1) = 0.09999999999999998`; 16 of these 99 thresholds used to answer
/// "disoriented".
#[test]
fn support_equal_to_the_threshold_is_chosen_at_every_two_decimal_threshold() {
    for t in 1..=99u32 {
        let theta = f64::from(t) / 100.0;
        for norm in [Normalisation::Min, Normalisation::Product] {
            let mut d = PlaceDistribution::new(3);
            d.support[0] = theta;
            d.update(norm);
            let got = decide(
                &d,
                DecisionParams {
                    threshold: theta,
                    margin: 0.0,
                },
            );
            assert_eq!(got.place(), Some(0), "θ = {theta}, {norm:?}: {got:?}");
        }
    }
}

/// The textbook case: π = (1, 0.6, 0.3) gives N(P1) = 1 − 0.6 = 0.4, so threshold 0.4 chooses
/// P1 and 0.41 does not (nothing above threshold: no support reaches 0.41 either).
#[test]
fn textbook_threshold_tie() {
    let mut d = PlaceDistribution::new(3);
    d.possibility_raw.copy_from_slice(&[1.0, 0.6, 0.3]);
    d.finish(Normalisation::Min);
    let at = |threshold| {
        decide(
            &d,
            DecisionParams {
                threshold,
                margin: 0.0,
            },
        )
    };
    assert_eq!(at(0.4).place(), Some(0));
    assert!(matches!(
        at(0.41),
        Decision::Disoriented(Disoriented::NothingAboveThreshold { best: 0, .. })
    ));
}

/// A margin is a strict excess, also up to rounding: N = 0.6, Inc = 0.5 gives N − Inc = 0.1
/// (0.09999999999999998 in floating point), which does not exceed a margin of 0.1 — and the
/// tie is not decided by which way the rounding fell.
#[test]
fn margin_tie_is_not_an_excess() {
    let mut d = PlaceDistribution::new(2);
    // π = (0.5, 0.2): h = 0.5, Inc = 0.5; min-based π' = (1, 0.2), N(P1) = 0.8.
    d.possibility_raw.copy_from_slice(&[0.5, 0.2]);
    d.finish(Normalisation::Min);
    let p = |margin| DecisionParams {
        threshold: 0.5,
        margin,
    };
    // N − Inc = 0.8 − 0.5 = 0.3: exceeds 0.29, ties 0.3.
    assert_eq!(decide(&d, p(0.29)).place(), Some(0));
    assert_eq!(decide(&d, p(0.3)).place(), None);
}

// ---------------------------------------------------------------------------------------------
// 2. Heads over sets of places
// ---------------------------------------------------------------------------------------------

const MAP3: &str = "
map three;
room R12; room R3;
place P1 corner in R12 at (0, 0);
place P2 doorway in R12 at (2, 0);
place P3 doorway in R3 at (4, 0);
path P1 -- P2; path P2 -- P3;
";

fn load(map: &str, rules: &str) -> Engine {
    match Engine::load(
        &SourceFile::new("t.map", map),
        &SourceFile::new("t.lpl", rules),
    ) {
        Ok(e) => e,
        Err(e) => panic!("{e}: {:?}", e.diagnostics),
    }
}

fn load_err(map: &str, rules: &str) -> Vec<DiagnosticKind> {
    match Engine::load(
        &SourceFile::new("t.map", map),
        &SourceFile::new("t.lpl", rules),
    ) {
        Ok(_) => panic!("expected the rules to be rejected"),
        Err(e) => e.diagnostics.into_iter().map(|d| d.kind).collect(),
    }
}

/// `(in_room(R12), 0.7)` with R12 = {P1, P2} is `(P1 ∨ P2, 0.7)`: it excludes P3 to 0.3, so
/// π = (1, 1, 0.3), N(R12) = 1 − 0.3 = 0.7, N(P1) = 1 − max(π(P2), π(P3)) = 0.
#[test]
fn in_room_head_is_a_weighted_disjunction() {
    let mut e = load(MAP3, "|- (1 -> in_room(R12), 0.7);");
    let f = e.new_frame();
    e.step(&f);
    let d = e.distribution();
    assert!(close(d.possibility_raw[0], 1.0) && close(d.possibility_raw[1], 1.0));
    assert!(close(d.possibility_raw[2], 0.3));
    assert!(close(e.rooms().necessity[0], 0.7));
    assert!(close(e.rooms().support[0], 0.7));
    assert!(close(d.necessity[0], 0.0));
}

/// The textbook base {(P1 ∨ P2, 0.7), (P1 ∨ P3, 0.4)}: P3 falsifies the first (π ≤ 0.3), P2 the
/// second (π ≤ 0.6), P1 neither: π = (1, 0.6, 0.3), N(P1) = 1 − 0.6 = 0.4,
/// N(P1 ∨ P2) = 1 − 0.3 = 0.7, Π(P2 ∨ P3) = 0.6, N(¬P3) = N(P1 ∨ P2) = 0.7,
/// N(R12 & !P2) = N(P1) = 0.4, Π(P1 & P3) = Π(∅) = 0.
#[test]
fn textbook_region_base_and_queries() {
    let rules = "
        region A = {P1, P2};
        region B = {P1, P3};
        |- (1 -> in_region(A), 0.7);
        |- (1 -> in_region(B), 0.4);
    ";
    let mut e = load(MAP3, rules);
    let f = e.new_frame();
    e.step(&f);
    let d = e.distribution();
    for (k, want) in [1.0, 0.6, 0.3].into_iter().enumerate() {
        assert!(
            close(d.possibility_raw[k], want),
            "π[{k}] = {}",
            d.possibility_raw[k]
        );
    }
    assert!(close(d.necessity[0], 0.4));
    let q = |text: &str| {
        let set = e
            .query_set(text)
            .unwrap_or_else(|err| panic!("{text}: {err}"));
        e.set_degrees(&set)
    };
    assert!(close(q("A").1, 0.7));
    assert!(close(q("P1 (+) P2").1, 0.7));
    assert!(close(q("in_region(A)").1, 0.7));
    assert!(close(q("!P3").1, 0.7));
    assert!(close(q("P2 (+) P3").0, 0.6));
    assert!(close(q("R12 & !P2").1, 0.4));
    assert_eq!(q("P1 & P3").0, 0.0);
    // A kind is a set too: doorway = {P2, P3}, Π = 0.6, N = 1 − π(P1) = 0.
    assert!(close(q("doorway").0, 0.6) && close(q("doorway").1, 0.0));
    assert!(close(e.regions().necessity[0], 0.7) && close(e.regions().necessity[1], 0.4));
    assert!(e.query_set("Nowhere").is_err());
    assert!(e.query_set("P1 * P2").is_err());
}

/// The inconsistency of {(p, 0.8), (¬p ∨ q, 0.6), (¬q, 0.3)} over the four worlds pq, p¬q, ¬pq,
/// ¬p¬q (here four places, p and q regions): pq falsifies only ¬q → 0.7; p¬q only ¬p ∨ q → 0.4;
/// ¬pq and ¬p¬q falsify p → 0.2 (¬p¬q also ¬q: min(0.2, 0.7)). h = 0.7, Inc = 0.3. Min-based
/// π' = (1, 0.4, 0.2, 0.2), N(q) = 1 − max(π'(p¬q), π'(¬p¬q)) = 1 − 0.4 = 0.6.
#[test]
fn textbook_inconsistency_degree_and_necessity() {
    let map = "
        place Wpq corner at (0, 0); place Wpnq corner at (1, 0);
        place Wnpq corner at (2, 0); place Wnpnq corner at (3, 0);
    ";
    let rules = "
        region Pw = {Wpq, Wpnq};
        region Qw = {Wpq, Wnpq};
        region NotPOrQ = {Wpq, Wnpq, Wnpnq};
        |- (1 -> in_region(Pw), 0.8);
        |- (1 -> in_region(NotPOrQ), 0.6);
        |- (1 -> !in_region(Qw), 0.3);
    ";
    let mut e = load(map, rules);
    let f = e.new_frame();
    e.step(&f);
    let d = e.distribution();
    for (k, want) in [0.7, 0.4, 0.2, 0.2].into_iter().enumerate() {
        assert!(
            close(d.possibility_raw[k], want),
            "π[{k}] = {}",
            d.possibility_raw[k]
        );
    }
    assert!(close(d.inconsistency, 0.3));
    let q = e.query_set("Qw").expect("a region");
    assert!(close(e.set_degrees(&q).1, 0.6));
}

// ---------------------------------------------------------------------------------------------
// 3. Negated heads, zero weights, parentheses
// ---------------------------------------------------------------------------------------------

#[test]
fn negated_head_of_a_derived_predicate_is_rejected() {
    let rules = "
        percept seen(time);
        predicate q(time);
        |- (seen(t) -> !q(t), 0.9);
        |- q(t) -> at_place(P1);
    ";
    let kinds = load_err(MAP3, rules);
    assert!(
        kinds
            .iter()
            .any(|k| matches!(k, DiagnosticKind::NegatedDerivedHead { name } if name == "q")),
        "{kinds:?}"
    );
}

#[test]
fn a_rule_of_weight_zero_is_reported_for_its_weight() {
    let kinds = load_err(MAP3, "percept seen(time); |- (seen(t) -> at_place(P1), 0);");
    assert!(kinds.contains(&DiagnosticKind::RuleNeverFires {
        reason: NeverFiresReason::ZeroWeight
    }));
    let text = DiagnosticKind::RuleNeverFires {
        reason: NeverFiresReason::ZeroWeight,
    }
    .to_string();
    assert!(text.contains("weight is 0"), "{text}");
    assert!(!text.contains("body is 0"), "{text}");
}

/// `|- (a -> b) -> at_place(P1);` is the body `(a -> b)` concluding `at_place(P1)`.
#[test]
fn parenthesised_implication_as_a_body() {
    let file = parse_rules("|- (a -> b) -> at_place(P1);").expect("parses");
    let Some(RuleItem::Rule(r)) = file.items.first() else {
        panic!("one rule")
    };
    assert!(matches!(r.body.node, Formula::Implies(..)));
    assert_eq!(r.head.atom.name.node, "at_place");
    // The weighted form still parses as a whole sequent.
    let file = parse_rules("|- ((a -> b) -> at_place(P1), 0.5);").expect("parses");
    let Some(RuleItem::Rule(r)) = file.items.first() else {
        panic!("one rule")
    };
    assert_eq!(r.weight.as_ref().map(|w| w.node), Some(0.5));
}

// ---------------------------------------------------------------------------------------------
// 4. Fusion of evidence groups, conditioning
// ---------------------------------------------------------------------------------------------

/// Group a gives π1 = (1, 0.6, 0.3) (the textbook base above); group b, `(P1 ∨ P2, 0.6)`, gives
/// π2 = (1, 1, 0.4). Product fusion: (1·1, 0.6·1, 0.3·0.4) = (1, 0.6, 0.12),
/// N(P1 ∨ P2) = 1 − 0.12 = 0.88. Min fusion: (1, 0.6, 0.3), N(P1 ∨ P2) = 0.7 — the same as
/// pooling all three rules.
#[test]
fn product_and_min_fusion_of_two_groups() {
    let body = "
        region A = {P1, P2};
        region B = {P1, P3};
        group a { |- (1 -> in_region(A), 0.7); |- (1 -> in_region(B), 0.4); }
        group b { |- (1 -> in_region(A), 0.6); }
    ";
    for (fusion, p3, n12) in [("product", 0.12, 0.88), ("min", 0.3, 0.7)] {
        let mut e = load(MAP3, &format!("logic {{ fusion = {fusion}; }} {body}"));
        let f = e.new_frame();
        e.step(&f);
        let d = e.distribution();
        assert!(close(d.possibility_raw[0], 1.0) && close(d.possibility_raw[1], 0.6));
        assert!(
            close(d.possibility_raw[2], p3),
            "{fusion}: {}",
            d.possibility_raw[2]
        );
        let a = e.query_set("A").expect("a region");
        assert!(close(e.set_degrees(&a).1, n12), "{fusion}");
    }
    assert_eq!(Fusion::Product.apply(0.3, 0.4), 0.3 * 0.4);
}

/// π = (1, 0.7, 0.4) (from (P1 ∨ P3, 0.3) and (P1 ∨ P2, 0.6)), conditioned on A = {P2, P3}:
/// Π(A) = 0.7. Min-based: P2 (at Π(A)) → 1, P3 → 0.4, P1 → 0. Product-based: P2 → 0.7/0.7 = 1,
/// P3 → 0.4/0.7 = 0.5714…, P1 → 0. Inc = 1 − Π(A) = 0.3 either way.
#[test]
fn min_and_product_conditioning_on_a_known_region() {
    // The logic layer alone.
    for (norm, w3) in [
        (Normalisation::Min, 0.4),
        (Normalisation::Product, 0.4 / 0.7),
    ] {
        let mut d = PlaceDistribution::new(3);
        d.possibility_raw.copy_from_slice(&[1.0, 0.7, 0.4]);
        d.condition(&PlaceSet::from_indices(3, [1, 2]));
        d.finish(norm);
        assert_eq!(d.possibility[0], 0.0);
        assert!(close(d.possibility[1], 1.0));
        assert!(
            close(d.possibility[2], w3),
            "{norm:?}: {}",
            d.possibility[2]
        );
        assert!(close(d.inconsistency, 0.3));
    }
    assert!(close(0.4 / 0.7, 0.571_428_571_428_571_4));
    // The engine, with the region known from outside.
    let rules = "
        region A = {P1, P2}; region B = {P1, P3};
        |- (1 -> in_region(B), 0.3);
        |- (1 -> in_region(A), 0.6);
    ";
    for (norm, w3) in [("min", 0.4), ("product", 0.4 / 0.7)] {
        let mut e = load(
            MAP3,
            &format!("logic {{ normalisation = {norm}; }} {rules}"),
        );
        let known = e.query_set("P2 (+) P3").expect("places");
        let f = e.new_frame();
        e.step_within(&f, Some(&known));
        let d = e.distribution();
        assert_eq!(d.possibility[0], 0.0);
        assert!(close(d.possibility[2], w3), "{norm}: {}", d.possibility[2]);
        // Without it, the same frame is unconditioned: π' = (1, 0.7, 0.4).
        e.step(&f);
        assert!(close(e.distribution().possibility[2], 0.4));
    }
}

// ---------------------------------------------------------------------------------------------
// 5. The command line
// ---------------------------------------------------------------------------------------------

/// Paper 003's eq. (5) on its own: in context P2 (A = 116.6, L = 1.12) the signature is the min
/// of the two matches, and its dissimilarity form is eq. (6), `max(β_θ, β_d)`.
#[test]
fn explain_atom_shows_the_beacon_signature_as_eq_6() {
    let out = lplace()
        .args(["explain", "--atom", "beacon_signature", "--dissimilarity"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    // Formulas are wrapped to 100 columns: compare without whitespace.
    let squeeze = |t: &str| t.split_whitespace().collect::<String>();
    let text = squeeze(&String::from_utf8(out).expect("utf-8"));
    assert!(
        text.contains(&squeeze(
            "beacon_signature(_, _, t) @P2 = min(beacon_angle ~bearing 116.6, beacon_distance ~range 1.12)"
        )),
        "{text}"
    );
    assert!(
        text.contains(&squeeze(
            "δ beacon_signature(_, _, t) @P2 = max(δ[beacon_angle ~bearing 116.6], δ[beacon_distance ~range 1.12])"
        )),
        "{text}"
    );
}

/// No evidence at all (π = 1 everywhere) and the record says the robot is at P3: conditioning
/// on {P3} leaves π' = 1 at P3 and 0 elsewhere, so N(P3) = 1 and P3 is chosen; Inc = 1 − Π({P3})
/// = 0. A region the map does not have rejects the record (exit 3).
#[test]
fn stream_region_field_conditions_the_frame() {
    let dir = std::env::temp_dir();
    let p = dir.join(format!("lplace-poss-{}-region.jsonl", std::process::id()));
    std::fs::write(
        &p,
        "{\"percepts\":[],\"region\":\"P3\"}\n{\"percepts\":[]}\n{\"percepts\":[],\"region\":\"Attic\"}\n",
    )
    .expect("temp file");
    let out = lplace()
        .arg("eval")
        .arg(&p)
        .args(["--no-track", "--summary", "none", "--query", "R0"])
        .assert()
        .code(3)
        .get_output()
        .stdout
        .clone();
    let text = String::from_utf8(out).expect("utf-8");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2, "{text}");
    // P3 is in R0: Π(R0) = 1, N(R0) = 1 − max_{k ∉ R0} π'_k = 1 − 0 = 1.
    assert_eq!(
        lines[0],
        "{\"line\":1,\"place\":\"P3\",\"necessity\":1.0000,\"inconsistency\":0.0000,\"queries\":[[1.0000,1.0000]]}"
    );
    assert!(lines[1].contains("\"place\":null"), "{}", lines[1]);
}
