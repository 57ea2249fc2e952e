//! Problems found in rule and map files: what went wrong ([`DiagnosticKind`], a `thiserror` enum
//! whose variants carry the names and numbers involved), where ([`Span`]), how bad
//! ([`Severity`]) and what to do about it (a help line per kind). Two renderers: a plain-text one
//! that needs nothing but the source text (`path:line:col: error: …`, the line, a caret, `help:`),
//! used by engine-only builds, and — with the `cli` feature — `Report`, a `miette` diagnostic
//! that bundles one file with all of its problems.
//!
//! Depends only on `syntax::span` and `syntax::suggest` (spelling help for unknown names); every other stage (parsers, map builder, checker, compiler)
//! produces these.

use super::span::Span;
use super::suggest::Suggestion;
use std::fmt;

/// A source text and the name it is shown under (usually the path as the user wrote it).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SourceFile {
    /// Name shown in diagnostics, e.g. `rules/office.lpl`.
    pub name: String,
    /// The whole text.
    pub text: String,
}

impl SourceFile {
    /// A source file named `name` with contents `text`.
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> Self {
        SourceFile {
            name: name.into(),
            text: text.into(),
        }
    }

    /// A source file from the bytes of a file: a UTF-8 byte-order mark is dropped (editors on
    /// Windows write one); bytes that are not UTF-8 are shown as `�`, with an
    /// [`DiagnosticKind::InvalidUtf8`] error at the first of them (so the caller can report it
    /// with its line and column, and must not use the text).
    pub fn from_bytes(name: impl Into<String>, mut bytes: Vec<u8>) -> (Self, Option<Diagnostic>) {
        if bytes.starts_with(b"\xEF\xBB\xBF") {
            bytes.drain(..3);
        }
        match String::from_utf8(bytes) {
            Ok(text) => (SourceFile::new(name, text), None),
            Err(e) => {
                let at = e.utf8_error().valid_up_to();
                let byte = e.as_bytes().get(at).copied().unwrap_or(0);
                let text = String::from_utf8_lossy(e.as_bytes()).into_owned();
                // The text before the bad byte is unchanged; `�` is 3 bytes long.
                let d = Diagnostic::error(
                    DiagnosticKind::InvalidUtf8 { byte },
                    Span::new(at, at + '\u{FFFD}'.len_utf8()),
                );
                (SourceFile::new(name, text), Some(d))
            }
        }
    }
}

/// How bad a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    /// The file cannot be used.
    Error,
    /// The file can be used, but probably does not say what its author meant.
    Warning,
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
        })
    }
}

/// The alternatives a parser expected, shown as "a, b or c".
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OneOf(pub Vec<&'static str>);

impl fmt::Display for OneOf {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0.len() {
            0 => f.write_str("something else"),
            n => {
                for (i, s) in self.0.iter().enumerate() {
                    if i > 0 {
                        f.write_str(if i + 1 == n { " or " } else { ", " })?;
                    }
                    f.write_str(s)?;
                }
                Ok(())
            }
        }
    }
}

/// What the parser found where it expected something else: a character, or the end of input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Found(pub Option<char>);

impl fmt::Display for Found {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            None => f.write_str("end of input"),
            Some(c) if c.is_control() || c.is_whitespace() => write!(f, "{:?}", c),
            Some(c) => write!(f, "`{c}`"),
        }
    }
}

/// An optional key shown as `(Key)` after a parameter name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KeySuffix(pub Option<String>);

impl fmt::Display for KeySuffix {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.0 {
            Some(k) => write!(f, "({k})"),
            None => Ok(()),
        }
    }
}

/// Why a rule can never contribute a non-zero degree.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NeverFiresReason {
    /// The body is the constant 0 whatever the sensors say (a degree 0 in it, or a weight 0
    /// inside it).
    AlwaysZero,
    /// The compiled body is the constant 0 at every place of this map (found by the compiler):
    /// the map's places lack what the rule tests. A warning, since the fix, if any, is in the map.
    NotOnThisMap,
    /// The body needs a derived predicate that no rule concludes.
    NeverConcluded {
        /// The predicate.
        predicate: String,
    },
    /// A schema ranges over nothing (an empty domain or tuple set), so the rule has no instances.
    EmptySchema,
    /// The rule's weight is 0, so whatever its body, its conclusion gets 0.
    ZeroWeight,
}

