//! The command line, end to end: every subcommand, its exit codes and its messages.

#[allow(dead_code)]
#[path = "../support/mod.rs"]
mod support;

mod cli_compare;
mod cli_conventions;
mod cli_eval;
mod cli_fuse;
mod cli_grid;
mod cli_hostile;
mod cli_pictures;
mod cli_report;
mod cli_simulate;
mod cli_survey;
