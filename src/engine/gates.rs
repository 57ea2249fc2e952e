//! The tape evaluated only where a frame can make a difference: instructions that a zero
//! *gate* forces to a known constant are evaluated only on frames where their gates may be
//! non-zero (issue 16: a 10,000-place map evaluates the office schema at every place, while a
//! beacon reading matches the signature of a few % of them).
//!
//! A *gate* is a `Match` leaf whose similarity has bias 0: it is exactly 0 unless the percept
//! is present with a value within the similarity's support around the leaf's centre. At load
//! time each register gets its *forcing set*: gates any one of which, when 0, fixes the
//! register to a constant, found from the tape's structure (0 annihilates `min`, every t-norm,
//! the detachment of a weight in `[0, 1]`, and makes `0 -> b` 1; 1 absorbs `max` and makes
//! `a -> 1` 1; an instruction whose operands are both forced by a common gate is forced to its
//! own value of theirs). Registers with the same forcing set form a *unit*; a unit is *active*
//! in a frame when all its gates may be non-zero, which a sorted index of each gate group's
//! centres finds by binary search (circular for a periodic similarity, with a margin for
//! rounding; a missing percept or a NaN value activates none). Active units are evaluated in
//! register order (the tape's order, so operands first); inactive ones hold their constants,
//! written when a unit stops being active. A gate read only by gated instructions is evaluated
//! with each unit that reads it, never on its own: no one else reads it.
//!
//! The annihilation rules hold on `[0, 1]` without NaN and without `−0`: the domain every
//! register stays in when the tape's constants and weights are in it, no similarity has a bias
//! of `−0`, and no degree of the frame is `−0` (a frame with one is evaluated whole). Registers
//! that depend on no gate are evaluated by [`Columns`] before the units; those that read gated
//! registers, after them (or, when a gated instruction reads them in turn, in register order
//! with the units). Every register any output, trace or later instruction reads holds the bits
//! [`Tape::eval`] writes; that is tested against the interpreter on random tapes and frames.
//! Built once at load time; [`Gated::eval`] allocates nothing and cannot panic.

use super::columns::Columns;
use super::frame::Frame;
use super::tape::{Op, Reg, Tape};
use crate::logic::{clamp_degree, Similarity};
use std::collections::HashMap;
use std::ops::Range;

/// Most gates a forcing set keeps: any subset of a forcing set forces the register too.
const MAX_GATES: usize = 4;

/// Relative margin on a gate's reach, far above the rounding of the distances compared.
const MARGIN: f64 = 1e-9;

/// Above this magnitude of values and centres a circular distance is not compared in the index
/// (the subtraction loses the centre's digits); every gate of the group is then active.
const CIRCULAR_LIMIT: f64 = 1e9;

/// The gates of one percept slot and similarity, indexed by their centres.
#[derive(Debug, Clone)]
struct GateGroup {
    slot: u32,
    /// The circle's period, when the similarity is circular.
    period: Option<f64>,
    /// Distance from a centre beyond which every gate of the group is 0: half the core, the
    /// slope and the widest half width.
    reach: f64,
    /// The largest finite centre's magnitude, for the margin.
    scale: f64,
    /// Finite centres (reduced to the circle when circular), ascending.
    keys: Vec<f64>,
    /// The gate of each key.
    gates: Vec<u32>,
}

/// A register fixed to `value` when any gate of `gates` is 0.
#[derive(Debug, Clone, PartialEq)]
struct Forced {
    gates: Vec<u32>,
    value: f64,
}

/// What evaluates an ungated register.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Class {
    /// Reads no gated register: before the units.
    Before,
    /// Reads a gated register and is read by a gated one: with the units, every frame.
    Between,
    /// Reads a gated register, feeds none: after the units.
    After,
    /// Gated.
    Gated,
}

/// The load-time plan (see the module docs).
#[derive(Debug, Clone)]
struct Plan {
    len: usize,
    full: Columns,
    before: Columns,
    after: Columns,
    between: Vec<u32>,
    groups: Vec<GateGroup>,
    units: UnitArrays,
}

