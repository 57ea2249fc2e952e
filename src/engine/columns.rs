//! The tape evaluated kind by kind: a [`Tape`] regrouped into runs of one instruction kind whose
//! operands are all computed by earlier runs, so that a step dispatches once per run instead of
//! once per instruction.
//!
//! A map of many places compiles the same rule schema once per place, with different
//! parameters; the tape interleaves the places' instructions, and [`Tape::eval`] pays a branch
//! on the instruction kind for each (the largest part of a step on a large map). Here every
//! instruction gets a *level* — 0 for a leaf, one more than its deepest operand otherwise — and
//! the instructions are evaluated level by level, each level grouped by kind (and by similarity
//! or operator), each group one tight loop over structure-of-arrays columns. Every register is
//! still written by the same floating-point operations on the same operand values as in
//! [`Tape::eval`], only in another order, so the registers are bit for bit the same; that is
//! tested against the interpreter on random tapes.
//!
//! Built once at load time; [`Columns::eval`] allocates nothing and cannot panic (a register
//! file of the wrong length is evaluated by [`Tape::eval`] instead).

use super::frame::Frame;
use super::tape::{Op, Tape};
use crate::logic::{clamp_degree, Implication, LogicConfig, TNorm};

/// What one run computes; the instruction's own parameters are in the columns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Kind {
    Const,
    Degree,
    /// With the index of its similarity.
    Match(u32),
    Min,
    Max,
    TNorm,
    Not,
    Implies,
    Detach,
}

/// One run: instructions `start..end` of the columns, all of one kind.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Run {
    kind: Kind,
    start: usize,
    end: usize,
}

/// A tape regrouped into runs over columns (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Columns {
    runs: Vec<Run>,
    /// The register each instruction writes.
    dest: Vec<u32>,
    /// First operand, or the percept slot of a leaf (0 for a constant).
    a: Vec<u32>,
    /// Second operand (0 when there is none).
    b: Vec<u32>,
    /// The constant, the detachment weight, or a match's centre (0 otherwise).
    x: Vec<f64>,
    /// A match's half width (0 otherwise).
    half: Vec<f64>,
    /// Registers the tape writes, which the register file must hold.
    len: usize,
}

/// An instruction's kind and its column entries `(a, b, x, half)`.
fn split(op: Op) -> (Kind, [u32; 2], [f64; 2]) {
    match op {
        Op::Const(c) => (Kind::Const, [0, 0], [c, 0.0]),
        Op::Degree(s) => (Kind::Degree, [s.0, 0], [0.0, 0.0]),
        Op::Match {
            slot,
            similarity,
            centre,
            half,
        } => (Kind::Match(similarity), [slot.0, 0], [centre, half]),
        Op::Min(a, b) => (Kind::Min, [a, b], [0.0, 0.0]),
        Op::Max(a, b) => (Kind::Max, [a, b], [0.0, 0.0]),
        Op::TNorm(a, b) => (Kind::TNorm, [a, b], [0.0, 0.0]),
        Op::Not(a) => (Kind::Not, [a, 0], [0.0, 0.0]),
        Op::Implies(a, b) => (Kind::Implies, [a, b], [0.0, 0.0]),
        Op::Detach(a, w) => (Kind::Detach, [a, 0], [w, 0.0]),
    }
}

impl Columns {
    /// Regroups `tape`, or `None` when an instruction reads a register that is not an earlier
    /// one (no compiled tape does; [`Tape::eval`] then stays the evaluator, whatever it makes
    /// of such a tape).
    pub fn new(tape: &Tape) -> Option<Columns> {
        Columns::subset(tape, |_| true)
    }

