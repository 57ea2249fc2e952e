//! Heading-invariant layout percepts of a planar laser scan: `corridor_width`
//! and `side_openings`. Paper 003's percepts are tied to compass directions
//! (a wall *North*), which a robot can only use when it knows its heading;
//! raw odometry heading drifts by tens of degrees within minutes in real
//! logs (the Intel Research Lab log drifts by more than 90°), so a map drawn
//! by compass direction cannot be matched. These two percepts describe the
//! free space around the robot in a way that does not change when the robot
//! turns round in a corridor, so a place can state one expected value per
//! percept (`param W`, `param O` in the map) whatever the direction of travel.
//! Depends on the scan view and record types only.
//!
//! # Definitions (robot frame, bearings CCW from the heading)
//! * **side distance** on the left: the shortest valid range among the beams
//!   with bearing in `[90° − side_cone_deg, 90°]`; on the right, in
//!   `[−90°, −90° + side_cone_deg]`. In a straight corridor the shortest
//!   range towards a wall is its perpendicular distance when the foot of the
//!   perpendicular lies inside that sector; when the robot is turned by `φ`
//!   from the corridor's axis, one foot falls behind the 180° scan and that
//!   side reads `d / cos φ` (< 2 % long for |φ| ≤ 10°, 15 % at 30°). So the sum
//!   is the corridor's width, whichever way the robot faces along it.
//! * `corridor_width` — value: left + right side distance, metres; degree 1
//!   when both sides have a return below `max_range_m`, else no support.
//! * `side_openings` — value: how many sides (0, 1 or 2) show an opening:
//!   at least `opening_min_beams` consecutive beams with bearing within
//!   `opening_cone_deg` of ±90° whose range exceeds that side's distance by
//!   `opening_depth_m` (a doorway or a side corridor). Degree 1 whenever the
//!   scan has any valid beam. Swapping left and right leaves it unchanged.
//!
//! Both are dimensionally what a place's map entry can state, and neither
//! needs the robot's pose.

use serde::{Deserialize, Serialize};

use super::config::{non_negative, positive, ConfigError};
use super::scan::ScanView;

/// Parameters of the layout percepts. RON-loadable; every field has a default.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LayoutConfig {
    /// Width of the sector next to ±90° searched for the side distance, degrees. Default 40.
    pub side_cone_deg: f64,
    /// Width of the sector next to ±90° searched for openings, degrees. Default 50.
    pub opening_cone_deg: f64,
    /// How much farther than the side distance a beam must reach to look through an
    /// opening, metres. Default 1.5.
    pub opening_depth_m: f64,
    /// Fewest consecutive such beams that make an opening. Default 6.
    pub opening_min_beams: usize,
    /// Ranges below this are self-hits, metres. Default 0.05.
    pub min_range_m: f64,
    /// Ranges at or above this are "no return", metres. Default 40.
    pub max_range_m: f64,
}

impl Default for LayoutConfig {
    fn default() -> Self {
        LayoutConfig {
            side_cone_deg: 40.0,
            opening_cone_deg: 50.0,
            opening_depth_m: 1.5,
            opening_min_beams: 6,
            min_range_m: 0.05,
            max_range_m: 40.0,
        }
    }
}

impl LayoutConfig {
    /// Checks every parameter's range.
    ///
    /// # Errors
    /// [`ConfigError::Invalid`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        positive("layout.side_cone_deg", self.side_cone_deg)?;
        positive("layout.opening_cone_deg", self.opening_cone_deg)?;
        non_negative("layout.opening_depth_m", self.opening_depth_m)?;
        if self.opening_min_beams == 0 {
            return Err(ConfigError::invalid(
                "layout.opening_min_beams",
                0.0,
                "must be ≥ 1",
            ));
        }
        non_negative("layout.min_range_m", self.min_range_m)?;
        positive("layout.max_range_m", self.max_range_m)
    }
}

/// One layout percept: its rule-file name, measured value and degree (1 = fully supported).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LayoutRecord {
    /// `corridor_width` or `side_openings`.
    pub name: &'static str,
    /// The measured value (metres, or a count), when there is one.
    pub value: Option<f64>,
    /// Engine degree in `[0, 1]`.
    pub degree: f64,
}

/// The layout percepts of one scan: `[corridor_width, side_openings]`.
///
/// # Complexity
/// `O(n)` in the number of beams; no allocation.
///
/// # Example
/// ```
/// use lplace::percept::layout::{layout, LayoutConfig};
/// use lplace::percept::scan::ScanView;
/// use lplace::core::Pose2;
/// use std::f64::consts::{FRAC_PI_2, PI};
/// // A 2 m wide corridor, robot in the middle facing along it.
/// let ranges: Vec<f64> = (0..180)
///     .map(|i| (1.0 / (-FRAC_PI_2 + i as f64 * PI / 180.0).sin().abs()).min(30.0))
///     .collect();
/// let view = ScanView { pose: Pose2::default(), ranges: &ranges, first_bearing: -FRAC_PI_2,
///     bearing_step: PI / 180.0, laser_offset_x: 0.0 };
/// let [w, o] = layout(&view, &LayoutConfig::default());
/// assert!((w.value.unwrap() - 2.0).abs() < 0.01);
/// assert_eq!(o.value, Some(0.0));
/// ```
pub fn layout(scan: &ScanView<'_>, cfg: &LayoutConfig) -> [LayoutRecord; 2] {
    let left = side(scan, cfg, 1.0);
    let right = side(scan, cfg, -1.0);
    let width = match (left.distance, right.distance) {
        (Some(l), Some(r)) => LayoutRecord {
            name: "corridor_width",
            value: Some(l + r),
            degree: 1.0,
        },
        _ => LayoutRecord {
            name: "corridor_width",
            value: None,
            degree: 0.0,
        },
    };
    let any = left.valid || right.valid;
    let openings = LayoutRecord {
        name: "side_openings",
        value: any.then_some(f64::from(u8::from(left.opening) + u8::from(right.opening))),
        degree: if any { 1.0 } else { 0.0 },
    };
    [width, openings]
}

