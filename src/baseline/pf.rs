//! Monte Carlo localization after paper 004 (Slušný, Neruda & Vidnerová, *Localization with a
//! low-cost robot*): a set of pose hypotheses moved by a noisy differential-drive odometry model,
//! weighted by how well each explains the landmark readings, and resampled.
//!
//! **Motion (paper 004 eqs. 1–5).** The paper integrates wheel travel: `Δθ = (Δs_R − Δs_L)/L`
//! (eq. 2), `Δs = (Δs_R + Δs_L)/2` (eq. 3), `Δx = Δs·cos(θ + Δθ/2)`, `Δy = Δs·sin(θ + Δθ/2)`
//! (eqs. 4–5), added to the old pose (eq. 1). Our frames carry the increment already in the
//! robot frame at the start of the interval, `Odometry { forward, left, turn }`. Eqs. 4–5 say the
//! displacement in that frame is `Δs·(cos Δθ/2, sin Δθ/2)`, so we read the paper's quantities off
//! the increment as `Δs = hypot(forward, left)`, chord angle `φ = atan2(left, forward)`
//! (= Δθ/2 for wheel odometry) and `Δθ = turn`, and apply `Δx = Δs·cos(θ + φ)`,
//! `Δy = Δs·sin(θ + φ)`, `θ += Δθ` ([`apply_motion`]). For wheel-derived increments
//! ([`wheel_increment`], eqs. 2–3) this is exactly eqs. 4–5; for increments with a lateral part
//! the paper's model has no term, and ours moves along the measured chord.
//!
//! **Noise.** The paper samples from `p(x_t | x_{t−1}, u)` without giving its form; we perturb the
//! two quantities of eqs. 2–3 (`Δs` by σ_s = `trans_per_m`·|Δs| + `trans_per_rad`·|Δθ|, `Δθ` by
//! σ_θ = `rot_per_rad`·|Δθ| + `rot_per_m`·|Δs|, the chord angle by half the `Δθ` perturbation, as
//! eq. 4 implies) and add a random walk of `xy_per_sqrt_s`·√dt (position) and
//! `theta_per_sqrt_s`·√dt (heading) for slip the wheels do not see.
//!
//! **Weights.** The paper lowers a particle's importance factor `w = p(z | x)` "the bigger the
//! mismatch" between the observed and expected landmark bearing (its range was too noisy to
//! use). We use the Gaussian of that mismatch, and of the range mismatch when a range is given:
//! `ℓ = (1 − ε)·exp(−½[(Δr/σ_r)² + (Δb/σ_b)²]) + ε` with `σ_r = range_sigma_abs +
//! range_sigma_rel·r`, `σ_b = bearing_sigma`, and an outlier floor `ε = outlier` so that one
//! wrong reading cannot wipe out the particle set. Weights are multiplied per reading and
//! renormalised.
//!
//! **Resampling.** Paper 004 resamples every step ("draws with replacement M particles"); we
//! resample with the low-variance (systematic) scheme ([`low_variance_resample`]) whenever the
//! effective sample size `(Σw)²/Σw²` drops below `resample_below · N` (1.0 resamples after
//! every reading, as the paper does).
//!
//! **Injection** (not in paper 004; needed for kidnapping): before the resampling test, each
//! particle is replaced with probability `p` by a particle drawn from the current reading
//! (sensor resetting, Lenser & Veloso 2000, cited by paper 001): on the circle of the measured
//! range around the landmark, facing it at the measured bearing. `p` is a fixed fraction, or
//! augmented MCL's `max(0, 1 − w_fast/w_slow)` (Thrun, Burgard & Fox, *Probabilistic Robotics*
//! §8.3.5) capped at `max_fraction`, where `w_slow`, `w_fast` follow the mean likelihood of the
//! readings with rates `alpha_slow < alpha_fast`.
//!
//! **Estimate.** Weighted mean position, circular weighted mean heading; heading reliability is
//! the mean resultant length of the headings; position **reliability** is the weight fraction of
//! the particles within `reliability_radius` of the mean.
//!
//! Initialisation is uniform over the bounds and all headings (total ignorance, like the grid).
//! Every random draw comes from one [`SplitMix64`] seeded at construction: a seed gives the same
//! run, bit for bit.
//!
//! May depend on `grid` (types), `localize`, `core::rng`.
//!
//! # Complexity
//!
//! [`Localizer::predict`] and [`Localizer::observe`] are O(N) for N particles (resampling
//! included), [`Localizer::estimate`] O(N); memory O(N).
//!
//! # Example
//!
//! ```
//! use lplace::baseline::{ParticleFilter, PfConfig};
//! use lplace::grid::{Landmark, LandmarkTable, Observation};
//! use lplace::localize::Localizer;
//! let table = LandmarkTable::new(vec![
//!     Landmark { id: 1, x: 0.0, y: 0.0 },
//!     Landmark { id: 2, x: 4.0, y: 0.0 },
//!     Landmark { id: 3, x: 0.0, y: 4.0 },
//! ]).unwrap();
//! let cfg = PfConfig { particles: 2000, ..PfConfig::default() };
//! let mut pf = ParticleFilter::new(&table, &cfg, [-1.0, -1.0, 5.0, 5.0], 1)?;
//! // The robot stands at (1, 1) facing +x.
//! for _ in 0..10 {
//!     for (id, lx, ly) in [(1, 0.0f32, 0.0f32), (2, 4.0, 0.0), (3, 0.0, 4.0)] {
//!         let (dx, dy) = (lx - 1.0, ly - 1.0);
//!         let obs = Observation { landmark: id, range: Some(dx.hypot(dy)), bearing: Some(dy.atan2(dx)) };
//!         pf.observe(&table, &obs)?;
//!     }
//! }
//! let e = pf.estimate();
//! assert!((e.pose.x - 1.0).hypot(e.pose.y - 1.0) < 0.3);
//! # Ok::<(), lplace::baseline::BaselineError>(())
//! ```