impl fmt::Display for NeverFiresReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NeverFiresReason::AlwaysZero => f.write_str("its body is 0 whatever the sensors say"),
            NeverFiresReason::NotOnThisMap => {
                f.write_str("its body is 0 at every place of this map: no place has what it tests")
            }
            NeverFiresReason::NeverConcluded { predicate } => {
                write!(f, "its body needs `{predicate}`, which no rule concludes")
            }
            NeverFiresReason::EmptySchema => f.write_str("a `for all` clause ranges over nothing"),
            NeverFiresReason::ZeroWeight => {
                f.write_str("its weight is 0, so its conclusion gets 0 whatever the body")
            }
        }
    }
}

/// Everything that can be wrong with a rule or map file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DiagnosticKind {
    // ----- syntax ------------------------------------------------------------------------
    /// The text does not follow the grammar.
    #[error("syntax error: expected {expected}, found {found}")]
    Syntax {
        /// What would have been accepted here.
        expected: OneOf,
        /// What was there instead.
        found: Found,
    },
    /// Parentheses, tuples or negations nest deeper than the parser allows.
    #[error("too deeply nested (more than {limit} levels)")]
    TooDeeplyNested {
        /// The nesting limit.
        limit: usize,
    },
    /// The file has so many syntax errors that the parser stopped looking (it is probably not
    /// a map or rule file at all).
    #[error("{count} syntax errors: stopped parsing here")]
    TooManySyntaxErrors {
        /// How many were reported before stopping.
        count: usize,
    },
    /// The file is not UTF-8 text; the span covers the first offending byte, shown as `�`.
    #[error("invalid UTF-8: byte 0x{byte:02x} is not part of a character")]
    InvalidUtf8 {
        /// The first byte that is not valid UTF-8.
        byte: u8,
    },
    /// A number that is not finite (`1e999`).
    #[error("number `{text}` is out of range")]
    NumberOutOfRange {
        /// The number as written.
        text: String,
    },
    /// `((φ -> h, 0.5), 0.6)`: two weights on one sequent.
    #[error("the sequent has more than one weight")]
    DuplicateWeight,
    /// The parser met a structure the grammar should have excluded (a bug in lplace).
    #[error("internal parser error: {what}")]
    Internal {
        /// What was unexpected.
        what: &'static str,
    },

    // ----- names -------------------------------------------------------------------------
    /// A name declared twice (in the same namespace).
    #[error("{what} `{name}` is defined more than once")]
    DuplicateName {
        /// Kind of thing (`place`, `domain`, …).
        what: &'static str,
        /// The name.
        name: String,
    },
    /// A name that belongs to lplace itself (`Place`, `at_place`, …).
    #[error("`{name}` is built in and cannot be redeclared")]
    ReservedName {
        /// The name.
        name: String,
    },
    /// An atom whose name is neither a percept, a predicate nor a built-in.
    #[error("unknown predicate `{name}`")]
    UnknownPredicate {
        /// The name.
        name: String,
    },
    /// An atom with the wrong number of arguments.
    #[error("`{name}` takes {expected} argument(s), found {found}")]
    ArityMismatch {
        /// The predicate.
        name: String,
        /// Declared arity.
        expected: usize,
        /// Arguments written.
        found: usize,
    },
    /// A variable used where it must be bound, but bound by nothing.
    #[error("variable `{name}` is not bound by a `for all` clause or a percept")]
    UnboundVariable {
        /// The variable.
        name: String,
    },
    /// A place name that the map does not declare.
    #[error("unknown place `{name}`")]
    UnknownPlace {
        /// The name.
        name: String,
    },
    /// A room name that the map does not declare.
    #[error("unknown room `{name}`")]
    UnknownRoom {
        /// The name.
        name: String,
    },
    /// A landmark name that the map does not declare.
    #[error("unknown landmark `{name}`")]
    UnknownLandmark {
        /// The name.
        name: String,
    },
    /// A domain name that is neither declared nor built in.
    #[error("unknown domain `{name}`")]
    UnknownDomain {
        /// The name.
        name: String,
    },
    /// A constant that is not a value of the domain its position requires.
    #[error("`{value}` is not a value of domain `{domain}`")]
    UnknownDomainValue {
        /// The domain.
        domain: String,
        /// The constant.
        value: String,
    },
    /// A similarity name that is not declared.
    #[error("unknown similarity `{name}`")]
    UnknownSimilarity {
        /// The name.
        name: String,
    },
    /// A `PlaceRef` parameter that no place of the map defines.
    #[error("no place of the map defines parameter `{name}{key}`")]
    UndefinedParameter {
        /// Parameter name.
        name: String,
        /// Its key.
        key: KeySuffix,
    },

    // ----- values ------------------------------------------------------------------------
    /// A degree or weight outside `[0, 1]`.
    #[error("degree {value} is outside [0, 1]")]
    DegreeOutOfRange {
        /// The value.
        value: f64,
    },
    /// A setting key that `logic { … }` does not know.
    #[error("unknown setting `{key}`")]
    UnknownSetting {
        /// The key.
        key: String,
    },
    /// A setting given a value of the wrong kind or out of range.
    #[error("bad value for setting `{key}`: expected {expected}")]
    BadSettingValue {
        /// The key.
        key: String,
        /// What it accepts.
        expected: &'static str,
    },
    /// A key that `tracker { … }` (or its `grid { … }`) does not know.
    #[error("unknown tracker setting `{key}`")]
    UnknownTrackerSetting {
        /// The key.
        key: String,
    },
    /// A tracker setting given a value of the wrong kind or out of range.
    #[error("bad value for tracker setting `{key}`: expected {expected}")]
    BadTrackerValue {
        /// The key.
        key: String,
        /// What it accepts.
        expected: &'static str,
    },
    /// A similarity shape other than `trapezoid`.
    #[error("unknown similarity shape `{name}`")]
    UnknownShape {
        /// The shape.
        name: String,
    },
    /// A similarity field that the shape does not have.
    #[error("unknown similarity field `{field}`")]
    UnknownField {
        /// The field.
        field: String,
    },
    /// A similarity field with an invalid value.
    #[error("bad value {value} for similarity field `{field}`: {requirement}")]
    BadFieldValue {
        /// The field.
        field: String,
        /// The value.
        value: f64,
        /// What is required.
        requirement: &'static str,
    },
    /// A negative (or otherwise invalid) length or radius.
    #[error("{what} must be a non-negative number, found {value}")]
    NegativeLength {
        /// `length`, `radius`, …
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// A path length of 0: two places with no distance between them are one place, and the
    /// tracker divides travelled distance by path lengths.
    #[error("path length must be positive, found {value}")]
    ZeroLength {
        /// The value.
        value: f64,
    },
    /// A landmark id outside what sensors report (0 ..= 4294967295).
    #[error("landmark id must be between 0 and {}, found {value}", u32::MAX)]
    BadLandmarkId {
        /// The id as written.
        value: i64,
    },
    /// The rules would ground to more instances than the compiler is allowed to make.
    #[error(
        "this rule grounds to {instances} instances (schema bindings × places), bringing the \
         file to {total}; the limit is {limit}"
    )]
    GroundingBudget {
        /// Instances of this rule.
        instances: u128,
        /// Instances of the file's rules up to and including this one.
        total: u128,
        /// The limit (`rules::MAX_GROUND_INSTANCES`).
        limit: u128,
    },
    /// A parameter range whose ends are in the wrong order.
    #[error("parameter range is empty ({low} > {high})")]
    EmptyRange {
        /// The lower end as written.
        low: f64,
        /// The upper end as written.
        high: f64,
    },
    /// A box extent whose corners are in the wrong order.
    #[error("box extent has its corners swapped ({low} > {high})")]
    InvalidBox {
        /// The lower bound as written.
        low: f64,
        /// The upper bound as written.
        high: f64,
    },

    // ----- rule structure ----------------------------------------------------------------
    /// A percept whose signature has `expect` but which names no similarity.
    #[error("percept `{percept}` has an `expect` argument but no `~ similarity`")]
    ExpectWithoutSimilarity {
        /// The percept.
        percept: String,
    },
    /// A schema tuple whose size differs from the number of variables.
    #[error("this tuple has {found} value(s) but the clause binds {expected} variable(s)")]
    SchemaArity {
        /// Number of variables.
        expected: usize,
        /// Number of values.
        found: usize,
    },
    /// A rule concluding something that is not a declared predicate, `at_place`, `in_room` or
    /// `in_region`.
    #[error("`{name}` cannot be the head of a rule: only declared predicates, `at_place`, `in_room` and `in_region` can")]
    BadHead {
        /// The head's name.
        name: String,
    },
    /// An argument that does not fit the role of its position.
    #[error("argument {position} of `{name}` must be {expected}")]
    BadArgument {
        /// The atom's name.
        name: String,
        /// 1-based argument position.
        position: usize,
        /// What the role accepts.
        expected: &'static str,
    },
    /// `at_wall(v, t)` with `v` not bound by a `value` position of a percept.
    #[error("`{relation}` needs `{var}` to be the value of a percept in the same rule")]
    MapRelationUnbound {
        /// `at_wall` or `at_corner`.
        relation: &'static str,
        /// The variable.
        var: String,
    },
    /// `at_wall(v, t)` where `v`'s percept has too few `Dir` arguments.
    #[error("`{relation}` needs a percept with at least {needed} `Dir` argument(s); `{percept}` has {found}")]
    MapRelationNeedsDirections {
        /// `at_wall` or `at_corner`.
        relation: &'static str,
        /// The percept binding the variable.
        percept: String,
        /// Required number.
        needed: usize,
        /// Number the percept has.
        found: usize,
    },
    /// A rule that can never contribute.
    #[error("this rule can never fire: {reason}")]
    RuleNeverFires {
        /// Why.
        reason: NeverFiresReason,
    },
    /// A derived predicate that depends on itself.
    #[error("predicate `{name}` is defined in terms of itself")]
    RecursivePredicate {
        /// The predicate.
        name: String,
    },
    /// A negated head `!q` of a declared predicate: bodies read `q` as a degree, so `(¬q, β)`
    /// could never be used.
    #[error("`!{name}` cannot be concluded: a negated head must be `at_place`, `in_room` or `in_region`")]
    NegatedDerivedHead {
        /// The predicate.
        name: String,
    },
    /// A region named like a place or room of the map (queries name all three alike).
    #[error("region `{name}` has the name of a {what} of the map")]
    RegionNameTaken {
        /// The name.
        name: String,
        /// `place` or `room`.
        what: &'static str,
    },
    /// A region over a kind no place of the map has, in a map that does not declare its kinds.
    #[error("no place of the map is of kind `{name}`")]
    UnknownKind {
        /// The kind.
        name: String,
    },
    /// A region name that is not declared.
    #[error("unknown region `{name}`")]
    UnknownRegion {
        /// The name.
        name: String,
    },

    // ----- maps --------------------------------------------------------------------------
    /// A path whose end is not a place of the map.
    #[error("path to unknown place `{name}`")]
    PathToUnknownPlace {
        /// The name.
        name: String,
    },
    /// The same two places joined twice.
    #[error("places `{from}` and `{to}` are already joined by a path")]
    DuplicatePath {
        /// One end.
        from: String,
        /// The other end.
        to: String,
    },
    /// A path from a place to itself.
    #[error("path from `{name}` to itself")]
    SelfPath {
        /// The place.
        name: String,
    },
    /// The same wall, corner or parameter written twice in one place.
    #[error("{what} `{name}` is given more than once in this place")]
    DuplicateFeature {
        /// `wall`, `corner`, `param`.
        what: &'static str,
        /// Which one.
        name: String,
    },
    /// A place without parameters that the rules read at other places (a warning).
    #[error("place `{place}` has no {params}, which the rules read at other places")]
    PlaceLacksParameters {
        /// The place.
        place: String,
        /// What it lacks, comma-separated (`A, L` or `free(North)`).
        params: String,
    },
    /// An `open D` side along which the extents beyond it reach over less than half its
    /// length (a warning): from most of the place that way reads a wall.
    #[error("`open {dir}`: the places beyond this side reach along {percent} % of it")]
    OpenSidePartlyReached {
        /// The direction.
        dir: String,
        /// The share of the side the adjoining extents cover, per cent.
        percent: u32,
    },
    /// A wall or corner direction that is not a value of the rule file's `Dir` domain.
    #[error("direction `{name}` is not a value of the rules' `Dir` domain")]
    UnknownDirection {
        /// The direction.
        name: String,
    },
    /// `map name;` written twice.
    #[error("the map is named more than once")]
    DuplicateMapName,
    /// `axis D;` or `kinds {…};` written twice.
    #[error("`{what}` is given more than once in the map")]
    DuplicateMapStatement {
        /// `axis` or `kinds`.
        what: &'static str,
    },
    /// `axis D;` with `D` outside ±45° (every building axis has a representative there).
    #[error("building axis {value}° is outside -45° ..= 45°")]
    AxisOutOfRange {
        /// The angle as written.
        value: f64,
    },
    /// A polygon extent whose last vertex is not its first.
    #[error(
        "polygon does not close: it ends at ({x1}, {y1}), not at its first vertex ({x0}, {y0})"
    )]
    PolygonNotClosed {
        /// First vertex x.
        x0: f64,
        /// First vertex y.
        y0: f64,
        /// Last vertex x.
        x1: f64,
        /// Last vertex y.
        y1: f64,
    },
    /// A polygon with fewer than three corners, or with no area.
    #[error("polygon has {count} distinct vertices and no area; it needs at least three")]
    DegeneratePolygon {
        /// Distinct vertices written.
        count: usize,
    },
    /// A polygon whose edges cross.
    #[error("polygon edges {first} and {second} cross")]
    SelfCrossingPolygon {
        /// One edge (1-based, in the order written).
        first: usize,
        /// The other.
        second: usize,
    },
    /// `open D` together with `door D` or `wall D` in one place.
    #[error("`{second} {dir}` contradicts `{first} {dir}` in this place")]
    ContradictoryDirection {
        /// The direction.
        dir: String,
        /// The statement written first (`open`, `wall`, `door`).
        first: &'static str,
        /// The one that contradicts it.
        second: &'static str,
    },
    /// A place kind missing from the map's `kinds {…};` list.
    #[error("place kind `{name}` is not in the map's `kinds` list")]
    UndeclaredKind {
        /// The kind.
        name: String,
    },
}