struct SideLook {
    distance: Option<f64>,
    opening: bool,
    valid: bool,
}

/// Side distance and opening on the side `sign` (+1 left, −1 right).
fn side(scan: &ScanView<'_>, cfg: &LayoutConfig, sign: f64) -> SideLook {
    let ok_step =
        scan.bearing_step.is_finite() && scan.bearing_step != 0.0 && scan.first_bearing.is_finite();
    let none = SideLook {
        distance: None,
        opening: false,
        valid: false,
    };
    if !ok_step {
        return none;
    }
    let valid = |r: f64| r.is_finite() && r >= cfg.min_range_m && r < cfg.max_range_m;
    let side_bearing = sign * std::f64::consts::FRAC_PI_2;
    let within = |i: usize, cone_deg: f64| {
        let b = scan.first_bearing + i as f64 * scan.bearing_step;
        // Bearings on this side of the heading, no farther than the cone from ±90°.
        let off = (side_bearing - b) * sign;
        (-1e-9..=cone_deg.to_radians() + 1e-9).contains(&off)
    };
    let mut distance: Option<f64> = None;
    let mut any = false;
    for (i, &r) in scan.ranges.iter().enumerate() {
        if within(i, cfg.side_cone_deg) && valid(r) {
            any = true;
            distance = Some(distance.map_or(r, |d: f64| d.min(r)));
        }
    }
    // An opening is measured from the wall the robot runs along; with no wall on this side,
    // the whole side is open.
    let reference = distance.unwrap_or(0.0);
    let (mut run, mut best) = (0usize, 0usize);
    for (i, &r) in scan.ranges.iter().enumerate() {
        if !within(i, cfg.opening_cone_deg) {
            continue;
        }
        // A missing return looks through the opening as far as the sensor reaches.
        let far = !r.is_nan() && (r >= cfg.max_range_m || r > reference + cfg.opening_depth_m);
        if far {
            any |= r.is_finite() || r >= cfg.max_range_m;
            run += 1;
            best = best.max(run);
        } else {
            run = 0;
        }
    }
    SideLook {
        distance,
        opening: best >= cfg.opening_min_beams,
        valid: any,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::Pose2;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn view(ranges: &[f64]) -> ScanView<'_> {
        ScanView {
            pose: Pose2::default(),
            ranges,
            first_bearing: -FRAC_PI_2,
            bearing_step: PI / 180.0,
            laser_offset_x: 0.0,
        }
    }

    fn corridor(left: f64, right: f64, yaw_deg: f64) -> Vec<f64> {
        (0..180)
            .map(|i| {
                let b = -FRAC_PI_2 + i as f64 * PI / 180.0 + yaw_deg.to_radians();
                let s = b.sin();
                let r = if s > 1e-9 {
                    left / s
                } else if s < -1e-9 {
                    right / -s
                } else {
                    81.0
                };
                r.min(81.0)
            })
            .collect()
    }

    #[test]
    fn width_is_invariant_under_yaw_and_turning_round() {
        for yaw in [-10.0, -5.0, 0.0, 5.0, 10.0] {
            let a = layout(&view(&corridor(0.8, 1.4, yaw)), &LayoutConfig::default());
            let b = layout(&view(&corridor(1.4, 0.8, yaw)), &LayoutConfig::default());
            for r in [a, b] {
                // One side reads d / cos(yaw): about 1.5 % long at 10°.
                assert!(
                    (r[0].value.unwrap() - 2.2).abs() < 0.035,
                    "yaw {yaw}: {r:?}"
                );
                assert_eq!(r[1].value, Some(0.0));
            }
        }
    }

    #[test]
    fn a_side_doorway_is_one_opening_and_a_crossing_two() {
        let mut r = corridor(1.0, 1.0, 0.0);
        for x in &mut r[165..178] {
            *x = 5.0; // a doorway on the left
        }
        let out = layout(&view(&r), &LayoutConfig::default());
        assert_eq!(out[1].value, Some(1.0));
        for x in &mut r[2..15] {
            *x = 81.9; // a side corridor on the right, no return
        }
        let out = layout(&view(&r), &LayoutConfig::default());
        assert_eq!(out[1].value, Some(2.0));
    }

    #[test]
    fn empty_or_broken_scans_give_no_support() {
        let out = layout(&view(&[]), &LayoutConfig::default());
        assert_eq!((out[0].degree, out[1].degree), (0.0, 0.0));
        let nan = vec![f64::NAN; 180];
        let out = layout(&view(&nan), &LayoutConfig::default());
        assert_eq!((out[0].value, out[1].value), (None, None));
    }
}