    /// Like [`Columns::new`], but [`Columns::eval`] writes only the registers `keep` selects
    /// (their operands must be written before, by this or another evaluator).
    pub fn subset(tape: &Tape, keep: impl Fn(usize) -> bool) -> Option<Columns> {
        let n = tape.ops.len();
        let mut level = vec![0u32; n];
        let mut order: Vec<(u32, Kind, u32)> = Vec::with_capacity(n);
        for (i, op) in tape.ops.iter().enumerate() {
            let mut l = 0;
            for r in op.operands().into_iter().flatten() {
                let r = r as usize;
                if r >= i {
                    return None;
                }
                l = l.max(level[r] + 1);
            }
            level[i] = l;
            if keep(i) {
                order.push((l, split(*op).0, u32::try_from(i).ok()?));
            }
        }
        order.sort_unstable();
        let mut c = Columns {
            runs: Vec::new(),
            dest: Vec::with_capacity(n),
            a: Vec::with_capacity(n),
            b: Vec::with_capacity(n),
            x: Vec::with_capacity(n),
            half: Vec::with_capacity(n),
            len: n,
        };
        for (k, &(l, kind, i)) in order.iter().enumerate() {
            let (_, [a, b], [x, half]) = split(tape.ops[i as usize]);
            let same = k > 0 && order[k - 1].0 == l && order[k - 1].1 == kind;
            match c.runs.last_mut() {
                Some(run) if same => run.end = k + 1,
                _ => c.runs.push(Run {
                    kind,
                    start: k,
                    end: k + 1,
                }),
            }
            c.dest.push(i);
            c.a.push(a);
            c.b.push(b);
            c.x.push(x);
            c.half.push(half);
        }
        Some(c)
    }

    /// Number of runs (one dispatch each per step).
    pub fn runs(&self) -> usize {
        self.runs.len()
    }

    /// Evaluates every register of `tape` (the tape these columns were built from) for `frame`:
    /// the same registers as [`Tape::eval`].
    pub fn eval(&self, tape: &Tape, frame: &Frame, regs: &mut [f64]) {
        if regs.len() != self.len || tape.ops.len() != self.len {
            tape.eval(frame, regs);
            return;
        }
        for run in &self.runs {
            let r = run.start..run.end;
            let (dest, a, b) = (
                &self.dest[r.clone()],
                &self.a[r.clone()],
                &self.b[r.clone()],
            );
            let x = &self.x[r.clone()];
            match run.kind {
                Kind::Const => {
                    for (&d, &c) in dest.iter().zip(x) {
                        regs[d as usize] = c;
                    }
                }
                Kind::Degree => {
                    for (&d, &s) in dest.iter().zip(a) {
                        regs[d as usize] = degree(frame, s);
                    }
                }
                Kind::Match(sim) => self.matches(tape, sim, run, frame, regs),
                Kind::Min => binary(regs, dest, a, b, f64::min),
                Kind::Max => binary(regs, dest, a, b, f64::max),
                Kind::TNorm => match tape.logic.tnorm {
                    // One loop per t-norm (each calling `apply` on a constant, so the same
                    // operations): no branch on the t-norm per instruction.
                    TNorm::Min => binary(regs, dest, a, b, |p, q| TNorm::Min.apply(p, q)),
                    TNorm::Product => binary(regs, dest, a, b, |p, q| TNorm::Product.apply(p, q)),
                    TNorm::Lukasiewicz => {
                        binary(regs, dest, a, b, |p, q| TNorm::Lukasiewicz.apply(p, q))
                    }
                },
                Kind::Not => {
                    for (&d, &p) in dest.iter().zip(a) {
                        regs[d as usize] = 1.0 - regs[p as usize];
                    }
                }
                Kind::Implies => {
                    let l: LogicConfig = tape.logic;
                    binary(regs, dest, a, b, |p, q| l.implies(p, q))
                }
                Kind::Detach => detach(tape.logic, regs, dest, a, x),
            }
        }
    }

