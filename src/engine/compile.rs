//! The compiler: a checked rule set and a map become one [`Tape`] whose output registers are the
//! degree functions of every `at_place(P_i)`, `!at_place(P_i)`, `in_room(R)` and asked-for
//! derived predicate — built once, evaluated per frame.
//!
//! Compilation grounds each rule completely:
//! 1. **schemas** (`for all (d1, d2) in {…}`) are expanded into one ground rule per binding;
//! 2. every ground rule is instantiated once per **hypothesis place** `i` of the map (the paper's
//!    `P_i`): `A_i` becomes place `i`'s parameter, `at_wall(p, t)` place `i`'s wall in the
//!    direction of the percept bound to `p`, a derived atom in a body the value derived in
//!    context `i`;
//! 3. derived predicates are compiled in dependency order (a recursive definition is an error),
//!    and several derivations of one ground atom are combined by `max`;
//! 4. each place's support is the `max` over contexts of its `at_place` derivations, and likewise
//!    each set head's degree (`in_room(R)`, `in_region(G)`, negated or not), which
//!    `Engine::step` applies as a weighted disjunction of the set's places;
//! 5. with `group` blocks, place and set heads are also accumulated per evidence group, so that
//!    each group has its own distribution to fuse.
//!
//! Map facts are constants, so most of a ground rule folds away at compile time; identical
//! sub-expressions are shared (hash-consing). A rule whose every instance folds to the constant 0
//! can never fire on this map, and is reported as a warning rather than silently kept: the rule
//! file's own checks already passed, so what it tests (walls, corners, parameters) is missing
//! from the map's places — a map without corners is a map, not an error of the rules.

use super::frame::{PerceptSlot, PerceptTable};
use super::tape::{Op, Reg, Tape};
use crate::logic::{LogicConfig, PlaceSet};
use crate::map::{Expected, Map};
use crate::rules::is_place_head;
use crate::rules::{RuleSet, Signature};
use crate::syntax::ast::{ArgRole, Atom, Formula, Rule, SchemaSource, Term};
use crate::syntax::diagnostic::{Diagnostic, DiagnosticKind, NeverFiresReason};
use crate::syntax::span::Spanned;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};

/// What to compile besides the place and room degrees.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CompileOptions {
    /// Derived predicates whose ground atoms become outputs too (by name).
    pub derived: Vec<String>,
    /// Keep one register per rule instance so that a trace can say which rules fired.
    pub trace: bool,
}

/// A ground atom: predicate name and its domain arguments.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct GroundAtom {
    /// Predicate name.
    pub name: String,
    /// Domain arguments.
    pub args: Vec<String>,
}

impl std::fmt::Display for GroundAtom {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}({})", self.name, self.args.join(", "))
    }
}

/// One instance of one rule: which rule, under which schema binding, in which place context,
/// concluding what, and the register holding its detached degree.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Contribution {
    /// Index of the rule in the rule set.
    pub rule: usize,
    /// Schema variables and their values.
    pub binding: Vec<(String, String)>,
    /// Hypothesis place index.
    pub context: usize,
    /// The conclusion.
    pub head: GroundAtom,
    /// True for a negated conclusion.
    pub negated: bool,
    /// Register of the head degree this instance yields.
    pub reg: Reg,
}

/// The compiled rule set.
#[derive(Debug, Clone, PartialEq)]
pub struct Compiled {
    /// The instruction tape.
    pub tape: Tape,
    /// The percept instances the tape reads.
    pub percepts: PerceptTable,
    /// Register of `α_k`, support for `at_place(P_k)`, per place.
    pub support: Vec<Reg>,
    /// Register of `β_k`, support for `!at_place(P_k)`, per place.
    pub exclusion: Vec<Reg>,
    /// Register of the support for `in_room(R)`, per room.
    pub rooms: Vec<Reg>,
    /// Register of the support for `in_region(G)`, per declared region.
    pub regions: Vec<Reg>,
    /// Asked-for derived atoms and their registers (max over place contexts).
    pub derived: Vec<(GroundAtom, Reg)>,
    /// Asked-for derived atoms per place context: `(atom, context, register)`.
    pub derived_in_context: Vec<(GroundAtom, usize, Reg)>,
    /// Weighted heads over sets of places that some rule concludes.
    pub set_heads: Vec<SetHead>,
    /// Number of evidence groups (1 + the declared `group`s).
    pub groups: usize,
    /// With declared groups: per group, the register of each place's support in that group
    /// (empty without groups).
    pub group_support: Vec<Vec<Reg>>,
    /// With declared groups: per group, each place's exclusion in that group.
    pub group_exclusion: Vec<Vec<Reg>>,
    /// Rule instances (only with `CompileOptions::trace`).
    pub contributions: Vec<Contribution>,
    /// Warnings about the rules on this map: rules that never fire on it
    /// ([`NeverFiresReason::NotOnThisMap`]), in rule order.
    pub warnings: Vec<Diagnostic>,
    /// Every register read from outside the tape — the registers above and the trace's — in
    /// no particular order: what an evaluator that skips registers must leave exact.
    pub observed: Vec<Reg>,
}

