//! The floor-plan statements of the map language (issue 18): the building axis, rotated boxes
//! and polygons (membership worked by hand and against a brute-force box), `open` and `door`
//! beside `wall`, the declared kinds domain, and the diagnostics each can raise.

use lplace::map::{Extent, Map};
use lplace::syntax::diagnostic::{Diagnostic, DiagnosticKind};
use lplace::syntax::parse_map;
use proptest::prelude::*;

fn map(text: &str) -> Map {
    Map::from_ast(&parse_map(text).expect("map parses")).expect("map builds")
}

fn errors(text: &str) -> Vec<Diagnostic> {
    Map::from_ast(&parse_map(text).expect("map parses")).expect_err("the map is rejected")
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

#[test]
fn axis_is_read_and_checked() {
    assert_eq!(
        map("axis -11; place A hall at (0, 0);").axis_deg(),
        Some(-11.0)
    );
    assert_eq!(
        map("axis 45; place A hall at (0, 0);").axis_deg(),
        Some(45.0)
    );
    assert_eq!(map("place A hall at (0, 0);").axis_deg(), None);
    let text = "place A hall at (0, 0);\naxis 79;";
    let d = errors(text);
    assert_eq!(d.len(), 1);
    assert_eq!(d[0].kind, DiagnosticKind::AxisOutOfRange { value: 79.0 });
    assert_eq!(&text[d[0].span.start..d[0].span.end], "79");
    let d = errors("axis 1; axis 2; place A hall at (0, 0);");
    assert!(matches!(
        d[0].kind,
        DiagnosticKind::DuplicateMapStatement { what: "axis" }
    ));
}

#[test]
fn start_is_read_once() {
    assert_eq!(
        map("start (1.5, -2); place A hall at (0, 0);").start(),
        Some((1.5, -2.0))
    );
    assert_eq!(map("place A hall at (0, 0);").start(), None);
    let text = "start (0, 0); place A hall at (0, 0);\nstart (1, 1);";
    let d = errors(text);
    assert_eq!(d.len(), 1);
    assert!(matches!(
        d[0].kind,
        DiagnosticKind::DuplicateMapStatement { what: "start" }
    ));
    assert_eq!(&text[d[0].span.start..d[0].span.end], "start (1, 1);");
}

#[test]
fn rotated_box_by_hand() {
    // (0,0)–(4,2) turned 90° about its centre (2,1) is x in [1,3], y in [-1,3].
    let m = map("place A room at (2, 1) extent box (0, 0, 4, 2) rotated 90;");
    let p = &m.places()[0];
    assert!(p.contains(2.0, 2.9));
    assert!(p.contains(1.001, -0.999)); // just inside a corner
    assert!(!p.contains(3.5, 1.0)); // inside the unturned box, outside the turned one
    let Extent::Box { x0, y0, x1, y1 } = p.extent else {
        panic!("a rotated box's extent is its bounding box")
    };
    assert!(close(x0, 1.0) && close(y0, -1.0) && close(x1, 3.0) && close(y1, 3.0));
    // A 2 m square turned 45° is the diamond |x| + |y| ≤ √2.
    let m = map("place A room at (0, 0) extent box (-1, -1, 1, 1) rotated 45;");
    let p = &m.places()[0];
    assert!(p.contains(1.0, 0.4));
    assert!(!p.contains(0.9, 0.9));
    assert!(p.contains(0.0, 1.41));
    assert!(!p.contains(0.0, 1.42));
}

#[test]
fn l_shaped_polygon_by_hand() {
    let m = map("place A room at (0.5, 0.5) extent polygon \
         ((0, 0), (4, 0), (4, 1), (1, 1), (1, 3), (0, 3), (0, 0));");
    let p = &m.places()[0];
    assert!(p.contains(0.5, 2.5));
    assert!(p.contains(3.5, 0.5));
    assert!(!p.contains(2.0, 2.0)); // in the bounding box, outside the L
    assert!(p.contains(4.0, 0.5)); // on an edge
    assert!(p.contains(1.0, 1.0)); // the inner corner
    assert!(!p.contains(-0.1, 0.0));
    assert_eq!(
        p.extent,
        Extent::Box {
            x0: 0.0,
            y0: 0.0,
            x1: 4.0,
            y1: 3.0
        }
    );
}

#[test]
fn polygons_that_do_not_close_or_enclose_nothing() {
    let text = "place A room at (0, 0) extent polygon ((0, 0), (2, 0), (2, 2), (0, 2));";
    let d = errors(text);
    assert_eq!(d.len(), 1);
    assert_eq!(
        d[0].kind,
        DiagnosticKind::PolygonNotClosed {
            x0: 0.0,
            y0: 0.0,
            x1: 0.0,
            y1: 2.0
        }
    );
    assert_eq!(&text[d[0].span.start..d[0].span.end], "(0, 2)");
    let d = errors("place A room at (0, 0) extent polygon ((0, 0), (1, 1), (2, 2), (0, 0));");
    assert_eq!(d[0].kind, DiagnosticKind::DegeneratePolygon { count: 3 });
    let d = errors("place A room at (0, 0) extent polygon ((0, 0), (2, 0), (0, 0));");
    assert_eq!(d[0].kind, DiagnosticKind::DegeneratePolygon { count: 2 });
    // A bow tie with area left over: edges 1 ((0,0)–(4,4)) and 3 ((4,0)–(0,2)) cross at
    // (4/3, 4/3).
    let d =
        errors("place A room at (0, 0) extent polygon ((0, 0), (4, 4), (4, 0), (0, 2), (0, 0));");
    assert_eq!(
        d[0].kind,
        DiagnosticKind::SelfCrossingPolygon {
            first: 1,
            second: 3
        }
    );
}

#[test]
fn open_door_and_wall() {
    let m = map("place D doorway at (0, 0) { wall East; wall West; door North; open South 0.8; }");
    let p = &m.places()[0];
    assert_eq!(p.door("North"), 1.0);
    assert_eq!(p.wall("North"), 1.0); // a door is an opening in a wall
    assert_eq!(p.open("South"), 0.8);
    assert_eq!(p.wall("South"), 0.0);
    assert_eq!(p.open("North"), 0.0);
    assert_eq!(m.door(0, "North"), 1.0);
    assert_eq!(m.open(0, "South"), 0.8);
    // `wall D` with `door D` is a wall with a door: allowed.
    map("place D doorway at (0, 0) { wall North 0.9; door North; }");
    let text = "place D doorway at (0, 0) { open North; door North; }";
    let d = errors(text);
    assert_eq!(d.len(), 1);
    assert_eq!(
        d[0].kind,
        DiagnosticKind::ContradictoryDirection {
            dir: "North".into(),
            first: "open",
            second: "door"
        }
    );
    assert_eq!(&text[d[0].span.start..d[0].span.end], "door North;");
    let d = errors("place D doorway at (0, 0) { wall West; open West; }");
    assert!(matches!(
        d[0].kind,
        DiagnosticKind::ContradictoryDirection {
            first: "wall",
            second: "open",
            ..
        }
    ));
    let d = errors("place D doorway at (0, 0) { door West; door West 0.5; }");
    assert!(matches!(
        d[0].kind,
        DiagnosticKind::DuplicateFeature { what: "door", .. }
    ));
    let d = errors("place D doorway at (0, 0) { open West 1.5; }");
    assert!(matches!(d[0].kind, DiagnosticKind::DegreeOutOfRange { .. }));
}

#[test]
fn kinds_domain() {
    let m = map("kinds {corner, doorway}; place A corner at (0, 0); place B doorway at (1, 0);");
    assert_eq!(
        m.kinds(),
        Some(&["corner".to_string(), "doorway".to_string()][..])
    );
    let text = "kinds {corner, doorway};\nplace A room at (0, 0);";
    let d = errors(text);
    assert_eq!(d.len(), 1);
    assert_eq!(
        d[0].kind,
        DiagnosticKind::UndeclaredKind {
            name: "room".into()
        }
    );
    assert_eq!(&text[d[0].span.start..d[0].span.end], "room");
    // Without a declaration any kind word goes, as before.
    assert_eq!(map("place A anything at (0, 0);").kinds(), None);
    let d = errors("kinds {corner, corner}; place A corner at (0, 0);");
    assert!(matches!(
        d[0].kind,
        DiagnosticKind::DuplicateName { what: "kind", .. }
    ));
}

#[test]
fn every_bundled_map_still_loads() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("maps");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .expect("maps/ lists")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "map"))
        .collect();
    names.sort();
    assert!(names.len() >= 5);
    for path in names {
        let text = std::fs::read_to_string(&path).expect("reads");
        let ast = parse_map(&text).unwrap_or_else(|d| panic!("{}: {d:?}", path.display()));
        Map::from_ast(&ast).unwrap_or_else(|d| panic!("{}: {d:?}", path.display()));
    }
}

