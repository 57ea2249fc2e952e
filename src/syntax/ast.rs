//! The abstract syntax of lplace's two languages — rule files (`.lpl`) and map files (`.map`) —
//! exactly as written, with a [`Span`] on everything. This is the contract between the parsers
//! (which build it and are the only code that knows about pest) and the checker and compiler
//! (which read it). Nothing here is resolved or validated: names are still strings, numbers are
//! still whatever the author typed. The checker turns it into a map model and a checked rule
//! set; see `rules`.
//!
//! # Rule files in one page
//!
//! ```text
//! logic { tnorm = product; implication = residuum; normalisation = min;
//!         threshold = 0.6; margin = 0.05; }
//! domain Dir = {North, East, South, West};
//! similarity angle_match = trapezoid(core: 10, slope: 30, height: 1, bias: 0.05);
//! percept beacon_angle(value, expect, time) ~ angle_match;
//! percept sonar_wall(value, Dir, time);
//! predicate corner(Dir, Dir, time);
//!
//! |- ((beacon_angle(a, A_i, t) & beacon_distance(l, L_i, t))
//!        -> beacon_signature(<a, l>, <A_i, L_i>, t));
//! |- ((laser_corner(p5, d1, d2, t) & at_corner(p5, t)) -> corner(d1, d2, t), 0.9)
//!    for all (d1, d2) in {(North, East), (South, West)};
//! ```
//!
//! Every rule is a schema instantiated once per *hypothesis place* `i` of the map (the paper's
//! `P_i`): identifiers ending in `_i` name the hypothesis place (`P_i`), its room (`R_i`) or its
//! parameters (`A_i`, or keyed `range_i(Yellow)`), and the map relations `at_wall`/`at_corner`
//! consult that place. Identifiers that start with a lower-case letter are variables, `t` is the
//! current time, identifiers that start with an upper-case letter are constants (domain values,
//! place, room and landmark names).

use super::span::{Ident, Span, Spanned};

// ---------------------------------------------------------------------------------------------
// Rule files
// ---------------------------------------------------------------------------------------------

/// A whole rule file, items in source order.
#[derive(Debug, Clone, PartialEq)]
pub struct RuleFile {
    /// The declarations and rules, in the order written.
    pub items: Vec<RuleItem>,
}

/// One top-level item of a rule file.
#[derive(Debug, Clone, PartialEq)]
pub enum RuleItem {
    /// `logic { key = value; … }`
    Logic(LogicBlock),
    /// `tracker { key = value; … grid { key = value; … } }`
    Tracker(TrackerBlock),
    /// `domain Dir = {North, East, South, West};`
    Domain(DomainDecl),
    /// `similarity name = trapezoid(core: …, slope: …, height: …, bias: …);`
    Similarity(SimilarityDecl),
    /// `percept name(role, …) [~ similarity];`
    Percept(PerceptDecl),
    /// `predicate name(role, …);` — a derived predicate that rules may conclude.
    Predicate(PredicateDecl),
    /// `[schemas] |- sequent [schemas];`
    Rule(Rule),
    /// `region Name = {P1, P2};` or `region Name = kind doorway;`
    Region(RegionDecl),
    /// `group name { rules }`: rules whose place conclusions form one evidence group.
    Group(GroupBlock),
}

/// `region Name = {P1, P2};` or `region Name = kind doorway;` — a named set of places that
/// heads (`in_region(Name)`) and queries can speak about.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionDecl {
    /// Region name (upper-case initial).
    pub name: Ident,
    /// Its places.
    pub members: RegionMembers,
    /// The whole declaration.
    pub span: Span,
}

/// What a region is made of.
#[derive(Debug, Clone, PartialEq)]
pub enum RegionMembers {
    /// Places by name.
    Places(Vec<Ident>),
    /// Every place of a map kind (`corner`, `doorway`, …).
    Kind(Ident),
}

