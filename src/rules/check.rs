//! The checker: resolves a parsed rule file against a map and produces a [`RuleSet`] the compiler
//! can trust — every atom names a known percept, predicate or built-in with the right arity,
//! every argument fits its role, every variable that must be bound is, every constant and
//! place parameter exists, every degree is in `[0, 1]`, the `logic` block and similarities are
//! well formed, and every rule can fire. All problems are reported at once.
//!
//! Depends on `syntax` (the AST in, diagnostics out), `map` (names, walls, parameters) and
//! `logic` (the `LogicConfig` and `Similarity` it produces).
//!
//! # Decisions
//!
//! - Built-in domains `Place`, `Room` and `Landmark` hold the map's names; a rule file may not
//!   redeclare them. Built-in predicates `at_place`, `in_room`, `at_wall`, `at_corner` may not be
//!   redeclared either.
//! - A place parameter (`A_i`, `range_i(g)`) that **no** place of the map defines is an error (it
//!   is almost certainly a typo); one that only some places define is fine — the comparison just
//!   has no expectation at the others. `P_i` and `R_i` are always defined; `range_i(L)` and
//!   `bearing_i(L)` with `L` a landmark are defined through geometry.
//! - A rule whose body is 0 whatever the sensors say — because it needs a derived predicate (or
//!   `at_place`/`in_room`) that no firing rule concludes — is an error: it is dead code that
//!   usually hides a misspelt head.

use super::tracker::{check_tracker, TrackerSettings};
use crate::logic::{Fusion, Implication, LogicConfig, Normalisation, Similarity, TNorm};
use crate::map::Map;
use crate::syntax::ast::*;
use crate::syntax::diagnostic::{Diagnostic, DiagnosticKind, KeySuffix, NeverFiresReason};
use crate::syntax::span::{Span, Spanned};
use crate::syntax::suggest::suggest;
use std::collections::{BTreeMap, BTreeSet};

/// Names that rule files may not declare as domains.
pub const BUILTIN_DOMAINS: [&str; 4] = ["Place", "Room", "Landmark", "Region"];
/// Names that rule files may not declare as percepts or predicates.
pub const BUILTIN_PREDICATES: [&str; 7] = [
    "at_place",
    "in_room",
    "in_region",
    "at_wall",
    "at_corner",
    "at_open",
    "at_door",
];

/// The built-in heads that speak about sets of places (and so constrain the distribution).
pub fn is_place_head(name: &str) -> bool {
    matches!(name, "at_place" | "in_room" | "in_region")
}

/// The declared shape of a percept or derived predicate.
#[derive(Debug, Clone, PartialEq)]
pub struct Signature {
    /// Its name.
    pub name: String,
    /// The role of each argument position.
    pub roles: Vec<ArgRole>,
    /// For percepts with an `expect` role: the similarity comparing value and expectation.
    pub similarity: Option<String>,
    /// The declaration.
    pub span: Span,
}

/// A checked rule file, resolved against a map.
#[derive(Debug, Clone, PartialEq)]
pub struct RuleSet {
    /// Operators and decision parameters (defaults for whatever `logic { … }` leaves out).
    pub logic: LogicConfig,
    /// Every domain with its values in declaration order, including the built-in `Place`,
    /// `Room` and `Landmark` filled from the map.
    pub domains: BTreeMap<String, Vec<String>>,
    /// Similarities by name.
    pub similarities: BTreeMap<String, Similarity>,
    /// Percepts by name.
    pub percepts: BTreeMap<String, Signature>,
    /// Derived predicates by name.
    pub predicates: BTreeMap<String, Signature>,
    /// The rules in source order (those of `group` blocks in place).
    pub rules: Vec<Rule>,
    /// Declared regions in declaration order, with the indices of their places.
    pub regions: Vec<(String, Vec<usize>)>,
    /// Declared evidence groups in declaration order (a rule's group is its position + 1;
    /// group 0 holds the rules written outside any group).
    pub groups: Vec<String>,
    /// The place parameters `(name, key)` the rules read that some place of the map defines
    /// (one that no place defines is an error): [`check_map_against_rules`] names the places
    /// that lack one.
    pub params: BTreeSet<(String, Option<String>)>,
    /// The file's `tracker { … }` block, checked, if it has one: the tracker settings used
    /// when no tracker file is given.
    pub tracker: Option<TrackerSettings>,
}

impl RuleSet {
    /// The evidence group of rule `r`: 0 outside every group, else the group's position + 1.
    pub fn group_of(&self, r: &Rule) -> usize {
        r.group
            .as_ref()
            .and_then(|g| self.groups.iter().position(|x| x == &g.node))
            .map_or(0, |i| i + 1)
    }
}

/// How many ground rule instances (schema bindings × hypothesis places, summed over the file's
/// rules) a rule file may ask the compiler for. The bundled office rules need 17 per place
/// (170,000 on a 10,000-place map); an instance costs the compiler about 350 bytes and 5 µs
/// (measured: 125,000 bindings × 8 places, 345 MB, 5.3 s), so the limit keeps compiling within
/// about 350 MB.
pub const MAX_GROUND_INSTANCES: u128 = 1_000_000;

/// Checks `file` against `map`; returns the rule set or every problem found, sorted by position.
/// Every returned diagnostic points into the rule file. Call [`check_map_against_rules`]
/// afterwards for the problems of the map that only the rule file reveals.
pub fn check_rules(file: &RuleFile, map: &Map) -> Result<RuleSet, Vec<Diagnostic>> {
    let mut c = Checker::declared(file, map);
    for item in &file.items {
        match item {
            RuleItem::Rule(r) => c.rule(r),
            RuleItem::Group(g) => g.rules.iter().for_each(|r| c.rule(r)),
            _ => {}
        }
    }
    c.never_fires();
    // The map's directions are checked separately (`check_map_against_rules`): those
    // diagnostics point into the map file, not this one.
    c.finish()
}

