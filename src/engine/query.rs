//! Queries over sets of places: what `eval --query`, `explain --query` and
//! [`super::Engine::query_set`] take.
//!
//! A query is one formula of the rule language whose atoms name sets of places — a place, room
//! or region name, a map kind (`doorway`), or `at_place(P)`, `in_room(R)`, `in_region(G)` — and
//! whose connectives are read on sets, since places are the worlds: `!` is the complement, `&`
//! the intersection and `(+)` the union. `EastWing (+) doorway`, `in_room(R0) & !P3`. Its Π and
//! N are then those of the set (see `logic::sets`). Depends on `syntax` (the parser and the
//! checked rule set), `map` and `logic`.

use crate::logic::PlaceSet;
use crate::map::Map;
use crate::rules::RuleSet;
use crate::syntax::ast::{Formula, Term};
use crate::syntax::parse_rules::parse_query;
use crate::syntax::span::{Span, Spanned};
use crate::syntax::Diagnostic;

/// Why a query names no set of places.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QueryError {
    /// The text is not a formula of the rule language.
    #[error("query does not parse: {}", .diagnostics.first().map_or(String::new(), |d| d.kind.to_string()))]
    Syntax {
        /// The parser's diagnostics (spans into the query text).
        diagnostics: Vec<Diagnostic>,
    },
    /// A name that is no place, room, region or kind.
    #[error("`{name}` is no place, room, region or kind of this map and rule file")]
    UnknownName {
        /// The name.
        name: String,
        /// Where it is in the query.
        span: Span,
    },
    /// A connective or atom that has no meaning on sets of places.
    #[error("{what} cannot be used in a query over places (use names, `!`, `&` and `(+)`)")]
    Unsupported {
        /// What was found.
        what: &'static str,
        /// Where.
        span: Span,
    },
}

/// The places of room `r`.
pub fn room_set(map: &Map, r: usize) -> PlaceSet {
    let places = map.places().iter().enumerate();
    let inside = places.filter(|(_, p)| p.room == Some(r)).map(|(k, _)| k);
    PlaceSet::from_indices(map.places().len(), inside)
}

/// The set a bare name denotes: a place, a room, a region, or every place of a kind.
pub fn named_set(name: &str, map: &Map, rules: &RuleSet) -> Option<PlaceSet> {
    let n = map.places().len();
    if let Some(k) = map.places().iter().position(|p| p.name == name) {
        return Some(PlaceSet::from_indices(n, [k]));
    }
    if let Some(r) = map.rooms().iter().position(|r| r.name == name) {
        return Some(room_set(map, r));
    }
    if let Some((_, ks)) = rules.regions.iter().find(|(g, _)| g == name) {
        return Some(PlaceSet::from_indices(n, ks.iter().copied()));
    }
    let kind = map
        .places()
        .iter()
        .enumerate()
        .filter(|(_, p)| p.kind == name);
    let ks: Vec<usize> = kind.map(|(k, _)| k).collect();
    (!ks.is_empty()).then(|| PlaceSet::from_indices(n, ks))
}

/// Every bare name a query (or a stream record's `region` field) can use: places, rooms,
/// regions, then kinds, each once.
pub fn set_names(map: &Map, rules: &RuleSet) -> Vec<String> {
    let mut names: Vec<String> = map.places().iter().map(|p| p.name.clone()).collect();
    names.extend(map.rooms().iter().map(|r| r.name.clone()));
    names.extend(rules.regions.iter().map(|(g, _)| g.clone()));
    // Kinds are few and places many: look names up in a set, not the list (n² at 10,000 places).
    let mut seen: std::collections::HashSet<String> = names.iter().cloned().collect();
    for p in map.places() {
        if seen.insert(p.kind.clone()) {
            names.push(p.kind.clone());
        }
    }
    names
}

/// Parses and resolves a query.
pub fn resolve(text: &str, map: &Map, rules: &RuleSet) -> Result<PlaceSet, QueryError> {
    let f = parse_query(text).map_err(|diagnostics| QueryError::Syntax { diagnostics })?;
    set_of(&f, map, rules)
}

fn set_of(f: &Spanned<Formula>, map: &Map, rules: &RuleSet) -> Result<PlaceSet, QueryError> {
    let unsupported = |what| QueryError::Unsupported { what, span: f.span };
    match &f.node {
        Formula::Not(a) => Ok(set_of(a, map, rules)?.complement()),
        Formula::And(v) | Formula::Or(v) => {
            let is_and = matches!(f.node, Formula::And(_));
            let n = map.places().len();
            let mut acc = if is_and {
                PlaceSet::all(n)
            } else {
                PlaceSet::empty(n)
            };
            for x in v {
                let s = set_of(x, map, rules)?;
                acc = if is_and {
                    acc.intersection(&s)
                } else {
                    acc.union(&s)
                };
            }
            Ok(acc)
        }
        Formula::Times(_) => Err(unsupported("`*` (a t-norm of degrees)")),
        Formula::Implies(..) => Err(unsupported("`->`")),
        Formula::Weighted(..) => Err(unsupported("a weighted formula")),
        Formula::Degree(_) => Err(unsupported("a number")),
        Formula::Atom(a) => {
            let name = a.name.node.as_str();
            let arg = match (name, a.args.as_slice()) {
                (_, []) => name,
                ("at_place" | "in_room" | "in_region", [t]) => match &t.node {
                    Term::Const(c) => c.as_str(),
                    _ => return Err(unsupported("an argument other than a name")),
                },
                _ => {
                    return Err(unsupported(
                        "an atom other than at_place, in_room, in_region",
                    ))
                }
            };
            named_set(arg, map, rules).ok_or_else(|| QueryError::UnknownName {
                name: arg.to_string(),
                span: a.span,
            })
        }
    }
}