/// The units, each list flattened: list `k` is `items[start[k]..start[k + 1]]`.
#[derive(Debug, Clone)]
struct UnitArrays {
    /// Per gate, its units.
    gate_start: Vec<u32>,
    gate_units: Vec<u32>,
    /// Per unit, the number of gates that must be active.
    need: Vec<u32>,
    /// Per unit, the registers it evaluates (the gates it reads with them), ascending.
    reg_start: Vec<u32>,
    regs: Vec<u32>,
    /// Per unit, its own registers and their constants.
    forced_start: Vec<u32>,
    forced_regs: Vec<u32>,
    forced_values: Vec<f64>,
}

/// What changes from frame to frame; sized at load time.
#[derive(Debug, Clone)]
struct State {
    now: u32,
    /// Per unit, the frame its count is of, and how many of its gates are active.
    stamp: Vec<u32>,
    count: Vec<u32>,
    active: Vec<u32>,
    /// The units evaluated in the last frame (their registers may not hold their constants).
    last: Vec<u32>,
    /// Every unit may hold evaluated values (at first, and after a frame evaluated whole).
    stale: bool,
    /// Registers to evaluate this frame, one bit each.
    bits: Vec<u64>,
}

/// A tape's zero-gated evaluator (see the module docs).
#[derive(Debug, Clone)]
pub struct Gated {
    plan: Plan,
    state: State,
}

/// In `[0, 1]`, not NaN, not `−0`: the domain the annihilation rules are proved on.
fn in_domain(x: f64) -> bool {
    (0.0..=1.0).contains(&x) && x.to_bits() != (-0.0f64).to_bits()
}

/// A frame whose degrees could put a `−0` in a register.
fn has_negative_zero(frame: &Frame) -> bool {
    frame
        .degree
        .iter()
        .any(|d| d.to_bits() == (-0.0f64).to_bits())
}

/// The tape keeps every register in the domain for frames without `−0` degrees.
fn closed(tape: &Tape) -> bool {
    let ops_ok = tape.ops.iter().all(|op| match *op {
        Op::Const(c) | Op::Detach(_, c) => in_domain(c),
        _ => true,
    });
    let sims_ok = tape
        .similarities
        .iter()
        .all(|s| s.shape.bias.to_bits() != (-0.0f64).to_bits());
    ops_ok && sims_ok
}

/// The group key `(slot, similarity)` and the reach of a gate, or `None` for a leaf that is not
/// one (a bias other than `+0`, or a shape whose support is not a finite interval).
fn gate_key(tape: &Tape, op: Op) -> Option<((u32, u32), f64)> {
    let Op::Match {
        slot,
        similarity,
        half,
        ..
    } = op
    else {
        return None;
    };
    let s: &Similarity = tape.similarities.get(similarity as usize)?;
    let shape = &s.shape;
    let finite = shape.core.is_finite() && shape.slope.is_finite() && shape.core >= 0.0;
    let period_ok = s.period.map_or(true, |p| p.is_finite() || p.is_nan());
    if shape.bias.to_bits() != 0 || !finite || !period_ok || half == f64::INFINITY {
        return None;
    }
    let half = if half > 0.0 { half } else { 0.0 };
    let reach = 0.5 * shape.core + shape.slope.max(0.0) + half;
    Some(((slot.0, similarity), reach))
}

