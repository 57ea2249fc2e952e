//! `lplace eval`: evaluate a percept stream (or one `--frame`) and print one decision per frame,
//! then a summary.
//!
//! The stream is read line by line ([`crate::io::stream`]) — on a second thread, a few batches
//! ahead, when the machine has a second core ([`Threads::available`]) — and each frame stepped
//! by a [`StreamRun`] (the engine and, unless `--no-track`, the tracker); decisions are written as they
//! come, so memory stays flat on any length. Rejected records are reported on stderr as `STREAM:LINE: reason`, counted,
//! and make the exit code 3.

use super::args::{ArgError, EvalArgs, Format, StreamForm, SummaryFormat};
use super::{load_engine, CliError, EXIT_OK, EXIT_REJECTED};
use crate::engine::outcome::QueryOutcome;
use crate::engine::tracker::TrackerConfig;
use crate::engine::{CompileOptions, Engine};
use crate::io::record::FrameRecord;
use crate::io::stream::{read_records, FrameMeta, Record, StreamFormat, StreamReader, Threads};
use crate::logic::{Decision, PlaceDistribution, PlaceSet};
use crate::report::summary::reason_name;
use crate::report::trajectory::{self, TrajectoryPoint, Verdict};
use crate::report::{RunPlot, StreamRun};
use std::io::{BufRead, IsTerminal, Write};

/// The bundled office recording (made by `lplace simulate`, see docs/streams.md).
pub const OFFICE_RECORDING: &str = include_str!("../../recordings/office.jsonl");

/// Runs `eval`.
pub fn run(args: &EvalArgs, out: &mut impl Write) -> Result<u8, CliError> {
    match &args.frame {
        Some(json) => run_frame(args, json, out),
        None => run_stream(args, out),
    }
}

/// Evaluates one frame. A frame with any unusable percept is rejected whole (exit 2): on the
/// command line, a typo should not quietly change the answer.
fn run_frame(args: &EvalArgs, json: &str, out: &mut impl Write) -> Result<u8, CliError> {
    let opts = CompileOptions {
        trace: args.trace,
        ..CompileOptions::default()
    };
    let mut engine = load_engine(&args.model, &opts)?;
    let record = FrameRecord::parse(json).map_err(ArgError::Frame)?;
    let mut frame = engine.new_frame();
    let mut rejected = Vec::new();
    record.fill(engine.percepts(), &mut frame, &mut rejected);
    if let Some(first) = rejected.into_iter().next() {
        return Err(ArgError::Frame(first).into());
    }
    let queries = resolve_queries(&engine, &args.query)?;
    let known = match &record.region {
        Some(name) => Some(engine.query_set(name).map_err(|error| ArgError::Query {
            query: name.clone(),
            error,
        })?),
        None => None,
    };
    engine.step_within(&frame, known.as_ref());
    let mut outcome = engine.outcome();
    let place_names = engine.map().places();
    for (q, set) in &queries {
        let (possibility, necessity) = engine.set_degrees(set);
        outcome.queries.push(QueryOutcome {
            query: q.clone(),
            places: set
                .indices()
                .filter_map(|k| place_names.get(k))
                .map(|p| p.name.clone())
                .collect(),
            possibility,
            necessity,
        });
    }
    match args.format {
        Format::Json => {
            serde_json::to_writer_pretty(&mut *out, &outcome).map_err(std::io::Error::from)?;
            writeln!(out)?;
        }
        Format::Csv => {
            writeln!(out, "outcome,place,necessity,reason,inconsistency")?;
            writeln!(
                out,
                "{},{},{},{},{}",
                outcome.outcome,
                outcome.place.as_deref().unwrap_or(""),
                outcome.necessity.map_or(String::new(), |n| n.to_string()),
                outcome.reason.unwrap_or(""),
                outcome.inconsistency
            )?;
        }
        Format::Table => write_table(&outcome, out)?,
    }
    Ok(EXIT_OK)
}

