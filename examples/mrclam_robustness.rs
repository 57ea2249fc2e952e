//! Robustness of the Fuzzy Position Grid's ATE on MRCLAM dataset 7 to its inputs: every
//! landmark moved by up to ±1 mm per coordinate (ten seeded draws, `localize::robust`), and
//! each non-zero configuration value changed by +1 % and by −1 %, one at a time. Prints per
//! robot the ATE RMSE from the first fix, the largest relative change under each perturbation
//! and the value that caused it.
//!
//! `cargo run --release --example mrclam_robustness [CONFIG] [ROBOT…]` (default
//! `config/grid-mrclam.ron`, robots 1–5). Data: `$LPLACE_DATA/mrclam-dataset7` or
//! `../shared/data/mrclam-dataset7` relative to the crate root.

#[path = "support/mrclam.rs"]
mod support;

use lplace::grid::place::survey_landmarks;
use lplace::grid::{GridConfig, LandmarkTable};
use lplace::io::mrclam_dir;
use lplace::localize::grid::run;
use lplace::localize::robust::{jitter_landmarks, nudged_configs};
use lplace::localize::{MetricFrame, RunOptions};

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

fn ate(table: &LandmarkTable, cfg: &GridConfig, frames: &[MetricFrame]) -> Result<f64> {
    let rep = run(table, cfg, frames.iter().cloned(), &RunOptions::default())?;
    Ok(rep.ate.ok_or("no fix")?.rmse)
}

fn main() -> Result<()> {
    let Some(dir) = support::dataset7() else {
        return Ok(());
    };
    let mut args = std::env::args().skip(1);
    let cfg_path = args
        .next()
        .unwrap_or_else(|| "config/grid-mrclam.ron".into());
    let cfg = GridConfig::from_ron(&std::fs::read_to_string(&cfg_path)?)?;
    let mut robots: Vec<u32> = args
        .map(|a| a.parse())
        .collect::<std::result::Result<_, _>>()?;
    if robots.is_empty() {
        robots = (1..=5).collect();
    }
    println!("| robot | ATE RMSE [m] | landmarks ±1 mm: ATE range [m] | max change | config ±1 %: ATE range [m] | max change | worst value |");
    println!("|---|---|---|---|---|---|---|");
    for robot in robots {
        let data = mrclam_dir::load(&dir, &[robot])?;
        let table = survey_landmarks(data.survey()?)?;
        let frames = data.robots.into_iter().next().ok_or("no robot")?.frames;
        let base = ate(&table, &cfg, &frames)?;
        let mut lm = Vec::new();
        for seed in 1..=10 {
            lm.push(ate(&jitter_landmarks(&table, 0.001, seed)?, &cfg, &frames)?);
        }
        let mut worst = (0.0, String::new());
        let mut cf = Vec::new();
        for factor in [1.01, 0.99] {
            for (name, c) in nudged_configs(&cfg, factor) {
                let a = ate(&table, &c, &frames)?;
                let change = (a - base).abs() / base;
                if change > worst.0 {
                    worst = (change, format!("{name} ×{factor}"));
                }
                cf.push(a);
            }
        }
        let span = |v: &[f64]| {
            let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let max = v
                .iter()
                .map(|a| (a - base).abs() / base)
                .fold(0.0, f64::max);
            (lo, hi, max)
        };
        let (l0, l1, lmax) = span(&lm);
        let (c0, c1, cmax) = span(&cf);
        println!(
            "| {robot} | {base:.3} | {l0:.3}–{l1:.3} | {:.1} % | {c0:.3}–{c1:.3} | {:.1} % | {} |",
            100.0 * lmax,
            100.0 * cmax,
            worst.1
        );
    }
    Ok(())
}
