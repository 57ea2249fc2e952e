//! Extraction + evaluation of the whole Intel Research Lab log (910 scans, 2,651 s of robot
//! time): CARMEN parsing, the scan extractors, the frame records, the engine step and the
//! tracker, with `maps/intel.map`, `rules/intel.lpl`, `config/intel.ron` and
//! `config/intel-tracker.ron` (the metric grid tracker), as the README's command runs them. The log is read into
//! memory once, outside the timed loop. Goal: ≥ 10,000× real time, i.e. ≤ 265 ms per run.
//! Skips with a message when the data is absent (`$LPLACE_DATA`, else `../shared/data`).

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use lplace::engine::tracker::{PlaceTracker, TrackerConfig};
use lplace::engine::Engine;
use lplace::io::carmen_stream::{convert, CarmenFramer};
use lplace::logic::DecisionParams;
use lplace::percept::ExtractConfig;
use lplace::syntax::diagnostic::SourceFile;

/// The log's own duration, seconds (data README).
const LOG_SECONDS: f64 = 2651.0;

fn crate_file(rel: &str) -> Option<String> {
    std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(rel)).ok()
}

fn bench(c: &mut Criterion) {
    let data = std::env::var_os("LPLACE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data"));
    let Ok(log) = std::fs::read(data.join("carmen-corrected-logs/intel-corrected.log")) else {
        eprintln!("SKIP: the Intel log is not under {}", data.display());
        return;
    };
    let (Some(map), Some(rules), Some(cfg), Some(track)) = (
        crate_file("maps/intel.map"),
        crate_file("rules/intel.lpl"),
        crate_file("config/intel.ron"),
        crate_file("config/intel-tracker.ron"),
    ) else {
        eprintln!("SKIP: the Intel map, rules or configurations are missing");
        return;
    };
    let Ok(track) = TrackerConfig::from_ron(&track) else {
        eprintln!("SKIP: config/intel-tracker.ron is invalid");
        return;
    };
    let Ok(mut engine) = Engine::load(
        &SourceFile::new("maps/intel.map", map),
        &SourceFile::new("rules/intel.lpl", rules),
    ) else {
        eprintln!("SKIP: the Intel map and rules do not load");
        return;
    };
    let Ok(cfg) = ExtractConfig::from_ron(&cfg) else {
        eprintln!("SKIP: config/intel.ron is invalid");
        return;
    };
    let places = engine.map().clone();
    let logic = engine.rules().logic;
    let params = DecisionParams {
        threshold: logic.threshold,
        margin: logic.margin,
    };
    let mut frame = engine.new_frame();
    let mut rejected = Vec::new();

    let mut group = c.benchmark_group("intel");
    group.sample_size(10);
    group.bench_function("extract_and_eval_whole_log", |b| {
        b.iter(|| {
            let mut tracker = PlaceTracker::new(&places, params, track);
            let Ok(mut framer) = CarmenFramer::new(cfg, Some(places.places())) else {
                return 0;
            };
            let mut decided = 0usize;
            let _ = convert(
                black_box(log.as_slice()),
                &mut framer,
                |f| {
                    rejected.clear();
                    f.fill(engine.percepts(), &mut frame, &mut rejected);
                    engine.step(&frame);
                    let d = tracker.step(
                        engine.distribution(),
                        f.odometry.unwrap_or_default().to_si(),
                        f.heading,
                    );
                    decided += usize::from(d.place().is_some());
                    Ok::<(), ()>(())
                },
                |_| {},
            );
            black_box(decided)
        })
    });
    group.finish();
    eprintln!(
        "intel: the log lasts {LOG_SECONDS} s; speed-up = {LOG_SECONDS} s / (time per run above)"
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