/// The `--frame` outcome as a table: the decision, Inc, per place α, β, π, Π, N, then rooms,
/// regions, queries and fired rules.
fn write_table(outcome: &crate::engine::Outcome, out: &mut impl Write) -> std::io::Result<()> {
    match (&outcome.place, outcome.reason) {
        (Some(p), _) => writeln!(
            out,
            "place {p} (N = {:.3})",
            outcome.necessity.unwrap_or(0.0)
        )?,
        (None, Some(r)) => writeln!(out, "disoriented: {r} {}", outcome.candidates.join(" vs "))?,
        (None, None) => writeln!(out, "disoriented")?,
    }
    writeln!(out, "Inc = {:.3}", outcome.inconsistency)?;
    writeln!(
        out,
        "{:<8} {:>7} {:>7} {:>7} {:>7} {:>7}",
        "place", "support", "exclude", "π", "Π", "N"
    )?;
    for p in &outcome.places {
        writeln!(
            out,
            "{:<8} {:>7.3} {:>7.3} {:>7.3} {:>7.3} {:>7.3}",
            p.place, p.support, p.exclusion, p.possibility_raw, p.possibility, p.necessity
        )?;
    }
    for r in &outcome.rooms {
        writeln!(
            out,
            "room {:<3} support {:.3}  Π {:.3}  N {:.3}",
            r.room, r.support, r.possibility, r.necessity
        )?;
    }
    for r in &outcome.regions {
        writeln!(
            out,
            "region {} support {:.3}  Π {:.3}  N {:.3}",
            r.room, r.support, r.possibility, r.necessity
        )?;
    }
    for q in &outcome.queries {
        writeln!(
            out,
            "query {} = {{{}}}  Π {:.3}  N {:.3}",
            q.query,
            q.places.join(", "),
            q.possibility,
            q.necessity
        )?;
    }
    for f in &outcome.fired {
        writeln!(
            out,
            "  rule {} @{} [{}] ⊢ {} = {:.3}",
            f.rule,
            f.context,
            f.binding.join(" "),
            f.head,
            f.degree
        )?;
    }
    Ok(())
}

/// Resolves every `--query` against the engine's map and rules.
fn resolve_queries(
    engine: &Engine,
    queries: &[String],
) -> Result<Vec<(String, PlaceSet)>, CliError> {
    let mut out = Vec::new();
    for q in queries {
        let set = engine.query_set(q).map_err(|error| ArgError::Query {
            query: q.clone(),
            error,
        })?;
        out.push((q.clone(), set));
    }
    Ok(out)
}

/// Reads the tracker configuration named by `--tracker` (defaults without it).
fn tracker_config(args: &EvalArgs) -> Result<TrackerConfig, CliError> {
    let Some(path) = &args.tracker else {
        return Ok(TrackerConfig::default());
    };
    let text = std::fs::read_to_string(path).map_err(|source| CliError::Read {
        path: path.display().to_string(),
        source,
    })?;
    TrackerConfig::from_ron(&text).map_err(|e| {
        eprintln!("{}: {e}", path.display());
        CliError::Diagnostics { count: 1 }
    })
}

/// Writes a degree in `[0, 1]` with 4 decimals, without going through float formatting (this
/// is on the per-frame path).
fn write_degree(out: &mut impl Write, x: f64) -> std::io::Result<()> {
    let v = (x.clamp(0.0, 1.0) * 10_000.0).round() as u32;
    let frac = v % 10_000;
    let digits = [
        b'0' + (v / 10_000) as u8,
        b'.',
        b'0' + (frac / 1000) as u8,
        b'0' + (frac / 100 % 10) as u8,
        b'0' + (frac / 10 % 10) as u8,
        b'0' + (frac % 10) as u8,
    ];
    out.write_all(&digits)
}

/// Writes `n` in decimal, without going through the formatting machinery (per-frame path).
fn write_u64(out: &mut impl Write, mut n: u64) -> std::io::Result<()> {
    // u64::MAX has 20 digits.
    let mut digits = [0u8; 20];
    let mut start = digits.len();
    loop {
        start -= 1;
        digits[start] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    out.write_all(&digits[start..])
}

/// Everything one stream evaluation needs, built once.
struct Session<'a> {
    run: StreamRun,
    places: Vec<String>,
    args: &'a EvalArgs,
    /// `--query` sets, resolved once.
    queries: Vec<(String, PlaceSet)>,
}

