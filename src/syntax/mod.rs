//! The front end for lplace's two languages: spans, the AST, the pest parsers for rule files and
//! map files, and the diagnostics every later stage reports with. Resolving a rule file against
//! a map is the next layer's job (`rules`).
//!
//! This module depends on nothing else in the crate. pest is used only in here:
//! everything outside sees the AST and [`diagnostic::Diagnostic`]s.

pub mod ast;
pub mod diagnostic;
mod grammar;
pub mod parse_map;
pub mod parse_rules;
mod recover;
pub mod span;
pub mod suggest;

pub use diagnostic::{Diagnostic, DiagnosticKind, SourceFile};
pub use parse_map::parse_map;
pub use parse_rules::parse_rules;

/// The pest parsers, exposed for grammar tests (`parses_to!` / `fails_with!`) only. They are not
/// part of the stable API: build ASTs with [`parse_rules()`] and [`parse_map()`].
#[doc(hidden)]
pub mod pest_parsers {
    pub use super::grammar::{MapGrammar, MapRule, RulesGrammar, RulesRule};
}
