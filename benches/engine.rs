//! Compiled evaluation of the office rules — all eight places plus the decision — per frame,
//! next to the tree-walking interpreter on the same frames, in the same run.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use lplace::engine::interpret::Interpreter;
use lplace::engine::{Engine, Frame};

/// Deterministic pseudo-random frames covering every office percept.
fn frames(engine: &Engine, n: usize) -> Vec<Frame> {
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let mut f = engine.new_frame();
            for i in 0..f.degree.len() {
                f.degree[i] = next();
                f.value[i] = next() * 360.0;
            }
            f
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let mut engine = Engine::office().expect("bundled office example loads");
    let frames = frames(&engine, 64);
    let mut g = c.benchmark_group("office_frame");
    let mut i = 0;
    g.bench_function("compiled_step", |b| {
        b.iter(|| {
            i = (i + 1) % frames.len();
            black_box(engine.step(black_box(&frames[i])))
        })
    });
    let reference = engine.clone();
    let interp = Interpreter::new(reference.rules(), reference.map(), reference.percepts());
    let mut dist = lplace::logic::PlaceDistribution::new(reference.map().places().len());
    let logic = reference.rules().logic;
    g.bench_function("interpreter_step", |b| {
        b.iter(|| {
            i = (i + 1) % frames.len();
            let r = interp.run(black_box(&frames[i]));
            dist.support.copy_from_slice(&r.support);
            dist.exclusion.copy_from_slice(&r.exclusion);
            dist.update(logic.normalisation);
            black_box(lplace::logic::decide(
                &dist,
                lplace::logic::DecisionParams {
                    threshold: logic.threshold,
                    margin: logic.margin,
                },
            ))
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