/// `group name { rules }`.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupBlock {
    /// The group's name.
    pub name: Ident,
    /// Its rules (each has `group` set to this name).
    pub rules: Vec<Rule>,
    /// The whole block.
    pub span: Span,
}

/// `logic { … }`: the file's choice of operators and decision parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct LogicBlock {
    /// The settings in source order (duplicates are a checker error, not a parse error).
    pub settings: Vec<Setting>,
    /// The whole block.
    pub span: Span,
}

/// `tracker { … }`: the tracker settings that go with this kind of sensor, used when no tracker
/// file is given. The keys are checked by `rules`, not by the grammar.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackerBlock {
    /// The settings outside `grid { … }`, in source order.
    pub settings: Vec<Setting>,
    /// Each `grid { … }` block (more than one is a checker error): its settings and span.
    pub grids: Vec<(Vec<Setting>, Span)>,
    /// The whole block.
    pub span: Span,
}

/// `key = value;` inside a `logic` or `tracker` block.
#[derive(Debug, Clone, PartialEq)]
pub struct Setting {
    /// The key (`tnorm`, `implication`, `normalisation`, `threshold`, `margin`).
    pub key: Ident,
    /// The value as written.
    pub value: Spanned<SettingValue>,
}

/// The right-hand side of a setting.
#[derive(Debug, Clone, PartialEq)]
pub enum SettingValue {
    /// A word such as `product`.
    Word(String),
    /// A number such as `0.6`.
    Number(f64),
}

/// `domain Name = {V1, V2, …};`
#[derive(Debug, Clone, PartialEq)]
pub struct DomainDecl {
    /// Domain name (upper-case initial).
    pub name: Ident,
    /// Its values in source order.
    pub values: Vec<Ident>,
    /// The whole declaration.
    pub span: Span,
}

/// `similarity name = trapezoid(core: c, slope: s, height: h, bias: b);`
///
/// The trapezoid ⟨θ, Δ, α, h, b⟩ of paper 000: its centre θ is the expected value supplied by the
/// place, `core` is Δ, `slope` is α, `height` h and `bias` b. Omitted fields take the defaults
/// documented on `logic::Similarity`.
#[derive(Debug, Clone, PartialEq)]
pub struct SimilarityDecl {
    /// Name by which percepts refer to it.
    pub name: Ident,
    /// The shape keyword (`trapezoid` today).
    pub shape: Ident,
    /// `field: number` pairs as written.
    pub fields: Vec<(Ident, Spanned<f64>)>,
    /// The whole declaration.
    pub span: Span,
}

/// The role of one argument position of a percept or predicate.
#[derive(Debug, Clone, PartialEq)]
pub enum ArgRole {
    /// `value`: the measured value; a variable written here is bound to the percept instance.
    Value,
    /// `expect`: the value the hypothesis place expects (`A_i`, `range_i(Yellow)`, a number);
    /// compared with the measured value through the percept's similarity.
    Expect,
    /// `time`: the time argument, always `t`.
    Time,
    /// A domain name: the argument is a value of that domain (constant or schema variable).
    Domain(String),
}

/// `percept name(roles…) [~ similarity];` — something the sensors report with a degree.
#[derive(Debug, Clone, PartialEq)]
pub struct PerceptDecl {
    /// Percept name.
    pub name: Ident,
    /// Argument roles, in order.
    pub roles: Vec<Spanned<ArgRole>>,
    /// The similarity comparing `value` with `expect`, when the percept has both.
    pub similarity: Option<Ident>,
    /// The whole declaration.
    pub span: Span,
}

/// `predicate name(roles…);` — a derived predicate concluded by rules.
#[derive(Debug, Clone, PartialEq)]
pub struct PredicateDecl {
    /// Predicate name.
    pub name: Ident,
    /// Argument roles, in order (only domain roles ground the atom; the others document it).
    pub roles: Vec<Spanned<ArgRole>>,
    /// The whole declaration.
    pub span: Span,
}

