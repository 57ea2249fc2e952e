//! Metric localizers and the driver that runs and scores them: the one place where "run a method
//! over a stream of landmark frames" is written, so that the Fuzzy Position Grid
//! ([`crate::grid`]), the particle filter and Fuzzy R-MCL (`baseline`) and the
//! cooperative layer are stepped, kidnapped and scored the same way.
//!
//! A method implements [`Localizer`]: it takes odometry increments ([`Odometry`], with the time
//! they took) and landmark readings ([`Observation`]) and gives a [`PoseEstimate`] with a reliability in [0, 1] of its
//! own definition. [`Drive`] feeds it one [`MetricFrame`] at a time — odometry first, then the
//! frame's readings of known landmarks, then the estimate — and [`Drive::finish`] turns the
//! frames into a [`RunReport`].
//!
//! Definitions used in the [`RunReport`]:
//! * **ATE** (absolute trajectory error): Euclidean position error per frame
//!   with truth, *without alignment* (the estimate's frame is the map's frame);
//!   RMSE, median and maximum, over the frames from the first fix on
//!   ([`RunReport::ate`]) and over all frames ([`RunReport::ate_all`]).
//! * **Common window** of several runs over the same frames: the frames from the latest of
//!   their first fixes on ([`common_window_start`]), i.e. the frames where every one of them
//!   has had its fix; [`RunReport::ate_from`] scores a run over it. Methods that fix at very
//!   different times (the grid in seconds, a particle filter up to a minute later) are compared
//!   on the same frames only there: "from each method's own first fix" counts different frames
//!   per method, and "all frames" charges each method for its time before its fix.
//! * **Fix**: the first frame whose reliability reaches the method's
//!   [`Localizer::fix_reliability`]; the *time to first fix* is measured from
//!   the first frame (every method starts in total ignorance).
//! * **Kidnap**: at the first frame at or after [`Kidnap::time`], the
//!   kidnap's offset is added to the frame's odometry increment, as if the
//!   robot had been carried away while the truth stays put. The run has
//!   **recovered** at the first frame time `t ≥ time` from which the
//!   position error stays within `recovery_radius` (0.45 m) for
//!   `recovery_hold` (10 s) of frames, as in Fox, Burgard & Thrun (1999); the
//!   recovery time is `t − time`.
//! * **Thinning**: a landmark is fed at most once per
//!   [`Localizer::reobserve_interval`] seconds; the readings in between are
//!   counted in [`RunReport::thinned`].
//!
//! The metric input types ([`MetricFrame`], [`LandmarkReading`], the truth track) live here, in
//! [`frame`], and the grid's [`Localizer`] in [`grid`]; the dataset readers in `io` build frames.
//!
//! May depend on: `core` (pose, odometry, angles, RNG), `grid` (the belief, the reading type and
//! the motion check).
//!
//! # Complexity
//!
//! The driver adds O(readings · log landmarks) to the method's own cost; memory O(frames).
//!
//! # Example
//!
//! ```
//! use lplace::core::Pose2;
//! use lplace::grid::{GridConfig, Landmark, LandmarkTable};
//! use lplace::localize::grid::GridLocalizer;
//! use lplace::localize::{Drive, LandmarkReading, MetricFrame, RunOptions};
//! let table = LandmarkTable::new(vec![
//!     Landmark { id: 1, x: 0.0, y: 0.0 },
//!     Landmark { id: 2, x: 3.0, y: 0.0 },
//!     Landmark { id: 3, x: 0.0, y: 2.0 },
//! ]).unwrap();
//! let mut grid = GridLocalizer::new(&table, &GridConfig::default()).unwrap();
//! let mut drive = Drive::new(&table, RunOptions::default());
//! let seen = |id: u32, lx: f64, ly: f64| {
//!     let (dx, dy) = (lx - 1.0, ly - 1.0);
//!     LandmarkReading { subject: id, range: dx.hypot(dy), bearing: dy.atan2(dx) }
//! };
//! for k in 0..3 {
//!     let frame = MetricFrame {
//!         t: k as f64,
//!         dt: if k == 0 { 0.0 } else { 1.0 },
//!         odometry: Default::default(),
//!         observations: vec![seen(1, 0.0, 0.0), seen(2, 3.0, 0.0), seen(3, 0.0, 2.0)],
//!         truth: Some(Pose2 { x: 1.0, y: 1.0, theta: 0.0 }),
//!     };
//!     let estimate = drive.step(&mut grid, &frame);
//!     assert!(estimate.t == k as f64);
//! }
//! assert!(drive.finish().ate.unwrap().rmse < 0.1);
//! ```

