//! `lplace eval`: evaluate a percept stream (or one `--frame`) and print one decision per frame,
//! then a summary.
//!
//! The stream is read line by line ([`crate::io::stream`]) — on a second thread, a few batches
//! ahead, when the machine has a second core ([`Threads::available`]) — and each frame stepped
//! by a [`StreamRun`] (the engine and, unless `--no-track`, the tracker); decisions are written as they
//! come, so memory stays flat on any length. Rejected records are reported on stderr as `STREAM:LINE: reason`, counted,
//! and make the exit code 3.

use super::args::{ArgError, EvalArgs, Format, StreamForm, SummaryFormat};
use super::output::{self, Output};
use super::{load_engine, CliError, EXIT_OK, EXIT_REJECTED};
use crate::engine::outcome::QueryOutcome;
use crate::engine::tracker::TrackerConfig;
use crate::engine::{CompileOptions, Engine};
use crate::io::stream::{
    read_records, FrameMeta, ReadOutcome, Record, Rejection, Schema, StreamFormat, StreamReader,
    Threads,
};
use crate::logic::{Decision, PlaceDistribution, PlaceSet};
use crate::report::summary::reason_name;
use crate::report::trajectory::{self, TrajectoryPoint, Verdict};
use crate::report::{RunPlot, StreamRun};
use crate::survey::{nearest_label, LabelRow};
use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};

/// The bundled office recording (made by `lplace simulate`, see docs/streams.md).
pub const OFFICE_RECORDING: &str = include_str!("../../recordings/office.jsonl");

/// Runs `eval`.
pub fn run(args: &EvalArgs, out: &mut impl Write) -> Result<u8, CliError> {
    match &args.frame {
        Some(json) => run_frame(args, json, out),
        None => run_stream(args, out),
    }
}