/// `for all (v1, v2) in {(A, B), …}` or `for all v in Domain` or `for all v in {A, B}`.
#[derive(Debug, Clone, PartialEq)]
pub struct Schema {
    /// The bound variables.
    pub vars: Vec<Ident>,
    /// What they range over.
    pub source: SchemaSource,
    /// The whole `for all …` clause.
    pub span: Span,
}

/// The range of a schema.
#[derive(Debug, Clone, PartialEq)]
pub enum SchemaSource {
    /// A declared domain, by name (only with one variable).
    Domain(Ident),
    /// An explicit list of tuples; each tuple has as many constants as there are variables.
    Tuples(Vec<Spanned<Vec<Ident>>>),
}

/// `|- body -> head` or `|- (body -> head, w)`, with its schemas.
#[derive(Debug, Clone, PartialEq)]
pub struct Rule {
    /// `for all` clauses, prefix ones first then suffix ones, in source order.
    pub schemas: Vec<Schema>,
    /// The antecedent.
    pub body: Spanned<Formula>,
    /// The conclusion (possibly negated: `!at_place(P_i)`).
    pub head: Literal,
    /// The necessity weight `w` of `(body -> head, w)`; `None` means 1.
    pub weight: Option<Spanned<f64>>,
    /// The evidence group the rule is written in (`group name { … }`), if any.
    pub group: Option<Ident>,
    /// The whole rule.
    pub span: Span,
}

/// An atom, possibly negated.
#[derive(Debug, Clone, PartialEq)]
pub struct Literal {
    /// True for `!atom`.
    pub negated: bool,
    /// The atom.
    pub atom: Atom,
    /// The whole literal.
    pub span: Span,
}

/// A formula of the rule language.
///
/// Precedence, tightest first: `!`, `*`, `&`, `(+)`, `->` (right-associative). Parentheses
/// group; `(φ, w)` attaches a degree.
#[derive(Debug, Clone, PartialEq)]
pub enum Formula {
    /// `name(args…)`
    Atom(Atom),
    /// A literal degree such as `0.3`.
    Degree(f64),
    /// `!φ`
    Not(Box<Spanned<Formula>>),
    /// `φ & ψ & …` — lattice conjunction (min).
    And(Vec<Spanned<Formula>>),
    /// `φ * ψ * …` — the file's t-norm.
    Times(Vec<Spanned<Formula>>),
    /// `φ (+) ψ (+) …` — lattice disjunction (max).
    Or(Vec<Spanned<Formula>>),
    /// `φ -> ψ` nested inside a body — the file's implication function.
    Implies(Box<Spanned<Formula>>, Box<Spanned<Formula>>),
    /// `(φ, w)` — a weighted formula.
    Weighted(Box<Spanned<Formula>>, Spanned<f64>),
}

/// `name(term, …)`; a nullary atom may be written `name` or `name()`.
#[derive(Debug, Clone, PartialEq)]
pub struct Atom {
    /// Predicate, percept or map-relation name.
    pub name: Ident,
    /// Arguments in order.
    pub args: Vec<Spanned<Term>>,
    /// The whole atom.
    pub span: Span,
}

/// An argument of an atom.
#[derive(Debug, Clone, PartialEq)]
pub enum Term {
    /// Lower-case identifier other than `t`: a variable.
    Var(String),
    /// Upper-case identifier: a constant (domain value, place, room or landmark).
    Const(String),
    /// `X_i` or `x_i(Key)`: the hypothesis place itself (`P_i`), its room (`R_i`) or one of its
    /// parameters, optionally keyed by a constant.
    PlaceRef {
        /// The name before `_i` (`P`, `R`, `A`, `range`…).
        name: String,
        /// The key in `range_i(Yellow)`.
        key: Option<String>,
    },
    /// `t`: the current time.
    Time,
    /// A number.
    Number(f64),
    /// `<a, l>`
    Tuple(Vec<Spanned<Term>>),
}

