//! Beacon percepts: `beacon_angle` and `beacon_distance` from a binary image
//! of the structured beacon (paper 003 §4, eqs. (1)–(2)), and
//! `landmark_range` / `landmark_bearing` from already-identified landmark
//! sightings (range, bearing, id, reliability). Depends on
//! [`crate::percept::image`], [`crate::percept::line_fit`] and the record types.
//!
//! # The beacon and its geometric model
//! The beacon is a vertical cylinder with two horizontal cuts and one
//! helical cut between them. Its binary image shows two horizontal bright
//! segments (the cuts `s1` on top, `s2` below) and a curve (the helix).
//! The paper does not give the model `m(u)`; we parametrise it as follows,
//! with image columns `u` and rows `v` (down), in pixels:
//!
//! * the two cuts are found as the topmost and bottommost *bands* of rows
//!   whose on-pixel count reaches `cut_row_fraction` of the beacon's pixel
//!   width, and each band is fitted with a line (orthogonal least squares);
//! * the left and right margins `u0`, `u1` are the extreme columns of the cut
//!   pixels, so the cylinder's axis projects to `uc = (u0 + u1)/2` and its
//!   apparent radius is `r = (u1 − u0)/2`;
//! * `vt`, `vb` are the rows of the top and bottom cut lines at `uc`, and
//!   `sep = vb − vt`;
//! * **assumption**: the helix makes exactly one turn between the two cuts,
//!   starting at the top cut. The surface point seen in column `u` has
//!   azimuth `asin((u − uc)/r)` relative to the camera, so with the beacon
//!   turned by `θ` the helix crosses that column at
//!   `m_θ(u) = vt + sep · frac((θ + h·asin((u − uc)/r)) / 2π)`,
//!   where `h = ±1` is the handedness (`helix_sign`);
//! * `θ` is searched over `angle_steps` equally spaced values; the best
//!   match is the one whose band `|v − m_θ(u)| ≤ w/2` holds the most helix
//!   pixels `N` (ties: smaller eq. (1) sum, then smaller θ). The paper says
//!   "best match" without a criterion; maximising coverage is our choice,
//!   because minimising `M` alone would prefer bands that catch few pixels.
//!   Helix pixels are those strictly between the two cut bands.
//!
//! Then, exactly as eqs. (1)–(2):
//! `M = Σ (m(u) − v)² P(u, v) / N²`, `β_θ = M·N/(w/2)²` — the mean squared
//! deviation in units of the half band, hence in `[0, 1]` — and
//! `β_d = max(δ_s1, δ_s2)` with `δ_si = min(S_i / cut_dispersion_max_px, 1)`
//! and `S_i` the RMS dispersion of the pixels of cut `i` about its fitted line
//! (the paper's "dispersion around the ideal segment", normalised by a
//! configurable saturation, since it must land in `[0, 1]`).
//!
//! Values: `beacon_angle` = θ in radians `[0, 2π)` — the azimuth of the
//! camera around the beacon measured from the start of the helix;
//! `beacon_distance` = `focal_px · cut_separation_m / sep` in metres
//! (pinhole camera, beacon upright and centred enough that the cuts'
//! separation scales with inverse distance).

use nalgebra::Point2;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::config::{non_negative, positive, ConfigError};
use super::image::BinaryImage;
use super::line_fit::{fit_line, LineFit, LineFitError};
use super::{PerceptArg, PerceptKind, PerceptRecord};

/// Parameters of the beacon image matcher. RON-loadable; defaults documented per field.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BeaconConfig {
    /// Physical vertical distance between the two cuts, metres. Default 0.20.
    pub cut_separation_m: f64,
    /// Camera focal length, pixels. Default 500.
    pub focal_px: f64,
    /// `w` of eq. (1): height of the match band, pixels. Default 6.
    pub band_px: f64,
    /// A row is part of a cut when its on-pixels reach this fraction of the
    /// beacon's pixel width. Default 0.5.
    pub cut_row_fraction: f64,
    /// Cut dispersion (pixels) at which `δ_s` saturates to 1. Default 2.
    pub cut_dispersion_max_px: f64,
    /// Number of θ values tried in `[0, 2π)`. Default 360.
    pub angle_steps: usize,
    /// Helix handedness, +1 or −1. Default +1.
    pub helix_sign: f64,
}

