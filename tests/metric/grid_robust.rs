//! The grid's ATE on MRCLAM robot 1 (the tuning robot) under changes that should not matter:
//! every landmark moved by up to ±1 mm (ten seeded draws), and each configuration value
//! changed by ±1 %, one at a time (`localize::robust`). Skipped when the data set is absent.
//! `cargo run --release --example mrclam_robustness` gives the same figures for robots 1–5.

use crate::support::mrclam_dir;
use lplace::grid::place::survey_landmarks;
use lplace::grid::{GridConfig, LandmarkTable};
use lplace::localize::grid::run;
use lplace::localize::robust::{jitter_landmarks, nudged_configs};
use lplace::localize::{MetricFrame, RunOptions};

/// The default MRCLAM configuration.
const FILE: &str = include_str!("../../config/grid-mrclam.ron");

fn ate(table: &LandmarkTable, cfg: &GridConfig, frames: &[MetricFrame]) -> f64 {
    let rep = run(table, cfg, frames.iter().cloned(), &RunOptions::default()).unwrap();
    rep.ate.expect("a fix and truth").rmse
}

/// Asserts robot 1's spreads under the configuration `ron` on `lattices` lattices: at most
/// `landmarks` for the landmark draws and `config` for the ±1 % changes (skipped without data).
fn assert_spreads_at_most(ron: &str, lattices: u32, landmarks: f64, config: f64) {
    let Some((l, c, worst)) = robot1_spreads(ron, lattices) else {
        return;
    };
    assert!(l <= landmarks, "landmarks: {l}");
    assert!(c <= config, "configuration: {c} ({worst})");
}

/// Robot 1's largest relative ATE change over the ten landmark draws and over the ±1 %
/// configuration changes (with the value that caused it), the configuration `ron` on `lattices`
/// lattices, or `None` without the data.
fn robot1_spreads(ron: &str, lattices: u32) -> Option<(f64, f64, String)> {
    let dir = mrclam_dir()?;
    let data = lplace::io::mrclam_dir::load(&dir, &[1]).unwrap();
    let table = survey_landmarks(data.survey().unwrap()).unwrap();
    let frames = data.robots.into_iter().next().unwrap().frames;
    let cfg = GridConfig {
        lattices,
        ..GridConfig::from_ron(ron).unwrap()
    };
    let base = ate(&table, &cfg, &frames);
    let change = |a: f64| (a - base).abs() / base;
    let landmarks = (1..=10)
        .map(|seed| {
            change(ate(
                &jitter_landmarks(&table, 0.001, seed).unwrap(),
                &cfg,
                &frames,
            ))
        })
        .fold(0.0, f64::max);
    let mut config = (0.0, String::new());
    for factor in [1.01, 0.99] {
        let nudged = nudged_configs(&cfg, factor);
        // Every tuned number of the file is among them (a silently empty list would pass).
        assert!(nudged.len() >= 20, "{}", nudged.len());
        for (name, c) in nudged {
            let d = change(ate(&table, &c, &frames));
            if d > config.0 {
                config = (d, format!("{name} ×{factor}"));
            }
        }
    }
    eprintln!(
        "robot 1, {lattices} lattice(s): ATE {base:.3} m; landmarks ±1 mm: up to {:.1} %; config ±1 %: up to {:.1} % ({})",
        100.0 * landmarks,
        100.0 * config.0,
        config.1
    );
    Some((landmarks, config.0, config.1))
}

/// Locks today's spread, measured 2.1 % (landmarks) and 6.0 % (configuration, its values now
/// including the odometry factors) with config/grid-mrclam.ron, each with half a point of
/// margin: 2.5 % (issue 20's goal is 3 %) and 6.5 % (the file before,
/// config/grid-mrclam-hard.ron, gives 13.8 % and 8.3 %), so the test fails if the grid falls back
/// towards that fragility.
#[test]
fn mrclam_robot1_ate_is_no_more_fragile_than_measured() {
    assert_spreads_at_most(FILE, 1, 0.025, 0.065);
}

/// Issue 20's robustness goal for the configuration: ≤ 3 % (the landmark half is met and
/// locked above). Not met (6.0 % on robot 1, `flank_per_metre` ×1.01); run with `--ignored`
/// to measure.
#[test]
#[ignore = "issue 20's 3 % goal for the configuration is not met yet (robot 1: 6.0 %)"]
fn mrclam_robot1_ate_moves_at_most_3_percent() {
    assert_spreads_at_most(FILE, 1, 0.03, 0.03);
}

/// Issue 20's 3 % goal, both halves, with eight shifted lattices averaged (`lattices: 8`;
/// measured 1.7 % and 2.5 %, `forward_scale` ×1.01). Not the file's setting: eight grids cost
/// eight times one (docs/compare.md, "Averaged shifted lattices").
#[test]
fn mrclam_robot1_ate_on_eight_lattices_moves_at_most_3_percent() {
    assert_spreads_at_most(FILE, 8, 0.03, 0.03);
}

/// config/grid-mrclam-shared.ron (`heading_sets: Shared`): measured 2.6 % (landmarks) and 4.5 %
/// (configuration, `delta_per_second` ×1.01) on robot 1, against 13.0 % and 11.1 % for
/// config/grid-mrclam-accurate.ron, which it differs from by that option only. Locked with
/// issue 20's 3 % for the landmarks and half a point of margin, 5 %, for the configuration.
#[test]
fn mrclam_robot1_ate_with_shared_heading_sets_is_no_more_fragile_than_measured() {
    assert_spreads_at_most(
        include_str!("../../config/grid-mrclam-shared.ron"),
        1,
        0.03,
        0.05,
    );
}

/// config/grid-mrclam-segments.ron (refitted on robot 1's whole run and six segments of it by
/// `scripts/mrclam_fit.py`): measured 1.0 % (landmarks) and 3.4 % (configuration, `cell_size`
/// ×0.99) on robot 1 — the least fragile single-lattice file measured. Locked with issue 20's
/// 3 % for the landmarks and half a point of margin, 3.9 %, for the configuration.
#[test]
fn mrclam_robot1_ate_with_the_segments_fit_is_no_more_fragile_than_measured() {
    assert_spreads_at_most(
        include_str!("../../config/grid-mrclam-segments.ron"),
        1,
        0.03,
        0.039,
    );
}

/// config/grid-mrclam-lukasiewicz.ron (the same fit with the Łukasiewicz dilation): measured
/// 4.0 % (landmarks) and 4.4 % (configuration, `flank_per_second` ×0.99) on robot 1; locked with
/// half a point of margin.
#[test]
fn mrclam_robot1_ate_with_the_lukasiewicz_fit_is_no_more_fragile_than_measured() {
    assert_spreads_at_most(
        include_str!("../../config/grid-mrclam-lukasiewicz.ron"),
        1,
        0.045,
        0.049,
    );
}