// ---------------------------------------------------------------------------------------------
// Map files
// ---------------------------------------------------------------------------------------------

/// A whole map file.
///
/// ```text
/// map office;
/// axis 4.75;                          // the building's walls run at 4.75° (mod 90°)
/// kinds {corner, corridor, doorway};  // the place kinds rules may test
/// room R0 "west room";
/// beacon B0 at (4.0, 3.0) id 1;
/// landmark Yellow at (0.0, 6.0) id 3;
/// place P0 corner in R0 at (0.5, 0.5) extent radius 0.6 {
///     wall South; wall West 0.9; corner South West;
///     param A = 215; param L = 4.6; param range(Yellow) = 2.5;
/// }
/// place C1 corridor at (3, 0) extent box (1, -1, 5, 1) rotated 4.75 { open East; open West; }
/// place D1 doorway at (3, 2) extent polygon ((2.5, 1.5), (3.5, 1.5), (3.5, 2.5), (2.5, 2.5), (2.5, 1.5)) {
///     wall East; wall West; door North; door South;
/// }
/// path P0 -- P1 length 4.0 heading 0;
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MapFile {
    /// `map name;` if present.
    pub name: Option<Ident>,
    /// Items in source order.
    pub items: Vec<MapItem>,
}

/// One top-level item of a map file.
#[derive(Debug, Clone, PartialEq)]
pub enum MapItem {
    /// `room R0 ["label"];`
    Room(RoomDecl),
    /// `beacon B0 at (x, y) [id n];` or `landmark L at (x, y) [id n];`
    Landmark(LandmarkDecl),
    /// `place P kind [in R] at (x, y [, θ]) [extent …] { features }`
    Place(PlaceDecl),
    /// `path A -- B [length l] [heading h];`
    Path(PathDecl),
    /// `axis D;`: the building's walls run at `D` degrees (mod 90°) in the map frame.
    Axis(AxisDecl),
    /// `kinds {corner, doorway, …};`: the place kinds this map may use.
    Kinds(KindsDecl),
    /// `start (x, y);`: where the runs evaluated with this map begin, in the map frame.
    Start(StartDecl),
}

/// `start (x, y);` — where the runs evaluated with this map begin (map frame, metres): the
/// metric tracker starts from there instead of from total ignorance.
#[derive(Debug, Clone, PartialEq)]
pub struct StartDecl {
    /// The point as written.
    pub position: Spanned<(f64, f64)>,
    /// The whole statement.
    pub span: Span,
}

/// `axis D;` — the direction (degrees, counter-clockwise from +x) the building's walls run in,
/// modulo 90°: what a heading that locks onto walls locks to.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisDecl {
    /// The angle as written.
    pub degrees: Spanned<f64>,
    /// The whole statement.
    pub span: Span,
}

/// `kinds {corner, doorway, …};` — the domain of place kinds.
#[derive(Debug, Clone, PartialEq)]
pub struct KindsDecl {
    /// The kinds in source order.
    pub kinds: Vec<Ident>,
    /// The whole statement.
    pub span: Span,
}

/// `room R0 ["label"];`
#[derive(Debug, Clone, PartialEq)]
pub struct RoomDecl {
    /// Room name.
    pub name: Ident,
    /// Free-text label.
    pub label: Option<Spanned<String>>,
    /// The whole declaration.
    pub span: Span,
}

/// Whether a landmark was declared with `beacon` or `landmark`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LandmarkKind {
    /// A structured beacon (paper 003).
    Beacon,
    /// Any other identifiable landmark.
    Landmark,
}

/// `beacon B0 at (x, y) [id n];`
#[derive(Debug, Clone, PartialEq)]
pub struct LandmarkDecl {
    /// Keyword used.
    pub kind: LandmarkKind,
    /// Name.
    pub name: Ident,
    /// Position in metres.
    pub position: Spanned<(f64, f64)>,
    /// Sensor-side identifier.
    pub id: Option<Spanned<i64>>,
    /// The whole declaration.
    pub span: Span,
}

