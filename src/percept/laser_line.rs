//! The structured-light percepts `laser_wall` and `laser_corner` (paper 003
//! §4, eq. (3)), computed from the points of the projected laser line — either
//! the "on" pixels of a binary camera image, or the front sector of a 2-D
//! laser scan standing in for the projected line. Depends on
//! [`crate::percept::line_fit`], [`crate::percept::image`] and the record types.
//!
//! # The procedure
//! Three lines are fitted by orthogonal least squares: `L1` through all
//! points, `L2` through the points left of a *pivot* point and `L3` through
//! those right of it (the pivot belongs to both, because it is the vertex
//! both walls of a corner share). Then
//!
//! ```text
//! δ_f = min(|M1| + S1/10, 1)
//! δ_c = min(1 − min(|M2 − M3| / 1.1, 1) + (S2 + S3)/20, 1)
//! ```
//!
//! with `Mi` the slope and `Si` the standard deviation (RMS orthogonal
//! dispersion) of line `i`. Degrees are `1 − δ`.
//!
//! # Coordinates and units
//! All points are expressed as `(a, b)`: `a` the *lateral* coordinate,
//! growing to the right as an image column does, and `b` the *depth*
//! coordinate. The slope is `M = db/da`, dimensionless, so a wall facing the
//! sensor squarely has `M = 0` whatever the unit, and a symmetric 90° corner
//! has `|M2 − M3| = 2` (saturating the 1.1 threshold, as a clear corner
//! should). A line running straight away from the sensor has no finite
//! slope; it counts as `|M| = ∞` (no front wall).
//!
//! * **Image**: `a = u` (column), `b = v` (row, growing downwards), both in
//!   pixels; `S` is in pixels as in the paper. The pivot is the lowest point
//!   in the image (largest `v`, first such pixel in row-major order).
//! * **Scan**: `a = −y`, `b = x` in the robot frame (x forward, y left,
//!   metres). `S` is expressed in units of [`LaserLineConfig::std_unit_m`],
//!   default 0.01 m — i.e. centimetres — so `S1/10` saturates `δ_f` at a
//!   10 cm dispersion, far above a laser's ~1 cm noise and about what a wall
//!   cluttered with furniture produces; the paper's pixel constants
//!   play the same role for its camera. The pivot is chosen by
//!   [`PivotRule`]: the point nearest the robot by default (the image's
//!   lowest point when the camera sits above the light plane), or the
//!   farthest (camera below the plane, the vertex of a concave corner).
//!
//! When a line cannot be fitted (fewer than `min_points` points, or a
//! degenerate set) the dissimilarity that needs it is 1.

use nalgebra::Point2;
use serde::{Deserialize, Serialize};

use super::image::BinaryImage;
use super::line_fit::{fit_line, LineFit};
use super::{PerceptArg, PerceptKind, PerceptRecord, Side};

/// How the pivot splitting `L2` from `L3` is chosen in a scan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum PivotRule {
    /// The point nearest the sensor: vertex of a convex (protruding) corner.
    Nearest,
    /// The point farthest from the sensor: vertex of a concave corner seen
    /// from inside the room.
    Farthest,
}

/// Parameters of the laser-line extractor. RON-loadable; every field has a default.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LaserLineConfig {
    /// Half-width of the front sector of a scan, degrees. Default 45.
    pub sector_half_width_deg: f64,
    /// Ranges below this are dropped as self-hits, metres. Default 0.05.
    pub min_range_m: f64,
    /// Ranges at or above this are "no return" and dropped, metres. Default 40.
    pub max_range_m: f64,
    /// Length, in metres, of one unit of `S` in eq. (3) for scans. Default 0.01 (cm).
    pub std_unit_m: f64,
    /// Fewest points a line may be fitted to. Default 5.
    pub min_points: usize,
    /// Pivot rule for scans. Default [`PivotRule::Nearest`].
    pub pivot: PivotRule,
}