/// Builds the tape: folds constants and shares identical instructions.
struct Builder {
    ops: Vec<Op>,
    dedup: HashMap<(u8, u64, u64, u64), Reg>,
    logic: LogicConfig,
}

impl Builder {
    fn konst(&self, r: Reg) -> Option<f64> {
        match self.ops[r as usize] {
            Op::Const(c) => Some(c),
            _ => None,
        }
    }

    fn c(&mut self, x: f64) -> Reg {
        self.push(Op::Const(x))
    }

    /// Appends `op` (after folding), or returns the register of an identical earlier one.
    fn mk(&mut self, op: Op) -> Reg {
        let l = &self.logic;
        match op {
            // Idempotence (not for `*`: `a·a ≠ a`).
            Op::Min(a, b) | Op::Max(a, b) if a == b => a,
            Op::Min(a, b) => match (self.konst(a), self.konst(b)) {
                (Some(x), Some(y)) => self.c(x.min(y)),
                (Some(x), None) | (None, Some(x)) if x <= 0.0 => self.c(0.0),
                (Some(x), None) if x >= 1.0 => b,
                (None, Some(y)) if y >= 1.0 => a,
                _ => self.push(Op::Min(a, b)),
            },
            Op::Max(a, b) => match (self.konst(a), self.konst(b)) {
                (Some(x), Some(y)) => self.c(x.max(y)),
                (Some(x), None) | (None, Some(x)) if x >= 1.0 => self.c(1.0),
                (Some(x), None) if x <= 0.0 => b,
                (None, Some(y)) if y <= 0.0 => a,
                _ => self.push(Op::Max(a, b)),
            },
            Op::TNorm(a, b) => match (self.konst(a), self.konst(b)) {
                (Some(x), Some(y)) => self.c(l.tnorm.apply(x, y)),
                (Some(x), None) | (None, Some(x)) if x <= 0.0 => self.c(0.0),
                (Some(x), None) if x >= 1.0 => b,
                (None, Some(y)) if y >= 1.0 => a,
                _ => self.push(Op::TNorm(a, b)),
            },
            Op::Not(a) => match self.konst(a) {
                Some(x) => self.c(1.0 - x),
                None => self.push(op),
            },
            Op::Implies(a, b) => match (self.konst(a), self.konst(b)) {
                (Some(x), Some(y)) => self.c(l.implies(x, y)),
                // R(0, b) = 1 and R(a, 1) = 1 for every implication offered; R(1, b) = b.
                (Some(x), None) if x <= 0.0 => self.c(1.0),
                (None, Some(y)) if y >= 1.0 => self.c(1.0),
                (Some(x), None) if x >= 1.0 => b,
                _ => self.push(op),
            },
            Op::Detach(a, w) => match self.konst(a) {
                Some(x) => self.c(l.detach(x, w)),
                // T(x, 1) = min(x, 1) = x; T(x, 0) = min(x, 0) = 0.
                None if w >= 1.0 => a,
                None if w <= 0.0 => self.c(0.0),
                None => self.push(op),
            },
            other => self.push(other),
        }
    }

    fn push(&mut self, op: Op) -> Reg {
        let key = match op {
            Op::Const(c) => (0, c.to_bits(), 0, 0),
            Op::Degree(s) => (1, s.0 as u64, 0, 0),
            Op::Match {
                slot,
                similarity,
                centre,
                half,
            } => (
                2,
                (u64::from(slot.0) << 32) | u64::from(similarity),
                centre.to_bits(),
                half.to_bits(),
            ),
            // Commutative: `min(a, b)` and `min(b, a)` share one register, which keeps the
            // operand order of whichever was written first (what `explain` prints).
            Op::Min(a, b) => (3, a.min(b) as u64, a.max(b) as u64, 0),
            Op::Max(a, b) => (4, a.min(b) as u64, a.max(b) as u64, 0),
            Op::TNorm(a, b) => (5, a.min(b) as u64, a.max(b) as u64, 0),
            Op::Not(a) => (6, a as u64, 0, 0),
            Op::Implies(a, b) => (7, a as u64, b as u64, 0),
            Op::Detach(a, w) => (8, a as u64, w.to_bits(), 0),
        };
        if let Some(&r) = self.dedup.get(&key) {
            return r;
        }
        let r = self.ops.len() as Reg;
        self.ops.push(op);
        self.dedup.insert(key, r);
        r
    }

