//! Accuracy of the Fuzzy Position Grid on MRCLAM dataset 7, robots 1–5:
//! prints a markdown table (ATE against Vicon, time to first fix, kidnap
//! recovery).
//!
//! Data: `$LPLACE_DATA/mrclam-dataset7` or `../shared/data/mrclam-dataset7`
//! relative to the crate root. Optional argument: a RON grid configuration.
//!
//! `cargo run --release --example mrclam_grid [config/grid-mrclam.ron]`

use lplace::grid::place::survey_landmarks;
use lplace::grid::run::{run, Kidnap, Recovery, RunOptions, RunReport};
use lplace::grid::{GridConfig, LandmarkTable};
use lplace::io::mrclam::MetricFrame;
use lplace::io::mrclam_dir;
use std::path::PathBuf;

fn data_dir() -> PathBuf {
    match std::env::var_os("LPLACE_DATA") {
        Some(d) => PathBuf::from(d).join("mrclam-dataset7"),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/mrclam-dataset7"),
    }
}

fn load(
    dir: &std::path::Path,
    robot: u32,
) -> Result<(LandmarkTable, Vec<MetricFrame>, usize), Box<dyn std::error::Error>> {
    let data = mrclam_dir::load(dir, &[robot])?;
    for s in &data.skipped {
        eprintln!("{}: {}", s.path.display(), s.error);
    }
    let table = survey_landmarks(data.survey()?)?;
    let log = data.robots.into_iter().next().ok_or("no robot")?;
    Ok((table, log.frames, log.misread))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = data_dir();
    if !dir.join("Barcodes.dat").exists() {
        println!(
            "MRCLAM dataset 7 not found at {} — set LPLACE_DATA; skipping.",
            dir.display()
        );
        return Ok(());
    }
    let cfg = match std::env::args().nth(1) {
        Some(p) => GridConfig::from_ron(&std::fs::read_to_string(p)?)?,
        None => GridConfig::default(),
    };
    println!("| robot | frames | misread | first fix [s] | ATE RMSE [m] | median [m] | max [m] | heading RMSE [rad] | ATE all [m] | kidnap recovery [s] | ms/frame |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for robot in 1..=5 {
        let (table, frames, misread) = load(&dir, robot)?;
        let n = frames.len();
        let t_mid = frames[n / 2].t;
        let start = std::time::Instant::now();
        let plain = run(&table, &cfg, frames.iter().cloned(), &RunOptions::default())?;
        let ms = start.elapsed().as_secs_f64() * 1e3 / n as f64;
        let kid = RunOptions {
            kidnap: Some(Kidnap {
                time: t_mid,
                forward: 0.0,
                lateral: 2.0,
                turn: 1.5,
            }),
            ..RunOptions::default()
        };
        let kidnapped: RunReport = run(&table, &cfg, frames, &kid)?;
        let f = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{v:.3}"));
        let ate = plain.ate;
        let rec = match kidnapped.recovery {
            Some(Recovery::Recovered { after }) => format!("{after:.1}"),
            _ => "not recovered".into(),
        };
        println!(
            "| {robot} | {n} | {misread} | {} | {} | {} | {} | {} | {} | {rec} | {ms:.2} |",
            f(plain.first_fix.map(|x| x.after)),
            f(ate.map(|a| a.rmse)),
            f(ate.map(|a| a.median)),
            f(ate.map(|a| a.max)),
            f(plain.heading_rmse),
            f(plain.ate_all.map(|a| a.rmse)),
        );
    }
    Ok(())
}