/// Evaluates one frame. It is read by the stream reader every other command uses (the same
/// validation and the same messages); a frame it would reject is an argument error (exit 2): on
/// the command line, a typo should not quietly change the answer.
fn run_frame(args: &EvalArgs, json: &str, out: &mut impl Write) -> Result<u8, CliError> {
    let opts = CompileOptions {
        trace: args.trace,
        ..CompileOptions::default()
    };
    let mut engine = load_engine(&args.model, &opts)?;
    let (frame, region) = read_one_frame(&engine, json)?;
    let queries = resolve_queries(&engine, &args.query)?;
    let known = match &region {
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
    match args.format.unwrap_or(Format::Json) {
        Format::Json | Format::Jsonl => {
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

/// The `--frame` record as the engine's frame, and the name of its known region if it gives one.
/// JSON allows a line break wherever it allows a space outside a string (and none inside one), so
/// a frame written over several lines in a shell reads as the same one-line record.
fn read_one_frame(
    engine: &Engine,
    json: &str,
) -> Result<(crate::engine::Frame, Option<String>), ArgError> {
    let line = json.replace(['\n', '\r'], " ");
    let regions = crate::engine::query::set_names(engine.map(), engine.rules());
    let schema = Schema::new(engine.percepts(), engine.map()).with_regions(regions.clone());
    let mut reader = StreamReader::new(line.as_bytes(), schema, StreamFormat::JsonLines);
    let mut frame = engine.new_frame();
    let mut meta = FrameMeta::default();
    match reader.next_frame(&mut frame, &mut meta) {
        Ok(ReadOutcome::Frame) => {
            let region = meta.region.and_then(|r| regions.get(r as usize).cloned());
            Ok((frame, region))
        }
        Ok(ReadOutcome::Rejected(e)) => Err(ArgError::Frame(e.reason)),
        Ok(ReadOutcome::End) => Err(ArgError::EmptyFrame),
        // Reading from memory cannot fail.
        Err(e) => Err(ArgError::Frame(Rejection::Malformed {
            column: 1,
            message: e.to_string(),
        })),
    }
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
    // Rooms are short names padded to a column; regions are written as named.
    for (label, width, sets) in [("room", 3, &outcome.rooms), ("region", 0, &outcome.regions)] {
        for r in sets {
            writeln!(
                out,
                "{label} {:<width$} support {:.3}  Π {:.3}  N {:.3}",
                r.room, r.support, r.possibility, r.necessity
            )?;
        }
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

/// Reads the tracker configuration named by `--tracker`; without it, the rule file's
/// `tracker { … }` block or the defaults ([`Engine::tracker_config`]).
fn tracker_config(args: &EvalArgs, engine: &Engine) -> Result<TrackerConfig, CliError> {
    let Some(path) = &args.tracker else {
        return Ok(engine.tracker_config());
    };
    super::read_config(path, TrackerConfig::from_ron)
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
    places: Vec<String>,
    args: &'a EvalArgs,
    format: Format,
    /// `--query` sets, resolved once.
    queries: Vec<(String, PlaceSet)>,
    /// Width of the table's decision column (see [`decision_width`]).
    decision_width: usize,
    /// Width of the table's truth column: the longest place name (padded only with `--degrees`,
    /// whose columns follow it).
    truth_width: usize,
}

impl Session<'_> {
    fn write_header(&self, out: &mut impl Write) -> std::io::Result<()> {
        match self.format {
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
            Format::Table => {
                write!(
                    out,
                    "{:>7} {:>9}  {:<dw$} {:>6} {:>6}  ",
                    "line",
                    "t",
                    "decision",
                    "N",
                    "Inc",
                    dw = self.decision_width
                )?;
                if self.args.degrees {
                    write!(out, "{:<tw$}", "truth", tw = self.truth_width)?;
                    for p in &self.places {
                        write!(out, "  {:>w$}", format!("π/N:{p}"), w = DEGREE_CELL)?;
                    }
                    writeln!(out)
                } else {
                    writeln!(out, "truth")
                }
            }
            Format::Json | Format::Jsonl => Ok(()),
        }
    }

    fn name(&self, k: usize) -> &str {
        self.places.get(k).map_or("?", String::as_str)
    }

    /// The truth column: `None` without truth, `Some("none")` between places.
    fn truth(&self, meta: &FrameMeta) -> Option<&str> {
        meta.truth_known
            .then(|| meta.truth_place.map_or("none", |k| self.name(k)))
    }

    fn write_decision(
        &self,
        out: &mut impl Write,
        dist: &PlaceDistribution,
        d: Decision,
        meta: &FrameMeta,
    ) -> std::io::Result<()> {
        match self.format {
            Format::Json | Format::Jsonl => self.write_json(out, dist, d, meta),
            Format::Csv => self.write_csv(out, dist, d, meta),
            Format::Table => self.write_table_row(out, dist, d, meta),
        }
    }

    /// One decision as a JSON line; `--degrees` adds `possibility`/`necessities` objects keyed
    /// by place name, in the map's place order.
    fn write_json(
        &self,
        out: &mut impl Write,
        dist: &PlaceDistribution,
        d: Decision,
        meta: &FrameMeta,
    ) -> std::io::Result<()> {
        out.write_all(b"{\"line\":")?;
        write_u64(out, meta.line)?;
        if let Some(t) = meta.t {
            write!(out, ",\"t\":{t}")?;
        }
        match d {
            Decision::Place { place, necessity } => {
                out.write_all(b",\"place\":\"")?;
                out.write_all(self.name(place).as_bytes())?;
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
        match self.truth(meta) {
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
                (&b",\"possibility\":{"[..], &dist.possibility),
                (&b",\"necessities\":{"[..], &dist.necessity),
            ] {
                out.write_all(key)?;
                for (k, place) in self.places.iter().enumerate() {
                    out.write_all(if k == 0 { b"\"" } else { b",\"" })?;
                    // Place names are identifiers of the map language: nothing to escape.
                    out.write_all(place.as_bytes())?;
                    out.write_all(b"\":")?;
                    write_degree(out, v.get(k).copied().unwrap_or(0.0))?;
                }
                out.write_all(b"}")?;
            }
        }
        out.write_all(b"}\n")
    }

    fn write_csv(
        &self,
        out: &mut impl Write,
        dist: &PlaceDistribution,
        d: Decision,
        meta: &FrameMeta,
    ) -> std::io::Result<()> {
        write_u64(out, meta.line)?;
        out.write_all(b",")?;
        if let Some(t) = meta.t {
            write!(out, "{t}")?;
        }
        match d {
            Decision::Place { place, necessity } => {
                out.write_all(b",place,")?;
                out.write_all(self.name(place).as_bytes())?;
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
        out.write_all(self.truth(meta).unwrap_or("").as_bytes())?;
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

    fn write_table_row(
        &self,
        out: &mut impl Write,
        dist: &PlaceDistribution,
        d: Decision,
        meta: &FrameMeta,
    ) -> std::io::Result<()> {
        let (what, nec) = match d {
            Decision::Place { place, necessity } => (
                format!("place {}", self.name(place)),
                format!("{necessity:.3}"),
            ),
            Decision::Disoriented(why) => {
                (format!("disoriented: {}", reason_name(&why)), "-".into())
            }
        };
        let truth = self.truth(meta).unwrap_or("-");
        write!(
            out,
            "{:>7} {:>9}  {:<dw$} {:>6} {:>6.3}  ",
            meta.line,
            meta.t.map_or("-".to_string(), |t| format!("{t:.3}")),
            clip(&what, self.decision_width),
            nec,
            dist.inconsistency,
            dw = self.decision_width
        )?;
        if !self.args.degrees {
            return writeln!(out, "{truth}");
        }
        write!(out, "{truth:<tw$}", tw = self.truth_width)?;
        for k in 0..self.places.len() {
            let pi = dist.possibility.get(k).copied().unwrap_or(0.0);
            let n = dist.necessity.get(k).copied().unwrap_or(0.0);
            write!(out, "  {:>w$}", format!("{pi:.2}/{n:.2}"), w = DEGREE_CELL)?;
        }
        writeln!(out)
    }
}

/// The longest reason, `disoriented: nothing_above_threshold`: every row fits it.
const REASON_CHARS: usize = 36;

/// The widest the table's decision column grows for long place names; longer ones are clipped
/// with `…` so that the columns after it stay aligned.
const MAX_DECISION: usize = 48;

/// Width of a `--degrees` cell in the table (`0.80/0.10`).
const DEGREE_CELL: usize = 9;

/// Width of the table's decision column: the longest reason or `place NAME` for the longest
/// place name, whichever is wider, but at most [`MAX_DECISION`].
fn decision_width(places: &[String]) -> usize {
    let longest = places.iter().map(|p| p.chars().count()).max().unwrap_or(0);
    (longest + "place ".len()).clamp(REASON_CHARS, MAX_DECISION)
}

/// `text` cut to `width` characters, the last one replaced by `…` when it was cut.
fn clip(text: &str, width: usize) -> std::borrow::Cow<'_, str> {
    if text.chars().count() <= width {
        return text.into();
    }
    let kept: String = text.chars().take(width.saturating_sub(1)).collect();
    format!("{kept}…").into()
}

/// An opened percept stream with its name and form.
pub(super) struct Source {
    /// How reports name the stream.
    pub(super) name: String,
    input: Box<dyn BufRead + Send>,
    size: Option<u64>,
    format: StreamFormat,
    /// How its times are read (`--time`).
    pub(super) time: crate::io::stream::TimePolicy,
    /// Ground truth replacing the records' own (`--labels`).
    pub(super) labels: Option<Labels>,
}

/// Ground truth from `--labels`: each frame's true place is the label nearest its time within
/// 0.5 s ([`nearest_label`], as `survey --labels` reads them), none when there is no such
/// label; the record's own truth place is not read. The pose, if any, is kept.
pub(super) struct Labels {
    rows: Vec<LabelRow>,
    /// Each row's place as an index into the run's places.
    places: Vec<Option<usize>>,
}

impl Labels {
    /// Reads the CSV at `path`; every place it names must be one of `places`.
    pub(super) fn load(path: &Path, places: &[String]) -> Result<Labels, CliError> {
        let rows = super::survey::read_labels(path)?;
        let mut index = Vec::with_capacity(rows.len());
        for row in &rows {
            index.push(match &row.place {
                None => None,
                Some(name) => match places.iter().position(|p| p == name) {
                    Some(k) => Some(k),
                    None => {
                        eprintln!(
                            "{}: no place `{name}` in the map (places: {})",
                            path.display(),
                            places.join(", ")
                        );
                        return Err(CliError::Diagnostics { count: 1 });
                    }
                },
            });
        }
        Ok(Labels {
            rows,
            places: index,
        })
    }

    /// `meta` with its truth place taken from the labels.
    fn apply(&self, meta: &FrameMeta) -> FrameMeta {
        let k = meta.t.and_then(|t| nearest_label(&self.rows, t));
        FrameMeta {
            truth_known: k.is_some(),
            truth_place: k.and_then(|k| self.places[k]),
            ..*meta
        }
    }
}

/// Opens `path` (the bundled office recording for `None`); `--input` overrides the form the
/// extension implies.
pub(super) fn open_source(
    path: Option<&Path>,
    input: Option<StreamForm>,
) -> Result<Source, CliError> {
    let (name, bytes, size): (String, Box<dyn BufRead + Send>, Option<u64>) = match path {
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
    let format = match (input, path) {
        (Some(StreamForm::Csv), _) => StreamFormat::Csv,
        (Some(StreamForm::Jsonl), _) => StreamFormat::JsonLines,
        (None, Some(p)) => StreamFormat::from_path(p),
        (None, None) => StreamFormat::JsonLines,
    };
    Ok(Source {
        name,
        input: bytes,
        size,
        format,
        time: Default::default(),
        labels: None,
    })
}

/// Steps every record of `source` through `run`: rejected records are reported on stderr and
/// counted, each decision handed to `on_frame`. Shows a progress bar on a terminal.
pub(super) fn evaluate(
    run: &mut StreamRun,
    source: Source,
    mut on_frame: impl FnMut(&StreamRun, Decision, &FrameMeta) -> Result<(), CliError>,
) -> Result<(), CliError> {
    let progress = super::progress::bytes(source.size, &source.name);
    let reader =
        StreamReader::new(source.input, run.schema(), source.format).with_time_policy(source.time);
    let name = source.name;
    let labels = source.labels;
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
                    super::progress::eprint(progress.as_ref(), &msg);
                    run.reject(&e.reason);
                }
                Record::Frame(frame, meta) => {
                    let relabelled;
                    let meta = match &labels {
                        Some(l) => {
                            relabelled = l.apply(meta);
                            &relabelled
                        }
                        None => meta,
                    };
                    if let Some(note) = meta.restart_note() {
                        let msg = super::stream_input::note(&name, &note);
                        super::progress::eprint(progress.as_ref(), &msg);
                    }
                    let d = run.step(frame, meta);
                    on_frame(run, d, meta)?;
                }
            }
            Ok::<(), CliError>(())
        },
    )?;
    if let Some(bar) = &progress {
        bar.finish_and_clear();
    }
    Ok(())
}

/// The pictures `--svg`/`--trajectory-svg` ask for, filled frame by frame.
struct Pictures {
    plot: Option<RunPlot>,
    points: Option<Vec<TrajectoryPoint>>,
    map: Option<crate::map::Map>,
}

impl Pictures {
    fn new(args: &EvalArgs, engine: &Engine, places: &[String], name: &str) -> Pictures {
        let title = format!("lplace eval {}", file_name(name));
        Pictures {
            plot: args.svg().map(|_| RunPlot::new(places.to_vec(), title)),
            points: args.trajectory_svg().map(|_| Vec::new()),
            map: args.trajectory_svg().map(|_| engine.map().clone()),
        }
    }

    fn push(&mut self, dist: &PlaceDistribution, d: Decision, meta: &FrameMeta) {
        if let Some(p) = &mut self.plot {
            p.push(dist, d, meta.truth_place);
        }
        if let (Some(pts), Some(pose)) = (&mut self.points, meta.truth_pose) {
            let verdict = match d.place() {
                None => Verdict::Disoriented,
                Some(k) if meta.truth_known && meta.truth_place == Some(k) => Verdict::Right,
                Some(_) => Verdict::Wrong,
            };
            pts.push(TrajectoryPoint {
                x: pose[0],
                y: pose[1],
                verdict,
            });
        }
    }

    /// Writes the pictures (atomically; their paths were checked before the run).
    fn write(&self, args: &EvalArgs, name: &str) -> Result<(), CliError> {
        if let (Some(path), Some(p)) = (args.svg(), &self.plot) {
            output::write_atomic(path, |w| w.write_all(p.to_svg().as_bytes()))?;
        }
        if let (Some(path), Some(pts), Some(map)) = (args.trajectory_svg(), &self.points, &self.map)
        {
            let title = format!("{}: decisions along the true trajectory", file_name(name));
            let picture = trajectory::svg(map, pts, 20.0, &title);
            output::write_atomic(path, |w| w.write_all(picture.as_bytes()))?;
        }
        Ok(())
    }
}

/// The last component of a stream's name, for picture titles: where the stream was stored (often
/// a scratch folder) says nothing about the run.
fn file_name(name: &str) -> &str {
    name.rsplit(['/', '\\']).next().unwrap_or(name)
}

/// Every file `eval` reads, as inputs no output may overwrite.
fn inputs(args: &EvalArgs) -> Vec<(&'static str, &Path)> {
    let mut v = super::simulate::model_inputs(&args.model);
    v.extend(args.stream.iter().map(|p| ("STREAM", p.as_path())));
    v.extend(args.tracker.as_deref().map(|p| ("--tracker", p)));
    v.extend(args.labels.as_deref().map(|p| ("--labels", p)));
    v
}

/// Every file `eval` writes.
fn outputs(args: &EvalArgs) -> Vec<Output<'_>> {
    let mut v = Vec::new();
    v.extend(args.output.as_deref().map(|p| Output::file("--output", p)));
    v.extend(args.svg().map(|p| Output::file("--svg", p)));
    v.extend(
        args.trajectory_svg()
            .map(|p| Output::file("--trajectory-svg", p)),
    );
    v
}

/// Evaluates the stream(s): one stream prints its decisions and summary; several (or a
/// folder) print one summary row per stream and a total.
fn run_stream(args: &EvalArgs, out: &mut impl Write) -> Result<u8, CliError> {
    output::check(&outputs(args), &inputs(args))?;
    let streams = super::batch::expand(&args.stream)?;
    if streams.len() > 1 || args.stream.iter().any(|p| super::batch::is_folder(p)) {
        return super::batch::run(args, &streams, out);
    }
    match &args.output {
        Some(path) => {
            let mut code = EXIT_OK;
            output::write_atomic(path, |w| {
                code = run_one(args, streams.first().map(PathBuf::as_path), w)
                    .map_err(std::io::Error::other)?;
                Ok(())
            })?;
            Ok(code)
        }
        None => run_one(args, streams.first().map(PathBuf::as_path), out),
    }
}

/// Loads the engine and, unless `--no-track`, the tracker for a stream run.
pub(super) fn new_run(args: &EvalArgs) -> Result<StreamRun, CliError> {
    let engine = load_engine(&args.model, &CompileOptions::default())?;
    let cfg = tracker_config(args, &engine)?;
    Ok(StreamRun::new(engine, (!args.no_track).then_some(cfg)))
}

/// Evaluates one stream, printing its decisions (unless `--only-summary`) and its summary.
fn run_one(args: &EvalArgs, path: Option<&Path>, out: &mut dyn Write) -> Result<u8, CliError> {
    let run = new_run(args)?;
    let mut source = open_source(path, args.input)?;
    source.time = args.time.into();
    source.labels = match &args.labels {
        Some(p) => Some(Labels::load(p, run.places())?),
        None => None,
    };
    let queries = resolve_queries(run.engine(), &args.query)?;
    let places = run.places().to_vec();
    let mut pictures = Pictures::new(args, run.engine(), &places, &source.name);
    let name = source.name.clone();
    let decision_width = decision_width(&places);
    let truth_width = places
        .iter()
        .map(|p| p.chars().count())
        .max()
        .unwrap_or(0)
        .max("truth".len());
    let session = Session {
        places,
        args,
        format: args.format.unwrap_or(Format::Jsonl),
        queries,
        decision_width,
        truth_width,
    };
    let mut run = run;
    let mut w = std::io::BufWriter::with_capacity(1 << 16, out);
    if !args.only_summary {
        session.write_header(&mut w)?;
    }
    evaluate(&mut run, source, |run, d, meta| {
        pictures.push(run.distribution(), d, meta);
        if !args.only_summary {
            session.write_decision(&mut w, run.distribution(), d, meta)?;
        }
        Ok(())
    })?;
    let summary = run.summary();
    if args.only_summary {
        write_summary(&summary, args.summary, &mut w)?;
    }
    w.flush()?;
    drop(w);
    if !args.only_summary {
        write_summary(&summary, args.summary, &mut std::io::stderr().lock())?;
    }
    pictures.write(args, &name)?;
    Ok(if summary.rejected > 0 {
        EXIT_REJECTED
    } else {
        EXIT_OK
    })
}

fn write_summary(
    s: &crate::report::Summary,
    how: SummaryFormat,
    out: &mut dyn Write,
) -> std::io::Result<()> {
    match how {
        SummaryFormat::Text => {
            let mut out = out;
            s.write_text(&mut out)
        }
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