/// The declarations of `file` over `map` — domains, regions, similarities, percepts and
/// predicates, with no rule: the [`RuleSet`] a stream's percept table is enumerated from. A map
/// whose places do not yet carry the parameters the rules compare with (before a survey) passes
/// here, where [`check_rules`] reports each such parameter.
pub fn check_declarations(file: &RuleFile, map: &Map) -> Result<RuleSet, Vec<Diagnostic>> {
    Checker::declared(file, map).finish()
}

impl<'m> Checker<'m> {
    /// A checker over `map` that has read the declarations of `file`.
    fn declared(file: &RuleFile, map: &'m Map) -> Checker<'m> {
        let mut c = Checker {
            map,
            diags: Vec::new(),
            set: RuleSet {
                logic: LogicConfig::default(),
                domains: BTreeMap::new(),
                similarities: BTreeMap::new(),
                percepts: BTreeMap::new(),
                predicates: BTreeMap::new(),
                rules: Vec::new(),
                regions: Vec::new(),
                groups: Vec::new(),
                params: BTreeSet::new(),
                tracker: None,
            },
            domain_spans: BTreeMap::new(),
            grounded: 0,
        };
        c.builtin_domains();
        c.regions(file);
        c.declarations(file);
        c
    }

    /// The rule set, or every problem found sorted by position when one is an error.
    fn finish(self) -> Result<RuleSet, Vec<Diagnostic>> {
        let Checker { mut diags, set, .. } = self;
        if diags.iter().any(Diagnostic::is_error) {
            diags.sort_by_key(|d| (d.span.start, d.span.end));
            Err(diags)
        } else {
            Ok(set)
        }
    }
}

/// Checks the map's `wall` and `corner` directions against the rule set's `Dir` domain (when it
/// declares one), and warns at each place that lacks parameters the rules read elsewhere and at
/// each `open` side the places beyond reach along less than half of. The diagnostics point into
/// the **map** file.
pub fn check_map_against_rules(map: &Map, rules: &RuleSet) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    if let Some(dirs) = rules.domains.get("Dir") {
        for p in map.places() {
            for (d, span) in &p.direction_spans {
                if !dirs.contains(d) {
                    out.push(Diagnostic::error(
                        DiagnosticKind::UnknownDirection { name: d.clone() },
                        *span,
                    ));
                }
            }
        }
    }
    out.extend(places_lacking_params(map, rules));
    out.extend(open_sides_partly_reached(map));
    out
}

/// A warning at each place with an `open` side that the places beyond reach along less than
/// half of ([`crate::map::expect::side_reached`]): the description promises a long view that
/// way from anywhere in the place, and from most of it the robot reads a wall.
fn open_sides_partly_reached(map: &Map) -> Vec<Diagnostic> {
    let places = map.places();
    let mut out = Vec::new();
    for (i, p) in places.iter().enumerate() {
        for dir in p.opens.keys() {
            let Some(share) = crate::map::expect::side_reached(places, i, dir) else {
                continue;
            };
            if share < 0.5 {
                out.push(Diagnostic::warning(
                    DiagnosticKind::OpenSidePartlyReached {
                        dir: dir.clone(),
                        percent: (100.0 * share).round() as u32,
                    },
                    p.span,
                ));
            }
        }
    }
    out
}

/// A warning at each place that lacks some of the parameters the rules read at other places:
/// the rules that read one give that place no evidence from it, which a survey or a typo may
/// have left unnoticed. One warning per place, naming what it lacks.
fn places_lacking_params(map: &Map, rules: &RuleSet) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for (i, p) in map.places().iter().enumerate() {
        let missing: Vec<String> = rules
            .params
            .iter()
            .filter(|(name, key)| map.expected(i, name, key.as_deref()).is_none())
            .map(|(name, key)| match key {
                Some(k) => format!("{name}({k})"),
                None => name.clone(),
            })
            .collect();
        if !missing.is_empty() {
            out.push(Diagnostic::warning(
                DiagnosticKind::PlaceLacksParameters {
                    place: p.name.clone(),
                    params: missing.join(", "),
                },
                p.span,
            ));
        }
    }
    out
}

struct Checker<'m> {
    map: &'m Map,
    diags: Vec<Diagnostic>,
    set: RuleSet,
    domain_spans: BTreeMap<String, Span>,
    /// Ground instances (schema bindings × hypothesis places) of the rules checked so far.
    grounded: u128,
}

/// What a rule binds: schema variables (with their candidate values) and percept value
/// variables (with the percept that binds them).
#[derive(Default)]
struct Bindings {
    schema: BTreeMap<String, Vec<String>>,
    values: BTreeMap<String, String>,
}

fn in_unit(x: f64) -> bool {
    (0.0..=1.0).contains(&x)
}

