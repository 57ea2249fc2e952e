//! `lplace survey --map MAP --rules RULES STREAM [--labels CSV] [--fit all|first-visits]
//! [-o OUT]`: fit each place's expected percept values from a run with ground truth and write
//! them into the map, touching nothing else (the fitting and the span edits are library code,
//! [`crate::survey`]). Prints per place the scans used and the spread on stderr, warns on
//! places with too few scans; with `--fit first-visits`, fits on each place's first visit and
//! prints how the map so written does on the later visits (held-out frames).

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};

use super::{read_source, render, CliError, EXIT_OK, EXIT_REJECTED};
use crate::engine::tracker::TrackerConfig;
use crate::engine::{CompileOptions, Engine};
use crate::io::record::FrameRecord;
use crate::report::run::StreamRun;
use crate::survey::{
    decide_all, fit, links_from_rules, visits, write_params, Protocol, Score, SurveyConfig,
};
use crate::syntax::diagnostic::SourceFile;
use crate::syntax::{parse_map, parse_rules};

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
    /// Percept stream of the survey run (JSON lines, `lplace extract`), with `truth.place`
    /// unless --labels is given.
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
    /// Tracker parameters (RON) for the held-out score of --fit first-visits.
    #[arg(long, value_name = "CONFIG")]
    pub tracker: Option<PathBuf>,
    /// Quantiles of each place's readings that bound its expected range.
    #[arg(long, num_args = 2, value_names = ["LO", "HI"], default_values_t = [0.1, 0.9])]
    pub quantiles: Vec<f64>,
    /// Places fitted from fewer scans are warned about.
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub min_scans: usize,
}

/// Runs `survey`.
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
    let rules_src = read_source(&args.rules)?;
    let map_ast = parse_map(&map_src.text).map_err(|d| fail(&map_src, d))?;
    let rules_ast = parse_rules(&rules_src.text).map_err(|d| fail(&rules_src, d))?;
    let (lo, hi) = match args.quantiles[..] {
        [lo, hi] if (0.0..=1.0).contains(&lo) && (lo..=1.0).contains(&hi) => (lo, hi),
        _ => {
            eprintln!("error: --quantiles LO HI needs 0 ≤ LO ≤ HI ≤ 1");
            return Err(CliError::Diagnostics { count: 1 });
        }
    };
    let cfg = SurveyConfig {
        lo,
        hi,
        min_scans: args.min_scans,
        ..SurveyConfig::default()
    };
    let (frames, rejected) = read_frames(&args.stream)?;
    let labels = match &args.labels {
        Some(path) => label_frames(&frames, &read_labels(path)?),
        None => frames
            .iter()
            .map(|f| f.truth.as_ref().and_then(|t| t.place.clone()))
            .collect(),
    };
    let links = links_from_rules(&rules_ast);
    if links.is_empty() {
        eprintln!("error: {}: no rule compares a percept with a place parameter (such as `free_i(d)`): nothing to fit", rules_src.name);
        return Err(CliError::Diagnostics { count: 1 });
    }
    let protocol = match args.fit {
        FitArg::All => Protocol::All,
        FitArg::FirstVisits => Protocol::FirstVisits,
    };
    let fits = fit(&frames, &labels, &links, protocol, &cfg);
    for f in &fits {
        let warn = if f.scans < cfg.min_scans {
            "  WARNING: few scans, the fit is unreliable"
        } else {
            ""
        };
        eprintln!(
            "survey: {}: {} scan(s), median spread {:.2}{warn}",
            f.place,
            f.scans,
            f.spread()
        );
    }
    let text = write_params(&map_src.text, &map_ast, &fits).map_err(|e| {
        eprintln!("error: {}: {e}", map_src.name);
        CliError::Diagnostics { count: 1 }
    })?;
    if protocol == Protocol::FirstVisits {
        let written = SourceFile::new(map_src.name.clone(), text.clone());
        let tracker = tracker_config(args.tracker.as_ref())?;
        let held = held_out(&written, &rules_src, tracker, &frames, &labels, &cfg)?;
        eprintln!("survey: later visits (held out): {held}");
    }
    match &args.output {
        Some(path) => super::output::write_atomic(path, |w| w.write_all(text.as_bytes()))?,
        None => out.write_all(text.as_bytes())?,
    }
    Ok(if rejected > 0 { EXIT_REJECTED } else { EXIT_OK })
}

fn fail(src: &SourceFile, d: Vec<crate::syntax::diagnostic::Diagnostic>) -> CliError {
    render::eprint(src, &d);
    CliError::Diagnostics { count: d.len() }
}

