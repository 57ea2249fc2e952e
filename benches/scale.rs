//! Issue 16's scale figures: loading (`Engine::load`: parse, check, compile — what `lplace
//! check` does) and tracked evaluation per frame (`Engine::step` + the graph tracker) on
//! generated lattice maps of 1,000 / 5,000 / 10,000 places with the office rules
//! ([`lplace::sim::large_map`]), each next to the bundled office (8 places) measured in the same
//! run. Peak heap bytes (a counting allocator) are printed beside them.
//!
//! `cargo bench --bench scale -- --warm-up-time 1 --measurement-time 3`; `LPLACE_SCALE_SIZES`
//! (e.g. `1000,5000`) picks the sizes. Frames come from a seeded simulated walk on each map,
//! one continuous run: criterion's timed batches take the walk's next frames, made before each
//! batch's clock starts (a walk cycled through a fixed list of frames would teleport the robot
//! at each wrap, and the tracker would pay for relocalising: not the steady frame). Rows per
//! map: `tracked_frame` (`Engine::step` + the graph tracker, after 400 frames of warm-up),
//! `engine_frame` (`Engine::step` alone, its own walk, after the same warm-up); the tracker's
//! first frames (every anchor still live) are measured once, by hand.

#[path = "../tests/support/counting_alloc.rs"]
mod counting_alloc;

#[global_allocator]
static GLOBAL: counting_alloc::Counting = counting_alloc::Counting;

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use lplace::engine::tracker::{PlaceTracker, TrackerConfig};
use lplace::engine::{Engine, Frame, PerceptTable};
use lplace::logic::DecisionParams;
use lplace::sim::{SimConfig, Simulator};
use lplace::syntax::diagnostic::SourceFile;
use std::time::{Duration, Instant};

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

/// One frame and its odometry.
type Step = (Frame, lplace::core::Odometry);

/// Frames a timed batch is given at most at once: criterion asks millions of office frames.
const CHUNK: usize = 4096;

/// Frames the engine and the tracker run before they are measured.
const WARM_UP: usize = 400;

/// A seeded simulated walk over an engine's map, as long as it is pulled.
struct Walk {
    sim: Simulator,
    table: PerceptTable,
    buf: Vec<Step>,
}

impl Walk {
    fn new(engine: &Engine) -> Walk {
        let cfg = SimConfig {
            steps: u64::MAX,
            seed: 3,
            ..SimConfig::default()
        };
        Walk {
            sim: Simulator::for_engine(engine, cfg),
            table: engine.percepts().clone(),
            buf: Vec::with_capacity(CHUNK),
        }
    }

    /// The walk's next `k` frames.
    fn next(&mut self, k: usize) -> &[Step] {
        self.buf.clear();
        for rec in self.sim.by_ref().take(k) {
            let mut f = Frame::new(self.table.len());
            rec.fill(&self.table, &mut f, &mut Vec::new());
            self.buf.push((f, rec.odometry.unwrap_or_default().to_si()));
        }
        &self.buf
    }

    /// Time `run` takes over the walk's next `iters` frames, frames made off the clock.
    fn time(&mut self, iters: u64, mut run: impl FnMut(&Step)) -> Duration {
        let mut total = Duration::ZERO;
        let mut left = iters as usize;
        while left > 0 {
            let frames = self.next(left.min(CHUNK));
            if frames.is_empty() {
                break;
            }
            left -= frames.len();
            let start = Instant::now();
            frames.iter().for_each(&mut run);
            total += start.elapsed();
        }
        total
    }
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
fn step(engine: &mut Engine, t: &mut PlaceTracker, f: &Step) -> bool {
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
fn startup(engine: &mut Engine, frames: &[Step], k: usize) -> f64 {
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
        let mut walk = Walk::new(&engine);
        let first = startup(&mut engine, walk.next(100), 100);
        // The tracked run walks from the start again, with a fresh tracker (the engine keeps
        // nothing between frames that changes a result).
        let mut walk = Walk::new(&engine);
        let ((mut t, _), track_bytes) = peak(|| {
            let mut t = tracker(&engine);
            let decided = walk
                .next(WARM_UP)
                .iter()
                .filter(|f| step(&mut engine, &mut t, f))
                .count();
            (t, decided)
        });
        eprintln!(
            "scale {name}: load peak {:.1} MB; tracker built + {WARM_UP} frames peak {:.1} MB; \
             first 100 tracked frames {first:.0} µs/frame",
            load_bytes as f64 / 1e6,
            track_bytes as f64 / 1e6
        );
        g.bench_function(format!("tracked_frame/{name}"), |b| {
            b.iter_custom(|iters| {
                walk.time(iters, |f| {
                    black_box(step(&mut engine, &mut t, f));
                })
            })
        });
        let mut walk = Walk::new(&engine);
        for (f, _) in walk.next(WARM_UP) {
            engine.step(f);
        }
        g.bench_function(format!("engine_frame/{name}"), |b| {
            b.iter_custom(|iters| {
                walk.time(iters, |(f, _)| {
                    black_box(engine.step(f));
                })
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
