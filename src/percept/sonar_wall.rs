//! The `sonar_wall(side)` percept of paper 003 §4, eq. (4):
//! `δ_w = min(Δ/Δmax, 1)`, with `Δ` the RMS orthogonal dispersion of a line
//! fitted to the last `N` (8 in the paper) side-sonar echoes taken at
//! significantly different robot poses. Depends on
//! [`crate::percept::line_fit`] and the record types.
//!
//! Each echo is placed in the odometry (world) frame when it is taken — a
//! reading of range `r` from a sensor mounted at `(mx, my)` with angle `ma`
//! in the robot frame, with the robot at `(x, y, θ)`, hits
//! `(x, y) + R(θ)·((mx, my) + r·(cos ma, sin ma))` — so that readings from
//! different poses can be fitted together. This is the only stateful
//! extractor: [`SonarWall`] keeps a fixed-capacity ring buffer and never
//! allocates after construction.
//!
//! A robot with a 2-D laser and no sonar (the CARMEN logs) uses the beams
//! near ±90° as side sonars; see [`crate::percept::scan`].
//!
//! Choices where the paper is silent: a reading is *kept* only when the robot
//! has travelled at least `min_travel_m` or turned at least `min_turn_deg`
//! since the last kept reading; readings with no echo (outside
//! `[min_range_m, max_range_m)`) are dropped without clearing the buffer;
//! the percept has no support (`δ_w = 1`) until the buffer holds
//! `readings` points.

use nalgebra::Point2;
use serde::{Deserialize, Serialize};

use super::config::ConfigError;
use super::line_fit::{fit_line, LineFit};
use super::{PerceptArg, PerceptKind, PerceptRecord, Side};
use crate::core::Pose2;

/// Most readings a [`SonarWall`] can hold.
pub const MAX_READINGS: usize = 32;

/// Where a range sensor sits on the robot: position (metres) and pointing
/// angle (radians, CCW from the heading), robot frame.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorMount {
    /// Forward offset, metres.
    pub x: f64,
    /// Leftward offset, metres.
    pub y: f64,
    /// Pointing angle, radians.
    pub angle: f64,
}

/// Parameters of the sonar-wall extractor. RON-loadable; every field has a default.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SonarWallConfig {
    /// Readings per fit, 2..=[`MAX_READINGS`]. Default 8 (the paper's).
    pub readings: usize,
    /// Minimum robot travel between kept readings, metres. Default 0.2.
    pub min_travel_m: f64,
    /// Alternatively, minimum robot rotation between kept readings, degrees. Default 15.
    pub min_turn_deg: f64,
    /// `Δmax` of eq. (4), metres: dispersion at which a fit is worthless. Default 0.10.
    pub delta_max_m: f64,
    /// Echoes closer than this are dropped, metres. Default 0.05.
    pub min_range_m: f64,
    /// Echoes at or beyond this are "no echo", metres. Default 5.0.
    pub max_range_m: f64,
}

impl Default for SonarWallConfig {
    fn default() -> Self {
        SonarWallConfig {
            readings: 8,
            min_travel_m: 0.2,
            min_turn_deg: 15.0,
            delta_max_m: 0.10,
            min_range_m: 0.05,
            max_range_m: 5.0,
        }
    }
}

impl SonarWallConfig {
    /// Checks ranges of every field.
    ///
    /// # Errors
    /// [`ConfigError::Invalid`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if !(2..=MAX_READINGS).contains(&self.readings) {
            return Err(ConfigError::invalid(
                "sonar_wall.readings",
                self.readings as f64,
                "must be in 2..=32",
            ));
        }
        for (field, v) in [
            ("sonar_wall.min_travel_m", self.min_travel_m),
            ("sonar_wall.min_turn_deg", self.min_turn_deg),
            ("sonar_wall.min_range_m", self.min_range_m),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(ConfigError::invalid(field, v, "must be finite and ≥ 0"));
            }
        }
        for (field, v) in [
            ("sonar_wall.delta_max_m", self.delta_max_m),
            ("sonar_wall.max_range_m", self.max_range_m),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(ConfigError::invalid(field, v, "must be finite and > 0"));
            }
        }
        Ok(())
    }
}

/// What [`SonarWall::push`] did with a reading.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PushOutcome {
    /// Stored (possibly evicting the oldest).
    Kept,
    /// The robot has not moved enough since the last kept reading.
    TooClose,
    /// No echo: out of `[min_range_m, max_range_m)`.
    NoEcho,
    /// Range, pose or mount not finite.
    NonFinite,
}