    /// A run of matches against similarity `sim`, as [`Tape::eval`] computes each.
    fn matches(&self, tape: &Tape, sim: u32, run: &Run, frame: &Frame, regs: &mut [f64]) {
        let r = run.start..run.end;
        let (dest, slot) = (&self.dest[r.clone()], &self.a[r.clone()]);
        let (centre, half) = (&self.x[r.clone()], &self.half[r]);
        let shape = tape.similarities.get(sim as usize);
        for k in 0..dest.len() {
            let s = slot[k] as usize;
            let d = clamp_degree(frame.degree.get(s).copied().unwrap_or(0.0));
            let v = frame.value.get(s).copied().unwrap_or(f64::NAN);
            let m = shape.map_or(0.0, |t| t.degree_within(v, centre[k], half[k]));
            regs[dest[k] as usize] = d.min(clamp_degree(m));
        }
    }
}

/// The degree of percept slot `s` as [`Tape::eval`] reads it (missing → 0).
fn degree(frame: &Frame, s: u32) -> f64 {
    clamp_degree(frame.degree.get(s as usize).copied().unwrap_or(0.0))
}

/// A run of detachments `regs[dest[k]] = logic.detach(regs[a[k]], w[k])`, one loop per reading
/// of `->` and t-norm (each calling `detach` on a constant configuration, so the same operations).
fn detach(logic: LogicConfig, regs: &mut [f64], dest: &[u32], a: &[u32], w: &[f64]) {
    let with = |tnorm, implication| LogicConfig {
        tnorm,
        implication,
        ..logic
    };
    match (logic.implication, logic.tnorm) {
        (Implication::MinMp, _) => {
            let l = with(TNorm::Min, Implication::MinMp);
            binary_const(regs, dest, a, w, |p, q| l.detach(p, q))
        }
        (Implication::Residuum, TNorm::Min) => {
            let l = with(TNorm::Min, Implication::Residuum);
            binary_const(regs, dest, a, w, |p, q| l.detach(p, q))
        }
        (Implication::Residuum, TNorm::Product) => {
            let l = with(TNorm::Product, Implication::Residuum);
            binary_const(regs, dest, a, w, |p, q| l.detach(p, q))
        }
        (Implication::Residuum, TNorm::Lukasiewicz) => {
            let l = with(TNorm::Lukasiewicz, Implication::Residuum);
            binary_const(regs, dest, a, w, |p, q| l.detach(p, q))
        }
    }
}

/// `regs[dest[k]] = f(regs[a[k]], w[k])` for each `k`.
#[inline(always)]
fn binary_const(regs: &mut [f64], dest: &[u32], a: &[u32], w: &[f64], f: impl Fn(f64, f64) -> f64) {
    for ((&d, &p), &q) in dest.iter().zip(a).zip(w) {
        regs[d as usize] = f(regs[p as usize], q);
    }
}

