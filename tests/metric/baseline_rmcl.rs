//! Fuzzy R-MCL (paper 001): the fallback path, refinement when samples qualify, determinism,
//! convergence on a simulated run, and hostile input.

use super::baseline_sim;

use baseline_sim::{table, BOUNDS};
use lplace::baseline::{BaselineError, FuzzyRmcl, RmclConfig};
use lplace::core::Odometry;
use lplace::grid::{GridConfig, Observation};
use lplace::localize::grid::GridLocalizer;
use lplace::localize::{drive, Localizer, RunOptions};
use proptest::prelude::*;

fn grid_cfg() -> GridConfig {
    GridConfig {
        bounds: Some(BOUNDS),
        ..GridConfig::default()
    }
}

/// Readings of all four landmarks from the pose (x, y, θ), noise-free.
fn readings(x: f32, y: f32, theta: f32) -> Vec<Observation> {
    table()
        .landmarks()
        .iter()
        .map(|m| {
            let (dx, dy) = (m.x - x, m.y - y);
            Observation {
                landmark: m.id,
                range: Some(dx.hypot(dy)),
                bearing: Some(lplace::core::angle::wrap_pi_f32(dy.atan2(dx) - theta)),
            }
        })
        .collect()
}

#[test]
fn impossible_readings_fall_back_to_the_grid() {
    let t = table();
    let mut rmcl = FuzzyRmcl::new(&t, &RmclConfig::default(), &grid_cfg(), BOUNDS, 1).unwrap();
    let mut grid = GridLocalizer::new(&t, &grid_cfg()).unwrap();
    // Localize both at (2, 3) facing +x.
    for _ in 0..3 {
        for o in readings(2.0, 3.0, 0.0) {
            rmcl.observe(&t, &o).unwrap();
            grid.observe(&t, &o).unwrap();
        }
        rmcl.estimate();
        grid.estimate();
    }
    let before = rmcl.fallbacks();
    // A 40 m range: no cell of an 8 × 8 m world is within 0.3 m of it, so no cell is chosen
    // and no sample can be drawn, let alone qualify.
    let o = Observation {
        landmark: 1,
        range: Some(40.0),
        bearing: Some(0.0),
    };
    rmcl.observe(&t, &o).unwrap();
    grid.observe(&t, &o).unwrap();
    let (e, g) = (rmcl.estimate(), grid.estimate());
    assert_eq!(rmcl.fallbacks(), before + 1);
    assert_eq!(e, g);
}

#[test]
fn a_frame_without_readings_is_the_grid_and_no_fallback() {
    let t = table();
    let mut rmcl = FuzzyRmcl::new(&t, &RmclConfig::default(), &grid_cfg(), BOUNDS, 1).unwrap();
    let mut grid = GridLocalizer::new(&t, &grid_cfg()).unwrap();
    let (m, dt) = (
        Odometry {
            forward: 0.1,
            left: 0.0,
            turn: 0.0,
        },
        0.2,
    );
    rmcl.predict(&m, dt).unwrap();
    grid.predict(&m, dt).unwrap();
    assert_eq!(rmcl.estimate(), grid.estimate());
    assert_eq!((rmcl.fallbacks(), rmcl.sampled()), (0, 0));
}

#[test]
fn qualifying_samples_refine_the_position() {
    let t = table();
    let mut rmcl = FuzzyRmcl::new(&t, &RmclConfig::default(), &grid_cfg(), BOUNDS, 1).unwrap();
    let (x, y) = (2.03f32, 3.07f32); // off the cell centres of the 10 cm grid
    let mut e = rmcl.estimate();
    for _ in 0..4 {
        for o in readings(x, y, 0.3) {
            rmcl.observe(&t, &o).unwrap();
        }
        e = rmcl.estimate();
    }
    assert!(rmcl.sampled() > 0, "no frame was sampled");
    // Exact readings: samples within μ₂'s 10 cm core are all best, and they surround the truth.
    let err = (e.pose.x - x as f64).hypot(e.pose.y - y as f64);
    assert!(err < 0.1, "error {err:.3} m");
}

