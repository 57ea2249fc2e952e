//! `lplace draw LOG -o scans.svg [--map MAP]`: a CARMEN log's laser scans drawn at the poses
//! the log gives them, with a metre grid in the log's frame and the map's place outlines over
//! them — the picture a floor plan is read off (docs/new-building.md, step 2), and the check
//! that a map's extents sit where the scans say. The picture is library code
//! ([`crate::report::scans`]); this module reads the files, reports malformed log lines on
//! stderr with their line numbers and picks the exit code (3 when any line was rejected, after
//! drawing all the others).

use std::path::PathBuf;

use super::args::ArgError;
use super::output::{self, Output};
use super::{CliError, EXIT_OK, EXIT_REJECTED};
use crate::io::carmen::{CarmenMessage, CarmenReader};
use crate::report::scans::{PictureStyle, ScanPicture};

/// `lplace draw`.
#[derive(Debug, Clone, clap::Args)]
pub struct DrawArgs {
    /// The CARMEN log (`FLASER` lines; gzipped or not). A corrected log, or one your SLAM
    /// wrote, gives the building's walls; a raw log smears them as its odometry drifts.
    #[arg(value_name = "LOG")]
    pub log: PathBuf,
    /// The SVG file to write.
    #[arg(short = 'o', long = "output", value_name = "SVG")]
    pub output: PathBuf,
    /// A map whose place outlines (boxes, rotated boxes, polygons) are drawn over the scans.
    #[arg(long, value_name = "MAP")]
    pub map: Option<PathBuf>,
    /// Side of the cells beam end points are counted in, metres (at least 0.01).
    #[arg(long, value_name = "M", default_value_t = 0.1)]
    pub cell: f64,
    /// Least beam end points for a cell to be drawn (2 hides stray beams and passers-by).
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub min_hits: u32,
    /// Draw every N-th scan (a long log at many scans per metre draws the same walls again).
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub every: usize,
    /// Beams at or beyond this range are "no return" (the CARMEN logs code it 32–82 m).
    #[arg(long, value_name = "M", default_value_t = 30.0)]
    pub max_range: f64,
    /// Pixels per metre.
    #[arg(long, value_name = "PX", default_value_t = 20.0)]
    pub scale: f64,
}

/// Runs `draw`: the picture to `args.output`, malformed lines and a summary to stderr.
///
/// # Errors
/// [`CliError::OutputPath`] or [`CliError::BadArgument`] before reading anything,
/// [`CliError::Read`] when a file cannot be read, [`CliError::Diagnostics`] when the map has
/// errors (printed first), [`CliError::WriteFile`] when the picture cannot be written.
pub fn run(args: &DrawArgs) -> Result<u8, CliError> {
    let mut inputs = vec![("LOG", args.log.as_path())];
    inputs.extend(args.map.as_deref().map(|m| ("--map", m)));
    output::check(&[Output::file("--output", &args.output)], &inputs)?;
    let mut picture = settings(args)?;
    let map = match &args.map {
        Some(path) => Some(super::extract::read_map(path)?),
        None => None,
    };
    let log = super::extract::open_log(&args.log)?;
    let log_name = args.log.display().to_string();
    let mut reader = CarmenReader::new(log);
    let (mut lasers, mut errors) = (0usize, 0usize);
    while let Some(item) = reader.next() {
        match item {
            Ok((_, CarmenMessage::Laser(scan))) => {
                if lasers % args.every == 0 {
                    picture.add(&scan, reader.laser_offset());
                }
                lasers += 1;
            }
            Ok(_) => {}
            Err(e) => {
                errors += 1;
                eprintln!("{log_name}: {e}");
            }
        }
    }
    let style = PictureStyle {
        min_hits: args.min_hits,
        scale: args.scale,
        title: format!(
            "{log_name}: {} of {lasers} scans{}",
            picture.scans(),
            args.map
                .as_ref()
                .map(|m| format!(", places of {}", m.display()))
                .unwrap_or_default()
        ),
    };
    let svg = picture.svg(map.as_ref(), &style);
    output::write_atomic(&args.output, |w| w.write_all(svg.as_bytes()))?;
    eprintln!(
        "draw: {} of {lasers} scan(s) drawn from {} line(s); {errors} malformed line(s) skipped{}",
        picture.scans(),
        reader.stats().lines,
        match picture.dropped() {
            0 => String::new(),
            n => format!("; {n} beam end(s) beyond the picture's cell limit left out"),
        }
    );
    Ok(if errors > 0 { EXIT_REJECTED } else { EXIT_OK })
}

/// The empty picture `args` ask for, or the flag that is out of range.
fn settings(args: &DrawArgs) -> Result<ScanPicture, CliError> {
    let bad = |flag, value: f64, range| {
        CliError::BadArgument(ArgError::OutOfRange { flag, value, range })
    };
    if args.every == 0 {
        return Err(bad("every", 0.0, "at least 1"));
    }
    if !(args.scale.is_finite() && args.scale > 0.0 && args.scale <= 1000.0) {
        return Err(bad("scale", args.scale, "above 0, at most 1000"));
    }
    ScanPicture::new(args.cell, args.max_range).map_err(|e| match e {
        crate::report::scans::PictureError::Cell(v) => bad("cell", v, "finite, at least 0.01"),
        crate::report::scans::PictureError::Range(v) => bad("max-range", v, "finite and positive"),
    })
}