    fn fold(&mut self, parts: &[Reg], f: fn(Reg, Reg) -> Op, empty: f64) -> Reg {
        match parts.split_first() {
            None => self.c(empty),
            Some((&first, rest)) => rest.iter().fold(first, |acc, &p| self.mk(f(acc, p))),
        }
    }
}

/// Every binding of a rule's schema variables (one empty binding when it has none).
pub(crate) fn schema_bindings(rule: &Rule, rules: &RuleSet) -> Vec<Vec<(String, String)>> {
    let mut out = vec![Vec::new()];
    for schema in &rule.schemas {
        let tuples: Vec<Vec<String>> = match &schema.source {
            SchemaSource::Domain(d) => rules
                .domains
                .get(&d.node)
                .map(|vals| vals.iter().map(|v| vec![v.clone()]).collect())
                .unwrap_or_default(),
            SchemaSource::Tuples(ts) => ts
                .iter()
                .map(|t| t.node.iter().map(|c| c.node.clone()).collect())
                .collect(),
        };
        let mut next = Vec::with_capacity(out.len() * tuples.len());
        for b in &out {
            for t in &tuples {
                let mut nb = b.clone();
                nb.extend(
                    schema
                        .vars
                        .iter()
                        .map(|v| v.node.clone())
                        .zip(t.iter().cloned()),
                );
                next.push(nb);
            }
        }
        out = next;
    }
    out
}

/// Resolution of names inside one ground rule in one context.
pub(crate) struct Scope<'a> {
    pub rules: &'a RuleSet,
    pub map: &'a Map,
    pub percepts: &'a PerceptTable,
    pub binding: &'a [(String, String)],
    /// Value variables → the percept slot that binds them.
    pub values: BTreeMap<String, PerceptSlot>,
    pub context: usize,
}

impl<'a> Scope<'a> {
    pub fn new(
        rules: &'a RuleSet,
        map: &'a Map,
        percepts: &'a PerceptTable,
        binding: &'a [(String, String)],
        body: &Formula,
        context: usize,
    ) -> Self {
        let mut s = Scope {
            rules,
            map,
            percepts,
            binding,
            values: BTreeMap::new(),
            context,
        };
        s.bind_values(body);
        s
    }

    /// A constant for a term in a domain position: the constant itself, or the value bound to
    /// a schema variable.
    pub fn constant(&self, term: &Term) -> Option<String> {
        match term {
            Term::Const(c) => Some(c.clone()),
            Term::Var(v) => self
                .binding
                .iter()
                .find(|(name, _)| name == v)
                .map(|(_, val)| val.clone()),
            Term::PlaceRef { name, key: None } if name == "P" => {
                self.map.places().get(self.context).map(|p| p.name.clone())
            }
            Term::PlaceRef { name, key: None } if name == "R" => self
                .map
                .places()
                .get(self.context)
                .and_then(|p| p.room)
                .and_then(|r| self.map.rooms().get(r))
                .map(|r| r.name.clone()),
            _ => None,
        }
    }

    /// The percept slot of a percept atom, from its domain-role arguments.
    pub fn slot(&self, atom: &Atom, sig: &Signature) -> Option<PerceptSlot> {
        let mut args = Vec::new();
        for (role, term) in sig.roles.iter().zip(&atom.args) {
            if let ArgRole::Domain(_) = role {
                args.push(self.constant(&term.node)?);
            }
        }
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        self.percepts.slot(&atom.name.node, &refs)
    }

    fn bind_values(&mut self, f: &Formula) {
        match f {
            Formula::Atom(atom) => {
                if let Some(sig) = self.rules.percepts.get(&atom.name.node) {
                    if let Some(slot) = self.slot(atom, sig) {
                        for (role, term) in sig.roles.iter().zip(&atom.args) {
                            if let (ArgRole::Value, Term::Var(v)) = (role, &term.node) {
                                self.values.entry(v.clone()).or_insert(slot);
                            }
                        }
                    }
                }
            }
            Formula::Degree(_) => {}
            Formula::Not(a) | Formula::Weighted(a, _) => self.bind_values(&a.node),
            Formula::And(v) | Formula::Times(v) | Formula::Or(v) => {
                v.iter().for_each(|x| self.bind_values(&x.node))
            }
            Formula::Implies(a, b) => {
                self.bind_values(&a.node);
                self.bind_values(&b.node);
            }
        }
    }

