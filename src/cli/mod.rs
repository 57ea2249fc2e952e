//! The command line: `lplace check | explain | eval | simulate | extract | grid | compare | fuse
//! | survey | report | completions | man`.
//!
//! Flags are handled in two stages, as in ripgrep: [`args`] parses the command line with clap
//! into plain data, then each command module turns that into a ready-to-run command (files read,
//! engine loaded) and runs it. Output goes to stdout, diagnostics and summaries to stderr.
//!
//! # Exit codes
//! | code | meaning |
//! |------|---------|
//! | 0 | success (warnings may have been printed) |
//! | 1 | failure: a file could not be read or written, or another runtime error |
//! | 2 | bad arguments, or an input file (map, rules, frame) with errors |
//! | 3 | finished, but some input records were rejected (each reported with its line) |
//!
//! A closed stdout (`lplace … | head`) ends the program quietly with code 0.

pub mod args;
mod batch;
mod check;
mod compare;
mod completions;
mod data;
mod draw;
mod eval;
mod explain;
mod extract;
mod extract_rosbag2;
mod fuse;
mod grid;
pub mod output;
mod progress;
mod render;
mod report;
mod simulate;
mod stream_input;
pub mod survey;
mod wrap;

use std::io::Write;
use std::process::ExitCode;

/// Exit code: success.
pub const EXIT_OK: u8 = 0;
/// Exit code: runtime failure.
pub const EXIT_FAILURE: u8 = 1;
/// Exit code: bad arguments or input files.
pub const EXIT_BAD_INPUT: u8 = 2;
/// Exit code: finished with rejected records.
pub const EXIT_REJECTED: u8 = 3;

/// What went wrong in a command, and which exit code it maps to.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A file could not be read.
    #[error("cannot read `{path}`: {source}")]
    Read {
        /// The path.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// Writing the output failed.
    #[error("cannot write output: {0}")]
    Write(#[from] std::io::Error),
    /// An output file could not be written (exit 1).
    #[error("cannot write `{path}`: {source}")]
    WriteFile {
        /// The path.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// An output path that cannot work, found before any work was done (exit 2).
    #[error("cannot write `{path}` ({flag}): {why}")]
    OutputPath {
        /// The flag that named it.
        flag: &'static str,
        /// The path.
        path: String,
        /// What is wrong with it.
        why: output::OutputProblem,
    },
    /// Input files had errors; they have been printed already.
    #[error("{count} problem(s) found")]
    Diagnostics {
        /// How many.
        count: usize,
    },
    /// A bad argument value.
    #[error("{0}")]
    BadArgument(#[from] args::ArgError),
}

impl CliError {
    fn exit_code(&self) -> u8 {
        match self {
            CliError::Read { .. } => EXIT_FAILURE,
            CliError::Write(_) | CliError::WriteFile { .. } => EXIT_FAILURE,
            CliError::Diagnostics { .. }
            | CliError::BadArgument(_)
            | CliError::OutputPath { .. } => EXIT_BAD_INPUT,
        }
    }
}

/// Runs the command line; returns the process exit code.
pub fn main() -> ExitCode {
    let cli = match args::parse(std::env::args_os()) {
        Ok(cli) => cli,
        Err(e) => {
            // clap prints help/version to stdout (exit 0) and usage errors to stderr (exit 2).
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() {
                EXIT_BAD_INPUT
            } else {
                EXIT_OK
            });
        }
    };
    for note in cli.deprecations() {
        eprintln!("note: {note} (the old spelling will be removed in the next release)");
    }
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    let result = match cli.command {
        args::Command::Check(a) => check::run(&a, &mut out),
        args::Command::Explain(a) => explain::run(&a, &mut out),
        args::Command::Eval(a) => eval::run(&a, &mut out),
        args::Command::Simulate(a) => simulate::run(&a, &mut out),
        args::Command::Extract(a) => extract::run(&a, &mut out),
        args::Command::Grid(a) => grid::run(&a, &mut out),
        args::Command::Compare(a) => compare::run(&a, &mut out),
        args::Command::Fuse(a) => fuse::run(&a, &mut out),
        args::Command::Survey(a) => survey::run(&a, &mut out),
        args::Command::Draw(a) => draw::run(&a),
        args::Command::Report(a) => report::run(&a, &mut out),
        args::Command::Completions(a) => completions::completions(&a, &mut out),
        args::Command::Man => completions::man(&mut out),
    };
    let result = result.and_then(|code| out.flush().map(|_| code).map_err(CliError::Write));
    match result {
        Ok(code) => ExitCode::from(code),
        Err(CliError::Write(e)) if e.kind() == std::io::ErrorKind::BrokenPipe => {
            ExitCode::from(EXIT_OK)
        }
        Err(e) => {
            if !matches!(e, CliError::Diagnostics { .. }) {
                eprintln!("error: {e}");
            }
            ExitCode::from(e.exit_code())
        }
    }
}

/// Reads a file into a [`crate::syntax::diagnostic::SourceFile`] named as the user wrote it.
fn read_source(path: &std::path::Path) -> Result<crate::syntax::diagnostic::SourceFile, CliError> {
    let bytes = std::fs::read(path).map_err(|source| CliError::Read {
        path: path.display().to_string(),
        source,
    })?;
    // Not UTF-8: a diagnostic with line and column (exit 2), not an I/O error.
    match crate::syntax::diagnostic::SourceFile::from_bytes(path.display().to_string(), bytes) {
        (file, None) => Ok(file),
        (file, Some(d)) => {
            render::eprint(&file, std::slice::from_ref(&d));
            Err(CliError::Diagnostics { count: 1 })
        }
    }
}

/// A bad input already explained: prints `error: MSG` and exits 2 without a second message.
pub(super) fn bad(msg: impl std::fmt::Display) -> CliError {
    eprintln!("error: {msg}");
    CliError::Diagnostics { count: 1 }
}

/// Reads a RON configuration file (`--config`, `--tracker`, …): a file that is not UTF-8 is a
/// diagnostic with its line, as maps and rules are; a bad key or value names the file (its
/// parser's message gives the line).
pub(super) fn read_config<T, E: std::fmt::Display>(
    path: &std::path::Path,
    parse: impl Fn(&str) -> Result<T, E>,
) -> Result<T, CliError> {
    let src = read_source(path)?;
    parse(&src.text).map_err(|e| bad(format!("{}: {e}", path.display())))
}

/// Loads the engine named by `--map/--rules` (bundled office files for those not given),
/// printing every diagnostic of the failing file.
fn load_engine(
    model: &args::ModelArgs,
    opts: &crate::engine::CompileOptions,
) -> Result<crate::engine::Engine, CliError> {
    use crate::engine::{Engine, OFFICE_MAP, OFFICE_RULES};
    use crate::syntax::diagnostic::SourceFile;
    let map = match &model.map {
        Some(p) => read_source(p)?,
        None => SourceFile::new("maps/office.map (bundled)", OFFICE_MAP),
    };
    let rules = match &model.rules {
        Some(p) => read_source(p)?,
        None => SourceFile::new("rules/office.lpl (bundled)", OFFICE_RULES),
    };
    let engine = Engine::load_with(&map, &rules, opts).map_err(|e| {
        render::eprint(&e.file, &e.diagnostics);
        CliError::Diagnostics {
            count: e.diagnostics.len(),
        }
    })?;
    if !engine.warnings().is_empty() {
        render::eprint(&rules, engine.warnings());
    }
    Ok(engine)
}
