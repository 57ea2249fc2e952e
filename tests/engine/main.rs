//! The `engine` layer: golden decisions, the compiled tape against the reference interpreter, and
//! both trackers against reference implementations.

#[allow(dead_code)]
#[path = "../support/mod.rs"]
mod support;

mod engine_golden;
mod engine_grid_tracker;
mod engine_props;
mod engine_tracker_ref;