    /// The expected value θ of an `expect` argument in this context.
    pub fn expectation(&self, term: &Term) -> Option<Expected> {
        match term {
            Term::Number(x) => Some(Expected::value(*x)),
            Term::PlaceRef { name, key } => {
                let key = match key {
                    None => None,
                    Some(k) => Some(self.constant(&key_term(k))?),
                };
                self.map.expected(self.context, name, key.as_deref())
            }
            _ => None,
        }
    }

    /// The value of a map relation (`at_wall(v, t)`, `at_corner(v, t)`, `at_open(v, t)`,
    /// `at_door(v, t)`) in this context.
    pub fn map_relation(&self, atom: &Atom) -> Option<f64> {
        let Some(Term::Var(v)) = atom.args.first().map(|t| &t.node) else {
            return Some(0.0);
        };
        let slot = *self.values.get(v)?;
        let inst = self.percepts.instance(slot)?;
        let sig = self.rules.percepts.get(&inst.name)?;
        // The instance's arguments of domain `Dir`, in order.
        let mut dirs = sig
            .roles
            .iter()
            .filter(|r| matches!(r, ArgRole::Domain(_)))
            .zip(&inst.args)
            .filter(|(r, _)| matches!(r, ArgRole::Domain(d) if d == "Dir"))
            .map(|(_, a)| a.as_str());
        match atom.name.node.as_str() {
            "at_wall" => Some(dirs.next().map_or(0.0, |d| self.map.wall(self.context, d))),
            "at_open" => Some(dirs.next().map_or(0.0, |d| self.map.open(self.context, d))),
            "at_door" => Some(dirs.next().map_or(0.0, |d| self.map.door(self.context, d))),
            "at_corner" => match (dirs.next(), dirs.next()) {
                (Some(d1), Some(d2)) => Some(self.map.corner(self.context, d1, d2)),
                _ => Some(0.0),
            },
            _ => None,
        }
    }

    /// The ground atom a derived-predicate atom denotes here; `None` when it names nothing in
    /// this context (`in_room(R_i)` at a place outside every room).
    pub fn ground(&self, atom: &Atom) -> Option<GroundAtom> {
        let name = &atom.name.node;
        let args = match name.as_str() {
            "at_place" | "in_room" | "in_region" => vec![self.constant(&atom.args.first()?.node)?],
            _ => {
                let sig = self.rules.predicates.get(name)?;
                let mut args = Vec::new();
                for (role, term) in sig.roles.iter().zip(&atom.args) {
                    if let ArgRole::Domain(_) = role {
                        args.push(self.constant(&term.node)?);
                    }
                }
                args
            }
        };
        Some(GroundAtom {
            name: name.clone(),
            args,
        })
    }
}

/// A key written as a name: lower-case initial is a variable, otherwise a constant.
pub(crate) fn key_term(k: &str) -> Term {
    if k.starts_with(|c: char| c.is_ascii_lowercase()) {
        Term::Var(k.to_string())
    } else {
        Term::Const(k.to_string())
    }
}

/// True for names the engine treats as map relations.
pub(crate) fn is_map_relation(name: &str) -> bool {
    matches!(name, "at_wall" | "at_corner" | "at_open" | "at_door")
}

