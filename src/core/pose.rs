//! The planar pose: metres and radians, θ counter-clockwise from +x.

use serde::{Deserialize, Serialize};

/// A planar pose in a metric frame.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose2 {
    /// x, metres.
    pub x: f64,
    /// y, metres.
    pub y: f64,
    /// Heading, radians, counter-clockwise from +x.
    pub theta: f64,
}

impl Pose2 {
    /// A pose from its three coordinates.
    pub const fn new(x: f64, y: f64, theta: f64) -> Self {
        Pose2 { x, y, theta }
    }
}
