//! The engine: load a map and a rule file once, then step frame by frame.
//!
//! [`Engine::load`] parses, checks and compiles (`compile`), producing a [`tape::Tape`] whose
//! output registers are the place supports. [`Engine::step`] evaluates the tape on one
//! [`Frame`] (regrouped by instruction kind, `columns`, one loop per kind and level; where a
//! similarity of bias 0 gates the rules, only the places its reading can match, `gates`), builds
//! the place distribution (`logic::possibility`; in two passes over the places, `distribution`)
//! and decides (`logic::decision`) — into buffers allocated at load time, so a step allocates
//! nothing and cannot panic on any frame. Room and region degrees are computed when first read
//! after a step (`named_sets`). The interpreter (`interpret`) is the slow reference the tape is
//! tested against. This module depends on `syntax`, `map` and `logic`; nothing in those depends
//! on it.
//!
//! # Example
//! ```
//! use lplace::engine::Engine;
//! let mut engine = Engine::office().expect("the bundled example loads");
//! let mut frame = engine.new_frame();
//! let table = engine.percepts();
//! // The robot sees the beacon from 116° at 1.1 m, and walls North and East: place P2.
//! frame.set(table.slot("beacon_angle", &[]).unwrap(), 0.9, Some(116.0));
//! frame.set(table.slot("beacon_distance", &[]).unwrap(), 0.9, Some(1.1));
//! frame.set(table.slot("sonar_wall", &["North"]).unwrap(), 0.8, None);
//! frame.set(table.slot("laser_wall", &["East"]).unwrap(), 0.9, None);
//! let decision = engine.step(&frame);
//! assert_eq!(decision.place().map(|p| engine.map().places()[p].name.as_str()), Some("P2"));
//! ```

pub mod columns;
pub mod compile;
mod distribution;
pub mod frame;
pub mod gates;
pub mod grid_tracker;
pub mod interpret;
mod named_sets;
pub mod outcome;
pub mod query;
pub mod tape;
pub mod tracker;
mod tracker_block;

pub use compile::{compile, CompileOptions, Compiled, Contribution, GroundAtom, SetHead};
pub use frame::{Frame, PerceptInstance, PerceptSlot, PerceptTable};
pub use outcome::Outcome;
pub use query::QueryError;

use crate::logic::decision::decide_with_peaks;
use crate::logic::{clamp_degree, decide, Decision, DecisionParams, PlaceDistribution, PlaceSet};
use crate::map::Map;
use crate::rules::{check_map_against_rules, check_rules, RuleSet};
use crate::syntax::diagnostic::{Diagnostic, SourceFile};
use crate::syntax::{parse_map, parse_rules};
use named_sets::NamedSets;
use serde::{Deserialize, Serialize};
use std::sync::OnceLock;

/// The bundled example map (paper 003's office).
pub const OFFICE_MAP: &str = include_str!("../../maps/office.map");
/// The bundled example rules (paper 003's office).
pub const OFFICE_RULES: &str = include_str!("../../rules/office.lpl");

/// Which of the two input files a load error is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum FileRole {
    /// The map file.
    Map,
    /// The rule file.
    Rules,
}

/// Why an engine could not be loaded: the diagnostics of one file (all of them, not the first).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{} problem(s) in {} file `{}`", diagnostics.len(), match role { FileRole::Map => "map", FileRole::Rules => "rule" }, file.name)]
pub struct LoadError {
    /// Which file.
    pub role: FileRole,
    /// The file, for rendering the diagnostics.
    pub file: SourceFile,
    /// Every problem found.
    pub diagnostics: Vec<Diagnostic>,
}

/// Counts of repairs made to the last frame (see `frame` for the contract).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Sanitised {
    /// Degrees that were NaN and read as missing (0).
    pub nan_degrees: u32,
    /// Degrees outside `[0, 1]` that were clamped.
    pub clamped_degrees: u32,
    /// Values that were infinite (NaN values mean "no value" and are not counted).
    pub infinite_values: u32,
}

/// Degrees of named sets of places (rooms, or declared regions) in the last step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoomDegrees {
    /// Support for `in_room(R)` (or `in_region(G)`) derived by the rules.
    pub support: Vec<f64>,
    /// `Π(R) = max_{k ∈ R} π'_k`.
    pub possibility: Vec<f64>,
    /// `N(R) = 1 − max_{k ∉ R} π'_k`.
    pub necessity: Vec<f64>,
}

