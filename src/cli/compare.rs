//! `lplace compare STREAM --methods fpg,pf:500,pf:2000,rmcl`: runs several metric localizers
//! over the same frames through the one driver ([`crate::localize::Drive`]), so they are fed,
//! kidnapped and scored alike, and prints one table: ATE RMSE / median / max, time to first fix,
//! kidnap recovery and wall time per step. `--tum-dir` writes each method's trajectory;
//! `--sweep` adds paper 001's noisy- and sparse-data runs ([`crate::localize::perturb`]), every
//! method on the same perturbed frames, and `--svg` plots them ([`crate::report::sweep`]).
//!
//! Input is read exactly as `lplace grid` reads it (a stream, or `--from-dir` MRCLAM files; see
//! `super::grid::load_frames`). Methods are named by [`MethodSpec`]; [`run_method`] is the one
//! place that builds a method from its spec, so adding a method is one variant and one arm.
//!
//! May depend on: `localize`, `grid`, `baseline`, `io`, `report`, and `super::grid` for input.

use std::fmt;
use std::io::Write;
use std::str::FromStr;
use std::time::{Duration, Instant};

use super::args::{CompareArgs, Format, SweepKind};
use super::grid::{input_title, kidnap, load_frames, output_error, write_trajectory, LoadedFrames};
use super::{bad, read_config, CliError, EXIT_OK, EXIT_REJECTED};
use crate::baseline::{FuzzyRmcl, ParticleFilter, PfConfig, RmclConfig};
use crate::core::Pose2;
use crate::grid::{GridConfig, LandmarkTable};
use crate::localize::grid::GridLocalizer;
use crate::localize::perturb::{perturb, Perturbation, KEEP_LEVELS, NOISE_LEVELS};
use crate::localize::{
    common_window_start, AteStats, Drive, Kidnap, Localizer, MetricFrame, Recovery, RunOptions,
    RunReport,
};
use crate::report::sweep::{self, Panel, Series};

/// The bundled grid parameters for MRCLAM (config/grid-mrclam.ron), the default of `--config`.
const GRID_CONFIG: &str = include_str!("../../config/grid-mrclam.ron");

/// One method to run, as written in `--methods`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum MethodSpec {
    /// `fpg`: the Fuzzy Position Grid (paper 000).
    Fpg,
    /// `pf` or `pf:N`: the particle filter (paper 004) with N particles (`pf`: the
    /// configuration's count).
    Pf {
        /// Particle count, overriding the configuration's.
        particles: Option<usize>,
    },
    /// `rmcl`: Fuzzy R-MCL (paper 001).
    Rmcl,
}

/// Largest particle count accepted in `pf:N` (a guard against typos that would exhaust memory).
pub const MAX_PARTICLES: usize = 1_000_000;

/// A `--methods` entry that names no method.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MethodSpecError {
    /// Not a method name.
    #[error("unknown method `{spec}` (methods: fpg, pf, pf:N, rmcl)")]
    Unknown {
        /// What was written.
        spec: String,
    },
    /// `pf:` followed by something that is not a particle count.
    #[error("`{spec}`: the particle count must be a whole number from 1 to {max}")]
    BadCount {
        /// What was written.
        spec: String,
        /// The largest count.
        max: usize,
    },
}

impl FromStr for MethodSpec {
    type Err = MethodSpecError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let spec = s.trim();
        match spec.to_ascii_lowercase().as_str() {
            "fpg" | "grid" => return Ok(MethodSpec::Fpg),
            "pf" => return Ok(MethodSpec::Pf { particles: None }),
            "rmcl" => return Ok(MethodSpec::Rmcl),
            _ => {}
        }
        let Some(count) = spec
            .strip_prefix("pf:")
            .or_else(|| spec.strip_prefix("PF:"))
        else {
            return Err(MethodSpecError::Unknown {
                spec: spec.to_string(),
            });
        };
        match count.parse::<usize>() {
            Ok(n) if (1..=MAX_PARTICLES).contains(&n) => Ok(MethodSpec::Pf { particles: Some(n) }),
            _ => Err(MethodSpecError::BadCount {
                spec: spec.to_string(),
                max: MAX_PARTICLES,
            }),
        }
    }
}

