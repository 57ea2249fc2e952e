//! The entry points the fuzz targets drive, shared with the stable replay test
//! (`tests/io/fuzz_corpus.rs` includes this file), so that CI replays the corpus through exactly
//! what was fuzzed even where cargo-fuzz cannot run. Each takes arbitrary bytes and must return
//! without panicking, whatever they hold.

use lplace::engine::Engine;
use lplace::io::carmen::CarmenReader;
use lplace::io::carmen_stream::{convert, CarmenFramer};
use lplace::io::stream::{FrameMeta, ReadOutcome, Schema, StreamFormat, StreamReader};
use lplace::map::Map;
use lplace::percept::ExtractConfig;
use lplace::rules::check_rules;
use lplace::syntax::{parse_map, parse_rules, SourceFile};

/// Bytes as a source file the way the command line reads one (BOM dropped, UTF-8 checked).
fn source(data: &[u8]) -> Option<SourceFile> {
    match SourceFile::from_bytes("fuzz", data.to_vec()) {
        (file, None) => Some(file),
        (file, Some(d)) => {
            let _ = d.render_plain(&file);
            None
        }
    }
}

fn office_map() -> Option<Map> {
    let ast = parse_map(lplace::engine::OFFICE_MAP).ok()?;
    Map::from_ast(&ast).ok()
}

/// A rule file: parsed, checked against the office map, compiled.
pub fn rules(data: &[u8]) {
    let (Some(file), Some(map)) = (source(data), office_map()) else {
        return;
    };
    let diags = match parse_rules(&file.text) {
        Ok(ast) => match check_rules(&ast, &map) {
            Ok(set) => {
                let opts = lplace::engine::CompileOptions::default();
                match lplace::engine::compile(&set, &map, &opts) {
                    Ok(_) => return,
                    Err(d) => d,
                }
            }
            Err(d) => d,
        },
        Err(d) => d,
    };
    for d in diags {
        let _ = d.render_plain(&file);
    }
}

/// A map file: parsed and built.
pub fn map(data: &[u8]) {
    let Some(file) = source(data) else { return };
    let diags = match parse_map(&file.text).and_then(|ast| Map::from_ast(&ast)) {
        Ok(_) => return,
        Err(d) => d,
    };
    for d in diags {
        let _ = d.render_plain(&file);
    }
}

/// A percept stream (JSON Lines or CSV) read against the office example, fast path on and off.
pub fn stream(data: &[u8], format: StreamFormat) {
    let Ok(engine) = Engine::office() else { return };
    for fast in [true, false] {
        let schema = Schema::new(engine.percepts(), engine.map());
        let mut reader = StreamReader::new(data, schema, format);
        reader.set_fast_path(fast);
        let mut frame = engine.new_frame();
        let mut meta = FrameMeta::default();
        while let Ok(ReadOutcome::Frame | ReadOutcome::Rejected(_)) =
            reader.next_frame(&mut frame, &mut meta)
        {}
    }
}

/// A CARMEN log: every line read, and converted to frames with the default extractors.
pub fn carmen(data: &[u8]) {
    for item in CarmenReader::new(data) {
        let _ = item;
    }
    let Ok(mut framer) = CarmenFramer::new(ExtractConfig::default(), None) else {
        return;
    };
    let _ = convert::<_, ()>(data, &mut framer, |_| Ok(()), |_| {});
}

/// The MRCLAM files: the same bytes read as each kind of `.dat` file.
pub fn mrclam(data: &[u8]) {
    use lplace::io::mrclam::*;
    let codes = read_barcodes(data).unwrap_or_default();
    let _ = read_landmarks(data);
    let _ = read_odometry(data);
    let _ = read_groundtruth(data);
    let _ = read_measurements(data, &codes);
}
