//! The driver: runs the predict–update–estimate cycle over a stream of
//! [`MetricFrame`]s and scores it against the stream's ground truth.
//!
//! Definitions used in the [`RunReport`]:
//! * **ATE** (absolute trajectory error): Euclidean position error per frame
//!   with truth, *without alignment* (the grid's frame is the map's frame);
//!   RMSE, median and maximum, over the frames from the first fix on
//!   ([`RunReport::ate`]) and over all frames ([`RunReport::ate_all`]).
//! * **Fix**: the first frame whose reliability reaches
//!   [`GridConfig::fix_reliability`]; the *time to first fix* is measured from
//!   the first frame (the grid starts in total ignorance).
//! * **Kidnap**: at the first frame at or after [`Kidnap::time`], the
//!   kidnap's offset is added to the frame's odometry increment, as if the
//!   robot had been carried away while the truth stays put. The run has
//!   **recovered** at the first frame time `t ≥ time` from which the
//!   position error stays within `recovery_radius` (0.45 m) for
//!   `recovery_hold` (10 s) of frames, as in Fox, Burgard & Thrun (1999); the
//!   recovery time is `t − time`.
//!
//! # Complexity
//!
//! O(frames · cells) time (one estimate per frame, updates per observation);
//! memory O(cells + frames).
//!
//! # Example
//!
//! ```
//! use lplace::grid::{GridConfig, Landmark, LandmarkTable};
//! use lplace::grid::run::{run, RunOptions};
//! use lplace::io::mrclam::{LandmarkReading, MetricFrame, Pose2};
//! let table = LandmarkTable::new(vec![
//!     Landmark { id: 1, x: 0.0, y: 0.0 },
//!     Landmark { id: 2, x: 3.0, y: 0.0 },
//!     Landmark { id: 3, x: 0.0, y: 2.0 },
//! ]).unwrap();
//! // The robot sits at (1, 1) facing +x and sees all three landmarks.
//! let seen = |id: u32, lx: f64, ly: f64| {
//!     let (dx, dy) = (lx - 1.0, ly - 1.0);
//!     LandmarkReading { subject: id, range: dx.hypot(dy), bearing: dy.atan2(dx) }
//! };
//! let frame = |t: f64| MetricFrame {
//!     t,
//!     odometry: Default::default(),
//!     observations: vec![seen(1, 0.0, 0.0), seen(2, 3.0, 0.0), seen(3, 0.0, 2.0)],
//!     truth: Some(Pose2 { x: 1.0, y: 1.0, theta: 0.0 }),
//! };
//! let report = run(&table, &GridConfig::default(), (0..3).map(|k| frame(k as f64)), &RunOptions::default()).unwrap();
//! assert!(report.ate.unwrap().rmse < 0.1);
//! ```

use super::{FuzzyGrid, GridConfig, GridError, LandmarkTable, Motion, Observation};
use crate::io::mrclam::{MetricFrame, Pose2};
use serde::{Deserialize, Serialize};

/// An injected kidnap: an offset added to one frame's odometry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Kidnap {
    /// Time (s, same clock as the frames) of the kidnap.
    pub time: f64,
    /// Forward offset (m, robot frame).
    pub forward: f64,
    /// Lateral offset (m, robot frame).
    pub lateral: f64,
    /// Rotation offset (rad).
    pub turn: f64,
}

/// What the driver uses and measures.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RunOptions {
    /// Use the range of each reading. Default true.
    pub use_range: bool,
    /// Use the bearing of each reading (with angle sets). Default true.
    pub use_bearing: bool,
    /// Use odometry (false: paper 000's odometry-free blur, time only). Default true.
    pub use_odometry: bool,
    /// Optional kidnap.
    pub kidnap: Option<Kidnap>,
    /// Recovery radius (m). Default 0.45.
    pub recovery_radius: f64,
    /// Time the error must stay within the radius (s). Default 10.
    pub recovery_hold: f64,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            use_range: true,
            use_bearing: true,
            use_odometry: true,
            kidnap: None,
            recovery_radius: 0.45,
            recovery_hold: 10.0,
        }
    }
}

