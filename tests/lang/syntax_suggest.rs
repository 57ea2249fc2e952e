//! Spelling help for unknown names: the edit distance against its recursive definition, the
//! choice between "did you mean" and the list of known names on hand-worked cases, and the
//! messages a misspelt percept, direction, place or similarity gets from the checker.

use lplace::map::Map;
use lplace::rules::check_rules;
use lplace::syntax::diagnostic::{Diagnostic, SourceFile};
use lplace::syntax::suggest::{edit_distance, suggest, Suggestion, MAX_LISTED};
use lplace::syntax::{parse_map, parse_rules};
use proptest::prelude::*;

/// Levenshtein distance straight from its definition (exponential; short strings only).
fn distance_by_definition(a: &[char], b: &[char]) -> usize {
    match (a.split_first(), b.split_first()) {
        (None, _) => b.len(),
        (_, None) => a.len(),
        (Some((x, ra)), Some((y, rb))) => {
            let substitute = distance_by_definition(ra, rb) + usize::from(x != y);
            let delete = distance_by_definition(ra, b) + 1;
            let insert = distance_by_definition(a, rb) + 1;
            substitute.min(delete).min(insert)
        }
    }
}

proptest! {
    #[test]
    fn edit_distance_is_the_definition(a in "[abé_]{0,6}", b in "[abé_]{0,6}") {
        let (ca, cb): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
        prop_assert_eq!(edit_distance(&a, &b), distance_by_definition(&ca, &cb));
    }
}

#[test]
fn edit_distance_hand_worked() {
    assert_eq!(edit_distance("", ""), 0);
    assert_eq!(edit_distance("kitten", "sitting"), 3);
    assert_eq!(edit_distance("sonar_wal", "sonar_wall"), 1);
    assert_eq!(edit_distance("Nord", "North"), 2); // d→t, +h
    assert_eq!(edit_distance("Nord", "West"), 4);
    assert_eq!(edit_distance("Süd", "Sud"), 1); // characters, not bytes
}

fn dirs() -> [&'static str; 4] {
    ["North", "East", "South", "West"]
}

#[test]
fn close_names_are_suggested_far_ones_listed() {
    let did = |s: &str| Some(Suggestion::DidYouMean(s.to_string()));
    assert_eq!(suggest("Nord", dirs()), did("North"));
    assert_eq!(suggest("north", dirs()), did("North"));
    assert_eq!(suggest("Wset", dirs()), did("West"));
    let all = Some(Suggestion::KnownAre {
        names: dirs().iter().map(|s| s.to_string()).collect(),
        more: 0,
    });
    assert_eq!(suggest("Up", dirs()), all);
    assert_eq!(suggest("Nowhere", dirs()), all);
    assert_eq!(suggest("x", std::iter::empty()), None);
    // Equally close to several: no guess, the list.
    let places = ["P0", "P1", "P2"];
    let listed = Some(Suggestion::KnownAre {
        names: places.iter().map(|s| s.to_string()).collect(),
        more: 0,
    });
    assert_eq!(suggest("P9", places), listed);
    assert_eq!(suggest("P1x", places), did("P1"));
    // A name given twice is one candidate, not a tie with itself.
    assert_eq!(suggest("rnage", ["range", "range"]), did("range"));
}

#[test]
fn the_list_of_known_names_is_capped() {
    let names: Vec<String> = (0..20).map(|i| format!("Room{i}")).collect();
    let got = suggest("Kitchen", names.iter().map(String::as_str));
    let want = Suggestion::KnownAre {
        names: names[..MAX_LISTED].to_vec(),
        more: 20 - MAX_LISTED,
    };
    assert_eq!(got, Some(want));
    assert_eq!(
        got.map(|s| s.to_string()).unwrap_or_default(),
        "known: `Room0`, `Room1`, `Room2`, `Room3`, `Room4`, `Room5`, `Room6`, `Room7` and 12 more"
    );
}

fn office_map() -> Map {
    let path = format!("{}/maps/office.map", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).expect("office map");
    Map::from_ast(&parse_map(&text).expect("office map parses")).expect("office map builds")
}

const MISSPELT: &str = "\
domain Dir = {North, East, South, West};
similarity range = trapezoid(core: 0.6, slope: 1.2, height: 1, bias: 0);
percept sonar_wall(value, Dir, time);
percept beacon_distance(value, expect, time) ~ rnage;
predicate walls(time);
|- sonar_wal(p, t) -> walls(t);
|- sonar_wall(p, Nord, t) -> walls(t);
|- walls(t) -> at_place(Kitchen);
";

fn diagnose() -> (SourceFile, Vec<Diagnostic>) {
    let file = SourceFile::new("misspelt.lpl", MISSPELT);
    let ast = parse_rules(&file.text).expect("parses");
    let diags = check_rules(&ast, &office_map()).expect_err("has errors");
    (file, diags)
}

#[test]
fn the_checker_suggests_spellings() {
    let (file, diags) = diagnose();
    let got: Vec<(usize, String)> = diags
        .iter()
        .map(|d| {
            (
                d.line_col(&file).0,
                d.suggestion
                    .as_ref()
                    .map(|s| s.to_string())
                    .unwrap_or_default(),
            )
        })
        .collect();
    let want = [
        (4, "did you mean `range`?".to_string()),
        (6, "did you mean `sonar_wall`?".to_string()),
        (7, "did you mean `North`?".to_string()),
        (
            8,
            "known: `P0`, `P1`, `P2`, `P3`, `P4`, `P5`, `P6`, `P7`".to_string(),
        ),
    ];
    assert_eq!(got, want);
    let plain = diags[1].render_plain(&file);
    assert_eq!(
        plain,
        "misspelt.lpl:6:4: error: unknown predicate `sonar_wal`\n\
         \x20   |- sonar_wal(p, t) -> walls(t);\n\
         \x20      ^^^^^^^^^\n\
         help: did you mean `sonar_wall`?\n\
         help: declare it with `percept …;` or `predicate …;`, or fix the spelling\n"
    );
}

#[cfg(feature = "cli")]
#[test]
fn suggestions_in_the_rendered_report() {
    use miette::{GraphicalReportHandler, GraphicalTheme};
    let (file, diags) = diagnose();
    let handler =
        GraphicalReportHandler::new_themed(GraphicalTheme::unicode_nocolor()).with_width(100);
    let report = lplace::syntax::diagnostic::Report::new(&file, &diags);
    let mut out = String::new();
    handler
        .render_report(&mut out, &report)
        .expect("rendering into a String");
    insta::assert_snapshot!("misspelt_names", out);
}