impl Checker<'_> {
    fn err(&mut self, kind: DiagnosticKind, span: Span) {
        self.diags.push(Diagnostic::error(kind, span));
    }

    /// An error about the unknown name `written`, with "did you mean" or the `known` names.
    fn err_unknown<'k>(
        &mut self,
        kind: DiagnosticKind,
        span: Span,
        written: &str,
        known: impl IntoIterator<Item = &'k str>,
    ) {
        let d = Diagnostic::error(kind, span).with_suggestion(suggest(written, known));
        self.diags.push(d);
    }

    fn dup(&mut self, what: &'static str, name: &Spanned<String>, first: Span) {
        self.diags.push(
            Diagnostic::error(
                DiagnosticKind::DuplicateName {
                    what,
                    name: name.node.clone(),
                },
                name.span,
            )
            .with_related(first, "first defined here"),
        );
    }

    fn builtin_domains(&mut self) {
        let m = self.map;
        let d = &mut self.set.domains;
        d.insert(
            "Place".into(),
            m.places().iter().map(|p| p.name.clone()).collect(),
        );
        d.insert(
            "Room".into(),
            m.rooms().iter().map(|r| r.name.clone()).collect(),
        );
        d.insert(
            "Landmark".into(),
            m.landmarks().iter().map(|l| l.name.clone()).collect(),
        );
    }

    /// Region declarations (`region Name = {…};`, `region Name = kind k;`) and group names; fills
    /// the built-in `Region` domain.
    fn regions(&mut self, file: &RuleFile) {
        let mut spans: BTreeMap<String, Span> = BTreeMap::new();
        let mut group_spans: BTreeMap<String, Span> = BTreeMap::new();
        for item in &file.items {
            match item {
                RuleItem::Region(r) => self.region(r, &mut spans),
                RuleItem::Group(g) => {
                    if let Some(first) = group_spans.get(&g.name.node) {
                        let first = *first;
                        self.dup("group", &g.name, first);
                    } else {
                        group_spans.insert(g.name.node.clone(), g.name.span);
                        self.set.groups.push(g.name.node.clone());
                    }
                }
                _ => {}
            }
        }
        let names = self.set.regions.iter().map(|(n, _)| n.clone()).collect();
        self.set.domains.insert("Region".into(), names);
    }

    fn region(&mut self, r: &RegionDecl, spans: &mut BTreeMap<String, Span>) {
        let name = &r.name.node;
        if let Some(first) = spans.get(name) {
            let first = *first;
            self.dup("region", &r.name, first);
            return;
        }
        let m = self.map;
        let taken = if m.places().iter().any(|p| &p.name == name) {
            Some("place")
        } else if m.rooms().iter().any(|x| &x.name == name) {
            Some("room")
        } else {
            None
        };
        if let Some(what) = taken {
            let kind = DiagnosticKind::RegionNameTaken {
                name: name.clone(),
                what,
            };
            self.err(kind, r.name.span);
            return;
        }
        spans.insert(name.clone(), r.name.span);
        let mut members = Vec::new();
        match &r.members {
            RegionMembers::Places(ps) => {
                for p in ps {
                    match m.places().iter().position(|x| x.name == p.node) {
                        Some(k) if !members.contains(&k) => members.push(k),
                        Some(_) => {}
                        None => self.err(
                            DiagnosticKind::UnknownPlace {
                                name: p.node.clone(),
                            },
                            p.span,
                        ),
                    }
                }
            }
            RegionMembers::Kind(k) => {
                members.extend(
                    m.places()
                        .iter()
                        .enumerate()
                        .filter(|(_, p)| p.kind == k.node)
                        .map(|(i, _)| i),
                );
                // A rule file is written for a kind of sensor, not for a building, so it may
                // name kinds a building lacks: a map that declares its kinds (`kinds {…};`) has
                // said which it has, and the region is then empty. Without that declaration an
                // empty region is most likely a misspelt kind.
                if members.is_empty() && m.kinds().is_none() {
                    self.err(
                        DiagnosticKind::UnknownKind {
                            name: k.node.clone(),
                        },
                        k.span,
                    );
                }
            }
        }
        members.sort_unstable();
        self.set.regions.push((name.clone(), members));
    }

    fn declarations(&mut self, file: &RuleFile) {
        // Domains and similarities first, so that percepts can refer to later ones.
        let sim_spans = self.logic_domains_similarities(file);
        let mut pred_spans: BTreeMap<String, Span> = BTreeMap::new();
        for item in &file.items {
            let (name, roles, similarity, span, is_percept) = match item {
                RuleItem::Percept(p) => (&p.name, &p.roles, p.similarity.as_ref(), p.span, true),
                RuleItem::Predicate(p) => (&p.name, &p.roles, None, p.span, false),
                _ => continue,
            };
            if BUILTIN_PREDICATES.contains(&name.node.as_str()) {
                self.err(
                    DiagnosticKind::ReservedName {
                        name: name.node.clone(),
                    },
                    name.span,
                );
                continue;
            }
            if let Some(first) = pred_spans.get(&name.node) {
                let first = *first;
                self.dup(
                    if is_percept { "percept" } else { "predicate" },
                    name,
                    first,
                );
                continue;
            }
            pred_spans.insert(name.node.clone(), name.span);
            self.signature_roles(name, roles, similarity, is_percept, &sim_spans);
            let sig = Signature {
                name: name.node.clone(),
                roles: roles.iter().map(|r| r.node.clone()).collect(),
                similarity: similarity.map(|s| s.node.clone()),
                span,
            };
            if is_percept {
                self.set.percepts.insert(name.node.clone(), sig);
            } else {
                self.set.predicates.insert(name.node.clone(), sig);
            }
        }
    }

    /// The `logic` block, domains and similarities of `file`; returns where each similarity was
    /// first declared (a percept may name one whose trapezoid was rejected, and must not be told
    /// it is unknown as well).
    fn logic_domains_similarities(&mut self, file: &RuleFile) -> BTreeMap<String, Span> {
        let mut logic_seen: Option<Span> = None;
        let mut tracker_seen: Option<Span> = None;
        let mut sim_spans: BTreeMap<String, Span> = BTreeMap::new();
        for item in &file.items {
            match item {
                RuleItem::Logic(l) => {
                    if let Some(first) = logic_seen {
                        self.diags.push(
                            Diagnostic::error(
                                DiagnosticKind::DuplicateName {
                                    what: "logic block",
                                    name: "logic".into(),
                                },
                                l.span,
                            )
                            .with_related(first, "first defined here"),
                        );
                    } else {
                        logic_seen = Some(l.span);
                        self.logic(l);
                    }
                }
                RuleItem::Tracker(t) => match tracker_seen {
                    Some(first) => self.diags.push(
                        Diagnostic::error(
                            DiagnosticKind::DuplicateName {
                                what: "tracker block",
                                name: "tracker".into(),
                            },
                            t.span,
                        )
                        .with_related(first, "first defined here"),
                    ),
                    None => {
                        tracker_seen = Some(t.span);
                        self.set.tracker = Some(check_tracker(t, &mut self.diags));
                    }
                },
                RuleItem::Domain(d) => self.domain(d),
                RuleItem::Similarity(s) => {
                    if let Some(first) = sim_spans.get(&s.name.node) {
                        let first = *first;
                        self.dup("similarity", &s.name, first);
                    } else {
                        sim_spans.insert(s.name.node.clone(), s.name.span);
                        if let Some(t) = self.similarity(s) {
                            self.set.similarities.insert(s.name.node.clone(), t);
                        }
                    }
                }
                _ => {}
            }
        }
        sim_spans
    }

    /// The domains and the similarity a percept or predicate declaration names must exist, and an
    /// `expect` role needs a similarity to compare with.
    fn signature_roles(
        &mut self,
        name: &Spanned<String>,
        roles: &[Spanned<ArgRole>],
        similarity: Option<&Spanned<String>>,
        is_percept: bool,
        sim_spans: &BTreeMap<String, Span>,
    ) {
        for r in roles {
            if let ArgRole::Domain(d) = &r.node {
                if !self.set.domains.contains_key(d) {
                    self.err(DiagnosticKind::UnknownDomain { name: d.clone() }, r.span);
                }
            }
        }
        if let Some(s) = similarity {
            if !self.set.similarities.contains_key(&s.node) && !sim_spans.contains_key(&s.node) {
                let known = self.set.similarities.keys().chain(sim_spans.keys());
                let known: Vec<&str> = known.map(String::as_str).collect();
                self.diags.push(
                    Diagnostic::error(
                        DiagnosticKind::UnknownSimilarity {
                            name: s.node.clone(),
                        },
                        s.span,
                    )
                    .with_suggestion(suggest(&s.node, known)),
                );
            }
        } else if is_percept && roles.iter().any(|r| r.node == ArgRole::Expect) {
            self.err(
                DiagnosticKind::ExpectWithoutSimilarity {
                    percept: name.node.clone(),
                },
                name.span,
            );
        }
    }

    fn logic(&mut self, l: &LogicBlock) {
        let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
        for s in &l.settings {
            let key = s.key.node.as_str();
            if let Some(first) = seen.get(key) {
                let first = *first;
                self.dup("setting", &s.key, first);
                continue;
            }
            seen.insert(key, s.key.span);
            let bad = |expected: &'static str| DiagnosticKind::BadSettingValue {
                key: key.to_string(),
                expected,
            };
            let word = match &s.value.node {
                SettingValue::Word(w) => Some(w.as_str()),
                SettingValue::Number(_) => None,
            };
            let number = match &s.value.node {
                SettingValue::Number(x) => Some(*x),
                SettingValue::Word(_) => None,
            };
            match key {
                "tnorm" => match word {
                    Some("min") => self.set.logic.tnorm = TNorm::Min,
                    Some("product") => self.set.logic.tnorm = TNorm::Product,
                    Some("lukasiewicz") => self.set.logic.tnorm = TNorm::Lukasiewicz,
                    _ => self.err(bad("min, product or lukasiewicz"), s.value.span),
                },
                "implication" => match word {
                    Some("residuum") => self.set.logic.implication = Implication::Residuum,
                    Some("min_mp") => self.set.logic.implication = Implication::MinMp,
                    _ => self.err(bad("residuum or min_mp"), s.value.span),
                },
                "normalisation" | "normalization" => match word {
                    Some("min") => self.set.logic.normalisation = Normalisation::Min,
                    Some("product") => self.set.logic.normalisation = Normalisation::Product,
                    _ => self.err(bad("min or product"), s.value.span),
                },
                "fusion" => match word {
                    Some("min") => self.set.logic.fusion = Fusion::Min,
                    Some("product") => self.set.logic.fusion = Fusion::Product,
                    _ => self.err(bad("min or product"), s.value.span),
                },
                "threshold" | "margin" => match number {
                    Some(x) if in_unit(x) => {
                        if key == "threshold" {
                            self.set.logic.threshold = x;
                        } else {
                            self.set.logic.margin = x;
                        }
                    }
                    _ => self.err(bad("a number in [0, 1]"), s.value.span),
                },
                _ => self.err(
                    DiagnosticKind::UnknownSetting {
                        key: key.to_string(),
                    },
                    s.key.span,
                ),
            }
        }
    }

    fn domain(&mut self, d: &DomainDecl) {
        let name = &d.name.node;
        if BUILTIN_DOMAINS.contains(&name.as_str()) {
            self.err(
                DiagnosticKind::ReservedName { name: name.clone() },
                d.name.span,
            );
            return;
        }
        if let Some(first) = self.domain_spans.get(name) {
            let first = *first;
            self.dup("domain", &d.name, first);
            return;
        }
        self.domain_spans.insert(name.clone(), d.name.span);
        let mut values: Vec<String> = Vec::new();
        let mut spans: BTreeMap<&str, Span> = BTreeMap::new();
        for v in &d.values {
            if let Some(first) = spans.get(v.node.as_str()) {
                let first = *first;
                self.dup("domain value", v, first);
                continue;
            }
            spans.insert(&v.node, v.span);
            values.push(v.node.clone());
        }
        self.set.domains.insert(name.clone(), values);
    }

    fn similarity(&mut self, s: &SimilarityDecl) -> Option<Similarity> {
        if s.shape.node != "trapezoid" {
            self.err(
                DiagnosticKind::UnknownShape {
                    name: s.shape.node.clone(),
                },
                s.shape.span,
            );
            return None;
        }
        let mut t = Similarity::default();
        let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
        let mut ok = true;
        let mut height_span = None;
        for (k, v) in &s.fields {
            if let Some(first) = seen.get(k.node.as_str()) {
                let first = *first;
                self.dup("field", k, first);
                ok = false;
                continue;
            }
            seen.insert(&k.node, k.span);
            let x = v.node;
            let bad = |requirement: &'static str| DiagnosticKind::BadFieldValue {
                field: k.node.clone(),
                value: x,
                requirement,
            };
            match k.node.as_str() {
                "core" | "slope" if x < 0.0 => {
                    self.err(bad("must be non-negative"), v.span);
                    ok = false;
                }
                "period" if x <= 0.0 => {
                    self.err(bad("must be positive"), v.span);
                    ok = false;
                }
                "height" | "bias" if !in_unit(x) => {
                    self.err(bad("must be in [0, 1]"), v.span);
                    ok = false;
                }
                "core" => t.shape.core = x,
                "slope" => t.shape.slope = x,
                "period" => t.period = Some(x),
                "height" => {
                    t.shape.height = x;
                    height_span = Some(v.span);
                }
                "bias" => t.shape.bias = x,
                _ => {
                    self.err(
                        DiagnosticKind::UnknownField {
                            field: k.node.clone(),
                        },
                        k.span,
                    );
                    ok = false;
                }
            }
        }
        if ok && t.shape.bias > t.shape.height {
            let span = s
                .fields
                .iter()
                .find(|(k, _)| k.node == "bias")
                .map(|(_, v)| v.span)
                .or(height_span)
                .unwrap_or(s.span);
            self.err(
                DiagnosticKind::BadFieldValue {
                    field: "bias".into(),
                    value: t.shape.bias,
                    requirement: "must not exceed the height",
                },
                span,
            );
            ok = false;
        }
        ok.then_some(t)
    }

    // ----- rules ---------------------------------------------------------------------------

    fn rule(&mut self, r: &Rule) {
        let mut b = Bindings::default();
        // Domains of schema variables, inferred from the domain positions they occupy.
        let mut uses: BTreeMap<String, String> = BTreeMap::new();
        collect_var_domains(&r.body.node, &self.set, &mut uses);
        collect_atom_var_domains(&r.head.atom, &self.set, &mut uses);
        for s in &r.schemas {
            self.schema(s, &uses, &mut b);
        }
        self.grounding_budget(r);
        collect_values(&r.body.node, &self.set, &mut b.values);
        self.formula(&r.body, &b);
        if let Some(w) = &r.weight {
            if !in_unit(w.node) {
                self.err(DiagnosticKind::DegreeOutOfRange { value: w.node }, w.span);
            }
        }
        // The head.
        let name = r.head.atom.name.node.as_str();
        let head_ok = is_place_head(name) || self.set.predicates.contains_key(name);
        if head_ok && r.head.negated && !is_place_head(name) {
            // `(¬q, β)` would need q's own possibility distribution; bodies read `q` as a
            // degree, so such a head could never be used: say so instead of ignoring it.
            self.err(
                DiagnosticKind::NegatedDerivedHead {
                    name: name.to_string(),
                },
                r.head.span,
            );
        } else if head_ok {
            self.atom(&r.head.atom, &b);
        } else {
            self.err(
                DiagnosticKind::BadHead {
                    name: name.to_string(),
                },
                r.head.atom.name.span,
            );
        }
        self.set.rules.push(r.clone());
    }

    /// Counts the ground instances the compiler would make of `r` (one per schema binding and
    /// hypothesis place) and reports the rule at its schemas when the file's total passes
    /// [`MAX_GROUND_INSTANCES`] — from the sizes alone, before anything is allocated: three
    /// nested `for all` over a 100-value domain once made the compiler abort out of memory.
    fn grounding_budget(&mut self, r: &Rule) {
        let bindings = r.schemas.iter().fold(1u128, |n, s| {
            let size = match &s.source {
                SchemaSource::Domain(d) => self.set.domains.get(&d.node).map_or(0, Vec::len),
                SchemaSource::Tuples(ts) => ts.len(),
            };
            n.saturating_mul(size as u128)
        });
        let instances = bindings.saturating_mul(self.map.places().len().max(1) as u128);
        let before = self.grounded;
        self.grounded = before.saturating_add(instances);
        if before <= MAX_GROUND_INSTANCES && self.grounded > MAX_GROUND_INSTANCES {
            let span = match (r.schemas.first(), r.schemas.last()) {
                (Some(first), Some(last)) => first.span.join(last.span),
                _ => r.span,
            };
            self.err(
                DiagnosticKind::GroundingBudget {
                    instances,
                    total: self.grounded,
                    limit: MAX_GROUND_INSTANCES,
                },
                span,
            );
        }
    }

    fn schema(&mut self, s: &Schema, uses: &BTreeMap<String, String>, b: &mut Bindings) {
        match &s.source {
            SchemaSource::Domain(d) => self.domain_schema(s, d, uses, b),
            SchemaSource::Tuples(ts) => self.tuples_schema(s, ts, uses, b),
        }
    }

    /// `for all x in D`: one variable ranging over a declared domain, which must agree with the
    /// domain its uses in the rule imply.
    fn domain_schema(
        &mut self,
        s: &Schema,
        d: &Spanned<String>,
        uses: &BTreeMap<String, String>,
        b: &mut Bindings,
    ) {
        if s.vars.len() != 1 {
            self.err(
                DiagnosticKind::SchemaArity {
                    expected: s.vars.len(),
                    found: 1,
                },
                d.span,
            );
            return;
        }
        let Some(values) = self.set.domains.get(&d.node).cloned() else {
            self.err(
                DiagnosticKind::UnknownDomain {
                    name: d.node.clone(),
                },
                d.span,
            );
            // Still bind the variable, so that its uses do not cascade into errors.
            b.schema.insert(s.vars[0].node.clone(), Vec::new());
            return;
        };
        if let Some(used) = uses.get(&s.vars[0].node) {
            if used != &d.node {
                self.err(
                    DiagnosticKind::UnknownDomainValue {
                        domain: used.clone(),
                        value: d.node.clone(),
                    },
                    d.span,
                );
            }
        }
        b.schema.insert(s.vars[0].node.clone(), values);
    }

    /// `for all (x, y) in {(a, b), …}`: each tuple must match the variables, and each value must
    /// belong to its variable's domain (or, when the rule does not fix one, to some domain).
    fn tuples_schema(
        &mut self,
        s: &Schema,
        ts: &[Spanned<Vec<Spanned<String>>>],
        uses: &BTreeMap<String, String>,
        b: &mut Bindings,
    ) {
        let mut values: Vec<Vec<String>> = vec![Vec::new(); s.vars.len()];
        for spanned in ts {
            let t = &spanned.node;
            if t.len() != s.vars.len() {
                self.err(
                    DiagnosticKind::SchemaArity {
                        expected: s.vars.len(),
                        found: t.len(),
                    },
                    spanned.span,
                );
                continue;
            }
            for (i, (var, val)) in s.vars.iter().zip(t).enumerate() {
                match uses.get(&var.node) {
                    Some(dom) => self.constant_in(dom, val),
                    None => self.constant_in_any_domain(val),
                }
                values[i].push(val.node.clone());
            }
        }
        for (var, vals) in s.vars.iter().zip(values) {
            b.schema.insert(var.node.clone(), vals);
        }
    }

    /// Checks that constant `c` is a value of some declared domain.
    fn constant_in_any_domain(&mut self, c: &Spanned<String>) {
        let known = self.set.domains.values().any(|vs| vs.contains(&c.node));
        if !known {
            let all: BTreeSet<String> = self.set.domains.values().flatten().cloned().collect();
            self.err_unknown(
                DiagnosticKind::UnknownDomainValue {
                    domain: "any domain".into(),
                    value: c.node.clone(),
                },
                c.span,
                &c.node,
                all.iter().map(String::as_str),
            );
        }
    }

    /// Checks that constant `c` is a value of domain `dom`.
    fn constant_in(&mut self, dom: &str, c: &Spanned<String>) {
        let Some(values) = self.set.domains.get(dom).cloned() else {
            return; // unknown domain: reported at the declaration
        };
        if values.contains(&c.node) {
            return;
        }
        let name = c.node.clone();
        let kind = match dom {
            "Place" => DiagnosticKind::UnknownPlace { name },
            "Room" => DiagnosticKind::UnknownRoom { name },
            "Region" => DiagnosticKind::UnknownRegion { name },
            "Landmark" => DiagnosticKind::UnknownLandmark { name },
            _ => DiagnosticKind::UnknownDomainValue {
                domain: dom.to_string(),
                value: name,
            },
        };
        self.err_unknown(kind, c.span, &c.node, values.iter().map(String::as_str));
    }

    fn formula(&mut self, f: &Spanned<Formula>, b: &Bindings) {
        match &f.node {
            Formula::Atom(a) => self.atom(a, b),
            Formula::Degree(x) => {
                if !in_unit(*x) {
                    self.err(DiagnosticKind::DegreeOutOfRange { value: *x }, f.span);
                }
            }
            Formula::Not(x) => self.formula(x, b),
            Formula::And(v) | Formula::Times(v) | Formula::Or(v) => {
                v.iter().for_each(|x| self.formula(x, b))
            }
            Formula::Implies(x, y) => {
                self.formula(x, b);
                self.formula(y, b);
            }
            Formula::Weighted(x, w) => {
                self.formula(x, b);
                if !in_unit(w.node) {
                    self.err(DiagnosticKind::DegreeOutOfRange { value: w.node }, w.span);
                }
            }
        }
    }

    fn arity(&mut self, a: &Atom, expected: usize) -> bool {
        if a.args.len() == expected {
            return true;
        }
        self.err(
            DiagnosticKind::ArityMismatch {
                name: a.name.node.clone(),
                expected,
                found: a.args.len(),
            },
            a.span,
        );
        false
    }

    fn bad_arg(&mut self, a: &Atom, i: usize, expected: &'static str) {
        self.err(
            DiagnosticKind::BadArgument {
                name: a.name.node.clone(),
                position: i + 1,
                expected,
            },
            a.args[i].span,
        );
    }

    fn atom(&mut self, a: &Atom, b: &Bindings) {
        match a.name.node.as_str() {
            "at_place" | "in_room" | "in_region" => self.place_atom(a, b),
            "at_wall" | "at_corner" | "at_open" | "at_door" => self.map_relation_atom(a, b),
            _ => self.declared_atom(a, b),
        }
    }

    /// `at_place(x)`, `in_room(x)`, `in_region(x)`: the argument names a place set of the map,
    /// or is the hypothesis' own `P_i` / `R_i`.
    fn place_atom(&mut self, a: &Atom, b: &Bindings) {
        if !self.arity(a, 1) {
            return;
        }
        let name = a.name.node.as_str();
        let (dom, own) = match name {
            "at_place" => ("Place", "P"),
            "in_room" => ("Room", "R"),
            _ => ("Region", "-"),
        };
        match &a.args[0].node {
            Term::PlaceRef { name: n, key: None } if n == own => {}
            _ => {
                let expected = match name {
                    "at_place" => "`P_i`, a place name or a `for all` variable over Place",
                    "in_room" => "`R_i`, a room name or a `for all` variable over Room",
                    _ => "a region name or a `for all` variable over Region",
                };
                self.domain_arg(a, 0, dom, b, expected);
            }
        }
    }

    /// `at_wall(v, t)` and its kin compare the map with a percept's directions, so `v` must be
    /// bound by a percept that has enough `Dir` positions.
    fn map_relation_atom(&mut self, a: &Atom, b: &Bindings) {
        if !self.arity(a, 2) {
            return;
        }
        let name = a.name.node.as_str();
        let relation: &'static str = match name {
            "at_wall" => "at_wall",
            "at_open" => "at_open",
            "at_door" => "at_door",
            _ => "at_corner",
        };
        let needed = if name == "at_corner" { 2 } else { 1 };
        match &a.args[0].node {
            Term::Var(v) => match b.values.get(v) {
                Some(p) => {
                    let dirs = self.set.percepts.get(p).map_or(0, |s| {
                        s.roles
                            .iter()
                            .filter(|r| matches!(r, ArgRole::Domain(d) if d == "Dir"))
                            .count()
                    });
                    if dirs < needed {
                        self.err(
                            DiagnosticKind::MapRelationNeedsDirections {
                                relation,
                                percept: p.clone(),
                                needed,
                                found: dirs,
                            },
                            a.args[0].span,
                        );
                    }
                }
                None => self.err(
                    DiagnosticKind::MapRelationUnbound {
                        relation,
                        var: v.clone(),
                    },
                    a.args[0].span,
                ),
            },
            _ => self.bad_arg(a, 0, "a variable bound by a percept's value"),
        }
        if a.args[1].node != Term::Time {
            self.bad_arg(a, 1, "the time `t`");
        }
    }

    /// An atom of a declared percept or derived predicate: each argument must fit its role.
    fn declared_atom(&mut self, a: &Atom, b: &Bindings) {
        let name = a.name.node.as_str();
        let sig = self
            .set
            .percepts
            .get(name)
            .map(|s| (s.roles.clone(), true))
            .or_else(|| {
                self.set
                    .predicates
                    .get(name)
                    .map(|s| (s.roles.clone(), false))
            });
        let Some((roles, is_percept)) = sig else {
            let known: Vec<String> = (self.set.percepts.keys())
                .chain(self.set.predicates.keys())
                .cloned()
                .chain(BUILTIN_PREDICATES.iter().map(|s| s.to_string()))
                .collect();
            self.err_unknown(
                DiagnosticKind::UnknownPredicate {
                    name: name.to_string(),
                },
                a.name.span,
                name,
                known.iter().map(String::as_str),
            );
            return;
        };
        if !self.arity(a, roles.len()) {
            return;
        }
        for (i, role) in roles.iter().enumerate() {
            match role {
                ArgRole::Domain(d) => {
                    self.domain_arg(a, i, d, b, "a value of the domain or a `for all` variable")
                }
                ArgRole::Time => {
                    if a.args[i].node != Term::Time {
                        self.bad_arg(a, i, "the time `t`");
                    }
                }
                ArgRole::Value => {
                    if is_percept && !is_value_pattern(&a.args[i].node) {
                        self.bad_arg(a, i, "a variable or a tuple of variables");
                    }
                }
                ArgRole::Expect => {
                    if is_percept && !is_expectation(&a.args[i].node) {
                        self.bad_arg(a, i, "a place parameter like `A_i` or a number");
                    } else {
                        self.expectation(&a.args[i], b);
                    }
                }
            }
        }
    }

    /// Checks argument `i` of `a` in a position of domain `dom`.
    fn domain_arg(&mut self, a: &Atom, i: usize, dom: &str, b: &Bindings, expected: &'static str) {
        let arg = &a.args[i];
        match &arg.node {
            Term::Const(c) => self.constant_in(dom, &Spanned::new(c.clone(), arg.span)),
            Term::Var(v) => {
                if !b.schema.contains_key(v) {
                    self.err(
                        DiagnosticKind::UnboundVariable { name: v.clone() },
                        arg.span,
                    );
                }
            }
            Term::PlaceRef { name, key: None }
                if (name == "P" && dom == "Place") || (name == "R" && dom == "Room") => {}
            _ => self.bad_arg(a, i, expected),
        }
    }

    /// Checks the place parameters mentioned in an `expect` argument.
    fn expectation(&mut self, t: &Spanned<Term>, b: &Bindings) {
        match &t.node {
            Term::Tuple(ts) => ts.iter().for_each(|x| self.expectation(x, b)),
            Term::PlaceRef { name, key } => {
                if key.is_none() && (name == "P" || name == "R") {
                    return;
                }
                let keys: Vec<Option<String>> = match key {
                    None => vec![None],
                    Some(k) if k.starts_with(|c: char| c.is_ascii_uppercase()) => {
                        vec![Some(k.clone())]
                    }
                    Some(k) => match b.schema.get(k) {
                        Some(vals) => vals.iter().cloned().map(Some).collect(),
                        None => {
                            self.err(DiagnosticKind::UnboundVariable { name: k.clone() }, t.span);
                            return;
                        }
                    },
                };
                let mut defined = false;
                for k in keys
                    .iter()
                    .filter(|k| self.map.defines_param(name, k.as_deref()))
                {
                    self.set.params.insert((name.clone(), k.clone()));
                    defined = true;
                }
                if !defined && !keys.is_empty() {
                    self.err(
                        DiagnosticKind::UndefinedParameter {
                            name: name.clone(),
                            key: KeySuffix(key.clone()),
                        },
                        t.span,
                    );
                }
            }
            _ => {}
        }
    }

    // ----- rules that can never fire --------------------------------------------------------

    fn never_fires(&mut self) {
        let rules = &self.set.rules;
        let mut concluded: BTreeSet<&str> = rules
            .iter()
            .map(|r| r.head.atom.name.node.as_str())
            .collect();
        let mut reasons: Vec<Option<NeverFiresReason>>;
        loop {
            reasons = rules
                .iter()
                .map(|r| {
                    if r.schemas
                        .iter()
                        .any(|s| schema_is_empty(s, &self.set.domains))
                    {
                        return Some(NeverFiresReason::EmptySchema);
                    }
                    if r.weight.as_ref().is_some_and(|w| w.node <= 0.0) {
                        return Some(NeverFiresReason::ZeroWeight);
                    }
                    zero_reason(&r.body.node, &self.set, &concluded)
                })
                .collect();
            let next: BTreeSet<&str> = rules
                .iter()
                .zip(&reasons)
                .filter(|(_, z)| z.is_none())
                .map(|(r, _)| r.head.atom.name.node.as_str())
                .collect();
            if next == concluded {
                break;
            }
            concluded = next;
        }
        let found: Vec<Diagnostic> = rules
            .iter()
            .zip(reasons)
            .filter_map(|(r, z)| {
                z.map(|reason| Diagnostic::error(DiagnosticKind::RuleNeverFires { reason }, r.span))
            })
            .collect();
        self.diags.extend(found);
    }
}