/// The estimate at one frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FrameEstimate {
    /// Frame time (s).
    pub t: f64,
    /// Estimated pose.
    pub pose: Pose2,
    /// Position reliability.
    pub reliability: f32,
    /// Heading reliability.
    pub heading_reliability: f32,
    /// Truth, when the frame has it.
    pub truth: Option<Pose2>,
    /// Position error (m), when the frame has truth.
    pub error: Option<f64>,
}

/// Error statistics (metres).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AteStats {
    /// Root mean square error.
    pub rmse: f64,
    /// Median error.
    pub median: f64,
    /// Largest error.
    pub max: f64,
    /// Frames counted.
    pub count: usize,
}

impl AteStats {
    /// Statistics of a set of errors; `None` when empty (NaNs are skipped).
    pub fn from_errors(errors: impl IntoIterator<Item = f64>) -> Option<AteStats> {
        let mut e: Vec<f64> = errors.into_iter().filter(|v| v.is_finite()).collect();
        if e.is_empty() {
            return None;
        }
        e.sort_by(f64::total_cmp);
        let n = e.len();
        let median = if n % 2 == 1 {
            e[n / 2]
        } else {
            0.5 * (e[n / 2 - 1] + e[n / 2])
        };
        let rmse = (e.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
        Some(AteStats {
            rmse,
            median,
            max: e[n - 1],
            count: n,
        })
    }
}

/// The first fix.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FirstFix {
    /// Seconds from the first frame.
    pub after: f64,
    /// Position error at the fix (m), when truth is known.
    pub error: Option<f64>,
}

/// Outcome of a kidnap.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Recovery {
    /// Recovered this many seconds after the kidnap.
    Recovered {
        /// Seconds after the kidnap.
        after: f64,
    },
    /// Never stayed within the radius for the hold time.
    NotRecovered,
}

/// Everything a run produces.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunReport {
    /// Per-frame estimates.
    pub frames: Vec<FrameEstimate>,
    /// ATE from the first fix on.
    pub ate: Option<AteStats>,
    /// ATE over all frames with truth.
    pub ate_all: Option<AteStats>,
    /// RMS heading error (rad) from the first fix on.
    pub heading_rmse: Option<f64>,
    /// First fix, if any.
    pub first_fix: Option<FirstFix>,
    /// Kidnap recovery, when a kidnap was injected.
    pub recovery: Option<Recovery>,
    /// Readings used in updates.
    pub used: usize,
    /// Readings of subjects not in the landmark table (other robots …).
    pub unknown: usize,
    /// Readings or odometry increments rejected as non-finite/negative.
    pub rejected: usize,
    /// Readings skipped by [`GridConfig::reobserve_interval`].
    pub thinned: usize,
}

