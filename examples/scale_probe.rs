//! Splits a tracked frame at N generated places into `Engine::step` and the graph tracker's
//! step (issue 16): `cargo run --release --example scale_probe -- 10000 800`. A third argument
//! `W` reports both over the frames from `W` on (default: the second half), so that a long walk
//! (`10000 4000 400`) measures, or profiles (`perf record -D`, after the line it prints when
//! frame `W` is reached), the steady state after every anchor's first 400 frames; `engine`
//! instead steps the engine alone (no tracker), its figure over the second half.

use lplace::engine::tracker::{PlaceTracker, TrackerConfig};
use lplace::engine::Engine;
use lplace::logic::DecisionParams;
use lplace::sim::{SimConfig, Simulator};
use lplace::syntax::diagnostic::SourceFile;
use std::time::Instant;

fn main() {
    let arg = |i: usize, d: u64| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or(d)
    };
    let (n, steps) = (arg(1, 1000) as usize, arg(2, 400));
    let engine_only = std::env::args().nth(3).is_some_and(|a| a == "engine");
    let warm = if engine_only {
        steps / 2
    } else {
        arg(3, steps / 2)
    } as usize;
    let text = lplace::sim::large_map::lattice_office(n, 1);
    let t0 = Instant::now();
    let begun = t0;
    let rules = include_str!("../rules/office.lpl");
    let Ok(mut engine) = Engine::load(
        &SourceFile::new("scale.map", text.as_str()),
        &SourceFile::new("rules/office.lpl", rules),
    ) else {
        eprintln!("the generated map does not load");
        return;
    };
    let load = t0.elapsed();
    let cfg = SimConfig {
        steps,
        seed: 3,
        ..SimConfig::default()
    };
    let frames: Vec<_> = Simulator::for_engine(&engine, cfg)
        .map(|rec| {
            let mut f = engine.new_frame();
            rec.fill(engine.percepts(), &mut f, &mut Vec::new());
            (f, rec.odometry.unwrap_or_default().to_si())
        })
        .collect();
    let k = frames.len().max(1) as f64;
    if engine_only {
        let (mut late, mut decided) = (0.0, 0);
        for (i, (f, _)) in frames.iter().enumerate() {
            let a = Instant::now();
            decided += usize::from(engine.step(f).place().is_some());
            if 2 * i >= frames.len() {
                late += a.elapsed().as_secs_f64();
            }
        }
        println!(
            "n {n}: load {:.3} s; Engine::step alone, second half: {:.1} µs per frame; decided {decided}/{}",
            load.as_secs_f64(),
            2e6 * late / k,
            frames.len()
        );
        return;
    }
    let logic = engine.rules().logic;
    let params = DecisionParams {
        threshold: logic.threshold,
        margin: logic.margin,
    };
    let t1 = Instant::now();
    let mut tracker = PlaceTracker::new(engine.map(), params, TrackerConfig::default());
    let build = t1.elapsed();
    let (mut e_time, mut t_time, mut decided) = (0.0, 0.0, 0);
    let (mut e_late, mut t_late) = (0.0, 0.0);
    for (i, (f, odo)) in frames.iter().enumerate() {
        if i == warm {
            eprintln!("frame {warm} at {:.2} s", begun.elapsed().as_secs_f64());
        }
        let a = Instant::now();
        engine.step(f);
        let b = Instant::now();
        decided += usize::from(
            tracker
                .step(engine.distribution(), *odo, None)
                .place()
                .is_some(),
        );
        let (e, t) = ((b - a).as_secs_f64(), b.elapsed().as_secs_f64());
        (e_time, t_time) = (e_time + e, t_time + t);
        if i >= warm {
            (e_late, t_late) = (e_late + e, t_late + t);
        }
    }
    let late = frames.len().saturating_sub(warm).max(1) as f64;
    println!(
        "n {n}: load {:.3} s, tracker built {:.3} s; per frame: engine {:.1} µs, tracker {:.1} µs (frames {warm}..: engine {:.1} µs, tracker {:.1} µs); decided {decided}/{}",
        load.as_secs_f64(),
        build.as_secs_f64(),
        1e6 * e_time / k,
        1e6 * t_time / k,
        1e6 * e_late / late,
        1e6 * t_late / late,
        frames.len()
    );
}
