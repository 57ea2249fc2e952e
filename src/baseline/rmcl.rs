//! Fuzzy Reverse Monte Carlo Localization after paper 001 (Köse & Akın, *A Fuzzy Touch to R-MCL
//! Localization Algorithm*): a grid stage finds the region the robot must be in, and a few
//! samples drawn inside its best cells give the precise position.
//!
//! **Grid stage.** Paper 001 uses a Markov grid of 30 cm cells; we use the crate's Fuzzy Position
//! Grid ([`GridLocalizer`], paper 000) with its own [`GridConfig`], fed every reading and every
//! odometry increment. At each [`Localizer::estimate`], the *best cells* are those of the grid's
//! top region (`h ≥ top_cut · h_max`) that agree with every reading of the frame "not only
//! \[in\] the distance but also the bearing" (§3): for the cell centre `c` and the cell's heading
//! (the centre of its heading set, or the grid's heading when the set is the full circle),
//! `|r − ‖L − c‖| ≤ cell_distance_error + half the cell diagonal` and
//! `|wrap_pi(∠(L − c) − θ − b)| ≤ cell_bearing_error`.
//!
//! **Certainty condition** (§3): samples are drawn only when there is at least one best cell and
//! no more than `max_cells` of them.
//!
//! **Samples.** `samples_per_cell` points uniform in each best cell (seeded generator). Each is
//! weighted by the fuzzy membership μ₂ of the distance error `d_i = r_i − ‖L_i − s‖` of each
//! reading (§4), combined over the frame's readings by the minimum (fuzzy *and*). Paper 001
//! gives μ₂ only as its Fig. 2(b), which our copy of the paper does not contain; we use the
//! trapezoid `μ₂(d) = 1` for `|d| ≤ distance_core`, falling linearly to 0 at
//! `distance_core + distance_slope` (paper 001 reports trapezoids among the shapes it tried).
//! A sample *qualifies* when its weight is at least `min_membership` and its bearing error
//! (with the cell's heading) is at most `sample_bearing_error` for every reading.
//!
//! **Pose.** The membership-weighted mean of the *best samples* — the qualifying samples whose
//! weight is at least `best_fraction` of the largest; the heading is the grid's ("the bearing of
//! the new pose is found by the ML module", §3). When the certainty condition fails or no sample
//! qualifies, the estimate is the grid's: a **fallback**, counted by [`FuzzyRmcl::fallbacks`].
//! Reliability and fix threshold are the grid's (the samples refine the position inside the region
//! the grid has already committed to; they do not add certainty).
//!
//! **Between readings.** The best samples are kept and moved by each odometry increment along
//! their own heading (the MCL half's motion step: paper 001 weighs samples by "their fitness to
//! the observation *and odometry*", §4), so a frame without readings is estimated by the
//! weighted mean of the carried samples ([`FuzzyRmcl::carried`]) — not by the grid, which would
//! make R-MCL the grid on every such frame. The carried set is replaced by the next frame with
//! readings and dropped at a fallback (the ML result is used instead, §3). Before the first
//! sampled frame, and after a fallback, frames without readings are the grid's. Our copy of the
//! paper lacks its flowchart (Fig. 1), so this reading of the text is ours.
//!
//! May depend on `grid`, `localize`, `core::rng`.
//!
//! # Complexity
//!
//! Per frame: the grid's own cost, plus O(cells · readings) to pick the best cells and
//! O(max_cells · samples_per_cell · readings) for the samples; per odometry increment
//! O(carried samples), at most max_cells · samples_per_cell; memory O(cells) (the grid).
//!
//! # Example
//!
//! ```
//! use lplace::baseline::{FuzzyRmcl, RmclConfig};
//! use lplace::grid::{GridConfig, Landmark, LandmarkTable, Observation};
//! use lplace::localize::Localizer;
//! let table = LandmarkTable::new(vec![
//!     Landmark { id: 1, x: 0.0, y: 0.0 },
//!     Landmark { id: 2, x: 3.0, y: 0.0 },
//!     Landmark { id: 3, x: 0.0, y: 2.0 },
//! ]).unwrap();
//! let mut rmcl = FuzzyRmcl::new(&table, &RmclConfig::default(), &GridConfig::default(),
//!                               [-1.0, -1.0, 4.0, 3.0], 1)?;
//! for _ in 0..3 {
//!     for (id, lx, ly) in [(1, 0.0f32, 0.0f32), (2, 3.0, 0.0), (3, 0.0, 2.0)] {
//!         let (dx, dy) = (lx - 1.0, ly - 1.0);
//!         rmcl.observe(&table, &Observation { landmark: id, range: Some(dx.hypot(dy)),
//!                                             bearing: Some(dy.atan2(dx)) })?;
//!     }
//!     let e = rmcl.estimate();
//!     assert!((e.pose.x - 1.0).hypot(e.pose.y - 1.0) < 0.2);
//! }
//! # Ok::<(), lplace::baseline::BaselineError>(())
//! ```