/// Orders derived predicates so that each comes after those its rules' bodies use.
///
/// # Complexity
/// `O(P + E)` for `P` predicates and `E` body references (Kahn's algorithm); ties broken by name,
/// so the order is deterministic.
pub(crate) fn predicate_order(rules: &RuleSet) -> Result<Vec<String>, Vec<Diagnostic>> {
    let mut preds: BTreeMap<String, Vec<String>> = BTreeMap::new(); // pred -> preds it depends on
    for p in rules
        .predicates
        .keys()
        .map(String::as_str)
        .chain(["at_place", "in_room", "in_region"])
    {
        preds.entry(p.to_string()).or_default();
    }
    for rule in &rules.rules {
        let mut used = Vec::new();
        derived_atoms(&rule.body.node, rules, &mut used);
        let deps = preds.entry(rule.head.atom.name.node.clone()).or_default();
        deps.extend(used.into_iter().map(|a| a.name.node.clone()));
    }
    let mut order = Vec::new();
    let mut done: BTreeMap<&str, bool> = preds.keys().map(|k| (k.as_str(), false)).collect();
    loop {
        let ready: Vec<&String> = preds
            .iter()
            .filter(|(p, deps)| {
                // A predicate that uses itself never becomes ready: that is how cycles show.
                !done[p.as_str()]
                    && deps
                        .iter()
                        .all(|d| done.get(d.as_str()).copied().unwrap_or(true))
            })
            .map(|(p, _)| p)
            .collect();
        if ready.is_empty() {
            break;
        }
        for p in ready {
            done.insert(p.as_str(), true);
            order.push(p.clone());
        }
    }
    if order.len() == preds.len() {
        return Ok(order);
    }
    // Whatever is left sits on a cycle (or depends on one): report each rule concluding it.
    let diags = rules
        .rules
        .iter()
        .filter(|r| {
            !done
                .get(r.head.atom.name.node.as_str())
                .copied()
                .unwrap_or(true)
        })
        .map(|r| {
            Diagnostic::error(
                DiagnosticKind::RecursivePredicate {
                    name: r.head.atom.name.node.clone(),
                },
                r.head.atom.name.span,
            )
        })
        .collect();
    Err(diags)
}

/// The atoms of `f` that refer to derived predicates.
pub(crate) fn derived_atoms<'f>(f: &'f Formula, rules: &RuleSet, out: &mut Vec<&'f Atom>) {
    match f {
        Formula::Atom(a) => {
            let n = a.name.node.as_str();
            if is_place_head(n) || rules.predicates.contains_key(n) {
                out.push(a);
            }
        }
        Formula::Degree(_) => {}
        Formula::Not(a) | Formula::Weighted(a, _) => derived_atoms(&a.node, rules, out),
        Formula::And(v) | Formula::Times(v) | Formula::Or(v) => {
            v.iter().for_each(|x| derived_atoms(&x.node, rules, out))
        }
        Formula::Implies(a, b) => {
            derived_atoms(&a.node, rules, out);
            derived_atoms(&b.node, rules, out);
        }
    }
}

/// Accumulated derivations: (ground atom, negated, context) → register of their `max`.
type Acc = BTreeMap<(GroundAtom, bool, usize), Reg>;

/// The same per evidence group, for place heads only: (group, atom, negated, context).
type GroupAcc = BTreeMap<(usize, GroundAtom, bool, usize), Reg>;

/// A weighted head over a set of places (`in_room(R)`, `in_region(G)`, negated or not), with the
/// register of its degree: `(S, α)` caps every place outside `S` at `1 − α`, `(¬S, β)` every
/// place inside it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SetHead {
    /// The head atom (`in_room(R0)`, `in_region(EastWing)`).
    pub atom: GroundAtom,
    /// Its places.
    pub members: PlaceSet,
    /// True for `!in_room(…)` / `!in_region(…)`.
    pub negated: bool,
    /// Its evidence group (0: outside every `group` block).
    pub group: usize,
    /// Register of its degree (max over derivations and contexts).
    pub reg: Reg,
}

/// Everything the derivation pass produces.
struct Derivations {
    acc: Acc,
    grouped: GroupAcc,
    contributions: Vec<Contribution>,
    fires: Vec<bool>,
}

/// The output registers, before pruning renumbers them.
struct Outputs {
    support: Vec<Reg>,
    exclusion: Vec<Reg>,
    rooms: Vec<Reg>,
    regions: Vec<Reg>,
    derived: Vec<(GroundAtom, Reg)>,
    derived_in_context: Vec<(GroundAtom, usize, Reg)>,
    set_heads: Vec<SetHead>,
    group_support: Vec<Vec<Reg>>,
    group_exclusion: Vec<Vec<Reg>>,
}

impl Outputs {
    /// Every register the outputs name: the one list of them, for marking, renumbering and
    /// [`Compiled::observed`] alike.
    fn regs_mut(&mut self) -> impl Iterator<Item = &mut Reg> {
        self.support
            .iter_mut()
            .chain(&mut self.exclusion)
            .chain(&mut self.rooms)
            .chain(&mut self.regions)
            .chain(self.derived.iter_mut().map(|(_, r)| r))
            .chain(self.derived_in_context.iter_mut().map(|(_, _, r)| r))
            .chain(self.set_heads.iter_mut().map(|h| &mut h.reg))
            .chain(self.group_support.iter_mut().flatten())
            .chain(self.group_exclusion.iter_mut().flatten())
    }
}

