//! `lplace fuse --from-dir DIR [--object N]… [--config GRID.ron] [--coop-config COOP.ron]`: paper
//! 002's cooperative object localization replayed on MRCLAM ([`crate::coop::experiment`]): each
//! chosen robot in turn is the object the others see; the table gives, per object robot and
//! overall, the observers' self-localization error, their own object errors, the best of them,
//! the plain and reliability-weighted averages and the fused estimate (mean / median, metres).
//!
//! Malformed data lines are reported on stderr as FILE:LINE and skipped; readings of an object
//! that give no object grid are counted. Either makes the exit code 3.

use std::io::Write;
use std::path::Path;

use super::args::{Format, FuseArgs};
use super::{bad, read_config, CliError, EXIT_OK, EXIT_REJECTED};
use crate::coop::experiment::{self, Options, Report, RobotTrack, Stat, Summary};
use crate::coop::CoopConfig;
use crate::grid::place::survey_landmarks;
use crate::grid::{GridConfig, LandmarkTable};
use crate::io::mrclam_dir::RobotLog;

/// The landmark table and the five robots' logs of an MRCLAM directory; malformed lines are
/// reported as FILE:LINE and counted in `skipped`.
fn load_dataset(
    dir: &Path,
    skipped: &mut usize,
) -> Result<(LandmarkTable, Vec<RobotLog>), CliError> {
    let (data, n) = super::extract::load_mrclam_dir(dir, &[1, 2, 3, 4, 5])?;
    *skipped += n;
    let table = survey_landmarks(data.survey().map_err(bad)?).map_err(bad)?;
    Ok((table, data.robots))
}

/// Runs `fuse`: the table to `out`, problems to stderr.
///
/// # Errors
/// [`CliError::Read`] when a file cannot be read, [`CliError::Diagnostics`] for a bad flag,
/// configuration or data file (printed first), [`CliError::Write`] when the output fails.
pub fn run(args: &FuseArgs, out: &mut impl Write) -> Result<u8, CliError> {
    if let Some(bad_n) = args.object.iter().find(|n| !(1..=5).contains(*n)) {
        return Err(bad(format!("--object {bad_n}: MRCLAM has robots 1 to 5")));
    }
    if let Some(u) = args.until {
        if !(u.is_finite() && u > 0.0) {
            return Err(bad(format!(
                "--until {u}: must be a positive number of seconds"
            )));
        }
    }
    let grid_cfg = match &args.config {
        None => GridConfig::default(),
        Some(p) => read_config(p, GridConfig::from_ron)?,
    };
    let cfg = match &args.coop_config {
        None => CoopConfig::default(),
        Some(p) => read_config(p, CoopConfig::from_ron)?,
    };
    let mut skipped = 0;
    let (table, logs) = load_dataset(&super::data::resolve(&args.from_dir), &mut skipped)?;
    let opts = Options {
        objects: if args.all {
            Vec::new()
        } else {
            args.object.clone()
        },
        until: args.until,
    };
    let tracks: Vec<RobotTrack> = logs
        .iter()
        .map(|l| RobotTrack {
            robot: l.robot,
            frames: &l.frames,
            truth: &l.truth,
        })
        .collect();
    // One call with no step hook: a spinner says the run is alive.
    let spinner = super::progress::spinner("fusing");
    let report = experiment::run(&table, &grid_cfg, &cfg, &tracks, &opts).map_err(bad);
    if let Some(s) = &spinner {
        s.finish_and_clear();
    }
    let report = report?;
    match args.format {
        Format::Json | Format::Jsonl => {
            let mut v = serde_json::to_value(&report).map_err(std::io::Error::from)?;
            if !args.events {
                if let Some(o) = v.as_object_mut() {
                    o.remove("events");
                }
            }
            writeln!(out, "{v}")?;
        }
        Format::Table => print_table(out, &report)?,
        Format::Csv => print_csv(out, &report)?,
    }
    if report.rejected_sightings > 0 {
        eprintln!(
            "fuse: {} reading(s) of an object rejected (non-finite)",
            report.rejected_sightings
        );
    }
    Ok(if skipped > 0 || report.rejected_sightings > 0 {
        EXIT_REJECTED
    } else {
        EXIT_OK
    })
}

fn rows(r: &Report) -> impl Iterator<Item = &Summary> {
    r.per_object.iter().chain(std::iter::once(&r.overall))
}

fn name(s: &Summary) -> String {
    s.object.map_or("all".to_string(), |o| format!("robot {o}"))
}

fn print_table(out: &mut impl Write, r: &Report) -> Result<(), CliError> {
    let st = |s: Option<Stat>| {
        s.map_or("–".to_string(), |s| {
            format!("{:.3} / {:.3}", s.mean, s.median)
        })
    };
    writeln!(
        out,
        "| object | sightings | events | Δ_self | Δ_object | Δ_best | Δ_avg | Δ_wavg | Δ_fuzzy | fuzzy < avg | fuzzy < wavg | bytes sent |"
    )?;
    writeln!(out, "|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    for s in rows(r) {
        writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            name(s),
            s.sightings,
            s.events,
            st(s.self_error),
            st(s.object_error),
            st(s.best),
            st(s.avg),
            st(s.wavg),
            st(s.fuzzy),
            s.fuzzy_beats_avg,
            s.fuzzy_beats_wavg,
            s.mean_code_bytes
                .map_or("–".to_string(), |b| format!("{b:.0} of {}", r.cells)),
        )?;
    }
    let lost = &r.with_lost_observer;
    writeln!(
        out,
        "| with a lost observer | – | {} | {} | {} | {} | {} | {} | {} | {} | {} | – |",
        lost.events,
        st(lost.self_error),
        st(lost.object_error),
        st(lost.best),
        st(lost.avg),
        st(lost.wavg),
        st(lost.fuzzy),
        lost.fuzzy_beats_avg,
        lost.fuzzy_beats_wavg,
    )?;
    writeln!(out)?;
    writeln!(out, "errors in metres, mean / median over events; Δ_self, Δ_object over every observer of every event; lost observer: self error above the configuration's lost_self_error; bytes: mean run-length code of one object grid, of the uncompressed one byte per cell")?;
    writeln!(out)?;
    writeln!(out, "| observer | Δ_self | Δ_object |")?;
    writeln!(out, "|---|---|---|")?;
    for (o, (a, b)) in &r.overall.per_observer {
        writeln!(out, "| robot {o} | {} | {} |", st(*a), st(*b))?;
    }
    Ok(())
}

fn print_csv(out: &mut impl Write, r: &Report) -> Result<(), CliError> {
    let st = |s: Option<Stat>| {
        s.map_or(",".to_string(), |s| {
            format!("{:.4},{:.4}", s.mean, s.median)
        })
    };
    writeln!(out, "object,sightings,events,unscored,self_mean,self_median,object_mean,object_median,best_mean,best_median,avg_mean,avg_median,wavg_mean,wavg_median,fuzzy_mean,fuzzy_median")?;
    for s in rows(r) {
        writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{}",
            s.object.map_or("all".to_string(), |o| o.to_string()),
            s.sightings,
            s.events,
            s.unscored,
            st(s.self_error),
            st(s.object_error),
            st(s.best),
            st(s.avg),
            st(s.wavg),
            st(s.fuzzy)
        )?;
    }
    Ok(())
}