use super::Reading;
use super::{check_bounds, check_motion, check_observation, ron_error, BaselineError};
use crate::core::angle::wrap_pi;
use crate::core::rng::SplitMix64;
use crate::core::{Odometry, Pose2};
use crate::grid::{GridConfig, LandmarkTable, Observation, Trapezoid};
use crate::localize::grid::GridLocalizer;
use crate::localize::{Localizer, PoseEstimate};
use serde::{Deserialize, Serialize};

/// Parameters of Fuzzy R-MCL's cell choice and samples (the grid has its own [`GridConfig`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RmclConfig {
    /// Candidate cells have `h ≥ top_cut · h_max`, in (0, 1]. Default 0.5.
    pub top_cut: f32,
    /// Largest number of best cells for which samples are drawn (certainty condition). Paper 001
    /// uses 50 cells of 30 cm (4.5 m²); default 450 cells of 10 cm (the same area).
    pub max_cells: usize,
    /// Largest range error (m) at a best cell's centre, beyond half its diagonal. Default 0.3.
    pub cell_distance_error: f32,
    /// Largest bearing error (rad) at a best cell's centre. Default 0.3.
    pub cell_bearing_error: f32,
    /// Samples drawn per best cell. Default 4.
    pub samples_per_cell: usize,
    /// μ₂ is 1 for range errors up to this (m). Default 0.1.
    pub distance_core: f32,
    /// μ₂ falls to 0 over this much more error (m). Default 0.3.
    pub distance_slope: f32,
    /// Largest bearing error (rad) of a qualifying sample. Default 0.2.
    pub sample_bearing_error: f32,
    /// Least weight of a qualifying sample, in [0, 1]. Default 0.3.
    pub min_membership: f32,
    /// Best samples have weight ≥ this fraction of the largest, in [0, 1]. Default 0.8.
    pub best_fraction: f32,
}

impl Default for RmclConfig {
    fn default() -> Self {
        RmclConfig {
            top_cut: 0.5,
            max_cells: 450,
            cell_distance_error: 0.3,
            cell_bearing_error: 0.3,
            samples_per_cell: 4,
            distance_core: 0.1,
            distance_slope: 0.3,
            sample_bearing_error: 0.2,
            min_membership: 0.3,
            best_fraction: 0.8,
        }
    }
}