use super::Reading;
use super::{check_bounds, check_motion, check_observation, ron_error, BaselineError};
use crate::core::angle::wrap_pi;
use crate::core::rng::SplitMix64;
use crate::core::{Odometry, Pose2};
use crate::grid::{LandmarkTable, Observation};
use crate::localize::{Localizer, PoseEstimate};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// How random particles are injected (kidnap recovery).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Injection {
    /// Never: a plain particle filter, which cannot recover once the set has collapsed.
    Off,
    /// Each particle is replaced with this probability after every reading.
    Fixed {
        /// Probability in [0, 1].
        fraction: f64,
    },
    /// Augmented MCL: probability `max(0, 1 − w_fast/w_slow)`, capped.
    Augmented {
        /// Rate of the long-term average of the likelihood, in (0, 1].
        alpha_slow: f64,
        /// Rate of the short-term average, in (0, 1], larger than `alpha_slow`.
        alpha_fast: f64,
        /// Largest replacement probability, in [0, 1].
        max_fraction: f64,
    },
}

/// Parameters of the particle filter (see the module docs for the model each one enters).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PfConfig {
    /// Number of particles N. Default 500 (paper 004 used 2000 in a 1 × 0.75 m arena).
    pub particles: usize,
    /// σ of Δs per metre travelled. Default 0.1.
    pub trans_per_m: f64,
    /// σ of Δs (m) per radian turned. Default 0.02.
    pub trans_per_rad: f64,
    /// σ of Δθ per radian turned. Default 0.1.
    pub rot_per_rad: f64,
    /// σ of Δθ (rad) per metre travelled. Default 0.1.
    pub rot_per_m: f64,
    /// Position random walk (m per √s). Default 0.02.
    pub xy_per_sqrt_s: f64,
    /// Heading random walk (rad per √s). Default 0.05 (0.02 on MRCLAM robot 1 let the set settle
    /// on a wrong heading when only one landmark is in view and stay there for a minute).
    pub theta_per_sqrt_s: f64,
    /// Constant part of the range σ (m). Default 0.15.
    pub range_sigma_abs: f64,
    /// Part of the range σ proportional to the reading. Default 0.1.
    pub range_sigma_rel: f64,
    /// Bearing σ (rad). Default 0.1.
    pub bearing_sigma: f64,
    /// Outlier floor ε of the likelihood, in [0, 1). Default 0.1.
    pub outlier: f64,
    /// Resample when the effective sample size falls below this fraction of N. Default 0.5.
    pub resample_below: f64,
    /// Random-particle injection. Default augmented MCL (0.001, 0.1, cap 0.05).
    pub injection: Injection,
    /// Radius (m) of the reliability: weight fraction within it of the mean. Default 0.5.
    pub reliability_radius: f64,
    /// Reliability from which the estimate counts as a fix. Default 0.8.
    pub fix_reliability: f32,
    /// Shortest time (s) between two fed readings of one landmark (the driver thins): a camera
    /// rereads a landmark several times a second with the same error, and the weights treat
    /// readings as independent. Default 0.5 (on MRCLAM robot 1, 0 gave 3.8 m worst error, 0.5
    /// gave 0.9 m).
    pub reobserve_interval: f64,
    /// Factor on the odometry's translation before the motion model uses it: a calibration of
    /// the odometry against ground truth, as the grid's `forward_scale`. Default 1.
    pub forward_scale: f64,
    /// Factor on the odometry's rotation, likewise (the grid's `turn_scale`). Default 1.
    pub turn_scale: f64,
}

