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
//!   (the possibility that the reading is an outlier), see `logic::Similarity::degree`.
//!
//! Both kinds of repair are counted per step in `Engine::sanitised`, so that a caller can report
//! them; nothing is dropped silently.

use crate::rules::RuleSet;
use crate::syntax::ast::ArgRole;
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
#[serde(from = "TableWire")]
pub struct PerceptTable {
    instances: Vec<PerceptInstance>,
    index: BTreeMap<PerceptInstance, PerceptSlot>,
    /// Borrowed-key look-up for [`PerceptTable::slot`]; derived from `instances`, so it is not
    /// serialized but rebuilt when a table is deserialized.
    #[serde(skip)]
    lookup: InstanceIndex,
}

/// The serialized fields of a [`PerceptTable`].
#[derive(Deserialize)]
struct TableWire {
    instances: Vec<PerceptInstance>,
    index: BTreeMap<PerceptInstance, PerceptSlot>,
}

impl From<TableWire> for PerceptTable {
    fn from(w: TableWire) -> Self {
        let lookup = InstanceIndex::new(&w.instances);
        PerceptTable {
            instances: w.instances,
            index: w.index,
            lookup,
        }
    }
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
        let lookup = InstanceIndex::new(&instances);
        PerceptTable {
            instances,
            index,
            lookup,
        }
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
        // The BTreeMap is keyed by owned instances, which would need an allocated key; the hash
        // index takes borrowed strings, since user code may call this per percept per frame.
        self.lookup.get(&self.instances, name.as_bytes(), args)
    }

    /// The borrowed-key index over [`PerceptTable::instances`].
    pub(crate) fn lookup(&self) -> &InstanceIndex {
        &self.lookup
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

/// A hash index from `name(args…)` to slot that is queried with borrowed strings, so that the
/// per-percept look-up of a stream reader neither allocates nor scans the table.
///
/// Open addressing with linear probing over a power-of-two table kept at most half full; each
/// bucket holds the upper half of the key's hash (to skip most string compares) and the slot + 1
/// (0 = empty). When the same instance occurs twice, the first slot wins, as a scan would find it.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct InstanceIndex {
    buckets: Vec<(u32, u32)>,
}

impl InstanceIndex {
    /// Indexes `instances` by position.
    pub(crate) fn new(instances: &[PerceptInstance]) -> Self {
        let size = (instances.len() * 2).next_power_of_two().max(8);
        let mut ix = InstanceIndex {
            buckets: vec![(0, 0); size],
        };
        for (i, p) in instances.iter().enumerate() {
            if ix.get(instances, p.name.as_bytes(), &p.args).is_some() {
                continue;
            }
            let h = key_hash(p.name.as_bytes(), &p.args);
            let mask = ix.buckets.len() - 1;
            let mut b = h as usize & mask;
            while ix.buckets[b].1 != 0 {
                b = (b + 1) & mask;
            }
            ix.buckets[b] = ((h >> 32) as u32, i as u32 + 1);
        }
        ix
    }

    /// The slot of `name(args…)` among `instances` (the list this index was built from). Keys
    /// are compared as bytes, so a caller holding raw bytes need not validate them as UTF-8
    /// first: bytes equal to a declared (valid) name are valid themselves.
    pub(crate) fn get<S: AsRef<[u8]>>(
        &self,
        instances: &[PerceptInstance],
        name: &[u8],
        args: &[S],
    ) -> Option<PerceptSlot> {
        if self.buckets.is_empty() {
            return None;
        }
        let h = key_hash(name, args);
        let tag = (h >> 32) as u32;
        let mask = self.buckets.len() - 1;
        let mut b = h as usize & mask;
        loop {
            let (t, s) = *self.buckets.get(b)?;
            if s == 0 {
                return None;
            }
            if t == tag {
                let p = instances.get(s as usize - 1)?;
                if p.name.as_bytes() == name
                    && p.args.len() == args.len()
                    && p.args
                        .iter()
                        .zip(args)
                        .all(|(x, y)| x.as_bytes() == y.as_ref())
                {
                    return Some(PerceptSlot(s - 1));
                }
            }
            b = (b + 1) & mask;
        }
    }
}

/// FNV-1a over the name and each argument, each argument preceded by the byte 0xFF, which
/// cannot occur in UTF-8, so that `("ab", [])` and `("a", ["b"])` hash apart.
fn key_hash<S: AsRef<[u8]>>(name: &[u8], args: &[S]) -> u64 {
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h = (h ^ u64::from(b)).wrapping_mul(PRIME);
        }
    };
    eat(name);
    for a in args {
        eat(&[0xff]);
        eat(a.as_ref());
    }
    // Fold the high bits into the low ones used for the bucket.
    h ^ (h >> 29)
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