impl GateGroup {
    /// The index ranges of the gates that may be non-zero in `frame` (see the module docs).
    fn window(&self, frame: &Frame) -> [Range<usize>; 2] {
        let none = [0..0, 0..0];
        let s = self.slot as usize;
        let d = clamp_degree(frame.degree.get(s).copied().unwrap_or(0.0));
        let x = frame.value.get(s).copied().unwrap_or(f64::NAN);
        // A degree of 0 makes every match `min(0, ·) = 0`; a value that is not finite gives the
        // bias, 0, at every centre.
        if d <= 0.0 || !x.is_finite() {
            return none;
        }
        let p = self.period.unwrap_or(0.0);
        let r = self.reach + MARGIN * (1.0 + x.abs() + self.scale + self.reach + p);
        let from = |v: f64| self.keys.partition_point(|&k| k < v);
        let to = |v: f64| self.keys.partition_point(|&k| k <= v);
        let n = self.keys.len();
        match self.period {
            None => [from(x - r)..to(x + r), 0..0],
            Some(p) if 2.0 * r >= p || x.abs() + self.scale > CIRCULAR_LIMIT => [0..n, 0..0],
            Some(p) => {
                let c = x.rem_euclid(p);
                let (lo, hi) = (c - r, c + r);
                if lo < 0.0 {
                    [0..to(hi), from(lo + p)..n]
                } else if hi >= p {
                    [from(lo)..n, 0..to(hi - p)]
                } else {
                    [from(lo)..to(hi), 0..0]
                }
            }
        }
    }
}

/// The gates of `tape` in their groups, and the gate of each register (if it is one).
fn gate_groups(tape: &Tape) -> (Vec<GateGroup>, Vec<Option<u32>>) {
    let mut by_key: HashMap<(u32, u32), usize> = HashMap::new();
    let mut groups: Vec<GateGroup> = Vec::new();
    let mut members: Vec<Vec<(f64, u32)>> = Vec::new();
    let mut gate_of = vec![None; tape.ops.len()];
    let mut gates = 0u32;
    for (i, &op) in tape.ops.iter().enumerate() {
        let (Some((key, reach)), Op::Match { centre, .. }) = (gate_key(tape, op), op) else {
            continue;
        };
        let g = *by_key.entry(key).or_insert_with(|| {
            let period = tape.similarities[key.1 as usize].period;
            groups.push(GateGroup {
                slot: key.0,
                period: period.filter(|p| *p > 0.0),
                reach: 0.0,
                scale: 0.0,
                keys: Vec::new(),
                gates: Vec::new(),
            });
            members.push(Vec::new());
            groups.len() - 1
        });
        let group = &mut groups[g];
        group.reach = group.reach.max(reach);
        // A centre that is not finite gives the bias, 0, for every value: never active.
        if centre.is_finite() {
            group.scale = group.scale.max(centre.abs());
            let k = group.period.map_or(centre, |p| centre.rem_euclid(p));
            members[g].push((k, gates));
        }
        gate_of[i] = Some(gates);
        gates += 1;
    }
    for (group, mut m) in groups.iter_mut().zip(members) {
        m.sort_by(|a, b| a.0.total_cmp(&b.0));
        (group.keys, group.gates) = m.into_iter().unzip();
    }
    (groups, gate_of)
}

/// The forcing set and constant of an instruction whose operands are `(a, b)`: `zero_a` and
/// `zero_b` say whether a forced operand annihilates (the result is then `absorbing` whatever
/// the other operand); otherwise both must be forced by a common gate.
fn combine(
    (a, zero_a): (Option<&Forced>, bool),
    (b, zero_b): (Option<&Forced>, bool),
    absorbing: f64,
    both: impl Fn(f64, f64) -> f64,
) -> Option<Forced> {
    let union = |x: &Forced, y: &Forced| {
        let mut gates: Vec<u32> = x.gates.iter().chain(&y.gates).copied().collect();
        gates.sort_unstable();
        gates.dedup();
        gates.truncate(MAX_GATES);
        gates
    };
    let gates = match (a, b) {
        (Some(x), Some(y)) if zero_a && zero_b => union(x, y),
        (Some(x), _) if zero_a => x.gates.clone(),
        (_, Some(y)) if zero_b => y.gates.clone(),
        (Some(x), Some(y)) => {
            let common: Vec<u32> = x
                .gates
                .iter()
                .copied()
                .filter(|g| y.gates.contains(g))
                .collect();
            return (!common.is_empty()).then(|| Forced {
                gates: common,
                value: both(x.value, y.value),
            });
        }
        _ => return None,
    };
    Some(Forced {
        gates,
        value: absorbing,
    })
}