/// `place P0 corner in R0 at (x, y[, θ]) [extent radius r | extent box (x0, y0, x1, y1)] { … }`
#[derive(Debug, Clone, PartialEq)]
pub struct PlaceDecl {
    /// Place name.
    pub name: Ident,
    /// Kind word (`corner`, `doorway`, `corridor`, `junction`, `room_centre`, …).
    pub kind: Ident,
    /// Room it belongs to.
    pub room: Option<Ident>,
    /// Approximate pose: x, y in metres and optional heading in degrees.
    pub pose: Spanned<(f64, f64, Option<f64>)>,
    /// The region of the metric frame the place covers.
    pub extent: Option<Spanned<Extent>>,
    /// Expected percepts and parameters.
    pub features: Vec<Feature>,
    /// The whole declaration.
    pub span: Span,
}

/// A place's extent.
#[derive(Debug, Clone, PartialEq)]
pub enum Extent {
    /// A disc of this radius around the pose.
    Radius(f64),
    /// An axis-aligned box `(x0, y0, x1, y1)`.
    Box(f64, f64, f64, f64),
    /// `box (x0, y0, x1, y1) rotated D`: that box turned by `D` degrees counter-clockwise
    /// about its centre.
    RotatedBox {
        /// The box before turning, `(x0, y0, x1, y1)`.
        corners: (f64, f64, f64, f64),
        /// The turn in degrees, with its span.
        degrees: Spanned<f64>,
    },
    /// `polygon ((x, y), …, (x, y))`: vertices in order, the last one repeating the first.
    Polygon(Vec<Spanned<(f64, f64)>>),
}

/// One line inside a place's braces.
#[derive(Debug, Clone, PartialEq)]
pub enum Feature {
    /// `wall North [degree];`
    Wall {
        /// Direction (a value of the rules' `Dir` domain).
        dir: Ident,
        /// Certainty the wall is there and visible; 1 when omitted.
        degree: Option<Spanned<f64>>,
        /// The whole feature.
        span: Span,
    },
    /// `open North [degree];` — nothing blocks the view that way (a corridor going on).
    Open {
        /// Direction.
        dir: Ident,
        /// Certainty; 1 when omitted.
        degree: Option<Spanned<f64>>,
        /// The whole feature.
        span: Span,
    },
    /// `door North [degree];` — a wall with an opening in it (a doorway or a door left open).
    Door {
        /// Direction.
        dir: Ident,
        /// Certainty; 1 when omitted.
        degree: Option<Spanned<f64>>,
        /// The whole feature.
        span: Span,
    },
    /// `corner North East [degree];`
    Corner {
        /// First direction.
        d1: Ident,
        /// Second direction.
        d2: Ident,
        /// Certainty; 1 when omitted.
        degree: Option<Spanned<f64>>,
        /// The whole feature.
        span: Span,
    },
    /// `param A = 215;`, `param range(Yellow) = 2.5;`, or a range of equally expected values,
    /// `param free(North) = 0.4 .. 1.9;`
    Param {
        /// Parameter name.
        name: Ident,
        /// Key constant for keyed parameters.
        key: Option<Ident>,
        /// Value (the lower end of a range).
        value: Spanned<f64>,
        /// The upper end of a range, if one is written.
        upper: Option<Spanned<f64>>,
        /// The whole feature.
        span: Span,
    },
}

/// `path A -- B [length l] [heading h];` — an undirected edge of the topological graph.
#[derive(Debug, Clone, PartialEq)]
pub struct PathDecl {
    /// One end.
    pub from: Ident,
    /// The other end.
    pub to: Ident,
    /// Approximate length in metres; the Euclidean distance of the poses when omitted.
    pub length: Option<Spanned<f64>>,
    /// Heading in degrees from `from` to `to`.
    pub heading: Option<Spanned<f64>>,
    /// The whole declaration.
    pub span: Span,
}
