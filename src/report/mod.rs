//! What a run looks like to a person: the summary of an evaluated stream (counts, accuracy
//! against ground truth, confusion matrix, kidnap recoveries) and the SVG run-time display of
//! paper 003's Fig. 3 unrolled over time. Both are fed one frame at a time with bounded memory.
//!
//! `batch` is the one-row-per-stream table of a batch evaluation; `html` is `lplace report`'s
//! self-contained page of one or more runs.
//!
//! `run` is the per-frame loop of an evaluated stream (engine, tracker, tally), shared by the
//! command line and the Python binding.
//!
//! `grid_svg` draws one frame of the Fuzzy Position Grid (`lplace grid --svg`), `sweep` the
//! perturbation sweep of `lplace compare`, `scans` a laser log's scans at their poses with a
//! map's places over them (`lplace draw`: the picture a floor plan is read off); `axis` holds what the pictures share (round ticks,
//! the metre scale bar, the possibility colour scale).
//!
//! Depends on `logic` (decisions, distributions), `engine` (the run's engine and tracker),
//! `grid` (the plane drawn by `grid_svg`), `io::stream` (frame meta data, rejections) and
//! `io::carmen` (the scans `scans` draws);
//! nothing depends on it except the command line and the Python binding.

pub mod axis;
pub mod batch;
pub mod grid_svg;
pub mod html;
pub mod plot;
pub mod run;
pub mod scans;
pub mod summary;
pub mod sweep;
pub mod trajectory;

pub use plot::RunPlot;
pub use run::StreamRun;
pub use summary::{Summary, Tally};
