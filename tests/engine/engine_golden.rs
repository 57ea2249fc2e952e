//! Golden tests of the compiler against paper 003: eq. (5) compiles to eq. (6), and eq. (7)
//! evaluates to degrees worked out by hand. Every expected value is derived in the comments from
//! the paper's formulas and the office map (`maps/office.map`), not read off the program.

use lplace::engine::{Engine, Frame, OFFICE_MAP};
use lplace::syntax::diagnostic::SourceFile;

const HEADER: &str = "
logic { tnorm = min; implication = residuum; normalisation = min; threshold = 0.5; }
domain Dir = {North, East, South, West};
similarity bearing = trapezoid(core: 20, slope: 40, height: 1, bias: 0, period: 360);
similarity range = trapezoid(core: 0.6, slope: 1.2, height: 1, bias: 0);
percept beacon_angle(value, expect, time) ~ bearing;
percept beacon_distance(value, expect, time) ~ range;
percept sonar_wall(value, Dir, time);
percept laser_wall(value, Dir, time);
percept laser_corner(value, Dir, Dir, time);
predicate beacon_signature(value, expect, time);
predicate corner(Dir, Dir, time);
";

const EQ5: &str = "
|- ((beacon_angle(a, A_i, t) & beacon_distance(l, L_i, t)) -> beacon_signature(<a, l>, <A_i, L_i>, t));
|- beacon_signature(<a, l>, <A_i, L_i>, t) -> at_place(P_i);
";

const EQ7: &str = "
|- ((sonar_wall(p1, d1, t) & at_wall(p1, t) & laser_wall(p2, d2, t) & at_wall(p2, t)) (+)
    (sonar_wall(p3, d2, t) & at_wall(p3, t) & laser_wall(p4, d1, t) & at_wall(p4, t)) (+)
    (laser_corner(p5, d1, d2, t) & at_corner(p5, t)))
   -> corner(d1, d2, t)
   for all (d1, d2) in {(North, East), (North, West), (South, East), (South, West)};
|- corner(North, East, t) (+) corner(North, West, t) (+) corner(South, East, t) (+) corner(South, West, t) -> at_place(P_i);
";

fn engine(rules: &str) -> Engine {
    let map = SourceFile::new("office.map", OFFICE_MAP);
    let rules = SourceFile::new("test.lpl", format!("{HEADER}{rules}"));
    match Engine::load(&map, &rules) {
        Ok(e) => e,
        Err(e) => panic!("{e}: {:#?}", e.diagnostics),
    }
}

fn place(engine: &Engine, name: &str) -> usize {
    engine
        .map()
        .places()
        .iter()
        .position(|p| p.name == name)
        .expect("office map place")
}

fn set(
    engine: &Engine,
    frame: &mut Frame,
    name: &str,
    args: &[&str],
    degree: f64,
    value: Option<f64>,
) {
    let slot = engine
        .percepts()
        .slot(name, args)
        .expect("declared percept");
    frame.set(slot, degree, value);
}

#[test]
fn eq5_compiles_to_eq6() {
    let e = engine(EQ5);
    let p1 = place(&e, "P1");
    // Paper eq. (6): β = max(β_θ, β_d) over dissimilarities. Ours is the min of confidences, each
    // percept compared with P1's signature A = 167.5°, L = 4.61 m (maps/office.map).
    let c = e.compiled();
    assert_eq!(
        c.tape.render(c.support[p1], &c.percepts),
        "min(beacon_angle ~bearing 167.5, beacon_distance ~range 4.61)"
    );
    assert_eq!(
        c.tape.render_dissimilarity(c.support[p1], &c.percepts),
        "max(δ[beacon_angle ~bearing 167.5], δ[beacon_distance ~range 4.61])"
    );
}

#[test]
fn eq5_numbers_equal_one_minus_max_of_dissimilarities() {
    let mut e = engine(EQ5);
    let p1 = place(&e, "P1");
    let mut frame = e.new_frame();
    // Values on P1's signature, so both similarities are 1 and only the percept degrees count.
    for (dt, dd) in [(0.9, 0.7), (0.2, 0.95), (1.0, 0.0), (0.55, 0.55)] {
        set(&e, &mut frame, "beacon_angle", &[], dt, Some(167.5));
        set(&e, &mut frame, "beacon_distance", &[], dd, Some(4.61));
        e.step(&frame);
        let (delta_t, delta_d): (f64, f64) = (1.0 - dt, 1.0 - dd);
        let beta = delta_t.max(delta_d); // eq. (6)
        let got = e.distribution().support[p1];
        assert!(
            (got - (1.0 - beta)).abs() < 1e-12,
            "β_θ={delta_t} β_d={delta_d}: got {got}"
        );
    }
    // Off-signature: angle 12° from A (inside the core ±10? no: 12 > 10, 2° down a 40° slope):
    // similarity 1 − 2/40 = 0.95; degree min(0.9, 0.95) = 0.9 → with distance 1.0: support 0.9.
    set(&e, &mut frame, "beacon_angle", &[], 0.9, Some(179.5));
    set(&e, &mut frame, "beacon_distance", &[], 1.0, Some(4.61));
    e.step(&frame);
    assert!((e.distribution().support[p1] - 0.9).abs() < 1e-12);
    // 30° off: similarity 1 − 20/40 = 0.5 caps the degree: support 0.5.
    set(&e, &mut frame, "beacon_angle", &[], 0.9, Some(137.5));
    e.step(&frame);
    assert!((e.distribution().support[p1] - 0.5).abs() < 1e-12);
}

