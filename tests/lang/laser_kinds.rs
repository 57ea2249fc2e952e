//! `rules/laser.lpl` reads the place's kind: two places described alike (same walls, openings
//! and extent size) differ only in kind, and a scan with no side opening rules out the one that
//! is a junction. Also the check that lets a rule file name a kind a building lacks.

use crate::support::carmen::repo;
use lplace::engine::{CompileOptions, Engine};
use lplace::map::Map;
use lplace::rules::check_rules;
use lplace::syntax::diagnostic::{DiagnosticKind, SourceFile};
use lplace::syntax::{parse_map, parse_rules};

/// Two places with the same description (a corridor piece running East–West, 2 m across) ten
/// metres apart, of the kinds `a` and `b`.
fn twin_map(a: &str, b: &str) -> String {
    let sides = "{ wall North; wall South; open East; open West; }";
    format!(
        "kinds {{corridor, junction}};\n\
         place A {a} at (0, 0) extent box (-1, -1, 1, 1) {sides}\n\
         place B {b} at (10, 0) extent box (9, -1, 11, 1) {sides}\n\
         path A -- B;"
    )
}

/// The normalised possibilities of A and B after one frame that fits both descriptions alike,
/// with `openings` side openings.
fn possibilities(map_text: &str, openings: f64) -> (f64, f64) {
    let map = SourceFile::new("twins.map", map_text);
    let rules = SourceFile::new("rules/laser.lpl", repo("rules/laser.lpl"));
    let mut engine = Engine::load_with(&map, &rules, &CompileOptions::default()).expect("loads");
    let mut frame = engine.new_frame();
    // Inside both places' derived ranges: 1 m to the wall South (0.3 m to 2 + 1.5 m), 5 m along
    // the open corridor (3–15 m), 2 m along the diagonals (next to an opening: 0.3–15 m). North
    // reads 15 m, ln 15 − ln 3.5 = 1.46 beyond its wall's range, past the trapezoid's 0.1 + 1.0:
    // that direction keeps the bias 0.5, so each place's signature is 0.5 (not 1, at which each
    // twin's support 0.5 would cap the other at 0.5, under the kind rule's 0.7).
    let reading = [
        ("North", 15.0_f64),
        ("South", 1.0),
        ("East", 5.0),
        ("West", 5.0),
        ("NorthEast", 2.0),
        ("NorthWest", 2.0),
        ("SouthEast", 2.0),
        ("SouthWest", 2.0),
    ];
    for (dir, metres) in reading {
        let slot = engine
            .percepts()
            .slot("free_range", &[dir])
            .expect("a free_range slot");
        frame.set(slot, 1.0, Some(metres.ln()));
    }
    let slot = engine
        .percepts()
        .slot("side_openings", &[])
        .expect("a side_openings slot");
    frame.set(slot, 1.0, Some(openings));
    engine.step(&frame);
    let pi = &engine.distribution().possibility;
    (pi[0], pi[1])
}

#[test]
fn a_scan_without_side_openings_rules_out_the_junction_whichever_place_it_is() {
    // Alike but for their kinds: each has support 0.5 · 0.5 = 0.25, capping the other at 0.75;
    // the rule-out of weight 0.3 caps the junction at 0.7. Min normalisation lifts the corridor
    // (the height, 0.75) to 1 and leaves the junction at 0.7.
    let (a, b) = possibilities(&twin_map("junction", "corridor"), 0.0);
    assert!(
        (b - 1.0).abs() < 1e-9 && (a - 0.7).abs() < 1e-9,
        "A {a}, B {b}"
    );
    let (a, b) = possibilities(&twin_map("corridor", "junction"), 0.0);
    assert!(
        (a - 1.0).abs() < 1e-9 && (b - 0.7).abs() < 1e-9,
        "A {a}, B {b}"
    );
    // A side opening seen: the kinds say nothing, the twins stay alike.
    let (a, b) = possibilities(&twin_map("junction", "corridor"), 1.0);
    assert!((a - b).abs() < 1e-12, "A {a}, B {b}");
    // Without a junction (Freiburg 101's hall) the region is empty and the rule does nothing.
    let (a, b) = possibilities(&twin_map("corridor", "corridor"), 0.0);
    assert!((a - b).abs() < 1e-12, "A {a}, B {b}");
}

fn region_check(map_text: &str) -> Result<(), Vec<DiagnosticKind>> {
    let map = Map::from_ast(&parse_map(map_text).expect("parses")).expect("builds");
    let rules = parse_rules("region Doors = kind doorway;").expect("parses");
    check_rules(&rules, &map)
        .map(|_| ())
        .map_err(|d| d.into_iter().map(|d| d.kind).collect())
}

#[test]
fn a_region_over_a_kind_no_place_has_is_empty_only_when_the_map_declares_its_kinds() {
    // Undeclared kinds: an empty region is most likely a misspelt kind.
    assert_eq!(
        region_check("place A corridor at (0, 0);"),
        Err(vec![DiagnosticKind::UnknownKind {
            name: "doorway".into()
        }])
    );
    // Declared: the building has no doorway, and says so.
    assert_eq!(
        region_check("kinds {corridor}; place A corridor at (0, 0);"),
        Ok(())
    );
    assert_eq!(
        region_check("kinds {corridor, doorway}; place A corridor at (0, 0);"),
        Ok(())
    );
}