#[test]
fn an_open_side_the_places_beyond_reach_along_less_than_half_of_is_warned_about() {
    use lplace::map::expect::side_reached;
    use lplace::rules::check_map_against_rules;
    use lplace::syntax::diagnostic::Severity;
    // J is 6 m tall; C adjoins its West side over y 2 .. 4.4 (2.4 m: 40 %), S its South side
    // over the whole 6 m (the 0.3 m gap is under a wall's thickness), nothing its East side.
    let text = "place J junction at (3, 3) extent box (0, 0, 6, 6) { open West; open South; open East; }\n\
                place C corridor at (-3, 3) extent box (-6, 2, 0, 4.4);\n\
                place S corridor at (3, -3) extent box (-1, -6, 7, -0.3);\n\
                place R room at (3, 9) extent box (0, 6, 6, 9) rotated 10;\n";
    let m = map(text);
    let near = |got: Option<f64>, want: f64| got.is_some_and(|g| close(g, want));
    assert!(near(side_reached(m.places(), 0, "West"), 0.4));
    assert!(near(side_reached(m.places(), 0, "South"), 1.0));
    assert_eq!(side_reached(m.places(), 0, "East"), None);
    // A turned box neither is checked nor counts as a neighbour; diagonals are not sides.
    assert_eq!(side_reached(m.places(), 0, "North"), None);
    assert_eq!(side_reached(m.places(), 3, "South"), None);
    assert_eq!(side_reached(m.places(), 0, "NorthWest"), None);
    let rules = lplace::syntax::parse_rules("predicate p(time);").expect("rules parse");
    let set = lplace::rules::check_rules(&rules, &m).expect("rules check");
    let d = check_map_against_rules(&m, &set);
    assert_eq!(d.len(), 1, "{d:?}");
    assert_eq!(d[0].severity, Severity::Warning);
    assert_eq!(
        d[0].kind,
        DiagnosticKind::OpenSidePartlyReached {
            dir: "West".into(),
            percent: 40
        }
    );
    assert!(text[d[0].span.start..d[0].span.end].starts_with("place J"));
    // Written as a door, the same side is fine.
    let fixed = map(&text.replace("open West;", "door West;"));
    let set = lplace::rules::check_rules(&rules, &fixed).expect("rules check");
    assert!(check_map_against_rules(&fixed, &set).is_empty());
}