/// The forcing set of every register (see the module docs).
fn forcing(tape: &Tape, gate_of: &[Option<u32>]) -> Vec<Option<Forced>> {
    let empty = Frame::new(0);
    // An instruction's own value on forced operands: the interpreter's, on a two-register file.
    let on = |op: Op, x: f64, y: f64| {
        let [a, _] = op.operands();
        let op = op.map_operands(|r| u32::from(Some(r) != a));
        tape.eval_op(op, &empty, &[x, y])
    };
    let is_zero = |f: Option<&Forced>| f.is_some_and(|f| f.value.to_bits() == 0);
    let is_one = |f: Option<&Forced>| f.is_some_and(|f| f.value == 1.0);
    let mut out: Vec<Option<Forced>> = Vec::with_capacity(tape.ops.len());
    for (i, &op) in tape.ops.iter().enumerate() {
        let get = |r: Reg| out.get(r as usize).and_then(Option::as_ref);
        let f = match (gate_of.get(i).copied().flatten(), op) {
            (Some(g), _) => Some(Forced {
                gates: vec![g],
                value: 0.0,
            }),
            (None, Op::Not(a) | Op::Detach(a, _)) => get(a).map(|x| Forced {
                gates: x.gates.clone(),
                value: on(op, x.value, x.value),
            }),
            (None, Op::Min(a, b) | Op::TNorm(a, b)) => {
                let (x, y) = (get(a), get(b));
                combine((x, is_zero(x)), (y, is_zero(y)), 0.0, |p, q| on(op, p, q))
            }
            (None, Op::Max(a, b)) => {
                let (x, y) = (get(a), get(b));
                combine((x, is_one(x)), (y, is_one(y)), 1.0, |p, q| on(op, p, q))
            }
            (None, Op::Implies(a, b)) => {
                let (x, y) = (get(a), get(b));
                combine((x, is_zero(x)), (y, is_one(y)), 1.0, |p, q| on(op, p, q))
            }
            _ => None,
        };
        out.push(f);
    }
    out
}

/// Each register's class, and whether a gate is read by a reader that is not gated.
fn classify(tape: &Tape, forced: &[Option<Forced>]) -> (Vec<Class>, Vec<bool>) {
    let n = tape.ops.len();
    let gated = |i: usize| forced[i].is_some();
    let mut depends = vec![false; n];
    let mut read_ungated = vec![false; n];
    for (i, op) in tape.ops.iter().enumerate() {
        for o in op.operands().into_iter().flatten() {
            let o = o as usize;
            depends[i] |= gated(o) || depends[o];
            read_ungated[o] |= !gated(i);
        }
    }
    let mut feeds = vec![false; n];
    for i in (0..n).rev() {
        if gated(i) || feeds[i] {
            for o in tape.ops[i].operands().into_iter().flatten() {
                feeds[o as usize] = true;
            }
        }
    }
    let class = (0..n)
        .map(|i| match (gated(i), depends[i], feeds[i]) {
            (true, _, _) => Class::Gated,
            (false, false, _) => Class::Before,
            (false, true, true) => Class::Between,
            (false, true, false) => Class::After,
        })
        .collect();
    (class, read_ungated)
}

/// Lists as one array and the start of each: `items[start[k]..start[k + 1]]` is list `k`.
fn flatten<T: Copy>(lists: &[Vec<T>]) -> (Vec<u32>, Vec<T>) {
    let mut start = Vec::with_capacity(lists.len() + 1);
    let mut items = Vec::new();
    start.push(0);
    for l in lists {
        items.extend_from_slice(l);
        start.push(items.len() as u32);
    }
    (start, items)
}