pub mod frame;
pub mod grid;
pub mod perturb;
pub mod robust;

pub use frame::{interpolate_truth, LandmarkReading, MetricFrame, TruthRow};

use crate::core::angle::wrap_pi_f32;
use crate::core::{Odometry, Pose2};
use crate::grid::{LandmarkTable, Observation};
use serde::{Deserialize, Serialize};

/// A pose estimate with the method's confidence in it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PoseEstimate {
    /// The estimated pose.
    pub pose: Pose2,
    /// Position reliability in [0, 1] (each method documents its definition).
    pub reliability: f32,
    /// Heading reliability in [0, 1].
    pub heading_reliability: f32,
}

/// A metric localization method, stepped by [`Drive`].
///
/// Implementations must not panic on any input: a non-finite or negative reading or motion is
/// returned as an error (which the driver counts) and leaves the belief unchanged.
pub trait Localizer {
    /// What a rejected input is.
    type Error: std::error::Error;
    /// Moves the belief by an odometry increment (robot frame at the start of the interval) that
    /// took `dt` seconds. A value not finite in single precision or a negative `dt` is rejected
    /// ([`crate::grid::check_motion`]).
    fn predict(&mut self, odometry: &Odometry, dt: f64) -> Result<(), Self::Error>;
    /// Takes one reading of a landmark of `table`.
    fn observe(&mut self, table: &LandmarkTable, obs: &Observation) -> Result<(), Self::Error>;
    /// The estimate after this frame's motion and readings.
    fn estimate(&mut self) -> PoseEstimate;
    /// Reliability at which the method counts as having a fix.
    fn fix_reliability(&self) -> f32;
    /// Minimum time (s) between two readings of the same landmark that are fed; 0 feeds all.
    fn reobserve_interval(&self) -> f64 {
        0.0
    }
}

/// An injected kidnap: an offset added to one frame's odometry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Kidnap {
    /// Time (s, same clock as the frames) of the kidnap.
    pub time: f64,
    /// The offset, as an odometry increment (robot frame at that frame, SI units).
    pub by: Odometry,
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
    /// Readings skipped by [`Localizer::reobserve_interval`].
    pub thinned: usize,
}

impl RunReport {
    /// Frame time (same clock as the frames) of the first fix, if any.
    pub fn first_fix_time(&self) -> Option<f64> {
        let t0 = self.frames.first()?.t;
        self.first_fix.map(|f| t0 + f.after)
    }

    /// ATE over the frames at or after time `t` (same clock as the frames); `None` when none of
    /// them has truth.
    pub fn ate_from(&self, t: f64) -> Option<AteStats> {
        AteStats::from_errors(
            self.frames
                .iter()
                .filter(|f| f.t >= t)
                .filter_map(|f| f.error),
        )
    }
}

/// Start (frame time) of the common window of `runs` (module docs): the latest of their first
/// fixes; `None` when `runs` is empty or one of them never has a fix.
pub fn common_window_start<'r>(runs: impl IntoIterator<Item = &'r RunReport>) -> Option<f64> {
    let mut start: Option<f64> = None;
    for r in runs {
        let t = r.first_fix_time()?;
        start = Some(start.map_or(t, |s: f64| s.max(t)));
    }
    start
}

/// Steps one [`Localizer`] over frames and collects what [`RunReport`] needs.
#[derive(Debug, Clone)]
pub struct Drive<'t> {
    table: &'t LandmarkTable,
    opts: RunOptions,
    kidnap: Option<Kidnap>,
    t_first: Option<f64>,
    first_fix: Option<FirstFix>,
    /// Last time each landmark was fed (by table position).
    last_fed: Vec<f64>,
    out: Vec<FrameEstimate>,
    used: usize,
    unknown: usize,
    rejected: usize,
    thinned: usize,
}

