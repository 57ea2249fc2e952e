//! The corpus of bad rule and map files in `tests/corpus/`: every file gives the expected
//! diagnostics (kind and line:column, asserted here independently of the rendering), and the
//! rendered report of each file is snapshotted (miette, unicode without colour, 100 columns).

use lplace::map::Map;
use lplace::rules::{check_map_against_rules, check_rules};
use lplace::syntax::diagnostic::{Diagnostic, SourceFile};
use lplace::syntax::{parse_map, parse_rules};

fn read(rel: &str) -> SourceFile {
    let path = format!("{}/{rel}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {rel}: {e}"));
    SourceFile::new(rel, text)
}

fn office_map() -> Map {
    let f = read("maps/office.map");
    Map::from_ast(&parse_map(&f.text).expect("office map parses")).expect("office map builds")
}

/// All diagnostics of a corpus file: rule files are checked against the office map, map files
/// are built on their own and (for `map_unknown_direction`) checked against the office rules.
fn diagnose(file: &SourceFile) -> Vec<Diagnostic> {
    if file.name.ends_with(".lpl") {
        match parse_rules(&file.text) {
            Err(d) => d,
            Ok(ast) => match check_rules(&ast, &office_map()) {
                Err(d) => d,
                Ok(_) => Vec::new(),
            },
        }
    } else {
        let ast = match parse_map(&file.text) {
            Err(d) => return d,
            Ok(a) => a,
        };
        let map = match Map::from_ast(&ast) {
            Err(d) => return d,
            Ok(m) => m,
        };
        let rules = read("rules/office.lpl");
        let ast = parse_rules(&rules.text).expect("office rules parse");
        // The office rules mention places of the office map; check them there, then cross-check
        // this map's directions against the resulting rule set. Only its errors: the corpus map
        // was not written for the office rules, so their parameters are missing from its places
        // (a warning each, tested in the CLI tests).
        let set = check_rules(&ast, &office_map()).expect("office rules check");
        check_map_against_rules(&map, &set)
            .into_iter()
            .filter(|d| d.is_error())
            .collect()
    }
}

/// The variant name of a diagnostic kind (`UnknownPredicate`).
fn kind_name(d: &Diagnostic) -> String {
    let dbg = format!("{:?}", d.kind);
    dbg.split(|c: char| !c.is_alphanumeric())
        .next()
        .unwrap_or("")
        .to_string()
}

