//! Place-constrained refinement (`grid::place`): the engine chooses the place, the grid gives
//! the pose inside it. Unit cases on small grids, then the office example of paper 003 — its
//! bundled simulator recording and a fresh simulator run — through the engine plus a grid fed
//! by odometry and the structured beacon, scoring how often the refined pose lies in the truth
//! place's extent on decided frames.

use lplace::core::Odometry;
use lplace::engine::Engine;
use lplace::grid::place::{place_regions, Refiner};
use lplace::grid::{FuzzyGrid, GridConfig, GridError, Region, SensorModel};
use lplace::io::record::FrameRecord;
use lplace::sim::{SimConfig, Simulator};

#[test]
fn ignorance_gives_the_middle_of_the_chosen_place() {
    let g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 4.0, 2.0]).unwrap();
    let places = vec![
        Region::Box {
            x_min: 0.0,
            y_min: 0.0,
            x_max: 1.0,
            y_max: 2.0,
        },
        Region::Disc {
            x: 3.0,
            y: 1.0,
            r: 0.5,
        },
    ];
    let mut r = Refiner::new(places, 0.0);
    let p = r.refine(&g, &[1.0, 0.3], 0).unwrap();
    assert!(
        (p.x - 0.5).abs() < 0.06 && (p.y - 1.0).abs() < 0.06,
        "{p:?}"
    );
    assert!(p.from_grid);
    assert_eq!(p.agreement, 1.0);
    assert!(matches!(
        r.refine(&g, &[1.0], 2),
        Err(GridError::BadRegion { index: 2, .. })
    ));
}

#[test]
fn the_pose_follows_the_grid_inside_the_place_and_the_grid_is_not_capped() {
    let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 4.0, 2.0]).unwrap();
    let sharp = SensorModel {
        core_abs: 0.1,
        core_rel: 0.0,
        slope_abs: 0.2,
        slope_rel: 0.0,
        bias: 0.0,
    };
    g.update_position(0.3, 0.4, &sharp, 0.0).unwrap();
    let before = g.possibilities().to_vec();
    let places = vec![Region::Box {
        x_min: 0.0,
        y_min: 0.0,
        x_max: 1.0,
        y_max: 2.0,
    }];
    let mut r = Refiner::new(places, 0.1);
    let p = r.refine(&g, &[0.6], 0).unwrap();
    assert!(
        (p.x - 0.3).abs() < 0.06 && (p.y - 0.4).abs() < 0.06,
        "{p:?}"
    );
    assert_eq!(g.possibilities(), &before[..], "refinement works on a copy");
    // The grid's belief is elsewhere: fall back to the extent's centre, say so.
    let far = vec![Region::Disc {
        x: 3.5,
        y: 1.5,
        r: 0.3,
    }];
    let p = Refiner::new(far, 0.1).refine(&g, &[1.0], 0).unwrap();
    assert!(
        !p.from_grid && p.agreement <= 1e-6 && p.x == 3.5 && p.y == 1.5,
        "{p:?}"
    );
    assert!(matches!(
        g.update_position(f32::NAN, 0.0, &sharp, 0.0),
        Err(GridError::NonFinite { .. })
    ));
}

/// The office beacon B0 (maps/office.map).
const BEACON: (f64, f64) = (5.0, 2.5);

/// Counts of one office run.
#[derive(Debug, Default)]
struct Score {
    frames: usize,
    decided: usize,
    inside: usize,
    grid_inside: usize,
}

