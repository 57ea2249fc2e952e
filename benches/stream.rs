//! `eval` throughput on a 1,000,000-frame simulated office stream (generated in memory by the
//! simulator, not committed), next to a plain serde_json parse of the same JSON-lines bytes into
//! the wire record type, in the same run.
//!
//! - `plain_serde_parse`: `serde_json::from_slice::<FrameRecord>` per line (owned strings and
//!   vectors), the baseline the issue asks for;
//! - `plain_serde_parse_fill`: the same, then `FrameRecord::fill` into the engine's `Frame`;
//! - `eval_no_track` / `eval_tracked`: the stream reader straight into the `Frame`, the engine
//!   step, the tracker (or not), the summary tally and the JSON decision line written to a sink —
//!   what `lplace eval` does per frame.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use lplace::engine::tracker::{Tracker, TrackerConfig};
use lplace::engine::Engine;
use lplace::io::record::FrameRecord;
use lplace::io::stream::{FrameMeta, ReadOutcome, Schema, StreamFormat, StreamReader};
use lplace::logic::DecisionParams;
use lplace::report::Tally;
use lplace::sim::{SimConfig, Simulator};
use std::io::Write;

const FRAMES: u64 = 1_000_000;

fn stream(engine: &Engine) -> Vec<u8> {
    let cfg = SimConfig {
        steps: FRAMES,
        seed: 11,
        kidnap_at: vec![250_000, 500_000, 750_000],
        ..SimConfig::default()
    };
    let mut out = Vec::with_capacity(FRAMES as usize * 320);
    for rec in Simulator::for_engine(engine, cfg) {
        serde_json::to_writer(&mut out, &rec).expect("in-memory write");
        out.push(b'\n');
    }
    out
}

fn eval(engine: &mut Engine, bytes: &[u8], track: bool) -> u64 {
    let logic = engine.rules().logic;
    let mut tracker = track.then(|| {
        Tracker::new(
            engine.map(),
            DecisionParams {
                threshold: logic.threshold,
                margin: logic.margin,
            },
            TrackerConfig::default(),
        )
    });
    let schema = Schema::new(engine.percepts(), engine.map());
    let mut tally = Tally::new(schema.places().to_vec(), track);
    let mut reader = StreamReader::new(bytes, schema, StreamFormat::JsonLines);
    let mut frame = engine.new_frame();
    let mut meta = FrameMeta::default();
    let mut sink = std::io::BufWriter::new(std::io::sink());
    let mut n = 0;
    while let Ok(r) = reader.next_frame(&mut frame, &mut meta) {
        match r {
            ReadOutcome::End => break,
            ReadOutcome::Rejected(e) => tally.reject(&e.reason),
            ReadOutcome::Frame => {
                engine.step(&frame);
                let d = match &mut tracker {
                    Some(t) => t.step(engine.distribution(), meta.odometry),
                    None => engine.decision(),
                };
                tally.record(d, &meta);
                let _ = writeln!(sink, "{{\"line\":{},\"place\":{:?}}}", meta.line, d.place());
                n += 1;
            }
        }
    }
    n
}

fn bench(c: &mut Criterion) {
    let mut engine = Engine::office().expect("bundled office example loads");
    let bytes = stream(&engine);
    let mut g = c.benchmark_group("office_stream_1M");
    g.sample_size(10);
    g.throughput(Throughput::Elements(FRAMES));
    g.bench_function("plain_serde_parse", |b| {
        b.iter(|| {
            let mut n = 0u64;
            for line in bytes.split(|&b| b == b'\n').filter(|l| !l.is_empty()) {
                let rec: FrameRecord = serde_json::from_slice(line).expect("valid record");
                n += rec.percepts.len() as u64;
            }
            black_box(n)
        })
    });
    let table = engine.percepts().clone();
    g.bench_function("plain_serde_parse_fill", |b| {
        let mut frame = engine.new_frame();
        let mut rejected = Vec::new();
        b.iter(|| {
            for line in bytes.split(|&b| b == b'\n').filter(|l| !l.is_empty()) {
                let rec: FrameRecord = serde_json::from_slice(line).expect("valid record");
                rec.fill(&table, &mut frame, &mut rejected);
            }
            black_box(frame.degree[0])
        })
    });
    g.bench_function("eval_no_track", |b| {
        b.iter(|| black_box(eval(&mut engine, &bytes, false)))
    });
    g.bench_function("eval_tracked", |b| {
        b.iter(|| black_box(eval(&mut engine, &bytes, true)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