proptest! {
    /// A polygon written as a box's four corners holds exactly the box's points, and a box turned
    /// by 0° is the box.
    #[test]
    fn rectangle_polygon_is_the_box(
        x0 in -5.0f64..5.0, y0 in -5.0f64..5.0, w in 0.1f64..4.0, h in 0.1f64..4.0,
        px in -10.0f64..10.0, py in -10.0f64..10.0,
    ) {
        let (x1, y1) = (x0 + w, y0 + h);
        let poly = map(&format!(
            "place A room at (0, 0) extent polygon (({x0}, {y0}), ({x1}, {y0}), ({x1}, {y1}), ({x0}, {y1}), ({x0}, {y0}));"
        ));
        let turned = map(&format!("place A room at (0, 0) extent box ({x0}, {y0}, {x1}, {y1}) rotated 0;"));
        let inside = x0 <= px && px <= x1 && y0 <= py && py <= y1;
        prop_assert_eq!(poly.places()[0].contains(px, py), inside);
        prop_assert_eq!(turned.places()[0].contains(px, py), inside);
    }

    /// Turning a box by θ and the point by θ about the box's centre keeps membership (the
    /// turned box against the plain box, as a brute-force reference).
    #[test]
    fn rotated_box_matches_turned_point(
        theta in -180.0f64..180.0, px in -4.0f64..4.0, py in -4.0f64..4.0,
    ) {
        let m = map(&format!("place A room at (0, 0) extent box (-2, -1, 2, 1) rotated {theta};"));
        let (s, c) = (-theta).to_radians().sin_cos();
        let (qx, qy) = (c * px - s * py, s * px + c * py);
        // Points within 1e-9 of the edge may go either way.
        let margin = (2.0 - qx.abs()).abs().min((1.0 - qy.abs()).abs());
        prop_assume!(margin > 1e-9);
        prop_assert_eq!(m.places()[0].contains(px, py), qx.abs() <= 2.0 && qy.abs() <= 1.0);
    }
}

/// `free(D)` of place 0 as (lo, hi) in metres.
fn free_m(m: &Map, dir: &str) -> Option<(f64, f64)> {
    m.expected(0, "free", Some(dir))
        .map(|e| (e.lo.exp(), e.hi.exp()))
}

fn close_pair(got: Option<(f64, f64)>, want: (f64, f64)) -> bool {
    got.is_some_and(|(lo, hi)| (lo - want.0).abs() < 1e-9 && (hi - want.1).abs() < 1e-9)
}