#[test]
fn samples_are_carried_by_odometry_until_a_fallback() {
    let t = table();
    let mut rmcl = FuzzyRmcl::new(&t, &RmclConfig::default(), &grid_cfg(), BOUNDS, 1).unwrap();
    let mut grid = GridLocalizer::new(&t, &grid_cfg()).unwrap();
    let theta = 0.3f32;
    let mut before = rmcl.estimate();
    for _ in 0..4 {
        for o in readings(2.03, 3.07, theta) {
            rmcl.observe(&t, &o).unwrap();
            grid.observe(&t, &o).unwrap();
        }
        before = rmcl.estimate();
        grid.estimate();
    }
    assert!(rmcl.sampled() > 0);
    // 0.2 m ahead: each sample moves along its own heading, the centre of its cell's heading
    // set, which the exact bearings put within the bearing core (±0.03 rad) of 0.3 rad; so the
    // mean moves by 0.2 m along 0.3 rad, to within 0.2 · 0.03 m plus rounding.
    let (m, dt) = (
        Odometry {
            forward: 0.2,
            left: 0.0,
            turn: 0.0,
        },
        1.0,
    );
    rmcl.predict(&m, dt).unwrap();
    grid.predict(&m, dt).unwrap();
    let after = rmcl.estimate();
    assert_eq!(rmcl.carried(), 1);
    let (dx, dy) = (after.pose.x - before.pose.x, after.pose.y - before.pose.y);
    let (ex, ey) = (0.2 * (theta as f64).cos(), 0.2 * (theta as f64).sin());
    assert!((dx - ex).hypot(dy - ey) < 0.01, "moved ({dx:.4}, {dy:.4})");
    // A fallback drops the carried samples: the next frame without readings is the grid's.
    let o = Observation {
        landmark: 1,
        range: Some(40.0),
        bearing: Some(0.0),
    };
    rmcl.observe(&t, &o).unwrap();
    grid.observe(&t, &o).unwrap();
    rmcl.estimate();
    grid.estimate();
    rmcl.predict(&m, dt).unwrap();
    grid.predict(&m, dt).unwrap();
    assert_eq!(rmcl.estimate(), grid.estimate());
    assert_eq!(rmcl.carried(), 1);
}

#[test]
fn converges_and_is_deterministic_on_a_simulated_run() {
    let frames = baseline_sim::run(300, 11);
    let go = |seed| {
        let mut r =
            FuzzyRmcl::new(&table(), &RmclConfig::default(), &grid_cfg(), BOUNDS, seed).unwrap();
        let rep = drive(&mut r, &table(), frames.clone(), &RunOptions::default());
        (rep, r.fallbacks(), r.sampled())
    };
    let (a, fa, sa) = go(3);
    let (b, fb, sb) = go(3);
    assert_eq!(a.frames, b.frames);
    assert_eq!((fa, sa), (fb, sb));
    let tail = baseline_sim::tail_error(&a.frames, 50);
    // The grid's range core (10 cm + 5 %) and the samples' μ₂ core (10 cm) bound the error
    // when the readings' σ is 5 cm; 0.25 m leaves room for the 10 cm cells and odometry.
    assert!(tail < 0.25, "mean error over the last 10 s: {tail:.3} m");
    assert!(sa > 0);
    let (c, _, _) = go(4);
    assert_ne!(
        a.frames, c.frames,
        "a different seed draws different samples"
    );
}

#[test]
fn bad_configurations_are_rejected() {
    let t = table();
    for cfg in [
        RmclConfig {
            top_cut: 0.0,
            ..RmclConfig::default()
        },
        RmclConfig {
            max_cells: 0,
            ..RmclConfig::default()
        },
        RmclConfig {
            samples_per_cell: 0,
            ..RmclConfig::default()
        },
        RmclConfig {
            distance_core: f32::NAN,
            ..RmclConfig::default()
        },
        RmclConfig {
            min_membership: 1.5,
            ..RmclConfig::default()
        },
    ] {
        assert!(matches!(
            FuzzyRmcl::new(&t, &cfg, &grid_cfg(), BOUNDS, 1),
            Err(BaselineError::BadConfig { .. })
        ));
    }
    let bad_grid = GridConfig {
        cell_size: -1.0,
        ..GridConfig::default()
    };
    assert!(matches!(
        FuzzyRmcl::new(&t, &RmclConfig::default(), &bad_grid, BOUNDS, 1),
        Err(BaselineError::Grid(_))
    ));
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/config/rmcl.ron")).unwrap();
    RmclConfig::from_ron(&text).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn hostile_input_is_rejected_and_changes_nothing(
        range in proptest::num::f32::ANY,
        bearing in proptest::num::f32::ANY,
        forward in proptest::num::f32::ANY,
        dt in proptest::num::f32::ANY,
    ) {
        let t = table();
        let gc = GridConfig { cell_size: 0.25, ..grid_cfg() };
        let mut r = FuzzyRmcl::new(&t, &RmclConfig::default(), &gc, BOUNDS, 1).unwrap();
        for o in readings(2.0, 3.0, 0.0) {
            r.observe(&t, &o).unwrap();
        }
        r.estimate();
        let plane = r.grid().grid().possibilities().to_vec();
        let obs = Observation { landmark: 2, range: Some(range), bearing: Some(bearing) };
        let bad_obs = !(range.is_finite() && range >= 0.0 && bearing.is_finite());
        prop_assert_eq!(r.observe(&t, &obs).is_err(), bad_obs);
        let m = Odometry { forward: forward as f64, left: 0.0, turn: 0.0 };
        let bad_m = !(forward.is_finite() && dt.is_finite() && dt >= 0.0);
        prop_assert_eq!(r.predict(&m, dt as f64).is_err(), bad_m);
        if bad_obs && bad_m {
            prop_assert_eq!(plane, r.grid().grid().possibilities().to_vec());
        }
        let e = r.estimate();
        prop_assert!((0.0..=1.0).contains(&e.reliability));
    }
}
