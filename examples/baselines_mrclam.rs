//! The baselines (particle filter with 500 and 2000 particles, Fuzzy R-MCL) and, for reference,
//! the Fuzzy Position Grid on MRCLAM dataset 7: prints a markdown table (ATE against Vicon from
//! the first fix, time to first fix, kidnap recovery, ms per frame), one row per robot and method.
//!
//! Data: `$LPLACE_DATA/mrclam-dataset7` or `../shared/data/mrclam-dataset7` relative to the
//! crate root. Configurations: `config/pf.ron`, `config/rmcl.ron`, `config/grid-mrclam.ron`.
//! Optional arguments: the robots to run (`1`, `1-5`; default 1-5) and the seed of every run
//! (default 1).
//!
//! `cargo run --release --example baselines_mrclam [1-5] [seed]`

#[path = "support/mrclam.rs"]
mod support;

use lplace::baseline::{FuzzyRmcl, ParticleFilter, PfConfig, RmclConfig};
use lplace::grid::place::survey_landmarks;
use lplace::grid::{GridConfig, LandmarkTable};
use lplace::io::mrclam_dir;
use lplace::localize::grid::GridLocalizer;
use lplace::localize::{drive, Kidnap, Localizer, MetricFrame, Recovery, RunOptions, RunReport};
use std::path::{Path, PathBuf};
use std::time::Instant;

type Res<T> = Result<T, Box<dyn std::error::Error>>;

fn load(dir: &Path, robot: u32) -> Res<(LandmarkTable, Vec<MetricFrame>)> {
    let data = mrclam_dir::load(dir, &[robot])?;
    for s in &data.skipped {
        eprintln!("{}: {}", s.path.display(), s.error);
    }
    let table = survey_landmarks(data.survey()?)?;
    let log = data.robots.into_iter().next().ok_or("no robot")?;
    Ok((table, log.frames))
}

fn config(name: &str) -> Res<String> {
    Ok(std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("config")
            .join(name),
    )?)
}

/// Runs a fresh localizer plain and kidnapped; returns both reports, ms per frame (plain) and
/// the kidnapped localizer.
fn both<L: Localizer>(
    make: &dyn Fn() -> Res<L>,
    table: &LandmarkTable,
    frames: &[MetricFrame],
) -> Res<(RunReport, RunReport, f64, L)> {
    let n = frames.len().max(1);
    let t_mid = frames.get(n / 2).map_or(0.0, |f| f.t);
    let mut loc = make()?;
    let start = Instant::now();
    let plain = drive(
        &mut loc,
        table,
        frames.iter().cloned(),
        &RunOptions::default(),
    );
    let ms = start.elapsed().as_secs_f64() * 1e3 / n as f64;
    let kid = RunOptions {
        kidnap: Some(Kidnap {
            time: t_mid,
            by: lplace::core::Odometry {
                forward: 0.0,
                left: 2.0,
                turn: 1.5,
            },
        }),
        ..RunOptions::default()
    };
    let mut loc = make()?;
    let kidnapped = drive(&mut loc, table, frames.iter().cloned(), &kid);
    Ok((plain, kidnapped, ms, loc))
}

fn main() -> Res<()> {
    let Some(dir) = support::dataset7() else {
        return Ok(());
    };
    let robots: Vec<u32> = match std::env::args().nth(1).as_deref() {
        None => (1..=5).collect(),
        Some(s) => match s.split_once('-') {
            Some((a, b)) => (a.parse()?..=b.parse()?).collect(),
            None => vec![s.parse()?],
        },
    };
    let seed: u64 = match std::env::args().nth(2) {
        Some(s) => s.parse()?,
        None => 1,
    };
    let pf = PfConfig::from_ron(&config("pf.ron")?)?;
    let rm = RmclConfig::from_ron(&config("rmcl.ron")?)?;
    let grid = GridConfig::from_ron(&config("grid-mrclam.ron")?)?;
    println!("| robot | method | first fix [s] | ATE RMSE [m] | median [m] | max [m] | ATE all [m] | kidnap recovery [s] | ms/frame | notes |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for robot in robots {
        let (table, frames) = load(&dir, robot)?;
        let bounds = table.bounds(grid.margin).ok_or("no landmarks")?;
        let f = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{v:.3}"));
        let row = |name: &str, p: RunReport, k: RunReport, ms: f64, notes: String| {
            let rec = match k.recovery {
                Some(Recovery::Recovered { after }) => format!("{after:.1}"),
                _ => "not recovered".into(),
            };
            println!(
                "| {robot} | {name} | {} | {} | {} | {} | {} | {rec} | {ms:.2} | {notes} |",
                f(p.first_fix.map(|x| x.after)),
                f(p.ate.map(|a| a.rmse)),
                f(p.ate.map(|a| a.median)),
                f(p.ate.map(|a| a.max)),
                f(p.ate_all.map(|a| a.rmse)),
            );
        };
        for n in [500, 2000] {
            let cfg = PfConfig {
                particles: n,
                ..pf.clone()
            };
            let (p, k, ms, _) = both(
                &|| Ok(ParticleFilter::new(&table, &cfg, bounds, seed)?),
                &table,
                &frames,
            )?;
            row(&format!("PF {n}"), p, k, ms, String::new());
        }
        let (p, k, ms, rmcl) = both(
            &|| Ok(FuzzyRmcl::new(&table, &rm, &grid, bounds, seed)?),
            &table,
            &frames,
        )?;
        let notes = format!(
            "kidnap run: {} fallbacks, {} sampled frames, {} carried frames",
            rmcl.fallbacks(),
            rmcl.sampled(),
            rmcl.carried()
        );
        row("Fuzzy R-MCL", p, k, ms, notes);
        let gcfg = GridConfig {
            bounds: Some(bounds),
            ..grid.clone()
        };
        let (p, k, ms, _) = both(&|| Ok(GridLocalizer::new(&table, &gcfg)?), &table, &frames)?;
        row("grid (reference)", p, k, ms, String::new());
    }
    Ok(())
}