impl DiagnosticKind {
    /// One line telling the author how to fix it.
    pub fn help(&self) -> &'static str {
        use DiagnosticKind as K;
        match self {
            K::Syntax { .. } => "check the punctuation here against the language examples in the README",
            K::TooManySyntaxErrors { .. } => {
                "fix the errors above first; is this really a map or rule file?"
            }
            K::InvalidUtf8 { .. } => "save the file as UTF-8 (maps and rules are UTF-8 text)",
            K::TooDeeplyNested { .. } => "split the formula into derived predicates",
            K::NumberOutOfRange { .. } => "write a finite number",
            K::DuplicateWeight => "write the weight once: `(body -> head, w)`",
            K::Internal { .. } => "this is a bug in lplace; please report it with the input file",
            K::DuplicateName { .. } => "rename one of the two definitions",
            K::ReservedName { .. } => "built-in domains and predicates come from the map; pick another name",
            K::UnknownPredicate { .. } => "declare it with `percept …;` or `predicate …;`, or fix the spelling",
            K::ArityMismatch { .. } => "give the atom as many arguments as its declaration has roles",
            K::UnboundVariable { .. } => {
                "bind it with `for all v in Domain`, or use it as the value of a percept first"
            }
            K::UnknownPlace { .. } => "use a place declared in the map, or `P_i` for the hypothesis place",
            K::UnknownRoom { .. } => "use a room declared in the map, or `R_i` for the hypothesis place's room",
            K::UnknownLandmark { .. } => "use a beacon or landmark declared in the map",
            K::UnknownDomain { .. } => "declare it with `domain Name = {…};` or use Place, Room or Landmark",
            K::UnknownDomainValue { .. } => "use one of the values listed in the domain's declaration",
            K::UnknownSimilarity { .. } => "declare it with `similarity name = trapezoid(…);`",
            K::UndefinedParameter { .. } => "add `param …` to the places of the map that should expect it",
            K::DegreeOutOfRange { .. } => "degrees and weights are numbers between 0 and 1",
            K::UnknownSetting { .. } => "settings are tnorm, implication, normalisation, fusion, threshold and margin",
            K::BadSettingValue { .. } => {
                "tnorm: min|product|lukasiewicz; implication: residuum|min_mp; normalisation, fusion: min|product; threshold, margin: numbers in [0, 1]"
            }
            K::UnknownTrackerSetting { .. } => {
                "the keys are the fields of a tracker file (docs/languages.md); the grid's go in `grid { … }`"
            }
            K::BadTrackerValue { .. } => {
                "supports and floors are in [0, 1], lengths are ≥ 0, cell_size is > 0; tnorm: min|product|lukasiewicz; normalisation: min|product; use_heading: true|false"
            }
            K::UnknownShape { .. } => "the only similarity shape is `trapezoid`",
            K::UnknownField { .. } => "trapezoid fields are core, slope, height, bias and period",
            K::BadFieldValue { .. } => "core, slope and period are non-negative; 0 ≤ bias ≤ height ≤ 1",
            K::NegativeLength { .. } => "lengths and radii are distances in metres",
            K::GroundingBudget { .. } => {
                "use a smaller domain or tuple list, or a derived predicate per dimension instead of nesting `for all`"
            }
            K::ZeroLength { .. } => "give the path's length in metres, or merge the two places",
            K::BadLandmarkId { .. } => "ids are the non-negative numbers the sensor reports (e.g. MRCLAM barcode subjects)",
            K::InvalidBox { .. } => "write the box as (x0, y0, x1, y1) with x0 ≤ x1 and y0 ≤ y1",
            K::EmptyRange { .. } => "write the range low end first: `param W = 1.5 .. 2.5;`",
            K::ExpectWithoutSimilarity { .. } => "add `~ similarity_name` before the `;`",
            K::SchemaArity { .. } => "give every tuple one value per variable of the `for all` clause",
            K::BadHead { .. } => "declare the head with `predicate name(…);`; percepts come from sensors only",
            K::BadArgument { .. } => "compare the argument with the roles in the declaration",
            K::MapRelationUnbound { .. } => {
                "write a percept such as `sonar_wall(p, d, t)` in the same body and pass its value `p`"
            }
            K::MapRelationNeedsDirections { .. } => {
                "at_wall needs a percept with a `Dir` argument, at_corner one with two"
            }
            K::RuleNeverFires { reason: NeverFiresReason::NotOnThisMap } => {
                "describe in the map the walls, corners or parameters it tests at the places that have them; on this map it adds nothing"
            }
            K::RuleNeverFires { .. } => {
                "give it a positive weight or add a rule that concludes what it needs; or remove it"
            }
            K::RecursivePredicate { .. } => "derived predicates must not depend on themselves",
            K::NegatedDerivedHead { .. } => {
                "conclude a predicate for the opposite instead, or exclude places with `!at_place`/`!in_region`"
            }
            K::RegionNameTaken { .. } => "give the region a name no place or room has",
            K::UnknownKind { .. } => {
                "use a kind written in the map's `place NAME KIND …` lines, or declare the map's kinds with `kinds {…};` (a region over a declared kind no place has is empty)"
            }
            K::UnknownRegion { .. } => "declare it with `region Name = {P1, P2};` in the rule file",
            K::PathToUnknownPlace { .. } => "declare the place, or fix the spelling",
            K::DuplicatePath { .. } => "keep one path between the two places",
            K::SelfPath { .. } => "paths join two different places",
            K::DuplicateFeature { .. } => "keep one of the two lines",
            K::UnknownDirection { .. } => "use one of the values of `domain Dir` in the rule file",
            K::PlaceLacksParameters { .. } => {
                "add the `param …` lines to the place (as `lplace survey` writes them); without them the rules that read them give it no evidence"
            }
            K::OpenSidePartlyReached { .. } => {
                "a corridor that leaves through part of a side is `door D`; `open D` expects a long view from anywhere in the place"
            }
            K::DuplicateMapName => "keep one `map name;` line",
            K::DuplicateMapStatement { .. } => "keep one of the two statements",
            K::AxisOutOfRange { .. } => {
                "walls repeat every 90°: add or subtract 90 (a building at 79° has `axis -11;`)"
            }
            K::PolygonNotClosed { .. } => "repeat the first vertex at the end to close the polygon",
            K::DegeneratePolygon { .. } => "give at least three corners that enclose an area",
            K::SelfCrossingPolygon { .. } => "list the vertices in order around the outline",
            K::ContradictoryDirection { .. } => {
                "`open D`: nothing that way; `door D`: a wall with an opening; `wall D`: a wall (with `door D` if it has a door)"
            }
            K::UndeclaredKind { .. } => "add the kind to `kinds {…};` or fix the spelling",
        }
    }
}

