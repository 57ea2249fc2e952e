//! One odometry increment, in SI units, in the robot's frame at the start of the increment.
//!
//! Readers convert whatever their source records (degrees in percept streams, velocities and
//! time steps in MRCLAM, successive ODOM poses in CARMEN) into this one type.

use serde::{Deserialize, Serialize};

/// Motion since the previous frame: metres forward and to the left, radians turned
/// counter-clockwise, all in the robot's frame at the previous frame.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Odometry {
    /// Metres along the heading at the start.
    pub forward: f64,
    /// Metres to the left of it.
    pub left: f64,
    /// Radians turned, counter-clockwise.
    pub turn: f64,
}

impl Odometry {
    /// Distance travelled in the plane, metres.
    pub fn distance(&self) -> f64 {
        self.forward.hypot(self.left)
    }
}