/// A loaded, compiled rule set over a map, with the buffers one step needs.
#[derive(Debug, Clone)]
pub struct Engine {
    map: Map,
    rules: RuleSet,
    compiled: Compiled,
    /// The tape regrouped by instruction kind, the evaluator a step uses (`None` only for a
    /// malformed tape, which [`tape::Tape::eval`] evaluates).
    columns: Option<columns::Columns>,
    /// The zero-gated evaluator, used instead when the tape has gates (`gates`).
    gated: Option<gates::Gated>,
    regs: Vec<f64>,
    dist: PlaceDistribution,
    /// One distribution per evidence group (empty without `group` blocks).
    group_dists: Vec<PlaceDistribution>,
    /// The room and region degrees of the last step, computed when first read: the 2,500
    /// rooms of a 10,000-place map cost a step as much as its tape, and a tracked run reads
    /// none of them.
    rooms: OnceLock<RoomDegrees>,
    regions: OnceLock<RoomDegrees>,
    room_sets: NamedSets,
    region_sets: NamedSets,
    /// Each set head's member places.
    head_members: distribution::HeadMembers,
    /// Scratch for [`named_sets::constrain_heads`], as long as the set heads.
    head_order: Vec<(f64, usize)>,
    /// Scratch for [`distribution::fill`].
    head_scratch: distribution::HeadScratch,
    /// The distinct exclusion registers, for [`distribution::fill`].
    exclusions: distribution::Exclusions,
    decision: Decision,
    sanitised: Sanitised,
}

impl Engine {
    /// Parses, checks and compiles a map and a rule file.
    pub fn load(map: &SourceFile, rules: &SourceFile) -> Result<Engine, LoadError> {
        Self::load_with(map, rules, &CompileOptions::default())
    }

    /// [`Engine::load`] with compile options (trace, derived predicates).
    pub fn load_with(
        map: &SourceFile,
        rules: &SourceFile,
        opts: &CompileOptions,
    ) -> Result<Engine, LoadError> {
        let fail = |role, file: &SourceFile, diagnostics| LoadError {
            role,
            file: file.clone(),
            diagnostics,
        };
        let map_ast = parse_map(&map.text).map_err(|d| fail(FileRole::Map, map, d))?;
        let model = Map::from_ast(&map_ast).map_err(|d| fail(FileRole::Map, map, d))?;
        let rule_ast = parse_rules(&rules.text).map_err(|d| fail(FileRole::Rules, rules, d))?;
        let checked =
            check_rules(&rule_ast, &model).map_err(|d| fail(FileRole::Rules, rules, d))?;
        // Cross-file problems (a wall direction the rules' `Dir` lacks) live in the map's text.
        let cross = check_map_against_rules(&model, &checked);
        if cross.iter().any(Diagnostic::is_error) {
            return Err(fail(FileRole::Map, map, cross));
        }
        Engine::new(model, checked, opts).map_err(|d| fail(FileRole::Rules, rules, d))
    }

    /// The bundled office example (`maps/office.map`, `rules/office.lpl`).
    pub fn office() -> Result<Engine, LoadError> {
        Self::load(
            &SourceFile::new("maps/office.map", OFFICE_MAP),
            &SourceFile::new("rules/office.lpl", OFFICE_RULES),
        )
    }

    /// Compiles an already checked rule set over a map.
    pub fn new(map: Map, rules: RuleSet, opts: &CompileOptions) -> Result<Engine, Vec<Diagnostic>> {
        let compiled = compile(&rules, &map, opts)?;
        let n = map.places().len();
        let groups = if compiled.groups > 1 {
            compiled.groups
        } else {
            0
        };
        let room_sets = NamedSets::new(
            (0..map.rooms().len())
                .map(|r| query::room_set(&map, r))
                .collect(),
        );
        let region_sets = NamedSets::new(
            rules
                .regions
                .iter()
                .map(|(_, ks)| PlaceSet::from_indices(n, ks.iter().copied()))
                .collect(),
        );
        let mut engine = Engine {
            columns: columns::Columns::new(&compiled.tape),
            gated: gates::Gated::new(&compiled.tape, &compiled.observed),
            regs: vec![0.0; compiled.tape.len()],
            dist: PlaceDistribution::new(n),
            group_dists: vec![PlaceDistribution::new(n); groups],
            rooms: OnceLock::new(),
            regions: OnceLock::new(),
            room_sets,
            region_sets,
            head_members: distribution::HeadMembers::new(&compiled.set_heads),
            head_order: Vec::with_capacity(compiled.set_heads.len()),
            head_scratch: distribution::HeadScratch::new(compiled.set_heads.len()),
            exclusions: distribution::Exclusions::new(&compiled.exclusion),
            decision: Decision::Disoriented(crate::logic::Disoriented::NoPlaces),
            sanitised: Sanitised::default(),
            map,
            rules,
            compiled,
        };
        let empty = engine.new_frame();
        engine.step(&empty);
        Ok(engine)
    }

