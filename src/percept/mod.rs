//! Percept extraction: from raw geometry (laser scans, sonar readings,
//! binary camera images, landmark sightings) to named percepts with degrees,
//! following paper 003 §4, eqs. (1)–(4).
//!
//! Responsibility: pure numeric extractors plus the small amount of state the
//! sonar-wall percept needs (a ring buffer of recent readings). Within the crate
//! this module may depend on `core` only (poses, angles, the configuration
//! reader), outside it on `nalgebra`, `serde` and `thiserror`; it knows
//! nothing about rules, maps or the engine — the engine maps
//! [`PerceptRecord`]s into its own percept frame.
//!
//! # Degree convention
//! Paper 003 writes each percept's weight as a *dissimilarity* `δ ∈ [0, 1]`,
//! 0 meaning a perfect match with the prototype (a straight wall, a V corner,
//! the ideal beacon image). The engine stores **degree = 1 − δ**, so 1 means
//! "fully supported". Every record carries both. With `min` as the engine's
//! conjunction, `1 − max(δa, δb) = min(1 − δa, 1 − δb)`, so the paper's
//! max-of-dissimilarities is reproduced exactly.
//!
//! When an extractor cannot evaluate its percept at all (too few points, no
//! echo, no beacon in the image) it reports `δ = 1`, degree 0 and no value:
//! "no support", which is what the possibilistic reading of missing evidence is.

pub mod beacon;
pub mod compass;
pub mod config;
pub mod image;
pub mod laser_line;
pub mod layout;
pub mod line_fit;
pub mod scan;
pub mod scan_match;
pub mod scan_rotation;
pub mod sonar_wall;

use serde::{Deserialize, Serialize};

pub use config::{ConfigError, ExtractConfig};
pub use line_fit::{fit_line, LineFit, LineFitError};
pub use scan::ScanExtractor;

/// Which percept a record is; serialised in `snake_case` as the rule files
/// name them (`laser_wall`, `sonar_wall`, …).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PerceptKind {
    /// Beacon orientation, eq. (2) `β_θ`. Value: radians.
    BeaconAngle,
    /// Beacon distance, eq. (2) `β_d`. Value: metres.
    BeaconDistance,
    /// Structured light / front laser sees a wall, eq. (3) `δ_f`. Value: metres.
    LaserWall,
    /// Structured light / front laser sees a corner, eq. (3) `δ_c`. Value: metres.
    LaserCorner,
    /// Side sonar sees a wall, eq. (4) `δ_w`. Value: metres.
    SonarWall,
    /// Range to an identified landmark. Value: metres.
    LandmarkRange,
    /// Bearing to an identified landmark. Value: radians, CCW from heading.
    LandmarkBearing,
}

impl PerceptKind {
    /// The name used in rule files.
    pub fn as_str(self) -> &'static str {
        match self {
            PerceptKind::BeaconAngle => "beacon_angle",
            PerceptKind::BeaconDistance => "beacon_distance",
            PerceptKind::LaserWall => "laser_wall",
            PerceptKind::LaserCorner => "laser_corner",
            PerceptKind::SonarWall => "sonar_wall",
            PerceptKind::LandmarkRange => "landmark_range",
            PerceptKind::LandmarkBearing => "landmark_bearing",
        }
    }
}

/// A direction relative to the robot's heading.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// Ahead of the robot.
    Front,
    /// To the robot's left (+90°).
    Left,
    /// To the robot's right (−90°).
    Right,
}

/// The argument a percept is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PerceptArg {
    /// No argument.
    None,
    /// A side of the robot (sonar walls, laser wall/corner ahead).
    Side(Side),
    /// A landmark or beacon id.
    Landmark(u32),
}

/// One percept with its measured value and degree.
///
/// Invariants (enforced by [`PerceptRecord::from_delta`]): `delta` and
/// `degree` are finite, in `[0, 1]`, and `degree == 1 − delta`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PerceptRecord {
    /// Which percept.
    pub kind: PerceptKind,
    /// What it is about.
    pub arg: PerceptArg,
    /// The measured value (units documented on [`PerceptKind`]), if any.
    pub value: Option<f64>,
    /// Engine degree, `1 − delta`; 1 = fully supported.
    pub degree: f64,
    /// Paper 003 dissimilarity; 0 = perfect match with the prototype.
    pub delta: f64,
}

impl PerceptRecord {
    /// Builds a record from the paper's dissimilarity. A NaN `delta` becomes
    /// 1 (no support) and values outside `[0, 1]` are clamped, so a record
    /// never carries a NaN degree whatever the sensor produced. A non-finite
    /// `value` is dropped for the same reason.
    pub fn from_delta(kind: PerceptKind, arg: PerceptArg, value: Option<f64>, delta: f64) -> Self {
        let delta = if delta.is_nan() {
            1.0
        } else {
            delta.clamp(0.0, 1.0)
        };
        PerceptRecord {
            kind,
            arg,
            value: value.filter(|v| v.is_finite()),
            degree: 1.0 - delta,
            delta,
        }
    }

    /// A record that says "no evidence": `δ = 1`, degree 0, no value.
    pub fn unsupported(kind: PerceptKind, arg: PerceptArg) -> Self {
        Self::from_delta(kind, arg, None, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn record_degree_is_one_minus_delta_and_sanitised() {
        let r =
            PerceptRecord::from_delta(PerceptKind::LaserWall, PerceptArg::None, Some(1.5), 0.25);
        assert_eq!((r.delta, r.degree), (0.25, 0.75));
        let r = PerceptRecord::from_delta(
            PerceptKind::LaserWall,
            PerceptArg::None,
            Some(f64::NAN),
            f64::NAN,
        );
        assert_eq!((r.delta, r.degree, r.value), (1.0, 0.0, None));
        let r = PerceptRecord::from_delta(PerceptKind::LaserWall, PerceptArg::None, None, -3.0);
        assert_eq!((r.delta, r.degree), (0.0, 1.0));
    }

    #[test]
    fn min_of_degrees_equals_one_minus_max_of_deltas() {
        // Paper eq. (6) β = max(β_θ, β_d) against the engine's min conjunction.
        for &(a, b) in &[(0.1, 0.7), (0.9, 0.2), (0.0, 1.0), (0.5, 0.5)] {
            let ra = PerceptRecord::from_delta(PerceptKind::BeaconAngle, PerceptArg::None, None, a);
            let rb =
                PerceptRecord::from_delta(PerceptKind::BeaconDistance, PerceptArg::None, None, b);
            let lhs = ra.degree.min(rb.degree);
            let rhs = 1.0 - f64::max(a, b);
            assert!((lhs - rhs).abs() < 1e-15);
        }
    }

    #[test]
    fn kind_serialises_as_rule_name() {
        for k in [
            PerceptKind::BeaconAngle,
            PerceptKind::BeaconDistance,
            PerceptKind::LaserWall,
            PerceptKind::LaserCorner,
            PerceptKind::SonarWall,
            PerceptKind::LandmarkRange,
            PerceptKind::LandmarkBearing,
        ] {
            let json = serde_json::to_string(&k).unwrap();
            assert_eq!(json, format!("\"{}\"", k.as_str()));
        }
    }
}