impl Gated {
    /// The plan for `tape`, whose registers in `observed` are read from outside (outputs,
    /// trace); `None` when the tape has no gate, or is not closed in the domain, or is not
    /// well formed (then [`Columns`] or the interpreter stays the evaluator).
    pub fn new(tape: &Tape, observed: &[Reg]) -> Option<Gated> {
        let full = Columns::new(tape)?;
        let (groups, gate_of) = gate_groups(tape);
        if groups.is_empty() || !closed(tape) {
            return None;
        }
        let forced = forcing(tape, &gate_of);
        let (class, read_ungated) = classify(tape, &forced);
        let mut is_observed = vec![false; tape.ops.len()];
        for &r in observed {
            if let Some(o) = is_observed.get_mut(r as usize) {
                *o = true;
            }
        }
        // A gate nothing outside its readers' units reads is evaluated with each of them.
        let embedded = |i: usize| gate_of[i].is_some() && !is_observed[i] && !read_ungated[i];
        let units = units(tape, &forced, embedded);
        let between = (0..tape.ops.len())
            .filter(|&i| class[i] == Class::Between)
            .map(|i| i as u32)
            .collect();
        let gates = gate_of.iter().flatten().count();
        let plan = Plan {
            len: tape.ops.len(),
            before: Columns::subset(tape, |i| class[i] == Class::Before)?,
            after: Columns::subset(tape, |i| class[i] == Class::After)?,
            full,
            between,
            groups,
            units: units.flatten(gates),
        };
        let n_units = plan.units.need.len();
        let state = State {
            now: 0,
            stamp: vec![0; n_units],
            count: vec![0; n_units],
            active: Vec::with_capacity(n_units),
            last: Vec::with_capacity(n_units),
            stale: true,
            bits: vec![0; plan.len.div_ceil(64)],
        };
        Some(Gated { plan, state })
    }

    /// Number of units (registers sharing a forcing set).
    pub fn units(&self) -> usize {
        self.plan.units.need.len()
    }

    /// Evaluates `tape` (the tape this plan was built from) for `frame`: every register anything
    /// reads holds what [`Tape::eval`] writes.
    pub fn eval(&mut self, tape: &Tape, frame: &Frame, regs: &mut [f64]) {
        let (plan, st) = (&self.plan, &mut self.state);
        if regs.len() != plan.len || tape.ops.len() != plan.len || has_negative_zero(frame) {
            plan.full.eval(tape, frame, regs);
            st.stale = true;
            st.last.clear();
            return;
        }
        plan.before.eval(tape, frame, regs);
        plan.find_active(frame, st);
        plan.force_inactive(st, regs);
        plan.run_active(tape, frame, st, regs);
        plan.after.eval(tape, frame, regs);
    }
}

/// The units of a plan while they are built.
struct Units {
    gate_units: Vec<Vec<u32>>,
    need: Vec<u32>,
    regs: Vec<Vec<u32>>,
    forced: Vec<Vec<(u32, f64)>>,
}

/// Groups the gated registers by forcing set; embedded gates join their readers' units.
fn units(tape: &Tape, forced: &[Option<Forced>], embedded: impl Fn(usize) -> bool) -> Units {
    let mut ids: HashMap<&[u32], usize> = HashMap::new();
    let mut u = Units {
        gate_units: Vec::new(),
        need: Vec::new(),
        regs: Vec::new(),
        forced: Vec::new(),
    };
    for (i, f) in forced.iter().enumerate() {
        let Some(f) = f.as_ref().filter(|_| !embedded(i)) else {
            continue;
        };
        let id = *ids.entry(f.gates.as_slice()).or_insert_with(|| {
            for &g in &f.gates {
                let g = g as usize;
                if u.gate_units.len() <= g {
                    u.gate_units.resize(g + 1, Vec::new());
                }
                u.gate_units[g].push(u.need.len() as u32);
            }
            u.need.push(f.gates.len() as u32);
            u.regs.push(Vec::new());
            u.forced.push(Vec::new());
            u.need.len() - 1
        });
        for o in tape.ops[i].operands().into_iter().flatten() {
            if embedded(o as usize) {
                u.regs[id].push(o);
            }
        }
        u.regs[id].push(i as u32);
        u.forced[id].push((i as u32, f.value));
    }
    for r in &mut u.regs {
        r.sort_unstable();
        r.dedup();
    }
    u
}

