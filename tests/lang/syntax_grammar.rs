//! Grammar tests in pest's style: `parses_to!` pins the token tree of small constructs,
//! `fails_with!` the position and expectations of a failure; whole constructs (paper 003 eqs. (5)
//! and (7), every map item) are checked through the AST they parse to.

use lplace::syntax::ast::*;
use lplace::syntax::pest_parsers::{MapGrammar, MapRule, RulesGrammar, RulesRule};
use lplace::syntax::{parse_map, parse_rules};
use pest::{consumes_to, fails_with, parses_to, Parser};

#[test]
fn numbers() {
    for ok in ["0", "1.5", "-2", "+0.25", ".5", "1e3", "2.5E-2", "7."] {
        let p = RulesGrammar::parse(RulesRule::number, ok).expect("number parses");
        assert_eq!(p.as_str(), ok);
    }
    fails_with! {
        parser: RulesGrammar,
        input: "-x",
        rule: RulesRule::number,
        positives: vec![RulesRule::number],
        negatives: vec![],
        pos: 0
    };
}

#[test]
fn place_references() {
    parses_to! {
        parser: RulesGrammar,
        input: "A_i",
        rule: RulesRule::place_ref,
        tokens: [place_ref(0, 3, [place_name(0, 3)])]
    };
    parses_to! {
        parser: RulesGrammar,
        input: "range_i(Yellow)",
        rule: RulesRule::place_ref,
        tokens: [place_ref(0, 15, [place_name(0, 7), place_key(7, 15, [ident(8, 14)])])]
    };
    // `x_ij` is an ordinary identifier, not a place reference.
    fails_with! {
        parser: RulesGrammar,
        input: "x_ij",
        rule: RulesRule::place_ref,
        positives: vec![RulesRule::place_name],
        negatives: vec![],
        pos: 0
    };
}

#[test]
fn atoms_and_tuples() {
    parses_to! {
        parser: RulesGrammar,
        input: "sig(<a, l>, t)",
        rule: RulesRule::atom,
        tokens: [atom(0, 14, [ident(0, 3), arglist(3, 14, [tuple(4, 10, [ident(5, 6), ident(8, 9)]), ident(12, 13)])])]
    };
    parses_to! {
        parser: RulesGrammar,
        input: "walls",
        rule: RulesRule::atom,
        tokens: [atom(0, 5, [ident(0, 5)])]
    };
}

#[test]
fn keywords_are_not_identifiers() {
    fails_with! {
        parser: RulesGrammar,
        input: "for",
        rule: RulesRule::ident,
        positives: vec![RulesRule::ident],
        negatives: vec![],
        pos: 0
    };
    // ... but may begin one.
    parses_to! {
        parser: RulesGrammar,
        input: "in_room",
        rule: RulesRule::ident,
        tokens: [ident(0, 7)]
    };
}

#[test]
fn formula_precedence() {
    parses_to! {
        parser: RulesGrammar,
        input: "!a * b & c",
        rule: RulesRule::disj,
        tokens: [disj(0, 10, [conj(0, 10, [
            times(0, 6, [
                unary(0, 2, [not_op(0, 1), atom(1, 2, [ident(1, 2)])]),
                unary(5, 6, [atom(5, 6, [ident(5, 6)])])
            ]),
            times(9, 10, [unary(9, 10, [atom(9, 10, [ident(9, 10)])])])
        ])])]
    };
}

fn rule_of(text: &str) -> Rule {
    let file = parse_rules(text).unwrap_or_else(|d| panic!("{text}: {d:?}"));
    file.items
        .into_iter()
        .find_map(|i| match i {
            RuleItem::Rule(r) => Some(r),
            _ => None,
        })
        .expect("a rule")
}

#[test]
fn precedence_in_the_ast() {
    // `a (+) b & c * !d` = a (+) (b & (c * (!d)))
    let r = rule_of("|- a (+) b & c * !d -> h;");
    let Formula::Or(parts) = &r.body.node else {
        panic!("{:?}", r.body.node)
    };
    assert_eq!(parts.len(), 2);
    let Formula::And(and) = &parts[1].node else {
        panic!()
    };
    let Formula::Times(times) = &and[1].node else {
        panic!()
    };
    assert!(matches!(times[1].node, Formula::Not(_)));
    // `->` inside parentheses is right-associative.
    let r = rule_of("|- (a -> b -> c) -> h;");
    let Formula::Implies(lhs, rhs) = &r.body.node else {
        panic!()
    };
    assert!(matches!(lhs.node, Formula::Atom(_)));
    assert!(matches!(rhs.node, Formula::Implies(_, _)));
}

