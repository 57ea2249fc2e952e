//! Parameters of cooperative object localization, loadable from RON (`config/coop-*.ron`).
//! [`CoopConfig::default`] documents the defaults; the self grids have their own
//! [`crate::grid::GridConfig`].

use super::CoopError;
use crate::grid::SensorModel;
use serde::{Deserialize, Serialize};

/// All parameters of the object grids, the fusion, the estimate and the MRCLAM protocol.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CoopConfig {
    /// Range model of a robot's reading of the object: the trapezoid put around `ρ` (paper 000's
    /// `⟨r, Δ, α, 1, b⟩`, widths growing with the reading). Default: the same as the grid's
    /// landmark range model (core 0.1 m + 5 %, flank 0.2 m + 15 %, bias 0.1) — the robots wear
    /// the same barcoded tubes as the landmarks and are seen by the same camera.
    pub range: SensorModel,
    /// Bearing model of the reading of the object. Default: the grid's (core 0.06 rad, flank
    /// 0.1 rad, bias 0.1).
    pub bearing: SensorModel,
    /// Put the observer's self-localization reliability into the object grid's floor:
    /// `floor = 1 − min(reliability(observation), reliability(self))`. Paper 002 lets the
    /// self-localization's unreliability reach the object grid as the bias of `μ_r`; our self
    /// grids keep a bias of only `GridConfig::floor` (1e-8), so it is added here explicitly.
    /// `false` uses the observation's reliability alone (paper 002's algorithm (3) literally).
    /// Default true.
    pub self_reliability_in_floor: bool,
    /// Fraction of the maximum above which cells enter the centre of gravity (paper 002 eq. (2)
    /// is over the whole grid; a floor of 0.1 spread over a 15 m field would pull every estimate
    /// towards the middle of the field, so, as the self grid's estimate does, only the cells at
    /// or above `cog_cut · max` count, with weights `μ − min μ`). Default 0.5.
    pub cog_cut: f32,
    /// MRCLAM protocol: observations of one object robot by different robots belong to the same
    /// event when they fall within this window (s) from the event's first observation.
    /// Default 0.5 s (the robots drive at ≤ 0.2 m/s, so the object moves ≤ 0.1 m, one cell).
    pub window: f64,
    /// Fewest distinct observers an event needs. Default 2.
    pub min_observers: usize,
    /// An observer whose self-localization error exceeds this (m) counts as *lost*; the
    /// report has a separate row for the events with a lost observer (paper 002's case 3,
    /// where averaging suffers). Default 0.5 m.
    pub lost_self_error: f64,
}

impl Default for CoopConfig {
    fn default() -> Self {
        let g = crate::grid::GridConfig::default();
        CoopConfig {
            range: g.range,
            bearing: g.bearing,
            self_reliability_in_floor: true,
            cog_cut: 0.5,
            window: 0.5,
            min_observers: 2,
            lost_self_error: 0.5,
        }
    }
}

impl CoopConfig {
    /// Parses a RON document (missing fields take their defaults) and checks it.
    pub fn from_ron(text: &str) -> Result<Self, CoopError> {
        let cfg: CoopConfig = crate::core::config::from_ron(text).map_err(|e| CoopError::Ron {
            line: e.line,
            column: e.column,
            problem: e.problem,
        })?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Checks ranges; every consumer may assume a validated configuration.
    pub fn validate(&self) -> Result<(), CoopError> {
        for (field, m) in [("range", &self.range), ("bearing", &self.bearing)] {
            let widths = [m.core_abs, m.core_rel, m.slope_abs, m.slope_rel];
            if widths.iter().any(|v| !v.is_finite() || *v < 0.0) {
                return Err(CoopError::BadConfig {
                    field,
                    reason: "widths must be finite and ≥ 0",
                });
            }
            if !(0.0..=1.0).contains(&m.bias) {
                return Err(CoopError::BadConfig {
                    field,
                    reason: "bias must be in [0, 1]",
                });
            }
        }
        if !(0.0..=1.0).contains(&self.cog_cut) {
            return Err(CoopError::BadConfig {
                field: "cog_cut",
                reason: "must be in [0, 1]",
            });
        }
        if !(self.window.is_finite() && self.window >= 0.0) {
            return Err(CoopError::BadConfig {
                field: "window",
                reason: "must be finite and ≥ 0",
            });
        }
        if !(self.lost_self_error.is_finite() && self.lost_self_error >= 0.0) {
            return Err(CoopError::BadConfig {
                field: "lost_self_error",
                reason: "must be finite and ≥ 0",
            });
        }
        if self.min_observers < 1 {
            return Err(CoopError::BadConfig {
                field: "min_observers",
                reason: "must be ≥ 1",
            });
        }
        Ok(())
    }

    /// Reliability of one reading of the object: `1 − max(b_range, b_bearing)`, the
    /// possibility that neither part of it is an outlier.
    pub fn observation_reliability(&self) -> f32 {
        1.0 - self.range.bias.max(self.bearing.bias)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_unknown_keys_and_defaults_omitted_ones() {
        let ok = CoopConfig::from_ron("(min_observers: 3)").unwrap();
        assert_eq!(ok.min_observers, 3);
        assert_eq!(ok.window, CoopConfig::default().window);
        match CoopConfig::from_ron("(min_observers: 3, totally_bogus_field: 1)") {
            Err(CoopError::Ron { problem, .. }) => {
                let message = problem.to_string();
                assert!(message.contains("totally_bogus_field"), "{message}");
            }
            other => panic!("{other:?}"),
        }
    }
}
