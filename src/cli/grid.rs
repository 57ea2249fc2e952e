//! `lplace grid [--map MAP] STREAM --tum OUT`: runs the Fuzzy Position Grid (`localize::grid::run`) over a
//! percept stream of landmark range/bearing frames (what `lplace extract --from mrclam` writes),
//! writes the estimated trajectory in TUM format, and prints the scores against the stream's
//! truth poses: ATE without alignment, time to first fix and, with `--kidnap-at`, the recovery
//! time after an injected kidnap. `--svg DIR` draws a few grid frames (paper 000 figs. 3/5).
//!
//! Landmark positions come from the map's `landmark … id N` lines, so the stream's
//! `landmark_range(NAME)` percepts are resolved by name. With no `--map`, `--from-dir DIR` reads
//! DIR's own landmark survey, and a stream (or a directory without one) the bundled
//! `maps/mrclam.map`; the map used is named on stderr. A map that names no reading at all ends
//! with a warning and exit 3. `--truth-tum` writes the frames' truth beside the trajectory. The stream is read by the same reader as `lplace eval`'s
//! (`io::landmark_stream`): rejected records are reported on stderr as STREAM:LINE: reason and
//! skipped (exit 3 at the end). A `.csv` stream is read as CSV.
//!
//! The input half (`FrameInput`, `load_frames`), the kidnap flags, configuration reading and
//! TUM writing are shared with `lplace compare`, so both commands read and write alike.

use std::io::Write;
use std::path::Path;

use super::args::{Format, FrameInput, GridArgs, KidnapArgs};
use super::output::{self, Output};
use super::{bad, read_config, read_source, render, CliError, EXIT_OK, EXIT_REJECTED};
use crate::core::Odometry;
use crate::grid::place::map_landmarks;
use crate::grid::{GridConfig, LandmarkTable, LandmarkTruth};
use crate::io::landmark_stream;
use crate::io::mrclam_dir::{self, Dataset};
use crate::io::mrclam_stream::RecordReader;
use crate::io::stream::{StreamFormat, StreamReader};
use crate::io::tum::{write_tum, TumPose};
use crate::localize::grid::{run as run_grid, GridLocalizer};
use crate::localize::{Drive, FrameEstimate, Kidnap, MetricFrame, Recovery, RunOptions, RunReport};
use crate::map::Map;
use crate::report::grid_svg;
use crate::syntax::diagnostic::SourceFile;
use crate::syntax::parse_map;

/// The MRCLAM map, bundled: the default of `grid` and `extract --from mrclam`.
pub const MRCLAM_MAP: &str = include_str!("../../maps/mrclam.map");

/// Loads a map file, or the bundled MRCLAM map, printing its diagnostics on failure.
pub(super) fn load_map(path: Option<&Path>) -> Result<Map, CliError> {
    let src = match path {
        Some(p) => read_source(p)?,
        None => SourceFile::new("maps/mrclam.map (bundled)", MRCLAM_MAP),
    };
    let fail = |d: Vec<crate::syntax::diagnostic::Diagnostic>| {
        render::eprint(&src, &d);
        CliError::Diagnostics { count: d.len() }
    };
    let ast = parse_map(&src.text).map_err(fail)?;
    Map::from_ast(&ast).map_err(fail)
}

/// Reads a landmark stream through the one stream reader ([`landmark_stream`]); each
/// rejected record is reported on stderr as STREAM:LINE and counted.
fn read_stream(
    path: &Path,
    map: &Map,
    conv: &mut RecordReader,
    time: crate::io::stream::TimePolicy,
) -> Result<(Vec<MetricFrame>, usize), CliError> {
    let stream = super::stream_input::open(path)?;
    let reader = StreamReader::new(
        stream.input,
        landmark_stream::schema(map),
        StreamFormat::from_path(path),
    )
    .with_time_policy(time);
    let mut rejected = 0;
    let name = stream.name;
    let frames = landmark_stream::read_frames(reader, conv, |event| match event {
        landmark_stream::Event::Rejected(e) => {
            eprintln!("{}", super::stream_input::rejection(&name, &e));
            rejected += 1;
        }
        landmark_stream::Event::Restart(n) => eprintln!("{}", super::stream_input::note(&name, &n)),
    })
    .map_err(|source| CliError::Read {
        path: name.clone(),
        source,
    })?;
    Ok((frames, rejected))
}

