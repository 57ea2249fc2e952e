//! The front end for lplace's two languages: spans, the AST, the pest parsers for rule files and
//! map files, the checker that resolves a rule file against a map, and the diagnostics all of
//! them report.
//!
//! This module may depend on `crate::logic` (the checker produces its `LogicConfig` and
//! `Trapezoid`) and `crate::map` (the checker resolves names against the map model). pest is used
//! only in here: everything outside sees the AST and [`diagnostic::Diagnostic`]s.

pub mod ast;
pub mod check;
pub mod diagnostic;
mod grammar;
pub mod parse_map;
pub mod parse_rules;
mod recover;
pub mod span;

pub use check::{check_map_against_rules, check_rules, RuleSet, Signature};
pub use diagnostic::{Diagnostic, DiagnosticKind, SourceFile};
pub use parse_map::parse_map;
pub use parse_rules::parse_rules;

/// The pest parsers, exposed for grammar tests (`parses_to!` / `fails_with!`) only. They are not
/// part of the stable API: build ASTs with [`parse_rules()`] and [`parse_map()`].
#[doc(hidden)]
pub mod pest_parsers {
    pub use super::grammar::{MapGrammar, MapRule, RulesGrammar, RulesRule};
}