impl fmt::Display for MethodSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MethodSpec::Fpg => write!(f, "fpg"),
            MethodSpec::Pf { particles: None } => write!(f, "pf"),
            MethodSpec::Pf { particles: Some(n) } => write!(f, "pf:{n}"),
            MethodSpec::Rmcl => write!(f, "rmcl"),
        }
    }
}

impl MethodSpec {
    /// The method's TUM file name in `--tum-dir` (`pf:500` → `pf-500.tum`: no `:` in names).
    pub fn file_name(&self) -> String {
        format!("{}.tum", self.to_string().replace(':', "-"))
    }
}

/// The bundled particle filter parameters (config/pf.ron), the default of `--pf-config`.
const PF_CONFIG: &str = include_str!("../../config/pf.ron");
/// The bundled Fuzzy R-MCL parameters (config/rmcl.ron), the default of `--rmcl-config`.
const RMCL_CONFIG: &str = include_str!("../../config/rmcl.ron");

/// Everything the methods are built from.
struct Setup<'a> {
    table: &'a LandmarkTable,
    grid: &'a GridConfig,
    pf: PfConfig,
    rmcl: RmclConfig,
    /// Where the sampling methods start spread: the grid's bounds, so all start alike.
    bounds: [f32; 4],
    seed: u64,
    /// `--start-at-truth`: the first frame's truth pose every method starts from.
    start: Option<Pose2>,
}

/// One method's run.
struct Ran {
    report: RunReport,
    /// Wall time of the stepping alone.
    took: Duration,
    /// R-MCL only: how its estimates were made (why it may match `fpg`).
    rmcl: Option<RmclCounts>,
}

/// How many of R-MCL's estimates came from its samples.
#[derive(Debug, Clone, Copy, serde::Serialize)]
struct RmclCounts {
    /// Frames whose estimate is the mean of the best samples.
    sampled: usize,
    /// Frames with readings whose estimate fell back to the grid's.
    fallbacks: usize,
    /// Frames without readings whose estimate is the mean of the carried samples.
    carried: usize,
}

/// Runs `loc` over `frames` through a fresh [`Drive`]; the duration is the wall time of the
/// stepping alone (building the method and scoring are left out).
fn timed<L: Localizer>(
    loc: &mut L,
    table: &LandmarkTable,
    frames: &[MetricFrame],
    opts: &RunOptions,
) -> Ran {
    let mut d = Drive::new(table, *opts);
    let start = Instant::now();
    for f in frames {
        d.step(loc, f);
    }
    let took = start.elapsed();
    Ran {
        report: d.finish(),
        took,
        rmcl: None,
    }
}

/// Builds the method `spec` afresh (seeded) and runs it: the one factory of methods.
fn run_method(
    spec: MethodSpec,
    s: &Setup<'_>,
    frames: &[MetricFrame],
    opts: &RunOptions,
) -> Result<Ran, CliError> {
    let why = |e: &dyn fmt::Display| bad(format!("{spec}: {e}"));
    Ok(match spec {
        MethodSpec::Fpg => {
            let mut g = GridLocalizer::new(s.table, s.grid).map_err(|e| why(&e))?;
            if let Some(p) = s.start {
                g.start_at(p).map_err(|e| why(&e))?;
            }
            timed(&mut g, s.table, frames, opts)
        }
        MethodSpec::Pf { particles } => {
            let cfg = PfConfig {
                particles: particles.unwrap_or(s.pf.particles),
                ..s.pf.clone()
            };
            let mut pf =
                ParticleFilter::new(s.table, &cfg, s.bounds, s.seed).map_err(|e| why(&e))?;
            if let Some(p) = s.start {
                pf.start_at(p).map_err(|e| why(&e))?;
            }
            timed(&mut pf, s.table, frames, opts)
        }
        MethodSpec::Rmcl => {
            let mut r =
                FuzzyRmcl::new(s.table, &s.rmcl, s.grid, s.bounds, s.seed).map_err(|e| why(&e))?;
            // Run first: the counts are read after the run.
            let ran = timed(&mut r, s.table, frames, opts);
            Ran {
                rmcl: Some(RmclCounts {
                    sampled: r.sampled(),
                    fallbacks: r.fallbacks(),
                    carried: r.carried(),
                }),
                ..ran
            }
        }
    })
}

