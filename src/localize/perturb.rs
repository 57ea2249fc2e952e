//! The perturbations of paper 001's test protocol, applied to a stream of [`MetricFrame`]s
//! before it is driven: *noisy data* (seeded Gaussian noise added to every reading's range and
//! bearing) and *sparse data* (a seeded fraction of the readings kept, the others deleted
//! "beyond the robot's awareness"). Odometry and truth are never touched, so the scores of a
//! perturbed run stay comparable with the clean one.
//!
//! Paper 001 gives its levels only in figures (its Figs. 4 and 5, not in the text); the sparsity
//! levels here are the issue's 100 / 50 / 25 / 10 % ([`KEEP_LEVELS`]), and the noise levels
//! ([`NOISE_LEVELS`]) are chosen against MRCLAM's camera (ranges 1–7 m, bearings within ±0.6 rad):
//! from none to a level where a single reading no longer tells which side of a landmark the
//! robot is on.
//!
//! Common random numbers: each reading consumes the same three draws (one keep test, two normal
//! samples) whatever the level, so with one seed the readings kept at 25 % are a subset of those
//! kept at 50 %, and a reading's noise at level 2σ is exactly twice its noise at σ. Differences
//! between levels are then the levels' doing, not the sampling's.
//!
//! May depend on: `core` (the seeded generator, angle wrapping), [`super::frame`] (frames).
//!
//! # Complexity
//!
//! O(readings) time; the output is a new frame vector of the input's size.
//!
//! # Example
//!
//! ```
//! use lplace::localize::{LandmarkReading, MetricFrame};
//! use lplace::localize::perturb::{perturb, Perturbation};
//! let frame = MetricFrame {
//!     t: 0.0,
//!     dt: 0.0,
//!     odometry: Default::default(),
//!     observations: vec![LandmarkReading { subject: 6, range: 2.0, bearing: 0.1 }; 100],
//!     truth: None,
//! };
//! let p = Perturbation { range_sigma: 0.0, bearing_sigma: 0.0, keep: 0.5 };
//! let out = perturb(std::slice::from_ref(&frame), &p, 7).unwrap();
//! let kept = out[0].observations.len();
//! assert!(kept > 25 && kept < 75);
//! // Noise 0 leaves the kept readings exactly as they were.
//! assert!(out[0].observations.iter().all(|r| r.range == 2.0 && r.bearing == 0.1));
//! ```

use super::frame::{LandmarkReading, MetricFrame};
use crate::core::angle::wrap_pi;
use crate::core::rng::SplitMix64;
use serde::{Deserialize, Serialize};

/// Noise levels of the noise sweep: (range σ in metres, bearing σ in degrees).
pub const NOISE_LEVELS: [(f64, f64); 5] = [
    (0.0, 0.0),
    (0.1, 2.0),
    (0.25, 5.0),
    (0.5, 10.0),
    (1.0, 20.0),
];

/// Fractions of readings kept in the sparsity sweep (paper 001's "sparse data").
pub const KEEP_LEVELS: [f64; 4] = [1.0, 0.5, 0.25, 0.1];

/// One perturbation of a stream.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Perturbation {
    /// Standard deviation (m) of the Gaussian noise added to each range; 0 adds none.
    pub range_sigma: f64,
    /// Standard deviation (rad) of the Gaussian noise added to each bearing; 0 adds none.
    pub bearing_sigma: f64,
    /// Probability in (0, 1] that a reading is kept; 1 keeps all.
    pub keep: f64,
}

impl Default for Perturbation {
    /// The identity: no noise, every reading kept.
    fn default() -> Self {
        Perturbation {
            range_sigma: 0.0,
            bearing_sigma: 0.0,
            keep: 1.0,
        }
    }
}

impl Perturbation {
    /// Noise only, every reading kept; `bearing_sigma_deg` in degrees (as [`NOISE_LEVELS`]).
    pub fn noise(range_sigma: f64, bearing_sigma_deg: f64) -> Self {
        Perturbation {
            range_sigma,
            bearing_sigma: bearing_sigma_deg.to_radians(),
            keep: 1.0,
        }
    }

    /// Sparsity only: keep this fraction of the readings.
    pub fn sparsity(keep: f64) -> Self {
        Perturbation {
            keep,
            ..Perturbation::default()
        }
    }

    /// Checks the fields: sigmas finite and ≥ 0, keep in (0, 1].
    ///
    /// # Errors
    /// [`PerturbError`] naming the first bad field and its value.
    pub fn validate(&self) -> Result<(), PerturbError> {
        for (field, v) in [
            ("range_sigma", self.range_sigma),
            ("bearing_sigma", self.bearing_sigma),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(PerturbError::BadSigma { field, value: v });
            }
        }
        if !(self.keep > 0.0 && self.keep <= 1.0) {
            return Err(PerturbError::BadKeep { value: self.keep });
        }
        Ok(())
    }
}

/// A perturbation that cannot be applied.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum PerturbError {
    /// A standard deviation that is negative or not finite.
    #[error("{field} must be finite and ≥ 0, got {value}")]
    BadSigma {
        /// Which field.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// A kept fraction outside (0, 1].
    #[error("the kept fraction must be in (0, 1], got {value}")]
    BadKeep {
        /// Its value.
        value: f64,
    },
}

/// Applies `p` to `frames` with the generator seeded by `seed` (see the module docs).
///
/// A perturbed range that would fall below 0 is clamped to 0 (a camera cannot report a negative
/// distance); a perturbed bearing is wrapped into (−π, π]. Readings already non-finite pass
/// through unchanged, so the driver still counts them as rejected.
///
/// # Errors
/// [`PerturbError`] from [`Perturbation::validate`].
pub fn perturb(
    frames: &[MetricFrame],
    p: &Perturbation,
    seed: u64,
) -> Result<Vec<MetricFrame>, PerturbError> {
    p.validate()?;
    let mut rng = SplitMix64::new(seed);
    let out = frames
        .iter()
        .map(|f| {
            let observations = f
                .observations
                .iter()
                .filter_map(|r| {
                    // Always three draws per reading: see "common random numbers" above.
                    let u = rng.unit();
                    let (nr, nb) = (rng.normal(), rng.normal());
                    if u >= p.keep {
                        return None;
                    }
                    let mut r: LandmarkReading = *r;
                    if p.range_sigma > 0.0 && r.range.is_finite() {
                        r.range = (r.range + p.range_sigma * nr).max(0.0);
                    }
                    if p.bearing_sigma > 0.0 && r.bearing.is_finite() {
                        r.bearing = wrap_pi(r.bearing + p.bearing_sigma * nb);
                    }
                    Some(r)
                })
                .collect();
            MetricFrame {
                observations,
                ..f.clone()
            }
        })
        .collect();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use crate::core::angle::wrap_pi as wrap;
    use std::f64::consts::PI;

    #[test]
    fn wrap_lands_in_the_half_open_interval() {
        assert_eq!(wrap(0.5), 0.5);
        assert!((wrap(PI) - PI).abs() < 1e-12);
        assert!((wrap(-PI) - PI).abs() < 1e-12);
        assert!((wrap(3.0 * PI / 2.0) + PI / 2.0).abs() < 1e-12);
        assert!((wrap(-5.0 * PI / 2.0) + PI / 2.0).abs() < 1e-12);
    }
}
