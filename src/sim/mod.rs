//! A simulated robot with ground truth: it walks the map's paths and emits the percept stream its
//! sensors would give — noisy, sometimes missing, sometimes wrong — with the true place and pose
//! on every frame, so that evaluation and tracking can be scored.
//!
//! # What each place looks like
//! Derived from the map and the rule file, per declared percept instance:
//! - a percept with an `expect` argument is a **measured value** compared with a place
//!   parameter; the rule file says which one (`beacon_angle(a, A_i, t)` → parameter `A`,
//!   `landmark_range(r, g, range_i(g), t)` → `range` keyed by the landmark, which the map computes
//!   from geometry when not written). At a place the value is that parameter plus noise
//!   (degrees of arc when the similarity is periodic, a fraction of the value otherwise);
//! - a percept with one domain argument and no value is a **wall** seen towards that direction
//!   (`sonar_wall(North)`), emitted where the place has that wall;
//! - with two domain arguments it is a **corner** (`laser_corner(North, East)`).
//!
//! # Errors the sensors make
//! Each percept is missing with `p_missing`; sonar walls are occluded with `p_occlude`; with
//! `p_mislabel` a frame's measured values are those of another place (a mislabelled beacon); with
//! `p_spurious` a corner that is not there is reported. Between places the robot emits only weak,
//! partial percepts of the nearest place. A **kidnap** (`kidnap_at`) teleports the robot to a
//! random other place without the odometry noticing.
//!
//! # Motion
//! A random walk along the graph's edges (straight lines between place positions, never straight
//! back unless it is a dead end), `speed` metres per frame with noise, a short random dwell at each
//! place; odometry reports the motion with multiplicative noise. Frames are 0.1 s apart.
//!
//! Everything is drawn from one [`SplitMix64`] seeded with `seed`, and numbers are rounded
//! to 3 decimals, so a seed gives byte-identical output. Depends on `map`, `syntax` (rule
//! bodies), `engine::frame` and `io::record`.

pub mod large_map;

use crate::core::angle::wrap_180;
use crate::core::rng::SplitMix64;
use crate::engine::{Engine, PerceptTable};
use crate::io::record::{FrameRecord, Odometry, PerceptRecord, Truth, FORMAT_VERSION};
use crate::map::Map;
use crate::rules::RuleSet;
use crate::syntax::ast::{ArgRole, Formula, Term};
use serde::{Deserialize, Serialize};

/// Simulator parameters (all have defaults; see `lplace simulate --help`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimConfig {
    /// Frames to emit.
    pub steps: u64,
    /// PRNG seed.
    pub seed: u64,
    /// Metres per frame.
    pub speed: f64,
    /// Relative noise of the true speed.
    pub speed_noise: f64,
    /// Relative noise of the odometry reading.
    pub odometry_noise: f64,
    /// Probability that a percept is missing.
    pub p_missing: f64,
    /// Probability that a sonar wall is occluded.
    pub p_occlude: f64,
    /// Probability that a frame's measured values belong to another place.
    pub p_mislabel: f64,
    /// Probability of a spurious corner in a frame.
    pub p_spurious: f64,
    /// Noise (standard deviation) of periodic values, in their unit (degrees).
    pub angle_noise: f64,
    /// Relative noise (standard deviation) of other values.
    pub range_noise: f64,
    /// Frames (0-based) at which the robot is kidnapped.
    pub kidnap_at: Vec<u64>,
    /// Emit the robot's heading (a compass), with this noise (standard deviation, degrees);
    /// `None` emits none. Off by default, so streams made without it are unchanged.
    pub heading_noise: Option<f64>,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            steps: 2000,
            seed: 1,
            speed: 0.3,
            speed_noise: 0.1,
            odometry_noise: 0.05,
            p_missing: 0.1,
            p_occlude: 0.1,
            p_mislabel: 0.04,
            p_spurious: 0.04,
            angle_noise: 5.0,
            range_noise: 0.05,
            kidnap_at: Vec::new(),
            heading_noise: None,
        }
    }
}