impl Units {
    /// The flattened arrays, over `gates` gates.
    fn flatten(mut self, gates: usize) -> UnitArrays {
        self.gate_units.resize(gates, Vec::new());
        let (gate_start, gate_units) = flatten(&self.gate_units);
        let (reg_start, regs) = flatten(&self.regs);
        let (forced_start, pairs) = flatten(&self.forced);
        let (forced_regs, forced_values) = pairs.into_iter().unzip();
        UnitArrays {
            gate_start,
            gate_units,
            need: self.need,
            reg_start,
            regs,
            forced_start,
            forced_regs,
            forced_values,
        }
    }
}

impl Plan {
    /// Lists the units whose gates are all active in `frame` into `st.active`.
    fn find_active(&self, frame: &Frame, st: &mut State) {
        st.now = st.now.wrapping_add(1);
        if st.now == 0 {
            st.stamp.fill(0);
            st.now = 1;
        }
        st.active.clear();
        let a = &self.units;
        for group in &self.groups {
            for range in group.window(frame) {
                for &g in group.gates.get(range).unwrap_or(&[]) {
                    let g = g as usize;
                    let (s, e) = (a.gate_start[g] as usize, a.gate_start[g + 1] as usize);
                    for &u in &a.gate_units[s..e] {
                        let u = u as usize;
                        if st.stamp[u] != st.now {
                            st.stamp[u] = st.now;
                            st.count[u] = 0;
                        }
                        st.count[u] += 1;
                        if st.count[u] == a.need[u] {
                            st.active.push(u as u32);
                        }
                    }
                }
            }
        }
    }

    fn is_active(&self, st: &State, u: usize) -> bool {
        st.stamp[u] == st.now && st.count[u] == self.units.need[u]
    }

    /// Writes the constants of the units that are not active now but may hold other values.
    fn force_inactive(&self, st: &mut State, regs: &mut [f64]) {
        let a = &self.units;
        let write = |u: usize, regs: &mut [f64]| {
            let r = a.forced_start[u] as usize..a.forced_start[u + 1] as usize;
            for (&d, &v) in a.forced_regs[r.clone()].iter().zip(&a.forced_values[r]) {
                regs[d as usize] = v;
            }
        };
        if st.stale {
            for u in 0..a.need.len() {
                if !self.is_active(st, u) {
                    write(u, regs);
                }
            }
            st.stale = false;
        } else {
            for &u in &st.last {
                if !self.is_active(st, u as usize) {
                    write(u as usize, regs);
                }
            }
        }
    }

