//! `lplace extract --from carmen LOG [--map MAP] [--config CONFIG]`: turn a raw sensor log into
//! the percept stream (JSON lines of [`crate::io::record::FrameRecord`]) on stdout, one frame
//! per laser scan. The conversion itself is library code (`io::carmen_stream`); this module
//! reads the files, reports malformed log lines on stderr with their line numbers and picks the
//! exit code (3 when any line was rejected, after converting all the others).

use std::io::{BufReader, Write};
use std::path::PathBuf;

use super::{read_source, render, CliError, EXIT_OK, EXIT_REJECTED};
use crate::io::carmen_stream::{convert, CarmenFramer};
use crate::map::Map;
use crate::percept::ExtractConfig;
use crate::syntax::parse_map;

/// Raw log formats `extract` reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LogFormat {
    /// CARMEN text log (FLASER, ODOM, PARAM), e.g. the Radish "corrected" logs.
    Carmen,
}

/// `lplace extract`.
#[derive(Debug, Clone, clap::Args)]
pub struct ExtractArgs {
    /// Format of the raw log.
    #[arg(long, value_enum, default_value_t = LogFormat::Carmen)]
    pub from: LogFormat,
    /// The raw log.
    #[arg(value_name = "LOG")]
    pub log: PathBuf,
    /// Map (.map) whose place extents give each frame's ground-truth place.
    #[arg(long, value_name = "MAP")]
    pub map: Option<PathBuf>,
    /// Extractor parameters (RON; see `percept::ExtractConfig`). Default: built-in defaults.
    #[arg(long, value_name = "CONFIG")]
    pub config: Option<PathBuf>,
}

/// Runs `extract`: frames to `out`, malformed lines and a summary to stderr.
///
/// # Errors
/// [`CliError::Read`] when a file cannot be read, [`CliError::Diagnostics`] when the map or the
/// config has errors (printed first), [`CliError::Write`] when `out` fails.
pub fn run(args: &ExtractArgs, out: &mut impl Write) -> Result<u8, CliError> {
    let cfg = match &args.config {
        None => ExtractConfig::default(),
        Some(path) => {
            let src = read_source(path)?;
            ExtractConfig::from_ron(&src.text).map_err(|e| {
                eprintln!("{}: {e}", path.display());
                CliError::Diagnostics { count: 1 }
            })?
        }
    };
    let map = match &args.map {
        None => None,
        Some(path) => {
            let src = read_source(path)?;
            let fail = |d: Vec<crate::syntax::diagnostic::Diagnostic>| {
                render::eprint(&src, &d);
                CliError::Diagnostics { count: d.len() }
            };
            let ast = parse_map(&src.text).map_err(fail)?;
            Some(Map::from_ast(&ast).map_err(fail)?)
        }
    };
    let file = std::fs::File::open(&args.log).map_err(|source| CliError::Read {
        path: args.log.display().to_string(),
        source,
    })?;
    let mut framer = CarmenFramer::new(cfg, map.as_ref().map(Map::places)).map_err(|e| {
        eprintln!("{e}");
        CliError::Diagnostics { count: 1 }
    })?;
    let log_name = args.log.display().to_string();
    let summary = convert(
        BufReader::new(file),
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
    Ok(if st.errors > 0 {
        EXIT_REJECTED
    } else {
        EXIT_OK
    })
}
