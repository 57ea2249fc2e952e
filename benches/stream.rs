//! `eval` throughput on a 1,000,000-frame simulated office stream (generated in memory by the
//! simulator, not committed), next to a plain serde_json parse of the same JSON-lines bytes into
//! the wire record type, in the same run.
//!
//! - `plain_serde_parse`: `serde_json::from_slice::<FrameRecord>` per line (owned strings and
//!   vectors), the baseline the issue asks for;
//! - `plain_serde_parse_fill`: the same, then `FrameRecord::fill` into the engine's `Frame`;
//! - `eval_no_track` / `eval_tracked`: `read_records` on one thread straight into the `Frame`, the
//!   engine step, the tracker (or not), the summary tally and a short JSON line written to a sink;
//! - `eval_tracked_read_ahead`: the same with the reading on a second thread, as `lplace eval`
//!   does when it has two cores;
//! - `cli_eval_tracked`: the `lplace eval` binary itself on the stream written to a temporary
//!   file, decisions to a null sink (process start included, a few milliseconds).

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use lplace::engine::tracker::{Tracker, TrackerConfig};
use lplace::engine::Engine;
use lplace::io::record::FrameRecord;
use lplace::io::stream::{read_records, Record, Schema, StreamFormat, StreamReader, Threads};
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

fn eval(engine: &mut Engine, bytes: &[u8], track: bool, threads: Threads) -> u64 {
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
    let reader = StreamReader::new(bytes, schema, StreamFormat::JsonLines);
    let mut sink = std::io::BufWriter::new(std::io::sink());
    let mut n = 0;
    let done = read_records(
        reader,
        threads,
        |_| {},
        |e| e,
        |record| {
            match record {
                Record::Rejected(e) => tally.reject(&e.reason),
                Record::Frame(frame, meta) => {
                    engine.step(frame);
                    let d = match &mut tracker {
                        Some(t) => {
                            t.step(engine.distribution(), meta.odometry.to_si(), meta.heading)
                        }
                        None => engine.decision(),
                    };
                    tally.record(d, meta);
                    writeln!(sink, "{{\"line\":{},\"place\":{:?}}}", meta.line, d.place())?;
                    n += 1;
                }
            }
            Ok(())
        },
    );
    done.expect("in-memory stream");
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
        b.iter(|| black_box(eval(&mut engine, &bytes, false, Threads::One)))
    });
    g.bench_function("eval_tracked", |b| {
        b.iter(|| black_box(eval(&mut engine, &bytes, true, Threads::One)))
    });
    g.bench_function("eval_tracked_read_ahead", |b| {
        b.iter(|| black_box(eval(&mut engine, &bytes, true, Threads::ReadAhead)))
    });
    let path = std::env::temp_dir().join(format!("lplace-bench-{}.jsonl", std::process::id()));
    std::fs::write(&path, &bytes).expect("temporary stream written");
    g.bench_function("cli_eval_tracked", |b| {
        b.iter(|| {
            let status = std::process::Command::new(env!("CARGO_BIN_EXE_lplace"))
                .arg("eval")
                .arg(&path)
                .args(["--summary", "none"])
                .stdout(std::process::Stdio::null())
                .status()
                .expect("lplace runs");
            black_box(status.success())
        })
    });
    let _ = std::fs::remove_file(&path);
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