impl RmclConfig {
    /// Parses a RON document (missing fields take their defaults) and checks it.
    pub fn from_ron(text: &str) -> Result<Self, BaselineError> {
        let cfg: RmclConfig = crate::core::config::from_ron(text).map_err(ron_error)?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Checks ranges; the method may assume a validated configuration.
    pub fn validate(&self) -> Result<(), BaselineError> {
        let bad = |field, reason| Err(BaselineError::BadConfig { field, reason });
        if !(self.top_cut > 0.0 && self.top_cut <= 1.0) {
            return bad("top_cut", "must be in (0, 1]");
        }
        if self.max_cells == 0 || self.max_cells > 1_000_000 {
            return bad("max_cells", "must be in 1..=1_000_000");
        }
        if self.samples_per_cell == 0 || self.samples_per_cell > 10_000 {
            return bad("samples_per_cell", "must be in 1..=10_000");
        }
        for (field, v) in [
            ("cell_distance_error", self.cell_distance_error),
            ("cell_bearing_error", self.cell_bearing_error),
            ("distance_core", self.distance_core),
            ("distance_slope", self.distance_slope),
            ("sample_bearing_error", self.sample_bearing_error),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(field, "must be finite and ≥ 0");
            }
        }
        for (field, v) in [
            ("min_membership", self.min_membership),
            ("best_fraction", self.best_fraction),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return bad(field, "must be in [0, 1]");
            }
        }
        Ok(())
    }

    /// μ₂ of a range error `d` (module docs).
    pub fn membership(&self, d: f32) -> f32 {
        Trapezoid::new(0.0, 2.0 * self.distance_core, self.distance_slope, 1.0, 0.0).linear(d)
    }

    /// Weight of a sample at `(x, y)` with heading `theta` against a frame's readings: the
    /// minimum over the readings of μ₂(range error), or `None` when the sample does not qualify
    /// (weight below `min_membership`, or a bearing error above `sample_bearing_error`).
    /// Readings without a range constrain only the bearing. Empty readings give `None`.
    pub fn sample_weight(
        &self,
        x: f64,
        y: f64,
        theta: f64,
        readings: &[(f64, f64, Option<f64>, Option<f64>)],
    ) -> Option<f32> {
        if readings.is_empty() {
            return None;
        }
        let mut w = 1.0f32;
        for &(lx, ly, range, bearing) in readings {
            let (dx, dy) = (lx - x, ly - y);
            if let Some(r) = range {
                w = w.min(self.membership((r - dx.hypot(dy)) as f32));
            }
            if let Some(b) = bearing {
                if wrap_pi(dy.atan2(dx) - theta - b).abs() > self.sample_bearing_error as f64 {
                    return None;
                }
            }
        }
        (w >= self.min_membership && w > 0.0).then_some(w)
    }
}

/// Fuzzy R-MCL as a [`Localizer`] (see the module docs).
#[derive(Debug, Clone)]
pub struct FuzzyRmcl {
    cfg: RmclConfig,
    grid: GridLocalizer,
    rng: SplitMix64,
    /// Readings of the current frame: landmark x, y, range, bearing.
    frame: Vec<(f64, f64, Option<f64>, Option<f64>)>,
    cells: Vec<(usize, usize, f64)>,
    /// Samples of the current frame: x, y, heading, weight.
    samples: Vec<(f64, f64, f64, f32)>,
    /// The best samples of the last sampled frame, moved by the odometry since: x, y, heading,
    /// weight.
    kept: Vec<(f64, f64, f64, f32)>,
    fallbacks: usize,
    sampled: usize,
    carried: usize,
}

impl FuzzyRmcl {
    /// Fuzzy R-MCL over `bounds = [x_min, y_min, x_max, y_max]` (metres; overrides
    /// `grid.bounds`), the grid stage in total ignorance, samples drawn from a generator seeded
    /// with `seed`.
    pub fn new(
        table: &LandmarkTable,
        cfg: &RmclConfig,
        grid: &GridConfig,
        bounds: [f32; 4],
        seed: u64,
    ) -> Result<Self, BaselineError> {
        cfg.validate()?;
        check_bounds(bounds)?;
        let gcfg = GridConfig {
            bounds: Some(bounds),
            ..grid.clone()
        };
        Ok(FuzzyRmcl {
            cfg: cfg.clone(),
            grid: GridLocalizer::new(table, &gcfg)?,
            rng: SplitMix64::new(seed),
            frame: Vec::new(),
            cells: Vec::new(),
            samples: Vec::new(),
            kept: Vec::new(),
            fallbacks: 0,
            sampled: 0,
            carried: 0,
        })
    }

