//! Per-scan extraction for robots with a planar laser scanner (the CARMEN
//! logs): the front sector feeds eq. (3) (`laser_wall`, `laser_corner`) and
//! the beams near ±90° stand in for the paper's side sonars feeding eq. (4)
//! (`sonar_wall(left)`, `sonar_wall(right)`). Depends on the sibling
//! extractor modules only; it is the single entry point the CLI's
//! `extract` command and the benchmarks drive.
//!
//! A side "sonar" reading is the *shortest* valid range among the beams
//! within `cone_half_width_deg` of ±90°, because a real sonar reports the
//! first echo inside its cone; the reading is placed in the world along the
//! bearing of the beam that produced it.

use serde::{Deserialize, Serialize};

use super::config::{ConfigError, ExtractConfig};
use super::laser_line::{from_scan, LaserScratch};
use super::sonar_wall::{SensorMount, SonarWall};
use super::{PerceptRecord, Side};
use crate::core::Pose2;

/// Which beams of a scan act as side sonars. RON-loadable; defaults documented per field.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SideBeamConfig {
    /// Bearing of the left "sonar", degrees CCW from the heading. Default 90.
    pub left_bearing_deg: f64,
    /// Bearing of the right "sonar", degrees. Default −90.
    pub right_bearing_deg: f64,
    /// Half-width of the emulated sonar cone, degrees. Default 5.
    pub cone_half_width_deg: f64,
}

impl Default for SideBeamConfig {
    fn default() -> Self {
        SideBeamConfig {
            left_bearing_deg: 90.0,
            right_bearing_deg: -90.0,
            cone_half_width_deg: 5.0,
        }
    }
}

/// One laser scan as the extractors need it; borrowed, so any reader's scan
/// type can lend one without copying.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanView<'a> {
    /// Robot pose when the scan was taken (odometry or corrected), world frame.
    pub pose: Pose2,
    /// Ranges, metres.
    pub ranges: &'a [f64],
    /// Bearing of `ranges[0]`, radians CCW from the heading.
    pub first_bearing: f64,
    /// Angular step between beams, radians.
    pub bearing_step: f64,
    /// Forward offset of the scanner from the robot origin, metres.
    pub laser_offset_x: f64,
}

/// The four records one scan yields, in a fixed order:
/// `laser_wall(front)`, `laser_corner(front)`, `sonar_wall(left)`, `sonar_wall(right)`.
pub type ScanPercepts = [PerceptRecord; 4];

/// Stateful per-scan extractor: owns the two side-wall ring buffers and the
/// scratch space of the line fits.
///
/// # Complexity
/// `O(n log n)` per scan of `n` beams; no allocation after the first scan.
///
/// # Example
/// ```
/// use lplace::percept::{ExtractConfig, ScanExtractor};
/// use lplace::percept::scan::ScanView;
/// use lplace::core::Pose2;
/// let mut ex = ScanExtractor::new(ExtractConfig::default()).unwrap();
/// let ranges = vec![3.0; 180];
/// let step = std::f64::consts::PI / 180.0;
/// let recs = ex.step(&ScanView { pose: Pose2::default(), ranges: &ranges,
///     first_bearing: -std::f64::consts::FRAC_PI_2, bearing_step: step, laser_offset_x: 0.0 });
/// assert_eq!(recs[0].kind.as_str(), "laser_wall");
/// assert!(recs.iter().all(|r| (0.0..=1.0).contains(&r.degree)));
/// ```
#[derive(Debug, Clone)]
pub struct ScanExtractor {
    cfg: ExtractConfig,
    scratch: LaserScratch,
    left: SonarWall,
    right: SonarWall,
}

impl ScanExtractor {
    /// Validates `cfg` and builds empty state.
    ///
    /// # Errors
    /// [`ConfigError`] when a parameter is out of range.
    pub fn new(cfg: ExtractConfig) -> Result<Self, ConfigError> {
        cfg.validate()?;
        Ok(ScanExtractor {
            cfg,
            scratch: LaserScratch::with_capacity(1024),
            left: SonarWall::new(Side::Left, cfg.sonar_wall)?,
            right: SonarWall::new(Side::Right, cfg.sonar_wall)?,
        })
    }