impl<'t> Drive<'t> {
    /// A driver for frames whose readings name landmarks of `table`.
    pub fn new(table: &'t LandmarkTable, opts: RunOptions) -> Self {
        Drive {
            table,
            opts,
            kidnap: opts.kidnap,
            t_first: None,
            first_fix: None,
            last_fed: vec![f64::NEG_INFINITY; table.landmarks().len()],
            out: Vec::new(),
            used: 0,
            unknown: 0,
            rejected: 0,
            thinned: 0,
        }
    }

    /// Feeds one frame to `loc` — odometry (with the kidnap, if due), then the readings of known
    /// landmarks — and records and returns its estimate.
    pub fn step<L: Localizer>(&mut self, loc: &mut L, f: &MetricFrame) -> FrameEstimate {
        let t0 = *self.t_first.get_or_insert(f.t);
        let mut o = f.odometry;
        if let Some(k) = self.kidnap {
            if f.t >= k.time {
                o.forward += k.by.forward;
                o.left += k.by.left;
                o.turn += k.by.turn;
                self.kidnap = None;
            }
        }
        if !self.opts.use_odometry {
            o = Odometry::default();
        }
        // Rounded once, here: every method computes with the grid's single-precision values
        // (`Odometry::to_single_precision`).
        let dt = f.dt as f32 as f64;
        if loc.predict(&o.to_single_precision(), dt).is_err() {
            self.rejected += 1;
        }
        let interval = loc.reobserve_interval();
        for r in &f.observations {
            let Ok(slot) = self
                .table
                .landmarks()
                .binary_search_by_key(&r.subject, |m| m.id)
            else {
                self.unknown += 1;
                continue;
            };
            if interval > 0.0 && f.t - self.last_fed[slot] < interval {
                self.thinned += 1;
                continue;
            }
            self.last_fed[slot] = f.t;
            let obs = Observation {
                landmark: r.subject,
                range: self.opts.use_range.then_some(r.range as f32),
                bearing: self.opts.use_bearing.then_some(r.bearing as f32),
            };
            match loc.observe(self.table, &obs) {
                Ok(()) => self.used += 1,
                Err(_) => self.rejected += 1,
            }
        }
        let e = loc.estimate();
        let error = f.truth.map(|tr| (tr.x - e.pose.x).hypot(tr.y - e.pose.y));
        if self.first_fix.is_none() && e.reliability >= loc.fix_reliability() {
            self.first_fix = Some(FirstFix {
                after: f.t - t0,
                error,
            });
        }
        let fe = FrameEstimate {
            t: f.t,
            pose: e.pose,
            reliability: e.reliability,
            heading_reliability: e.heading_reliability,
            truth: f.truth,
            error,
        };
        self.out.push(fe);
        fe
    }

    /// The estimates so far.
    pub fn frames(&self) -> &[FrameEstimate] {
        &self.out
    }

    /// Scores the run.
    pub fn finish(self) -> RunReport {
        let out = self.out;
        let fix_t = self
            .first_fix
            .map(|x| x.after + self.t_first.unwrap_or(0.0));
        let after_fix = |fe: &&FrameEstimate| fix_t.is_some_and(|t| fe.t >= t);
        let ate = AteStats::from_errors(out.iter().filter(after_fix).filter_map(|f| f.error));
        let ate_all = AteStats::from_errors(out.iter().filter_map(|f| f.error));
        let head: Vec<f64> = out
            .iter()
            .filter(after_fix)
            .filter_map(|f| {
                f.truth
                    .map(|tr| wrap_pi_f32((f.pose.theta - tr.theta) as f32) as f64)
            })
            .collect();
        let heading_rmse = (!head.is_empty())
            .then(|| (head.iter().map(|v| v * v).sum::<f64>() / head.len() as f64).sqrt());
        let recovery = self.opts.kidnap.map(|k| {
            recovery_time(
                &out,
                k.time,
                self.opts.recovery_radius,
                self.opts.recovery_hold,
            )
        });
        RunReport {
            frames: out,
            ate,
            ate_all,
            heading_rmse,
            first_fix: self.first_fix,
            recovery,
            used: self.used,
            unknown: self.unknown,
            rejected: self.rejected,
            thinned: self.thinned,
        }
    }
}

