//! A step's result with names instead of indices: what `lplace eval` prints as JSON, and what an
//! embedder logs. Building it allocates, so it is kept off `Engine::step`'s path.

use super::Engine;
use crate::logic::{Decision, Disoriented};
use serde::{Deserialize, Serialize};

/// Degrees of one place in one step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlaceDegrees {
    /// Place name.
    pub place: String,
    /// `α`: support for `at_place`.
    pub support: f64,
    /// `β`: support for `!at_place`.
    pub exclusion: f64,
    /// `Π` after normalisation.
    pub possibility: f64,
    /// `N`.
    pub necessity: f64,
    /// `π_k` before normalisation (after set heads, fusion and conditioning).
    pub possibility_raw: f64,
}

/// Π and N of a query over sets of places.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct QueryOutcome {
    /// The query as written.
    pub query: String,
    /// Its places.
    pub places: Vec<String>,
    /// `Π(S)`.
    pub possibility: f64,
    /// `N(S)`.
    pub necessity: f64,
}

/// Degrees of one room (or region) in one step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoomOutcome {
    /// Room name.
    pub room: String,
    /// Support for `in_room` from the rules.
    pub support: f64,
    /// `Π(R)`.
    pub possibility: f64,
    /// `N(R)`.
    pub necessity: f64,
}

/// One fired rule instance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fired {
    /// 1-based rule number in the file.
    pub rule: usize,
    /// Hypothesis place of the instance.
    pub context: String,
    /// Schema binding, `var=value`.
    pub binding: Vec<String>,
    /// The conclusion, `!` for negated.
    pub head: String,
    /// The degree it yielded.
    pub degree: f64,
}

/// A step's decision and degrees, by name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    /// `place` or `disoriented`.
    pub outcome: &'static str,
    /// The chosen place, if any.
    pub place: Option<String>,
    /// Its necessity.
    pub necessity: Option<f64>,
    /// Why no place was chosen (`nothing_above_threshold`, `too_close`, `inconsistent`, `no_places`).
    pub reason: Option<&'static str>,
    /// For `too_close`: the best place and the runner-up.
    pub candidates: Vec<String>,
    /// `Inc`.
    pub inconsistency: f64,
    /// Per place, in map order.
    pub places: Vec<PlaceDegrees>,
    /// Per room, in map order.
    pub rooms: Vec<RoomOutcome>,
    /// Declared regions (`room` holds the region's name), when the rule file has any.
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub regions: Vec<RoomOutcome>,
    /// Asked-for queries over sets of places (`eval --query`).
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub queries: Vec<QueryOutcome>,
    /// Rule instances with a positive degree (only when loaded with trace).
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub fired: Vec<Fired>,
}

impl Outcome {
    /// Summarises `engine`'s last step.
    pub fn of(engine: &Engine) -> Outcome {
        let places = engine.map().places();
        let name = |k: usize| {
            places
                .get(k)
                .map_or_else(|| format!("#{k}"), |p| p.name.clone())
        };
        let d = engine.distribution();
        let (outcome, place, necessity, reason, candidates) = match engine.decision() {
            Decision::Place { place, necessity } => {
                ("place", Some(name(place)), Some(necessity), None, vec![])
            }
            Decision::Disoriented(why) => {
                let (reason, candidates) = match why {
                    Disoriented::NothingAboveThreshold { best, .. } => {
                        ("nothing_above_threshold", vec![name(best)])
                    }
                    Disoriented::TooClose {
                        best, runner_up, ..
                    } => ("too_close", vec![name(best), name(runner_up)]),
                    Disoriented::Inconsistent { .. } => ("inconsistent", vec![]),
                    Disoriented::NoPlaces => ("no_places", vec![]),
                };
                ("disoriented", None, None, Some(reason), candidates)
            }
        };
        Outcome {
            outcome,
            place,
            necessity,
            reason,
            candidates,
            inconsistency: d.inconsistency,
            places: (0..d.len())
                .map(|k| PlaceDegrees {
                    place: name(k),
                    support: d.support[k],
                    exclusion: d.exclusion[k],
                    possibility: d.possibility[k],
                    necessity: d.necessity[k],
                    possibility_raw: d.possibility_raw[k],
                })
                .collect(),
            rooms: room_outcomes(engine),
            regions: region_outcomes(engine),
            queries: Vec::new(),
            fired: fired(engine, name),
        }
    }
}

/// The map's rooms with their degrees, in map order.
fn room_outcomes(engine: &Engine) -> Vec<RoomOutcome> {
    let rooms = engine.rooms();
    engine
        .map()
        .rooms()
        .iter()
        .enumerate()
        .map(|(r, room)| RoomOutcome {
            room: room.name.clone(),
            support: rooms.support[r],
            possibility: rooms.possibility[r],
            necessity: rooms.necessity[r],
        })
        .collect()
}

/// The rule file's regions with their degrees, in declaration order.
fn region_outcomes(engine: &Engine) -> Vec<RoomOutcome> {
    engine
        .rules()
        .regions
        .iter()
        .enumerate()
        .map(|(g, (region, _))| RoomOutcome {
            room: region.clone(),
            support: engine.regions().support[g],
            possibility: engine.regions().possibility[g],
            necessity: engine.regions().necessity[g],
        })
        .collect()
}

/// The traced rule instances with a positive degree, their context place named by `name`.
fn fired(engine: &Engine, name: impl Fn(usize) -> String) -> Vec<Fired> {
    engine
        .trace()
        .filter(|(_, deg)| *deg > 0.0)
        .map(|(c, deg)| Fired {
            rule: c.rule + 1,
            context: name(c.context),
            binding: c.binding.iter().map(|(v, x)| format!("{v}={x}")).collect(),
            head: format!(
                "{}{}",
                if c.negated { "!" } else { "" },
                engine.atom_text(&c.head)
            ),
            degree: deg,
        })
        .collect()
}

impl Engine {
    /// A ground atom with every argument of its predicate's declaration: the ground domain
    /// values in their positions, `t` for the time and `_` for a value or expectation (a
    /// [`GroundAtom`](super::compile::GroundAtom) keeps domain values only, so `walls(t)`
    /// would otherwise print as `walls()`). Built-in atoms have domain arguments only.
    pub fn atom_text(&self, atom: &super::compile::GroundAtom) -> String {
        use crate::syntax::ast::ArgRole;
        let Some(sig) = self.rules().predicates.get(&atom.name) else {
            return atom.to_string();
        };
        let mut domain_args = atom.args.iter();
        let args: Vec<&str> = sig
            .roles
            .iter()
            .map(|r| match r {
                ArgRole::Domain(_) => domain_args.next().map_or("?", String::as_str),
                ArgRole::Time => "t",
                ArgRole::Value | ArgRole::Expect => "_",
            })
            .collect();
        format!("{}({})", atom.name, args.join(", "))
    }
}