impl Default for PfConfig {
    fn default() -> Self {
        PfConfig {
            particles: 500,
            trans_per_m: 0.1,
            trans_per_rad: 0.02,
            rot_per_rad: 0.1,
            rot_per_m: 0.1,
            xy_per_sqrt_s: 0.02,
            theta_per_sqrt_s: 0.05,
            range_sigma_abs: 0.15,
            range_sigma_rel: 0.1,
            bearing_sigma: 0.1,
            outlier: 0.1,
            resample_below: 0.5,
            injection: Injection::Augmented {
                alpha_slow: 0.001,
                alpha_fast: 0.1,
                max_fraction: 0.05,
            },
            reliability_radius: 0.5,
            fix_reliability: 0.8,
            reobserve_interval: 0.5,
            forward_scale: 1.0,
            turn_scale: 1.0,
        }
    }
}

/// Largest particle count accepted (memory: 40 bytes per particle).
pub const MAX_PARTICLES: usize = 10_000_000;

impl PfConfig {
    /// Parses a RON document (missing fields take their defaults) and checks it.
    pub fn from_ron(text: &str) -> Result<Self, BaselineError> {
        let cfg: PfConfig = crate::core::config::from_ron(text).map_err(ron_error)?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Checks ranges; the filter may assume a validated configuration.
    pub fn validate(&self) -> Result<(), BaselineError> {
        let bad = |field, reason| Err(BaselineError::BadConfig { field, reason });
        if self.particles == 0 || self.particles > MAX_PARTICLES {
            return bad("particles", "must be in 1..=10_000_000");
        }
        for (field, v) in [
            ("trans_per_m", self.trans_per_m),
            ("trans_per_rad", self.trans_per_rad),
            ("rot_per_rad", self.rot_per_rad),
            ("rot_per_m", self.rot_per_m),
            ("xy_per_sqrt_s", self.xy_per_sqrt_s),
            ("theta_per_sqrt_s", self.theta_per_sqrt_s),
            ("range_sigma_rel", self.range_sigma_rel),
            ("reobserve_interval", self.reobserve_interval),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(field, "must be finite and ≥ 0");
            }
        }
        for (field, v) in [
            ("range_sigma_abs", self.range_sigma_abs),
            ("bearing_sigma", self.bearing_sigma),
            ("reliability_radius", self.reliability_radius),
            ("forward_scale", self.forward_scale),
            ("turn_scale", self.turn_scale),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return bad(field, "must be finite and > 0");
            }
        }
        if !(0.0..1.0).contains(&self.outlier) {
            return bad("outlier", "must be in [0, 1)");
        }
        if !(0.0..=1.0).contains(&self.resample_below) {
            return bad("resample_below", "must be in [0, 1]");
        }
        if !(0.0..=1.0).contains(&self.fix_reliability) {
            return bad("fix_reliability", "must be in [0, 1]");
        }
        match self.injection {
            Injection::Off => {}
            Injection::Fixed { fraction } => {
                if !(0.0..=1.0).contains(&fraction) {
                    return bad("injection", "fraction must be in [0, 1]");
                }
            }
            Injection::Augmented {
                alpha_slow,
                alpha_fast,
                max_fraction,
            } => {
                let rate = |a: f64| a > 0.0 && a <= 1.0;
                if !(rate(alpha_slow) && rate(alpha_fast) && alpha_slow < alpha_fast) {
                    return bad("injection", "need 0 < alpha_slow < alpha_fast ≤ 1");
                }
                if !(0.0..=1.0).contains(&max_fraction) {
                    return bad("injection", "max_fraction must be in [0, 1]");
                }
            }
        }
        Ok(())
    }
}