/// Every parseable record of the stream; malformed lines are reported and counted.
fn read_frames(path: &Path) -> Result<(Vec<FrameRecord>, usize), CliError> {
    let file = std::fs::File::open(path).map_err(|source| CliError::Read {
        path: path.display().to_string(),
        source,
    })?;
    let (mut frames, mut rejected) = (Vec::new(), 0);
    for (n, line) in BufReader::new(file).lines().enumerate() {
        let line = line.map_err(|source| CliError::Read {
            path: path.display().to_string(),
            source,
        })?;
        if line.trim().is_empty() {
            continue;
        }
        match FrameRecord::parse(&line) {
            Ok(f) => frames.push(f),
            Err(e) => {
                eprintln!("{}:{}: {e}", path.display(), n + 1);
                rejected += 1;
            }
        }
    }
    Ok((frames, rejected))
}

/// `t,place` rows (a header and blank lines are skipped; an empty place is "between places"),
/// sorted by time.
fn read_labels(path: &Path) -> Result<Vec<(f64, Option<String>)>, CliError> {
    let src = read_source(path)?;
    let mut rows = Vec::new();
    for (n, line) in src.text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (t, place) = line.split_once(',').unwrap_or((line, ""));
        match t.trim().parse::<f64>() {
            Ok(t) if t.is_finite() => {
                let p = place.trim();
                rows.push((t, (!p.is_empty()).then(|| p.to_owned())));
            }
            _ if n == 0 => {} // a header
            _ => {
                eprintln!("{}:{}: expected `t,place`", src.name, n + 1);
                return Err(CliError::Diagnostics { count: 1 });
            }
        }
    }
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(rows)
}

/// Each frame's label: the row nearest its time, if within 0.5 s.
fn label_frames(frames: &[FrameRecord], rows: &[(f64, Option<String>)]) -> Vec<Option<String>> {
    frames
        .iter()
        .map(|f| {
            let t = f.t?;
            let i = rows.partition_point(|r| r.0 < t);
            let near = [i.checked_sub(1), Some(i)]
                .into_iter()
                .flatten()
                .filter_map(|k| rows.get(k))
                .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))?;
            ((near.0 - t).abs() <= 0.5)
                .then(|| near.1.clone())
                .flatten()
        })
        .collect()
}

fn tracker_config(path: Option<&PathBuf>) -> Result<TrackerConfig, CliError> {
    let Some(path) = path else {
        return Ok(TrackerConfig::default());
    };
    let src = read_source(path)?;
    TrackerConfig::from_ron(&src.text).map_err(|e| {
        eprintln!("error: {}: {e}", src.name);
        CliError::Diagnostics { count: 1 }
    })
}

/// Runs the engine and the tracker over every frame with the written map and scores the
/// frames of later visits (the tracker sees the whole run, as it would live).
fn held_out(
    map: &SourceFile,
    rules: &SourceFile,
    tracker: TrackerConfig,
    frames: &[FrameRecord],
    labels: &[Option<String>],
    cfg: &SurveyConfig,
) -> Result<Score, CliError> {
    let engine = Engine::load_with(map, rules, &CompileOptions::default()).map_err(|e| {
        render::eprint(&e.file, &e.diagnostics);
        CliError::Diagnostics {
            count: e.diagnostics.len(),
        }
    })?;
    let names: BTreeMap<String, usize> = engine
        .map()
        .places()
        .iter()
        .enumerate()
        .map(|(k, p)| (p.name.clone(), k))
        .collect();
    let mut run = StreamRun::new(engine, Some(tracker));
    let visit = visits(frames, labels, cfg.visit_gap_m);
    let decisions = decide_all(&mut run, frames);
    let truth: Vec<Option<usize>> = labels
        .iter()
        .map(|l| l.as_ref().and_then(|l| names.get(l)).copied())
        .collect();
    let score = Score::of(&decisions, &truth, |k| {
        visit.get(k).copied().flatten().is_some_and(|v| v > 0)
    });
    Ok(score)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_take_the_label_nearest_in_time_within_half_a_second() {
        let at = |t: f64| FrameRecord {
            version: None,
            t: Some(t),
            odometry: None,
            heading: None,
            region: None,
            percepts: Vec::new(),
            truth: None,
        };
        let frames = [at(0.0), at(1.0), at(2.0), at(2.3)];
        let rows = [
            (0.1, Some("A".to_owned())),
            (1.9, Some("B".to_owned())),
            (2.35, None),
        ];
        let got = label_frames(&frames, &rows);
        // 1.0 is 0.9 s from both rows: no label; 2.3 is nearest the "between places" row.
        assert_eq!(
            got,
            vec![Some("A".to_owned()), None, Some("B".to_owned()), None]
        );
    }
}