#[test]
fn free_ranges_from_a_corridor_description() {
    // A 4 m × 2 m stretch of an East–West corridor.
    let m = map("place C corridor at (2, 0) extent box (0, -1, 4, 1) \
                 { wall North; wall South; open East; open West; }");
    // Wall: 0.3 m against it, up to the 2 m across the extent + 1.5 m beyond its edge.
    assert!(close_pair(free_m(&m, "North"), (0.3, 3.5)));
    assert!(close_pair(free_m(&m, "South"), (0.3, 3.5)));
    // Open branch: 3–15 m.
    assert!(close_pair(free_m(&m, "East"), (3.0, 15.0)));
    // A diagonal beside an open branch may meet a corner or run on: 0.3–15 m.
    assert!(close_pair(free_m(&m, "NorthEast"), (0.3, 15.0)));
    assert_eq!(free_m(&m, "Up"), None);
}

#[test]
fn free_ranges_of_a_room_a_door_and_overrides() {
    // A 3 m square room, door to the West: the diagonal between two plain walls runs at most
    // the square's diagonal, 3√2 m, + 1.5 m.
    let m = map("place R room at (1.5, 1.5) extent box (0, 0, 3, 3) \
                 { wall North; wall East; wall South; door West; }");
    let diag = 3.0 * 2f64.sqrt() + 1.5;
    assert!(close_pair(free_m(&m, "NorthEast"), (0.3, diag)));
    assert!(close_pair(free_m(&m, "SouthEast"), (0.3, diag)));
    // Door: a jamb close by, or the view through it.
    assert!(close_pair(free_m(&m, "West"), (0.3, 15.0)));
    assert!(close_pair(free_m(&m, "NorthWest"), (0.3, 15.0)));
    // A hall longer than the cap: the wall range stops at 15 m.
    let m = map("place H hall at (0, 0) extent box (0, 0, 20, 4) { wall East; }");
    assert!(close_pair(free_m(&m, "East"), (0.3, 15.0)));
    // Unsaid cardinal directions of a described place: anything.
    assert!(close_pair(free_m(&m, "North"), (0.3, 15.0)));
    // A disc: its diameter.
    let m = map("place D corner at (0, 0) extent radius 1 { wall East; }");
    assert!(close_pair(free_m(&m, "East"), (0.3, 3.5)));
    // An undescribed place has none; a written parameter wins over geometry.
    assert_eq!(free_m(&map("place A room at (0, 0);"), "North"), None);
    let m = map("place A room at (0, 0) { wall North; param free(North) = 0.1 .. 0.2; }");
    assert_eq!(
        m.expected(0, "free", Some("North")).map(|e| (e.lo, e.hi)),
        Some((0.1, 0.2))
    );
}

#[test]
fn the_reference_example_loads() {
    let doc = include_str!("../../docs/languages.md");
    let section = doc
        .split("### Floor-plan statements")
        .nth(1)
        .expect("the section exists");
    let block = section
        .split("```text\n")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("the example block");
    let m = map(block);
    assert_eq!(m.axis_deg(), Some(-11.0));
    assert_eq!(m.places().len(), 3);
    let d1 = &m.places()[1];
    assert_eq!(
        (d1.wall("East"), d1.door("North"), d1.wall("North")),
        (1.0, 1.0, 1.0)
    );
    assert!(d1.contains(3.0, 1.6) && !d1.contains(3.0, 0.9));
}

/// The place `at_open`/`at_door`/`at_wall` pick out when a `Dir` percept towards North is seen
/// fully.
fn decided_by(relation: &str) -> Option<usize> {
    use lplace::engine::{CompileOptions, Engine};
    use lplace::logic::Decision;
    use lplace::syntax::diagnostic::SourceFile;
    let map = SourceFile::new(
        "m.map",
        "place A corridor at (0, 0) { open North; }\n\
         place B doorway at (5, 0) { door North; }\n\
         place C room at (10, 0) { wall West; }",
    );
    let rules = SourceFile::new(
        "r.lpl",
        format!(
            "logic {{ tnorm = product; implication = residuum; normalisation = min; threshold = 0.5; margin = 0.1; }}\n\
             domain Dir = {{North, West}};\n\
             percept sonar_wall(value, Dir, time);\n\
             |- ((sonar_wall(p, d, t) & {relation}(p, t)) -> at_place(P_i)) for all d in Dir;"
        ),
    );
    let mut engine = Engine::load_with(&map, &rules, &CompileOptions::default()).expect("loads");
    let mut frame = engine.new_frame();
    let slot = engine
        .percepts()
        .slot("sonar_wall", &["North"])
        .expect("a slot");
    frame.set(slot, 1.0, None);
    match engine.step(&frame) {
        Decision::Place { place, .. } => Some(place),
        Decision::Disoriented(_) => None,
    }
}

#[test]
fn rules_read_openings_and_doors() {
    assert_eq!(decided_by("at_open"), Some(0));
    assert_eq!(decided_by("at_door"), Some(1));
    // A door is in a wall: B has a wall to the North; C's wall is to the West.
    assert_eq!(decided_by("at_wall"), Some(1));
}
