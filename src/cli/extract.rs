//! `lplace extract --from carmen LOG [--map MAP] [--config CONFIG]`: turn a raw sensor log into
//! the percept stream (JSON lines of [`crate::io::record::FrameRecord`]) on stdout, one frame
//! per laser scan. The conversion itself is library code (`io::carmen_stream`); this module
//! reads the files, reports malformed log lines on stderr with their line numbers and picks the
//! exit code (3 when any line was rejected, after converting all the others).

use std::io::{BufRead, BufReader, Write};

use super::args::{ExtractArgs, LogFormat};
use super::{read_source, render, CliError, EXIT_OK, EXIT_REJECTED};
use crate::io::carmen_stream::{convert, CarmenFramer};
use crate::io::mrclam_dir;
use crate::map::Map;
use crate::percept::ExtractConfig;
use crate::syntax::parse_map;

/// Runs `extract`: frames to `out`, malformed lines and a summary to stderr.
///
/// # Errors
/// [`CliError::Read`] when a file cannot be read, [`CliError::Diagnostics`] when the map or the
/// config has errors (printed first), [`CliError::Write`] when `out` fails.
pub fn run(args: &ExtractArgs, out: &mut impl Write) -> Result<u8, CliError> {
    if args.from == LogFormat::Mrclam {
        return run_mrclam(args, out);
    }
    let mut cfg = load_config(args)?;
    let map = load_truth_map(args)?;
    // The building's axis is a statement of its map (`axis D;`): with it, the map and the log
    // are a building's only inputs.
    if let Some(axis) = map.as_ref().and_then(Map::axis_deg) {
        cfg.compass.axis_deg = axis;
    }
    if args.from == LogFormat::Rosbag2 {
        return super::extract_rosbag2::run(args, cfg, map.as_ref(), out);
    }
    let log = open_log(&args.log)?;
    let mut framer = CarmenFramer::new(cfg, map.as_ref().map(Map::places)).map_err(|e| {
        eprintln!("{e}");
        CliError::Diagnostics { count: 1 }
    })?;
    let log_name = args.log.display().to_string();
    let summary = convert(
        log,
        &mut framer,
        |frame| -> Result<(), CliError> {
            serde_json::to_writer(&mut *out, &frame).map_err(std::io::Error::from)?;
            out.write_all(b"\n")?;
            Ok(())
        },
        |e| eprintln!("{log_name}: {e}"),
    )?;
    let st = &summary.stats;
    eprintln!(
        "extract: {} frame(s) from {} line(s) ({} FLASER, {} ODOM); {} malformed line(s) skipped",
        summary.frames, st.lines, st.lasers, st.odoms, st.errors
    );
    // Figures a user can check without ground truth: a log much denser than ~2 frames per
    // metre, many capped ranges or an unsteady heading lock show here, not only against truth.
    eprintln!("extract: quality: {}", framer.quality());
    Ok(if st.errors > 0 {
        EXIT_REJECTED
    } else {
        EXIT_OK
    })
}

/// Opens the log; a gzipped one (told by its first two bytes, not its name) is read through
/// the decoder, so that `run.log.gz` needs no unpacking. A corrupt stream ends the log with a
/// line-numbered read error, as any read error does.
pub(super) fn open_log(path: &std::path::Path) -> Result<Box<dyn BufRead>, CliError> {
    let read_err = |source| CliError::Read {
        path: path.display().to_string(),
        source,
    };
    let mut file = BufReader::new(std::fs::File::open(path).map_err(read_err)?);
    let gzipped = file
        .fill_buf()
        .map_err(read_err)?
        .starts_with(&[0x1f, 0x8b]);
    Ok(if gzipped {
        Box::new(BufReader::new(flate2::bufread::MultiGzDecoder::new(file)))
    } else {
        Box::new(file)
    })
}

/// The extractor parameters of `--config`, or the travelling ones
/// ([`ExtractConfig::travelling`]: no building's own settings, the map gives the axis).
pub(super) fn load_config(args: &ExtractArgs) -> Result<ExtractConfig, CliError> {
    match &args.config {
        None => Ok(ExtractConfig::travelling()),
        Some(path) => super::read_config(path, ExtractConfig::from_ron),
    }
}

/// The `--map` whose place extents give the truth places, if given.
pub(super) fn load_truth_map(args: &ExtractArgs) -> Result<Option<Map>, CliError> {
    args.map.as_deref().map(read_map).transpose()
}

/// The map at `path`, its problems printed (as `check` prints them) when it has any.
pub(super) fn read_map(path: &std::path::Path) -> Result<Map, CliError> {
    let src = read_source(path)?;
    let fail = |d: Vec<crate::syntax::diagnostic::Diagnostic>| {
        render::eprint(&src, &d);
        CliError::Diagnostics { count: d.len() }
    };
    let ast = parse_map(&src.text).map_err(fail)?;
    Map::from_ast(&ast).map_err(fail)
}