impl Session<'_> {
    fn dist(&self) -> &PlaceDistribution {
        self.run.distribution()
    }

    fn write_header(&self, out: &mut impl Write) -> std::io::Result<()> {
        match self.args.format {
            Format::Csv => {
                write!(
                    out,
                    "line,t,outcome,place,necessity,reason,inconsistency,truth"
                )?;
                for (q, _) in &self.queries {
                    write!(out, ",pi:{q},n:{q}")?;
                }
                if self.args.degrees {
                    for p in &self.places {
                        write!(out, ",pi:{p},n:{p}")?;
                    }
                }
                writeln!(out)
            }
            Format::Table => writeln!(
                out,
                "{:>7} {:>9}  {:<26} {:>6} {:>6}  truth",
                "line", "t", "decision", "N", "Inc"
            ),
            Format::Json => Ok(()),
        }
    }

    fn write_decision(
        &self,
        out: &mut impl Write,
        d: Decision,
        meta: &FrameMeta,
    ) -> std::io::Result<()> {
        let dist = self.dist();
        let name = |k: usize| self.places.get(k).map_or("?", String::as_str);
        let truth = if meta.truth_known {
            Some(meta.truth_place.map_or("none", name))
        } else {
            None
        };
        match self.args.format {
            Format::Json => {
                out.write_all(b"{\"line\":")?;
                write_u64(out, meta.line)?;
                if let Some(t) = meta.t {
                    write!(out, ",\"t\":{t}")?;
                }
                match d {
                    Decision::Place { place, necessity } => {
                        out.write_all(b",\"place\":\"")?;
                        out.write_all(name(place).as_bytes())?;
                        out.write_all(b"\",\"necessity\":")?;
                        write_degree(out, necessity)?;
                    }
                    Decision::Disoriented(why) => {
                        out.write_all(b",\"place\":null,\"reason\":\"")?;
                        out.write_all(reason_name(&why).as_bytes())?;
                        out.write_all(b"\"")?;
                    }
                }
                out.write_all(b",\"inconsistency\":")?;
                write_degree(out, dist.inconsistency)?;
                match truth {
                    Some(t) if meta.truth_place.is_some() => {
                        out.write_all(b",\"truth\":\"")?;
                        out.write_all(t.as_bytes())?;
                        out.write_all(b"\"")?;
                    }
                    Some(_) => out.write_all(b",\"truth\":null")?,
                    None => {}
                }
                for (i, (_, set)) in self.queries.iter().enumerate() {
                    out.write_all(if i == 0 { b",\"queries\":[[" } else { b",[" })?;
                    write_degree(out, set.possibility(&dist.possibility))?;
                    out.write_all(b",")?;
                    write_degree(out, set.necessity(&dist.possibility))?;
                    out.write_all(if i + 1 == self.queries.len() {
                        b"]]"
                    } else {
                        b"]"
                    })?;
                }
                if self.args.degrees {
                    for (key, v) in [
                        (&b",\"possibility\":["[..], &dist.possibility),
                        (&b",\"necessities\":["[..], &dist.necessity),
                    ] {
                        out.write_all(key)?;
                        for (i, x) in v.iter().enumerate() {
                            if i > 0 {
                                out.write_all(b",")?;
                            }
                            write_degree(out, *x)?;
                        }
                        out.write_all(b"]")?;
                    }
                }
                out.write_all(b"}\n")
            }
            Format::Csv => {
                write_u64(out, meta.line)?;
                out.write_all(b",")?;
                if let Some(t) = meta.t {
                    write!(out, "{t}")?;
                }
                match d {
                    Decision::Place { place, necessity } => {
                        out.write_all(b",place,")?;
                        out.write_all(name(place).as_bytes())?;
                        out.write_all(b",")?;
                        write_degree(out, necessity)?;
                        out.write_all(b",,")?;
                    }
                    Decision::Disoriented(why) => {
                        out.write_all(b",disoriented,,,")?;
                        out.write_all(reason_name(&why).as_bytes())?;
                        out.write_all(b",")?;
                    }
                }
                write_degree(out, dist.inconsistency)?;
                out.write_all(b",")?;
                out.write_all(truth.unwrap_or("").as_bytes())?;
                for (_, set) in &self.queries {
                    out.write_all(b",")?;
                    write_degree(out, set.possibility(&dist.possibility))?;
                    out.write_all(b",")?;
                    write_degree(out, set.necessity(&dist.possibility))?;
                }
                if self.args.degrees {
                    for k in 0..self.places.len() {
                        out.write_all(b",")?;
                        write_degree(out, dist.possibility.get(k).copied().unwrap_or(0.0))?;
                        out.write_all(b",")?;
                        write_degree(out, dist.necessity.get(k).copied().unwrap_or(0.0))?;
                    }
                }
                out.write_all(b"\n")
            }
            Format::Table => {
                let (what, nec) = match d {
                    Decision::Place { place, necessity } => {
                        (format!("place {}", name(place)), format!("{necessity:.3}"))
                    }
                    Decision::Disoriented(why) => {
                        (format!("disoriented: {}", reason_name(&why)), "-".into())
                    }
                };
                writeln!(
                    out,
                    "{:>7} {:>9}  {:<26} {:>6} {:>6.3}  {}",
                    meta.line,
                    meta.t.map_or("-".to_string(), |t| format!("{t:.3}")),
                    what,
                    nec,
                    dist.inconsistency,
                    truth.unwrap_or("-")
                )
            }
        }
    }
}