impl Default for LaserLineConfig {
    fn default() -> Self {
        LaserLineConfig {
            sector_half_width_deg: 45.0,
            min_range_m: 0.05,
            max_range_m: 40.0,
            std_unit_m: 0.01,
            min_points: 5,
            pivot: PivotRule::Nearest,
        }
    }
}

/// Everything eq. (3) computed, for inspection and for the records.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaserLineOutcome {
    /// Line through all points.
    pub l1: Option<LineFit>,
    /// Line through the points left of (and including) the pivot.
    pub l2: Option<LineFit>,
    /// Line through the points right of (and including) the pivot.
    pub l3: Option<LineFit>,
    /// The pivot, in `(a, b)` coordinates.
    pub pivot: Option<Point2<f64>>,
    /// `δ_f` of eq. (3).
    pub delta_front: f64,
    /// `δ_c` of eq. (3).
    pub delta_corner: f64,
    /// Metres from the sensor origin to `L1` (scans only).
    pub wall_distance: Option<f64>,
    /// Metres from the sensor origin to the pivot (scans only).
    pub corner_distance: Option<f64>,
}

impl LaserLineOutcome {
    /// The two percepts: `laser_wall(front)` and `laser_corner(front)`.
    pub fn records(&self) -> [PerceptRecord; 2] {
        let arg = PerceptArg::Side(Side::Front);
        [
            PerceptRecord::from_delta(
                PerceptKind::LaserWall,
                arg,
                self.wall_distance,
                self.delta_front,
            ),
            PerceptRecord::from_delta(
                PerceptKind::LaserCorner,
                arg,
                self.corner_distance,
                self.delta_corner,
            ),
        ]
    }
}

/// `δ_f = min(|M1| + S1/10, 1)`; an undefined slope gives 1.
pub fn delta_front(m1: Option<f64>, s1: f64) -> f64 {
    match m1 {
        Some(m) if m.is_finite() && s1.is_finite() => (m.abs() + s1 / 10.0).clamp(0.0, 1.0),
        _ => 1.0,
    }
}

/// `δ_c = min(1 − min(|M2 − M3|/1.1, 1) + (S2+S3)/20, 1)`.
///
/// One undefined (vertical) slope against a finite one is an infinite
/// difference; two undefined slopes are parallel, a zero difference.
pub fn delta_corner(m2: Option<f64>, m3: Option<f64>, s2: f64, s3: f64) -> f64 {
    let diff = match (m2, m3) {
        (Some(a), Some(b)) => (a - b).abs(),
        (None, None) => 0.0,
        _ => f64::INFINITY,
    };
    let v = 1.0 - (diff / 1.1).min(1.0) + (s2 + s3) / 20.0;
    if v.is_nan() {
        1.0
    } else {
        v.clamp(0.0, 1.0)
    }
}

/// Reusable buffers so that extraction allocates nothing once warmed up.
#[derive(Debug, Clone, Default)]
pub struct LaserScratch {
    points: Vec<Point2<f64>>,
}

impl LaserScratch {
    /// Buffers sized for `n` points.
    pub fn with_capacity(n: usize) -> Self {
        LaserScratch {
            points: Vec::with_capacity(n),
        }
    }
}

fn fit_min(points: &[Point2<f64>], min_points: usize) -> Option<LineFit> {
    if points.len() < min_points.max(2) {
        return None;
    }
    fit_line(points).ok()
}

