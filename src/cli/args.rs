//! Stage one of the command line: clap definitions, parsed into plain data. Nothing here reads a
//! file; `--help` texts are the reference for every flag.

use clap::{Args, Parser, Subcommand};
use std::ffi::OsString;
use std::path::PathBuf;

/// Possibilistic place recognition over annotated topological maps.
///
/// With no --map/--rules, commands use the bundled office example of paper 003
/// (maps/office.map, rules/office.lpl).
#[derive(Debug, Parser)]
#[command(name = "lplace", version, about, long_about = None, propagate_version = true)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Parse and check map (.map) and rule (.lpl) files; print every problem found.
    ///
    /// Rule files are checked against the map given among the files, else --map, else the
    /// bundled office map. Exit 0 when clean, 2 with errors.
    Check(CheckArgs),
    /// Print the closed-form degree function of each place (paper 003 eq. (6) style).
    Explain(ExplainArgs),
    /// Evaluate one frame and print the decision as JSON.
    Eval(EvalArgs),
}

/// The map and rules to load.
#[derive(Debug, Args, Clone)]
pub struct ModelArgs {
    /// Map file (.map). Default: the bundled office map.
    #[arg(long, value_name = "MAP")]
    pub map: Option<PathBuf>,
    /// Rule file (.lpl). Default: the bundled office rules.
    #[arg(long, value_name = "RULES")]
    pub rules: Option<PathBuf>,
}

/// `lplace check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Files to check: .map and .lpl.
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Map to check rule files against when no .map is among FILES.
    #[arg(long, value_name = "MAP")]
    pub map: Option<PathBuf>,
}

/// `lplace explain`.
#[derive(Debug, Args)]
pub struct ExplainArgs {
    /// The map and rules.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Only this place.
    #[arg(long, value_name = "PLACE")]
    pub place: Option<String>,
    /// Also print each formula in the paper's dissimilarity form (δ = 1 − degree).
    #[arg(long)]
    pub dissimilarity: bool,
}

/// Output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// One JSON object.
    Json,
    /// A human-readable table.
    Table,
}

/// `lplace eval`.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// The map and rules.
    #[command(flatten)]
    pub model: ModelArgs,
    /// One frame as JSON, e.g. '{"percepts":[{"name":"sonar_wall","args":["North"],"degree":0.8}]}'.
    #[arg(long, value_name = "JSON", required = true)]
    pub frame: String,
    /// Also list the rule instances that fired and how strongly.
    #[arg(long)]
    pub trace: bool,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Json)]
    pub format: Format,
}

/// A flag value that parsed but makes no sense.
#[derive(Debug, thiserror::Error)]
pub enum ArgError {
    /// `--place` names no place of the map.
    #[error("no place `{name}` in the map (places: {known})")]
    UnknownPlace {
        /// What was asked.
        name: String,
        /// The places there are.
        known: String,
    },
    /// The frame given with `--frame` is not usable.
    #[error("--frame: {0}")]
    Frame(#[from] crate::io::record::RecordError),
}

/// Parses the command line (stage one).
pub fn parse<I, T>(args: I) -> Result<Cli, clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    Cli::try_parse_from(args)
}
