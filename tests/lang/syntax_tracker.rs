//! The `tracker { … }` block of a rule file: it parses and checks into the settings the engine
//! tracks with, equal to a tracker file's; a bad key or value is an error at its span.

use crate::support::carmen::repo;
use lplace::engine::grid_tracker::GridTrackConfig;
use lplace::engine::tracker::TrackerConfig;
use lplace::engine::{CompileOptions, Engine};
use lplace::map::Map;
use lplace::rules::check_rules;
use lplace::syntax::diagnostic::{DiagnosticKind, SourceFile};
use lplace::syntax::{parse_map, parse_rules};

fn office_map() -> Map {
    Map::from_ast(&parse_map(&repo("maps/office.map")).expect("parses")).expect("builds")
}

/// The diagnostics of `text` (a rule file) against the office map, as (kind, excerpt).
fn errors(text: &str) -> Vec<(DiagnosticKind, String)> {
    let ast = parse_rules(text).expect("parses");
    match check_rules(&ast, &office_map()) {
        Ok(_) => Vec::new(),
        Err(d) => d
            .into_iter()
            .map(|d| (d.kind.clone(), text[d.span.start..d.span.end].to_string()))
            .collect(),
    }
}

#[test]
fn the_laser_rules_track_as_the_intel_tracker_file() {
    let file = TrackerConfig::from_ron(&repo("config/intel-tracker.ron")).expect("tracker file");
    // rules/laser.lpl takes a place on less support of its own, holds a decided one and lets a
    // surveyed place that fits worse than the best lose down to a relative floor (its comments
    // say why).
    let grid = file.grid.map(|g| GridTrackConfig {
        relative_floor: 0.5,
        ..g
    });
    let laser = TrackerConfig {
        min_support: 0.05,
        hold: 0.3,
        grid,
        ..file
    };
    for (rules, want) in [("rules/intel.lpl", &file), ("rules/laser.lpl", &laser)] {
        let map = SourceFile::new("maps/intel.map", repo("maps/intel.map"));
        let src = SourceFile::new(rules, repo(rules));
        let engine = Engine::load_with(&map, &src, &CompileOptions::default()).expect("loads");
        assert_eq!(&engine.tracker_config(), want, "{rules}");
    }
    let office = Engine::office().expect("bundled engine");
    assert!(office.rules().tracker.is_none());
    assert_eq!(office.tracker_config(), TrackerConfig::default());
}

#[test]
fn settings_left_out_keep_their_defaults_and_an_empty_grid_asks_for_the_grid() {
    let ast = parse_rules("tracker { tnorm = min; use_heading = false; grid { } }").unwrap();
    let set = check_rules(&ast, &office_map()).expect("checks");
    let cfg = TrackerConfig::from_settings(set.tracker.as_ref().expect("a block"));
    let want = TrackerConfig::from_ron("(tnorm: min, use_heading: false, grid: Some(()))").unwrap();
    assert_eq!(cfg, want);
    assert_ne!(cfg, TrackerConfig::default());
}

#[test]
fn a_bad_key_or_value_is_diagnosed_at_its_span() {
    let got = errors("tracker {\n  bais = 0.1;\n  grid { floor = 2; }\n  tnorm = 0.5;\n}\n");
    let kinds: Vec<(String, &str)> = got
        .iter()
        .map(|(k, s)| (format!("{k}"), s.as_str()))
        .collect();
    assert_eq!(
        kinds,
        [
            ("unknown tracker setting `bais`".to_string(), "bais"),
            (
                "bad value for tracker setting `floor`: expected a number in [0, 1]".to_string(),
                "2"
            ),
            (
                "bad value for tracker setting `tnorm`: expected min, product or lukasiewicz"
                    .to_string(),
                "0.5"
            ),
        ]
    );
    // A grid key outside `grid { … }` is unknown there; two blocks or two keys are duplicates.
    let got = errors("tracker { cell_size = 0.5; }");
    assert!(
        matches!(&got[..], [(DiagnosticKind::UnknownTrackerSetting { .. }, s)] if s == "cell_size")
    );
    let got = errors("tracker { bias = 0.1; bias = 0.2; }\ntracker { }");
    assert_eq!(got.len(), 2, "{got:?}");
    assert!(got
        .iter()
        .all(|(k, _)| matches!(k, DiagnosticKind::DuplicateName { .. })));
}