/// Runs eq. (3) on points in `(a, b)` coordinates with the given pivot.
///
/// `points` is reordered (sorted by `a`). `std_unit` divides every RMS
/// dispersion before it enters eq. (3).
///
/// # Complexity
/// `O(n log n)` for the sort, then three `O(n)` fits; no allocation.
///
/// # Example
/// ```
/// use lplace::percept::laser_line::eq3_from_points;
/// use nalgebra::Point2;
/// // A V: b = |a|, pivot at the origin. |M2 − M3| = 2, no dispersion → δ_c = 0.
/// let mut pts: Vec<_> = (-5..=5).map(|i| Point2::new(i as f64, (i as f64).abs())).collect();
/// let out = eq3_from_points(&mut pts, Point2::new(0.0, 0.0), 1.0, 3);
/// assert!(out.delta_corner < 1e-12);
/// ```
pub fn eq3_from_points(
    points: &mut [Point2<f64>],
    pivot: Point2<f64>,
    std_unit: f64,
    min_points: usize,
) -> LaserLineOutcome {
    points.sort_by(|p, q| p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y)));
    let lo = points.partition_point(|p| p.x < pivot.x);
    let hi = points.partition_point(|p| p.x <= pivot.x);
    let l1 = fit_min(points, min_points);
    let l2 = fit_min(&points[..hi], min_points);
    let l3 = fit_min(&points[lo..], min_points);
    let unit = if std_unit > 0.0 && std_unit.is_finite() {
        std_unit
    } else {
        1.0
    };
    let d_front = match &l1 {
        Some(f) => delta_front(f.slope, f.rms_dispersion / unit),
        None => 1.0,
    };
    let d_corner = match (&l2, &l3) {
        (Some(f2), Some(f3)) => delta_corner(
            f2.slope,
            f3.slope,
            f2.rms_dispersion / unit,
            f3.rms_dispersion / unit,
        ),
        _ => 1.0,
    };
    LaserLineOutcome {
        l1,
        l2,
        l3,
        pivot: Some(pivot),
        delta_front: d_front,
        delta_corner: d_corner,
        wall_distance: None,
        corner_distance: None,
    }
}

/// Eq. (3) on the front sector of a 2-D laser scan.
///
/// `ranges[i]` (metres) was measured along bearing `first_bearing + i·step`
/// (radians, CCW from the heading, robot frame); the scanner sits
/// `laser_offset_x` metres ahead of the robot origin. Beams outside
/// `±sector_half_width_deg`, below `min_range_m`, at or above `max_range_m`
/// or non-finite are ignored.
///
/// # Complexity
/// `O(n log n)` in the number of beams; allocation-free once `scratch` has
/// grown to the sector size.
///
/// # Example
/// ```
/// use lplace::percept::laser_line::{from_scan, LaserLineConfig, LaserScratch};
/// // 181 beams over 180°, a wall 2 m ahead: r = 2 / cos(bearing).
/// let step = std::f64::consts::PI / 180.0;
/// let ranges: Vec<f64> = (0..181)
///     .map(|i| { let b = -std::f64::consts::FRAC_PI_2 + i as f64 * step; 2.0 / b.cos().max(1e-3) })
///     .collect();
/// let out = from_scan(&ranges, -std::f64::consts::FRAC_PI_2, step, 0.0,
///                     &LaserLineConfig::default(), &mut LaserScratch::default());
/// assert!(out.delta_front < 1e-9);
/// assert!((out.wall_distance.unwrap() - 2.0).abs() < 1e-9);
/// ```
pub fn from_scan(
    ranges: &[f64],
    first_bearing: f64,
    step: f64,
    laser_offset_x: f64,
    cfg: &LaserLineConfig,
    scratch: &mut LaserScratch,
) -> LaserLineOutcome {
    let half = cfg.sector_half_width_deg.to_radians();
    scratch.points.clear();
    let mut pivot: Option<(f64, Point2<f64>)> = None;
    for (i, &r) in ranges.iter().enumerate() {
        let bearing = first_bearing + i as f64 * step;
        if !(r.is_finite() && bearing.is_finite())
            || bearing.abs() > half
            || r < cfg.min_range_m
            || r >= cfg.max_range_m
        {
            continue;
        }
        let (s, c) = bearing.sin_cos();
        let x = laser_offset_x + r * c;
        let y = r * s;
        let p = Point2::new(-y, x);
        let d = x.hypot(y);
        let better = match (pivot, cfg.pivot) {
            (None, _) => true,
            (Some((best, _)), PivotRule::Nearest) => d < best,
            (Some((best, _)), PivotRule::Farthest) => d > best,
        };
        if better {
            pivot = Some((d, p));
        }
        scratch.points.push(p);
    }
    let Some((pivot_dist, pivot)) = pivot else {
        return empty_outcome();
    };
    let mut out = eq3_from_points(&mut scratch.points, pivot, cfg.std_unit_m, cfg.min_points);
    // Distance from the robot origin to L1: |n·0 − offset| = |offset|.
    out.wall_distance = out.l1.as_ref().map(|f| f.offset.abs());
    out.corner_distance = Some(pivot_dist);
    out
}

