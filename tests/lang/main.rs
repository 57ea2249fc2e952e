//! The `syntax`, `map` and `rules` layers: the grammars, the diagnostics, the bundled examples,
//! hostile text, and the map model.

#[allow(dead_code)]
#[path = "../support/mod.rs"]
mod support;

mod laser_kinds;
mod map_floor_plan;
mod map_model;
mod syntax_diagnostics;
mod syntax_examples;
mod syntax_grammar;
mod syntax_no_panic;
mod syntax_suggest;
mod syntax_tracker;
