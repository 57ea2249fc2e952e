//! The grid as a [`Localizer`], and [`run`]: the Fuzzy Position Grid driven over a stream of
//! [`MetricFrame`]s and scored against the stream's ground truth (definitions of ATE, fix,
//! kidnap and recovery in [`crate::localize`]).
//!
//! The grid's reliability is that of [`crate::grid::estimate`] (the extent of the top region);
//! its fix threshold is [`GridConfig::fix_reliability`] and its thinning
//! [`GridConfig::reobserve_interval`]. Prediction is lazy (the grid accumulates motion until the
//! next update), so [`Localizer::estimate`] applies the pending motion first.
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
use crate::localize::{drive, Localizer, PoseEstimate};
pub use crate::localize::{
    recovery_time, AteStats, FirstFix, FrameEstimate, Kidnap, Recovery, RunOptions, RunReport,
};

/// The Fuzzy Position Grid as a [`Localizer`].
#[derive(Debug, Clone)]
pub struct GridLocalizer {
    grid: FuzzyGrid,
}

impl GridLocalizer {
    /// A grid in total ignorance over `cfg.bounds`, or over the landmarks' extent plus
    /// `cfg.margin` when the configuration has no bounds.
    pub fn new(table: &LandmarkTable, cfg: &GridConfig) -> Result<Self, GridError> {
        let bounds = match cfg.bounds {
            Some(b) => b,
            None => table.bounds(cfg.margin).ok_or(GridError::BadConfig {
                field: "bounds",
                reason: "no bounds and no landmarks",
            })?,
        };
        Ok(GridLocalizer {
            grid: FuzzyGrid::new(cfg.clone(), bounds)?,
        })
    }

    /// The grid (its planes, for pictures and for the cooperative layer).
    pub fn grid(&self) -> &FuzzyGrid {
        &self.grid
    }
}

impl Localizer for GridLocalizer {
    type Error = GridError;

    fn predict(&mut self, motion: &Motion) -> Result<(), GridError> {
        self.grid.predict(motion)
    }

    fn observe(&mut self, table: &LandmarkTable, obs: &Observation) -> Result<(), GridError> {
        self.grid.observe(table, obs).map(|_| ())
    }

    fn estimate(&mut self) -> PoseEstimate {
        self.grid.apply_pending();
        let e = self.grid.estimate();
        PoseEstimate {
            pose: Pose2 {
                x: e.x as f64,
                y: e.y as f64,
                theta: e.theta as f64,
            },
            reliability: e.reliability,
            heading_reliability: e.heading_reliability,
        }
    }

    fn fix_reliability(&self) -> f32 {
        self.grid.config().fix_reliability
    }

    fn reobserve_interval(&self) -> f64 {
        self.grid.config().reobserve_interval as f64
    }
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
    let mut loc = GridLocalizer::new(table, cfg)?;
    Ok(drive(&mut loc, table, frames, opts))
}
