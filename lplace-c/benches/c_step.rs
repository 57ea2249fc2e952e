//! One control cycle through the C API against the same cycle on the Rust engine, in one run:
//! clear the frame, set the frame's percepts, step — over the 2500 frames of the bundled office
//! recording, per frame. The C functions are called through function pointers hidden from the
//! optimiser, as a C caller reaches them (no inlining across the boundary).

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use lplace::engine::{Engine, PerceptSlot};
use lplace::io::record::FrameRecord;
use lplace_c::{
    lplace_engine_clear, lplace_engine_free, lplace_engine_load, lplace_engine_set,
    lplace_engine_step, LplaceDecision, LplaceEngine,
};

type Percepts = Vec<(u32, f64, f64)>;

/// The recording's frames as (slot, degree, value) lists, resolved once.
fn frames(engine: &Engine) -> Vec<Percepts> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../recordings/office.jsonl");
    let text = std::fs::read_to_string(path).expect("the bundled recording");
    text.lines()
        .map(|l| {
            let rec = FrameRecord::parse(l).expect("a valid record");
            rec.percepts
                .iter()
                .filter_map(|p| {
                    let args: Vec<&str> = p.args.iter().map(String::as_str).collect();
                    let s = engine.percepts().slot(&p.name, &args)?;
                    Some((s.0, p.degree, p.value.unwrap_or(f64::NAN)))
                })
                .collect()
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let mut engine = Engine::office().expect("office loads");
    let frames = frames(&engine);
    let mut frame = engine.new_frame();
    let mut g = c.benchmark_group("control_cycle");
    g.throughput(Throughput::Elements(frames.len() as u64));
    g.bench_function("rust", |b| {
        b.iter(|| {
            let mut chosen = 0usize;
            for f in &frames {
                frame.clear();
                for &(s, d, v) in f {
                    frame.set(PerceptSlot(s), d, (!v.is_nan()).then_some(v));
                }
                chosen += usize::from(engine.step(&frame).place().is_some());
            }
            chosen
        })
    });

    let e =
        unsafe { lplace_engine_load(std::ptr::null(), std::ptr::null(), std::ptr::null_mut(), 0) };
    assert!(!e.is_null());
    let clear: unsafe extern "C" fn(*mut LplaceEngine) = black_box(lplace_engine_clear);
    let set: unsafe extern "C" fn(*mut LplaceEngine, i32, f64, f64) -> i32 =
        black_box(lplace_engine_set);
    let step: unsafe extern "C" fn(*mut LplaceEngine, *mut LplaceDecision) -> i32 =
        black_box(lplace_engine_step);
    let mut d = LplaceDecision {
        place: 0,
        necessity: 0.0,
        inconsistency: 0.0,
        reason: 0,
    };
    g.bench_function("c_api", |b| {
        b.iter(|| {
            let mut chosen = 0usize;
            for f in &frames {
                unsafe {
                    clear(e);
                    for &(s, deg, v) in f {
                        set(e, s as i32, deg, v);
                    }
                    step(e, &mut d);
                }
                chosen += usize::from(d.place >= 0);
            }
            chosen
        })
    });
    g.finish();
    unsafe { lplace_engine_free(e) };
}

criterion_group!(benches, bench);
criterion_main!(benches);