/// Runs `grid`: scores to `out`, problems to stderr.
///
/// # Errors
/// [`CliError::Read`] when a file cannot be read, [`CliError::Diagnostics`] for a bad map,
/// configuration or flag (printed first), [`CliError::Write`] when an output fails.
pub fn run(args: &GridArgs, out: &mut impl Write) -> Result<u8, CliError> {
    let mut inputs = frame_inputs(&args.input);
    inputs.extend(args.config.as_deref().map(|p| ("--config", p)));
    let outputs: Vec<Output<'_>> = (args.tum.as_deref().map(|p| Output::file("--tum", p)))
        .into_iter()
        .chain(
            args.truth_tum
                .as_deref()
                .map(|p| Output::file("--truth-tum", p)),
        )
        .chain(args.svg.as_deref().map(|p| Output::folder("--svg", p)))
        .collect();
    output::check(&outputs, &inputs)?;
    let spinner = super::progress::spinner("grid");
    let input = load_frames(&args.input)?;
    let mut cfg = match &args.config {
        None => GridConfig::default(),
        Some(p) => read_config(p, GridConfig::from_ron)?,
    };
    if let Some(c) = args.cell {
        cfg.cell_size = c;
    }
    cfg.validate().map_err(bad)?;
    let (table, frames) = (&input.table, &input.frames);
    let report =
        run_grid(table, &cfg, frames.iter().cloned(), &RunOptions::default()).map_err(bad)?;
    let kidnapped = match kidnap(&args.kidnap, frames)? {
        None => None,
        Some((after, k)) => {
            let opts = RunOptions {
                kidnap: Some(k),
                ..RunOptions::default()
            };
            Some((
                after,
                run_grid(table, &cfg, frames.iter().cloned(), &opts).map_err(bad)?,
            ))
        }
    };
    if let Some(path) = &args.tum {
        // With a kidnap, the trajectory is the kidnapped run's: the one whose recovery is told.
        let ran = kidnapped.as_ref().map_or(&report, |k| &k.1);
        write_trajectory(path, &ran.frames)?;
    }
    if let Some(path) = &args.truth_tum {
        write_truth(path, &report.frames)?;
    }
    if let Some(dir) = &args.svg {
        write_frames(dir, table, &cfg, frames, &input_title(&args.input))?;
    }
    if let Some(s) = &spinner {
        s.finish_and_clear();
    }
    let json = args.json || matches!(args.format, Some(Format::Json | Format::Jsonl));
    print_scores(out, json, &report, kidnapped.as_ref(), &input)?;
    let unmatched = warn_if_unmatched(&input);
    Ok(if input.rejected > 0 || unmatched {
        EXIT_REJECTED
    } else {
        EXIT_OK
    })
}

/// Warns on stderr when no reading named a landmark of the map although some named subjects
/// it does not know (the map is not the stream's); true when it warned (exit 3).
pub(super) fn warn_if_unmatched(input: &LoadedFrames) -> bool {
    let matched: usize = input.frames.iter().map(|f| f.observations.len()).sum();
    let unknown = input.reader.stats.unknown;
    if matched > 0 || unknown == 0 {
        return false;
    }
    eprintln!(
        "warning: no reading names a landmark of the map ({unknown} reading(s) of unknown subjects): is it the map of these readings?"
    );
    true
}

/// Frames read and converted, ready to drive.
pub(super) struct LoadedFrames {
    /// The map's landmarks with ids.
    pub table: LandmarkTable,
    /// One frame per record.
    pub frames: Vec<MetricFrame>,
    /// The converter, with its counts of unknown, unpaired and dropped readings.
    pub reader: RecordReader,
    /// Malformed lines or rows reported and skipped.
    pub rejected: usize,
}

