//! `Engine::step` allocates nothing: a counting allocator (per thread, `main.rs`) watches a thousand steps on
//! varied frames (including hostile ones) after the engine is loaded.

use super::allocations;
use lplace::engine::Engine;

#[test]
fn step_allocates_nothing() {
    let mut engine = Engine::office().expect("office loads");
    let mut frames: Vec<_> = (0..16).map(|_| engine.new_frame()).collect();
    for (i, f) in frames.iter_mut().enumerate() {
        for (j, d) in f.degree.iter_mut().enumerate() {
            *d = match (i + j) % 7 {
                0 => f64::NAN,
                1 => 1.5,
                _ => ((i * 31 + j * 17) % 100) as f64 / 100.0,
            };
        }
        for (j, v) in f.value.iter_mut().enumerate() {
            *v = ((i * 13 + j * 7) % 360) as f64;
        }
    }
    let before = allocations();
    let mut chosen = 0usize;
    for k in 0..1000 {
        if engine.step(&frames[k % frames.len()]).place().is_some() {
            chosen += 1;
        }
    }
    let after = allocations();
    assert_eq!(after - before, 0, "step allocated {} times", after - before);
    // Keep the decisions observable so the loop cannot be optimised away.
    assert!(chosen <= 1000);
}