/// Eqs. 2–3 of paper 004: the robot-frame increment of wheel travels `ds_left`, `ds_right` (m)
/// on a track of width `track` (m), with the displacement along the chord of eqs. 4–5:
/// `forward = Δs·cos(Δθ/2)`, `left = Δs·sin(Δθ/2)`, `turn = Δθ`.
///
/// # Example
/// ```
/// use lplace::baseline::pf::wheel_increment;
/// // Both wheels 0.1 m: straight ahead.
/// let m = wheel_increment(0.1, 0.1, 0.053);
/// assert_eq!((m.forward, m.left, m.turn), (0.1, 0.0, 0.0));
/// ```
pub fn wheel_increment(ds_left: f64, ds_right: f64, track: f64) -> Odometry {
    let dtheta = (ds_right - ds_left) / track; // eq. 2
    let ds = 0.5 * (ds_right + ds_left); // eq. 3
    Odometry {
        forward: ds * (0.5 * dtheta).cos(),
        left: ds * (0.5 * dtheta).sin(),
        turn: dtheta,
    }
}

/// Eqs. 1, 4, 5 of paper 004 on a robot-frame increment (noise-free; see the module docs for the
/// mapping): `Δs = hypot(forward, left)`, `φ = atan2(left, forward)`,
/// `x += Δs·cos(θ + φ)`, `y += Δs·sin(θ + φ)`, `θ ← wrap_pi(θ + turn)`.
///
/// # Example
/// ```
/// use lplace::baseline::pf::apply_motion;
/// use lplace::core::{Odometry, Pose2};
/// let p = apply_motion(Pose2 { x: 0.0, y: 0.0, theta: std::f64::consts::FRAC_PI_2 },
///                      &Odometry { forward: 1.0, left: 0.0, turn: 0.0 });
/// assert!(p.x.abs() < 1e-7 && (p.y - 1.0).abs() < 1e-7);
/// ```
pub fn apply_motion(p: Pose2, odometry: &Odometry) -> Pose2 {
    let (f, l) = (odometry.forward, odometry.left);
    let ds = f.hypot(l);
    let phi = l.atan2(f);
    Pose2 {
        x: p.x + ds * (p.theta + phi).cos(),
        y: p.y + ds * (p.theta + phi).sin(),
        theta: wrap_pi(p.theta + odometry.turn),
    }
}

/// Low-variance (systematic) resampling (*Probabilistic Robotics*, Table 4.4): one random
/// offset `start ∈ [0, 1)`, then N equally spaced pointers `U_m = (start + m)·Σw/N` into the
/// cumulative weights; `out[m]` is the index whose cumulative interval contains `U_m`. Each index
/// is copied ⌊N·w_i/Σw⌋ or ⌈N·w_i/Σw⌉ times. Weights need not be normalised; when their sum is
/// not finite and positive, `out` is the identity (nothing is known to prefer).
///
/// # Complexity
/// O(N).
///
/// # Example
/// ```
/// use lplace::baseline::pf::low_variance_resample;
/// let mut out = Vec::new();
/// low_variance_resample(&[0.0, 3.0, 1.0, 0.0], 0.5, &mut out);
/// // Pointers at 0.5, 1.5, 2.5, 3.5 of the cumulative [0, 0, 3, 4].
/// assert_eq!(out, vec![1, 1, 1, 2]);
/// ```
pub fn low_variance_resample(weights: &[f64], start: f64, out: &mut Vec<usize>) {
    out.clear();
    let n = weights.len();
    let total: f64 = weights.iter().sum();
    if n == 0 {
        return;
    }
    if !(total.is_finite() && total > 0.0) {
        out.extend(0..n);
        return;
    }
    let step = total / n as f64;
    let start = if (0.0..1.0).contains(&start) {
        start
    } else {
        0.0
    };
    let mut i = 0;
    let mut c = weights[0];
    for m in 0..n {
        let u = (start + m as f64) * step;
        while u >= c && i + 1 < n {
            i += 1;
            c += weights[i];
        }
        out.push(i);
    }
}

/// Paper 004's particle filter as a [`Localizer`] (see the module docs).
#[derive(Debug, Clone)]
pub struct ParticleFilter {
    cfg: PfConfig,
    bounds: [f64; 4],
    rng: SplitMix64,
    x: Vec<f64>,
    y: Vec<f64>,
    th: Vec<f64>,
    w: Vec<f64>,
    /// Scratch for the update and resampling (allocated once).
    w_new: Vec<f64>,
    idx: Vec<usize>,
    tmp: Vec<f64>,
    w_slow: f64,
    w_fast: f64,
    resamples: usize,
    injected: usize,
}

