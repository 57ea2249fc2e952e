//! Where a perturbed grid run parts from the unperturbed one on MRCLAM dataset 7: both run side
//! by side, frame by frame, through the same driver (`localize::Drive`), and per frame the
//! discrete decisions of the run are recorded — which readings the driver fed (thinning),
//! whether the motion was shifted along the estimated heading (`directed_min_reliability`), the
//! whole-cell shift, whether the pending blur was applied, whether the reliability reached
//! `fix_reliability` — next to the estimate and the belief's maximum cell. Nothing in the runs is
//! changed by the recording (`FuzzyGrid::last_motion` only reads).
//!
//! `cargo run --release --example mrclam_divergence [CONFIG] ROBOT [CASE…] [--around SECONDS]`
//! (`--around`: both runs' frames within 3 s of that time, one line each), a case being
//! `lm:SEED` (every landmark moved by ±1 mm, `localize::robust::jitter_landmarks`) or
//! `NAME*FACTOR` (one value of the configuration, as `localize::robust::nudged_configs` names
//! it, e.g. `flank_per_second*0.99`). Without cases, every perturbation of
//! `examples/mrclam_robustness.rs` is run and those that move the ATE by more than 3 % are
//! traced. Per traced case one markdown row: the ATE change, the first decision that differs
//! (time from the first frame, kind, both sides), the first frame after both runs' first fix
//! whose position estimates differ by more than 1 cm and 5 cm, the decision flips counted by kind up to that 5 cm
//! frame, and the share of the ATE change (Σ e² difference) accrued after it.

#[path = "support/mrclam.rs"]
mod support;

use lplace::core::Odometry;
use lplace::grid::place::survey_landmarks;
use lplace::grid::{GridConfig, GridError, LandmarkTable, MotionTrace, Observation};
use lplace::io::mrclam_dir;
use lplace::localize::grid::GridLocalizer;
use lplace::localize::robust::{jitter_landmarks, nudged_configs};
use lplace::localize::{Drive, Localizer, MetricFrame, PoseEstimate, RunOptions};

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

/// The grid, recording the decisions taken in the current frame.
struct Traced {
    grid: GridLocalizer,
    fed: Vec<u32>,
    motions: Vec<MotionTrace>,
}