/// Eq. (3) on the "on" pixels of a binary image of the projected line, in
/// pixel units exactly as the paper: `M = dv/du`, `S` in pixels, pivot = the
/// lowest "on" pixel (largest row; leftmost on ties).
///
/// # Complexity
/// `O(W·H)` to collect the pixels, then `O(k log k)` in the `k` on-pixels.
///
/// # Example
/// ```
/// use lplace::percept::image::BinaryImage;
/// use lplace::percept::laser_line::{from_image, LaserScratch};
/// // A horizontal line of light across a 20×5 image: a wall straight ahead.
/// let mut img = BinaryImage::new(20, 5).unwrap();
/// for u in 0..20 { img.set(u, 2, true); }
/// let out = from_image(&img, 5, &mut LaserScratch::default());
/// assert!(out.delta_front < 1e-12);
/// assert_eq!(out.delta_corner, 1.0);
/// ```
pub fn from_image(
    img: &BinaryImage,
    min_points: usize,
    scratch: &mut LaserScratch,
) -> LaserLineOutcome {
    scratch.points.clear();
    let mut pivot: Option<Point2<f64>> = None;
    for (u, v) in img.on_pixels() {
        let p = Point2::new(u as f64, v as f64);
        if pivot.map_or(true, |q| p.y > q.y) {
            pivot = Some(p);
        }
        scratch.points.push(p);
    }
    match pivot {
        Some(pv) => eq3_from_points(&mut scratch.points, pv, 1.0, min_points),
        None => empty_outcome(),
    }
}

fn empty_outcome() -> LaserLineOutcome {
    LaserLineOutcome {
        l1: None,
        l2: None,
        l3: None,
        pivot: None,
        delta_front: 1.0,
        delta_corner: 1.0,
        wall_distance: None,
        corner_distance: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq3_hand_values() {
        // |M1| = 0.2, S1 = 3 → 0.2 + 0.3 = 0.5.
        assert!((delta_front(Some(-0.2), 3.0) - 0.5).abs() < 1e-12);
        assert_eq!(delta_front(Some(0.9), 5.0), 1.0);
        assert_eq!(delta_front(None, 0.0), 1.0);
        // |M2 − M3| = 0.55 → 1 − 0.5 = 0.5; (S2+S3)/20 = 2/20 = 0.1 → 0.6.
        assert!((delta_corner(Some(0.3), Some(-0.25), 1.0, 1.0) - 0.6).abs() < 1e-12);
        assert!(delta_corner(Some(1.0), Some(-1.0), 0.0, 0.0).abs() < 1e-12);
        assert_eq!(delta_corner(Some(0.1), Some(0.1), 0.0, 0.0), 1.0);
        assert!(delta_corner(None, Some(0.0), 0.0, 0.0).abs() < 1e-12);
        assert_eq!(delta_corner(None, None, 0.0, 0.0), 1.0);
    }

    #[test]
    fn empty_scan_is_unsupported() {
        let out = from_scan(
            &[],
            0.0,
            0.01,
            0.0,
            &LaserLineConfig::default(),
            &mut LaserScratch::default(),
        );
        assert_eq!((out.delta_front, out.delta_corner), (1.0, 1.0));
        let recs = out.records();
        assert_eq!(recs[0].degree, 0.0);
        assert_eq!(recs[1].kind, PerceptKind::LaserCorner);
    }
}