/// Runs records through the engine and a grid over the office; on each decided frame with a
/// truth place, refines the pose in the chosen place and checks it against the truth extent.
fn run_office(records: impl IntoIterator<Item = FrameRecord>) -> Score {
    let mut engine = Engine::office().unwrap();
    let map = engine.map().clone();
    let cfg = GridConfig {
        undirected_per_metre: 0.5,
        ..GridConfig::default()
    };
    let mut grid = FuzzyGrid::new(cfg, [0.0, 0.0, 10.0, 4.0]).unwrap();
    let mut refiner = Refiner::new(place_regions(&map), 0.2);
    // The beacon's direction and distance put the robot at a point; its uncertainty grows with
    // the distance (5° of direction noise ≈ 0.09 m per metre).
    let beacon = SensorModel {
        core_abs: 0.15,
        core_rel: 0.05,
        slope_abs: 0.3,
        slope_rel: 0.1,
        bias: 0.1,
    };
    let mut frame = engine.new_frame();
    let mut rejected = Vec::new();
    let mut s = Score::default();
    for rec in records {
        s.frames += 1;
        let o = rec.odometry.unwrap_or_default();
        // The record's degrees converted at this edge; the grid rounds to its single precision.
        let increment = Odometry {
            forward: o.dx,
            left: o.dy,
            turn: o.dtheta.to_radians(),
        };
        grid.predict(&increment, 0.1).unwrap();
        let value = |name: &str| {
            rec.percepts
                .iter()
                .find(|p| p.name == name)
                .and_then(|p| p.value)
        };
        if let (Some(a), Some(l)) = (value("beacon_angle"), value("beacon_distance")) {
            let a = a.to_radians();
            let (x, y) = (BEACON.0 + l * a.cos(), BEACON.1 + l * a.sin());
            grid.update_position(x as f32, y as f32, &beacon, l as f32)
                .unwrap();
        }
        grid.apply_pending();
        rec.fill(engine.percepts(), &mut frame, &mut rejected);
        let Some(chosen) = engine.step(&frame).place() else {
            continue;
        };
        let Some(truth) = rec
            .truth
            .as_ref()
            .and_then(|t| t.place.as_deref())
            .and_then(|n| map.place_index(n))
        else {
            continue;
        };
        s.decided += 1;
        let pi = engine.distribution().possibility.clone();
        let p = refiner.refine(&grid, &pi, chosen).unwrap();
        if map.places()[truth].contains(p.x as f64, p.y as f64) {
            s.inside += 1;
        }
        let e = grid.estimate();
        if map.places()[truth].contains(e.x as f64, e.y as f64) {
            s.grid_inside += 1;
        }
    }
    assert!(rejected.is_empty(), "{rejected:?}");
    s
}

fn report(what: &str, s: &Score) -> f64 {
    let frac = s.inside as f64 / s.decided.max(1) as f64;
    let grid_only = s.grid_inside as f64 / s.decided.max(1) as f64;
    println!(
        "{what}: {} frames, {} decided with a truth place; refined pose inside the truth place on {:.3} (grid alone {:.3})",
        s.frames, s.decided, frac, grid_only
    );
    frac
}

#[test]
fn office_recording_refined_pose_lies_in_the_truth_place() {
    let text = include_str!("../../recordings/office.jsonl");
    let records: Vec<FrameRecord> = text
        .lines()
        .map(|l| FrameRecord::parse(l).unwrap())
        .collect();
    let s = run_office(records);
    let frac = report("office.jsonl", &s);
    assert!(s.decided > 500, "{s:?}");
    assert!(frac >= LOCK_RECORDING, "{frac} < {LOCK_RECORDING}");
}

#[test]
fn office_simulator_refined_pose_lies_in_the_truth_place() {
    let engine = Engine::office().unwrap();
    let mut sim = Simulator::for_engine(
        &engine,
        SimConfig {
            seed: 7,
            steps: 1500,
            ..SimConfig::default()
        },
    );
    let records: Vec<FrameRecord> = (0..1500).map(|_| sim.next_record()).collect();
    let s = run_office(records);
    let frac = report("simulator seed 7", &s);
    assert!(s.decided > 300, "{s:?}");
    assert!(frac >= LOCK_SIMULATOR, "{frac} < {LOCK_SIMULATOR}");
}

/// Measured fractions, locked in slightly below (see docs/grid.md).
const LOCK_RECORDING: f64 = 0.90; // measured 0.930 (grid alone 0.262)
const LOCK_SIMULATOR: f64 = 0.95; // measured 0.984 (grid alone 0.238)
