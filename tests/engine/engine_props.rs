//! Property tests of the engine: the compiled tape agrees with the tree-walking interpreter on
//! random frames, for every t-norm and both readings of `->`; supports are monotone in the
//! percept degrees under positive rules; shuffling rules or percepts changes nothing; and a step
//! never yields NaN or a degree outside [0, 1], whatever the frame holds.

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