impl Default for BeaconConfig {
    fn default() -> Self {
        BeaconConfig {
            cut_separation_m: 0.20,
            focal_px: 500.0,
            band_px: 6.0,
            cut_row_fraction: 0.5,
            cut_dispersion_max_px: 2.0,
            angle_steps: 360,
            helix_sign: 1.0,
        }
    }
}

impl BeaconConfig {
    /// Checks every field.
    ///
    /// # Errors
    /// [`ConfigError::Invalid`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        positive("beacon.cut_separation_m", self.cut_separation_m)?;
        positive("beacon.focal_px", self.focal_px)?;
        positive("beacon.band_px", self.band_px)?;
        positive("beacon.cut_row_fraction", self.cut_row_fraction)?;
        positive("beacon.cut_dispersion_max_px", self.cut_dispersion_max_px)?;
        if !(1..=100_000).contains(&self.angle_steps) {
            return Err(ConfigError::invalid(
                "beacon.angle_steps",
                self.angle_steps as f64,
                "must be in 1..=100000",
            ));
        }
        if self.helix_sign != 1.0 && self.helix_sign != -1.0 {
            return Err(ConfigError::invalid(
                "beacon.helix_sign",
                self.helix_sign,
                "must be 1 or -1",
            ));
        }
        Ok(())
    }
}

/// Why a beacon image could not be interpreted.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BeaconError {
    /// The image has no "on" pixel.
    #[error("beacon image has no on pixels")]
    Empty,
    /// Fewer than two cut bands were found.
    #[error("beacon image: {bands} horizontal cut band(s) found, need 2")]
    CutsNotFound {
        /// Bands found.
        bands: usize,
    },
    /// A cut band could not be fitted.
    #[error("beacon cut {cut}: {source}")]
    CutFit {
        /// 1 (top) or 2 (bottom).
        cut: u8,
        /// Why.
        source: LineFitError,
    },
    /// The cut geometry is unusable (vertical cut, cuts crossing, zero width).
    #[error("beacon geometry unusable: separation {separation_px} px, radius {radius_px} px")]
    Geometry {
        /// `vb − vt` at the axis.
        separation_px: f64,
        /// Apparent radius.
        radius_px: f64,
    },
}

/// Everything eqs. (1)–(2) computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeaconOutcome {
    /// Fitted top cut.
    pub cut_top: LineFit,
    /// Fitted bottom cut.
    pub cut_bottom: LineFit,
    /// Axis column `uc`, pixels.
    pub axis_u: f64,
    /// Apparent radius `r`, pixels.
    pub radius_px: f64,
    /// `sep = vb − vt`, pixels.
    pub separation_px: f64,
    /// Best θ, radians in `[0, 2π)`; `None` when no helix pixel matched.
    pub angle: Option<f64>,
    /// `N`: helix pixels inside the band at the best θ.
    pub matched: usize,
    /// `M` of eq. (1).
    pub m: f64,
    /// `β_θ` of eq. (2) (a dissimilarity).
    pub beta_theta: f64,
    /// `δ_s1`, `δ_s2`.
    pub delta_cuts: [f64; 2],
    /// `β_d` of eq. (2) (a dissimilarity).
    pub beta_d: f64,
    /// Distance estimate, metres.
    pub distance: f64,
}

impl BeaconOutcome {
    /// `beacon_angle` and `beacon_distance` records.
    pub fn records(&self) -> [PerceptRecord; 2] {
        [
            PerceptRecord::from_delta(
                PerceptKind::BeaconAngle,
                PerceptArg::None,
                self.angle,
                self.beta_theta,
            ),
            PerceptRecord::from_delta(
                PerceptKind::BeaconDistance,
                PerceptArg::None,
                Some(self.distance),
                self.beta_d,
            ),
        ]
    }
}