/// Runs `loc` over `frames` with a fresh [`Drive`] and scores it.
pub fn drive<L, I>(loc: &mut L, table: &LandmarkTable, frames: I, opts: &RunOptions) -> RunReport
where
    L: Localizer,
    I: IntoIterator<Item = MetricFrame>,
{
    let mut d = Drive::new(table, *opts);
    for f in frames {
        d.step(loc, &f);
    }
    d.finish()
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A run over frames at t = 10, 11, …, with these errors and its first fix at `fix`.
    fn report(errors: &[Option<f64>], fix: Option<f64>) -> RunReport {
        let frames: Vec<FrameEstimate> = errors
            .iter()
            .enumerate()
            .map(|(k, &e)| FrameEstimate {
                t: 10.0 + k as f64,
                pose: Pose2::default(),
                reliability: 0.0,
                heading_reliability: 0.0,
                truth: e.map(|_| Pose2::default()),
                error: e,
            })
            .collect();
        RunReport {
            frames,
            ate: None,
            ate_all: None,
            heading_rmse: None,
            first_fix: fix.map(|after| FirstFix { after, error: None }),
            recovery: None,
            used: 0,
            unknown: 0,
            rejected: 0,
            thinned: 0,
        }
    }

    #[test]
    fn common_window_is_from_the_latest_fix() {
        let e = [Some(3.0), Some(4.0), None, Some(1.0), Some(2.0)];
        let early = report(&e, Some(1.0)); // fix at t = 11
        let late = report(&e, Some(3.0)); // fix at t = 13
        let never = report(&e, None);
        assert_eq!(early.first_fix_time(), Some(11.0));
        assert_eq!(common_window_start([&early, &late]), Some(13.0));
        assert_eq!(common_window_start([&late, &early]), Some(13.0));
        assert_eq!(common_window_start([&early, &never]), None);
        assert_eq!(common_window_start(std::iter::empty::<&RunReport>()), None);
        // Frames at t = 13, 14: errors 1 and 2 → RMSE √2.5, median 1.5, max 2.
        let a = early.ate_from(13.0).unwrap();
        assert_eq!(a.count, 2);
        assert!((a.rmse - 2.5f64.sqrt()).abs() < 1e-12);
        assert_eq!((a.median, a.max), (1.5, 2.0));
        // From t = 12 the frame without truth adds nothing.
        assert_eq!(early.ate_from(12.0), a.into());
        assert_eq!(early.ate_from(15.0), None);
    }

    /// Records what the driver feeds it.
    #[derive(Default)]
    struct Recorder {
        fed: Vec<(Odometry, f64)>,
    }

    impl Localizer for Recorder {
        type Error = crate::grid::GridError;
        fn predict(&mut self, odometry: &Odometry, dt: f64) -> Result<(), Self::Error> {
            self.fed.push((*odometry, dt));
            Ok(())
        }
        fn observe(&mut self, _: &LandmarkTable, _: &Observation) -> Result<(), Self::Error> {
            Ok(())
        }
        fn estimate(&mut self) -> PoseEstimate {
            PoseEstimate {
                pose: Pose2::default(),
                reliability: 0.0,
                heading_reliability: 0.0,
            }
        }
        fn fix_reliability(&self) -> f32 {
            1.0
        }
    }

    #[test]
    fn the_driver_rounds_the_increment_to_single_precision_once() {
        let table = LandmarkTable::new(Vec::new()).unwrap();
        let frame = MetricFrame {
            t: 0.0,
            dt: 0.1,
            odometry: Odometry {
                forward: 0.1,
                left: -0.3,
                turn: 0.7,
            },
            observations: Vec::new(),
            truth: None,
        };
        let mut loc = Recorder::default();
        Drive::new(&table, RunOptions::default()).step(&mut loc, &frame);
        let no_odometry = RunOptions {
            use_odometry: false,
            ..RunOptions::default()
        };
        Drive::new(&table, no_odometry).step(&mut loc, &frame);
        let rounded = Odometry {
            forward: 0.1f32 as f64,
            left: -0.3f32 as f64,
            turn: 0.7f32 as f64,
        };
        assert_ne!(rounded.forward, 0.1);
        assert_eq!(
            loc.fed,
            vec![
                (rounded, 0.1f32 as f64),
                (Odometry::default(), 0.1f32 as f64)
            ]
        );
    }
}