    /// Evaluates the active units and the registers between, in register order.
    fn run_active(&self, tape: &Tape, frame: &Frame, st: &mut State, regs: &mut [f64]) {
        let mut mark = |r: u32| {
            if let Some(w) = st.bits.get_mut(r as usize / 64) {
                *w |= 1 << (r % 64);
            }
        };
        for &u in &st.active {
            let u = u as usize;
            let r = self.units.reg_start[u] as usize..self.units.reg_start[u + 1] as usize;
            self.units.regs[r].iter().for_each(|&r| mark(r));
        }
        self.between.iter().for_each(|&r| mark(r));
        for (w, word) in st.bits.iter_mut().enumerate() {
            let mut bits = std::mem::take(word);
            while bits != 0 {
                let i = w * 64 + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                regs[i] = tape.eval_op(tape.ops[i], frame, regs);
            }
        }
        std::mem::swap(&mut st.active, &mut st.last);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::rng::SplitMix64;
    use crate::engine::frame::PerceptSlot;
    use crate::logic::{Implication, LogicConfig, TNorm};

    /// Similarities a tape can name: circular and linear with bias 0 (gates), a crisp one, one
    /// with a bias (not a gate); index 4 names none.
    fn similarities() -> Vec<Similarity> {
        vec![
            Similarity::new(20.0, 40.0, 1.0, 0.0, Some(360.0)),
            Similarity::new(0.6, 1.2, 1.0, 0.0, None),
            Similarity::new(2.0, 0.0, 0.9, 0.0, Some(10.0)),
            Similarity::new(0.6, 1.2, 0.9, 0.1, None),
        ]
    }

    /// A degree in the domain, now and then 0 or 1.
    fn degree(rng: &mut SplitMix64) -> f64 {
        match rng.below(6) {
            0 => 0.0,
            1 => 1.0,
            _ => rng.unit(),
        }
    }

    /// A random well-formed tape: per "place", matches against its own centres combined with
    /// shared degrees by every kind of instruction, and maxima across places.
    fn random_tape(rng: &mut SplitMix64, n: usize, slots: u32) -> Tape {
        let tnorm = [TNorm::Min, TNorm::Product, TNorm::Lukasiewicz][rng.below(3)];
        let implication = [Implication::Residuum, Implication::MinMp][rng.below(2)];
        let mut ops = Vec::with_capacity(n);
        for i in 0..n {
            let kind = if i == 0 { rng.below(3) } else { rng.below(11) };
            // Mostly recent operands, so that chains form as a schema's do.
            let near = |rng: &mut SplitMix64| (i - 1 - rng.below(i.min(6))) as Reg;
            let (a, b) = if i == 0 {
                (0, 0)
            } else if rng.below(3) == 0 {
                (rng.below(i) as Reg, near(rng))
            } else {
                (near(rng), near(rng))
            };
            let op = match kind {
                0 => Op::Const(degree(rng)),
                1 => Op::Degree(PerceptSlot(rng.below(slots as usize + 1) as u32)),
                2 | 3 => Op::Match {
                    slot: PerceptSlot(rng.below(slots as usize + 1) as u32),
                    similarity: rng.below(5) as u32,
                    centre: match rng.below(16) {
                        0 => f64::NAN,
                        1 => f64::INFINITY,
                        _ => 360.0 * rng.unit() - 90.0,
                    },
                    half: [0.0, 3.0 * rng.unit(), -1.0, f64::NAN][rng.below(4)],
                },
                4 => Op::Min(a, b),
                5 => Op::Max(a, b),
                6 | 7 => Op::TNorm(a, b),
                8 => Op::Not(a),
                9 => Op::Implies(a, b),
                _ => Op::Detach(a, degree(rng)),
            };
            ops.push(op);
        }
        Tape {
            ops,
            similarities: similarities(),
            similarity_names: Vec::new(),
            logic: LogicConfig {
                tnorm,
                implication,
                ..LogicConfig::default()
            },
        }
    }

    /// A frame whose values fall near some match's centre (or anywhere, or are NaN or
    /// infinite), with degrees now and then missing, NaN, out of range or `−0`.
    fn random_frame(rng: &mut SplitMix64, tape: &Tape, slots: u32) -> Frame {
        let centres: Vec<f64> = tape
            .ops
            .iter()
            .filter_map(|op| match *op {
                Op::Match { centre, .. } if centre.is_finite() => Some(centre),
                _ => None,
            })
            .collect();
        let mut frame = Frame::new(slots as usize);
        for s in 0..slots as usize {
            frame.degree[s] = match rng.below(14) {
                0 => f64::NAN,
                1 => -0.0,
                2 => 1.5,
                3 => -0.5,
                _ => degree(rng),
            };
            let near = centres.get(rng.below(centres.len().max(1))).copied();
            frame.value[s] = match rng.below(10) {
                0 => f64::NAN,
                1 => f64::NEG_INFINITY,
                2 => 720.0 * rng.unit() - 360.0,
                3 => near.map_or(0.0, |c| c + 360.0 * (rng.below(3) as f64 - 1.0)),
                _ => near.map_or(0.0, |c| c + 60.0 * (rng.unit() - 0.5)),
            };
        }
        frame
    }

    #[test]
    fn gated_registers_are_the_interpreters_bit_for_bit() {
        let mut rng = SplitMix64::new(16);
        let mut planned = 0;
        for case in 0..400 {
            let (n, slots) = (1 + rng.below(160), 1 + rng.below(4) as u32);
            let tape = random_tape(&mut rng, n, slots);
            // Every register is read from outside but some matches: those may be embedded.
            let observed: Vec<Reg> = (0..n as Reg)
                .filter(|&r| !matches!(tape.ops[r as usize], Op::Match { .. }) || rng.below(2) == 0)
                .collect();
            let Some(mut gated) = Gated::new(&tape, &observed) else {
                continue;
            };
            planned += 1;
            let columns = Columns::new(&tape).expect("a well-formed tape regroups");
            let mut got = vec![-7.0; n];
            for step in 0..12 {
                let frame = random_frame(&mut rng, &tape, slots);
                let (mut want, mut by_columns) = (vec![0.0; n], vec![0.0; n]);
                tape.eval(&frame, &mut want);
                columns.eval(&tape, &frame, &mut by_columns);
                gated.eval(&tape, &frame, &mut got);
                // With a `−0` degree the evaluators' `min(−0, 0)` may keep either zero: the
                // frame is evaluated whole, as the columns do (the engine's evaluator before).
                let reference = if has_negative_zero(&frame) {
                    &by_columns
                } else {
                    &want
                };
                for &r in &observed {
                    let (w, g) = (reference[r as usize], got[r as usize]);
                    assert_eq!(
                        w.to_bits(),
                        g.to_bits(),
                        "case {case} step {step} reg {r}: {w} vs {g}"
                    );
                }
            }
        }
        assert!(planned > 200, "only {planned} tapes had gates");
    }

    #[test]
    fn a_schema_over_many_places_evaluates_only_the_places_in_the_window() {
        // Per place: a circular match, a linear one, their min detached; the supports maxed.
        let mut ops = vec![Op::Degree(PerceptSlot(2))];
        let mut supports = Vec::new();
        for p in 0..100 {
            let k = ops.len() as Reg;
            let centre = 3.6 * p as f64;
            ops.push(Op::Match {
                slot: PerceptSlot(0),
                similarity: 0,
                centre,
                half: 0.0,
            });
            ops.push(Op::Match {
                slot: PerceptSlot(1),
                similarity: 1,
                centre: p as f64,
                half: 0.0,
            });
            ops.push(Op::Min(k, k + 1));
            ops.push(Op::TNorm(k + 2, 0));
            ops.push(Op::Detach(k + 3, 0.8));
            supports.push(k + 4);
        }
        let tape = Tape {
            ops,
            similarities: similarities(),
            similarity_names: Vec::new(),
            logic: LogicConfig::default(),
        };
        let mut gated = Gated::new(&tape, &supports).expect("the matches are gates");
        // One unit per place: the min, t-norm and detachment share the place's two gates.
        assert_eq!(gated.units(), 100);
        let mut frame = Frame::new(3);
        frame.set(PerceptSlot(0), 0.9, Some(1.0));
        frame.set(PerceptSlot(1), 0.9, Some(99.5));
        frame.set(PerceptSlot(2), 0.7, None);
        let (mut want, mut got) = (vec![0.0; tape.len()], vec![0.0; tape.len()]);
        tape.eval(&frame, &mut want);
        gated.eval(&tape, &frame, &mut got);
        // Angle 1° is within 50° of places 0–14 and 87–99 (around 360°); distance 99.5 within
        // 1.5 of places 98 and 99 only.
        assert_eq!(gated.state.last.len(), 2);
        for &r in &supports {
            assert_eq!(want[r as usize].to_bits(), got[r as usize].to_bits());
        }
        assert!(got[supports[99] as usize] > 0.0 && got[supports[50] as usize] == 0.0);
    }
}
