//! The project's vocabulary: the few types and conversions every layer shares — a planar pose,
//! one odometry increment in SI units, angle wrapping, the compass directions, the seeded random
//! generator, the one reader of RON configuration files, the edit distance behind "did you
//! mean", and paper 000's one trapezoid (f32 or f64) with its two named bias readings.
//!
//! Everything above uses these and nothing else for the same idea; unit conversions (degrees in
//! streams, velocities in MRCLAM files, ODOM poses in CARMEN logs) happen at the readers and
//! writers in `io`, never inside the models. Depends on nothing in the crate.

pub mod angle;
pub mod compass;
pub mod config;
pub mod odometry;
pub mod pose;
pub mod rng;
pub mod spelling;
pub mod trapezoid;

pub use odometry::Odometry;
pub use pose::Pose2;
