//! Paper 002's experiment on real MRCLAM dataset 7 data (skipped when the data set is absent):
//! the first 200 s, every robot in turn the object. Checks that events happen and every error
//! is finite, and that the bundled configuration parses.

use crate::support::mrclam_dir;
use lplace::coop::experiment::{run, Options, RobotTrack};
use lplace::coop::CoopConfig;
use lplace::grid::place::survey_landmarks;
use lplace::grid::GridConfig;
use std::path::PathBuf;

fn config(name: &str) -> String {
    std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("config")
            .join(name),
    )
    .unwrap()
}

#[test]
fn bundled_configuration_is_the_default() {
    assert_eq!(
        CoopConfig::from_ron(&config("coop-mrclam.ron")).unwrap(),
        CoopConfig::default()
    );
    assert!(CoopConfig::from_ron("(window: -1.0)").is_err());
    assert!(CoopConfig::from_ron("(cog_cut: 2.0)").is_err());
    assert!(CoopConfig::from_ron("(min_observers: 0)").is_err());
    assert!(CoopConfig::from_ron("(range: 3)").is_err());
}

#[test]
fn mrclam_fusion_gives_finite_errors() {
    let Some(dir) = mrclam_dir() else {
        return;
    };
    let data = lplace::io::mrclam_dir::load(&dir, &[1, 2, 3, 4, 5]).unwrap();
    assert!(data.skipped.is_empty(), "{:?}", data.skipped);
    let table = survey_landmarks(data.survey().unwrap()).unwrap();
    let logs: Vec<RobotTrack> = data
        .robots
        .iter()
        .map(|l| RobotTrack {
            robot: l.robot,
            frames: &l.frames,
            truth: &l.truth,
        })
        .collect();
    let grid = GridConfig::from_ron(&config("grid-mrclam.ron")).unwrap();
    let opts = Options {
        objects: Vec::new(),
        until: Some(200.0),
    };
    let r = run(&table, &grid, &CoopConfig::default(), &logs, &opts).unwrap();
    assert_eq!(r.per_object.len(), 5);
    assert!(r.overall.events > 0, "no event in 200 s");
    assert_eq!(
        r.overall.events,
        r.per_object.iter().map(|s| s.events).sum::<usize>()
    );
    for e in &r.events {
        assert!(e.observers.len() >= 2 && e.observers.windows(2).all(|w| w[0] < w[1]));
        assert!(!e.observers.contains(&e.object));
        for v in [e.fuzzy, e.avg, e.wavg].iter().chain(&e.object_errors) {
            assert!(v.is_finite() && *v >= 0.0, "{e:?}");
        }
    }
    // The lost-observer row counts exactly the events with an observer beyond the threshold
    // (brute force over the event list).
    let lost = CoopConfig::default().lost_self_error;
    let expect = r
        .events
        .iter()
        .filter(|e| e.self_errors.iter().any(|&x| x > lost))
        .count();
    assert_eq!(r.with_lost_observer.events, expect);
    let fuzzy = r.overall.fuzzy.unwrap();
    // Robots 1–5 localize to a few decimetres; a fused error of metres would mean a frame or
    // sign mistake in the sup formula.
    assert!(fuzzy.mean < 1.0, "{fuzzy:?}");
    // Only one restricted object: only its events.
    let one = run(
        &table,
        &grid,
        &CoopConfig::default(),
        &logs,
        &Options {
            objects: vec![4],
            until: Some(200.0),
        },
    )
    .unwrap();
    assert_eq!(one.per_object.len(), 1);
    assert!(one.events.iter().all(|e| e.object == 4));
    assert_eq!(one.overall.events, r.per_object[3].events);
}