    /// The configuration in use.
    pub fn config(&self) -> &ExtractConfig {
        &self.cfg
    }

    /// Forgets the side-wall history.
    pub fn reset(&mut self) {
        self.left.clear();
        self.right.clear();
    }

    /// Extracts the four percepts of one scan (see [`ScanPercepts`]).
    pub fn step(&mut self, scan: &ScanView<'_>) -> ScanPercepts {
        let laser = from_scan(
            scan.ranges,
            scan.first_bearing,
            scan.bearing_step,
            scan.laser_offset_x,
            &self.cfg.laser_line,
            &mut self.scratch,
        );
        let sb = self.cfg.side_beams;
        for (wall, centre) in [
            (&mut self.left, sb.left_bearing_deg),
            (&mut self.right, sb.right_bearing_deg),
        ] {
            if let Some((range, bearing)) = side_reading(
                scan,
                centre.to_radians(),
                sb.cone_half_width_deg.to_radians(),
                &self.cfg,
            ) {
                let mount = SensorMount {
                    x: scan.laser_offset_x,
                    y: 0.0,
                    angle: bearing,
                };
                wall.push(scan.pose, &mount, range);
            }
        }
        let [wall, corner] = laser.records();
        [
            wall,
            corner,
            self.left.evaluate(&scan.pose).record(),
            self.right.evaluate(&scan.pose).record(),
        ]
    }
}

/// Shortest valid echo within `half` of `centre`; `(range, bearing)`.
fn side_reading(
    scan: &ScanView<'_>,
    centre: f64,
    half: f64,
    cfg: &ExtractConfig,
) -> Option<(f64, f64)> {
    if !(scan.bearing_step.is_finite()
        && scan.bearing_step != 0.0
        && scan.first_bearing.is_finite())
    {
        return None;
    }
    // Only the beams inside the cone are visited, so the cost is independent of scan size.
    let n = scan.ranges.len();
    let i_lo = ((centre - half - scan.first_bearing) / scan.bearing_step).floor();
    let i_hi = ((centre + half - scan.first_bearing) / scan.bearing_step).ceil();
    let (a, b) = if i_lo <= i_hi {
        (i_lo, i_hi)
    } else {
        (i_hi, i_lo)
    };
    let a = a.max(0.0).min(n as f64) as usize;
    let b = (b.max(-1.0) + 1.0).min(n as f64) as usize;
    let mut best: Option<(f64, f64)> = None;
    for i in a..b {
        let r = scan.ranges[i];
        let bearing = scan.first_bearing + i as f64 * scan.bearing_step;
        if (bearing - centre).abs() > half + 1e-9
            || !r.is_finite()
            || r < cfg.sonar_wall.min_range_m
            || r >= cfg.laser_line.max_range_m
        {
            continue;
        }
        if best.map_or(true, |(br, _)| r < br) {
            best = Some((r, bearing));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn side_reading_takes_shortest_echo_in_cone() {
        // 181 beams at 1°: index 180 is +90°, index 0 is −90°.
        let mut ranges = vec![10.0; 181];
        ranges[178] = 1.5; // +88°, inside the ±5° cone
        ranges[170] = 0.5; // +80°, outside
        let view = ScanView {
            pose: Pose2::default(),
            ranges: &ranges,
            first_bearing: -std::f64::consts::FRAC_PI_2,
            bearing_step: std::f64::consts::PI / 180.0,
            laser_offset_x: 0.0,
        };
        let cfg = ExtractConfig::default();
        let (r, b) =
            side_reading(&view, std::f64::consts::FRAC_PI_2, 5f64.to_radians(), &cfg).unwrap();
        assert_eq!(r, 1.5);
        assert!((b - 88f64.to_radians()).abs() < 1e-12);
        let (r, _) =
            side_reading(&view, -std::f64::consts::FRAC_PI_2, 5f64.to_radians(), &cfg).unwrap();
        assert_eq!(r, 10.0);
    }
}