/// Compiles `rules` over `map`. Errors are the diagnostics of recursive predicate definitions;
/// rules that never fire on this map are warnings in [`Compiled::warnings`].
pub fn compile(
    rules: &RuleSet,
    map: &Map,
    opts: &CompileOptions,
) -> Result<Compiled, Vec<Diagnostic>> {
    let percepts = PerceptTable::new(rules);
    let mut b = Builder {
        ops: Vec::new(),
        dedup: HashMap::new(),
        logic: rules.logic,
    };
    let order = predicate_order(rules)?;
    let d = derive(&mut b, rules, map, &percepts, &order, opts);
    let warnings = never_fires(rules, &d.fires);
    let out = outputs(&mut b, rules, map, &d, opts);
    let mut compiled = prune(b, out, d.contributions, rules, percepts);
    compiled.warnings = warnings;
    Ok(compiled)
}

/// Grounds every rule in every context, in dependency order.
fn derive(
    b: &mut Builder,
    rules: &RuleSet,
    map: &Map,
    percepts: &PerceptTable,
    order: &[String],
    opts: &CompileOptions,
) -> Derivations {
    let mut d = Derivations {
        acc: BTreeMap::new(),
        grouped: BTreeMap::new(),
        contributions: Vec::new(),
        fires: vec![false; rules.rules.len()],
    };
    let grouped = !rules.groups.is_empty();
    for pred in order {
        for (ri, rule) in rules.rules.iter().enumerate() {
            if &rule.head.atom.name.node != pred {
                continue;
            }
            let w = rule.weight.as_ref().map_or(1.0, |w| w.node);
            let group = rules.group_of(rule);
            for binding in schema_bindings(rule, rules) {
                for ctx in 0..map.places().len() {
                    let scope = Scope::new(rules, map, percepts, &binding, &rule.body.node, ctx);
                    let Some(head) = scope.ground(&rule.head.atom) else {
                        continue;
                    };
                    let body = formula(b, &scope, &rule.body, &d.acc);
                    let reg = b.mk(Op::Detach(body, w));
                    if b.konst(reg) != Some(0.0) {
                        d.fires[ri] = true;
                    }
                    let neg = rule.head.negated;
                    merge(b, &mut d.acc, (head.clone(), neg, ctx), reg);
                    if grouped && is_place_head(pred) {
                        merge(b, &mut d.grouped, (group, head.clone(), neg, ctx), reg);
                    }
                    if opts.trace {
                        d.contributions.push(Contribution {
                            rule: ri,
                            binding: binding.clone(),
                            context: ctx,
                            head,
                            negated: neg,
                            reg,
                        });
                    }
                }
            }
        }
    }
    d
}

/// Several derivations of one key combine by `max`.
fn merge<K: Ord>(b: &mut Builder, acc: &mut BTreeMap<K, Reg>, key: K, reg: Reg) {
    let merged = match acc.get(&key) {
        Some(&prev) => b.mk(Op::Max(prev, reg)),
        None => reg,
    };
    acc.insert(key, merged);
}

/// The compiler's own never-fires check: every instance of the rule folded to 0 on this map.
fn never_fires(rules: &RuleSet, fires: &[bool]) -> Vec<Diagnostic> {
    rules
        .rules
        .iter()
        .zip(fires)
        .filter(|(_, f)| !**f)
        .map(|(r, _)| {
            Diagnostic::warning(
                DiagnosticKind::RuleNeverFires {
                    reason: NeverFiresReason::NotOnThisMap,
                },
                r.span,
            )
        })
        .collect()
}

fn unary(name: &str, arg: &str) -> GroundAtom {
    GroundAtom {
        name: name.into(),
        args: vec![arg.to_string()],
    }
}

/// The sets of places that heads can name: rooms, then declared regions.
fn named_sets(rules: &RuleSet, map: &Map) -> Vec<GroundAtom> {
    map.rooms()
        .iter()
        .map(|r| unary("in_room", &r.name))
        .chain(rules.regions.iter().map(|(g, _)| unary("in_region", g)))
        .collect()
}

/// The places of a set head's atom.
fn members_of(atom: &GroundAtom, rules: &RuleSet, map: &Map) -> PlaceSet {
    let n = map.places().len();
    let arg = atom.args.first().map_or("", String::as_str);
    match atom.name.as_str() {
        "in_room" => {
            let r = map.rooms().iter().position(|r| r.name == arg);
            let places = map.places().iter().enumerate();
            PlaceSet::from_indices(n, places.filter(|(_, p)| p.room == r).map(|(k, _)| k))
        }
        _ => rules.regions.iter().find(|(g, _)| g == arg).map_or_else(
            || PlaceSet::empty(n),
            |(_, ks)| PlaceSet::from_indices(n, ks.iter().copied()),
        ),
    }
}