/// One method's row of the main table.
#[derive(Debug, Clone, serde::Serialize)]
struct MethodRow {
    method: String,
    frames: usize,
    ate: Option<AteStats>,
    ate_all: Option<AteStats>,
    /// ATE over the common window of all the methods run (`localize::common_window_start`).
    ate_common: Option<AteStats>,
    /// Start of that window, seconds after the first frame.
    common_from: Option<f64>,
    heading_rmse: Option<f64>,
    first_fix: Option<f64>,
    /// The first fix on the log's own clock (for `evo_ape --t_start`).
    first_fix_t: Option<f64>,
    kidnap_at: Option<f64>,
    /// Seconds to recover; `None` with `kidnap_at` set means not recovered.
    recovery: Option<f64>,
    wall_s: f64,
    time_per_step_us: f64,
    used: usize,
    thinned: usize,
    /// Readings of subjects not in the map, other robots included.
    unknown: usize,
    /// Of those, the sightings of other robots.
    other_robots: usize,
    rejected_readings: usize,
    /// R-MCL: how its estimates were made.
    rmcl: Option<RmclCounts>,
}

/// One method at one perturbation level.
#[derive(Debug, Clone, serde::Serialize)]
struct SweepPoint {
    method: String,
    sweep: &'static str,
    range_sigma: f64,
    bearing_sigma_deg: f64,
    keep: f64,
    ate: Option<AteStats>,
    ate_all: Option<AteStats>,
    first_fix: Option<f64>,
}

/// Checks `--svg` and `--tum-dir` before any work (issue 16: a typo must not cost the run).
fn check_outputs(args: &CompareArgs) -> Result<(), CliError> {
    use super::output::Output;
    let mut inputs = super::grid::frame_inputs(&args.input);
    inputs.extend(args.config.as_deref().map(|p| ("--config", p)));
    let outputs: Vec<Output<'_>> = (args.svg.as_deref().map(|p| Output::file("--svg", p)))
        .into_iter()
        .chain(
            args.tum_dir
                .as_deref()
                .map(|p| Output::folder("--tum-dir", p)),
        )
        .collect();
    super::output::check(&outputs, &inputs)
}

/// Runs `compare`: tables to `out`, problems to stderr.
///
/// # Errors
/// [`CliError::Read`] when a file cannot be read, [`CliError::Diagnostics`] for a bad map,
/// configuration or flag (printed first), [`CliError::Write`] when an output fails.
pub fn run(args: &CompareArgs, out: &mut impl Write) -> Result<u8, CliError> {
    check_methods(&args.methods)?;
    let grid = match &args.config {
        None => GridConfig::from_ron(GRID_CONFIG).map_err(bad)?,
        Some(p) => read_config(p, GridConfig::from_ron)?,
    };
    grid.validate().map_err(bad)?;
    check_outputs(args)?;
    let input = load_frames(&args.input)?;
    let frames = &input.frames;
    let setup = setup(args, &input.table, &grid, frames)?;
    let kidnapped = kidnap(&args.kidnap, frames)?;
    if let Some(dir) = &args.tum_dir {
        std::fs::create_dir_all(dir).map_err(|e| output_error(dir, e))?;
    }
    let rows = method_rows(args, &setup, &input, kidnapped)?;
    let points = match args.sweep {
        None => Vec::new(),
        Some(kind) => run_sweeps(kind, args, &setup, frames)?,
    };
    if let Some(path) = &args.svg {
        let picture = plot(&args.methods, &points, &input_title(&args.input));
        super::output::write_atomic(path, |w| w.write_all(picture.as_bytes()))?;
    }
    match args.format {
        Format::Table => print_table(out, &rows, &points)?,
        Format::Json | Format::Jsonl => {
            let v = serde_json::json!({
                "methods": rows,
                "sweep": points,
                "rejected_lines": input.rejected,
            });
            writeln!(out, "{v}")?;
        }
        Format::Csv => print_csv(out, &rows, &points)?,
    }
    let unmatched = super::grid::warn_if_unmatched(&input);
    Ok(if input.rejected > 0 || unmatched {
        EXIT_REJECTED
    } else {
        EXIT_OK
    })
}