/// The result of eq. (4) for one side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SonarWallOutcome {
    /// Which side.
    pub side: Side,
    /// The fitted wall, when the buffer is full and the fit defined.
    pub fit: Option<LineFit>,
    /// `δ_w`.
    pub delta: f64,
    /// Distance from the robot to the fitted wall, metres.
    pub distance: Option<f64>,
}

impl SonarWallOutcome {
    /// The `sonar_wall(side)` record.
    pub fn record(&self) -> PerceptRecord {
        PerceptRecord::from_delta(
            PerceptKind::SonarWall,
            PerceptArg::Side(self.side),
            self.distance,
            self.delta,
        )
    }
}

/// `δ_w = min(Δ/Δmax, 1)`; NaN or non-positive `Δmax` gives 1.
pub fn delta_wall(dispersion: f64, delta_max: f64) -> f64 {
    if delta_max.is_nan() || delta_max <= 0.0 || dispersion.is_nan() {
        return 1.0;
    }
    (dispersion / delta_max).clamp(0.0, 1.0)
}

/// Side-wall detector for one side of the robot.
///
/// # Complexity
/// `push` is `O(1)`; `evaluate` fits at most [`MAX_READINGS`] points, `O(N)`.
/// Neither allocates.
///
/// # Example
/// ```
/// use lplace::core::Pose2;
/// use lplace::percept::sonar_wall::{SensorMount, SonarWall, SonarWallConfig};
/// use lplace::percept::Side;
/// let mut w = SonarWall::new(Side::Left, SonarWallConfig::default()).unwrap();
/// let left = SensorMount { x: 0.0, y: 0.0, angle: std::f64::consts::FRAC_PI_2 };
/// // Drive along +x with a wall 1 m to the left.
/// for k in 0..10 {
///     w.push(Pose2 { x: 0.3 * k as f64, y: 0.0, theta: 0.0 }, &left, 1.0);
/// }
/// let out = w.evaluate(&Pose2 { x: 3.0, y: 0.0, theta: 0.0 });
/// assert!(out.delta < 1e-9);
/// assert!((out.distance.unwrap() - 1.0).abs() < 1e-9);
/// ```
#[derive(Debug, Clone)]
pub struct SonarWall {
    side: Side,
    cfg: SonarWallConfig,
    points: [Point2<f64>; MAX_READINGS],
    len: usize,
    head: usize,
    last_kept: Option<Pose2>,
}

impl SonarWall {
    /// A detector with an empty buffer.
    ///
    /// # Errors
    /// [`ConfigError`] when `cfg` fails [`SonarWallConfig::validate`].
    pub fn new(side: Side, cfg: SonarWallConfig) -> Result<Self, ConfigError> {
        cfg.validate()?;
        Ok(SonarWall {
            side,
            cfg,
            points: [Point2::origin(); MAX_READINGS],
            len: 0,
            head: 0,
            last_kept: None,
        })
    }

    /// Which side this detector watches.
    pub fn side(&self) -> Side {
        self.side
    }

    /// Number of readings held.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when no reading is held.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Forgets every reading (e.g. after a relocalisation jump).
    pub fn clear(&mut self) {
        self.len = 0;
        self.head = 0;
        self.last_kept = None;
    }

    /// Offers a reading taken at `pose` by a sensor at `mount`.
    pub fn push(&mut self, pose: Pose2, mount: &SensorMount, range: f64) -> PushOutcome {
        let finite = [
            range,
            pose.x,
            pose.y,
            pose.theta,
            mount.x,
            mount.y,
            mount.angle,
        ]
        .iter()
        .all(|v| v.is_finite());
        if !finite {
            return PushOutcome::NonFinite;
        }
        if range < self.cfg.min_range_m || range >= self.cfg.max_range_m {
            return PushOutcome::NoEcho;
        }
        if let Some(last) = self.last_kept {
            let travel = (pose.x - last.x).hypot(pose.y - last.y);
            let turn = crate::core::angle::wrap_pi(pose.theta - last.theta).abs();
            if travel < self.cfg.min_travel_m && turn < self.cfg.min_turn_deg.to_radians() {
                return PushOutcome::TooClose;
            }
        }
        let (s, c) = pose.theta.sin_cos();
        let (ms, mc) = mount.angle.sin_cos();
        let lx = mount.x + range * mc;
        let ly = mount.y + range * ms;
        let p = Point2::new(pose.x + c * lx - s * ly, pose.y + s * lx + c * ly);
        let cap = self.cfg.readings;
        self.points[self.head] = p;
        self.head = (self.head + 1) % cap;
        self.len = (self.len + 1).min(cap);
        self.last_kept = Some(pose);
        PushOutcome::Kept
    }