fn schema_is_empty(s: &Schema, domains: &BTreeMap<String, Vec<String>>) -> bool {
    match &s.source {
        SchemaSource::Domain(d) => domains.get(&d.node).is_some_and(|v| v.is_empty()),
        SchemaSource::Tuples(ts) => ts.is_empty(),
    }
}

/// Why `f` is 0 whatever the sensors say, given the predicates that some firing rule concludes
/// (`None` when it can be positive).
fn zero_reason(f: &Formula, set: &RuleSet, concluded: &BTreeSet<&str>) -> Option<NeverFiresReason> {
    match f {
        Formula::Atom(a) => {
            let n = a.name.node.as_str();
            let derived = is_place_head(n) || set.predicates.contains_key(n);
            (derived && !concluded.contains(n)).then(|| NeverFiresReason::NeverConcluded {
                predicate: n.to_string(),
            })
        }
        Formula::Degree(x) => (*x <= 0.0).then_some(NeverFiresReason::AlwaysZero),
        Formula::Not(_) | Formula::Implies(_, _) => None,
        Formula::And(v) | Formula::Times(v) => {
            v.iter().find_map(|x| zero_reason(&x.node, set, concluded))
        }
        Formula::Or(v) => {
            let mut first = None;
            for x in v {
                match zero_reason(&x.node, set, concluded) {
                    None => return None,
                    Some(r) => {
                        first.get_or_insert(r);
                    }
                }
            }
            first
        }
        Formula::Weighted(x, w) => zero_reason(&x.node, set, concluded)
            .or((w.node <= 0.0).then_some(NeverFiresReason::AlwaysZero)),
    }
}