/// Reads `input`'s map and records (stream or MRCLAM files) and converts them to frames;
/// malformed lines are reported on stderr and counted in [`LoadedFrames::rejected`]. Which
/// landmark map is used ([`frame_map`]) is said on stderr.
pub(super) fn load_frames(input: &FrameInput) -> Result<LoadedFrames, CliError> {
    let dataset = match (&input.from_dir, &input.stream) {
        (Some(dir), _) => {
            let robot = input.robot.ok_or_else(|| bad("--from-dir needs --robot"))?;
            let dir = super::data::resolve(dir);
            Some((super::extract::load_mrclam_dir(&dir, &[robot])?, robot))
        }
        (None, Some(_)) => None,
        (None, None) => return Err(bad("no STREAM given")),
    };
    let (map, source) = frame_map(input.map.as_deref(), dataset.as_ref().map(|d| &d.0 .0))?;
    let (table, names) = map_landmarks(&map).map_err(bad)?;
    if table.landmarks().is_empty() {
        return Err(bad("the map has no landmark with an id"));
    }
    let n = table.landmarks().len();
    let plural = if n == 1 { "" } else { "s" };
    eprintln!("landmarks: {source} ({n} landmark{plural})");
    let mut reader = RecordReader::new(names);
    reader.min_degree = input.min_degree;
    let (frames, rejected) = match (dataset, &input.stream) {
        (Some(((data, malformed), robot)), _) => {
            let records = super::extract::mrclam_records(&data, robot, &map, malformed)?;
            let frames = records.iter().map(|r| reader.convert(r)).collect();
            (frames, malformed)
        }
        (None, Some(path)) => read_stream(
            &super::data::resolve(path),
            &map,
            &mut reader,
            input.time.into(),
        )?,
        (None, None) => return Err(bad("no STREAM given")),
    };
    Ok(LoadedFrames {
        table,
        frames,
        reader,
        rejected,
    })
}

/// The landmark map of a frame input, and its name for stderr: `--map`; else, with
/// `--from-dir`, the directory's own survey (`Landmark_Groundtruth.dat`), so that another
/// MRCLAM data set is read against its own landmarks; else the bundled MRCLAM map.
fn frame_map(path: Option<&Path>, data: Option<&Dataset>) -> Result<(Map, String), CliError> {
    if let Some(p) = path {
        return Ok((load_map(Some(p))?, p.display().to_string()));
    }
    match data.and_then(|d| d.landmarks.as_deref().map(|s| (d, s))) {
        Some((d, survey)) => {
            let file = d.dir.join(mrclam_dir::LANDMARKS);
            Ok((survey_map(survey, &file)?, file.display().to_string()))
        }
        None => Ok((load_map(None)?, "maps/mrclam.map (bundled)".to_string())),
    }
}

/// A landmark survey as a map of landmarks `L<subject>` with id `<subject>`, the names and ids
/// of the bundled MRCLAM map. Built as map text and parsed, so that it is the map every
/// command reads; `{}` prints the shortest decimal that parses back to the same number, so the
/// positions are the survey's to the last bit.
fn survey_map(survey: &[LandmarkTruth], file: &Path) -> Result<Map, CliError> {
    let mut text = String::from("map survey;\n");
    for l in survey {
        if !(l.x.is_finite() && l.y.is_finite()) {
            return Err(bad(format!(
                "{}: landmark {} has no finite position",
                file.display(),
                l.subject
            )));
        }
        text.push_str(&format!(
            "landmark L{0} at ({1}, {2}) id {0};\n",
            l.subject, l.x, l.y
        ));
    }
    let fail = |_| bad(format!("{}: the survey is not a map", file.display()));
    let ast = parse_map(&text).map_err(fail)?;
    Map::from_ast(&ast).map_err(fail)
}