/// The output registers: place supports and exclusions (pooled and per group), room and region
/// supports, set heads, asked-for derived atoms.
fn outputs(
    b: &mut Builder,
    rules: &RuleSet,
    map: &Map,
    d: &Derivations,
    opts: &CompileOptions,
) -> Outputs {
    let places: Vec<GroundAtom> = map
        .places()
        .iter()
        .map(|p| unary("at_place", &p.name))
        .collect();
    let per_place = |b: &mut Builder, negated: bool, group: Option<usize>| -> Vec<Reg> {
        places
            .iter()
            .map(|a| global(b, d, map, a, negated, group))
            .collect()
    };
    let support = per_place(b, false, None);
    let exclusion = per_place(b, true, None);
    let n_groups = rules.groups.len() + 1;
    let (mut group_support, mut group_exclusion) = (Vec::new(), Vec::new());
    if n_groups > 1 {
        for g in 0..n_groups {
            group_support.push(per_place(b, false, Some(g)));
            group_exclusion.push(per_place(b, true, Some(g)));
        }
    }
    let mut support_of = |name: &str, arg: &str| global(b, d, map, &unary(name, arg), false, None);
    let rooms = map
        .rooms()
        .iter()
        .map(|r| support_of("in_room", &r.name))
        .collect();
    let regions = rules
        .regions
        .iter()
        .map(|(g, _)| support_of("in_region", g))
        .collect();
    let (derived, derived_in_context) = derived_outputs(b, d, map, opts);
    Outputs {
        support,
        exclusion,
        rooms,
        regions,
        derived,
        derived_in_context,
        set_heads: set_heads(b, d, rules, map),
        group_support,
        group_exclusion,
    }
}

/// The degree of a ground atom in one group (`None`: pooled over groups): the max over every
/// context that derives it.
fn global(
    b: &mut Builder,
    d: &Derivations,
    map: &Map,
    atom: &GroundAtom,
    negated: bool,
    group: Option<usize>,
) -> Reg {
    // A range of the ordered map, contexts ascending: as a lookup per place but in time
    // growing with the derivations, not with rooms × places (issue 16).
    let n = map.places().len();
    let parts: Vec<Reg> = match group {
        None => d
            .acc
            .range((atom.clone(), negated, 0)..(atom.clone(), negated, n))
            .map(|(_, &r)| r)
            .collect(),
        Some(g) => d
            .grouped
            .range((g, atom.clone(), negated, 0)..(g, atom.clone(), negated, n))
            .map(|(_, &r)| r)
            .collect(),
    };
    b.fold(&parts, Op::Max, 0.0)
}

/// Every room and region head (plain and negated, per group) that some rule concludes; a head
/// concluded nowhere is the constant 0 and constrains nothing.
fn set_heads(b: &mut Builder, d: &Derivations, rules: &RuleSet, map: &Map) -> Vec<SetHead> {
    let n_groups = rules.groups.len() + 1;
    let mut heads = Vec::new();
    for atom in &named_sets(rules, map) {
        for negated in [false, true] {
            for group in 0..n_groups {
                let reg = global(b, d, map, atom, negated, (n_groups > 1).then_some(group));
                if b.konst(reg) != Some(0.0) {
                    heads.push(SetHead {
                        atom: atom.clone(),
                        members: members_of(atom, rules, map),
                        negated,
                        group,
                        reg,
                    });
                }
            }
        }
    }
    heads
}

/// Asked-for derived atoms: pooled over contexts, and per context.
#[allow(clippy::type_complexity)]
fn derived_outputs(
    b: &mut Builder,
    d: &Derivations,
    map: &Map,
    opts: &CompileOptions,
) -> (Vec<(GroundAtom, Reg)>, Vec<(GroundAtom, usize, Reg)>) {
    let in_context: Vec<(GroundAtom, usize, Reg)> = d
        .acc
        .iter()
        .filter(|((a, neg, _), _)| !neg && opts.derived.iter().any(|x| x == &a.name))
        .map(|((a, _, ctx), &r)| (a.clone(), *ctx, r))
        .collect();
    let atoms: std::collections::BTreeSet<&GroundAtom> =
        in_context.iter().map(|(a, _, _)| a).collect();
    let pooled = atoms
        .into_iter()
        .map(|a| (a.clone(), global(b, d, map, a, false, None)))
        .collect();
    (pooled, in_context)
}

