//! The Rust side of the Python binding's benchmark (`python/bench/bench.py`): one office step
//! with the frame copied in from a row of a dense array (what a Python `Engine.step` wraps), and
//! the `Engine.step_many` loop over 10 000 rows keeping the same outputs (decision, Inc and the
//! per-place support, Π and N). The Python script times the same two loops inside the extension
//! in its own run as its reference; this is the figure without Python in the process at all.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use lplace::engine::Engine;
use lplace::logic::Decision;

/// `n` rows of degrees and values, deterministic (xorshift), covering every slot.
fn rows(slots: usize, n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut d = Vec::with_capacity(slots * n);
    let mut v = Vec::with_capacity(slots * n);
    for _ in 0..slots * n {
        d.push(next());
        v.push(next() * 360.0);
    }
    (d, v)
}

fn bench(c: &mut Criterion) {
    let mut engine = Engine::office().expect("bundled office example loads");
    let mut frame = engine.new_frame();
    let slots = frame.degree.len();
    let n = 10_000;
    let (deg, val) = rows(slots, n);
    let k = engine.map().places().len();
    let mut g = c.benchmark_group("python_reference");
    let mut i = 0;
    g.bench_function("row_step", |b| {
        b.iter(|| {
            i = (i + 1) % n;
            frame
                .degree
                .copy_from_slice(&deg[i * slots..(i + 1) * slots]);
            frame
                .value
                .copy_from_slice(&val[i * slots..(i + 1) * slots]);
            black_box(engine.step(&frame))
        })
    });
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("step_many_loop_10k", |b| {
        b.iter(|| {
            let mut place = Vec::with_capacity(n);
            let mut inc = Vec::with_capacity(n);
            let mut per_place = Vec::with_capacity(3 * n * k);
            for (d, v) in deg.chunks_exact(slots).zip(val.chunks_exact(slots)) {
                frame.degree.copy_from_slice(d);
                frame.value.copy_from_slice(v);
                let dec = engine.step(&frame);
                place.push(match dec {
                    Decision::Place { place, .. } => place as i64,
                    Decision::Disoriented(_) => -1,
                });
                let dist = engine.distribution();
                inc.push(dist.inconsistency);
                per_place.extend_from_slice(&dist.support);
                per_place.extend_from_slice(&dist.possibility);
                per_place.extend_from_slice(&dist.necessity);
            }
            black_box((place, inc, per_place))
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
