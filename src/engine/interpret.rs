//! The reference interpreter: the same rules, evaluated by walking the syntax tree for every
//! frame, with no compilation, folding or sharing.
//!
//! It exists to be obviously right, not fast. The compiled tape is tested against it on random
//! frames, and benchmarked next to it. It shares with the compiler only the resolution of names
//! (`compile::Scope`: which percept slot, which map fact, which place parameter an argument
//! denotes), not the evaluation: every connective, every `max` over derivations and contexts is
//! computed here afresh, top-down, by recursion on derived atoms.

use super::compile::{is_map_relation, schema_bindings, GroundAtom, Scope};
use super::frame::{Frame, PerceptTable};
use crate::logic::{clamp_degree, LogicConfig};
use crate::map::Map;
use crate::rules::RuleSet;
use crate::syntax::ast::{ArgRole, Formula};

/// Degrees the interpreter derives for one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Interpretation {
    /// `α_k` per place.
    pub support: Vec<f64>,
    /// `β_k` per place.
    pub exclusion: Vec<f64>,
    /// `in_room` support per room.
    pub rooms: Vec<f64>,
}

/// A tree-walking evaluator over a checked rule set and its map.
pub struct Interpreter<'a> {
    rules: &'a RuleSet,
    map: &'a Map,
    percepts: &'a PerceptTable,
    logic: LogicConfig,
}

impl<'a> Interpreter<'a> {
    /// An interpreter for `rules` over `map`; `percepts` must be the table of `rules`.
    pub fn new(rules: &'a RuleSet, map: &'a Map, percepts: &'a PerceptTable) -> Self {
        Interpreter {
            rules,
            map,
            percepts,
            logic: rules.logic,
        }
    }

    /// Evaluates every place and room degree for `frame`.
    pub fn run(&self, frame: &Frame) -> Interpretation {
        let atom = |name: &str, arg: &str| GroundAtom {
            name: name.to_string(),
            args: vec![arg.to_string()],
        };
        let places = self.map.places();
        Interpretation {
            support: places
                .iter()
                .map(|p| self.global(&atom("at_place", &p.name), false, frame))
                .collect(),
            exclusion: places
                .iter()
                .map(|p| self.global(&atom("at_place", &p.name), true, frame))
                .collect(),
            rooms: self
                .map
                .rooms()
                .iter()
                .map(|r| self.global(&atom("in_room", &r.name), false, frame))
                .collect(),
        }
    }

    /// The degree of a ground atom: max over every place context.
    pub fn global(&self, atom: &GroundAtom, negated: bool, frame: &Frame) -> f64 {
        (0..self.map.places().len())
            .map(|ctx| self.derive(atom, negated, ctx, frame))
            .fold(0.0, f64::max)
    }

    /// The degree of a ground atom in one context: max over every rule instance concluding it.
    fn derive(&self, atom: &GroundAtom, negated: bool, ctx: usize, frame: &Frame) -> f64 {
        let mut best = 0.0f64;
        for rule in &self.rules.rules {
            if rule.head.negated != negated || rule.head.atom.name.node != atom.name {
                continue;
            }
            let w = rule.weight.as_ref().map_or(1.0, |w| w.node);
            for binding in schema_bindings(rule, self.rules) {
                let scope = Scope::new(
                    self.rules,
                    self.map,
                    self.percepts,
                    &binding,
                    &rule.body.node,
                    ctx,
                );
                if scope.ground(&rule.head.atom).as_ref() != Some(atom) {
                    continue;
                }
                let body = self.eval(&rule.body.node, &scope, frame);
                best = best.max(self.logic.detach(body, w));
            }
        }
        best
    }

    fn eval(&self, f: &Formula, scope: &Scope, frame: &Frame) -> f64 {
        let l = &self.logic;
        match f {
            Formula::Degree(x) => *x,
            Formula::Not(a) => 1.0 - self.eval(&a.node, scope, frame),
            Formula::Weighted(a, w) => l.detach(self.eval(&a.node, scope, frame), w.node),
            Formula::Implies(a, b) => l.implies(
                self.eval(&a.node, scope, frame),
                self.eval(&b.node, scope, frame),
            ),
            Formula::And(v) => v
                .iter()
                .map(|x| self.eval(&x.node, scope, frame))
                .fold(1.0, f64::min),
            Formula::Or(v) => v
                .iter()
                .map(|x| self.eval(&x.node, scope, frame))
                .fold(0.0, f64::max),
            Formula::Times(v) => v
                .iter()
                .map(|x| self.eval(&x.node, scope, frame))
                .fold(1.0, |acc, x| l.tnorm.apply(acc, x)),
            Formula::Atom(atom) => {
                let name = atom.name.node.as_str();
                if let Some(sig) = self.rules.percepts.get(name) {
                    let Some(slot) = scope.slot(atom, sig) else {
                        return 0.0;
                    };
                    let i = slot.0 as usize;
                    let degree = clamp_degree(frame.degree.get(i).copied().unwrap_or(0.0));
                    let expect = sig
                        .roles
                        .iter()
                        .zip(&atom.args)
                        .find(|(r, _)| matches!(r, ArgRole::Expect));
                    let similarity = sig
                        .similarity
                        .as_ref()
                        .and_then(|s| self.rules.similarities.get(s));
                    return match (expect, similarity) {
                        (Some((_, term)), Some(sim)) => match scope.expectation(&term.node) {
                            None => 0.0,
                            Some(e) => {
                                let x = frame.value.get(i).copied().unwrap_or(f64::NAN);
                                let mu = sim.degree_within(x, e.centre(), e.half_width());
                                degree.min(clamp_degree(mu))
                            }
                        },
                        _ => degree,
                    };
                }
                if is_map_relation(name) {
                    return scope.map_relation(atom).unwrap_or(0.0);
                }
                match scope.ground(atom) {
                    Some(g) => self.derive(&g, false, scope.context, frame),
                    None => 0.0,
                }
            }
        }
    }
}

/// True when `rules` has no recursive definitions, i.e. the interpreter terminates.
pub fn terminates(rules: &RuleSet) -> bool {
    super::compile::predicate_order(rules).is_ok()
}