/// How a percept instance is derived from the map.
#[derive(Debug, Clone, PartialEq)]
enum Derive {
    /// Wall towards this direction.
    Wall(String),
    /// Corner between these directions.
    Corner(String, String),
    /// Place parameter `name` (keyed), compared periodically or not.
    Value {
        param: String,
        key: Option<String>,
        periodic: bool,
    },
    /// Nothing the simulator can derive: never emitted.
    Never,
}

/// The key of an `expect` parameter as written in the rule: none, a constant, or the value of
/// the atom's domain argument number `k`.
#[derive(Debug, Clone, PartialEq)]
enum KeySpec {
    None,
    Const(String),
    DomainArg(usize),
}

/// Finds, for percept `name`, the first place parameter the rules compare it with.
fn expectation_of(rules: &RuleSet, name: &str) -> Option<(String, KeySpec)> {
    let sig = rules.percepts.get(name)?;
    let expect_pos = sig
        .roles
        .iter()
        .position(|r| matches!(r, ArgRole::Expect))?;
    fn walk(f: &Formula, name: &str, pos: usize, roles: &[ArgRole]) -> Option<(String, KeySpec)> {
        match f {
            Formula::Atom(a) if a.name.node == name => {
                let Term::PlaceRef { name: p, key } = &a.args.get(pos)?.node else {
                    return None;
                };
                let key = match key {
                    None => KeySpec::None,
                    Some(k) if k.starts_with(|c: char| c.is_ascii_lowercase()) => {
                        // A variable: which domain argument of this atom carries it?
                        let mut d = 0;
                        let mut found = None;
                        for (r, t) in roles.iter().zip(&a.args) {
                            if let ArgRole::Domain(_) = r {
                                if matches!(&t.node, Term::Var(v) if v == k) {
                                    found = Some(d);
                                }
                                d += 1;
                            }
                        }
                        KeySpec::DomainArg(found?)
                    }
                    Some(k) => KeySpec::Const(k.clone()),
                };
                Some((p.clone(), key))
            }
            Formula::Atom(_) | Formula::Degree(_) => None,
            Formula::Not(a) | Formula::Weighted(a, _) => walk(&a.node, name, pos, roles),
            Formula::And(v) | Formula::Times(v) | Formula::Or(v) => {
                v.iter().find_map(|x| walk(&x.node, name, pos, roles))
            }
            Formula::Implies(a, b) => {
                walk(&a.node, name, pos, roles).or_else(|| walk(&b.node, name, pos, roles))
            }
        }
    }
    rules
        .rules
        .iter()
        .find_map(|r| walk(&r.body.node, name, expect_pos, &sig.roles))
}

fn derive_all(rules: &RuleSet, table: &PerceptTable) -> Vec<Derive> {
    table
        .instances()
        .iter()
        .map(|inst| {
            let Some(sig) = rules.percepts.get(&inst.name) else {
                return Derive::Never;
            };
            let has_expect = sig.roles.iter().any(|r| matches!(r, ArgRole::Expect));
            if has_expect {
                let Some((param, key)) = expectation_of(rules, &inst.name) else {
                    return Derive::Never;
                };
                let key = match key {
                    KeySpec::None => None,
                    KeySpec::Const(k) => Some(k),
                    KeySpec::DomainArg(d) => match inst.args.get(d) {
                        Some(a) => Some(a.clone()),
                        None => return Derive::Never,
                    },
                };
                let periodic = sig
                    .similarity
                    .as_ref()
                    .and_then(|s| rules.similarities.get(s))
                    .is_some_and(|t| t.period.is_some());
                return Derive::Value {
                    param,
                    key,
                    periodic,
                };
            }
            match inst.args.as_slice() {
                [d] => Derive::Wall(d.clone()),
                [d1, d2] => Derive::Corner(d1.clone(), d2.clone()),
                _ => Derive::Never,
            }
        })
        .collect()
}

/// Rounds to 3 decimals: compact, and the same bytes on every platform.
fn r3(x: f64) -> f64 {
    let r = (x * 1000.0).round() / 1000.0;
    if r == 0.0 {
        0.0 // no "-0.0"
    } else {
        r
    }
}