/// One problem in one file.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// What is wrong.
    pub kind: DiagnosticKind,
    /// How bad it is.
    pub severity: Severity,
    /// Where.
    pub span: Span,
    /// A second place in the same file that explains it (e.g. the first definition of a
    /// duplicate), with its label.
    pub related: Option<(Span, &'static str)>,
    /// For an unknown name: the likely intended spelling, or the names that are known.
    pub suggestion: Option<Suggestion>,
}

impl Diagnostic {
    /// An error of `kind` at `span`.
    pub fn error(kind: DiagnosticKind, span: Span) -> Self {
        Diagnostic {
            kind,
            severity: Severity::Error,
            span,
            related: None,
            suggestion: None,
        }
    }

    /// A warning of `kind` at `span`.
    pub fn warning(kind: DiagnosticKind, span: Span) -> Self {
        Diagnostic {
            severity: Severity::Warning,
            ..Diagnostic::error(kind, span)
        }
    }

    /// Adds a related span with a label.
    pub fn with_related(mut self, span: Span, label: &'static str) -> Self {
        self.related = Some((span, label));
        self
    }

    /// Adds spelling help (`None` leaves the diagnostic as it is).
    pub fn with_suggestion(mut self, suggestion: Option<Suggestion>) -> Self {
        self.suggestion = suggestion;
        self
    }

