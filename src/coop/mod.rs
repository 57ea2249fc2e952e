//! Cooperative object localization (paper 002, Cánovas, LeBlanc & Saffiotti): every robot turns
//! its self grid (a [`crate::grid::FuzzyGrid`]) and its observation `(ρ, φ)` of an object into an
//! *object grid* by the sup formula ([`object`]), the robots exchange their object grids as one
//! byte per cell, run-length encoded ([`rle`]), and each fuses what it received by the product
//! t-norm and takes the centre of gravity ([`fuse()`]). [`experiment`] replays MRCLAM with one
//! robot as the object the others see and scores the fused estimate against each robot's own
//! and against plain and reliability-weighted averages, as paper 002's tables do.
//!
//! May depend on: [`crate::grid`] (self grids, trapezoids, sensor models), [`crate::localize`]
//! (the one per-frame driver, frames, truth tracks). It does no I/O: the caller reads the
//! dataset and hands [`experiment::run`] borrowed [`experiment::RobotTrack`]s.

pub mod config;
pub mod experiment;
pub mod fuse;
pub mod object;
pub mod rle;

pub use config::CoopConfig;
pub use fuse::{average, fuse, weighted_average, Fused};
pub use object::{object_grid, GridGeometry, ObjectGrid, ObjectReading};
pub use rle::RleError;

/// What can go wrong in the cooperative layer. Variants carry the offending data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CoopError {
    /// A configuration value is out of range.
    #[error("bad cooperative configuration: `{field}` {reason}")]
    BadConfig {
        /// Name of the field.
        field: &'static str,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// The RON text of a configuration does not parse.
    #[error("cooperative configuration, line {line} column {column}: {problem}")]
    Ron {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong there (an unknown key names the nearest known one).
        problem: crate::core::config::RonProblem,
    },
    /// An observation of the object is not usable.
    #[error("object observation: {what} is {value} (must be finite{extra})")]
    BadReading {
        /// `range`, `bearing` or `self reliability`.
        what: &'static str,
        /// The value given.
        value: f32,
        /// Further condition (`" and ≥ 0"`, `" and in [0, 1]"`).
        extra: &'static str,
    },
    /// Grids to be fused do not share one geometry (paper 002 assumes one global frame).
    #[error("object grid {index} is {found_nx}×{found_ny} cells, the first is {nx}×{ny} (or origin/cell differ)")]
    GeometryMismatch {
        /// Position of the offending grid in the input.
        index: usize,
        /// Columns of the first grid.
        nx: usize,
        /// Rows of the first grid.
        ny: usize,
        /// Columns of the offending grid.
        found_nx: usize,
        /// Rows of the offending grid.
        found_ny: usize,
    },
    /// Nothing to fuse.
    #[error("no object grid to fuse")]
    Empty,
    /// A run-length code did not decode.
    #[error(transparent)]
    Rle(#[from] RleError),
    /// The self-localization grid could not be built.
    #[error(transparent)]
    Grid(#[from] crate::grid::GridError),
}