/// The simulated robot. Iterate it for frame records.
#[derive(Debug, Clone)]
pub struct Simulator {
    cfg: SimConfig,
    map: Map,
    table: PerceptTable,
    derive: Vec<Derive>,
    rng: SplitMix64,
    frame: u64,
    /// Place the robot last left (or is at).
    from: usize,
    /// Place it is heading to.
    to: usize,
    /// Metres travelled along the edge.
    along: f64,
    dwell: u32,
    pose: (f64, f64, f64),
}

impl Simulator {
    /// A simulator for an engine's map and rules.
    pub fn for_engine(engine: &Engine, cfg: SimConfig) -> Simulator {
        let mut used = vec![false; engine.percepts().len()];
        for op in &engine.compiled().tape.ops {
            if let crate::engine::tape::Op::Degree(s)
            | crate::engine::tape::Op::Match { slot: s, .. } = op
            {
                if let Some(u) = used.get_mut(s.0 as usize) {
                    *u = true;
                }
            }
        }
        Simulator::with_used(
            engine.map(),
            engine.rules(),
            engine.percepts(),
            Some(&used),
            cfg,
        )
    }

    /// A simulator for `map` with the percepts of `rules`.
    pub fn new(map: &Map, rules: &RuleSet, table: &PerceptTable, cfg: SimConfig) -> Simulator {
        Self::with_used(map, rules, table, None, cfg)
    }

    /// As [`Simulator::new`]; `used[slot]` (when given) says which instances the compiled rules
    /// read, so that a corner is reported in the argument order the rules use.
    fn with_used(
        map: &Map,
        rules: &RuleSet,
        table: &PerceptTable,
        used: Option<&[bool]>,
        cfg: SimConfig,
    ) -> Simulator {
        let mut rng = SplitMix64::new(cfg.seed);
        let mut derive = derive_all(rules, table);
        // A corner has two names, (a, b) and (b, a): emit one, the one the rules read.
        let insts = table.instances();
        for k in 0..derive.len() {
            if let Derive::Corner(a, b) = &derive[k] {
                let rev = insts.iter().position(|p| {
                    p.name == insts[k].name
                        && p.args.len() == 2
                        && &p.args[0] == b
                        && &p.args[1] == a
                });
                let is_used = |i: usize| used.map_or(true, |u| u.get(i).copied().unwrap_or(false));
                if let Some(r) = rev.filter(|&r| r != k) {
                    let keep_this = match (is_used(k), is_used(r)) {
                        (true, false) => true,
                        (false, true) => false,
                        _ => k < r,
                    };
                    if !keep_this {
                        derive[k] = Derive::Never;
                    }
                }
            }
        }
        let n = map.places().len();
        let from = rng.below(n);
        let mut s = Simulator {
            derive,
            table: table.clone(),
            map: map.clone(),
            rng,
            frame: 0,
            from,
            to: from,
            along: 0.0,
            dwell: 0,
            pose: (0.0, 0.0, 0.0),
            cfg,
        };
        if let Some(p) = s.map.places().get(from) {
            s.pose = (p.pose.0, p.pose.1, p.pose.2.unwrap_or(0.0));
        }
        s.to = s.pick_next(from, None);
        s
    }

    fn place_xy(&self, i: usize) -> (f64, f64) {
        self.map
            .places()
            .get(i)
            .map_or((0.0, 0.0), |p| (p.pose.0, p.pose.1))
    }

    /// A random neighbour of `at`, avoiding `came_from` unless it is the only one.
    fn pick_next(&mut self, at: usize, came_from: Option<usize>) -> usize {
        let nb = self.map.neighbours(at);
        let choices: Vec<usize> = nb
            .iter()
            .copied()
            .filter(|&j| Some(j) != came_from)
            .collect();
        let pool = if choices.is_empty() { nb } else { choices };
        if pool.is_empty() {
            return at;
        }
        pool[self.rng.below(pool.len())]
    }

