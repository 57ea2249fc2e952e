//! The spread of MRCLAM's camera readings against the ground truth, and the grid's range and
//! bearing sensor models derived from it.
//!
//! For every reading of a surveyed landmark taken while the robot's Vicon pose is known, the
//! error is reading − truth: range minus the true distance from the robot to the landmark
//! (`Landmark_Groundtruth.dat`), bearing minus the true bearing (wrapped to ±π). Printed per
//! quantity: the number of readings, the mean and median signed error, the median and the 90th
//! percentile of |error|, and the share beyond that 90th percentile's double.
//!
//! Two rules that turn the spread into `GridConfig::range` / `GridConfig::bearing` are printed
//! as RON (fields as `grid::SensorModel`; the core is a full width, so ± its half):
//!
//! * **A**: core ± median |e|, flanks reaching 0 at the 90th percentile of |e|, outlier bias the
//!   share of |e| beyond twice that percentile (at least 0.01);
//! * **B**: core ± median |e|, flanks reaching 0 at the 99th percentile, bias the share beyond
//!   it (at least 0.01); the range's widths relative to the true range (`core_rel`,
//!   `slope_rel`), since range errors grow with the distance.
//!
//! `docs/compare.md` gives what each did on MRCLAM (neither beat the tuned file).
//!
//! Only the tuning robot's readings should feed the rule (robot 1 for `config/grid-mrclam.ron`;
//! robots 2–5 are held out).
//!
//! `cargo run --release --example mrclam_sensor_spread [ROBOT]` (default robot 1). Data:
//! `$LPLACE_DATA/mrclam-dataset7` or `../shared/data/mrclam-dataset7` relative to the crate root.

#[path = "support/mrclam.rs"]
mod support;

use lplace::core::angle::wrap_pi;
use lplace::grid::place::survey_landmarks;
use lplace::io::mrclam_dir;

/// The `q`-quantile of sorted values (nearest rank).
fn quantile(sorted: &[f64], q: f64) -> f64 {
    let k = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[k - 1]
}

/// |error| quantiles of one quantity: median, 90th and 99th percentile, and the shares beyond
/// twice the 90th and beyond the 99th.
struct Spread {
    med: f64,
    p90: f64,
    p99: f64,
    beyond_2p90: f64,
    beyond_p99: f64,
}

/// Prints one quantity's spread and returns it.
fn spread(name: &str, unit: &str, errors: &[f64]) -> Spread {
    let mut signed = errors.to_vec();
    signed.sort_by(f64::total_cmp);
    let mut abs: Vec<f64> = errors.iter().map(|e| e.abs()).collect();
    abs.sort_by(f64::total_cmp);
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    let share = |x: f64| abs.iter().filter(|&&a| a > x).count() as f64 / abs.len() as f64;
    let (med, p90, p99) = (
        quantile(&abs, 0.5),
        quantile(&abs, 0.9),
        quantile(&abs, 0.99),
    );
    println!(
        "{name}: {} readings, mean {mean:+.4} {unit}, median {:+.4} {unit}, |e|: median {med:.4}, p90 {p90:.4}, p99 {p99:.4} {unit}, beyond 2·p90 {:.1} %",
        errors.len(),
        quantile(&signed, 0.5),
        100.0 * share(2.0 * p90)
    );
    Spread {
        med,
        p90,
        p99,
        beyond_2p90: share(2.0 * p90),
        beyond_p99: share(p99),
    }
}

/// A sensor model as RON: absolute widths, or relative ones when `relative`.
fn model(core: f64, slope: f64, bias: f64, relative: bool) -> String {
    let (ca, cr, sa, sr) = if relative {
        (0.0, core, 0.0, slope)
    } else {
        (core, 0.0, slope, 0.0)
    };
    format!(
        "(core_abs: {ca:.3}, core_rel: {cr:.3}, slope_abs: {sa:.3}, slope_rel: {sr:.3}, bias: {:.2})",
        bias.max(0.01)
    )
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let Some(dir) = support::dataset7() else {
        return Ok(());
    };
    let robot: u32 = match std::env::args().nth(1) {
        Some(a) => a.parse()?,
        None => 1,
    };
    let data = mrclam_dir::load(&dir, &[robot])?;
    let table = survey_landmarks(data.survey()?)?;
    let log = data.robots.first().ok_or("no robot")?;
    let (mut range, mut relative, mut bearing) = (Vec::new(), Vec::new(), Vec::new());
    for f in &log.frames {
        let Some(tr) = f.truth else { continue };
        for o in &f.observations {
            let Some(m) = table.get(o.subject) else {
                continue;
            };
            let (dx, dy) = (m.x as f64 - tr.x, m.y as f64 - tr.y);
            let d = dx.hypot(dy);
            range.push(o.range - d);
            relative.push((o.range - d) / d);
            bearing.push(wrap_pi(o.bearing - (dy.atan2(dx) - tr.theta)));
        }
    }
    if range.is_empty() {
        return Err("no landmark reading with a truth pose".into());
    }
    println!("robot {robot}, readings of surveyed landmarks against Vicon:");
    let r = spread("range", "m", &range);
    let rel = spread("range / true range", "", &relative);
    let b = spread("bearing", "rad", &bearing);
    let a = |s: &Spread, rel: bool| model(2.0 * s.med, s.p90 - s.med, s.beyond_2p90, rel);
    let bb = |s: &Spread, rel: bool| model(2.0 * s.med, s.p99 - s.med, s.beyond_p99, rel);
    println!(
        "rule A:\n    range: {},\n    bearing: {},",
        a(&r, false),
        a(&b, false)
    );
    println!(
        "rule B:\n    range: {},\n    bearing: {},",
        bb(&rel, true),
        bb(&b, false)
    );
    Ok(())
}
