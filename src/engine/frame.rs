//! The percept vector: which percept instances a rule set can consume ([`PerceptTable`]) and one
//! frame of their degrees and measured values ([`Frame`]).
//!
//! A *percept instance* is a declared percept with its domain arguments fixed — `sonar_wall(North)`
//! is one instance, `sonar_wall(East)` another. The table enumerates every instance once, in a
//! deterministic order (percepts by name, arguments in domain order), and gives each a slot; a
//! [`Frame`] is two dense arrays indexed by slot. Building a frame does the name look-ups; the
//! engine's step then reads only slots, which is what keeps it allocation-free.
//!
//! # Treatment of bad values (documented contract of `Engine::step`)
//! - a percept not set in the frame is **missing**: degree 0 (no support), value NaN;
//! - a NaN degree counts as missing (0); a degree outside `[0, 1]` is clamped into it;
//! - a NaN or infinite value makes every similarity against it equal to that similarity's bias
//!   (the possibility that the reading is an outlier), see `logic::Trapezoid::degree`.
//!
//! Both kinds of repair are counted per step in `Engine::sanitised`, so that a caller can report
//! them; nothing is dropped silently.

use crate::syntax::ast::ArgRole;
use crate::syntax::check::RuleSet;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The index of one percept instance in a [`Frame`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct PerceptSlot(pub u32);

/// One percept instance: its name and domain arguments.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct PerceptInstance {
    /// Percept name.
    pub name: String,
    /// Values of its domain-role arguments, in order.
    pub args: Vec<String>,
}

impl std::fmt::Display for PerceptInstance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.args.is_empty() {
            write!(f, "{}", self.name)
        } else {
            write!(f, "{}({})", self.name, self.args.join(", "))
        }
    }
}

/// Every percept instance of a rule set, with its slot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PerceptTable {
    instances: Vec<PerceptInstance>,
    index: BTreeMap<PerceptInstance, PerceptSlot>,
}

impl PerceptTable {
    /// Enumerates the instances of every declared percept over its argument domains.
    pub fn new(rules: &RuleSet) -> Self {
        let mut instances = Vec::new();
        for (name, sig) in &rules.percepts {
            let domains: Vec<&[String]> = sig
                .roles
                .iter()
                .filter_map(|r| match r {
                    ArgRole::Domain(d) => Some(rules.domains.get(d).map_or(&[][..], |v| &v[..])),
                    _ => None,
                })
                .collect();
            for_each_product(&domains, &mut |args| {
                instances.push(PerceptInstance {
                    name: name.clone(),
                    args: args.to_vec(),
                })
            });
        }
        let index = instances
            .iter()
            .enumerate()
            .map(|(i, p)| (p.clone(), PerceptSlot(i as u32)))
            .collect();
        PerceptTable { instances, index }
    }

    /// Number of slots.
    pub fn len(&self) -> usize {
        self.instances.len()
    }

    /// True when the rule set declares no percept.
    pub fn is_empty(&self) -> bool {
        self.instances.is_empty()
    }

    /// The slot of `name(args…)`, if the rule set declares that instance.
    pub fn slot(&self, name: &str, args: &[&str]) -> Option<PerceptSlot> {
        // The map is keyed by owned instances; a linear scan over the (small) table avoids
        // allocating a key on a path that user code may call per frame.
        self.instances
            .iter()
            .position(|p| {
                p.name == name
                    && p.args.len() == args.len()
                    && p.args.iter().zip(args).all(|(a, b)| a == b)
            })
            .map(|i| PerceptSlot(i as u32))
    }

    /// The slot of an instance given as an owned key.
    pub fn slot_of(&self, instance: &PerceptInstance) -> Option<PerceptSlot> {
        self.index.get(instance).copied()
    }

    /// The instance in `slot`.
    pub fn instance(&self, slot: PerceptSlot) -> Option<&PerceptInstance> {
        self.instances.get(slot.0 as usize)
    }

    /// All instances in slot order.
    pub fn instances(&self) -> &[PerceptInstance] {
        &self.instances
    }
}

/// Calls `f` with every tuple of the cartesian product of `domains` (once, with `[]`, for none).
pub(crate) fn for_each_product(domains: &[&[String]], f: &mut dyn FnMut(&[String])) {
    fn go(domains: &[&[String]], acc: &mut Vec<String>, f: &mut dyn FnMut(&[String])) {
        match domains.split_first() {
            None => f(acc),
            Some((first, rest)) => {
                for v in first.iter() {
                    acc.push(v.clone());
                    go(rest, acc, f);
                    acc.pop();
                }
            }
        }
    }
    go(domains, &mut Vec::new(), f)
}

/// Degrees and measured values of one frame, indexed by [`PerceptSlot`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Frame {
    /// Degree per slot; 0 = missing.
    pub degree: Vec<f64>,
    /// Measured value per slot; NaN = none.
    pub value: Vec<f64>,
}

impl Frame {
    /// An empty frame (every percept missing) with `slots` slots.
    pub fn new(slots: usize) -> Self {
        Frame {
            degree: vec![0.0; slots],
            value: vec![f64::NAN; slots],
        }
    }

    /// Marks every percept missing again, keeping the buffers.
    pub fn clear(&mut self) {
        self.degree.fill(0.0);
        self.value.fill(f64::NAN);
    }

    /// Sets one percept. Out-of-range slots are ignored and reported by the `false` result.
    pub fn set(&mut self, slot: PerceptSlot, degree: f64, value: Option<f64>) -> bool {
        let i = slot.0 as usize;
        match (self.degree.get_mut(i), self.value.get_mut(i)) {
            (Some(d), Some(v)) => {
                *d = degree;
                *v = value.unwrap_or(f64::NAN);
                true
            }
            _ => false,
        }
    }
}
