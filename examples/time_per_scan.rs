//! lplace's time per scan, timed as MRPT's `pf-localization` times its filter step (its `Done
//! in`): the log is read and parsed into messages before the clock starts, and the clock runs
//! over what lplace does per scan — the frame made from the scan and the odometry (scan
//! extractors, compass, scan match), the engine's step and the tracker's. No log text, no JSON,
//! no process start: `scripts/mrpt_side_by_side.py` reports this beside the whole commands'
//! wall time.
//!
//! Run: `cargo run --release --example time_per_scan -- LOG PLAN_MAP SURVEYED_MAP RULES [PASSES]`
//! (the log plain or gzipped; the plan map gives the axis and the truth, as `lplace extract
//! --map` takes it; the surveyed map and the rules are `lplace eval`'s). Prints
//! `scans S decided D ms_per_scan M`, M the median of PASSES passes (default 5); D is the
//! number of frames with a place decided, which must equal `lplace eval`'s on the same inputs.

use std::io::{BufRead, Read};
use std::time::Instant;

use lplace::engine::tracker::PlaceTracker;
use lplace::engine::Engine;
use lplace::io::carmen::{CarmenMessage, CarmenReader};
use lplace::io::carmen_stream::CarmenFramer;
use lplace::logic::DecisionParams;
use lplace::map::Map;
use lplace::percept::ExtractConfig;
use lplace::syntax::diagnostic::SourceFile;
use lplace::syntax::parse_map;

type Failure = Box<dyn std::error::Error>;

fn main() -> Result<(), Failure> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [log, plan, surveyed, rules, ..] = args.as_slice() else {
        return Err("usage: time_per_scan LOG PLAN_MAP SURVEYED_MAP RULES [PASSES]".into());
    };
    let passes: usize = match args.get(4) {
        Some(p) => p.parse().map_err(|e| format!("PASSES {p}: {e}"))?,
        None => 5,
    };
    let messages = read_log(log)?;
    let plan = read_map(plan)?;
    let mut cfg = ExtractConfig::travelling();
    if let Some(axis) = plan.axis_deg() {
        cfg.compass.axis_deg = axis;
    }
    let (surveyed, rules) = (source(surveyed)?, source(rules)?);
    let mut times = Vec::new();
    let mut counts = (0, 0);
    for _ in 0..passes.max(1) {
        let engine = Engine::load(&surveyed, &rules).map_err(|d| {
            let (m, r) = (&surveyed.name, &rules.name);
            format!("{m} with {r}: {} problem(s)", d.diagnostics.len())
        })?;
        let t = Instant::now();
        counts = run(&messages, &plan, cfg, engine)?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    let (scans, decided) = counts;
    let per_scan = 1e3 * median / scans.max(1) as f64;
    println!("scans {scans} decided {decided} ms_per_scan {per_scan:.4}");
    Ok(())
}

/// One pass: frames from the messages, each evaluated and tracked; (frames, decided).
fn run(
    messages: &[(CarmenMessage, f64)],
    plan: &Map,
    cfg: ExtractConfig,
    mut engine: Engine,
) -> Result<(usize, usize), Failure> {
    let logic = engine.rules().logic;
    let params = DecisionParams {
        threshold: logic.threshold,
        margin: logic.margin,
    };
    let mut tracker = PlaceTracker::new(engine.map(), params, engine.tracker_config());
    let mut framer = CarmenFramer::new(cfg, Some(plan.places()))?;
    let mut frame = engine.new_frame();
    let mut rejected = Vec::new();
    let (mut frames, mut decided) = (0, 0);
    for (msg, laser_offset) in messages {
        let Some(f) = framer.push(msg, *laser_offset) else {
            continue;
        };
        rejected.clear();
        f.fill(engine.percepts(), &mut frame, &mut rejected);
        engine.step(&frame);
        let odometry = f.odometry.unwrap_or_default().to_si();
        let d = tracker.step(engine.distribution(), odometry, f.heading);
        frames += 1;
        decided += usize::from(d.place().is_some());
    }
    Ok((frames, decided))
}

/// The log's messages, each with the laser offset in force when it was read.
fn read_log(path: &str) -> Result<Vec<(CarmenMessage, f64)>, Failure> {
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|mut f| f.read_to_end(&mut bytes))
        .map_err(|e| format!("{path}: {e}"))?;
    let text: Box<dyn BufRead> = if bytes.starts_with(&[0x1f, 0x8b]) {
        Box::new(std::io::BufReader::new(flate2::read::GzDecoder::new(
            &bytes[..],
        )))
    } else {
        Box::new(&bytes[..])
    };
    let mut reader = CarmenReader::new(text);
    let mut messages = Vec::new();
    while let Some(item) = reader.next() {
        if let Ok((_, msg)) = item {
            messages.push((msg, reader.laser_offset()));
        }
    }
    Ok(messages)
}

fn source(path: &str) -> Result<SourceFile, Failure> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    Ok(SourceFile::new(path, text))
}

fn read_map(path: &str) -> Result<Map, Failure> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let problems =
        |d: Vec<lplace::syntax::diagnostic::Diagnostic>| format!("{path}: {} problem(s)", d.len());
    let ast = parse_map(&text).map_err(problems)?;
    Ok(Map::from_ast(&ast).map_err(problems)?)
}
