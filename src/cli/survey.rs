//! `lplace survey --map MAP --rules RULES STREAM [--labels CSV] [--fit all|first-visits]
//! [-o OUT]`: fit each place's expected percept values from a run with ground truth and write
//! them into the map, touching nothing else. The survey itself is library code
//! ([`crate::survey::Survey`], shared with the Python binding); this file parses the arguments,
//! reads the files (the stream opened as every command opens one, `cli::stream_input`, and read
//! by the survey's [`crate::io::stream::StreamReader`]: a rejected record is reported as
//! `STREAM:LINE: reason` and makes the exit code 3, as in `eval`) and prints: per place the scans
//! used and the spread on stderr, a warning on
//! places with too few scans, and with `--fit first-visits` how the map so written does on the
//! later visits (held-out frames) and a warning on places most of whose later readings lie
//! outside the fitted ranges.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::{read_source, render, stream_input, CliError, EXIT_OK, EXIT_REJECTED};
use crate::engine::tracker::TrackerConfig;
use crate::io::stream::StreamFormat;
use crate::survey::{
    parse_labels, LabelRow, Protocol, Records, Survey, SurveyConfig, SurveyError, Truth,
};

/// Which frames fit the map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FitArg {
    /// Every frame with a place.
    All,
    /// Each place's first visit; the later visits are scored with the map so fitted.
    FirstVisits,
}

/// `lplace survey`.
#[derive(Debug, Clone, clap::Args)]
pub struct SurveyArgs {
    /// The map to fill in (.map).
    #[arg(long, value_name = "MAP")]
    pub map: PathBuf,
    /// The rules (.lpl): which percepts feed which place parameters.
    #[arg(long, value_name = "RULES")]
    pub rules: PathBuf,
    /// Percept stream of the survey run (JSON Lines as `lplace extract` writes them, or CSV by
    /// the .csv extension; `-` reads stdin), with `truth.place` unless --labels is given.
    #[arg(value_name = "STREAM")]
    pub stream: PathBuf,
    /// Ground truth as a CSV `t,place` (header optional): each frame takes the label nearest
    /// in time, within 0.5 s.
    #[arg(long, value_name = "CSV")]
    pub labels: Option<PathBuf>,
    /// Fit on every frame, or on first visits (and score the later ones).
    #[arg(long, value_enum, default_value_t = FitArg::All)]
    pub fit: FitArg,
    /// Write the map here instead of stdout.
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Tracker parameters (RON) for the held-out score of --fit first-visits. Default: the rule
    /// file's `tracker { … }` block, else the built-in defaults.
    #[arg(long, value_name = "CONFIG")]
    pub tracker: Option<PathBuf>,
    /// Quantiles of each place's readings that bound its expected range.
    #[arg(long, num_args = 2, value_names = ["LO", "HI"], default_values_t = [0.1, 0.9])]
    pub quantiles: Vec<f64>,
    /// Places fitted from fewer scans are warned about.
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub min_scans: usize,
}