impl ParticleFilter {
    /// A filter of `cfg.particles` particles spread uniformly over `bounds = [x_min, y_min, x_max,
    /// y_max]` and all headings, drawing from a generator seeded with `seed`.
    pub fn new(
        _table: &LandmarkTable,
        cfg: &PfConfig,
        bounds: [f32; 4],
        seed: u64,
    ) -> Result<Self, BaselineError> {
        cfg.validate()?;
        check_bounds(bounds)?;
        let n = cfg.particles;
        let mut pf = ParticleFilter {
            cfg: cfg.clone(),
            bounds: bounds.map(f64::from),
            rng: SplitMix64::new(seed),
            x: vec![0.0; n],
            y: vec![0.0; n],
            th: vec![0.0; n],
            w: vec![1.0 / n as f64; n],
            w_new: vec![0.0; n],
            idx: Vec::with_capacity(n),
            tmp: vec![0.0; n],
            w_slow: 0.0,
            w_fast: 0.0,
            resamples: 0,
            injected: 0,
        };
        for i in 0..n {
            let (x, y, th) = pf.uniform_pose();
            pf.x[i] = x;
            pf.y[i] = y;
            pf.th[i] = th;
        }
        Ok(pf)
    }

    /// Puts every particle at `pose`, weights equal (tracking from a known pose instead of
    /// global localization); the motion noise spreads them from the first prediction on.
    ///
    /// # Errors
    /// [`BaselineError::BadConfig`] (field `start`) when a value of `pose` is not finite; the
    /// particles are then unchanged.
    pub fn start_at(&mut self, pose: Pose2) -> Result<(), BaselineError> {
        if !(pose.x.is_finite() && pose.y.is_finite() && pose.theta.is_finite()) {
            return Err(BaselineError::BadConfig {
                field: "start",
                reason: "the start pose must be finite",
            });
        }
        let n = self.x.len();
        self.x.fill(pose.x);
        self.y.fill(pose.y);
        self.th.fill(wrap_pi(pose.theta));
        self.w.fill(1.0 / n.max(1) as f64);
        Ok(())
    }

    /// The configuration.
    pub fn config(&self) -> &PfConfig {
        &self.cfg
    }

