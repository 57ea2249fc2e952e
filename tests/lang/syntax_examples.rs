//! The bundled example environments parse and check with zero diagnostics.

use lplace::map::Map;
use lplace::rules::check_rules;
use lplace::syntax::diagnostic::SourceFile;
use lplace::syntax::{parse_map, parse_rules};

fn load(map_path: &str, rules_path: &str) -> (Map, lplace::rules::RuleSet) {
    let root = env!("CARGO_MANIFEST_DIR");
    let map_text =
        std::fs::read_to_string(format!("{root}/{map_path}")).expect("example map is readable");
    let rules_text = std::fs::read_to_string(format!("{root}/{rules_path}"))
        .expect("example rules are readable");
    let map_file = SourceFile::new(map_path, map_text.clone());
    let rules_file = SourceFile::new(rules_path, rules_text.clone());
    let render = |f: &SourceFile, d: Vec<lplace::syntax::Diagnostic>| -> String {
        d.iter()
            .map(|d| d.render_plain(f))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let ast = parse_map(&map_text).unwrap_or_else(|d| panic!("{}", render(&map_file, d)));
    let map = Map::from_ast(&ast).unwrap_or_else(|d| panic!("{}", render(&map_file, d)));
    let rules = parse_rules(&rules_text).unwrap_or_else(|d| panic!("{}", render(&rules_file, d)));
    let set = check_rules(&rules, &map).unwrap_or_else(|d| panic!("{}", render(&rules_file, d)));
    (map, set)
}

#[test]
fn office_example_is_clean() {
    let (map, set) = load("maps/office.map", "rules/office.lpl");
    assert_eq!(map.places().len(), 8);
    assert_eq!(map.rooms().len(), 2);
    assert_eq!(map.landmarks().len(), 1);
    assert_eq!(set.rules.len(), 8);
    assert_eq!(set.logic.tnorm, lplace::logic::TNorm::Product);
    assert_eq!(set.domains["Dir"], ["North", "East", "South", "West"]);
    assert_eq!(set.domains["Place"].len(), 8);
}

#[test]
fn field_example_is_clean() {
    let (map, set) = load("maps/field.map", "rules/field.lpl");
    assert!(map.places().len() >= 8);
    assert_eq!(map.landmarks().len(), 6);
    assert_eq!(set.logic.tnorm, lplace::logic::TNorm::Product);
    assert_eq!(set.logic.implication, lplace::logic::Implication::MinMp);
}