/// Keeps only what the outputs (and the trace) need, renumbering registers.
fn prune(
    b: Builder,
    mut out: Outputs,
    mut contributions: Vec<Contribution>,
    rules: &RuleSet,
    percepts: PerceptTable,
) -> Compiled {
    let mut live = vec![false; b.ops.len()];
    let roots = out
        .regs_mut()
        .chain(contributions.iter_mut().map(|c| &mut c.reg));
    for r in roots {
        live[*r as usize] = true;
    }
    for i in (0..b.ops.len()).rev() {
        if live[i] {
            for o in b.ops[i].operands().into_iter().flatten() {
                live[o as usize] = true;
            }
        }
    }
    let mut renumber = vec![0 as Reg; b.ops.len()];
    let mut ops = Vec::new();
    for (i, op) in b.ops.iter().enumerate() {
        if live[i] {
            renumber[i] = ops.len() as Reg;
            ops.push(op.map_operands(|r| renumber[r as usize]));
        }
    }
    let observed = out
        .regs_mut()
        .chain(contributions.iter_mut().map(|c| &mut c.reg))
        .map(|r| {
            *r = renumber[*r as usize];
            *r
        })
        .collect();
    Compiled {
        tape: Tape {
            ops,
            similarities: rules.similarities.values().copied().collect(),
            similarity_names: rules.similarities.keys().cloned().collect(),
            logic: rules.logic,
        },
        percepts,
        support: out.support,
        exclusion: out.exclusion,
        rooms: out.rooms,
        regions: out.regions,
        derived: out.derived,
        derived_in_context: out.derived_in_context,
        set_heads: out.set_heads,
        groups: rules.groups.len() + 1,
        group_support: out.group_support,
        group_exclusion: out.group_exclusion,
        contributions,
        warnings: Vec::new(),
        observed,
    }
}

/// Compiles one body formula in one scope.
fn formula(b: &mut Builder, scope: &Scope, f: &Spanned<Formula>, acc: &Acc) -> Reg {
    match &f.node {
        Formula::Degree(x) => b.c(*x),
        Formula::Not(a) => {
            let a = formula(b, scope, a, acc);
            b.mk(Op::Not(a))
        }
        Formula::Weighted(a, w) => {
            let a = formula(b, scope, a, acc);
            b.mk(Op::Detach(a, w.node))
        }
        Formula::Implies(x, y) => {
            let x = formula(b, scope, x, acc);
            let y = formula(b, scope, y, acc);
            b.mk(Op::Implies(x, y))
        }
        Formula::And(v) | Formula::Times(v) | Formula::Or(v) => {
            let parts: Vec<Reg> = v.iter().map(|x| formula(b, scope, x, acc)).collect();
            match &f.node {
                Formula::And(_) => b.fold(&parts, Op::Min, 1.0),
                Formula::Times(_) => b.fold(&parts, Op::TNorm, 1.0),
                _ => b.fold(&parts, Op::Max, 0.0),
            }
        }
        Formula::Atom(atom) => atom_reg(b, scope, atom, acc),
    }
}

fn atom_reg(b: &mut Builder, scope: &Scope, atom: &Atom, acc: &Acc) -> Reg {
    let name = atom.name.node.as_str();
    if let Some(sig) = scope.rules.percepts.get(name) {
        let Some(slot) = scope.slot(atom, sig) else {
            return b.c(0.0);
        };
        let expect = sig
            .roles
            .iter()
            .zip(&atom.args)
            .find(|(r, _)| matches!(r, ArgRole::Expect))
            .map(|(_, t)| &t.node);
        let sim = sig
            .similarity
            .as_ref()
            .and_then(|s| scope.rules.similarities.keys().position(|k| k == s));
        return match (expect, sim) {
            (None, _) => b.mk(Op::Degree(slot)),
            (Some(term), Some(similarity)) => match scope.expectation(term) {
                // A place that expects nothing for this percept cannot be matched by it.
                None => b.c(0.0),
                Some(expected) => b.mk(Op::Match {
                    slot,
                    similarity: similarity as u32,
                    centre: expected.centre(),
                    half: expected.half_width(),
                }),
            },
            (Some(_), None) => b.mk(Op::Degree(slot)),
        };
    }
    if is_map_relation(name) {
        let v = scope.map_relation(atom).unwrap_or(0.0);
        return b.c(v);
    }
    match scope.ground(atom) {
        Some(g) => match acc.get(&(g, false, scope.context)) {
            Some(&r) => r,
            None => b.c(0.0),
        },
        None => b.c(0.0),
    }
}
