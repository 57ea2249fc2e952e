//! The CARMEN buildings' shared steps: a repository file's text, a map loaded from the
//! repository, and a raw log extracted to frames as `lplace extract --map` does (the map's
//! `axis D;` replaces the config's axis). Logs kept gzipped (`*.log.gz`, the data set's
//! secondary buildings) are read through a decoder, never unpacked to disk.

use flate2::read::GzDecoder;
use lplace::io::carmen_stream::{convert, CarmenFramer};
use lplace::io::record::FrameRecord;
use lplace::map::Map;
use lplace::percept::ExtractConfig;
use lplace::syntax::parse_map;
use std::io::{BufReader, Read};
use std::path::{Path, PathBuf};

/// The text of a file of the repository (`maps/intel.map`).
pub fn repo(path: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// A map of the repository, parsed and built (panics on errors: the maps are the repository's).
pub fn load_map(path: &str) -> Map {
    let text = repo(path);
    let ast = parse_map(&text).unwrap_or_else(|d| panic!("{path}: {d:?}"));
    Map::from_ast(&ast).unwrap_or_else(|d| panic!("{path}: {d:?}"))
}

/// The frames of a CARMEN log with the extractor config at `config` (a repository path), truth
/// places from `map`'s extents and its axis, if it states one. A `.gz` log is decompressed as it
/// is read.
pub fn extract(log: &Path, config: &str, map: &Map) -> Vec<FrameRecord> {
    let cfg = ExtractConfig::from_ron(&repo(config)).expect("extractor config");
    extract_with(log, cfg, map)
}

/// [`extract`] with the extractor settings `cfg` (`ExtractConfig::travelling()`: what
/// `lplace extract` uses without `--config`).
pub fn extract_with(log: &Path, mut cfg: ExtractConfig, map: &Map) -> Vec<FrameRecord> {
    if let Some(axis) = map.axis_deg() {
        cfg.compass.axis_deg = axis;
    }
    let mut framer = CarmenFramer::new(cfg, Some(map.places())).expect("a valid config");
    let file = std::fs::File::open(log).expect("the log opens");
    let source: Box<dyn Read> = if log.extension().is_some_and(|e| e == "gz") {
        Box::new(GzDecoder::new(file))
    } else {
        Box::new(file)
    };
    let mut frames = Vec::new();
    convert(
        BufReader::new(source),
        &mut framer,
        |f| -> Result<(), ()> {
            frames.push(f);
            Ok(())
        },
        |e| panic!("{e}"),
    )
    .expect("conversion");
    frames
}
