//! The `engine` layer: golden decisions, the compiled tape against the reference interpreter, and
//! both trackers against reference implementations; the possibilistic layer over sets of places
//! (regions, fusion, conditioning, ties) with its command-line faces.

#[allow(dead_code)]
#[path = "../support/mod.rs"]
mod support;

mod engine_golden;
mod engine_grid_tracker;
mod engine_passes;
mod engine_places;
mod engine_props;
mod engine_tracker_ref;
