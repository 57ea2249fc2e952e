//! Replays the fuzz corpus (`fuzz/corpus/<target>/`: hand-made hostile cases and whatever the
//! fuzzers found) through the fuzz targets' own entry points on the stable toolchain, so that
//! `cargo test` guards every kept case even where cargo-fuzz cannot run. A case fails by
//! panicking (or by running away: each target's whole corpus must replay in seconds).

#[allow(dead_code)]
#[path = "../../fuzz/src/entries.rs"]
mod entries;

use lplace::io::stream::StreamFormat;
use std::path::PathBuf;

/// The corpus files of `target`, sorted; at least one (an empty folder would test nothing).
fn corpus(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/corpus")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| Some(e.ok()?.path()))
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no corpus in {}", dir.display());
    files
        .into_iter()
        .map(|p| {
            let bytes = std::fs::read(&p).expect("corpus file is readable");
            (p, bytes)
        })
        .collect()
}

fn replay(target: &str, run: impl Fn(&[u8])) {
    for (path, bytes) in corpus(target) {
        let t = std::time::Instant::now();
        run(&bytes);
        // Generous for a loaded CI machine; the slowest case takes well under 1 s here.
        assert!(t.elapsed().as_secs() < 20, "{} ran away", path.display());
    }
}

#[test]
fn rules_corpus() {
    replay("rules", entries::rules);
}

#[test]
fn map_corpus() {
    replay("map", entries::map);
}

#[test]
fn stream_jsonl_corpus() {
    replay("stream_jsonl", |b| {
        entries::stream(b, StreamFormat::JsonLines)
    });
}

#[test]
fn stream_csv_corpus() {
    replay("stream_csv", |b| entries::stream(b, StreamFormat::Csv));
}

#[test]
fn carmen_corpus() {
    replay("carmen", entries::carmen);
}

#[test]
fn mrclam_corpus() {
    replay("mrclam", entries::mrclam);
}