/// `extract --from mrclam DIR --robot N [--map MAP]`: one robot's files as a percept stream
/// (`io::mrclam_stream`). Landmark names and truth places come from the map (default: the
/// bundled `maps/mrclam.map`). Misread barcodes are dropped and counted; malformed lines are
/// reported as FILE:LINE and skipped (exit 3).
fn run_mrclam(args: &ExtractArgs, out: &mut impl Write) -> Result<u8, CliError> {
    let Some(robot) = args.robot else {
        eprintln!("error: --from mrclam needs --robot N");
        return Err(CliError::Diagnostics { count: 1 });
    };
    let map = super::grid::load_map(args.map.as_deref())?;
    let (records, malformed) = load_mrclam(&args.log, robot, &map)?;
    for r in &records {
        serde_json::to_writer(&mut *out, r).map_err(std::io::Error::from)?;
        out.write_all(b"\n")?;
    }
    Ok(if malformed > 0 {
        EXIT_REJECTED
    } else {
        EXIT_OK
    })
}

/// Reads MRCLAM robots from `dir` ([`mrclam_dir::load`]), reporting every malformed line as
/// FILE:LINE on stderr. Returns the dataset and the number of malformed lines skipped. Shared by
/// the commands that read MRCLAM directories (`extract`, `grid`, `compare`, `fuse`).
pub(super) fn load_mrclam_dir(
    dir: &std::path::Path,
    robots: &[u32],
) -> Result<(mrclam_dir::Dataset, usize), CliError> {
    let data = mrclam_dir::load(dir, robots).map_err(|e| match e {
        mrclam_dir::DatasetError::Open { path, source } => CliError::Read {
            path: path.display().to_string(),
            source,
        },
        other => {
            eprintln!("error: {other}");
            CliError::Diagnostics { count: 1 }
        }
    })?;
    for s in &data.skipped {
        eprintln!("{}:{}", s.path.display(), line_problem(&s.error));
    }
    let skipped = data.skipped.len();
    Ok((data, skipped))
}

/// `LINE: problem` of a reader error (the path is the caller's).
fn line_problem(e: &crate::io::mrclam::MrclamError) -> String {
    use crate::io::mrclam::MrclamError;
    match e {
        MrclamError::Malformed { line, problem, .. } => format!("{line}: {problem}"),
        MrclamError::Read { line, source, .. } => format!("{line}: read error: {source}"),
    }
}

/// Reads MRCLAM robot `robot` from `dir` into records, reporting malformed lines (FILE:LINE) and
/// a summary on stderr. Returns the records and the number of malformed lines skipped.
pub(super) fn load_mrclam(
    dir: &std::path::Path,
    robot: u32,
    map: &Map,
) -> Result<(Vec<crate::io::record::FrameRecord>, usize), CliError> {
    let (data, malformed) = load_mrclam_dir(dir, &[robot])?;
    let records = mrclam_records(&data, robot, map, malformed)?;
    Ok((records, malformed))
}

/// The records of robot `robot` of a dataset read by [`load_mrclam_dir`], subjects named after
/// `map`; prints the summary line (`malformed` lines were skipped while reading).
pub(super) fn mrclam_records(
    data: &mrclam_dir::Dataset,
    robot: u32,
    map: &Map,
    malformed: usize,
) -> Result<Vec<crate::io::record::FrameRecord>, CliError> {
    use crate::io::mrclam_stream::to_record;
    let Some(log) = data.robots.iter().find(|r| r.robot == robot) else {
        return Err(CliError::Diagnostics { count: 1 });
    };
    let names = crate::io::landmark_stream::landmark_names(map);
    // The names a landmark stream's schema expects (`io::landmark_stream`).
    let name_of = |id: u32| crate::io::landmark_stream::subject_name(&names, id);
    let place_at = |x: f64, y: f64| {
        map.places()
            .iter()
            .find(|p| p.contains(x, y))
            .map(|p| p.name.clone())
    };
    let records: Vec<_> = log
        .frames
        .iter()
        .map(|f| to_record(f, &name_of, place_at))
        .collect();
    let listed: Vec<String> = log
        .misread_barcodes
        .iter()
        .map(|(b, n)| format!("{b}×{n}"))
        .collect();
    eprintln!(
        "extract: robot {robot}: {} frame(s), {} reading(s); {} misread barcode(s) dropped [{}]; {} malformed line(s) skipped",
        records.len(),
        log.readings,
        log.misread,
        listed.join(", "),
        malformed
    );
    Ok(records)
}
