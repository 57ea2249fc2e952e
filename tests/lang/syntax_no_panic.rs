//! Hostile input: the parsers, the map builder and the checker never panic — on arbitrary
//! strings, on randomly mutated copies of the office example, and on 100 000-deep nesting, which
//! must give a "too deeply nested" diagnostic rather than a stack overflow.

use lplace::map::Map;
use lplace::rules::check_rules;
use lplace::syntax::{parse_map, parse_rules, DiagnosticKind};
use proptest::prelude::*;

const OFFICE_MAP: &str = include_str!("../../maps/office.map");
const OFFICE_RULES: &str = include_str!("../../rules/office.lpl");

fn office_map() -> Map {
    Map::from_ast(&parse_map(OFFICE_MAP).expect("office map parses")).expect("office map builds")
}

/// Runs every stage that applies; the point is that none of them panics, and that every
/// diagnostic's span lies inside the text.
fn exercise(rules: &str, map_text: &str, map: &Map) {
    let in_bounds = |text: &str, ds: &[lplace::syntax::Diagnostic]| {
        for d in ds {
            assert!(
                d.span.start <= d.span.end && d.span.end <= text.len(),
                "{d:?}"
            );
            let _ = d.render_plain(&lplace::syntax::SourceFile::new("x", text));
        }
    };
    match parse_rules(rules) {
        Ok(ast) => {
            if let Err(ds) = check_rules(&ast, map) {
                in_bounds(rules, &ds);
            }
        }
        Err(ds) => {
            assert!(!ds.is_empty());
            in_bounds(rules, &ds);
        }
    }
    match parse_map(map_text) {
        Ok(ast) => {
            if let Err(ds) = Map::from_ast(&ast) {
                in_bounds(map_text, &ds);
            }
        }
        Err(ds) => {
            assert!(!ds.is_empty());
            in_bounds(map_text, &ds);
        }
    }
}

#[derive(Debug, Clone)]
enum Mutation {
    Delete(usize, usize),
    Insert(usize, u8),
    Duplicate(usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 1usize..20).prop_map(|(a, n)| Mutation::Delete(a, n)),
        (
            any::<usize>(),
            prop::sample::select(b"(){}<>;,!*&+-|:=~\"/ \naZ_0.".to_vec())
        )
            .prop_map(|(a, b)| Mutation::Insert(a, b)),
        (any::<usize>(), 1usize..40).prop_map(|(a, n)| Mutation::Duplicate(a, n)),
    ]
}

fn mutate(text: &str, ms: &[Mutation]) -> String {
    let mut b = text.as_bytes().to_vec();
    for m in ms {
        let len = b.len().max(1);
        match *m {
            Mutation::Delete(a, n) => {
                let a = a % len;
                let e = (a + n).min(b.len());
                if a < e {
                    b.drain(a..e);
                }
            }
            Mutation::Insert(a, c) => b.insert(a % (b.len() + 1), c),
            Mutation::Duplicate(a, n) => {
                let a = a % len;
                let e = (a + n).min(b.len());
                let chunk: Vec<u8> = b.get(a..e).map(<[u8]>::to_vec).unwrap_or_default();
                let at = e.min(b.len());
                b.splice(at..at, chunk);
            }
        }
    }
    String::from_utf8_lossy(&b).into_owned()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn arbitrary_strings_never_panic(s in any::<String>()) {
        exercise(&s, &s, &office_map());
    }

    #[test]
    fn grammar_alphabet_soup_never_panics(s in "[(){}<>;,!*&+|:=~\"/ \\-\\na-zA-Z_0-9.]{0,300}") {
        exercise(&s, &s, &office_map());
    }

    #[test]
    fn mutated_examples_never_panic(ms in prop::collection::vec(mutation(), 1..6)) {
        let map = office_map();
        exercise(&mutate(OFFICE_RULES, &ms), &mutate(OFFICE_MAP, &ms), &map);
    }
}

fn assert_too_deep(result: Result<impl std::fmt::Debug, Vec<lplace::syntax::Diagnostic>>) {
    let ds = result.expect_err("deep nesting is rejected");
    assert!(
        ds.iter()
            .any(|d| matches!(d.kind, DiagnosticKind::TooDeeplyNested { .. })),
        "{ds:?}"
    );
}

#[test]
fn hundred_thousand_deep_nesting_is_a_diagnostic() {
    const N: usize = 100_000;
    let parens = format!("|- {}a{} -> h;", "(".repeat(N), ")".repeat(N));
    assert_too_deep(parse_rules(&parens));
    let unclosed = format!("|- {}", "(".repeat(N));
    assert_too_deep(parse_rules(&unclosed));
    let bangs = format!("|- {}a -> h;", "!".repeat(N));
    assert_too_deep(parse_rules(&bangs));
    let tuples = format!("|- p({}a{}) -> h;", "<".repeat(N), ">".repeat(N));
    assert_too_deep(parse_rules(&tuples));
    let arrows = format!("|- ({}a) -> h;", "a -> ".repeat(N));
    assert_too_deep(parse_rules(&arrows));
    let braces = "{".repeat(N);
    assert_too_deep(parse_map(&braces));
}

const STACK: usize = 2 * 1024 * 1024;

#[test]
fn nesting_just_below_the_limit_parses_on_a_small_stack() {
    // 31 levels around an atom (the limit) must parse on a 2 MiB thread stack, the default for spawned threads.
    let text = format!(
        "percept s(value, time); |- {}s(v, t){} -> at_place(P_i);",
        "(".repeat(31),
        ")".repeat(31)
    );
    let handle = std::thread::Builder::new()
        .stack_size(STACK)
        .spawn(move || parse_rules(&text).map(|f| f.items.len()))
        .expect("thread starts");
    assert_eq!(handle.join().expect("no stack overflow"), Ok(2));
}
