//! Accuracy of the Fuzzy Position Grid on MRCLAM dataset 7, robots 1–5:
//! prints a markdown table (ATE against Vicon, time to first fix, kidnap
//! recovery).
//!
//! Data: `$LPLACE_DATA/mrclam-dataset7` or `../shared/data/mrclam-dataset7`
//! relative to the crate root. Optional argument: a RON grid configuration; with
//! `--diagnose DIR` it also writes, per robot, `DIR/rN.csv`: one line per frame of the plain
//! run with the quantities `docs/compare.md`'s diagnosis is about (error, along- and
//! cross-track error, heading error, reliability, the areas of the top region and of the region
//! the centre of gravity is taken over, whether the truth lies in that region, the truth cell's
//! possibility over the maximum, the time since the last fed reading, and the range and bearing
//! error of the frame's first fed reading against the truth).
//!
//! `cargo run --release --example mrclam_grid [config/grid-mrclam.ron] [--diagnose DIR]`

#[path = "support/mrclam.rs"]
mod support;

use lplace::core::angle::wrap_pi_f32 as wrap_pi;
use lplace::core::Odometry;
use lplace::grid::place::survey_landmarks;
use lplace::grid::{GridConfig, GridError, LandmarkTable, Observation};
use lplace::io::mrclam_dir;
use lplace::localize::grid::{run, GridLocalizer};
use lplace::localize::{
    Drive, Kidnap, Localizer, MetricFrame, PoseEstimate, Recovery, RunOptions, RunReport,
};
use std::io::Write;
use std::path::{Path, PathBuf};

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

/// The grid, recording which readings the driver fed it in the current frame.
struct Spy {
    grid: GridLocalizer,
    fed: Vec<Observation>,
}

impl Localizer for Spy {
    type Error = GridError;
    fn predict(&mut self, odometry: &Odometry, dt: f64) -> Result<(), GridError> {
        self.fed.clear();
        self.grid.predict(odometry, dt)
    }
    fn observe(&mut self, t: &LandmarkTable, o: &Observation) -> Result<(), GridError> {
        self.grid.observe(t, o)?;
        self.fed.push(*o);
        Ok(())
    }
    fn estimate(&mut self) -> PoseEstimate {
        self.grid.estimate()
    }
    fn fix_reliability(&self) -> f32 {
        self.grid.fix_reliability()
    }
    fn reobserve_interval(&self) -> f64 {
        self.grid.reobserve_interval()
    }
}

/// Writes the per-frame diagnosis of one robot's plain run (see the module docs).
fn diagnose(
    table: &LandmarkTable,
    cfg: &GridConfig,
    frames: &[MetricFrame],
    out: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut spy = Spy {
        grid: GridLocalizer::new(table, cfg)?,
        fed: Vec::new(),
    };
    let mut drive = Drive::new(table, RunOptions::default());
    let mut w = std::io::BufWriter::new(std::fs::File::create(out)?);
    writeln!(w, "t,error,along,cross,heading_error,reliability,top_area,cog_area,truth_in_cog,truth_h,since_reading,fed,range_error,bearing_error")?;
    let mut last_fed = f64::NEG_INFINITY;
    for f in frames {
        let e = drive.step(&mut spy, f);
        if !spy.fed.is_empty() {
            last_fed = f.t;
        }
        let (Some(tr), Some(err)) = (f.truth, e.error) else {
            continue;
        };
        let g = spy.grid.grid();
        let h = g.possibilities();
        let h_max = h.iter().copied().fold(0.0f32, f32::max);
        let (cut, top) = (cfg.cog_cut * h_max, cfg.top_cut * h_max);
        let cell_area = (g.cell_size() * g.cell_size()) as f64;
        let truth_cell = g.cell_of(tr.x as f32, tr.y as f32);
        let (mut top_area, mut cog_area) = (0.0, 0.0);
        for &v in h {
            top_area += if v >= top { cell_area } else { 0.0 };
            cog_area += if v >= cut { cell_area } else { 0.0 };
        }
        let truth_h = truth_cell.map_or(f32::NAN, |(c, r)| g.possibility(c, r) / h_max);
        let in_cog = truth_cell.is_some_and(|(c, r)| g.possibility(c, r) >= cut);
        let (dx, dy) = (e.pose.x - tr.x, e.pose.y - tr.y);
        let (s, c) = tr.theta.sin_cos();
        let (mut range_error, mut bearing_error) = (f64::NAN, f64::NAN);
        if let Some(o) = spy.fed.first() {
            if let Some(m) = table.get(o.landmark) {
                let (lx, ly) = (m.x as f64 - tr.x, m.y as f64 - tr.y);
                if let Some(r) = o.range {
                    range_error = r as f64 - lx.hypot(ly);
                }
                if let Some(b) = o.bearing {
                    bearing_error = wrap_pi((ly.atan2(lx) - tr.theta - b as f64) as f32) as f64;
                }
            }
        }
        writeln!(
            w,
            "{:.3},{:.4},{:.4},{:.4},{:.4},{:.3},{:.3},{:.3},{},{:.4},{:.2},{},{:.4},{:.4}",
            f.t,
            err,
            c * dx + s * dy,
            -s * dx + c * dy,
            wrap_pi((e.pose.theta - tr.theta) as f32),
            e.reliability,
            top_area,
            cog_area,
            in_cog as u8,
            truth_h,
            f.t - last_fed,
            spy.fed.len(),
            range_error,
            bearing_error
        )?;
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let Some(dir) = support::dataset7() else {
        return Ok(());
    };
    let mut args = std::env::args().skip(1);
    let (mut cfg_path, mut diag_dir) = (None, None);
    while let Some(a) = args.next() {
        if a == "--diagnose" {
            diag_dir = Some(PathBuf::from(
                args.next().ok_or("--diagnose needs a directory")?,
            ));
        } else {
            cfg_path = Some(a);
        }
    }
    let cfg = match cfg_path {
        Some(p) => GridConfig::from_ron(&std::fs::read_to_string(p)?)?,
        None => GridConfig::default(),
    };
    if let Some(d) = &diag_dir {
        std::fs::create_dir_all(d)?;
    }
    println!("| robot | frames | misread | first fix [s] | ATE RMSE [m] | median [m] | max [m] | heading RMSE [rad] | ATE all [m] | kidnap recovery [s] | ms/frame |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for robot in 1..=5 {
        let (table, frames, misread) = load(&dir, robot)?;
        if let Some(d) = &diag_dir {
            diagnose(&table, &cfg, &frames, &d.join(format!("r{robot}.csv")))?;
        }
        let n = frames.len();
        let t_mid = frames[n / 2].t;
        let start = std::time::Instant::now();
        let plain = run(&table, &cfg, frames.iter().cloned(), &RunOptions::default())?;
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
