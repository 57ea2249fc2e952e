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

    /// The increment calibrated against ground truth: translation (forward and left) times
    /// `translation`, rotation times `rotation`. Factors of 1 give the increment unchanged, bit
    /// for bit.
    ///
    /// # Example
    /// ```
    /// use lplace::core::Odometry;
    /// let o = Odometry { forward: 1.0, left: 0.5, turn: 0.2 }.scaled(0.5, 2.0);
    /// assert_eq!((o.forward, o.left, o.turn), (0.5, 0.25, 0.4));
    /// ```
    pub fn scaled(&self, translation: f64, rotation: f64) -> Odometry {
        Odometry {
            forward: self.forward * translation,
            left: self.left * translation,
            turn: self.turn * rotation,
        }
    }

    /// The increment with each component rounded to single precision (and back, exactly).
    ///
    /// The metric methods share the Fuzzy Position Grid's single precision: the driver rounds
    /// once, here at the edge, so that the grid, which works in `f32`, and the methods that
    /// compute in `f64` are fed the very same numbers. A component beyond `f32`'s range becomes
    /// infinite, which every localizer rejects.
    ///
    /// # Example
    /// ```
    /// use lplace::core::Odometry;
    /// let o = Odometry { forward: 0.1, left: 0.0, turn: 1e39 }.to_single_precision();
    /// assert_eq!(o.forward, 0.1f32 as f64);
    /// assert!(o.turn.is_infinite());
    /// ```
    pub fn to_single_precision(&self) -> Odometry {
        Odometry {
            forward: self.forward as f32 as f64,
            left: self.left as f32 as f64,
            turn: self.turn as f32 as f64,
        }
    }
}
