//! The compiled form of a rule set: a flat instruction tape over a register file, its evaluator,
//! and its printer (what `lplace explain` shows).
//!
//! Each instruction writes one register from registers before it, so one forward pass evaluates
//! every degree function at once, with shared sub-expressions computed once. The tape is built by
//! `engine::compile` and never changes afterwards; evaluation allocates nothing.
//!
//! Semantics of each instruction (DESIGN §3), `T` the file's t-norm:
//!
//! | op              | value                                              | rule syntax          |
//! |-----------------|----------------------------------------------------|----------------------|
//! | `Const(c)`      | `c`                                                | `0.3`, map facts     |
//! | `Degree(s)`     | degree of percept slot `s` (missing → 0)           | `laser_wall(p, N, t)`|
//! | `Match(s, σ, θ)`| `min(degree(s), σ(value(s); θ))`                   | `beacon_angle(a, A_i, t)` |
//! | `Min(a, b)`     | `min(a, b)`                                        | `&`                  |
//! | `Max(a, b)`     | `max(a, b)`                                        | `(+)`, several derivations |
//! | `TNorm(a, b)`   | `T(a, b)`                                          | `*`                  |
//! | `Not(a)`        | `1 − a`                                            | `!`                  |
//! | `Implies(a, b)` | `R_T(a, b)` (residuum) or `max(1 − a, b)` (min-MP) | nested `->`          |
//! | `Detach(a, w)`  | `T(a, w)` (residuum) or `min(a, w)` (min-MP)       | `(φ -> head, w)`, `(φ, w)` |

use super::frame::{Frame, PerceptSlot, PerceptTable};
use crate::logic::{clamp_degree, LogicConfig, Similarity, TNorm};
use std::fmt::Write as _;

/// Index of a register (= of the instruction that writes it).
pub type Reg = u32;

/// One instruction; operands always name earlier registers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Op {
    /// A constant degree.
    Const(f64),
    /// The degree of a percept instance.
    Degree(PerceptSlot),
    /// A percept's degree, capped by the similarity of its value with an expected value.
    Match {
        /// The percept instance.
        slot: PerceptSlot,
        /// Index into the tape's similarities.
        similarity: u32,
        /// The expected value θ (the middle of an expected range).
        centre: f64,
        /// Half the width of the expected range (0 for a single value).
        half: f64,
    },
    /// Lattice conjunction.
    Min(Reg, Reg),
    /// Lattice disjunction.
    Max(Reg, Reg),
    /// The file's t-norm.
    TNorm(Reg, Reg),
    /// Negation `1 − a`.
    Not(Reg),
    /// Nested implication.
    Implies(Reg, Reg),
    /// Detachment of a weighted conclusion.
    Detach(Reg, f64),
}

impl Op {
    /// The registers this instruction reads.
    pub fn operands(&self) -> [Option<Reg>; 2] {
        match *self {
            Op::Const(_) | Op::Degree(_) | Op::Match { .. } => [None, None],
            Op::Not(a) | Op::Detach(a, _) => [Some(a), None],
            Op::Min(a, b) | Op::Max(a, b) | Op::TNorm(a, b) | Op::Implies(a, b) => {
                [Some(a), Some(b)]
            }
        }
    }

    /// The same instruction with its operands renamed by `f`.
    pub fn map_operands(self, f: impl Fn(Reg) -> Reg) -> Op {
        match self {
            Op::Not(a) => Op::Not(f(a)),
            Op::Detach(a, w) => Op::Detach(f(a), w),
            Op::Min(a, b) => Op::Min(f(a), f(b)),
            Op::Max(a, b) => Op::Max(f(a), f(b)),
            Op::TNorm(a, b) => Op::TNorm(f(a), f(b)),
            Op::Implies(a, b) => Op::Implies(f(a), f(b)),
            other => other,
        }
    }
}

/// An instruction tape with the similarities and operators it refers to.
#[derive(Debug, Clone, PartialEq)]
pub struct Tape {
    /// Instructions in evaluation order.
    pub ops: Vec<Op>,
    /// Similarity shapes referenced by `Op::Match`.
    pub similarities: Vec<Similarity>,
    /// Their names, for printing.
    pub similarity_names: Vec<String>,
    /// The file's operators.
    pub logic: LogicConfig,
}

