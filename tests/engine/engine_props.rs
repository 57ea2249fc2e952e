//! Property tests of the engine: the compiled tape agrees with the tree-walking interpreter on
//! random frames, for every t-norm and both readings of `->`; supports are monotone in the
//! percept degrees under positive rules; shuffling rules or percepts changes nothing; and a step
//! never yields NaN or a degree outside [0, 1], whatever the frame holds; and heads over sets of
//! places, evidence groups (min and product fusion) and conditioning on a known region, written
//! as rule files, agree with enumeration over the places.

use lplace::engine::interpret::Interpreter;
use lplace::engine::{CompileOptions, Engine, Frame, OFFICE_MAP, OFFICE_RULES};
use lplace::io::record::{FrameRecord, PerceptRecord};
use lplace::map::Map;
use lplace::rules::{check_rules, RuleSet};
use lplace::syntax::{parse_map, parse_rules};
use proptest::prelude::*;

const FIELD_MAP: &str = include_str!("../../maps/field.map");
const FIELD_RULES: &str = include_str!("../../rules/field.lpl");
// Expected ranges (`param free(North) = a .. b;`) and a negated derived atom.
const INTEL_MAP: &str = include_str!("../../maps/intel.map");
const INTEL_RULES: &str = include_str!("../../rules/intel.lpl");