#[test]
fn eq7_by_hand() {
    let mut e = engine(EQ7);
    let mut frame = e.new_frame();
    set(&e, &mut frame, "sonar_wall", &["North"], 0.7, None);
    set(&e, &mut frame, "laser_wall", &["East"], 0.6, None);
    set(&e, &mut frame, "sonar_wall", &["East"], 0.2, None);
    set(&e, &mut frame, "laser_wall", &["North"], 0.9, None);
    set(
        &e,
        &mut frame,
        "laser_corner",
        &["North", "East"],
        0.5,
        None,
    );
    e.step(&frame);
    let s = |name: &str| e.distribution().support[place(&e, name)];
    // P2 and P5 have walls North and East and a North-East corner (at_wall = at_corner = 1):
    //   corner(N, E) = max(min(0.7, 1, 0.6, 1), min(0.2, 1, 0.9, 1), min(0.5, 1)) = 0.6.
    // The other pairs: corner(N, W) needs a West wall (none at P2/P5) except its second
    // disjunct uses sonar West / laser North: sonar_wall(West) is missing (0) → 0. Likewise
    // corner(S, ·) needs a South wall. So at_place = 0.6.
    assert!((s("P2") - 0.6).abs() < 1e-12, "P2 {}", s("P2"));
    assert!((s("P5") - 0.6).abs() < 1e-12, "P5 {}", s("P5"));
    // P1 (walls North, West): corner(N, W) = max(min(sonar N 0.7, 1, laser W 0, 1), min(sonar W 0,
    // …), min(laser_corner(N, W) 0, 1)) = 0; corner(N, E): at_wall(East) = 0 → 0. So 0.
    assert_eq!(s("P1"), 0.0);
    // P3 has a half-certain East wall (0.5) and no North wall: every disjunct needs a North
    // wall or the North-East corner → 0.
    assert_eq!(s("P3"), 0.0);
    assert_eq!(s("P0"), 0.0);
}

/// A place may expect a range of values (`param W = 1.5 .. 2.5;`): a reading inside it is a full
/// match, one outside is compared with the nearest end. Worked with a 1-m core (±0.5) and 2-m
/// slope: readings 2.0 and 2.9 match fully (inside; 0.4 beyond the end, within ±0.5), 3.5 is 1.0
/// beyond, 0.5 into the slope, μ = 1 − 0.5/2 = 0.75; 5.5 is 3.0 beyond, past the slope: 0. The
/// single-valued place B (W = 2) sees 2.9 at 0.9, 0.4 into the slope: μ = 0.8.
#[test]
fn expected_ranges_by_hand() {
    let map = SourceFile::new(
        "m.map",
        "map m; place A corridor at (0, 0) { param W = 1.5 .. 2.5; } \
         place B corridor at (5, 0) { param W = 2; } path A -- B;",
    );
    let rules = SourceFile::new(
        "r.lpl",
        "logic { tnorm = min; implication = residuum; normalisation = min; threshold = 0.5; }
         similarity width = trapezoid(core: 1, slope: 2, height: 1, bias: 0);
         percept width(value, expect, time) ~ width;
         |- width(w, W_i, t) -> at_place(P_i);",
    );
    let mut e = match Engine::load(&map, &rules) {
        Ok(e) => e,
        Err(e) => panic!("{e}: {:#?}", e.diagnostics),
    };
    let slot = e.percepts().slot("width", &[]).expect("declared");
    let mut frame = e.new_frame();
    for (reading, want_a, want_b) in [
        (2.0, 1.0, 1.0),
        (2.9, 1.0, 0.8),
        (3.5, 0.75, 0.5),
        (5.5, 0.0, 0.0),
    ] {
        frame.clear();
        frame.set(slot, 1.0, Some(reading));
        e.step(&frame);
        let s = &e.distribution().support;
        assert!((s[0] - want_a).abs() < 1e-12, "A at {reading}: {}", s[0]);
        assert!((s[1] - want_b).abs() < 1e-12, "B at {reading}: {}", s[1]);
    }
    // `explain` prints the range.
    let text = e.explain_place(0).expect("place A");
    assert!(text.contains("1.5..2.5"), "{text}");
}