    /// Particles as `(x, y, θ, weight)` (weights sum to 1).
    pub fn particles(&self) -> impl Iterator<Item = (f64, f64, f64, f64)> + '_ {
        (0..self.x.len()).map(|i| (self.x[i], self.y[i], self.th[i], self.w[i]))
    }

    /// Number of resamplings so far.
    pub fn resamples(&self) -> usize {
        self.resamples
    }

    /// Number of particles replaced by injection so far.
    pub fn injected(&self) -> usize {
        self.injected
    }

    /// Effective sample size `(Σw)²/Σw²`.
    pub fn effective_sample_size(&self) -> f64 {
        let s: f64 = self.w.iter().sum();
        let s2: f64 = self.w.iter().map(|w| w * w).sum();
        if s2 > 0.0 {
            s * s / s2
        } else {
            0.0
        }
    }

    fn uniform_pose(&mut self) -> (f64, f64, f64) {
        let [x0, y0, x1, y1] = self.bounds;
        (
            self.rng.uniform(x0, x1),
            self.rng.uniform(y0, y1),
            self.rng.uniform(-PI, PI),
        )
    }

    /// A pose drawn from one reading (sensor resetting): on the range circle, facing the
    /// landmark at the measured bearing, with the sensor noise of the likelihood.
    fn pose_from_reading(&mut self, r: &Reading) -> (f64, f64, f64) {
        let (x, y) = match r.range {
            Some(range) => {
                let rr = (range + self.range_sigma(range) * self.rng.normal()).max(0.0);
                let a = self.rng.uniform(-PI, PI);
                (r.lx + rr * a.cos(), r.ly + rr * a.sin())
            }
            None => {
                let (x, y, _) = self.uniform_pose();
                (x, y)
            }
        };
        let th = match r.bearing {
            Some(b) => {
                wrap_pi((r.ly - y).atan2(r.lx - x) - b + self.cfg.bearing_sigma * self.rng.normal())
            }
            None => self.rng.uniform(-PI, PI),
        };
        (x, y, th)
    }

    fn range_sigma(&self, r: f64) -> f64 {
        self.cfg.range_sigma_abs + self.cfg.range_sigma_rel * r
    }

    /// Likelihood factor ℓ of one reading for a pose (module docs).
    fn likelihood(&self, r: &Reading, x: f64, y: f64, th: f64) -> f64 {
        let (dx, dy) = (r.lx - x, r.ly - y);
        let mut q = 0.0;
        if let Some(range) = r.range {
            let e = (range - dx.hypot(dy)) / self.range_sigma(range);
            q += e * e;
        }
        if let Some(b) = r.bearing {
            let e = wrap_pi(dy.atan2(dx) - th - b) / self.cfg.bearing_sigma;
            q += e * e;
        }
        let eps = self.cfg.outlier;
        (1.0 - eps) * (-0.5 * q).exp() + eps
    }

    fn injection_probability(&mut self, mean_likelihood: f64) -> f64 {
        match self.cfg.injection {
            Injection::Off => 0.0,
            Injection::Fixed { fraction } => fraction,
            Injection::Augmented {
                alpha_slow,
                alpha_fast,
                max_fraction,
            } => {
                // Both averages start at the first reading's mean likelihood: started at 0 (as
                // in Probabilistic Robotics), `w_slow` lags `w_fast` for ~1/alpha_slow readings
                // and no particle is injected in that time, however bad the readings get.
                if self.w_slow <= 0.0 {
                    self.w_slow = mean_likelihood;
                    self.w_fast = mean_likelihood;
                }
                self.w_slow += alpha_slow * (mean_likelihood - self.w_slow);
                self.w_fast += alpha_fast * (mean_likelihood - self.w_fast);
                if self.w_slow > 0.0 {
                    (1.0 - self.w_fast / self.w_slow).clamp(0.0, max_fraction)
                } else {
                    0.0
                }
            }
        }
    }

    fn resample(&mut self) {
        let start = self.rng.unit();
        low_variance_resample(&self.w, start, &mut self.idx);
        for v in [&mut self.x, &mut self.y, &mut self.th] {
            for (t, &i) in self.tmp.iter_mut().zip(&self.idx) {
                *t = v.get(i).copied().unwrap_or_default();
            }
            v.copy_from_slice(&self.tmp);
        }
        let n = self.w.len() as f64;
        self.w.iter_mut().for_each(|w| *w = 1.0 / n);
        self.resamples += 1;
    }
}

impl Localizer for ParticleFilter {
    type Error = BaselineError;

    fn predict(&mut self, odometry: &Odometry, dt: f64) -> Result<(), BaselineError> {
        check_motion(odometry, dt)?;
        let odometry = odometry.scaled(self.cfg.forward_scale, self.cfg.turn_scale);
        let (f, l) = (odometry.forward, odometry.left);
        let ds = f.hypot(l);
        let phi = l.atan2(f);
        let turn = odometry.turn;
        let c = &self.cfg;
        let sig_s = c.trans_per_m * ds + c.trans_per_rad * turn.abs();
        let sig_t = c.rot_per_rad * turn.abs() + c.rot_per_m * ds;
        let sdt = dt.sqrt();
        let (sig_xy, sig_th) = (c.xy_per_sqrt_s * sdt, c.theta_per_sqrt_s * sdt);
        for i in 0..self.x.len() {
            let ds_i = ds + sig_s * self.rng.normal();
            let dturn = sig_t * self.rng.normal();
            // Eq. 4–5: the chord turns with half the perturbed rotation.
            let a = self.th[i] + phi + 0.5 * dturn;
            self.x[i] += ds_i * a.cos() + sig_xy * self.rng.normal();
            self.y[i] += ds_i * a.sin() + sig_xy * self.rng.normal();
            self.th[i] = wrap_pi(self.th[i] + turn + dturn + sig_th * self.rng.normal());
        }
        Ok(())
    }