#[test]
fn weighted_formulas_and_degrees() {
    let r = rule_of("|- ((a, 0.7) * 0.5 -> h, 0.9);");
    assert_eq!(r.weight.as_ref().map(|w| w.node), Some(0.9));
    let Formula::Times(parts) = &r.body.node else {
        panic!()
    };
    assert!(matches!(&parts[0].node, Formula::Weighted(_, w) if w.node == 0.7));
    assert!(matches!(parts[1].node, Formula::Degree(d) if d == 0.5));
    // Extra parentheses around a sequent are allowed.
    let r = rule_of("|- (((a -> !h, 0.4)));");
    assert!(r.head.negated);
    assert_eq!(r.weight.map(|w| w.node), Some(0.4));
}

#[test]
fn paper_003_equation_5_parses_nearly_verbatim() {
    let text = "|- ((beacon_angle(a, A_i, t) & beacon_distance(l, L_i, t)) \
                -> beacon_signature(<a, l>, <A_i, L_i>, t));";
    assert!(RulesGrammar::parse(RulesRule::rule, text).is_ok());
    let r = rule_of(text);
    assert_eq!(r.head.atom.name.node, "beacon_signature");
    assert!(r.weight.is_none());
    let Formula::And(parts) = &r.body.node else {
        panic!()
    };
    let Formula::Atom(a) = &parts[0].node else {
        panic!()
    };
    assert_eq!(
        a.args[1].node,
        Term::PlaceRef {
            name: "A".into(),
            key: None
        }
    );
    assert_eq!(a.args[2].node, Term::Time);
    let Term::Tuple(expect) = &r.head.atom.args[1].node else {
        panic!()
    };
    assert_eq!(expect.len(), 2);
}

#[test]
fn paper_003_equation_7_parses_nearly_verbatim() {
    let text =
        "|- ((sonar_wall(p1, d1, t) & at_wall(p1, t) & laser_wall(p2, d2, t) & at_wall(p2, t)) (+)
        (sonar_wall(p3, d2, t) & at_wall(p3, t) & laser_wall(p4, d1, t) & at_wall(p4, t)) (+)
        (laser_corner(p5, d1, d2, t) & at_corner(p5, t)))
       -> corner(d1, d2, t)
       for all (d1, d2) in {(North, East), (North, West), (South, East), (South, West)};";
    assert!(RulesGrammar::parse(RulesRule::rule, text).is_ok());
    let r = rule_of(text);
    let Formula::Or(parts) = &r.body.node else {
        panic!()
    };
    assert_eq!(parts.len(), 3);
    assert_eq!(r.schemas.len(), 1);
    assert_eq!(r.schemas[0].vars.len(), 2);
    let SchemaSource::Tuples(ts) = &r.schemas[0].source else {
        panic!()
    };
    assert_eq!(ts.len(), 4);
    assert_eq!(ts[3].node[1].node, "West");
}

#[test]
fn schemas_before_and_after() {
    let r = rule_of("for all d in Dir |- s(p, d, t) -> w(t) for all e in {A, B};");
    assert_eq!(r.schemas.len(), 2);
    assert!(matches!(&r.schemas[0].source, SchemaSource::Domain(d) if d.node == "Dir"));
    assert!(matches!(&r.schemas[1].source, SchemaSource::Tuples(t) if t.len() == 2));
}

#[test]
fn declarations() {
    let f = parse_rules(
        "logic { tnorm = product; threshold = 0.6; }
         domain Dir = {North, East};
         similarity s = trapezoid(core: 10, slope: 30, height: 1, bias: 0.05);
         percept p(value, Dir, expect, time) ~ s;
         predicate q(Dir, time);
         predicate nullary;",
    )
    .expect("declarations parse");
    assert_eq!(f.items.len(), 6);
    let RuleItem::Percept(p) = &f.items[3] else {
        panic!()
    };
    assert_eq!(p.roles[1].node, ArgRole::Domain("Dir".into()));
    assert_eq!(p.similarity.as_ref().map(|s| s.node.as_str()), Some("s"));
    let RuleItem::Logic(l) = &f.items[0] else {
        panic!()
    };
    assert_eq!(l.settings[1].value.node, SettingValue::Number(0.6));
}

#[test]
fn comments_anywhere() {
    let f = parse_rules("// line\n/* block\n * more */ predicate /* inner */ q(time); // end")
        .expect("parses");
    assert_eq!(f.items.len(), 1);
}