/// The helix model `m_θ(u)` described in the module docs.
pub fn helix_row(
    theta: f64,
    u: f64,
    axis_u: f64,
    radius: f64,
    vt: f64,
    sep: f64,
    sign: f64,
) -> f64 {
    let x = ((u - axis_u) / radius).clamp(-1.0, 1.0);
    let psi = (theta + sign * x.asin()).rem_euclid(std::f64::consts::TAU);
    vt + sep * psi / std::f64::consts::TAU
}

/// Interprets a binary beacon image (eqs. (1)–(2)).
///
/// # Errors
/// [`BeaconError`] when the cuts cannot be found or fitted.
///
/// # Complexity
/// `O(W·H + S·K)` for a `W×H` image with `K` helix pixels and `S = angle_steps`.
///
/// # Example
/// ```
/// use lplace::percept::beacon::{beacon_from_image, BeaconConfig};
/// use lplace::percept::image::BinaryImage;
/// let img = BinaryImage::new(10, 10).unwrap();
/// assert!(beacon_from_image(&img, &BeaconConfig::default()).is_err());
/// ```
pub fn beacon_from_image(
    img: &BinaryImage,
    cfg: &BeaconConfig,
) -> Result<BeaconOutcome, BeaconError> {
    let (top, bottom) = cut_bands(img, cfg)?;
    let band_points = |b: (usize, usize)| -> Vec<Point2<f64>> {
        img.on_pixels()
            .filter(|&(_, v)| v >= b.0 && v <= b.1)
            .map(|(u, v)| Point2::new(u as f64, v as f64))
            .collect()
    };
    let p_top = band_points(top);
    let p_bot = band_points(bottom);
    let cut_top = fit_line(&p_top).map_err(|source| BeaconError::CutFit { cut: 1, source })?;
    let cut_bottom = fit_line(&p_bot).map_err(|source| BeaconError::CutFit { cut: 2, source })?;
    let (u0, u1) = p_top
        .iter()
        .chain(p_bot.iter())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.x), b.max(p.x))
        });
    let axis_u = 0.5 * (u0 + u1);
    let radius = 0.5 * (u1 - u0);
    let row_at = |f: &LineFit| f.slope.map(|m| f.centroid.y + m * (axis_u - f.centroid.x));
    let (vt, vb) = match (row_at(&cut_top), row_at(&cut_bottom)) {
        (Some(a), Some(b)) => (a, b),
        _ => (f64::NAN, f64::NAN),
    };
    let sep = vb - vt;
    if !(sep > 0.0 && radius > 0.0 && sep.is_finite()) {
        return Err(BeaconError::Geometry {
            separation_px: sep,
            radius_px: radius,
        });
    }
    let helix: Vec<(usize, f64)> = img
        .on_pixels()
        .filter(|&(u, v)| v > top.1 && v < bottom.0 && (u as f64) >= u0 && (u as f64) <= u1)
        .map(|(u, v)| (u, v as f64))
        .collect();
    // asin of each column once, not once per (θ, pixel).
    let first_col = u0 as usize;
    let asin_col: Vec<f64> = (first_col..=u1 as usize)
        .map(|u| cfg.helix_sign * ((u as f64 - axis_u) / radius).clamp(-1.0, 1.0).asin())
        .collect();
    let half = 0.5 * cfg.band_px;
    let helix_phase = |theta: f64, u: usize| theta + asin_col[u - first_col];
    let (matched, sum, theta) =
        best_phase(&helix, helix_phase, (vt, sep, half), cfg.angle_steps.max(1));
    let (angle, m, beta_theta) = if matched == 0 {
        (None, 0.0, 1.0)
    } else {
        let n = matched as f64;
        let m = sum / (n * n);
        (Some(theta), m, m * n / (half * half))
    };
    let ds1 = (cut_top.rms_dispersion / cfg.cut_dispersion_max_px).min(1.0);
    let ds2 = (cut_bottom.rms_dispersion / cfg.cut_dispersion_max_px).min(1.0);
    Ok(BeaconOutcome {
        cut_top,
        cut_bottom,
        axis_u,
        radius_px: radius,
        separation_px: sep,
        angle,
        matched,
        m,
        beta_theta,
        delta_cuts: [ds1, ds2],
        beta_d: ds1.max(ds2),
        distance: cfg.focal_px * cfg.cut_separation_m / sep,
    })
}