/// The kidnap asked for by `--kidnap-at`/`--kidnap-by`, with its time after the first frame (s);
/// `None` without `--kidnap-at`.
pub(super) fn kidnap(
    args: &KidnapArgs,
    frames: &[MetricFrame],
) -> Result<Option<(f64, Kidnap)>, CliError> {
    let Some(spec) = &args.kidnap_at else {
        return Ok(None);
    };
    let Some(first) = frames.first() else {
        return Err(bad("--kidnap-at: the stream has no frames"));
    };
    let time = if spec == "mid" {
        frames[frames.len() / 2].t
    } else {
        match spec.parse::<f64>() {
            Ok(s) if s.is_finite() && s >= 0.0 => first.t + s,
            _ => {
                return Err(bad(format!(
                    "--kidnap-at: `{spec}` is not seconds or `mid`"
                )))
            }
        }
    };
    if args.kidnap_by.len() != 3 {
        return Err(bad(format!(
            "--kidnap-by needs three numbers DX,DY,DTHETA; got {}",
            args.kidnap_by.len()
        )));
    }
    let by = |k: usize| args.kidnap_by.get(k).copied().unwrap_or(0.0);
    Ok(Some((
        time - first.t,
        Kidnap {
            time,
            by: Odometry {
                forward: by(0),
                left: by(1),
                turn: by(2).to_radians(),
            },
        },
    )))
}

/// Writes a run's estimates as a TUM trajectory (`t x y z qx qy qz qw`).
pub(super) fn write_trajectory(path: &Path, frames: &[FrameEstimate]) -> Result<(), CliError> {
    let poses: Vec<TumPose> = frames
        .iter()
        .map(|f| TumPose {
            t: f.t,
            x: f.pose.x,
            y: f.pose.y,
            yaw: f.pose.theta,
        })
        .collect();
    output::write_atomic(path, |w| write_tum(w, &poses))
}

/// Writes the frames' truth poses as a TUM trajectory, in [`write_trajectory`]'s format;
/// frames without truth are left out.
fn write_truth(path: &Path, frames: &[FrameEstimate]) -> Result<(), CliError> {
    let poses: Vec<TumPose> = frames
        .iter()
        .filter_map(|f| {
            f.truth.map(|p| TumPose {
                t: f.t,
                x: p.x,
                y: p.y,
                yaw: p.theta,
            })
        })
        .collect();
    output::write_atomic(path, |w| write_tum(w, &poses))
}

/// The files a [`FrameInput`] reads, as inputs no output may overwrite.
pub(super) fn frame_inputs(input: &FrameInput) -> Vec<(&'static str, &Path)> {
    let map = input.map.as_deref().map(|p| ("--map", p));
    let stream = input.stream.as_deref().map(|p| ("STREAM", p));
    map.into_iter().chain(stream).collect()
}

/// What a picture shows, for its title: the data set's folder and the robot (`--from-dir`), or
/// the stream's folder and file (which names the robot it was extracted for); never a whole
/// path.
pub(super) fn input_title(input: &FrameInput) -> String {
    let full = |p: &Path| {
        let p = super::data::resolve(p);
        std::fs::canonicalize(&p).unwrap_or(p)
    };
    let name = |p: &Path| p.file_name().map(|n| n.to_string_lossy().into_owned());
    match (&input.from_dir, input.robot, &input.stream) {
        (Some(dir), Some(r), _) => {
            let set = name(&full(dir)).unwrap_or_else(|| dir.display().to_string());
            format!("data set {set}, robot {r}")
        }
        (_, _, Some(s)) if s.as_os_str() == "-" => "stream on standard input".to_string(),
        (_, _, Some(s)) => {
            let s = full(s);
            let file = name(&s).unwrap_or_default();
            match s.parent().and_then(name) {
                Some(set) => format!("data set {set}, stream {file}"),
                None => format!("stream {file}"),
            }
        }
        _ => "no input".to_string(),
    }
}

/// An output file's I/O error with the file named in the message (exit 1).
pub(super) fn output_error(path: &Path, source: std::io::Error) -> CliError {
    CliError::WriteFile {
        path: path.display().to_string(),
        source,
    }
}

