//! What a run looks like to a person: the summary of an evaluated stream (counts, accuracy
//! against ground truth, confusion matrix, kidnap recoveries) and the SVG run-time display of
//! paper 003's Fig. 3 unrolled over time. Both are fed one frame at a time with bounded memory.
//!
//! Depends on `logic` (decisions, distributions) and `io::stream` (frame meta data, rejections);
//! nothing depends on it except the command line.

pub mod plot;
pub mod summary;
pub mod sweep;
pub mod trajectory;

pub use plot::RunPlot;
pub use summary::{Summary, Tally};
