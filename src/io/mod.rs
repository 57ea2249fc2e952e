//! Readers for raw sensor logs. Every reader here parses bytes or lines that
//! the caller supplies and performs no I/O of its own, so the same code serves
//! files, pipes and tests; malformed records are typed errors carrying the
//! line number, and the caller decides whether to skip and report them.
//! May depend on `crate::percept` types only, never on the engine.

pub mod carmen;
pub mod uci;