#[test]
fn a_bare_top_level_arrow_chain_is_rejected() {
    fails_with! {
        parser: RulesGrammar,
        input: "|- a -> b -> c;",
        rule: RulesRule::file,
        positives: vec![RulesRule::kw_for, RulesRule::arglist],
        negatives: vec![],
        pos: 10
    };
}

// ----- maps ----------------------------------------------------------------------------------

#[test]
fn map_items() {
    parses_to! {
        parser: MapGrammar,
        input: "path A -- B length 2;",
        rule: MapRule::path_decl,
        tokens: [path_decl(0, 21, [kw_path(0, 4), ident(5, 6), edge(7, 9), ident(10, 11), kw_length(12, 18), number(19, 20)])]
    };
    let m = parse_map(
        "map m;
         room R0 \"west room\";
         beacon B0 at (5.0, 2.5) id 1;
         landmark Yellow at (-3, 0) id 3;
         place P0 corner in R0 at (0.5, 0.5, 90) extent radius 0.6 {
             wall South; wall West 0.9; corner South West 0.8;
             param A = 215; param range(Yellow) = 2.5;
         }
         place P1 doorway at (1, 1) extent box (0, 0, 2, 2);
         place P2 corridor at (3, 1) {}
         path P0 -- P1 length 4.0 heading 0;
         path P1 -- P2;",
    )
    .expect("map parses");
    assert_eq!(m.name.map(|n| n.node).as_deref(), Some("m"));
    assert_eq!(m.items.len(), 8);
    let MapItem::Place(p) = &m.items[3] else {
        panic!()
    };
    assert_eq!(p.pose.node, (0.5, 0.5, Some(90.0)));
    assert_eq!(p.room.as_ref().map(|r| r.node.as_str()), Some("R0"));
    assert_eq!(p.features.len(), 5);
    assert!(
        matches!(&p.features[4], Feature::Param { key: Some(k), value, .. } if k.node == "Yellow" && value.node == 2.5)
    );
    let MapItem::Place(p) = &m.items[4] else {
        panic!()
    };
    assert_eq!(
        p.extent.as_ref().map(|e| e.node.clone()),
        Some(Extent::Box(0.0, 0.0, 2.0, 2.0))
    );
    let MapItem::Path(path) = &m.items[7] else {
        panic!()
    };
    assert!(path.length.is_none() && path.heading.is_none());
}

#[test]
fn map_param_ranges() {
    parses_to! {
        parser: MapGrammar,
        input: "param W = 1 .. 2.5;",
        rule: MapRule::param,
        tokens: [param(0, 19, [kw_param(0, 5), ident(6, 7), number(10, 11), number(15, 18)])]
    };
    // `start (x, y);`: a point, like a landmark's.
    parses_to! {
        parser: MapGrammar,
        input: "start (1.5, -2);",
        rule: MapRule::start_decl,
        tokens: [start_decl(0, 16, [kw_start(0, 5), point(6, 15, [number(7, 10), number(12, 14)])])]
    };
    fails_with! {
        parser: MapGrammar,
        input: "start 1.5, -2;",
        rule: MapRule::start_decl,
        positives: vec![MapRule::point],
        negatives: vec![],
        pos: 6
    };
    // `1..2` is a range, not the number `1.` followed by `.2`.
    parses_to! {
        parser: MapGrammar,
        input: "param V(North) = 1..2;",
        rule: MapRule::param,
        tokens: [param(0, 22, [kw_param(0, 5), ident(6, 7), ident(8, 13), number(17, 18), number(20, 21)])]
    };
    fails_with! {
        parser: MapGrammar,
        input: "param W = 1 .. ;",
        rule: MapRule::param,
        positives: vec![MapRule::number],
        negatives: vec![],
        pos: 15
    };
    let m = parse_map("place P corridor at (0, 0) { param W = -1.5 .. 2; param A = 3; }")
        .expect("map parses");
    let MapItem::Place(p) = &m.items[0] else {
        panic!()
    };
    assert!(matches!(
        &p.features[0],
        Feature::Param { value, upper: Some(u), .. } if value.node == -1.5 && u.node == 2.0
    ));
    assert!(matches!(&p.features[1], Feature::Param { upper: None, .. }));
}

#[test]
fn map_place_needs_a_pose() {
    fails_with! {
        parser: MapGrammar,
        input: "place P0 corner (0, 0);",
        rule: MapRule::place_decl,
        positives: vec![MapRule::kw_at, MapRule::kw_in],
        negatives: vec![],
        pos: 16
    };
}