/// A method given twice would write the same `--tum-dir` file twice; none at all is a mistake.
fn check_methods(methods: &[MethodSpec]) -> Result<(), CliError> {
    let mut seen = std::collections::BTreeSet::new();
    for m in methods {
        if !seen.insert(m.file_name()) {
            return Err(bad(format!("--methods: `{m}` is given twice")));
        }
    }
    if methods.is_empty() {
        return Err(bad("--methods: no method given"));
    }
    Ok(())
}

/// The methods' common setup: the baselines' configurations (bundled unless given) and the
/// bounds every method starts spread over.
fn setup<'a>(
    args: &CompareArgs,
    table: &'a LandmarkTable,
    grid: &'a GridConfig,
    frames: &[MetricFrame],
) -> Result<Setup<'a>, CliError> {
    let start = if args.start_at_truth {
        if args.methods.contains(&MethodSpec::Rmcl) {
            return Err(bad(
                "--start-at-truth: rmcl cannot start from a pose (fpg and pf can)",
            ));
        }
        let first = frames.first().and_then(|f| f.truth);
        Some(first.ok_or_else(|| bad("--start-at-truth: the first frame has no truth pose"))?)
    } else {
        None
    };
    let bounds = match grid.bounds {
        Some(b) => b,
        None => table
            .bounds(grid.margin)
            .ok_or_else(|| bad("the map has no landmark with an id"))?,
    };
    Ok(Setup {
        table,
        grid,
        pf: match &args.pf_config {
            None => PfConfig::from_ron(PF_CONFIG).map_err(bad)?,
            Some(p) => read_config(p, PfConfig::from_ron)?,
        },
        rmcl: match &args.rmcl_config {
            None => RmclConfig::from_ron(RMCL_CONFIG).map_err(bad)?,
            Some(p) => read_config(p, RmclConfig::from_ron)?,
        },
        bounds,
        seed: args.seed,
        start,
    })
}

/// Runs every method (and, with a kidnap, each once more kidnapped) and makes its row; the rows'
/// common-window ATE is filled once all have run, since the window depends on all of them.
fn method_rows(
    args: &CompareArgs,
    setup: &Setup<'_>,
    input: &LoadedFrames,
    kidnapped: Option<(f64, Kidnap)>,
) -> Result<Vec<MethodRow>, CliError> {
    let frames = &input.frames;
    let mut rows = Vec::new();
    let mut reports = Vec::new();
    let bar = super::progress::steps(args.methods.len() as u64, "methods");
    for &m in &args.methods {
        if let Some(b) = &bar {
            b.inc(1);
        }
        let ran = run_method(m, setup, frames, &RunOptions::default())?;
        let kidnap_run = match kidnapped {
            None => None,
            Some((_, k)) => {
                let opts = RunOptions {
                    kidnap: Some(k),
                    ..RunOptions::default()
                };
                Some(run_method(m, setup, frames, &opts)?.report)
            }
        };
        if let Some(dir) = &args.tum_dir {
            // With a kidnap, the trajectory is the kidnapped run's, as `grid --tum` writes.
            let written = kidnap_run.as_ref().unwrap_or(&ran.report);
            write_trajectory(&dir.join(m.file_name()), &written.frames)?;
        }
        let recovery = match kidnap_run.and_then(|r| r.recovery) {
            Some(Recovery::Recovered { after }) => Some(after),
            _ => None,
        };
        let stats = input.reader.stats;
        let (kidnap_at, unknown) = (kidnapped.map(|k| k.0), (stats.unknown, stats.robots));
        rows.push(method_row(m, &ran, kidnap_at, recovery, unknown));
        reports.push(ran.report);
    }
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let start = common_window_start(&reports);
    let t0 = frames.first().map_or(0.0, |f| f.t);
    for (row, report) in rows.iter_mut().zip(&reports) {
        row.ate_common = start.and_then(|t| report.ate_from(t));
        row.common_from = start.map(|t| t - t0);
    }
    Ok(rows)
}