fn model(map: &str, rules: &str, tnorm: &str, implication: &str) -> (Map, RuleSet) {
    let map = Map::from_ast(&parse_map(map).expect("map parses")).expect("map checks");
    // Swap the file's operator choices for the ones under test.
    let rules = rules
        .lines()
        .map(|l| {
            let t = l.trim_start();
            if t.starts_with("tnorm") {
                format!("tnorm = {tnorm};")
            } else if t.starts_with("implication") {
                format!("implication = {implication};")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let ast = parse_rules(&rules).expect("rules parse");
    let checked = check_rules(&ast, &map).expect("rules check");
    (map, checked)
}

/// A frame from a vector of (degree, value) pairs, one per slot.
fn frame_of(n: usize, cells: &[(f64, f64)]) -> Frame {
    let mut f = Frame::new(n);
    for (i, &(d, v)) in cells.iter().enumerate().take(n) {
        f.degree[i] = d;
        f.value[i] = v;
    }
    f
}

fn cells() -> impl Strategy<Value = Vec<(f64, f64)>> {
    // Values over the range of the maps' expectations (angles 0–360°, distances 0–10 m), with
    // some exactly-missing and some hostile entries.
    let degree = prop_oneof![8 => 0.0..=1.0f64, 1 => Just(0.0), 1 => Just(1.0)];
    // … and ln(metres) for the Intel map's free ranges.
    let value = prop_oneof![
        6 => 0.0..360.0f64,
        3 => 0.0..10.0f64,
        3 => -3.0..3.0f64,
        1 => Just(f64::NAN)
    ];
    prop::collection::vec((degree, value), 64)
}

fn operators() -> impl Strategy<Value = (&'static str, &'static str)> {
    (
        prop::sample::select(vec!["min", "product", "lukasiewicz"]),
        prop::sample::select(vec!["residuum", "min_mp"]),
    )
}

fn example() -> impl Strategy<Value = (&'static str, &'static str)> {
    prop::sample::select(vec![(OFFICE_MAP, OFFICE_RULES), (FIELD_MAP, FIELD_RULES)])
}

/// The examples, and the Intel lab's map and rules (expected ranges, a negated signature).
fn every_example() -> impl Strategy<Value = (&'static str, &'static str)> {
    prop::sample::select(vec![
        (OFFICE_MAP, OFFICE_RULES),
        (FIELD_MAP, FIELD_RULES),
        (INTEL_MAP, INTEL_RULES),
    ])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn compiled_equals_interpreter((map, rules) in every_example(), (tn, imp) in operators(), cells in cells()) {
        let (map, rules) = model(map, rules, tn, imp);
        let mut engine = Engine::new(map.clone(), rules.clone(), &CompileOptions::default()).expect("compiles");
        let frame = frame_of(engine.percepts().len(), &cells);
        engine.step(&frame);
        let reference = Interpreter::new(&rules, &map, engine.percepts()).run(&frame);
        let d = engine.distribution();
        for k in 0..d.len() {
            prop_assert!((d.support[k] - reference.support[k]).abs() < 1e-12,
                "place {k}: tape {} interpreter {}", d.support[k], reference.support[k]);
            prop_assert!((d.exclusion[k] - reference.exclusion[k]).abs() < 1e-12);
        }
        for r in 0..reference.rooms.len() {
            prop_assert!((engine.rooms().support[r] - reference.rooms[r]).abs() < 1e-12);
        }
    }

    #[test]
    fn raising_a_degree_never_lowers_a_support(
        (map, rules) in example(), (tn, imp) in operators(), cells in cells(),
        slot in 0usize..64, raise in 0.0..=1.0f64,
    ) {
        // Both example rule files use percepts only positively (negation appears on map facts
        // and on conclusions), so every support is monotone in every percept degree.
        let (map, rules) = model(map, rules, tn, imp);
        let mut engine = Engine::new(map, rules, &CompileOptions::default()).expect("compiles");
        let n = engine.percepts().len();
        let mut frame = frame_of(n, &cells);
        engine.step(&frame);
        let before = engine.distribution().support.clone();
        let slot = slot % n;
        frame.degree[slot] = frame.degree[slot].max(raise);
        engine.step(&frame);
        for (k, (&a, &b)) in before.iter().zip(&engine.distribution().support).enumerate() {
            prop_assert!(b >= a - 1e-12, "place {k}: {a} → {b} after raising slot {slot}");
        }
    }

    #[test]
    fn rule_order_does_not_matter((map, rules) in example(), (tn, imp) in operators(), cells in cells(), seed in any::<u64>()) {
        let (map, rules) = model(map, rules, tn, imp);
        let mut shuffled = rules.clone();
        // A seeded Fisher–Yates shuffle of the rules.
        let mut s = seed | 1;
        for i in (1..shuffled.rules.len()).rev() {
            s ^= s << 13; s ^= s >> 7; s ^= s << 17;
            shuffled.rules.swap(i, (s % (i as u64 + 1)) as usize);
        }
        let mut a = Engine::new(map.clone(), rules, &CompileOptions::default()).expect("compiles");
        let mut b = Engine::new(map, shuffled, &CompileOptions::default()).expect("compiles");
        let frame = frame_of(a.percepts().len(), &cells);
        prop_assert_eq!(a.step(&frame), b.step(&frame));
        prop_assert_eq!(&a.distribution().support, &b.distribution().support);
        prop_assert_eq!(&a.distribution().necessity, &b.distribution().necessity);
    }

    #[test]
    fn percept_order_does_not_matter(cells in cells(), seed in any::<u64>()) {
        let mut engine = Engine::office().expect("office loads");
        let table = engine.percepts().clone();
        let mut records: Vec<PerceptRecord> = table
            .instances()
            .iter()
            .zip(&cells)
            .filter(|(_, (d, _))| *d > 0.0)
            .map(|(p, &(d, v))| PerceptRecord { name: p.name.clone(), args: p.args.clone(), value: v.is_finite().then_some(v), degree: d })
            .collect();
        let run = |engine: &mut Engine, records: &[PerceptRecord]| {
            let rec = FrameRecord { percepts: records.to_vec(), ..FrameRecord::default() };
            let mut frame = engine.new_frame();
            let mut rejected = Vec::new();
            rec.fill(engine.percepts(), &mut frame, &mut rejected);
            assert!(rejected.is_empty());
            (engine.step(&frame), engine.distribution().necessity.clone())
        };
        let first = run(&mut engine, &records);
        let mut s = seed | 1;
        for i in (1..records.len()).rev() {
            s ^= s << 13; s ^= s >> 7; s ^= s << 17;
            records.swap(i, (s % (i as u64 + 1)) as usize);
        }
        prop_assert_eq!(first, run(&mut engine, &records));
    }

    #[test]
    fn hostile_frames_give_clean_degrees(degrees in prop::collection::vec(prop_oneof![
            Just(f64::NAN), Just(f64::INFINITY), Just(-1.0), Just(7.5), 0.0..=1.0f64], 0..80),
        values in prop::collection::vec(prop_oneof![Just(f64::NAN), Just(f64::NEG_INFINITY), -1e9..1e9f64], 0..80)) {
        // Frames of the wrong length and full of NaN/∞ must still give degrees in [0, 1].
        let mut engine = Engine::office().expect("office loads");
        let frame = Frame { degree: degrees, value: values };
        let decision = engine.step(&frame);
        let d = engine.distribution();
        for v in d.support.iter().chain(&d.exclusion).chain(&d.possibility).chain(&d.necessity) {
            prop_assert!((0.0..=1.0).contains(v), "{v}");
        }
        prop_assert!((0.0..=1.0).contains(&d.inconsistency));
        if let Some(p) = decision.place() {
            prop_assert!(d.necessity[p] >= 0.5);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Heads over sets, evidence groups and conditioning, through the rule language
// ---------------------------------------------------------------------------------------------

/// One generated rule: `|- (e<i>(t) -> [!]in_region(G<i>), w)` (or `at_place(P<k>)` when the
/// region is a single place), written in group `none`, `a` or `b`.
#[derive(Debug, Clone)]
struct GenRule {
    members: Vec<bool>,
    negated: bool,
    weight: f64,
    degree: f64,
    group: usize,
}

/// Places, rules, known region, query set, product fusion?, product normalisation?, conditioned?
type GenCase = (usize, Vec<GenRule>, Vec<bool>, Vec<bool>, bool, bool, bool);

fn gen_case() -> impl Strategy<Value = GenCase> {
    (2usize..6).prop_flat_map(|n| {
        let rule = (
            prop::collection::vec(any::<bool>(), n),
            any::<bool>(),
            (1u32..=20).prop_map(|k| f64::from(k) / 20.0),
            prop_oneof![Just(0.0), Just(1.0), 0.0..=1.0f64],
            0usize..3,
        )
            .prop_map(|(members, negated, weight, degree, group)| GenRule {
                members,
                negated,
                weight,
                degree,
                group,
            });
        (
            Just(n),
            prop::collection::vec(rule, 1..7),
            prop::collection::vec(any::<bool>(), n),
            prop::collection::vec(any::<bool>(), n),
            any::<bool>(),
            any::<bool>(),
            any::<bool>(),
        )
    })
}

/// The map, rule file and frame degrees of a generated case.
fn gen_files(
    n: usize,
    rules: &[GenRule],
    product_fusion: bool,
    product_norm: bool,
) -> (String, String) {
    let map: String = (0..n)
        .map(|k| format!("place P{k} corner at ({k}, 0);\n"))
        .collect();
    let mut text = format!(
        "logic {{ tnorm = product; fusion = {}; normalisation = {}; }}\n",
        if product_fusion { "product" } else { "min" },
        if product_norm { "product" } else { "min" },
    );
    let mut groups = [String::new(), String::new(), String::new()];
    for (i, r) in rules.iter().enumerate() {
        let places: Vec<String> = (0..n)
            .filter(|&k| r.members[k])
            .map(|k| format!("P{k}"))
            .collect();
        text.push_str(&format!(
            "percept e{i}(time);\nregion G{i} = {{{}}};\n",
            places.join(", ")
        ));
        let neg = if r.negated { "!" } else { "" };
        groups[r.group].push_str(&format!(
            "|- (e{i}(t) -> {neg}in_region(G{i}), {});\n",
            r.weight
        ));
    }
    text.push_str(&groups[0]);
    text.push_str(&format!(
        "group a {{\n{}}}\ngroup b {{\n{}}}\n",
        groups[1], groups[2]
    ));
    (map, text)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// The engine's π, π', N, Inc and Π/N of a set, for random region heads in three groups,
    /// both fusions, both normalisations, with and without a known region — against
    /// enumeration over the places: π_g(w) = min over group g's heads that w falsifies of
    /// 1 − degree·weight (product t-norm, residuum), fused world by world, zeroed outside the
    /// known region, normalised.
    #[test]
    fn set_heads_groups_and_conditioning_match_enumeration(
        (n, rules, known, query, product_fusion, product_norm, conditioned) in gen_case()
    ) {
        let (map, text) = gen_files(n, &rules, product_fusion, product_norm);
        let mut engine = Engine::load(
            &lplace::syntax::diagnostic::SourceFile::new("g.map", map),
            &lplace::syntax::diagnostic::SourceFile::new("g.lpl", text.clone()),
        ).map_err(|e| TestCaseError::fail(format!("{e}: {:?}\n{text}", e.diagnostics)))?;
        let mut frame = engine.new_frame();
        for (i, r) in rules.iter().enumerate() {
            let slot = engine.percepts().slot(&format!("e{i}"), &[]).expect("declared");
            frame.set(slot, r.degree, None);
        }
        let set = |v: &[bool]| lplace::logic::PlaceSet::from_indices(n, (0..n).filter(|&k| v[k]));
        let known_set = set(&known);
        engine.step_within(&frame, conditioned.then_some(&known_set));

        // Reference.
        let mut pi = vec![1.0f64; n];
        for g in 0..3 {
            let pg: Vec<f64> = (0..n).map(|w| {
                rules.iter().filter(|r| r.group == g && r.members[w] == r.negated)
                    .map(|r| 1.0 - r.degree * r.weight)
                    .fold(1.0, f64::min)
            }).collect();
            for (p, q) in pi.iter_mut().zip(&pg) {
                *p = if product_fusion { *p * q } else { p.min(*q) };
            }
        }
        if conditioned {
            for (w, p) in pi.iter_mut().enumerate() {
                if !known[w] {
                    *p = 0.0;
                }
            }
        }
        let h = pi.iter().copied().fold(0.0, f64::max);
        let norm: Vec<f64> = pi.iter().map(|&p| {
            if h == 0.0 { 1.0 } else if product_norm { p / h } else if p == h { 1.0 } else { p }
        }).collect();
        let d = engine.distribution();
        for w in 0..n {
            prop_assert!((d.possibility_raw[w] - pi[w]).abs() < 1e-12, "π[{w}] {} vs {}\n{text}", d.possibility_raw[w], pi[w]);
            prop_assert!((d.possibility[w] - norm[w]).abs() < 1e-12, "π'[{w}] {} vs {}\n{text}", d.possibility[w], norm[w]);
            let n_w = 1.0 - (0..n).filter(|&v| v != w).map(|v| norm[v]).fold(0.0, f64::max);
            prop_assert!((d.necessity[w] - n_w).abs() < 1e-12);
        }
        prop_assert!((d.inconsistency - (1.0 - h)).abs() < 1e-12);
        let q = set(&query);
        let (poss, nec) = engine.set_degrees(&q);
        let want_p = (0..n).filter(|&w| query[w]).map(|w| norm[w]).fold(0.0, f64::max);
        let want_n = 1.0 - (0..n).filter(|&w| !query[w]).map(|w| norm[w]).fold(0.0, f64::max);
        prop_assert!((poss - want_p).abs() < 1e-12 && (nec - want_n).abs() < 1e-12);
    }
}