impl Tape {
    /// Number of registers the evaluator needs.
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    /// True for an empty tape.
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Evaluates every register for `frame`. `regs` must have [`Tape::len`] entries (extra
    /// instructions are skipped if it is shorter, rather than panicking).
    ///
    /// Slots beyond the frame's length read as missing; degrees are sanitised by
    /// [`clamp_degree`].
    pub fn eval(&self, frame: &Frame, regs: &mut [f64]) {
        let n = self.ops.len().min(regs.len());
        for i in 0..n {
            regs[i] = self.eval_op(self.ops[i], frame, regs);
        }
    }

    /// The value instruction `op` writes for `frame`, its operands read from `regs` (which must
    /// hold them): one step of [`Tape::eval`], shared with the evaluators that skip registers.
    #[inline(always)]
    pub(crate) fn eval_op(&self, op: Op, frame: &Frame, regs: &[f64]) -> f64 {
        match op {
            Op::Const(c) => c,
            Op::Degree(s) => clamp_degree(frame.degree.get(s.0 as usize).copied().unwrap_or(0.0)),
            Op::Match {
                slot,
                similarity,
                centre,
                half,
            } => {
                let s = slot.0 as usize;
                let d = clamp_degree(frame.degree.get(s).copied().unwrap_or(0.0));
                let x = frame.value.get(s).copied().unwrap_or(f64::NAN);
                let sim = self
                    .similarities
                    .get(similarity as usize)
                    .map_or(0.0, |t| t.degree_within(x, centre, half));
                d.min(clamp_degree(sim))
            }
            Op::Min(a, b) => regs[a as usize].min(regs[b as usize]),
            Op::Max(a, b) => regs[a as usize].max(regs[b as usize]),
            Op::TNorm(a, b) => self.logic.tnorm.apply(regs[a as usize], regs[b as usize]),
            Op::Not(a) => 1.0 - regs[a as usize],
            Op::Implies(a, b) => self.logic.implies(regs[a as usize], regs[b as usize]),
            Op::Detach(a, w) => self.logic.detach(regs[a as usize], w),
        }
    }

    /// Prints register `r` as a closed-form formula over percept degrees, the way paper 003
    /// eq. (6) reads. Nested `min`/`max` are flattened; `name ≈ θ` is a percept whose value is
    /// compared with θ.
    pub fn render(&self, r: Reg, percepts: &PerceptTable) -> String {
        let mut s = String::new();
        self.render_into(&mut s, r, percepts, false);
        s
    }

    /// Prints register `r` in the paper's dissimilarity form: `δ = 1 − degree`, so `min` of
    /// confidences prints as `max` of dissimilarities (paper 003 eq. (6): `β = max(β_θ, β_d)`).
    pub fn render_dissimilarity(&self, r: Reg, percepts: &PerceptTable) -> String {
        let mut s = String::new();
        self.render_into(&mut s, r, percepts, true);
        s
    }

    fn collect_chain(&self, r: Reg, same: fn(&Op) -> Option<(Reg, Reg)>, out: &mut Vec<Reg>) {
        match self.ops.get(r as usize).and_then(same) {
            Some((a, b)) => {
                self.collect_chain(a, same, out);
                self.collect_chain(b, same, out);
            }
            None => out.push(r),
        }
    }

    /// Writes register `r` as a formula; `dual` writes its dissimilarity `1 − degree` instead,
    /// with De Morgan moving the complement to the leaves where it can, so that the text reads
    /// as a combination of dissimilarities.
    fn render_into(&self, s: &mut String, r: Reg, percepts: &PerceptTable, dual: bool) {
        let Some(op) = self.ops.get(r as usize) else {
            s.push('?');
            return;
        };
        match *op {
            Op::Const(c) => {
                let _ = write!(s, "{}", fmt_num(if dual { 1.0 - c } else { c }));
            }
            Op::Degree(slot) => push_leaf(s, &slot_name(percepts, slot), dual),
            Op::Match {
                slot,
                similarity,
                centre,
                half,
            } => {
                let sim = self
                    .similarity_names
                    .get(similarity as usize)
                    .map_or("?", String::as_str);
                let expect = if half > 0.0 {
                    format!("{}..{}", fmt_num(centre - half), fmt_num(centre + half))
                } else {
                    fmt_num(centre)
                };
                let text = format!("{} ~{} {}", slot_name(percepts, slot), sim, expect);
                push_leaf(s, &text, dual);
            }
            Op::Min(..) | Op::Max(..) => {
                self.render_chain(s, r, matches!(op, Op::Min(..)), percepts, dual)
            }
            Op::TNorm(a, b) => self.render_tnorm(s, (a, b), percepts, dual),
            Op::Not(a) => {
                // In the dual form this reads 1 − δ(a), which is a's degree: still correct.
                s.push_str("1 - ");
                self.render_into(s, a, percepts, dual);
            }
            Op::Implies(a, b) => {
                let f = if dual { "1 - imp" } else { "imp" };
                let _ = write!(s, "{f}(");
                self.render_into(s, a, percepts, false);
                s.push_str(", ");
                self.render_into(s, b, percepts, false);
                s.push(')');
            }
            Op::Detach(a, w) => self.render_detach(s, a, w, percepts, dual),
        }
    }

    /// A chain of nested `Min` (or `Max`) registers, flattened into one `min(a, b, c)`.
    fn render_chain(
        &self,
        s: &mut String,
        r: Reg,
        is_min: bool,
        percepts: &PerceptTable,
        dual: bool,
    ) {
        let same: fn(&Op) -> Option<(Reg, Reg)> = if is_min {
            |o| {
                if let Op::Min(a, b) = *o {
                    Some((a, b))
                } else {
                    None
                }
            }
        } else {
            |o| {
                if let Op::Max(a, b) = *o {
                    Some((a, b))
                } else {
                    None
                }
            }
        };
        let mut parts = Vec::new();
        self.collect_chain(r, same, &mut parts);
        // De Morgan: 1 − min(a, b) = max(1 − a, 1 − b).
        s.push_str(if is_min != dual { "min(" } else { "max(" });
        for (i, p) in parts.iter().enumerate() {
            if i > 0 {
                s.push_str(", ");
            }
            self.render_into(s, *p, percepts, dual);
        }
        s.push(')');
    }

    /// The t-norm of `a` and `b`; in the dual form, its t-conorm of the dissimilarities.
    fn render_tnorm(
        &self,
        s: &mut String,
        (a, b): (Reg, Reg),
        percepts: &PerceptTable,
        dual: bool,
    ) {
        let f = match (self.logic.tnorm, dual) {
            (TNorm::Min, false) => "min",
            (TNorm::Min, true) => "max",
            (TNorm::Product, false) => "prod",
            (TNorm::Product, true) => "probsum",
            (TNorm::Lukasiewicz, false) => "luk",
            (TNorm::Lukasiewicz, true) => "boundedsum",
        };
        let _ = write!(s, "{f}(");
        self.render_into(s, a, percepts, dual);
        s.push_str(", ");
        self.render_into(s, b, percepts, dual);
        s.push(')');
    }

    /// A rule's detachment of weight `w`: its body is read as a degree in both forms, only the
    /// result is complemented in the dual.
    fn render_detach(&self, s: &mut String, a: Reg, w: f64, percepts: &PerceptTable, dual: bool) {
        let f = match self.logic.implication {
            crate::logic::Implication::Residuum => match self.logic.tnorm {
                TNorm::Min => "min",
                TNorm::Product => "prod",
                TNorm::Lukasiewicz => "luk",
            },
            crate::logic::Implication::MinMp => "min",
        };
        if dual {
            let _ = write!(s, "1 - {f}(");
            self.render_into(s, a, percepts, false);
        } else {
            let _ = write!(s, "{f}(");
            self.render_into(s, a, percepts, false);
        }
        let _ = write!(s, ", {})", fmt_num(w));
    }
}

/// A leaf of a formula; in the dual form, wrapped as its dissimilarity `δ[…]`.
fn push_leaf(s: &mut String, text: &str, dual: bool) {
    if dual {
        let _ = write!(s, "δ[{text}]");
    } else {
        s.push_str(text);
    }
}

/// The percept instance in `slot`, or `slotN` when the table does not know it.
fn slot_name(percepts: &PerceptTable, slot: PerceptSlot) -> String {
    percepts
        .instance(slot)
        .map_or_else(|| format!("slot{}", slot.0), |p| p.to_string())
}

/// Shortest decimal form of a number for formulas (`4.6`, not `4.600000`).
fn fmt_num(x: f64) -> String {
    let r = (x * 1e6).round() / 1e6;
    format!("{r}")
}