fn run_stream(args: &EvalArgs, out: &mut impl Write) -> Result<u8, CliError> {
    let engine = load_engine(&args.model, &CompileOptions::default())?;
    let cfg = tracker_config(args)?;
    let (name, input, size): (String, Box<dyn BufRead + Send>, Option<u64>) = match &args.stream {
        None => (
            "recordings/office.jsonl (bundled)".into(),
            Box::new(OFFICE_RECORDING.as_bytes()),
            None,
        ),
        Some(p) => {
            let s = super::stream_input::open(p)?;
            (s.name, s.input, s.size)
        }
    };
    let format = match (args.input, &args.stream) {
        (Some(StreamForm::Csv), _) => StreamFormat::Csv,
        (Some(StreamForm::Jsonl), _) => StreamFormat::JsonLines,
        (None, Some(p)) => StreamFormat::from_path(p),
        (None, None) => StreamFormat::JsonLines,
    };
    let queries = resolve_queries(&engine, &args.query)?;
    let map_for_picture = args.trajectory.as_ref().map(|_| engine.map().clone());
    let run = StreamRun::new(engine, (!args.no_track).then_some(cfg));
    let places = run.places().to_vec();
    let reader = StreamReader::new(input, run.schema(), format);
    let mut plot = args
        .plot
        .as_ref()
        .map(|_| RunPlot::new(places.clone(), format!("lplace eval {name}")));
    let mut points: Option<Vec<TrajectoryPoint>> = args.trajectory.as_ref().map(|_| Vec::new());
    let mut session = Session {
        run,
        places,
        args,
        queries,
    };
    // A progress bar only for a file with a person watching stderr.
    let progress = match size {
        Some(len) if std::io::stderr().is_terminal() => {
            let bar = indicatif::ProgressBar::new(len);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{bar:40} {bytes}/{total_bytes} {bytes_per_sec} eta {eta}",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            Some(bar)
        }
        _ => None,
    };
    let mut w = std::io::BufWriter::with_capacity(1 << 16, &mut *out);
    if !args.only_summary {
        session.write_header(&mut w)?;
    }
    let show_progress = |r: &StreamReader<_>| {
        if let Some(bar) = &progress {
            if r.lines_read() % 4096 == 0 {
                bar.set_position(r.bytes_read());
            }
        }
    };
    let read_error = |source| CliError::Read {
        path: name.clone(),
        source,
    };
    read_records(
        reader,
        Threads::available(),
        show_progress,
        read_error,
        |record| {
            match record {
                Record::Rejected(e) => {
                    let msg = super::stream_input::rejection(&name, &e);
                    match &progress {
                        Some(bar) => bar.suspend(|| eprintln!("{msg}")),
                        None => eprintln!("{msg}"),
                    }
                    session.run.reject(&e.reason);
                }
                Record::Frame(frame, meta) => {
                    let d = session.run.step(frame, meta);
                    if let Some(p) = &mut plot {
                        p.push(session.dist(), d, meta.truth_place);
                    }
                    if let (Some(pts), Some(pose)) = (&mut points, meta.truth_pose) {
                        let verdict = match d.place() {
                            None => Verdict::Disoriented,
                            Some(k) if meta.truth_known && meta.truth_place == Some(k) => {
                                Verdict::Right
                            }
                            Some(_) => Verdict::Wrong,
                        };
                        pts.push(TrajectoryPoint {
                            x: pose[0],
                            y: pose[1],
                            verdict,
                        });
                    }
                    if !args.only_summary {
                        session.write_decision(&mut w, d, meta)?;
                    }
                }
            }
            Ok::<(), CliError>(())
        },
    )?;
    if let Some(bar) = &progress {
        bar.finish_and_clear();
    }
    let summary = session.run.summary();
    if args.only_summary {
        write_summary(&summary, args.summary, &mut w)?;
    }
    w.flush()?;
    drop(w);
    if !args.only_summary {
        let mut err = std::io::stderr().lock();
        write_summary(&summary, args.summary, &mut err)?;
    }
    if let (Some(path), Some(p)) = (&args.plot, &plot) {
        std::fs::write(path, p.to_svg()).map_err(|e| super::grid::output_error(path, e))?;
    }
    if let (Some(path), Some(pts), Some(map)) = (&args.trajectory, &points, &map_for_picture) {
        let title = format!("lplace eval {name}: decisions along the true trajectory");
        let picture = trajectory::svg(map, pts, 20.0, &title);
        std::fs::write(path, picture).map_err(|e| super::grid::output_error(path, e))?;
    }
    Ok(if summary.rejected > 0 {
        EXIT_REJECTED
    } else {
        EXIT_OK
    })
}

fn write_summary(
    s: &crate::report::Summary,
    how: SummaryFormat,
    out: &mut impl Write,
) -> std::io::Result<()> {
    match how {
        SummaryFormat::Text => s.write_text(out),
        SummaryFormat::Json => {
            serde_json::to_writer_pretty(&mut *out, s).map_err(std::io::Error::from)?;
            writeln!(out)
        }
        SummaryFormat::None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn u64_in_decimal() {
        for (n, want) in [
            (0u64, "0"),
            (7, "7"),
            (10, "10"),
            (1_000_001, "1000001"),
            (u64::MAX, "18446744073709551615"),
        ] {
            let mut out = Vec::new();
            write_u64(&mut out, n).expect("writes to a Vec");
            assert_eq!(out, want.as_bytes());
        }
    }
}
