//! `lplace extract --from rosbag2 PATH`: a ROS 2 bag (MCAP storage) as a percept stream on
//! stdout. PATH is a `.mcap` file or a bag directory; a directory's `metadata.yaml` must name
//! the `mcap` storage (the sqlite3 storage is not read: convert such a bag with
//! `ros2 bag convert` or the `rosbags` tools first), and its `.mcap` files are read in name
//! order. The conversion is library code (`io::rosbag2`); this module finds the files, reads
//! them, reports skipped messages on stderr as `PATH: TOPIC at LOG_TIME ns: reason` and
//! picks the exit code (3 when any message was skipped, after converting all the others).

use std::io::Write;
use std::path::{Path, PathBuf};

use super::args::ExtractArgs;
use super::{CliError, EXIT_OK, EXIT_REJECTED};
use crate::io::carmen_stream::CarmenFramer;
use crate::io::rosbag2::{resolve_topics, BagConverter, TopicChoice};
use crate::map::Map;
use crate::percept::ExtractConfig;

/// Runs `extract --from rosbag2`.
pub(super) fn run(
    args: &ExtractArgs,
    cfg: ExtractConfig,
    map: Option<&Map>,
    out: &mut impl Write,
) -> Result<u8, CliError> {
    let files = bag_files(&args.log)?;
    let read = |path: &Path| {
        std::fs::read(path).map_err(|source| CliError::Read {
            path: path.display().to_string(),
            source,
        })
    };
    let Some(first) = files.first() else {
        eprintln!("error: {}: no .mcap file in the bag", args.log.display());
        return Err(CliError::Diagnostics { count: 1 });
    };
    let choice = TopicChoice {
        scan: args.scan_topic.clone(),
        odom: args.odom_topic.clone(),
        truth: args.truth_topic.clone(),
    };
    let topics = resolve_topics(&read(first)?, &choice).map_err(|e| bag_error(first, &e))?;
    if map.is_some() && topics.truth.is_none() {
        eprintln!("extract: the bag has no truth topic (--truth-topic): frames carry no truth");
    }
    // Truth places only from truth poses, never from odometry.
    let places = map.filter(|_| topics.truth.is_some()).map(Map::places);
    let mut framer = CarmenFramer::new(cfg, places).map_err(|e| {
        eprintln!("{e}");
        CliError::Diagnostics { count: 1 }
    })?;
    let mut conv = BagConverter::new(&mut framer, topics.clone(), args.laser_offset);
    for path in &files {
        let bytes = read(path)?;
        let name = path.display().to_string();
        let written = conv
            .push_file(
                &bytes,
                |frame| -> Result<(), CliError> {
                    serde_json::to_writer(&mut *out, &frame).map_err(std::io::Error::from)?;
                    out.write_all(b"\n")?;
                    Ok(())
                },
                |e| eprintln!("{name}: {e}"),
            )
            .map_err(|e| bag_error(path, &e))?;
        written?;
    }
    let s = conv.summary();
    eprintln!(
        "extract: {} frame(s) from {} scan(s) on {}, {} odometry message(s) on {}, {} truth pose(s){}; \
         {} scan(s) before the first odometry skipped; {} bad message(s) skipped",
        s.frames,
        s.scans,
        topics.scan,
        s.odoms,
        topics.odom,
        s.truths,
        topics.truth.as_deref().map_or(String::new(), |t| format!(" on {t}")),
        s.scans_before_odometry,
        s.rejected
    );
    Ok(if s.rejected > 0 {
        EXIT_REJECTED
    } else {
        EXIT_OK
    })
}

fn bag_error(path: &Path, e: &crate::io::rosbag2::BagError) -> CliError {
    eprintln!("error: {}: {e}", path.display());
    CliError::Diagnostics { count: 1 }
}

/// The `.mcap` files of a bag: PATH itself, or a directory's, in name order (rosbag2 numbers
/// split files `NAME_0.mcap`, `NAME_1.mcap`, …; shorter names first keeps `_10` after `_9`).
fn bag_files(path: &Path) -> Result<Vec<PathBuf>, CliError> {
    let read_err = |source| CliError::Read {
        path: path.display().to_string(),
        source,
    };
    if !path.is_dir() {
        return Ok(vec![path.to_path_buf()]);
    }
    let meta = path.join("metadata.yaml");
    let text = std::fs::read_to_string(&meta).map_err(|source| CliError::Read {
        path: meta.display().to_string(),
        source,
    })?;
    // One key of the metadata decides; the rest of the YAML is not needed.
    let storage = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("storage_identifier:"))
        .map(str::trim);
    if storage != Some("mcap") {
        eprintln!(
            "error: {}: storage {:?} is not read (only mcap); convert the bag first",
            meta.display(),
            storage.unwrap_or("unknown")
        );
        return Err(CliError::Diagnostics { count: 1 });
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(path)
        .map_err(read_err)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "mcap"))
        .collect();
    files.sort_by_key(|p| (p.as_os_str().len(), p.clone()));
    Ok(files)
}