/// A `value` argument of a percept: a variable or a tuple of them.
fn is_value_pattern(t: &Term) -> bool {
    match t {
        Term::Var(_) => true,
        Term::Tuple(ts) => ts.iter().all(|x| is_value_pattern(&x.node)),
        _ => false,
    }
}

/// An `expect` argument of a percept: a place parameter, a number, or a tuple of them.
fn is_expectation(t: &Term) -> bool {
    match t {
        Term::PlaceRef { .. } | Term::Number(_) => true,
        Term::Tuple(ts) => ts.iter().all(|x| is_expectation(&x.node)),
        _ => false,
    }
}

/// Records, for each variable in a domain position of a percept or predicate atom of `f`, the
/// domain of that position (first use wins).
fn collect_var_domains(f: &Formula, set: &RuleSet, out: &mut BTreeMap<String, String>) {
    match f {
        Formula::Atom(a) => collect_atom_var_domains(a, set, out),
        Formula::Degree(_) => {}
        Formula::Not(x) | Formula::Weighted(x, _) => collect_var_domains(&x.node, set, out),
        Formula::And(v) | Formula::Times(v) | Formula::Or(v) => v
            .iter()
            .for_each(|x| collect_var_domains(&x.node, set, out)),
        Formula::Implies(x, y) => {
            collect_var_domains(&x.node, set, out);
            collect_var_domains(&y.node, set, out);
        }
    }
}