/// The row of method `m` from its run, before the common window is known; `unknown_read` counts
/// the readings the input's reader could not place (unknown subjects, other robots), added to
/// the run's own.
fn method_row(
    m: MethodSpec,
    ran: &Ran,
    kidnap_at: Option<f64>,
    recovery: Option<f64>,
    unknown_read: (usize, usize),
) -> MethodRow {
    let Ran { report, took, rmcl } = ran;
    let n = report.frames.len();
    MethodRow {
        method: m.to_string(),
        frames: n,
        ate: report.ate,
        ate_all: report.ate_all,
        heading_rmse: report.heading_rmse,
        first_fix: report.first_fix.map(|f| f.after),
        first_fix_t: report.first_fix_time(),
        kidnap_at,
        recovery,
        wall_s: took.as_secs_f64(),
        time_per_step_us: if n > 0 {
            took.as_secs_f64() * 1e6 / n as f64
        } else {
            0.0
        },
        used: report.used,
        thinned: report.thinned,
        unknown: report.unknown + unknown_read.0 + unknown_read.1,
        other_robots: unknown_read.1,
        rejected_readings: report.rejected,
        rmcl: *rmcl,
        ate_common: None,
        common_from: None,
    }
}

/// The perturbations of a sweep kind: (sweep name, perturbation), in plotting order.
fn levels(kind: SweepKind) -> Vec<(&'static str, Perturbation)> {
    let mut v = Vec::new();
    if matches!(kind, SweepKind::Noise | SweepKind::Both) {
        v.extend(
            NOISE_LEVELS
                .iter()
                .map(|&(r, b)| ("noise", Perturbation::noise(r, b))),
        );
    }
    if matches!(kind, SweepKind::Sparsity | SweepKind::Both) {
        v.extend(
            KEEP_LEVELS
                .iter()
                .map(|&k| ("sparsity", Perturbation::sparsity(k))),
        );
    }
    v
}

/// Runs every method at every level; each level's frames are perturbed once, with `--seed`,
/// and shared by all methods.
fn run_sweeps(
    kind: SweepKind,
    args: &CompareArgs,
    s: &Setup<'_>,
    frames: &[MetricFrame],
) -> Result<Vec<SweepPoint>, CliError> {
    let mut points = Vec::new();
    let levels: Vec<_> = levels(kind).into_iter().collect();
    let runs = (levels.len() * args.methods.len()) as u64;
    let bar = super::progress::steps(runs, "sweep");
    for (sweep, p) in levels {
        let perturbed = perturb(frames, &p, args.seed).map_err(bad)?;
        for &m in &args.methods {
            if let Some(b) = &bar {
                b.inc(1);
            }
            let r = run_method(m, s, &perturbed, &RunOptions::default())?.report;
            points.push(SweepPoint {
                method: m.to_string(),
                sweep,
                range_sigma: p.range_sigma,
                bearing_sigma_deg: p.bearing_sigma.to_degrees(),
                keep: p.keep,
                ate: r.ate,
                ate_all: r.ate_all,
                first_fix: r.first_fix.map(|f| f.after),
            });
        }
    }
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    Ok(points)
}

/// A level's column label: `σr m / σb °` for noise, `k %` for sparsity.
fn level_label(p: &SweepPoint) -> String {
    if p.sweep == "noise" {
        format!("{} m / {}°", trim(p.range_sigma), trim(p.bearing_sigma_deg))
    } else {
        format!("{} %", trim(p.keep * 100.0))
    }
}

/// The points of one sweep (`noise` or `sparsity`) and its level labels in run order; `None`
/// when that sweep was not run.
fn one_sweep<'p>(
    points: &'p [SweepPoint],
    sweep: &str,
) -> Option<(Vec<&'p SweepPoint>, Vec<String>)> {
    let of: Vec<&SweepPoint> = points.iter().filter(|p| p.sweep == sweep).collect();
    if of.is_empty() {
        return None;
    }
    let mut labels: Vec<String> = Vec::new();
    for p in &of {
        let l = level_label(p);
        if !labels.contains(&l) {
            labels.push(l);
        }
    }
    Some((of, labels))
}

