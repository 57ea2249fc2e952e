//! The `logic` layer: connectives, trapezoids, possibility distributions and decisions, against
//! hand-worked textbook cases and brute-force enumeration.

#[allow(dead_code)]
#[path = "../support/mod.rs"]
mod support;

mod logic_cases;
mod logic_props;