/// A band of consecutive image rows, `[start, end]` inclusive.
type Band = (usize, usize);

/// The first and last bands of consecutive cut rows: rows whose lit pixels cover
/// `cut_row_fraction` of the lit width.
fn cut_bands(img: &BinaryImage, cfg: &BeaconConfig) -> Result<(Band, Band), BeaconError> {
    let (mut umin, mut umax) = (usize::MAX, 0usize);
    let mut row_count = vec![0usize; img.height()];
    for (u, v) in img.on_pixels() {
        umin = umin.min(u);
        umax = umax.max(u);
        row_count[v] += 1;
    }
    if umin > umax {
        return Err(BeaconError::Empty);
    }
    let width = (umax - umin + 1) as f64;
    let is_cut = |v: usize| row_count[v] as f64 >= cfg.cut_row_fraction * width;
    let mut bands: Vec<Band> = Vec::new();
    for v in 0..img.height() {
        if is_cut(v) {
            match bands.last_mut() {
                Some(b) if b.1 + 1 == v => b.1 = v,
                _ => bands.push((v, v)),
            }
        }
    }
    match (bands.first(), bands.last()) {
        (Some(&top), Some(&bottom)) if bands.len() >= 2 => Ok((top, bottom)),
        _ => Err(BeaconError::CutsNotFound { bands: bands.len() }),
    }
}

/// The helix phase θ among `steps` equally spaced ones that puts the most helix pixels within
/// `half` rows of the helix (ties: the smaller sum of squared offsets), as `(N, Σ, θ)`; `phase`
/// is a pixel column's angle around the axis plus θ, `(vt, sep, half)` the top cut's row, the
/// cut separation and the half band, in pixels.
fn best_phase(
    helix: &[(usize, f64)],
    phase: impl Fn(f64, usize) -> f64,
    (vt, sep, half): (f64, f64, f64),
    steps: usize,
) -> (usize, f64, f64) {
    let mut best: Option<(usize, f64, f64)> = None;
    for k in 0..steps {
        let theta = std::f64::consts::TAU * k as f64 / steps as f64;
        let (mut n, mut sum) = (0usize, 0.0f64);
        for &(u, v) in helix {
            let psi = phase(theta, u).rem_euclid(std::f64::consts::TAU);
            let d = vt + sep * psi / std::f64::consts::TAU - v;
            if d.abs() <= half {
                n += 1;
                sum += d * d;
            }
        }
        let better = match best {
            None => true,
            Some((bn, bs, _)) => n > bn || (n == bn && sum < bs),
        };
        if better {
            best = Some((n, sum, theta));
        }
    }
    best.unwrap_or((0, 0.0, 0.0))
}

/// Parameters turning a landmark sighting's reliability into a degree.
/// RON-loadable; defaults documented per field.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LandmarkConfig {
    /// Up to this range the reported reliability is taken as is, metres. Default 3.
    pub full_trust_range_m: f64,
    /// Beyond this range a sighting gives no support; in between, the degree
    /// falls linearly, metres. Default 10.
    pub max_range_m: f64,
}

impl Default for LandmarkConfig {
    fn default() -> Self {
        LandmarkConfig {
            full_trust_range_m: 3.0,
            max_range_m: 10.0,
        }
    }
}