/// Every corpus file with the diagnostics it must produce: kind and 1-based line:column.
/// A diagnostic kind's variant name with its 1-based line and column.
type Expected = (&'static str, usize, usize);

const CASES: &[(&str, &[Expected])] = &[
    ("arity_mismatch.lpl", &[("ArityMismatch", 3, 4)]),
    (
        "bad_field_value.lpl",
        &[("BadFieldValue", 1, 36), ("UnknownField", 2, 76)],
    ),
    ("bad_head.lpl", &[("BadHead", 3, 18)]),
    (
        "bad_setting_value.lpl",
        &[("BadSettingValue", 2, 13), ("BadSettingValue", 3, 17)],
    ),
    ("degree_out_of_range.lpl", &[("DegreeOutOfRange", 2, 34)]),
    ("duplicate_name.lpl", &[("DuplicateName", 2, 8)]),
    (
        "expect_without_similarity.lpl",
        &[("ExpectWithoutSimilarity", 1, 9)],
    ),
    ("grounding_budget.lpl", &[("GroundingBudget", 6, 4)]),
    (
        "map_bad_landmark_id.map",
        &[("BadLandmarkId", 1, 26), ("BadLandmarkId", 2, 26)],
    ),
    (
        "map_degree_out_of_range.map",
        &[("DegreeOutOfRange", 2, 16), ("DegreeOutOfRange", 3, 23)],
    ),
    ("map_duplicate_name.map", &[("DuplicateName", 2, 7)]),
    ("map_duplicate_path.map", &[("DuplicatePath", 4, 1)]),
    ("map_empty_range.map", &[("EmptyRange", 2, 31)]),
    ("map_invalid_box.map", &[("InvalidBox", 1, 28)]),
    (
        "map_negative_length.map",
        &[("NegativeLength", 1, 27), ("NegativeLength", 3, 22)],
    ),
    (
        "map_path_unknown_place.map",
        &[("PathToUnknownPlace", 4, 12)],
    ),
    ("map_relation_unbound.lpl", &[("MapRelationUnbound", 3, 35)]),
    (
        "map_syntax.map",
        &[("Syntax", 2, 20), ("Syntax", 4, 23), ("Syntax", 5, 9)],
    ),
    ("map_unknown_direction.map", &[("UnknownDirection", 4, 18)]),
    ("map_unknown_room.map", &[("UnknownRoom", 3, 20)]),
    ("map_zero_length.map", &[("ZeroLength", 3, 22)]),
    ("never_fires.lpl", &[("RuleNeverFires", 5, 1)]),
    (
        "reserved_name.lpl",
        &[("ReservedName", 1, 8), ("ReservedName", 2, 11)],
    ),
    ("schema_arity.lpl", &[("SchemaArity", 5, 40)]),
    (
        "several_errors.lpl",
        &[("Syntax", 5, 24), ("Syntax", 6, 23), ("Syntax", 8, 38)],
    ),
    ("syntax_missing_semicolon.lpl", &[("Syntax", 2, 32)]),
    ("too_deeply_nested.lpl", &[("TooDeeplyNested", 2, 36)]),
    ("unbound_variable.lpl", &[("UnboundVariable", 4, 18)]),
    ("undefined_parameter.lpl", &[("UndefinedParameter", 3, 20)]),
    ("unknown_domain.lpl", &[("UnknownDomain", 1, 28)]),
    ("unknown_domain_value.lpl", &[("UnknownDomainValue", 3, 62)]),
    ("unknown_landmark.lpl", &[("UnknownLandmark", 2, 21)]),
    ("unknown_place.lpl", &[("UnknownPlace", 2, 27)]),
    ("unknown_predicate.lpl", &[("UnknownPredicate", 2, 4)]),
    ("unknown_room.lpl", &[("UnknownRoom", 1, 29)]),
    ("unknown_setting.lpl", &[("UnknownSetting", 3, 5)]),
    ("unknown_similarity.lpl", &[("UnknownSimilarity", 1, 45)]),
    (
        "unknown_tracker_setting.lpl",
        &[("UnknownTrackerSetting", 4, 5)],
    ),
];

#[test]
fn every_corpus_file_gives_its_diagnostics() {
    for (name, expected) in CASES {
        let f = read(&format!("tests/corpus/{name}"));
        let got: Vec<(String, usize, usize)> = diagnose(&f)
            .iter()
            .map(|d| {
                let (l, c) = d.line_col(&f);
                (kind_name(d), l, c)
            })
            .collect();
        let want: Vec<(String, usize, usize)> = expected
            .iter()
            .map(|(k, l, c)| (k.to_string(), *l, *c))
            .collect();
        assert_eq!(got, want, "diagnostics of {name}");
    }
}

#[test]
fn the_corpus_covers_at_least_fifteen_kinds_and_every_file_is_listed() {
    let kinds: std::collections::BTreeSet<&str> = CASES
        .iter()
        .flat_map(|(_, e)| e.iter().map(|x| x.0))
        .collect();
    assert!(kinds.len() >= 15, "only {} kinds", kinds.len());
    let mut on_disk: Vec<String> =
        std::fs::read_dir(format!("{}/tests/corpus", env!("CARGO_MANIFEST_DIR")))
            .expect("corpus directory")
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .collect();
    on_disk.sort();
    let listed: Vec<String> = CASES.iter().map(|(n, _)| n.to_string()).collect();
    assert_eq!(on_disk, listed);
}

#[test]
fn plain_rendering_has_position_caret_and_help() {
    let f = read("tests/corpus/unknown_predicate.lpl");
    let text: String = diagnose(&f).iter().map(|d| d.render_plain(&f)).collect();
    assert_eq!(
        text,
        "tests/corpus/unknown_predicate.lpl:2:4: error: unknown predicate `sonar_wal`\n\
         \x20   |- sonar_wal(p, t) -> walls(t);\n\
         \x20      ^^^^^^^^^\n\
         help: known: `walls`, `at_place`, `in_room`, `in_region`, `at_wall`, `at_corner`, `at_open`, `at_door`\n\
         help: declare it with `percept …;` or `predicate …;`, or fix the spelling\n"
    );
}

#[cfg(feature = "cli")]
#[test]
fn rendered_reports_match_snapshots() {
    use miette::{GraphicalReportHandler, GraphicalTheme};
    let handler =
        GraphicalReportHandler::new_themed(GraphicalTheme::unicode_nocolor()).with_width(100);
    for (name, _) in CASES {
        let f = read(&format!("tests/corpus/{name}"));
        let report = lplace::syntax::diagnostic::Report::new(&f, &diagnose(&f));
        let mut out = String::new();
        handler
            .render_report(&mut out, &report)
            .expect("rendering into a String");
        insta::assert_snapshot!(name.replace('.', "_"), out);
    }
}
