//! Issue 16's scale figures: loading (`Engine::load`: parse, check, compile — what `lplace
//! check` does) and tracked evaluation per frame (`Engine::step` + the graph tracker) on
//! generated lattice maps of 1,000 / 5,000 / 10,000 places with the office rules
//! ([`lplace::sim::large_map`]), each next to the bundled office (8 places) measured in the same
//! run. Peak heap bytes (a counting allocator) are printed beside them.
//!
//! `cargo bench --bench scale -- --warm-up-time 1 --measurement-time 3`; `LPLACE_SCALE_SIZES`
//! (e.g. `1000,5000`) picks the sizes. Frames come from the seeded simulator on each map; the
//! tracker is measured in its steady state (after one pass over the frames) by criterion, and
//! over its first frames (every anchor still live) once, by hand.

#[path = "../tests/support/counting_alloc.rs"]
mod counting_alloc;

#[global_allocator]
static GLOBAL: counting_alloc::Counting = counting_alloc::Counting;

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use lplace::engine::tracker::{PlaceTracker, TrackerConfig};
use lplace::engine::{Engine, Frame};
use lplace::logic::DecisionParams;
use lplace::sim::{SimConfig, Simulator};
use lplace::syntax::diagnostic::SourceFile;
use std::time::Instant;

const OFFICE_RULES: &str = include_str!("../rules/office.lpl");
const OFFICE_MAP: &str = include_str!("../maps/office.map");

fn sizes() -> Vec<usize> {
    std::env::var("LPLACE_SCALE_SIZES")
        .ok()
        .map(|v| v.split(',').filter_map(|s| s.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![1000, 5000, 10000])
}

fn load(map: &str) -> Engine {
    Engine::load(
        &SourceFile::new("scale.map", map),
        &SourceFile::new("rules/office.lpl", OFFICE_RULES),
    )
    .expect("generated maps load")
}

/// Frames and odometry of a seeded simulated run over `engine`'s map.
fn frames(engine: &Engine, steps: u64) -> Vec<(Frame, lplace::core::Odometry)> {
    let cfg = SimConfig {
        steps,
        seed: 3,
        ..SimConfig::default()
    };
    Simulator::for_engine(engine, cfg)
        .map(|rec| {
            let mut f = engine.new_frame();
            rec.fill(engine.percepts(), &mut f, &mut Vec::new());
            (f, rec.odometry.unwrap_or_default().to_si())
        })
        .collect()
}

fn tracker(engine: &Engine) -> PlaceTracker {
    let logic = engine.rules().logic;
    let params = DecisionParams {
        threshold: logic.threshold,
        margin: logic.margin,
    };
    PlaceTracker::new(engine.map(), params, TrackerConfig::default())
}

/// One tracked frame, as `lplace eval` does it.
fn step(engine: &mut Engine, t: &mut PlaceTracker, f: &(Frame, lplace::core::Odometry)) -> bool {
    engine.step(&f.0);
    t.step(engine.distribution(), f.1, None).place().is_some()
}

/// Peak heap bytes while `f` runs, above what was live before it, and its result.
fn peak<T>(f: impl FnOnce() -> T) -> (T, usize) {
    counting_alloc::reset_peak();
    let base = counting_alloc::live_bytes();
    let out = f();
    (out, counting_alloc::peak_bytes().saturating_sub(base))
}

/// The first `k` tracked frames from a fresh tracker, by hand: mean µs per frame.
fn startup(engine: &mut Engine, frames: &[(Frame, lplace::core::Odometry)], k: usize) -> f64 {
    let mut t = tracker(engine);
    let start = Instant::now();
    for f in frames.iter().take(k) {
        black_box(step(engine, &mut t, f));
    }
    start.elapsed().as_secs_f64() * 1e6 / k.min(frames.len()).max(1) as f64
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("scale");
    g.sample_size(10);
    let mut maps = vec![("office".to_string(), OFFICE_MAP.to_string())];
    for n in sizes() {
        maps.push((n.to_string(), lplace::sim::large_map::lattice_office(n, 1)));
    }
    for (name, text) in &maps {
        let (mut engine, load_bytes) = peak(|| load(text));
        g.bench_function(format!("load/{name}"), |b| b.iter(|| black_box(load(text))));
        let frames = frames(&engine, 400);
        let first = startup(&mut engine, &frames, 100);
        let ((mut t, _), track_bytes) = peak(|| {
            let mut t = tracker(&engine);
            let decided = frames
                .iter()
                .filter(|f| step(&mut engine, &mut t, f))
                .count();
            (t, decided)
        });
        eprintln!(
            "scale {name}: load peak {:.1} MB; tracker built + one pass peak {:.1} MB; \
             first 100 tracked frames {first:.0} µs/frame",
            load_bytes as f64 / 1e6,
            track_bytes as f64 / 1e6
        );
        let mut i = 0;
        g.bench_function(format!("tracked_frame/{name}"), |b| {
            b.iter(|| {
                i = (i + 1) % frames.len();
                black_box(step(&mut engine, &mut t, &frames[i]))
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