    fn observe(&mut self, table: &LandmarkTable, obs: &Observation) -> Result<(), BaselineError> {
        let r = check_observation(table, obs)?;
        if r.range.is_none() && r.bearing.is_none() {
            return Ok(());
        }
        let mut total = 0.0;
        let mut mean_l = 0.0;
        for i in 0..self.x.len() {
            let l = self.likelihood(&r, self.x[i], self.y[i], self.th[i]);
            mean_l += self.w[i] * l;
            self.w_new[i] = self.w[i] * l;
            total += self.w_new[i];
        }
        // With ε = 0 a reading can contradict every particle: it then carries no usable
        // information and the weights stay as they were.
        if total.is_finite() && total > 0.0 {
            for (w, wn) in self.w.iter_mut().zip(&self.w_new) {
                *w = wn / total;
            }
        }
        let p = self.injection_probability(mean_l);
        if p > 0.0 {
            let n = self.w.len() as f64;
            for i in 0..self.x.len() {
                if self.rng.chance(p) {
                    let (x, y, th) = self.pose_from_reading(&r);
                    self.x[i] = x;
                    self.y[i] = y;
                    self.th[i] = th;
                    self.w[i] = 1.0 / n;
                    self.injected += 1;
                }
            }
            let s: f64 = self.w.iter().sum();
            self.w.iter_mut().for_each(|w| *w /= s);
        }
        if self.effective_sample_size() < self.cfg.resample_below * self.w.len() as f64
            || self.cfg.resample_below >= 1.0
        {
            self.resample();
        }
        Ok(())
    }

    fn estimate(&mut self) -> PoseEstimate {
        let (mut sx, mut sy, mut sc, mut ss, mut sw) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for i in 0..self.x.len() {
            let w = self.w[i];
            sx += w * self.x[i];
            sy += w * self.y[i];
            sc += w * self.th[i].cos();
            ss += w * self.th[i].sin();
            sw += w;
        }
        let sw = if sw > 0.0 { sw } else { 1.0 };
        let (mx, my) = (sx / sw, sy / sw);
        let rad = self.cfg.reliability_radius;
        let near: f64 = (0..self.x.len())
            .filter(|&i| (self.x[i] - mx).hypot(self.y[i] - my) <= rad)
            .map(|i| self.w[i])
            .sum();
        PoseEstimate {
            pose: Pose2 {
                x: mx,
                y: my,
                theta: ss.atan2(sc),
            },
            reliability: (near / sw).clamp(0.0, 1.0) as f32,
            heading_reliability: (sc.hypot(ss) / sw).clamp(0.0, 1.0) as f32,
        }
    }

    fn fix_reliability(&self) -> f32 {
        self.cfg.fix_reliability
    }