    /// Moves one frame; returns the distance moved and the heading change in degrees.
    fn advance(&mut self) -> (f64, f64) {
        if self.dwell > 0 || self.from == self.to {
            self.dwell = self.dwell.saturating_sub(1);
            return (0.0, 0.0);
        }
        let (a, b) = (self.place_xy(self.from), self.place_xy(self.to));
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        let step = (self.cfg.speed * (1.0 + self.cfg.speed_noise * self.rng.normal())).max(0.02);
        let heading = (b.1 - a.1).atan2(b.0 - a.0).to_degrees();
        let before = self.along;
        self.along = (self.along + step).min(len);
        let moved = self.along - before;
        let f = if len > 0.0 { self.along / len } else { 1.0 };
        let dtheta = wrap180(heading - self.pose.2);
        self.pose = (a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1), heading);
        if self.along >= len {
            let came = self.from;
            self.from = self.to;
            self.along = 0.0;
            self.dwell = self.rng.below(3) as u32;
            self.to = self.pick_next(self.from, Some(came));
        }
        (moved, dtheta)
    }

    fn kidnap(&mut self) {
        let n = self.map.places().len();
        if n < 2 {
            return;
        }
        let here = self.truth_place().unwrap_or(self.from);
        let mut q = self.rng.below(n - 1);
        if q >= here {
            q += 1;
        }
        let (x, y) = self.place_xy(q);
        self.pose = (x, y, self.pose.2);
        self.from = q;
        self.along = 0.0;
        // Put down by hand, the robot stands a moment before it moves on.
        self.dwell = 2 + self.rng.below(3) as u32;
        self.to = self.pick_next(q, None);
    }

    fn truth_place(&self) -> Option<usize> {
        self.map
            .places()
            .iter()
            .position(|p| p.contains(self.pose.0, self.pose.1))
    }

    fn nearest_place(&self) -> usize {
        let mut best = (0, f64::INFINITY);
        for (i, p) in self.map.places().iter().enumerate() {
            let d = (p.pose.0 - self.pose.0).hypot(p.pose.1 - self.pose.1);
            if d < best.1 {
                best = (i, d);
            }
        }
        best.0
    }

    /// The expected value of a `Value` percept at place `p`.
    fn expected(&self, p: usize, param: &str, key: Option<&str>) -> Option<f64> {
        self.map.param(p, param, key)
    }

    fn noisy(&mut self, v: f64, periodic: bool, scale: f64) -> f64 {
        if periodic {
            (v + scale * self.cfg.angle_noise * self.rng.normal()).rem_euclid(360.0)
        } else {
            v * (1.0 + scale * self.cfg.range_noise * self.rng.normal())
        }
    }

    /// The percepts at place `p` (the robot is inside its extent).
    fn percepts_at(&mut self, p: usize, out: &mut Vec<PerceptRecord>) {
        let n = self.map.places().len();
        let label = if self.rng.chance(self.cfg.p_mislabel) && n > 1 {
            let q = self.rng.below(n - 1);
            if q >= p {
                q + 1
            } else {
                q
            }
        } else {
            p
        };
        for k in 0..self.derive.len() {
            let (degree, value) = match self.derive[k].clone() {
                Derive::Never => continue,
                Derive::Wall(d) => {
                    let w = self.map.wall(p, &d);
                    if w <= 0.0 || self.rng.chance(self.cfg.p_missing) {
                        continue;
                    }
                    let sonar = self.table.instances()[k].name.contains("sonar");
                    if sonar && self.rng.chance(self.cfg.p_occlude) {
                        continue;
                    }
                    // A front laser looks through a doorway; a partial wall is for the sonars.
                    if !sonar && w < 0.75 {
                        continue;
                    }
                    (self.rng.uniform(0.8, 1.0), None)
                }
                Derive::Corner(d1, d2) => {
                    let c = self.map.corner(p, &d1, &d2);
                    if c <= 0.0 || self.rng.chance(self.cfg.p_missing) {
                        continue;
                    }
                    (c * self.rng.uniform(0.8, 1.0), None)
                }
                Derive::Value {
                    param,
                    key,
                    periodic,
                } => {
                    let Some(v) = self.expected(label, &param, key.as_deref()) else {
                        continue;
                    };
                    if self.rng.chance(self.cfg.p_missing) {
                        continue;
                    }
                    let v = self.noisy(v, periodic, 1.0);
                    (self.rng.uniform(0.8, 1.0), Some(v))
                }
            };
            out.push(self.record(k, degree, value));
        }
        if self.rng.chance(self.cfg.p_spurious) {
            let absent: Vec<usize> = (0..self.derive.len())
                .filter(|&k| match &self.derive[k] {
                    Derive::Corner(d1, d2) => self.map.corner(p, d1, d2) <= 0.0,
                    _ => false,
                })
                .collect();
            if !absent.is_empty() {
                let k = absent[self.rng.below(absent.len())];
                let d = self.rng.uniform(0.5, 0.9);
                out.push(self.record(k, d, None));
            }
        }
    }

    /// Weak, partial percepts between places: a glimpse of the nearest place.
    fn percepts_between(&mut self, out: &mut Vec<PerceptRecord>) {
        let q = self.nearest_place();
        let walls: Vec<usize> = (0..self.derive.len())
            .filter(|&k| matches!(&self.derive[k], Derive::Wall(d) if self.map.wall(q, d) > 0.0))
            .collect();
        if !walls.is_empty() && self.rng.chance(0.5) {
            let k = walls[self.rng.below(walls.len())];
            let d = self.rng.uniform(0.1, 0.4);
            out.push(self.record(k, d, None));
        }
        if self.rng.chance(0.3) {
            for k in 0..self.derive.len() {
                if let Derive::Value {
                    param,
                    key,
                    periodic,
                } = self.derive[k].clone()
                {
                    if let Some(v) = self.expected(q, &param, key.as_deref()) {
                        let v = self.noisy(v, periodic, 3.0);
                        let d = self.rng.uniform(0.2, 0.45);
                        out.push(self.record(k, d, Some(v)));
                    }
                }
            }
        }
    }

    fn record(&self, slot: usize, degree: f64, value: Option<f64>) -> PerceptRecord {
        let inst = &self.table.instances()[slot];
        PerceptRecord {
            name: inst.name.clone(),
            args: inst.args.clone(),
            value: value.map(r3),
            degree: r3(degree.clamp(0.0, 1.0)),
        }
    }

    /// The next frame record.
    pub fn next_record(&mut self) -> FrameRecord {
        let k = self.frame;
        self.frame += 1;
        let (moved, dtheta) = if k == 0 {
            (0.0, 0.0)
        } else if self.cfg.kidnap_at.contains(&k) {
            self.kidnap();
            // The wheels turned as usual: odometry sees an ordinary step.
            (self.cfg.speed, 0.0)
        } else {
            self.advance()
        };
        let odometry = Odometry {
            dx: r3(moved * (1.0 + self.cfg.odometry_noise * self.rng.normal())),
            dy: r3(0.01 * self.rng.normal()),
            dtheta: r3(dtheta + self.rng.normal()),
        };
        // Drawn only when asked for, so that streams made without it keep their bytes.
        let heading = self
            .cfg
            .heading_noise
            .map(|sd| r3(wrap180(self.pose.2 + sd * self.rng.normal())));
        let mut percepts = Vec::new();
        let place = self.truth_place();
        match place {
            Some(p) => self.percepts_at(p, &mut percepts),
            None => self.percepts_between(&mut percepts),
        }
        FrameRecord {
            version: Some(FORMAT_VERSION),
            t: Some(r3(k as f64 * 0.1)),
            odometry: Some(odometry),
            heading,
            percepts,
            region: None,
            truth: Some(Truth {
                place: place.map(|p| self.map.places()[p].name.clone()),
                pose: Some([r3(self.pose.0), r3(self.pose.1), r3(self.pose.2)]),
            }),
        }
    }

    /// True when `slot`'s percept carries a measured value.
    pub fn has_value(&self, slot: usize) -> bool {
        matches!(self.derive.get(slot), Some(Derive::Value { .. }))
    }
}

/// Degrees wrapped into (−180, 180]; a non-finite angle counts as no turn.
fn wrap180(a: f64) -> f64 {
    let a = wrap_180(a);
    if a.is_finite() {
        a
    } else {
        0.0
    }
}

impl Iterator for Simulator {
    type Item = FrameRecord;
    fn next(&mut self) -> Option<FrameRecord> {
        if self.frame >= self.cfg.steps {
            return None;
        }
        Some(self.next_record())
    }
}
