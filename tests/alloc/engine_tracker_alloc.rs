//! `Tracker::step` and `GridTracker::step` allocate nothing (their module docs promise it, and
//! `eval` calls one of them once per frame): a counting global allocator watches hundreds of
//! steps, with evidence of the right and the wrong length, odometry that is large, zero or not
//! finite, headings known, missing or not finite, after the tracker is built.

use super::allocations;
use lplace::core::Odometry;
use lplace::engine::tracker::{Tracker, TrackerConfig};
use lplace::engine::Engine;
use lplace::logic::{DecisionParams, PlaceDistribution};

#[test]
fn step_allocates_nothing() {
    let engine = Engine::office().expect("office loads");
    let n = engine.map().places().len();
    let params = DecisionParams {
        threshold: 0.5,
        margin: 0.1,
    };
    let mut tracker = Tracker::new(engine.map(), params, TrackerConfig::default());
    let evidence: Vec<PlaceDistribution> = (0..n + 2)
        .map(|k| {
            // The last two have the wrong length: missing places read as "no evidence".
            let mut d = PlaceDistribution::new(if k < n { n } else { n / 2 });
            if k < n {
                d.support[k] = 0.9;
                d.possibility.fill(0.3);
                d.possibility[k] = 1.0;
            }
            d
        })
        .collect();
    let steps = [0.3, 0.0, 25.0, f64::NAN, f64::INFINITY, 0.05];
    let before = allocations();
    let mut chosen = 0usize;
    for k in 0..1000 {
        let odometry = Odometry {
            forward: steps[k % steps.len()],
            left: 0.1,
            turn: 0.0,
        };
        // Headings on most frames (displacement gates), none or not finite on some.
        let heading = match k % 5 {
            0 => None,
            1 => Some(f64::NAN),
            _ => Some((k as f64 * 7.0) % 360.0),
        };
        if tracker
            .step(&evidence[(k / 7) % evidence.len()], odometry, heading)
            .place()
            .is_some()
        {
            chosen += 1;
        }
    }
    let after = allocations();
    assert_eq!(after - before, 0, "step allocated {} times", after - before);
    // Some frames decide and some do not: the loop did real work.
    assert!(chosen > 0 && chosen < 1000, "{chosen} decided");
}

#[test]
fn grid_step_allocates_nothing() {
    let engine = Engine::office().expect("office loads");
    let n = engine.map().places().len();
    let params = DecisionParams {
        threshold: 0.5,
        margin: 0.1,
    };
    let cfg = TrackerConfig {
        grid: Some(lplace::engine::grid_tracker::GridTrackConfig::default()),
        ..TrackerConfig::default()
    };
    let mut tracker = lplace::engine::tracker::PlaceTracker::new(engine.map(), params, cfg);
    let mut evidence = PlaceDistribution::new(n);
    evidence.support[2] = 0.9;
    evidence.possibility.fill(0.3);
    evidence.possibility[2] = 1.0;
    let before = allocations();
    let mut chosen = 0usize;
    for k in 0..500 {
        let odometry = Odometry {
            forward: [0.3, 0.0, 25.0, f64::NAN][k % 4],
            left: 0.05,
            turn: 3.0_f64.to_radians(),
        };
        let heading = (k % 3 != 0).then_some(k as f64);
        if tracker.step(&evidence, odometry, heading).place().is_some() {
            chosen += 1;
        }
    }
    let after = allocations();
    assert_eq!(after - before, 0, "step allocated {} times", after - before);
    assert!(chosen > 0, "{chosen} decided");
}