    /// The map.
    pub fn map(&self) -> &Map {
        &self.map
    }

    /// Warnings about the rules on this map (rules that never fire on it), with spans in the
    /// rule file: the engine runs, and a front end shows them.
    pub fn warnings(&self) -> &[Diagnostic] {
        &self.compiled.warnings
    }

    /// The checked rule set.
    pub fn rules(&self) -> &RuleSet {
        &self.rules
    }

    /// The tracker settings of the rule file's `tracker { … }` block, or the defaults: what
    /// tracks a run when no tracker file is given.
    pub fn tracker_config(&self) -> tracker::TrackerConfig {
        self.rules.tracker.as_ref().map_or_else(
            tracker::TrackerConfig::default,
            tracker::TrackerConfig::from_settings,
        )
    }

    /// The compiled form.
    pub fn compiled(&self) -> &Compiled {
        &self.compiled
    }

    /// The percept instances a frame can carry.
    pub fn percepts(&self) -> &PerceptTable {
        &self.compiled.percepts
    }

    /// A frame with every percept missing, sized for this engine.
    pub fn new_frame(&self) -> Frame {
        Frame::new(self.compiled.percepts.len())
    }

    /// Evaluates one frame and decides. Allocates nothing; never panics. A frame of the wrong
    /// size reads its missing slots as missing percepts.
    pub fn step(&mut self, frame: &Frame) -> Decision {
        self.step_within(frame, None)
    }

    /// [`Engine::step`], knowing from outside that the robot is somewhere in `known` (a room,
    /// region or any set of places, e.g. from [`Engine::query_set`]): the distribution is
    /// conditioned on it — min-based or product-based, as the rule file's `normalisation` says
    /// (see `logic::possibility`). Allocates nothing.
    pub fn step_within(&mut self, frame: &Frame, known: Option<&PlaceSet>) -> Decision {
        self.sanitise(frame);
        match (&mut self.gated, &self.columns) {
            (Some(g), _) => g.eval(&self.compiled.tape, frame, &mut self.regs),
            (None, Some(c)) => c.eval(&self.compiled.tape, frame, &mut self.regs),
            (None, None) => self.compiled.tape.eval(frame, &mut self.regs),
        }
        self.rooms = OnceLock::new();
        self.regions = OnceLock::new();
        let logic = self.rules.logic;
        let params = DecisionParams {
            threshold: logic.threshold,
            margin: logic.margin,
        };
        if self.group_dists.is_empty() && known.is_none() {
            let c = &self.compiled;
            let inputs = distribution::Inputs {
                regs: &self.regs,
                support: &c.support,
                heads: &c.set_heads,
                members: &self.head_members,
            };
            let (d, s, x) = (&mut self.dist, &mut self.head_scratch, &mut self.exclusions);
            if let Some(peaks) = distribution::fill(d, &inputs, s, x, logic.normalisation) {
                self.decision = decide_with_peaks(&self.dist, params, peaks);
                return self.decision;
            }
        }
        self.separate_passes(known);
        self.decision = decide(&self.dist, params);
        self.decision
    }

    /// The distribution pass by pass: supports, `π`, the set heads or the evidence groups, the
    /// known region, the normalisation.
    fn separate_passes(&mut self, known: Option<&PlaceSet>) {
        let read =
            |regs: &[f64], r: u32| clamp_degree(regs.get(r as usize).copied().unwrap_or(0.0));
        for (k, &r) in self.compiled.support.iter().enumerate() {
            self.dist.support[k] = read(&self.regs, r);
        }
        for (k, &r) in self.compiled.exclusion.iter().enumerate() {
            self.dist.exclusion[k] = read(&self.regs, r);
        }
        if self.group_dists.is_empty() {
            self.dist.fill_raw();
            let regs = &self.regs;
            named_sets::constrain_heads(
                &mut self.dist,
                &self.compiled.set_heads,
                None,
                |r| read(regs, r),
                &mut self.head_order,
            );
        } else {
            self.fuse_groups();
        }
        if let Some(a) = known {
            self.dist.condition(a);
        }
        self.dist.finish(self.rules.logic.normalisation);
    }