/// The scores, as text or as one JSON object.
fn print_scores(
    out: &mut impl Write,
    json: bool,
    r: &RunReport,
    kidnapped: Option<&(f64, RunReport)>,
    input: &LoadedFrames,
) -> Result<(), CliError> {
    let recovery = kidnapped.map(|(at, k)| match k.recovery {
        Some(Recovery::Recovered { after }) => (*at, Some(after)),
        _ => (*at, None),
    });
    let stats = &input.reader.stats;
    if json {
        let v = serde_json::json!({
            "frames": r.frames.len(),
            "ate": r.ate,
            "ate_all": r.ate_all,
            "heading_rmse": r.heading_rmse,
            "first_fix": r.first_fix.map(|f| f.after),
            "first_fix_t": r.first_fix_time(),
            "kidnap_at": recovery.map(|x| x.0),
            "recovery": recovery.and_then(|x| x.1),
            "used": r.used,
            "unknown": r.unknown + stats.unknown + stats.robots,
            "other_robots": stats.robots,
            "unpaired": stats.unpaired,
            "dropped": stats.dropped,
            "rejected_lines": input.rejected,
        });
        writeln!(out, "{v}")?;
        return Ok(());
    }
    let f = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{v:.3}"));
    writeln!(out, "frames: {}", r.frames.len())?;
    match r.ate {
        Some(a) => writeln!(
            out,
            "ATE (from first fix, no alignment): RMSE {:.3} m, median {:.3} m, max {:.3} m over {} frames",
            a.rmse, a.median, a.max, a.count
        )?,
        None => writeln!(out, "ATE: – (no fix, or no truth in the stream)")?,
    }
    writeln!(
        out,
        "ATE over all frames: RMSE {} m",
        f(r.ate_all.map(|a| a.rmse))
    )?;
    writeln!(out, "heading RMSE: {} rad", f(r.heading_rmse))?;
    match r.first_fix_time() {
        Some(t) => writeln!(
            out,
            "first fix: {} s (t = {t:.3})",
            f(r.first_fix.map(|x| x.after))
        )?,
        None => writeln!(out, "first fix: – s")?,
    }
    if let Some((at, rec)) = recovery {
        match rec {
            Some(s) => writeln!(out, "kidnap at {at:.1} s: recovered after {s:.1} s")?,
            None => writeln!(out, "kidnap at {at:.1} s: not recovered")?,
        }
    }
    writeln!(
        out,
        "readings: {} used, {} thinned, {} of other robots, {} of unknown subjects, {} unpaired, {} below --min-degree",
        r.used,
        r.thinned,
        stats.robots,
        r.unknown + stats.unknown,
        stats.unpaired,
        stats.dropped
    )?;
    Ok(())
}

/// Times after the first frame (s) at which `--svg` draws the grid: doubling, so that the
/// pictures show the belief shrinking from total ignorance.
const SVG_TIMES: [f64; 6] = [0.5, 1.0, 2.0, 4.0, 8.0, 16.0];

/// Replays the grid's run (the same [`Drive`] as `localize::grid::run`) and writes the plane at
/// [`SVG_TIMES`], drawn by [`grid_svg::svg`] with `what` was run in the title.
fn write_frames(
    dir: &Path,
    table: &LandmarkTable,
    cfg: &GridConfig,
    frames: &[MetricFrame],
    what: &str,
) -> Result<(), CliError> {
    output::create_folder(dir)?;
    let mut loc = GridLocalizer::new(table, cfg).map_err(bad)?;
    let mut drive = Drive::new(table, RunOptions::default());
    let Some(t0) = frames.first().map(|f| f.t) else {
        return Ok(());
    };
    let mut next = 0;
    for f in frames {
        if next >= SVG_TIMES.len() {
            break;
        }
        drive.step(&mut loc, f);
        if f.t - t0 >= SVG_TIMES[next] {
            let path = dir.join(format!("grid-{:03}.svg", next));
            let picture = grid_svg::svg(loc.grid(), table, f.truth, f.t - t0, what);
            output::write_atomic(&path, |w| w.write_all(picture.as_bytes()))?;
            next += 1;
        }
    }
    Ok(())
}