    /// Eq. (4) on the readings held, seen from `pose`.
    pub fn evaluate(&self, pose: &Pose2) -> SonarWallOutcome {
        let unsupported = SonarWallOutcome {
            side: self.side,
            fit: None,
            delta: 1.0,
            distance: None,
        };
        if self.len < self.cfg.readings {
            return unsupported;
        }
        let Ok(fit) = fit_line(&self.points[..self.len]) else {
            return unsupported;
        };
        let distance = fit.signed_distance(&Point2::new(pose.x, pose.y)).abs();
        SonarWallOutcome {
            side: self.side,
            fit: Some(fit),
            delta: delta_wall(fit.rms_dispersion, self.cfg.delta_max_m),
            distance: Some(distance),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LEFT: SensorMount = SensorMount {
        x: 0.0,
        y: 0.0,
        angle: std::f64::consts::FRAC_PI_2,
    };

    #[test]
    fn readings_too_close_are_not_kept_and_buffer_wraps() {
        let mut w = SonarWall::new(Side::Left, SonarWallConfig::default()).unwrap();
        assert_eq!(w.push(Pose2::default(), &LEFT, 1.0), PushOutcome::Kept);
        // 0.1 m < 0.2 m, no turn.
        assert_eq!(
            w.push(
                Pose2 {
                    x: 0.1,
                    y: 0.0,
                    theta: 0.0
                },
                &LEFT,
                1.0
            ),
            PushOutcome::TooClose
        );
        // A 20° turn in place counts as a new pose.
        assert_eq!(
            w.push(
                Pose2 {
                    x: 0.0,
                    y: 0.0,
                    theta: 0.35
                },
                &LEFT,
                1.0
            ),
            PushOutcome::Kept
        );
        assert_eq!(
            w.push(
                Pose2 {
                    x: 5.0,
                    y: 0.0,
                    theta: 0.0
                },
                &LEFT,
                9.0
            ),
            PushOutcome::NoEcho
        );
        assert_eq!(
            w.push(
                Pose2 {
                    x: 5.0,
                    y: 0.0,
                    theta: 0.0
                },
                &LEFT,
                f64::NAN
            ),
            PushOutcome::NonFinite
        );
        for k in 0..20 {
            w.push(
                Pose2 {
                    x: k as f64,
                    y: 0.0,
                    theta: 0.0,
                },
                &LEFT,
                1.0,
            );
        }
        assert_eq!(w.len(), 8);
    }

    #[test]
    fn not_full_is_unsupported() {
        let mut w = SonarWall::new(Side::Right, SonarWallConfig::default()).unwrap();
        for k in 0..7 {
            w.push(
                Pose2 {
                    x: k as f64,
                    y: 0.0,
                    theta: 0.0,
                },
                &LEFT,
                1.0,
            );
        }
        let r = w.evaluate(&Pose2::default()).record();
        assert_eq!((r.delta, r.degree, r.value), (1.0, 0.0, None));
    }

    #[test]
    fn zigzag_wall_dispersion_maps_linearly() {
        // Ranges 1.0 / 1.04 in the pattern a b b a a b b a: points at y = 1
        // and 1.04, balanced about the centre x so the scatter has no x–y
        // correlation; the fitted line is y = 1.02 and every point is
        // 0.02 m away → Δ = 0.02, δ_w = 0.02/0.10 = 0.2.
        let mut w = SonarWall::new(Side::Left, SonarWallConfig::default()).unwrap();
        for k in 0..8 {
            let r = if matches!(k, 0 | 3 | 4 | 7) {
                1.0
            } else {
                1.04
            };
            w.push(
                Pose2 {
                    x: 0.5 * k as f64,
                    y: 0.0,
                    theta: 0.0,
                },
                &LEFT,
                r,
            );
        }
        let out = w.evaluate(&Pose2 {
            x: 3.5,
            y: 0.0,
            theta: 0.0,
        });
        assert!((out.delta - 0.2).abs() < 1e-9, "{}", out.delta);
        assert!((out.distance.unwrap() - 1.02).abs() < 1e-9);
    }

    #[test]
    fn bad_config_rejected() {
        let cfg = SonarWallConfig {
            readings: 1,
            ..Default::default()
        };
        assert!(SonarWall::new(Side::Left, cfg).is_err());
        let cfg = SonarWallConfig {
            delta_max_m: 0.0,
            ..Default::default()
        };
        assert!(SonarWall::new(Side::Left, cfg).is_err());
    }
}