    /// Frames with readings whose estimate fell back to the grid's (certainty condition failed
    /// or no sample qualified).
    pub fn fallbacks(&self) -> usize {
        self.fallbacks
    }

    /// Frames with readings whose estimate is the mean of best samples.
    pub fn sampled(&self) -> usize {
        self.sampled
    }

    /// Frames without readings whose estimate is the mean of the carried samples.
    pub fn carried(&self) -> usize {
        self.carried
    }

    /// The grid stage.
    pub fn grid(&self) -> &GridLocalizer {
        &self.grid
    }

    /// The sample stage on the current grid and frame readings; `None` is a fallback.
    fn refine(&mut self, grid_theta: f64) -> Option<(f64, f64)> {
        let g = self.grid.grid();
        let h = g.possibilities();
        let h_max = h.iter().copied().fold(0.0f32, f32::max);
        if h_max <= 0.0 {
            return None;
        }
        let cut = self.cfg.top_cut * h_max;
        let cell = g.cell_size() as f64;
        let slack = self.cfg.cell_distance_error as f64 + cell * std::f64::consts::FRAC_1_SQRT_2;
        let b_lim = self.cfg.cell_bearing_error as f64;
        self.cells.clear();
        for row in 0..g.ny() {
            for col in 0..g.nx() {
                if g.possibility(col, row) < cut {
                    continue;
                }
                let (cx, cy) = g.cell_center(col, row);
                let (cx, cy) = (cx as f64, cy as f64);
                let theta = match g.heading_set(col, row) {
                    Some(t) if !t.is_full_circle() => t.center as f64,
                    _ => grid_theta,
                };
                let good = self.frame.iter().all(|&(lx, ly, r, b)| {
                    let (dx, dy) = (lx - cx, ly - cy);
                    r.map_or(true, |r| (r - dx.hypot(dy)).abs() <= slack)
                        && b.map_or(true, |b| wrap_pi(dy.atan2(dx) - theta - b).abs() <= b_lim)
                });
                if good {
                    self.cells.push((col, row, theta));
                    if self.cells.len() > self.cfg.max_cells {
                        return None;
                    }
                }
            }
        }
        if self.cells.is_empty() {
            return None;
        }
        self.samples.clear();
        for &(col, row, theta) in &self.cells {
            let (cx, cy) = g.cell_center(col, row);
            for _ in 0..self.cfg.samples_per_cell {
                let x = cx as f64 + cell * (self.rng.unit() - 0.5);
                let y = cy as f64 + cell * (self.rng.unit() - 0.5);
                if let Some(w) = self.cfg.sample_weight(x, y, theta, &self.frame) {
                    self.samples.push((x, y, theta, w));
                }
            }
        }
        let w_max = self.samples.iter().map(|s| s.3).fold(0.0f32, f32::max);
        let best = self.cfg.best_fraction * w_max;
        self.kept.clear();
        self.kept
            .extend(self.samples.iter().filter(|s| s.3 >= best).copied());
        weighted_mean(&self.kept)
    }
}

impl Localizer for FuzzyRmcl {
    type Error = BaselineError;

    fn predict(&mut self, odometry: &Odometry, dt: f64) -> Result<(), BaselineError> {
        check_motion(odometry, dt)?;
        self.grid.predict(odometry, dt)?;
        let (f, l, turn) = (odometry.forward, odometry.left, odometry.turn);
        for (x, y, theta, _) in &mut self.kept {
            let (s, c) = theta.sin_cos();
            *x += c * f - s * l;
            *y += s * f + c * l;
            *theta = wrap_pi(*theta + turn);
        }
        Ok(())
    }

    fn observe(&mut self, table: &LandmarkTable, obs: &Observation) -> Result<(), BaselineError> {
        let Reading {
            lx,
            ly,
            range,
            bearing,
        } = check_observation(table, obs)?;
        self.grid.observe(table, obs)?;
        if range.is_some() || bearing.is_some() {
            self.frame.push((lx, ly, range, bearing));
        }
        Ok(())
    }