fn collect_atom_var_domains(a: &Atom, set: &RuleSet, out: &mut BTreeMap<String, String>) {
    let n = a.name.node.as_str();
    let roles: Vec<ArgRole> = match n {
        "at_place" => vec![ArgRole::Domain("Place".into())],
        "in_room" => vec![ArgRole::Domain("Room".into())],
        "in_region" => vec![ArgRole::Domain("Region".into())],
        _ => match set.percepts.get(n).or_else(|| set.predicates.get(n)) {
            Some(s) => s.roles.clone(),
            None => return,
        },
    };
    for (r, t) in roles.iter().zip(&a.args) {
        if let (ArgRole::Domain(d), Term::Var(v)) = (r, &t.node) {
            out.entry(v.clone()).or_insert_with(|| d.clone());
        }
        // Keys of place parameters (`range_i(g)`) range over landmarks.
        if let Term::PlaceRef { key: Some(k), .. } = &t.node {
            if !k.starts_with(|c: char| c.is_ascii_uppercase()) {
                out.entry(k.clone()).or_insert_with(|| "Landmark".into());
            }
        }
    }
}

/// Records the variables in `value` positions of percept atoms of `f`, with their percept.
fn collect_values(f: &Formula, set: &RuleSet, out: &mut BTreeMap<String, String>) {
    match f {
        Formula::Atom(a) => {
            if let Some(s) = set.percepts.get(&a.name.node) {
                for (r, t) in s.roles.iter().zip(&a.args) {
                    if *r == ArgRole::Value {
                        value_vars(&t.node, &a.name.node, out);
                    }
                }
            }
        }
        Formula::Degree(_) => {}
        Formula::Not(x) | Formula::Weighted(x, _) => collect_values(&x.node, set, out),
        Formula::And(v) | Formula::Times(v) | Formula::Or(v) => {
            v.iter().for_each(|x| collect_values(&x.node, set, out))
        }
        Formula::Implies(x, y) => {
            collect_values(&x.node, set, out);
            collect_values(&y.node, set, out);
        }
    }
}

fn value_vars(t: &Term, percept: &str, out: &mut BTreeMap<String, String>) {
    match t {
        Term::Var(v) => {
            out.entry(v.clone()).or_insert_with(|| percept.to_string());
        }
        Term::Tuple(ts) => ts.iter().for_each(|x| value_vars(&x.node, percept, out)),
        _ => {}
    }
}
