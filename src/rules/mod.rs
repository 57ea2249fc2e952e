//! Rule files resolved against a map: the checker turns a parsed rule file and a [`crate::map::Map`]
//! into a [`RuleSet`] the compiler can trust, or reports every problem at once.
//!
//! This layer sits above `syntax` (it reads the AST and reports [`crate::syntax::Diagnostic`]s)
//! and `map` (it resolves places, walls and parameters), and below `engine`, which compiles a
//! checked rule set. It may depend on `core`, `logic`, `syntax` and `map`.

mod check;
mod tracker;

pub use check::{
    check_declarations, check_map_against_rules, check_rules, is_place_head, RuleSet, Signature,
    MAX_GROUND_INSTANCES,
};
pub use tracker::{TrackerSettings, TrackerValue, GRID_KEYS, TRACKER_KEYS};