    /// The help line for this diagnostic's kind.
    pub fn help(&self) -> &'static str {
        self.kind.help()
    }

    /// The help shown to the author: the spelling suggestion, if any, on its own line before
    /// the kind's help.
    pub fn full_help(&self) -> String {
        match &self.suggestion {
            Some(s) => format!("{s}\n{}", self.help()),
            None => self.help().to_string(),
        }
    }

    /// True for errors.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// 1-based line and column of the start of the span in `file`.
    pub fn line_col(&self, file: &SourceFile) -> (usize, usize) {
        self.span.line_col(&file.text)
    }

    /// Renders the diagnostic as plain text:
    ///
    /// ```text
    /// rules/x.lpl:3:5: error: unknown predicate `foo`
    ///     |- foo(t) -> at_place(P_i);
    ///        ^^^
    /// help: declare it with `percept …;` or `predicate …;`, or fix the spelling
    /// ```
    pub fn render_plain(&self, file: &SourceFile) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        // Writing into a String cannot fail.
        let level = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        let _ = write_plain(&mut out, self.span, level, &self.kind, file);
        if let Some((span, label)) = self.related {
            let _ = write_plain(&mut out, span, "note", &Note(label), file);
        }
        if let Some(s) = &self.suggestion {
            let _ = writeln!(out, "help: {s}");
        }
        let _ = writeln!(out, "help: {}", self.help());
        out
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.kind, f)
    }
}