    fn estimate(&mut self) -> PoseEstimate {
        let mut e = self.grid.estimate();
        let position = if self.frame.is_empty() {
            let p = weighted_mean(&self.kept);
            self.carried += p.is_some() as usize;
            p
        } else {
            let p = self.refine(e.pose.theta);
            match p {
                Some(_) => self.sampled += 1,
                None => {
                    self.fallbacks += 1;
                    self.kept.clear();
                }
            }
            self.frame.clear();
            p
        };
        if let Some((x, y)) = position {
            e.pose = Pose2 {
                x,
                y,
                theta: e.pose.theta,
            };
        }
        e
    }

    fn fix_reliability(&self) -> f32 {
        self.grid.fix_reliability()
    }

    fn reobserve_interval(&self) -> f64 {
        self.grid.reobserve_interval()
    }
}

/// Weighted mean position of samples (x, y, heading, weight); `None` without weight.
fn weighted_mean(samples: &[(f64, f64, f64, f32)]) -> Option<(f64, f64)> {
    let (mut sx, mut sy, mut sw) = (0.0, 0.0, 0.0);
    for &(x, y, _, w) in samples {
        sx += w as f64 * x;
        sy += w as f64 * y;
        sw += w as f64;
    }
    (sw > 0.0).then(|| (sx / sw, sy / sw))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn config_rejects_unknown_keys_and_defaults_omitted_ones() {
        let ok = RmclConfig::from_ron("(max_cells: 7)").unwrap();
        assert_eq!(ok.max_cells, 7);
        assert_eq!(ok.top_cut, RmclConfig::default().top_cut);
        match RmclConfig::from_ron("(max_cells: 7,\n totally_bogus_field: 1)") {
            Err(BaselineError::Ron { problem, line, .. }) => {
                let message = problem.to_string();
                assert!(message.contains("totally_bogus_field"), "{message}");
                assert_eq!(line, 2);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn weighting_hand_case() {
        let cfg = RmclConfig {
            distance_core: 0.1,
            distance_slope: 0.4,
            sample_bearing_error: 0.2,
            min_membership: 0.3,
            ..RmclConfig::default()
        };
        // Landmark at (3, 4), sample at the origin facing +x: true range 5, bearing 0.9273.
        let b = 4f64.atan2(3.0);
        // Range 5.3 → d = 0.3: 0.2 past the core, over a slope of 0.4 → μ = 1 − 0.2/0.4 = 0.5.
        let w = cfg.sample_weight(0.0, 0.0, 0.0, &[(3.0, 4.0, Some(5.3), Some(b))]);
        assert!((w.unwrap() - 0.5).abs() < 1e-5, "{w:?}");
        // Range 5.05 → inside the core: μ = 1.
        let w = cfg.sample_weight(0.0, 0.0, 0.0, &[(3.0, 4.0, Some(5.05), Some(b))]);
        assert_eq!(w, Some(1.0));
        // Two readings: min(1, 0.5) = 0.5 (second landmark at (0, 2), range 2.3 → d = 0.3).
        let w = cfg.sample_weight(
            0.0,
            0.0,
            0.0,
            &[(3.0, 4.0, Some(5.0), None), (0.0, 2.0, Some(2.3), None)],
        );
        assert!((w.unwrap() - 0.5).abs() < 1e-5);
        // Range 5.45 → μ = 1 − 0.35/0.4 = 0.125 < 0.3: does not qualify.
        assert_eq!(
            cfg.sample_weight(0.0, 0.0, 0.0, &[(3.0, 4.0, Some(5.45), None)]),
            None
        );
        // Bearing off by 0.25 rad > 0.2: does not qualify.
        assert_eq!(
            cfg.sample_weight(0.0, 0.0, 0.0, &[(3.0, 4.0, Some(5.0), Some(b + 0.25))]),
            None
        );
    }
}
