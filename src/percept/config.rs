//! Extractor parameters, loaded from RON so that they live in files next to
//! the map and rules rather than in code. Depends on `ron`, `serde` and the
//! per-extractor config structs it aggregates.
//!
//! Every field has a documented default, and a RON file may give any subset:
//!
//! ```ron
//! (
//!     laser_line: (sector_half_width_deg: 30.0, pivot: Farthest),
//!     sonar_wall: (readings: 8, delta_max_m: 0.05),
//! )
//! ```

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::beacon::{BeaconConfig, LandmarkConfig};
use super::compass::CompassConfig;
use super::laser_line::LaserLineConfig;
use super::layout::LayoutConfig;
use super::scan::SideBeamConfig;
use super::sonar_wall::SonarWallConfig;

/// Why a configuration was rejected.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// The RON text does not parse or does not match the structure.
    #[error("extractor config: {0}")]
    Ron(#[from] crate::core::config::RonError),
    /// A field is out of its admissible range.
    #[error("extractor config: {field} = {value}: {reason}")]
    Invalid {
        /// Dotted field path, e.g. `sonar_wall.readings`.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// What it must satisfy.
        reason: &'static str,
    },
}

impl ConfigError {
    pub(crate) fn invalid(field: &'static str, value: f64, reason: &'static str) -> Self {
        ConfigError::Invalid {
            field,
            value,
            reason,
        }
    }
}

/// All extractor parameters.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExtractConfig {
    /// Eq. (3) on the front laser / structured light.
    pub laser_line: LaserLineConfig,
    /// Eq. (4) on side sonars.
    pub sonar_wall: SonarWallConfig,
    /// Which scan beams emulate side sonars.
    pub side_beams: SideBeamConfig,
    /// Eqs. (1)–(2) on beacon images.
    pub beacon: BeaconConfig,
    /// Landmark range/bearing readings.
    pub landmark: LandmarkConfig,
    /// Heading-invariant layout percepts of a scan (`corridor_width`, `side_openings`).
    pub layout: LayoutConfig,
    /// Axis-locked heading and compass free ranges (`free_range(Dir)`); off by default.
    pub compass: CompassConfig,
}

impl ExtractConfig {
    /// The settings `lplace extract` uses without `--config`: the defaults with the compass on
    /// (eight directions, each the longest of a 10° fan, the drift of the heading lock
    /// corrected at gain 0.5, the motion between scans from the scan match where it holds) and
    /// the initial heading taken from the first scan's odometry —
    /// nothing of one building, so that a new building needs only its map (whose `axis`
    /// statement gives the axis) and its log. `default()` keeps the compass off: it is what
    /// every field left out of a RON file falls back to.
    pub fn travelling() -> Self {
        let mut cfg = ExtractConfig::default();
        let c = &mut cfg.compass;
        c.enabled = true;
        c.drift_gain = 0.5;
        c.directions = 8;
        c.fan_deg = 10.0;
        c.fan_step_deg = 5.0;
        c.scan_match = true;
        cfg
    }

    /// Parses RON text; absent fields take their defaults. Validates.
    ///
    /// # Errors
    /// [`ConfigError`] on a syntax error or an out-of-range value.
    pub fn from_ron(text: &str) -> Result<Self, ConfigError> {
        let cfg: ExtractConfig = crate::core::config::from_ron(text)?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Checks every parameter's range.
    ///
    /// # Errors
    /// [`ConfigError::Invalid`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let l = &self.laser_line;
        positive("laser_line.sector_half_width_deg", l.sector_half_width_deg)?;
        non_negative("laser_line.min_range_m", l.min_range_m)?;
        positive("laser_line.max_range_m", l.max_range_m)?;
        positive("laser_line.std_unit_m", l.std_unit_m)?;
        if l.min_points < 2 {
            return Err(ConfigError::invalid(
                "laser_line.min_points",
                l.min_points as f64,
                "must be ≥ 2",
            ));
        }
        self.sonar_wall.validate()?;
        let s = &self.side_beams;
        finite("side_beams.left_bearing_deg", s.left_bearing_deg)?;
        finite("side_beams.right_bearing_deg", s.right_bearing_deg)?;
        non_negative("side_beams.cone_half_width_deg", s.cone_half_width_deg)?;
        self.beacon.validate()?;
        self.landmark.validate()?;
        self.layout.validate()?;
        self.compass.validate()
    }
}

pub(crate) fn finite(field: &'static str, v: f64) -> Result<(), ConfigError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(ConfigError::invalid(field, v, "must be finite"))
    }
}

pub(crate) fn positive(field: &'static str, v: f64) -> Result<(), ConfigError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(ConfigError::invalid(field, v, "must be finite and > 0"))
    }
}

pub(crate) fn non_negative(field: &'static str, v: f64) -> Result<(), ConfigError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(ConfigError::invalid(field, v, "must be finite and ≥ 0"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::percept::laser_line::PivotRule;

    #[test]
    fn partial_ron_keeps_defaults() {
        let cfg =
            ExtractConfig::from_ron("(laser_line: (pivot: Farthest), sonar_wall: (readings: 6))")
                .unwrap();
        assert_eq!(cfg.laser_line.pivot, PivotRule::Farthest);
        assert_eq!(cfg.sonar_wall.readings, 6);
        assert_eq!(cfg.sonar_wall.delta_max_m, 0.10);
        assert_eq!(cfg.laser_line.sector_half_width_deg, 45.0);
    }

    #[test]
    fn defaults_round_trip_through_ron() {
        let text = ron::to_string(&ExtractConfig::default()).unwrap();
        assert_eq!(
            ExtractConfig::from_ron(&text).unwrap(),
            ExtractConfig::default()
        );
    }

    #[test]
    fn travelling_settings_are_valid_and_differ_from_the_defaults_only_in_the_compass() {
        let t = ExtractConfig::travelling();
        t.validate().unwrap();
        assert!(t.compass.enabled && t.compass.initial_heading_deg.is_none());
        let d = ExtractConfig::default();
        assert_eq!(
            ExtractConfig {
                compass: d.compass,
                ..t
            },
            d
        );
    }

    #[test]
    fn invalid_values_and_syntax_are_typed() {
        assert!(matches!(
            ExtractConfig::from_ron("(sonar_wall: (readings: 40))"),
            Err(ConfigError::Invalid {
                field: "sonar_wall.readings",
                ..
            })
        ));
        assert!(matches!(
            ExtractConfig::from_ron("(laser_line: (std_unit_m: -1.0))"),
            Err(ConfigError::Invalid {
                field: "laser_line.std_unit_m",
                ..
            })
        ));
        assert!(matches!(
            ExtractConfig::from_ron("(laser_line: "),
            Err(ConfigError::Ron(_))
        ));
    }
}