/// A number with no trailing zeros (levels are short decimals).
fn trim(v: f64) -> String {
    let t = format!("{v:.3}");
    t.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The sweeps as plot panels: ATE RMSE (from the first fix) per method, titled with `what` was
/// evaluated.
fn plot(methods: &[MethodSpec], points: &[SweepPoint], what: &str) -> String {
    let mut panels = Vec::new();
    for (sweep, title) in [
        ("noise", "added noise (σ range / σ bearing)"),
        ("sparsity", "readings kept"),
    ] {
        let Some((of, labels)) = one_sweep(points, sweep) else {
            continue;
        };
        let series = methods
            .iter()
            .map(|m| {
                let name = m.to_string();
                Series {
                    values: of
                        .iter()
                        .filter(|p| p.method == name)
                        .map(|p| p.ate.map(|a| a.rmse))
                        .collect(),
                    name,
                }
            })
            .collect();
        panels.push(Panel {
            title: title.to_string(),
            levels: labels,
            series,
        });
    }
    let title = format!("Perturbation sweep: {what}");
    sweep::svg(&panels, &title, "ATE RMSE from first fix [m]")
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("–".to_string(), |v| format!("{v:.digits$}"))
}

/// The notes under the main table: how R-MCL made its estimates, the first fixes on the log's
/// clock, the kidnap, and what the columns mean.
fn print_notes(out: &mut impl Write, rows: &[MethodRow]) -> Result<(), CliError> {
    for r in rows {
        if let Some(c) = r.rmcl {
            writeln!(
                out,
                "\n{}: estimate from fresh samples in {} of {} frames, from samples carried by odometry in {}, the grid's after a failed sampling in {}, the grid's (no samples yet) in the rest",
                r.method, c.sampled, r.frames, c.carried, c.fallbacks
            )?;
        }
    }
    let fixes: Vec<String> = rows
        .iter()
        .filter_map(|r| Some(format!("{} t = {:.3}", r.method, r.first_fix_t?)))
        .collect();
    if !fixes.is_empty() {
        writeln!(
            out,
            "\nfirst fix on the log's clock (evo_ape --t_start): {}",
            fixes.join(", ")
        )?;
    }
    if let Some(at) = rows.first().and_then(|r| r.kidnap_at) {
        writeln!(out, "\nkidnap injected {at:.1} s after the first frame")?;
    }
    let window = match rows.first().and_then(|r| r.common_from) {
        Some(s) => format!("from {s:.1} s, the latest first fix of the methods above"),
        None => "none: some method never has a fix".to_string(),
    };
    writeln!(
        out,
        "\nATE: position error vs truth, no alignment, RMSE / median / max from each method's own first fix; ATE common window: RMSE over the frames where every method above has had its fix ({window}); ATE all frames: RMSE from the first frame. time/step: wall time of the run / frames."
    )?;
    Ok(())
}

fn print_table(
    out: &mut impl Write,
    rows: &[MethodRow],
    points: &[SweepPoint],
) -> Result<(), CliError> {
    writeln!(
        out,
        "| method | frames | ATE RMSE [m] | median [m] | max [m] | ATE common window [m] | ATE all frames [m] | heading RMSE [rad] | first fix [s] | kidnap recovery [s] | time/step [µs] |"
    )?;
    writeln!(out, "|---|---|---|---|---|---|---|---|---|---|---|")?;
    for r in rows {
        let recovery = match (r.kidnap_at, r.recovery) {
            (None, _) => "–".to_string(),
            (Some(_), Some(s)) => format!("{s:.1}"),
            (Some(_), None) => "not recovered".to_string(),
        };
        writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.1} |",
            r.method,
            r.frames,
            opt(r.ate.map(|a| a.rmse), 3),
            opt(r.ate.map(|a| a.median), 3),
            opt(r.ate.map(|a| a.max), 3),
            opt(r.ate_common.map(|a| a.rmse), 3),
            opt(r.ate_all.map(|a| a.rmse), 3),
            opt(r.heading_rmse, 3),
            opt(r.first_fix, 1),
            recovery,
            r.time_per_step_us
        )?;
    }
    print_notes(out, rows)?;
    for (sweep, title) in [
        (
            "noise",
            "ATE RMSE [m] from first fix vs added noise (σ range / σ bearing)",
        ),
        ("sparsity", "ATE RMSE [m] from first fix vs readings kept"),
    ] {
        let Some((of, labels)) = one_sweep(points, sweep) else {
            continue;
        };
        writeln!(out, "\n{title}\n")?;
        writeln!(out, "| method | {} |", labels.join(" | "))?;
        writeln!(out, "|---|{}", "---|".repeat(labels.len()))?;
        for r in rows {
            let cells: Vec<String> = of
                .iter()
                .filter(|p| p.method == r.method)
                .map(|p| {
                    p.ate
                        .map_or("no fix".to_string(), |a| format!("{:.3}", a.rmse))
                })
                .collect();
            writeln!(out, "| {} | {} |", r.method, cells.join(" | "))?;
        }
    }
    Ok(())
}