    fn reobserve_interval(&self) -> f64 {
        self.cfg.reobserve_interval
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn config_rejects_unknown_keys_and_defaults_omitted_ones() {
        let ok = PfConfig::from_ron("(particles: 300)").unwrap();
        assert_eq!(ok.particles, 300);
        assert_eq!(ok.outlier, PfConfig::default().outlier);
        for text in [
            "(particles: 300, totally_bogus_field: 1)",
            "(injection: Fixed(fraction: 0.1, totally_bogus_field: 1))",
        ] {
            match PfConfig::from_ron(text) {
                Err(BaselineError::Ron { problem, line, .. }) => {
                    let message = problem.to_string();
                    assert!(message.contains("totally_bogus_field"), "{message}");
                    assert_eq!(line, 1);
                }
                other => panic!("{text}: {other:?}"),
            }
        }
    }

    #[test]
    fn low_variance_hand_case() {
        // Weights 1, 1, 2 (sum 4), N = 3: step 4/3; start 0.25 → pointers 1/3, 5/3, 3.
        // Cumulative bounds 1, 2, 4: 1/3 → 0, 5/3 → 1, 3 → 2.
        let mut out = Vec::new();
        low_variance_resample(&[1.0, 1.0, 2.0], 0.25, &mut out);
        assert_eq!(out, vec![0, 1, 2]);
        // Start 0.9 → pointers 1.2, 2.53, 3.87 → 1, 2, 2.
        low_variance_resample(&[1.0, 1.0, 2.0], 0.9, &mut out);
        assert_eq!(out, vec![1, 2, 2]);
    }

    #[test]
    fn degenerate_weights_keep_the_set() {
        let mut out = Vec::new();
        low_variance_resample(&[0.0, 0.0], 0.3, &mut out);
        assert_eq!(out, vec![0, 1]);
        low_variance_resample(&[], 0.3, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn augmented_injection_hand_case() {
        let table = LandmarkTable::new(vec![crate::grid::Landmark {
            id: 1,
            x: 0.0,
            y: 0.0,
        }])
        .unwrap();
        let cfg = PfConfig {
            injection: Injection::Augmented {
                alpha_slow: 0.001,
                alpha_fast: 0.1,
                max_fraction: 1.0,
            },
            ..PfConfig::default()
        };
        let mut pf = ParticleFilter::new(&table, &cfg, [0.0, 0.0, 1.0, 1.0], 1).unwrap();
        // First reading: both averages start at 0.5 and stay there → p = 0.
        assert_eq!(pf.injection_probability(0.5), 0.0);
        // Mean likelihood drops to 0.1: w_slow = 0.5 + 0.001·(0.1 − 0.5) = 0.4996,
        // w_fast = 0.5 + 0.1·(0.1 − 0.5) = 0.46, p = 1 − 0.46/0.4996 = 0.079263.
        let p = pf.injection_probability(0.1);
        assert!((p - 0.079_263).abs() < 1e-6, "{p}");
    }

    #[test]
    fn likelihood_hand_case() {
        let table = LandmarkTable::new(vec![crate::grid::Landmark {
            id: 1,
            x: 3.0,
            y: 4.0,
        }])
        .unwrap();
        let cfg = PfConfig {
            range_sigma_abs: 0.5,
            range_sigma_rel: 0.0,
            bearing_sigma: 0.1,
            outlier: 0.1,
            ..PfConfig::default()
        };
        let pf = ParticleFilter::new(&table, &cfg, [0.0, 0.0, 1.0, 1.0], 1).unwrap();
        // Pose (0, 0, 0): expected range 5, bearing atan2(4, 3) = 0.9273.
        // Range 5.5 → e = 0.5/0.5 = 1; bearing exact → e = 0; q = 1.
        // ℓ = 0.9·exp(−0.5) + 0.1 = 0.9·0.60653 + 0.1 = 0.64588.
        let r = Reading {
            lx: 3.0,
            ly: 4.0,
            range: Some(5.5),
            bearing: Some(0.927_295_2),
        };
        let l = pf.likelihood(&r, 0.0, 0.0, 0.0);
        assert!((l - 0.645_88).abs() < 1e-4, "{l}");
    }

    #[test]
    fn start_at_puts_every_particle_on_the_pose_and_rejects_nan() {
        let t = LandmarkTable::new(vec![]).unwrap();
        let mut pf =
            ParticleFilter::new(&t, &PfConfig::default(), [0.0, 0.0, 5.0, 5.0], 3).unwrap();
        let p = Pose2 {
            x: 1.5,
            y: 2.5,
            theta: -3.0,
        };
        pf.start_at(p).unwrap();
        let e = pf.estimate();
        assert!(
            (e.pose.x - 1.5).abs() < 1e-9 && (e.pose.y - 2.5).abs() < 1e-9,
            "{e:?}"
        );
        assert!((e.pose.theta + 3.0).abs() < 1e-9, "{e:?}");
        assert_eq!(e.reliability, 1.0);
        assert!(pf.start_at(Pose2 { x: f64::NAN, ..p }).is_err());
        assert!(pf.particles().all(|(x, _, _, _)| x == 1.5));
    }

    #[test]
    fn the_odometry_calibration_scales_the_motion() {
        let t = LandmarkTable::new(vec![]).unwrap();
        // Noise-free motion model: each particle moves by exactly the scaled increment.
        let cfg = PfConfig {
            particles: 4,
            trans_per_m: 0.0,
            trans_per_rad: 0.0,
            rot_per_rad: 0.0,
            rot_per_m: 0.0,
            xy_per_sqrt_s: 0.0,
            theta_per_sqrt_s: 0.0,
            forward_scale: 0.5,
            turn_scale: 2.0,
            ..PfConfig::default()
        };
        let mut pf = ParticleFilter::new(&t, &cfg, [0.0, 0.0, 5.0, 5.0], 3).unwrap();
        let start = Pose2 {
            x: 1.0,
            y: 1.0,
            theta: 0.0,
        };
        pf.start_at(start).unwrap();
        let step = Odometry {
            forward: 2.0,
            left: 0.0,
            turn: 0.25,
        };
        pf.predict(&step, 1.0).unwrap();
        // 2 m × 0.5 along θ = 0 (the chord turns by half the perturbation, here 0), 0.25 × 2 rad.
        for (x, y, th, _) in pf.particles() {
            assert!(
                (x - 2.0).abs() < 1e-12 && (y - 1.0).abs() < 1e-12,
                "{x} {y}"
            );
            assert!((th - 0.5).abs() < 1e-12, "{th}");
        }
        let zero = PfConfig {
            forward_scale: 0.0,
            ..PfConfig::default()
        };
        assert!(zero.validate().is_err());
    }
}
