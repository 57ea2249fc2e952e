//! The metric input: what a localizer is fed per frame — the odometry since the previous frame,
//! the range/bearing readings taken at the frame's time and, for scoring, the true pose — and
//! the ground-truth track the truth is interpolated from.
//!
//! Readers (`io::mrclam`, the percept stream's converter) build these from their files; every
//! quantity is in SI units (metres, radians, seconds) by then. Depends on `core` only.

use crate::core::angle::wrap_pi;
use crate::core::{Odometry, Pose2};
use serde::{Deserialize, Serialize};

/// One range + bearing reading of a subject.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LandmarkReading {
    /// Subject id (in MRCLAM: landmarks 6–20; robots 1–5 are kept for cooperative use).
    pub subject: u32,
    /// Range (m).
    pub range: f64,
    /// Bearing (rad, robot frame, counter-clockwise).
    pub bearing: f64,
}

/// One step of the metric stream: motion since the previous frame, what was seen at `t`, and
/// where the robot truly was.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MetricFrame {
    /// Time (s).
    pub t: f64,
    /// Seconds since the previous frame (0 for the first): the time the odometry covers.
    pub dt: f64,
    /// Odometry since the previous frame, in the robot frame at the previous frame.
    pub odometry: Odometry,
    /// Readings taken at `t`.
    pub observations: Vec<LandmarkReading>,
    /// Ground-truth pose at `t`, when available.
    pub truth: Option<Pose2>,
}

/// One sample of a ground-truth track: a time and the pose then.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TruthRow {
    /// Time (s).
    pub t: f64,
    /// x (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// Heading (rad).
    pub theta: f64,
}

/// Ground truth at `t` from a time-ordered track, linearly interpolated (heading the short way
/// round); `None` outside the track or across a gap longer than `max_gap`.
///
/// # Complexity
///
/// O(log samples).
pub fn interpolate_truth(truth: &[TruthRow], t: f64, max_gap: f64) -> Option<Pose2> {
    let k = truth.partition_point(|r| r.t <= t);
    if k == 0 {
        return None;
    }
    let a = truth[k - 1];
    if a.t == t || k == truth.len() {
        return (a.t == t).then_some(Pose2 {
            x: a.x,
            y: a.y,
            theta: wrap_pi(a.theta),
        });
    }
    let b = truth[k];
    if b.t - a.t > max_gap {
        return None;
    }
    let u = (t - a.t) / (b.t - a.t);
    Some(Pose2 {
        x: a.x + u * (b.x - a.x),
        y: a.y + u * (b.y - a.y),
        theta: wrap_pi(a.theta + u * wrap_pi(b.theta - a.theta)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn truth_is_interpolated_the_short_way() {
        // Samples 1 s apart; heading from 3.0 to −2.9 rad crosses ±π: the short way is
        // 2π − 5.9 ≈ 0.383 rad, so half way is 3.0 + 0.192 = 3.192, which wraps to 3.192 − 2π.
        let track = [
            TruthRow {
                t: 0.0,
                x: 0.0,
                y: 0.0,
                theta: 3.0,
            },
            TruthRow {
                t: 1.0,
                x: 2.0,
                y: -4.0,
                theta: -2.9,
            },
            TruthRow {
                t: 5.0,
                x: 9.0,
                y: 9.0,
                theta: 0.0,
            },
        ];
        let p = interpolate_truth(&track, 0.5, 1.0).unwrap();
        assert_eq!((p.x, p.y), (1.0, -2.0));
        let tau = std::f64::consts::TAU;
        let half = 3.0 + 0.5 * (tau - 5.9);
        assert!((p.theta - (half - tau)).abs() < 1e-12, "{}", p.theta);
        // Outside the track, and across the 4 s gap with max_gap 1: none.
        assert_eq!(interpolate_truth(&track, -0.1, 1.0), None);
        assert_eq!(interpolate_truth(&track, 5.1, 1.0), None);
        assert_eq!(interpolate_truth(&track, 3.0, 1.0), None);
        // The last sample itself is known.
        assert_eq!(interpolate_truth(&track, 5.0, 1.0).map(|p| p.x), Some(9.0));
    }
}