fn print_csv(
    out: &mut impl Write,
    rows: &[MethodRow],
    points: &[SweepPoint],
) -> Result<(), CliError> {
    let o = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v}"));
    writeln!(
        out,
        "method,run,range_sigma_m,bearing_sigma_deg,keep,ate_rmse_m,ate_median_m,ate_max_m,ate_all_rmse_m,first_fix_s,kidnap_recovery_s,time_per_step_us,ate_common_rmse_m,common_from_s,first_fix_t"
    )?;
    for r in rows {
        let recovery = match (r.kidnap_at, r.recovery) {
            (Some(_), None) => "never".to_string(),
            (_, v) => o(v),
        };
        writeln!(
            out,
            "{},main,0,0,1,{},{},{},{},{},{},{},{},{},{}",
            r.method,
            o(r.ate.map(|a| a.rmse)),
            o(r.ate.map(|a| a.median)),
            o(r.ate.map(|a| a.max)),
            o(r.ate_all.map(|a| a.rmse)),
            o(r.first_fix),
            recovery,
            r.time_per_step_us,
            o(r.ate_common.map(|a| a.rmse)),
            o(r.common_from),
            o(r.first_fix_t),
        )?;
    }
    for p in points {
        writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},,,,,",
            p.method,
            p.sweep,
            p.range_sigma,
            p.bearing_sigma_deg,
            p.keep,
            o(p.ate.map(|a| a.rmse)),
            o(p.ate.map(|a| a.median)),
            o(p.ate.map(|a| a.max)),
            o(p.ate_all.map(|a| a.rmse)),
            o(p.first_fix),
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn method_specs_parse_and_print_back() {
        for (s, m) in [
            ("fpg", MethodSpec::Fpg),
            ("rmcl", MethodSpec::Rmcl),
            ("pf", MethodSpec::Pf { particles: None }),
            (
                "pf:500",
                MethodSpec::Pf {
                    particles: Some(500),
                },
            ),
        ] {
            assert_eq!(s.parse::<MethodSpec>(), Ok(m));
            assert_eq!(m.to_string(), s);
        }
        assert_eq!(
            " PF:2000 ".parse::<MethodSpec>(),
            Ok(MethodSpec::Pf {
                particles: Some(2000)
            })
        );
        assert_eq!(
            MethodSpec::Pf {
                particles: Some(500)
            }
            .file_name(),
            "pf-500.tum"
        );
    }

    #[test]
    fn bad_method_specs_say_why() {
        assert!(matches!(
            "kalman".parse::<MethodSpec>(),
            Err(MethodSpecError::Unknown { .. })
        ));
        assert!(matches!(
            "".parse::<MethodSpec>(),
            Err(MethodSpecError::Unknown { .. })
        ));
        for bad in ["pf:", "pf:0", "pf:-3", "pf:1e3", "pf:2000000", "pf:x"] {
            assert!(
                matches!(
                    bad.parse::<MethodSpec>(),
                    Err(MethodSpecError::BadCount { .. })
                ),
                "{bad}"
            );
        }
    }
}
