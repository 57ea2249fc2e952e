//! `lplace report RUN… -o report.html`: evaluate one or more percept streams exactly as `lplace
//! eval` does (same map, rules, tracker, decisions and summary) and write one self-contained
//! HTML page about them ([`crate::report::html`]).
//!
//! A RUN is a percept stream (JSON Lines or CSV, as `eval` reads; `-` is stdin) evaluated with
//! the `--map`, `--rules` and `--tracker` given once for all runs. Rejected records are
//! reported on stderr as `STREAM:LINE: reason`, counted in the page, and make the exit code 3
//! once the page is written.

use std::path::PathBuf;

use clap::Args;

use super::args::ModelArgs;
use super::{load_engine, CliError, EXIT_OK, EXIT_REJECTED};
use crate::engine::CompileOptions;
use crate::io::stream::{read_records, Record, StreamFormat, StreamReader, Threads};
use crate::report::html::{self, RunPage, RunRecorder, Setup};
use crate::report::StreamRun;

/// `lplace report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// The map and rules, shared by every run.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Percept streams to evaluate, one section each: JSON Lines (.jsonl) or CSV (.csv); `-`
    /// reads stdin. Default: the bundled office recording.
    #[arg(value_name = "RUN")]
    pub runs: Vec<PathBuf>,
    /// Tracker parameters (a RON file such as config/intel-tracker.ron, whose metric grid
    /// tracker adds belief pictures to the page); fields left out take the defaults. Default:
    /// the rule file's `tracker { … }` block, else the built-in defaults.
    #[arg(long, value_name = "RON")]
    pub tracker: Option<PathBuf>,
    /// Decide each frame on its own evidence, without tracking.
    #[arg(long, conflicts_with = "tracker")]
    pub no_track: bool,
    /// Write the page to this file (default: stdout).
    #[arg(long, short, value_name = "HTML")]
    pub output: Option<PathBuf>,
    /// The page's title.
    #[arg(long, value_name = "TEXT", default_value = "lplace run report")]
    pub title: String,
}

/// Runs `report`.
pub fn run(args: &ReportArgs, out: &mut impl std::io::Write) -> Result<u8, CliError> {
    let engine = load_engine(&args.model, &CompileOptions::default())?;
    let cfg = match &args.tracker {
        Some(path) => Some(super::read_config(
            path,
            crate::engine::tracker::TrackerConfig::from_ron,
        )?),
        None => (!args.no_track).then(|| engine.tracker_config()),
    };
    let map = engine.map().clone();
    let mut pages = Vec::new();
    let mut rejected = 0;
    if args.runs.is_empty() {
        let input = Box::new(super::eval::OFFICE_RECORDING.as_bytes());
        let name = "recordings/office.jsonl (bundled)".to_string();
        let run = StreamRun::new(engine.clone(), cfg);
        pages.push(one_run(run, name, input, StreamFormat::JsonLines, &map)?);
    }
    for path in &args.runs {
        let s = super::stream_input::open(path)?;
        let run = StreamRun::new(engine.clone(), cfg);
        pages.push(one_run(
            run,
            s.name,
            s.input,
            StreamFormat::from_path(path),
            &map,
        )?);
    }
    for p in &pages {
        rejected += p.summary.rejected;
    }
    let page = html::page(&args.title, &setup(args), &pages);
    match &args.output {
        Some(path) => {
            std::fs::write(path, page).map_err(|e| super::grid::output_error(path, e))?;
        }
        None => out.write_all(page.as_bytes())?,
    }
    Ok(if rejected > 0 { EXIT_REJECTED } else { EXIT_OK })
}

/// Evaluates one stream and returns its section.
fn one_run(
    mut run: StreamRun,
    name: String,
    input: Box<dyn std::io::BufRead + Send>,
    format: StreamFormat,
    map: &crate::map::Map,
) -> Result<RunPage, CliError> {
    let mut rec = RunRecorder::new(name.clone(), run.places().to_vec());
    let reader = StreamReader::new(input, run.schema(), format);
    let read_error = |source| CliError::Read {
        path: name.clone(),
        source,
    };
    read_records(
        reader,
        Threads::available(),
        |_| {},
        read_error,
        |record| {
            match record {
                Record::Rejected(e) => {
                    eprintln!("{}", super::stream_input::rejection(&name, &e));
                    run.reject(&e.reason);
                }
                Record::Frame(frame, meta) => {
                    let d = run.step(frame, meta);
                    rec.push(run.distribution(), d, meta, run.grid_tracker());
                }
            }
            Ok::<(), CliError>(())
        },
    )?;
    Ok(rec.finish(run.summary(), map, run.grid_tracker()))
}

/// How the runs were made, for the page's header.
fn setup(args: &ReportArgs) -> Setup {
    let name = |p: &Option<PathBuf>, bundled: &str| {
        p.as_ref()
            .map_or(bundled.to_string(), |p| p.display().to_string())
    };
    let tracker = match (&args.tracker, args.no_track) {
        (Some(p), _) => p.display().to_string(),
        (None, true) => "none (--no-track)".into(),
        (None, false) => "graph tracker, defaults".into(),
    };
    vec![
        (
            "map".into(),
            name(&args.model.map, "maps/office.map (bundled)"),
        ),
        (
            "rules".into(),
            name(&args.model.rules, "rules/office.lpl (bundled)"),
        ),
        ("tracker".into(), tracker),
        (
            "made by".into(),
            format!("lplace {} report", env!("CARGO_PKG_VERSION")),
        ),
    ]
}
