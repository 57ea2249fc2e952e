//! Accuracy of the Fuzzy Position Grid on MRCLAM dataset 7, robots 1–5:
//! prints a markdown table (ATE against Vicon, time to first fix, kidnap
//! recovery).
//!
//! Data: `$LPLACE_DATA/mrclam-dataset7` or `../shared/data/mrclam-dataset7`
//! relative to the crate root. Optional argument: a RON grid configuration.
//!
//! `cargo run --release --example mrclam_grid [config/grid-mrclam.ron]`

use lplace::grid::run::{run, Kidnap, Recovery, RunOptions, RunReport};
use lplace::grid::{GridConfig, Landmark, LandmarkTable};
use lplace::io::mrclam::{self, MergeOptions, MetricFrame};
use std::fs::File;
use std::io::BufReader;
use std::path::PathBuf;

fn data_dir() -> PathBuf {
    match std::env::var_os("LPLACE_DATA") {
        Some(d) => PathBuf::from(d).join("mrclam-dataset7"),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/mrclam-dataset7"),
    }
}

fn open(dir: &std::path::Path, name: &str) -> Result<BufReader<File>, Box<dyn std::error::Error>> {
    Ok(BufReader::new(File::open(dir.join(name))?))
}

fn load(
    dir: &std::path::Path,
    robot: u32,
) -> Result<(LandmarkTable, Vec<MetricFrame>, usize), Box<dyn std::error::Error>> {
    let codes = mrclam::read_barcodes(open(dir, "Barcodes.dat")?)?;
    let marks = mrclam::read_landmarks(open(dir, "Landmark_Groundtruth.dat")?)?;
    let table = LandmarkTable::new(
        marks
            .iter()
            .map(|m| Landmark {
                id: m.subject,
                x: m.x as f32,
                y: m.y as f32,
            })
            .collect(),
    )?;
    let odo = mrclam::read_odometry(open(dir, &format!("Robot{robot}_Odometry.dat"))?)?;
    let meas =
        mrclam::read_measurements(open(dir, &format!("Robot{robot}_Measurement.dat"))?, &codes)?;
    let truth = mrclam::read_groundtruth(open(dir, &format!("Robot{robot}_Groundtruth.dat"))?)?;
    let frames = mrclam::merge(&odo, &meas.rows, &truth, &MergeOptions::default());
    Ok((table, frames, meas.misread))
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
