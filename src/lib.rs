//! # lplace — which place is the robot at?
//!
//! lplace recognises places (corners, doorways, junctions) of an annotated topological map from
//! cheap, unreliable percepts, by possibilistic logic (Bison, Chemello & Trainito, *Possibilistic
//! position estimation*). An operator writes, per environment, a **map** (`.map`: places, rooms,
//! paths, beacons, what each place looks like) and a **rule file** (`.lpl`: LPL sequents saying
//! how percepts support `at_place(P_i)`). lplace parses and checks both, compiles the rules into
//! one degree function per place, and decides frame by frame: a place with its necessity, or a
//! typed *disoriented* outcome.
//!
//! The modules follow the data: [`syntax`] (languages) → [`map`] (the graph) → [`engine`]
//! (compile, step) using [`logic`] (semantics) → [`io`] (records) → `cli` (feature `cli`).
//! The metric layer beside it: [`grid`] (paper 000's Fuzzy Position Grid), [`baseline`]
//! (particle filter, Fuzzy R-MCL), all stepped and scored by one driver in [`localize`];
//! [`coop`] fuses several robots' grids of one object (paper 002).
//!
//! # Example
//! ```
//! use lplace::engine::Engine;
//! use lplace::io::record::FrameRecord;
//!
//! let mut engine = Engine::office()?;          // the bundled paper-003 office
//! let record = FrameRecord::parse(r#"{"percepts": [
//!     {"name": "beacon_angle", "value": 167.0, "degree": 0.9},
//!     {"name": "beacon_distance", "value": 4.5, "degree": 0.8},
//!     {"name": "sonar_wall", "args": ["North"], "degree": 0.9},
//!     {"name": "laser_wall", "args": ["West"], "degree": 0.8}]}"#)?;
//! let mut frame = engine.new_frame();
//! let mut rejected = Vec::new();
//! record.fill(engine.percepts(), &mut frame, &mut rejected);
//! assert!(rejected.is_empty());
//! let decision = engine.step(&frame);           // allocation-free, never panics
//! let place = decision.place().map(|k| engine.map().places()[k].name.clone());
//! assert_eq!(place.as_deref(), Some("P1"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod baseline;
pub mod coop;
pub mod core;
pub mod engine;
pub mod grid;
pub mod io;
pub mod localize;
pub mod logic;
pub mod map;
pub mod percept;
pub mod report;
pub mod rules;
pub mod sim;
pub mod survey;
pub mod syntax;

#[cfg(feature = "cli")]
pub mod cli;