impl LandmarkConfig {
    /// Checks every field.
    ///
    /// # Errors
    /// [`ConfigError::Invalid`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        non_negative("landmark.full_trust_range_m", self.full_trust_range_m)?;
        positive("landmark.max_range_m", self.max_range_m)?;
        if self.max_range_m < self.full_trust_range_m {
            return Err(ConfigError::invalid(
                "landmark.max_range_m",
                self.max_range_m,
                "must be ≥ full_trust_range_m",
            ));
        }
        Ok(())
    }
}

/// A landmark sighting from a detector that already identifies landmarks
/// (e.g. MRCLAM barcodes): metres, radians CCW from the heading, and the
/// detector's reliability in `[0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LandmarkReading {
    /// Landmark id.
    pub id: u32,
    /// Range, metres.
    pub range_m: f64,
    /// Bearing, radians.
    pub bearing_rad: f64,
    /// Detector reliability in `[0, 1]`.
    pub reliability: f64,
}

/// `landmark_range(id)` and `landmark_bearing(id)` records.
///
/// Degree = `reliability × f(range)`, `f` = 1 up to `full_trust_range_m`,
/// falling linearly to 0 at `max_range_m` (far sightings are less
/// trustworthy); `δ = 1 − degree`. A non-finite range or bearing gives no
/// support. The bearing value is wrapped into `(−π, π]`.
///
/// # Complexity
/// `O(1)`.
///
/// # Example
/// ```
/// use lplace::percept::beacon::{landmark_records, LandmarkConfig, LandmarkReading};
/// let r = LandmarkReading { id: 7, range_m: 6.5, bearing_rad: 0.3, reliability: 0.8 };
/// // Halfway between 3 m and 10 m: 0.8 × 0.5 = 0.4.
/// let [range, _bearing] = landmark_records(&r, &LandmarkConfig::default());
/// assert!((range.degree - 0.4).abs() < 1e-12);
/// ```
pub fn landmark_records(r: &LandmarkReading, cfg: &LandmarkConfig) -> [PerceptRecord; 2] {
    let arg = PerceptArg::Landmark(r.id);
    if !(r.range_m.is_finite() && r.bearing_rad.is_finite()) {
        return [
            PerceptRecord::unsupported(PerceptKind::LandmarkRange, arg),
            PerceptRecord::unsupported(PerceptKind::LandmarkBearing, arg),
        ];
    }
    let span = cfg.max_range_m - cfg.full_trust_range_m;
    let falloff = if r.range_m <= cfg.full_trust_range_m {
        1.0
    } else if span > 0.0 {
        (1.0 - (r.range_m - cfg.full_trust_range_m) / span).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let rel = if r.reliability.is_nan() {
        0.0
    } else {
        r.reliability.clamp(0.0, 1.0)
    };
    let delta = 1.0 - rel * falloff;
    let bearing = crate::core::angle::wrap_pi(r.bearing_rad);
    [
        PerceptRecord::from_delta(PerceptKind::LandmarkRange, arg, Some(r.range_m), delta),
        PerceptRecord::from_delta(PerceptKind::LandmarkBearing, arg, Some(bearing), delta),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn landmark_degree_falls_with_range() {
        let cfg = LandmarkConfig::default();
        let mk = |range_m, reliability| LandmarkReading {
            id: 1,
            range_m,
            bearing_rad: 4.0,
            reliability,
        };
        assert_eq!(landmark_records(&mk(2.0, 0.9), &cfg)[0].degree, 0.9);
        assert_eq!(landmark_records(&mk(12.0, 0.9), &cfg)[0].degree, 0.0);
        assert_eq!(landmark_records(&mk(f64::NAN, 0.9), &cfg)[0].degree, 0.0);
        assert_eq!(landmark_records(&mk(1.0, f64::NAN), &cfg)[1].degree, 0.0);
        // 4 rad wraps to 4 − 2π.
        let b = landmark_records(&mk(1.0, 1.0), &cfg)[1].value.unwrap();
        assert!((b - (4.0 - std::f64::consts::TAU)).abs() < 1e-12);
    }
}