/// Runs the grid over `frames` (see the module docs).
pub fn run<I>(
    table: &LandmarkTable,
    cfg: &GridConfig,
    frames: I,
    opts: &RunOptions,
) -> Result<RunReport, GridError>
where
    I: IntoIterator<Item = MetricFrame>,
{
    let bounds = match cfg.bounds {
        Some(b) => b,
        None => table.bounds(cfg.margin).ok_or(GridError::BadConfig {
            field: "bounds",
            reason: "no bounds and no landmarks",
        })?,
    };
    let mut grid = FuzzyGrid::new(cfg.clone(), bounds)?;
    let mut out = Vec::new();
    let (mut used, mut unknown, mut rejected) = (0, 0, 0);
    let mut kidnap = opts.kidnap;
    let mut t_first = None;
    let mut first_fix = None;
    let mut thinned = 0;
    // Last time each landmark was fed to the grid (by table position).
    let mut last_fed = vec![f64::NEG_INFINITY; table.landmarks().len()];
    let interval = cfg.reobserve_interval as f64;
    for f in frames {
        let t0 = *t_first.get_or_insert(f.t);
        let mut o = f.odometry;
        if let Some(k) = kidnap {
            if f.t >= k.time {
                o.forward += k.forward;
                o.lateral += k.lateral;
                o.turn += k.turn;
                kidnap = None;
            }
        }
        let m = if opts.use_odometry {
            Motion {
                forward: o.forward as f32,
                lateral: o.lateral as f32,
                turn: o.turn as f32,
                dt: o.dt as f32,
            }
        } else {
            Motion {
                forward: 0.0,
                lateral: 0.0,
                turn: 0.0,
                dt: o.dt as f32,
            }
        };
        if grid.predict(&m).is_err() {
            rejected += 1;
        }
        for r in &f.observations {
            let Ok(slot) = table.landmarks().binary_search_by_key(&r.subject, |m| m.id) else {
                unknown += 1;
                continue;
            };
            if interval > 0.0 && f.t - last_fed[slot] < interval {
                thinned += 1;
                continue;
            }
            last_fed[slot] = f.t;
            let obs = Observation {
                landmark: r.subject,
                range: opts.use_range.then_some(r.range as f32),
                bearing: opts.use_bearing.then_some(r.bearing as f32),
            };
            match grid.observe(table, &obs) {
                Ok(_) => used += 1,
                Err(_) => rejected += 1,
            }
        }
        grid.apply_pending();
        let e = grid.estimate();
        let pose = Pose2 {
            x: e.x as f64,
            y: e.y as f64,
            theta: e.theta as f64,
        };
        let error = f.truth.map(|tr| (tr.x - pose.x).hypot(tr.y - pose.y));
        if first_fix.is_none() && e.reliability >= cfg.fix_reliability {
            first_fix = Some(FirstFix {
                after: f.t - t0,
                error,
            });
        }
        out.push(FrameEstimate {
            t: f.t,
            pose,
            reliability: e.reliability,
            heading_reliability: e.heading_reliability,
            truth: f.truth,
            error,
        });
    }
    let fix_t = first_fix.map(|x| x.after + t_first.unwrap_or(0.0));
    let after_fix = |fe: &&FrameEstimate| fix_t.is_some_and(|t| fe.t >= t);
    let ate = AteStats::from_errors(out.iter().filter(after_fix).filter_map(|f| f.error));
    let ate_all = AteStats::from_errors(out.iter().filter_map(|f| f.error));
    let head: Vec<f64> = out
        .iter()
        .filter(after_fix)
        .filter_map(|f| {
            f.truth
                .map(|tr| super::wrap_pi((f.pose.theta - tr.theta) as f32) as f64)
        })
        .collect();
    let heading_rmse = (!head.is_empty())
        .then(|| (head.iter().map(|v| v * v).sum::<f64>() / head.len() as f64).sqrt());
    let recovery = opts
        .kidnap
        .map(|k| recovery_time(&out, k.time, opts.recovery_radius, opts.recovery_hold));
    Ok(RunReport {
        frames: out,
        ate,
        ate_all,
        heading_rmse,
        first_fix,
        recovery,
        used,
        unknown,
        rejected,
        thinned,
    })
}

/// First time `t ≥ since` from which every frame with truth within
/// `[t, t + hold]` has an error ≤ `radius` (and the frames span the hold).
pub fn recovery_time(frames: &[FrameEstimate], since: f64, radius: f64, hold: f64) -> Recovery {
    let f: Vec<(f64, f64)> = frames
        .iter()
        .filter(|f| f.t >= since)
        .filter_map(|f| f.error.map(|e| (f.t, e)))
        .collect();
    // Scan backwards: `good_until` = time up to which the run of good frames
    // starting at the current index extends.
    let mut best = None;
    let mut run_end: Option<f64> = None;
    for &(t, e) in f.iter().rev() {
        if e <= radius {
            let end = *run_end.get_or_insert(t);
            if end - t >= hold {
                best = Some(t);
            }
        } else {
            run_end = None;
        }
    }
    match best {
        Some(t) => Recovery::Recovered { after: t - since },
        None => Recovery::NotRecovered,
    }
}
