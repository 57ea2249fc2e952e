//! The metric layer: paper 000's Fuzzy Position Grid (FPG).
//!
//! A 2½-D grid over the metric frame: each cell holds the possibility `h` that
//! the robot is there and a trapezoidal fuzzy set over its heading. Landmark
//! observations intersect the grid ([`observe`]), motion blurs it by fuzzy
//! dilation ([`dilate`], [`predict`]), and the estimate is a centre of gravity
//! with a reliability ([`estimate`]). [`cap`] lets the place engine bound the
//! cells of each place by that place's possibility, and [`place`] refines a
//! place decision to a pose. Driving the grid over a recorded stream and
//! scoring it is the job of `localize`, a layer above.
//!
//! May depend on: `core` (angle wrapping, the odometry increment), `map` (place extents, landmarks);
//! besides `serde`/`ron`/`thiserror`. It never does I/O.

pub mod blur;
pub mod cap;
pub mod cells;
pub mod classes;
pub mod config;
pub mod dilate;
pub mod estimate;
pub mod headings;
pub mod observe;
pub mod place;
pub mod predict;
pub mod start;
pub mod trapezoid;
mod workspace;

pub use blur::Blur;
pub use cap::Region;
pub use cells::FuzzyGrid;
pub use config::{
    CellMotion, Combine, Cuts, Dilation, ElementShape, GridConfig, HeadingSets, RaisedHeadings,
    SensorModel, Shift, MAX_HEADING_BINS, MAX_LATTICES,
};
pub use estimate::Estimate;
pub use observe::{Landmark, LandmarkTable, Observation};
pub use place::LandmarkTruth;
pub use predict::{check_motion, MotionTrace};
pub use trapezoid::Trapezoid;

/// Everything that can go wrong in the grid layer. Variants carry the
/// offending data; nothing here panics on bad input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GridError {
    /// A configuration value is out of range.
    #[error("bad grid configuration: `{field}` {reason}")]
    BadConfig {
        /// Name of the field.
        field: &'static str,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// The RON text of a configuration does not parse.
    #[error("grid configuration, line {line} column {column}: {problem}")]
    Ron {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong there (an unknown key names the nearest known one).
        problem: crate::core::config::RonProblem,
    },
    /// The requested extent would need too many cells.
    #[error("grid of {nx}×{ny} cells exceeds the limit of {limit} cells")]
    TooLarge {
        /// Columns requested.
        nx: usize,
        /// Rows requested.
        ny: usize,
        /// The limit.
        limit: usize,
    },
    /// An observation value is NaN or infinite.
    #[error("non-finite {what} in observation of landmark {landmark}: {value}")]
    NonFinite {
        /// Which quantity (`"range"`, `"bearing"`, `"landmark x"` …).
        what: &'static str,
        /// Landmark id (0 when not applicable).
        landmark: u32,
        /// The rejected value.
        value: f32,
    },
    /// A range reading is negative.
    #[error("negative range {range} to landmark {landmark}")]
    NegativeRange {
        /// Landmark id.
        landmark: u32,
        /// The rejected value.
        range: f32,
    },
    /// The observed landmark is not in the table.
    #[error("unknown landmark {0}")]
    UnknownLandmark(u32),
    /// A motion increment is not finite in single precision, or its elapsed time is negative.
    #[error("bad motion increment ({forward}, {left}, {turn}, dt {dt})")]
    BadMotion {
        /// Forward displacement (m).
        forward: f64,
        /// Displacement to the left (m).
        left: f64,
        /// Rotation (rad).
        turn: f64,
        /// Elapsed time (s).
        dt: f64,
    },
    /// A place-cap region or value is malformed.
    #[error("bad cap region #{index}: {reason}")]
    BadRegion {
        /// Position of the region in the list.
        index: usize,
        /// What is wrong with it.
        reason: &'static str,
    },
}

/// The unit tests' deterministic source of values in [0, 1): a linear congruential generator
/// seeded by `seed`, 24 bits per draw (exact in `f32`).
#[cfg(test)]
pub(crate) fn test_rng(mut seed: u32) -> impl FnMut() -> f32 {
    move || {
        seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12_345);
        (seed >> 8) as f32 / (1u32 << 24) as f32
    }
}