/// Runs `survey`: reads the files, hands them to [`Survey`], prints what it says.
///
/// # Errors
/// [`CliError`] when a file cannot be read or written, or the map, rules or stream are bad.
pub fn run(args: &SurveyArgs, out: &mut impl Write) -> Result<u8, CliError> {
    if let Some(p) = &args.output {
        let inputs = [
            ("--map", args.map.as_path()),
            ("--rules", args.rules.as_path()),
            ("STREAM", args.stream.as_path()),
        ];
        let labels = args.labels.as_deref().map(|p| ("--labels", p));
        let inputs: Vec<_> = inputs.into_iter().chain(labels).collect();
        super::output::check(&[super::output::Output::file("--output", p)], &inputs)?;
    }
    let map_src = read_source(&args.map)?;
    let map_name = map_src.name.clone();
    let rules_src = read_source(&args.rules)?;
    let (lo, hi) = match args.quantiles[..] {
        [lo, hi] => (lo, hi),
        _ => (f64::NAN, f64::NAN),
    };
    let cfg = SurveyConfig {
        lo,
        hi,
        min_scans: args.min_scans,
        ..SurveyConfig::default()
    };
    let survey = Survey::new(map_src, rules_src, cfg).map_err(|e| fail(&map_name, e))?;
    let records = read_frames(&survey, &args.stream)?;
    let labels = match &args.labels {
        Some(path) => Some(read_labels(path)?),
        None => None,
    };
    let truth = labels.as_deref().map_or(Truth::Records, Truth::Labels);
    let protocol = match args.fit {
        FitArg::All => Protocol::All,
        FitArg::FirstVisits => Protocol::FirstVisits,
    };
    // The tracker only scores first visits: a file given with `--fit all` is not read.
    let tracker = match protocol {
        Protocol::All => None,
        Protocol::FirstVisits => tracker_config(args.tracker.as_ref())?,
    };
    let outcome = survey
        .run(&records.frames, truth, protocol, tracker.as_ref())
        .map_err(|e| fail(&map_name, e))?;
    for row in &outcome.report {
        eprintln!("survey: {row}");
    }
    if let Some(held) = &outcome.held_out {
        eprintln!("survey: later visits (held out): {held}");
    }
    let text = outcome.map_text.as_bytes();
    match &args.output {
        Some(path) => super::output::write_atomic(path, |w| w.write_all(text))?,
        None => out.write_all(text)?,
    }
    Ok(if records.rejected.is_empty() {
        EXIT_OK
    } else {
        EXIT_REJECTED
    })
}

/// Prints a survey error as the command line words it (exit 2).
fn fail(map_name: &str, e: SurveyError) -> CliError {
    match e {
        SurveyError::Load(e) => {
            render::eprint(&e.file, &e.diagnostics);
            return CliError::Diagnostics {
                count: e.diagnostics.len(),
            };
        }
        SurveyError::Quantiles { .. } => {
            eprintln!("error: --quantiles LO HI needs 0 ≤ LO ≤ HI ≤ 1");
        }
        SurveyError::UnknownPlace { .. } | SurveyError::SpanMismatch { .. } => {
            eprintln!("error: {map_name}: {e}");
        }
        SurveyError::NothingToFit { .. } | SurveyError::LabelRow { .. } => {
            eprintln!("error: {e}");
        }
    }
    CliError::Diagnostics { count: 1 }
}

/// Every accepted record of the stream at `path` (`-` for stdin; CSV by its extension), read as
/// `lplace eval` reads it; each rejected record is reported as `STREAM:LINE: reason`.
fn read_frames(survey: &Survey, path: &Path) -> Result<Records, CliError> {
    let stream = stream_input::open(path)?;
    let records = survey
        .read_records(stream.input, StreamFormat::from_path(path))
        .map_err(|source| CliError::Read {
            path: stream.name.clone(),
            source,
        })?;
    for e in &records.rejected {
        eprintln!("{}", stream_input::rejection(&stream.name, e));
    }
    Ok(records)
}

/// The rows of the labels CSV at `path` ([`parse_labels`]).
pub(super) fn read_labels(path: &Path) -> Result<Vec<LabelRow>, CliError> {
    let src = read_source(path)?;
    parse_labels(&src.text).map_err(|e| {
        if let SurveyError::LabelRow { line } = e {
            eprintln!("{}:{line}: expected `t,place`", src.name);
        } else {
            eprintln!("error: {}: {e}", src.name);
        }
        CliError::Diagnostics { count: 1 }
    })
}

/// The `--tracker` file, if given (without it the rule file's `tracker { … }` block, or the
/// defaults, track the held-out visits).
fn tracker_config(path: Option<&PathBuf>) -> Result<Option<TrackerConfig>, CliError> {
    let Some(path) = path else {
        return Ok(None);
    };
    super::read_config(path, TrackerConfig::from_ron).map(Some)
}