impl std::error::Error for Diagnostic {}

/// A label on a related span, rendered as a note.
struct Note(&'static str);

impl fmt::Display for Note {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
}

fn write_plain(
    out: &mut String,
    span: Span,
    level: &str,
    message: &dyn fmt::Display,
    file: &SourceFile,
) -> fmt::Result {
    use std::fmt::Write;
    let text = &file.text;
    let (line, col) = span.line_col(text);
    writeln!(out, "{}:{line}:{col}: {level}: {message}", file.name)?;
    let source_line = text
        .split('\n')
        .nth(line - 1)
        .unwrap_or("")
        .trim_end_matches('\r');
    let line_chars = source_line.chars().count();
    if line_chars > EXCERPT_CHARS {
        return write_excerpt(out, source_line, line_chars, col, span, text);
    }
    writeln!(out, "    {source_line}")?;
    // Carets under the span's characters on its first line (one caret for an empty span).
    let mut start = span.start.min(text.len());
    while !text.is_char_boundary(start) {
        start -= 1;
    }
    let mut end = span.end.min(text.len()).max(start);
    while !text.is_char_boundary(end) {
        end += 1;
    }
    let width = text[start..end]
        .split('\n')
        .next()
        .map_or(0, |s| s.chars().count());
    let width = width.min(line_chars.saturating_sub(col - 1)).max(1);
    writeln!(out, "    {}{}", " ".repeat(col - 1), "^".repeat(width))
}

/// Lines longer than this many characters are shown as an excerpt around the span: a machine-made
/// or corrupted file can put megabytes on one line, and reprinting it per problem would flood the
/// terminal (and the memory of whoever captures stderr).
pub const EXCERPT_CHARS: usize = 160;

/// Writes the window of `source_line` around column `col` (1-based, in characters), `…` marking
/// each cut end, and carets under the span clipped to the window.
fn write_excerpt(
    out: &mut String,
    source_line: &str,
    line_chars: usize,
    col: usize,
    span: Span,
    text: &str,
) -> fmt::Result {
    use std::fmt::Write;
    // The span's start sits a quarter into the window, so some context before it shows too.
    let first = (col - 1)
        .saturating_sub(EXCERPT_CHARS / 4)
        .min(line_chars.saturating_sub(EXCERPT_CHARS));
    let last = (first + EXCERPT_CHARS).min(line_chars);
    let window: String = source_line.chars().skip(first).take(last - first).collect();
    let left = if first > 0 { "…" } else { "" };
    let right = if last < line_chars { "…" } else { "" };
    writeln!(out, "    {left}{window}{right}")?;
    let start = span.start.min(text.len());
    let span_chars = text
        .get(start..span.end.clamp(start, text.len()))
        .map_or(1, |s| s.split('\n').next().map_or(0, |l| l.chars().count()));
    let width = span_chars.min(last - (col - 1).min(last)).max(1);
    let pad = (col - 1 - first) + usize::from(first > 0);
    writeln!(out, "    {}{}", " ".repeat(pad), "^".repeat(width))
}

#[cfg(feature = "cli")]
pub use self::report::Report;

#[cfg(feature = "cli")]
mod report {
    //! The `miette` face of diagnostics (only with the `cli` feature).

    use super::{Diagnostic, Severity, SourceFile};
    use miette::{LabeledSpan, NamedSource, SourceCode};
    use std::fmt;

    impl miette::Diagnostic for Diagnostic {
        fn severity(&self) -> Option<miette::Severity> {
            Some(match self.severity {
                Severity::Error => miette::Severity::Error,
                Severity::Warning => miette::Severity::Warning,
            })
        }

        fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
            Some(Box::new(self.full_help()))
        }

        fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
            let main = LabeledSpan::new_primary_with_span(
                Some("here".into()),
                (self.span.start, self.span.len()),
            );
            let related = self.related.map(|(s, label)| {
                LabeledSpan::new_with_span(Some(label.into()), (s.start, s.len()))
            });
            Some(Box::new(std::iter::once(main).chain(related)))
        }
    }

    /// One file with all of its diagnostics, as a single `miette` report: rendering it shows
    /// `path:line:column`, the source with a caret under each span, and a help line, for every
    /// problem at once.
    #[derive(Debug)]
    pub struct Report {
        source: NamedSource<String>,
        name: String,
        diagnostics: Vec<Diagnostic>,
    }

    impl Report {
        /// Bundles `file` with its `diagnostics`. Spans beyond the end of the text are clamped so
        /// that rendering never fails.
        pub fn new(file: &SourceFile, diagnostics: &[Diagnostic]) -> Self {
            let len = file.text.len();
            let clamp = |s: crate::syntax::span::Span| {
                let mut start = s.start.min(len);
                while !file.text.is_char_boundary(start) {
                    start -= 1;
                }
                let mut end = s.end.min(len).max(start);
                while !file.text.is_char_boundary(end) {
                    end += 1;
                }
                crate::syntax::span::Span::new(start, end)
            };
            let diagnostics = diagnostics
                .iter()
                .map(|d| {
                    let mut d = d.clone();
                    d.span = clamp(d.span);
                    d.related = d.related.map(|(s, l)| (clamp(s), l));
                    d
                })
                .collect();
            Report {
                source: NamedSource::new(file.name.clone(), file.text.clone()),
                name: file.name.clone(),
                diagnostics,
            }
        }

        /// The bundled diagnostics.
        pub fn diagnostics(&self) -> &[Diagnostic] {
            &self.diagnostics
        }
    }

    impl fmt::Display for Report {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            let errors = self.diagnostics.iter().filter(|d| d.is_error()).count();
            let warnings = self.diagnostics.len() - errors;
            match (errors, warnings) {
                (0, w) if w > 0 => write!(f, "`{}`: {w} warning(s)", self.name),
                (e, 0) => write!(f, "`{}`: {e} error(s)", self.name),
                (e, w) => write!(f, "`{}`: {e} error(s), {w} warning(s)", self.name),
            }
        }
    }

    impl std::error::Error for Report {}

    impl miette::Diagnostic for Report {
        fn source_code(&self) -> Option<&dyn SourceCode> {
            Some(&self.source)
        }

        /// A file with warnings only is reported as a warning, not under an error's cross.
        fn severity(&self) -> Option<miette::Severity> {
            Some(if self.diagnostics.iter().any(Diagnostic::is_error) {
                miette::Severity::Error
            } else {
                miette::Severity::Warning
            })
        }

        fn related<'a>(
            &'a self,
        ) -> Option<Box<dyn Iterator<Item = &'a dyn miette::Diagnostic> + 'a>> {
            Some(Box::new(
                self.diagnostics
                    .iter()
                    .map(|d| d as &dyn miette::Diagnostic),
            ))
        }
    }
}