impl Localizer for Traced {
    type Error = GridError;
    fn predict(&mut self, odometry: &Odometry, dt: f64) -> std::result::Result<(), GridError> {
        self.fed.clear();
        self.motions.clear();
        self.grid.predict(odometry, dt)
    }
    fn observe(
        &mut self,
        t: &LandmarkTable,
        o: &Observation,
    ) -> std::result::Result<(), GridError> {
        let before = self.grid.grid().last_motion().applied;
        self.grid.observe(t, o)?;
        self.fed.push(o.landmark);
        let m = self.grid.grid().last_motion();
        if m.applied != before {
            self.motions.push(m);
        }
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

/// One frame of a traced run.
struct Rec {
    t: f64,
    x: f64,
    y: f64,
    theta: f64,
    error: Option<f64>,
    fixed: bool,
    fed: Vec<u32>,
    motions: Vec<MotionTrace>,
    argmax: usize,
    heading_reliability: f32,
    /// Top region (h ≥ 0.9 max): cells, and the share of its possibility whose heading is
    /// unknown (bias ≥ 0.99).
    top: (usize, f32),
    /// The top region's cells: column, row, h / max, heading centre, bias.
    top_cells: Vec<(usize, usize, f32, f32, f32)>,
}

fn top_cells(g: &lplace::grid::FuzzyGrid) -> Vec<(usize, usize, f32, f32, f32)> {
    let h = g.possibilities();
    let max = h.iter().copied().fold(0.0f32, f32::max);
    let mut out = Vec::new();
    for (i, &v) in h.iter().enumerate() {
        let (c, r) = (i % g.nx(), i / g.nx());
        if let Some(t) = g.heading_set(c, r).filter(|_| v >= 0.9 * max && max > 0.0) {
            out.push((c, r, v / max, t.center, t.shape.bias));
        }
    }
    out
}

fn top_region(g: &lplace::grid::FuzzyGrid) -> (usize, f32) {
    let h = g.possibilities();
    let max = h.iter().copied().fold(0.0f32, f32::max);
    let (mut n, mut all, mut blind) = (0, 0.0f32, 0.0f32);
    for (i, &v) in h.iter().enumerate() {
        if v >= 0.9 * max && max > 0.0 {
            n += 1;
            all += v;
            let set = g.heading_set(i % g.nx(), i / g.nx());
            if set.is_some_and(|t| t.shape.bias >= 0.99) {
                blind += v;
            }
        }
    }
    (n, if all > 0.0 { blind / all } else { 0.0 })
}

fn trace(table: &LandmarkTable, cfg: &GridConfig, frames: &[MetricFrame]) -> Result<Vec<Rec>> {
    let mut loc = Traced {
        grid: GridLocalizer::new(table, cfg)?,
        fed: Vec::new(),
        motions: Vec::new(),
    };
    let mut drive = Drive::new(table, RunOptions::default());
    let mut out = Vec::with_capacity(frames.len());
    let mut fixed = false;
    for f in frames {
        let e = drive.step(&mut loc, f);
        fixed |= e.reliability >= cfg.fix_reliability;
        let h = loc.grid.grid().possibilities();
        let argmax = (0..h.len()).fold(0, |b, i| if h[i] > h[b] { i } else { b });
        out.push(Rec {
            t: f.t,
            x: e.pose.x,
            y: e.pose.y,
            theta: e.pose.theta,
            error: e.error,
            fixed,
            fed: std::mem::take(&mut loc.fed),
            motions: std::mem::take(&mut loc.motions),
            argmax,
            heading_reliability: e.heading_reliability,
            top: top_region(loc.grid.grid()),
            top_cells: top_cells(loc.grid.grid()),
        });
    }
    Ok(out)
}

/// ATE RMSE from the first fix, as the driver scores it.
fn ate(run: &[Rec]) -> f64 {
    let e: Vec<f64> = run
        .iter()
        .filter(|r| r.fixed)
        .filter_map(|r| r.error)
        .collect();
    (e.iter().map(|v| v * v).sum::<f64>() / e.len().max(1) as f64).sqrt()
}

/// The decisions that differ between two records of the same frame, by kind, with both sides.
/// Under `Shift::Lattice` (`lattice`) a shift rounded the other way leaves the same belief and
/// is not counted.
fn flips(a: &Rec, b: &Rec, lattice: bool) -> Vec<(&'static str, String)> {
    let mut out = Vec::new();
    if a.fed != b.fed {
        out.push(("thinning", format!("{:?} / {:?}", a.fed, b.fed)));
    }
    if a.fixed != b.fixed {
        out.push(("first fix", format!("{} / {}", a.fixed, b.fixed)));
    }
    if a.motions.len() != b.motions.len() {
        out.push((
            "motion applied",
            format!("{} / {}", a.motions.len(), b.motions.len()),
        ));
    }
    for (m, n) in a.motions.iter().zip(&b.motions) {
        if (m.directed - n.directed).abs() > 0.05 {
            let what = format!("{:.2} / {:.2}", m.directed, n.directed);
            out.push(("directed", what));
        } else if m.shift != n.shift && !lattice {
            out.push(("whole-cell shift", format!("{:?} / {:?}", m.shift, n.shift)));
        }
        if m.blurred != n.blurred {
            out.push(("blur applied", format!("{} / {}", m.blurred, n.blurred)));
        }
    }
    out
}

fn moved(a: &Rec, b: &Rec) -> f64 {
    (a.x - b.x).hypot(a.y - b.y)
}

/// One markdown row comparing `base` with the perturbed run `other` (module docs).
fn row(case: &str, base: &[Rec], other: &[Rec], lattice: bool) -> String {
    let t0 = base.first().map_or(0.0, |r| r.t);
    let (a0, a1) = (ate(base), ate(other));
    // Before both runs have their fix the estimate is of a flat belief: not counted.
    let first = |eps: f64| {
        (base.iter().zip(other)).position(|(a, b)| a.fixed && b.fixed && moved(a, b) > eps)
    };
    let (k1, k5) = (first(0.01), first(0.05));
    let end = k5.unwrap_or(base.len());
    let mut first_flip = None;
    let mut kinds: Vec<(&str, usize)> = Vec::new();
    for (k, (a, b)) in base.iter().zip(other).enumerate().take(end + 1) {
        for (kind, what) in flips(a, b, lattice) {
            first_flip.get_or_insert((k, kind, what));
            match kinds.iter_mut().find(|(n, _)| *n == kind) {
                Some(c) => c.1 += 1,
                None => kinds.push((kind, 1)),
            }
        }
    }
    let argmax = base
        .iter()
        .zip(other)
        .position(|(a, b)| a.argmax != b.argmax);
    let at = |k: Option<usize>| k.map_or("—".into(), |k| format!("{:.1}", base[k].t - t0));
    let flip = first_flip.map_or("none".into(), |(k, kind, what)| {
        format!("{:.1} s {kind} ({what})", base[k].t - t0)
    });
    let sq = |r: &Rec| r.error.map_or(0.0, |e| e * e);
    let total: f64 = base.iter().zip(other).map(|(a, b)| sq(b) - sq(a)).sum();
    let after: f64 = base[end.min(base.len())..]
        .iter()
        .zip(&other[end.min(base.len())..])
        .map(|(a, b)| sq(b) - sq(a))
        .sum();
    let kinds: Vec<String> = kinds.iter().map(|(n, c)| format!("{n} {c}")).collect();
    let dtheta = k5.map_or(0.0, |k| {
        lplace::core::angle::wrap_pi(base[k].theta - other[k].theta)
    });
    format!(
        "| {case} | {:+.1} % | {flip} | {} | {} (Δθ {dtheta:+.3}) | {} | {} | {:.0} % |",
        100.0 * (a1 - a0) / a0,
        at(argmax),
        at(k1),
        at(k5),
        kinds.join(", "),
        if total != 0.0 {
            100.0 * after / total
        } else {
            0.0
        },
    )
}

/// The frames within 3 s of `at` (seconds from the first frame) of both runs, one line each.
fn dump(base: &[Rec], other: &[Rec], at: f64) {
    let t0 = base.first().map_or(0.0, |r| r.t);
    for (a, b) in base.iter().zip(other) {
        if (a.t - t0 - at).abs() > 3.0 {
            continue;
        }
        let m = |r: &Rec| {
            r.motions
                .iter()
                .map(|m| {
                    format!(
                        "w {:.2} {:?}{}",
                        m.directed,
                        m.shift,
                        if m.blurred { " blur" } else { "" }
                    )
                })
                .collect::<Vec<_>>()
                .join(";")
        };
        println!(
            "  {:.2}  Δ {:.3} m | top {:?} / {:?} | R̄ {:.3} / {:.3} | θ {:+.3} / {:+.3} | err {:.3} / {:.3} | fed {:?} / {:?} | {} / {}",
            a.t - t0,
            moved(a, b),
            a.top,
            b.top,
            a.heading_reliability,
            b.heading_reliability,
            a.theta,
            b.theta,
            a.error.unwrap_or(f64::NAN),
            b.error.unwrap_or(f64::NAN),
            a.fed,
            b.fed,
            m(a),
            m(b),
        );
        if a.top_cells != b.top_cells {
            println!(
                "      top cells {:?}\n             / {:?}",
                a.top_cells, b.top_cells
            );
        }
    }
}

fn perturbed(
    case: &str,
    table: &LandmarkTable,
    cfg: &GridConfig,
) -> Result<(LandmarkTable, GridConfig)> {
    if let Some(seed) = case.strip_prefix("lm:") {
        return Ok((jitter_landmarks(table, 0.001, seed.parse()?)?, cfg.clone()));
    }
    let (name, factor) = case.split_once('*').ok_or("case: lm:SEED or NAME*FACTOR")?;
    let factor: f64 = factor.parse()?;
    let c = nudged_configs(cfg, factor)
        .into_iter()
        .find(|(n, _)| n == name)
        .ok_or_else(|| format!("no value {name}"))?;
    Ok((table.clone(), c.1))
}

fn main() -> Result<()> {
    let Some(dir) = support::dataset7() else {
        return Ok(());
    };
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let cfg_path = if args.first().is_some_and(|a| a.ends_with(".ron")) {
        args.remove(0)
    } else {
        "config/grid-mrclam.ron".into()
    };
    let cfg = GridConfig::from_ron(&std::fs::read_to_string(&cfg_path)?)?;
    let robot: u32 = args.first().ok_or("ROBOT")?.parse()?;
    let data = mrclam_dir::load(&dir, &[robot])?;
    let table = survey_landmarks(data.survey()?)?;
    let frames = data.robots.into_iter().next().ok_or("no robot")?.frames;
    let base = trace(&table, &cfg, &frames)?;
    let lattice = cfg.shift == lplace::grid::Shift::Lattice;
    let around = match args.iter().position(|a| a == "--around") {
        Some(k) => {
            let v: f64 = args.get(k + 1).ok_or("--around SECONDS")?.parse()?;
            args.drain(k..k + 2);
            Some(v)
        }
        None => None,
    };
    let mut cases: Vec<String> = args[1..].to_vec();
    let all = cases.is_empty();
    if all {
        cases.extend((1..=10).map(|s| format!("lm:{s}")));
        for f in [1.01, 0.99] {
            cases.extend(
                nudged_configs(&cfg, f)
                    .into_iter()
                    .map(|(n, _)| format!("{n}*{f}")),
            );
        }
    }
    println!("robot {robot}, {cfg_path}: ATE {:.3} m", ate(&base));
    println!("| case | ATE change | first decision that differs | argmax differs [s] | > 1 cm [s] | > 5 cm [s] | flips up to 5 cm | ΔATE after 5 cm |");
    println!("|---|---|---|---|---|---|---|---|");
    for case in cases {
        let (t, c) = perturbed(&case, &table, &cfg)?;
        let other = trace(&t, &c, &frames)?;
        let change = (ate(&other) - ate(&base)).abs() / ate(&base);
        if !all || change > 0.03 {
            println!("{}", row(&case, &base, &other, lattice));
            if let Some(at) = around {
                dump(&base, &other, at);
            }
        }
    }
    Ok(())
}
