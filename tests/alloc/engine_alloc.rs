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

/// The same with regions, set heads, two evidence groups fused by product, and a known region:
/// `step_within` allocates nothing either (every buffer is sized at load time).
#[test]
fn step_within_groups_and_regions_allocates_nothing() {
    use lplace::engine::OFFICE_MAP;
    use lplace::syntax::diagnostic::SourceFile;
    let rules = lplace::engine::OFFICE_RULES.replace(
        "|- at_place(P_i) -> in_room(R_i);",
        "region Doors = kind doorway;
         group walls { |- (walls(t) -> in_region(Doors), 0.5); }
         group rooms { |- at_place(P_i) -> in_room(R_i); |- (walls(t) -> !in_room(R1), 0.2); }",
    );
    let rules = rules.replace("margin = 0.1;", "margin = 0.1; fusion = product;");
    let mut engine = Engine::load(
        &SourceFile::new("office.map", OFFICE_MAP),
        &SourceFile::new("office-groups.lpl", rules),
    )
    .unwrap_or_else(|e| panic!("{e}: {:?}", e.diagnostics));
    assert_eq!(engine.compiled().groups, 3);
    let known = engine.query_set("R0 (+) Doors").expect("a set");
    let mut frames: Vec<_> = (0..8).map(|_| engine.new_frame()).collect();
    for (i, f) in frames.iter_mut().enumerate() {
        for (j, d) in f.degree.iter_mut().enumerate() {
            *d = ((i * 29 + j * 11) % 100) as f64 / 100.0;
        }
        for (j, v) in f.value.iter_mut().enumerate() {
            *v = ((i * 13 + j * 7) % 360) as f64;
        }
    }
    let before = allocations();
    let mut chosen = 0usize;
    for k in 0..1000 {
        let within = (k % 2 == 0).then_some(&known);
        if engine
            .step_within(&frames[k % frames.len()], within)
            .place()
            .is_some()
        {
            chosen += 1;
        }
    }
    let after = allocations();
    assert_eq!(
        after - before,
        0,
        "step_within allocated {} times",
        after - before
    );
    assert!(chosen <= 1000);
}