/// `regs[dest[k]] = f(regs[a[k]], regs[b[k]])` for each `k`.
#[inline(always)]
fn binary(regs: &mut [f64], dest: &[u32], a: &[u32], b: &[u32], f: impl Fn(f64, f64) -> f64) {
    for ((&d, &p), &q) in dest.iter().zip(a).zip(b) {
        regs[d as usize] = f(regs[p as usize], regs[q as usize]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::rng::SplitMix64;
    use crate::engine::frame::PerceptSlot;
    use crate::engine::tape::Reg;
    use crate::logic::{Implication, Similarity, TNorm};

    /// A degree or value as streams carry them: mostly in range, now and then NaN, infinite or
    /// out of `[0, 1]`.
    fn reading(rng: &mut SplitMix64, scale: f64) -> f64 {
        match rng.below(12) {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => -0.5 * scale,
            3 => 1.5 * scale,
            4 => 0.0,
            _ => scale * rng.unit(),
        }
    }

    /// A random well-formed tape of `n` instructions over `slots` percept slots (operands name
    /// earlier registers; some slots lie beyond the frame, some similarities beyond the list).
    fn random_tape(rng: &mut SplitMix64, n: usize, slots: u32) -> Tape {
        let tnorm = [TNorm::Min, TNorm::Product, TNorm::Lukasiewicz][rng.below(3)];
        let implication = [Implication::Residuum, Implication::MinMp][rng.below(2)];
        let mut ops = Vec::with_capacity(n);
        for i in 0..n {
            let kinds = if i == 0 { 3 } else { 9 };
            let kind = rng.below(kinds);
            let (a, b) = (rng.below(i.max(1)) as Reg, rng.below(i.max(1)) as Reg);
            let op = match kind {
                0 => Op::Const(reading(rng, 1.0)),
                1 => Op::Degree(PerceptSlot(rng.below(slots as usize + 2) as u32)),
                2 => Op::Match {
                    slot: PerceptSlot(rng.below(slots as usize + 2) as u32),
                    similarity: rng.below(4) as u32,
                    centre: 360.0 * rng.unit(),
                    half: [0.0, 5.0 * rng.unit(), -1.0][rng.below(3)],
                },
                3 => Op::Min(a, b),
                4 => Op::Max(a, b),
                5 => Op::TNorm(a, b),
                6 => Op::Not(a),
                7 => Op::Implies(a, b),
                _ => Op::Detach(a, rng.unit()),
            };
            ops.push(op);
        }
        Tape {
            ops,
            similarities: vec![
                Similarity::new(20.0, 40.0, 1.0, 0.0, Some(360.0)),
                Similarity::new(0.6, 1.2, 0.9, 0.1, None),
                Similarity::new(0.0, 0.0, 1.0, 0.0, None),
            ],
            similarity_names: Vec::new(),
            logic: LogicConfig {
                tnorm,
                implication,
                ..LogicConfig::default()
            },
        }
    }

    #[test]
    fn columns_give_the_interpreters_registers_bit_for_bit() {
        let mut rng = SplitMix64::new(16);
        for case in 0..300 {
            let (n, slots) = (1 + rng.below(200), 1 + rng.below(12) as u32);
            let tape = random_tape(&mut rng, n, slots);
            let columns = Columns::new(&tape).expect("a well-formed tape regroups");
            assert!(columns.runs() <= n);
            for _ in 0..5 {
                let mut frame = Frame::new(slots as usize);
                for s in 0..slots as usize {
                    frame.degree[s] = reading(&mut rng, 1.0);
                    frame.value[s] = reading(&mut rng, 400.0);
                }
                let (mut want, mut got) = (vec![0.0; n], vec![-7.0; n]);
                tape.eval(&frame, &mut want);
                columns.eval(&tape, &frame, &mut got);
                for (r, (w, g)) in want.iter().zip(&got).enumerate() {
                    assert_eq!(w.to_bits(), g.to_bits(), "case {case}, register {r}");
                }
            }
        }
    }

    #[test]
    fn a_tape_reading_a_later_register_keeps_the_interpreter() {
        let tape = Tape {
            ops: vec![Op::Const(0.5), Op::Min(0, 2), Op::Const(0.25)],
            similarities: Vec::new(),
            similarity_names: Vec::new(),
            logic: LogicConfig::default(),
        };
        assert!(Columns::new(&tape).is_none());
    }

    #[test]
    fn a_schema_over_many_places_takes_few_runs() {
        // Per place: two matches, their min, a detachment and a max with a shared degree.
        let mut ops = vec![Op::Degree(PerceptSlot(2))];
        for p in 0..100 {
            let k = ops.len() as Reg;
            let centre = p as f64;
            ops.push(Op::Match {
                slot: PerceptSlot(0),
                similarity: 0,
                centre,
                half: 0.0,
            });
            ops.push(Op::Match {
                slot: PerceptSlot(1),
                similarity: 1,
                centre,
                half: 0.0,
            });
            ops.push(Op::Min(k, k + 1));
            ops.push(Op::Detach(k + 2, 0.8));
            ops.push(Op::Max(k + 3, 0));
        }
        let tape = Tape {
            ops,
            similarities: random_tape(&mut SplitMix64::new(1), 1, 1).similarities,
            similarity_names: Vec::new(),
            logic: LogicConfig::default(),
        };
        // Level 0: the degree and the two similarities' matches; then min, detach, max.
        assert_eq!(Columns::new(&tape).map(|c| c.runs()), Some(6));
    }
}