    fn sanitise(&mut self, frame: &Frame) {
        self.sanitised = Sanitised::default();
        for &d in &frame.degree {
            if d.is_nan() {
                self.sanitised.nan_degrees += 1;
            } else if !(0.0..=1.0).contains(&d) {
                self.sanitised.clamped_degrees += 1;
            }
        }
        self.sanitised.infinite_values =
            frame.value.iter().filter(|v| v.is_infinite()).count() as u32;
    }

    /// With `group` blocks: each group's own distribution (its place and set heads), fused world
    /// by world into `dist.possibility_raw` by the file's `fusion`.
    fn fuse_groups(&mut self) {
        let regs = &self.regs;
        let read = |r: u32| clamp_degree(regs.get(r as usize).copied().unwrap_or(0.0));
        let c = &self.compiled;
        for (g, gd) in self.group_dists.iter_mut().enumerate() {
            let (sup, exc) = (c.group_support.get(g), c.group_exclusion.get(g));
            for k in 0..gd.len() {
                gd.support[k] = sup.and_then(|v| v.get(k)).map_or(0.0, |&r| read(r));
                gd.exclusion[k] = exc.and_then(|v| v.get(k)).map_or(0.0, |&r| read(r));
            }
            gd.fill_raw();
            for h in c.set_heads.iter().filter(|h| h.group == g) {
                gd.constrain(&h.members, read(h.reg), h.negated);
            }
        }
        self.dist.possibility_raw.fill(1.0);
        for gd in &self.group_dists {
            self.dist.fuse(&gd.possibility_raw, self.rules.logic.fusion);
        }
    }

    /// The decision of the last step.
    pub fn decision(&self) -> Decision {
        self.decision
    }

    /// Supports, Π, N and Inc of the last step.
    pub fn distribution(&self) -> &PlaceDistribution {
        &self.dist
    }

    /// Room degrees of the last step (computed when first asked for after a step: that read
    /// allocates the result, [`Engine::step`] itself allocates nothing).
    pub fn rooms(&self) -> &RoomDegrees {
        self.rooms
            .get_or_init(|| (self.room_sets).degrees(&self.dist, &self.regs, &self.compiled.rooms))
    }

    /// Degrees of the declared regions in the last step (in `rules().regions` order; computed
    /// when first asked for after a step).
    pub fn regions(&self) -> &RoomDegrees {
        self.regions.get_or_init(|| {
            (self.region_sets).degrees(&self.dist, &self.regs, &self.compiled.regions)
        })
    }

    /// The unnormalised distribution of each evidence group in the last step (empty without
    /// `group` blocks; group 0 holds the rules outside every block).
    pub fn group_distributions(&self) -> &[PlaceDistribution] {
        &self.group_dists
    }

    /// The set of places a query names (see [`query`]): place, room, region and kind names,
    /// `at_place(P)`, `in_room(R)`, `in_region(G)`, combined with `!`, `&` and `(+)`.
    pub fn query_set(&self, text: &str) -> Result<PlaceSet, QueryError> {
        query::resolve(text, &self.map, &self.rules)
    }

    /// `(Π(S), N(S))` of a set of places under the last step's normalised distribution.
    pub fn set_degrees(&self, set: &PlaceSet) -> (f64, f64) {
        (self.dist.set_possibility(set), self.dist.set_necessity(set))
    }

    /// Repairs made to the last frame.
    pub fn sanitised(&self) -> Sanitised {
        self.sanitised
    }

    /// Degree of each rule instance in the last step (empty unless loaded with `trace`).
    pub fn trace(&self) -> impl Iterator<Item = (&Contribution, f64)> + '_ {
        self.compiled
            .contributions
            .iter()
            .map(|c| (c, self.regs.get(c.reg as usize).copied().unwrap_or(0.0)))
    }

    /// Degree of an asked-for derived atom in the last step.
    pub fn derived(&self) -> impl Iterator<Item = (&GroundAtom, f64)> + '_ {
        self.compiled
            .derived
            .iter()
            .map(|(a, r)| (a, self.regs.get(*r as usize).copied().unwrap_or(0.0)))
    }

    /// The closed-form degree function of place `k`'s support, as `explain` prints it.
    pub fn explain_place(&self, k: usize) -> Option<String> {
        let r = *self.compiled.support.get(k)?;
        Some(self.compiled.tape.render(r, &self.compiled.percepts))
    }

    /// A named, serialisable summary of the last step.
    pub fn outcome(&self) -> Outcome {
        Outcome::of(self)
    }
}
