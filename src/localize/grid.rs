//! The grid as a [`Localizer`], and [`run`]: the Fuzzy Position Grid driven over a stream of
//! [`MetricFrame`]s and scored against the stream's ground truth (definitions of ATE, fix,
//! kidnap and recovery in [`crate::localize`]).
//!
//! The grid's reliability is that of [`crate::grid::estimate`] (the extent of the top region);
//! its fix threshold is [`GridConfig::fix_reliability`] and its thinning
//! [`GridConfig::reobserve_interval`]. Prediction is lazy (the grid accumulates motion until the
//! next update), and [`Localizer::estimate`] keeps it so: it moves the estimate of the belief as
//! last updated by the odometry since, and leaves the belief to be predicted once, with all of
//! that motion, by the next reading.
//!
//! # Complexity
//!
//! O(frames · cells) time (one estimate per frame, updates per observation);
//! memory O(cells + frames).
//!
//! # Example
//!
//! ```
//! use lplace::core::Pose2;
//! use lplace::grid::{GridConfig, Landmark, LandmarkTable};
//! use lplace::localize::grid::run;
//! use lplace::localize::{LandmarkReading, MetricFrame, RunOptions};
//! let table = LandmarkTable::new(vec![
//!     Landmark { id: 1, x: 0.0, y: 0.0 },
//!     Landmark { id: 2, x: 3.0, y: 0.0 },
//!     Landmark { id: 3, x: 0.0, y: 2.0 },
//! ]).unwrap();
//! // The robot sits at (1, 1) facing +x and sees all three landmarks.
//! let seen = |id: u32, lx: f64, ly: f64| {
//!     let (dx, dy) = (lx - 1.0, ly - 1.0);
//!     LandmarkReading { subject: id, range: dx.hypot(dy), bearing: dy.atan2(dx) }
//! };
//! let frame = |t: f64| MetricFrame {
//!     t,
//!     dt: 1.0,
//!     odometry: Default::default(),
//!     observations: vec![seen(1, 0.0, 0.0), seen(2, 3.0, 0.0), seen(3, 0.0, 2.0)],
//!     truth: Some(Pose2 { x: 1.0, y: 1.0, theta: 0.0 }),
//! };
//! let report = run(&table, &GridConfig::default(), (0..3).map(|k| frame(k as f64)), &RunOptions::default()).unwrap();
//! assert!(report.ate.unwrap().rmse < 0.1);
//! ```

use super::{drive, Localizer, MetricFrame, PoseEstimate, RunOptions, RunReport};
use crate::core::angle::wrap_pi_f32;
use crate::core::{Odometry, Pose2};
use crate::grid::{FuzzyGrid, GridConfig, GridError, LandmarkTable, Observation};

/// The Fuzzy Position Grid as a [`Localizer`]: one grid, or [`GridConfig::lattices`] grids on
/// cell lattices moved by fractions of a cell, whose estimates it averages.
#[derive(Debug, Clone)]
pub struct GridLocalizer {
    /// The grid on the unmoved lattice first.
    members: Vec<Member>,
}

/// One grid and the odometry composed since it last applied its pending motion (robot frame at
/// the start): forward, left, turn.
#[derive(Debug, Clone)]
struct Member {
    grid: FuzzyGrid,
    moved: [f32; 3],
}

/// Where the `k` lattices' origins sit within a cell, in cells: a rank-1 lattice `(i/k,
/// frac(i·a/k))` with `a` coprime to `k` near `k/φ²` (Korobov's choice), so that the offsets
/// cover the cell evenly along both axes and along the diagonals.
///
/// # Complexity
/// O(k) after a search for `a` of at most `k` greatest common divisors.
fn lattice_offsets(k: u32) -> Vec<(f32, f32)> {
    fn gcd(a: u32, b: u32) -> u32 {
        if b == 0 {
            a
        } else {
            gcd(b, a % b)
        }
    }
    let k = k.max(1);
    let near = ((k as f64) * 0.381_966).round().max(1.0) as u32;
    let a = (near..k).find(|&a| gcd(a, k) == 1).unwrap_or(1);
    (0..k)
        .map(|i| (i as f32 / k as f32, ((i * a) % k) as f32 / k as f32))
        .collect()
}

impl GridLocalizer {
    /// Grids in total ignorance over `cfg.bounds`, or over the landmarks' extent plus
    /// `cfg.margin` when the configuration has no bounds. With `lattices` > 1, lattice `i` is
    /// moved towards negative x and y by its offset and reaches one cell further the other way,
    /// so every lattice covers the bounds.
    pub fn new(table: &LandmarkTable, cfg: &GridConfig) -> Result<Self, GridError> {
        cfg.validate()?;
        let bounds = match cfg.bounds {
            Some(b) => b,
            None => table.bounds(cfg.margin).ok_or(GridError::BadConfig {
                field: "bounds",
                reason: "no bounds and no landmarks",
            })?,
        };
        let member = |b: [f32; 4]| -> Result<Member, GridError> {
            Ok(Member {
                grid: FuzzyGrid::new(cfg.clone(), b)?,
                moved: [0.0; 3],
            })
        };
        let members = if cfg.lattices <= 1 {
            vec![member(bounds)?]
        } else {
            let c = cfg.cell_size;
            lattice_offsets(cfg.lattices)
                .into_iter()
                .map(|(ox, oy)| {
                    let (dx, dy) = (ox * c, oy * c);
                    member([
                        bounds[0] - dx,
                        bounds[1] - dy,
                        bounds[2] - dx + c,
                        bounds[3] - dy + c,
                    ])
                })
                .collect::<Result<_, _>>()?
        };
        Ok(GridLocalizer { members })
    }

    /// Starts from a known pose (tracking) instead of total ignorance
    /// ([`FuzzyGrid::start_at`]), every lattice alike.
    ///
    /// # Errors
    /// As [`FuzzyGrid::start_at`]: a pose outside the grid or not finite.
    pub fn start_at(&mut self, pose: Pose2) -> Result<(), GridError> {
        for m in &mut self.members {
            m.grid
                .start_at(pose.x as f32, pose.y as f32, pose.theta as f32)?;
            m.moved = [0.0; 3];
        }
        Ok(())
    }

    /// The grid on the unmoved lattice as last updated (its planes, for pictures): the odometry
    /// since the last reading is still pending in it (see [`Localizer::estimate`]).
    pub fn grid(&self) -> &FuzzyGrid {
        &self.first().grid
    }

    /// The grid on the unmoved lattice with the pending odometry applied (shifted and blurred),
    /// for a consumer that needs the belief now, such as the cooperative layer's object grid at
    /// a sighting. Every lattice applies it, as the next reading would have.
    pub fn grid_now(&mut self) -> &FuzzyGrid {
        for m in &mut self.members {
            m.grid.apply_pending();
            m.moved = [0.0; 3];
        }
        &self.first().grid
    }

    fn first(&self) -> &Member {
        // `new` makes at least one member and nothing removes one.
        &self.members[0]
    }
}

impl Member {
    /// The estimate of the belief as last updated, moved by the odometry since (along the
    /// estimated heading when it is reliable, as [`FuzzyGrid::apply_pending`] would shift the
    /// grid). The belief itself is left alone: applying the motion here, on every frame, split
    /// it into per-frame blurs of a few centimetres, each below what one dilation pass reaches
    /// on a 0.1 m grid and dropped.
    fn estimate(&self) -> PoseEstimate {
        let e = self.grid.estimate();
        let [f, l, t] = self.moved;
        // The share the next prediction will shift along the heading.
        let w = self.grid.directed_weight(&e);
        let (dx, dy, dt) = if w > 0.0 {
            let (s, c) = e.theta.sin_cos();
            (w * (c * f - s * l), w * (s * f + c * l), t)
        } else {
            (0.0, 0.0, t)
        };
        PoseEstimate {
            pose: Pose2 {
                x: (e.x + dx) as f64,
                y: (e.y + dy) as f64,
                theta: wrap_pi_f32(e.theta + dt) as f64,
            },
            reliability: e.reliability,
            heading_reliability: e.heading_reliability,
        }
    }
}

/// The mean of the lattices' estimates: position and reliabilities arithmetic, heading circular.
fn average(estimates: &[PoseEstimate]) -> PoseEstimate {
    let n = estimates.len().max(1) as f64;
    let sum = |f: &dyn Fn(&PoseEstimate) -> f64| estimates.iter().map(f).sum::<f64>();
    PoseEstimate {
        pose: Pose2 {
            x: sum(&|e| e.pose.x) / n,
            y: sum(&|e| e.pose.y) / n,
            theta: sum(&|e| e.pose.theta.sin()).atan2(sum(&|e| e.pose.theta.cos())),
        },
        reliability: (sum(&|e| e.reliability as f64) / n) as f32,
        heading_reliability: (sum(&|e| e.heading_reliability as f64) / n) as f32,
    }
}

impl Localizer for GridLocalizer {
    type Error = GridError;

    fn predict(&mut self, odometry: &Odometry, dt: f64) -> Result<(), GridError> {
        for m in &mut self.members {
            m.grid.predict(odometry, dt)?;
            // In the grid's single precision and calibration, as the grid composes it.
            let [forward, left, turn] = m.grid.scaled(odometry);
            let [f, l, t] = &mut m.moved;
            let (s, c) = t.sin_cos();
            *f += c * forward - s * left;
            *l += s * forward + c * left;
            *t += turn;
        }
        Ok(())
    }

    fn observe(&mut self, table: &LandmarkTable, obs: &Observation) -> Result<(), GridError> {
        for m in &mut self.members {
            m.grid.observe(table, obs)?;
            // An accepted reading applied the pending motion (a reading with neither value
            // applies nothing).
            if obs.range.is_some() || obs.bearing.is_some() {
                m.moved = [0.0; 3];
            }
        }
        Ok(())
    }

    /// One lattice's estimate (see `Member::estimate`), or the mean of the lattices'.
    fn estimate(&mut self) -> PoseEstimate {
        match self.members.as_slice() {
            [one] => one.estimate(),
            all => average(&all.iter().map(Member::estimate).collect::<Vec<_>>()),
        }
    }

    fn fix_reliability(&self) -> f32 {
        self.first().grid.config().fix_reliability
    }

    fn reobserve_interval(&self) -> f64 {
        self.first().grid.config().reobserve_interval as f64
    }
}

/// Runs the grid over `frames` (see the module docs).
pub fn run<I>(
    table: &LandmarkTable,
    cfg: &GridConfig,
    frames: I,
    opts: &RunOptions,
) -> Result<RunReport, GridError>
where
    I: IntoIterator<Item = MetricFrame>,
{
    let mut loc = GridLocalizer::new(table, cfg)?;
    Ok(drive(&mut loc, table, frames, opts))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Landmark, MAX_LATTICES};

    fn table() -> LandmarkTable {
        LandmarkTable::new(vec![
            Landmark {
                id: 1,
                x: 0.0,
                y: 0.0,
            },
            Landmark {
                id: 2,
                x: 3.0,
                y: 0.0,
            },
            Landmark {
                id: 3,
                x: 0.0,
                y: 2.0,
            },
        ])
        .unwrap()
    }

    /// Readings of the three landmarks from (x, y) facing +x.
    fn seen(x: f32, y: f32) -> Vec<Observation> {
        [(1, 0.0f32, 0.0f32), (2, 3.0, 0.0), (3, 0.0, 2.0)]
            .iter()
            .map(|&(id, lx, ly)| Observation {
                landmark: id,
                range: Some((lx - x).hypot(ly - y)),
                bearing: Some((ly - y).atan2(lx - x)),
            })
            .collect()
    }

    fn localizer() -> GridLocalizer {
        let cfg = GridConfig {
            bounds: Some([-1.0, -1.0, 4.0, 3.0]),
            ..GridConfig::default()
        };
        let t = table();
        let mut g = GridLocalizer::new(&t, &cfg).unwrap();
        for _ in 0..3 {
            for o in seen(1.0, 1.0) {
                g.observe(&t, &o).unwrap();
            }
        }
        g
    }

    #[test]
    fn estimates_do_not_change_the_belief() {
        // Ten small motions with an estimate after each must leave the grid exactly where the
        // same motions without estimates leave it, also after the next reading.
        let t = table();
        let step = Odometry {
            forward: 0.02,
            left: 0.0,
            turn: 0.01,
        };
        let dt = 0.25;
        let (mut a, mut b) = (localizer(), localizer());
        for _ in 0..10 {
            a.predict(&step, dt).unwrap();
            a.estimate();
            b.predict(&step, dt).unwrap();
        }
        assert_eq!(a.grid().possibilities(), b.grid().possibilities());
        for o in seen(1.2, 1.0) {
            a.observe(&t, &o).unwrap();
            b.observe(&t, &o).unwrap();
        }
        assert_eq!(a.grid().possibilities(), b.grid().possibilities());
        assert_eq!(a.estimate(), b.estimate());
    }

    #[test]
    fn grid_now_applies_the_pending_motion() {
        let mut g = localizer();
        let step = Odometry {
            forward: 0.1,
            left: 0.0,
            turn: 0.0,
        };
        let dt = 0.25;
        for _ in 0..3 {
            g.predict(&step, dt).unwrap();
        }
        let moved = g.estimate();
        let as_last_updated = g.grid().estimate();
        let now = g.grid_now().estimate();
        // The plane is shifted by whole cells (the rest is carried over, under half a cell per
        // axis), so its own estimate now agrees with the moved one; before, it lagged 0.3 m.
        let lag = |x: f32, y: f32| (x as f64 - moved.pose.x).hypot(y as f64 - moved.pose.y);
        assert!(lag(as_last_updated.x, as_last_updated.y) > 0.25);
        assert!(lag(now.x, now.y) <= 0.05 * std::f64::consts::SQRT_2 + 1e-4);
        // Nothing is pending any more: the estimate is the plane's.
        let e = g.estimate();
        assert!((e.pose.x - now.x as f64).abs() < 1e-6 && (e.pose.y - now.y as f64).abs() < 1e-6);
    }

    #[test]
    fn estimate_moves_with_the_odometry_since_the_last_reading() {
        let mut g = localizer();
        let before = g.estimate();
        assert!(before.heading_reliability >= 0.8, "{before:?}");
        let step = Odometry {
            forward: 0.03,
            left: 0.01,
            turn: 0.0,
        };
        let dt = 0.25;
        for _ in 0..4 {
            g.predict(&step, dt).unwrap();
        }
        let after = g.estimate();
        // Robot frame (0.12, 0.04) turned by the estimated heading.
        let (s, c) = before.pose.theta.sin_cos();
        let (dx, dy) = (c * 0.12 - s * 0.04, s * 0.12 + c * 0.04);
        assert!(
            (after.pose.x - before.pose.x - dx).abs() < 1e-5,
            "{before:?} {after:?}"
        );
        assert!(
            (after.pose.y - before.pose.y - dy).abs() < 1e-5,
            "{before:?} {after:?}"
        );
        // A rejected reading applies nothing, so the estimate still carries the motion.
        let bad = Observation {
            landmark: 9,
            range: Some(1.0),
            bearing: None,
        };
        assert!(g.observe(&table(), &bad).is_err());
        assert_eq!(g.estimate(), after);
    }

    #[test]
    fn lattice_offsets_place_every_lattice_once_along_each_axis() {
        assert_eq!(lattice_offsets(1), vec![(0.0, 0.0)]);
        // Worked by hand: k = 4 gives a = 2 by k/φ², not coprime with 4, so a = 3.
        assert_eq!(
            lattice_offsets(4),
            vec![(0.0, 0.0), (0.25, 0.75), (0.5, 0.5), (0.75, 0.25)]
        );
        for k in 2..=16u32 {
            let offs = lattice_offsets(k);
            assert_eq!(offs.len(), k as usize);
            for axis in [0, 1] {
                let mut steps: Vec<u32> = offs
                    .iter()
                    .map(|o| ((if axis == 0 { o.0 } else { o.1 }) * k as f32).round() as u32)
                    .collect();
                steps.sort_unstable();
                assert_eq!(steps, (0..k).collect::<Vec<_>>(), "k = {k}, axis {axis}");
            }
        }
    }

    #[test]
    fn several_lattices_average_the_grids_on_moved_bounds() {
        // Four lattices against four single grids built by hand on the moved bounds, fed the
        // same readings and motion: the estimate is their mean.
        let t = table();
        let cfg = GridConfig {
            bounds: Some([-1.0, -1.0, 4.0, 3.0]),
            lattices: 4,
            ..GridConfig::default()
        };
        let c = cfg.cell_size;
        let by_hand: Vec<GridLocalizer> = [(0.0, 0.0), (0.25, 0.75), (0.5, 0.5), (0.75, 0.25)]
            .iter()
            .map(|&(ox, oy)| {
                let b = [
                    -1.0 - ox * c,
                    -1.0 - oy * c,
                    4.0 - ox * c + c,
                    3.0 - oy * c + c,
                ];
                let one = GridConfig {
                    bounds: Some(b),
                    lattices: 1,
                    ..cfg.clone()
                };
                GridLocalizer::new(&t, &one).unwrap()
            })
            .collect();
        let mut all = GridLocalizer::new(&t, &cfg).unwrap();
        let mut singles = by_hand;
        let step = Odometry {
            forward: 0.23,
            left: 0.0,
            turn: 0.05,
        };
        for g in std::iter::once(&mut all).chain(singles.iter_mut()) {
            for _ in 0..3 {
                for o in seen(1.0, 1.0) {
                    g.observe(&t, &o).unwrap();
                }
            }
            g.predict(&step, 0.5).unwrap();
        }
        let got = all.estimate();
        let each: Vec<PoseEstimate> = singles.iter_mut().map(|g| g.estimate()).collect();
        let mean = |f: fn(&PoseEstimate) -> f64| each.iter().map(f).sum::<f64>() / 4.0;
        assert!((got.pose.x - mean(|e| e.pose.x)).abs() < 1e-12);
        assert!((got.pose.y - mean(|e| e.pose.y)).abs() < 1e-12);
        let (s, co) = (mean(|e| e.pose.theta.sin()), mean(|e| e.pose.theta.cos()));
        assert!((got.pose.theta - s.atan2(co)).abs() < 1e-12);
        assert!((got.reliability as f64 - mean(|e| e.reliability as f64)).abs() < 1e-6);
        // The lattices differ (else the test would not tell averaging from copying).
        assert!(each.iter().any(|e| e.pose.x != each[0].pose.x));
        // And the mean is where the robot is, moved by the odometry.
        assert!((got.pose.x - 1.23).abs() < 0.15 && (got.pose.y - 1.0).abs() < 0.15);
    }

    #[test]
    fn lattice_counts_out_of_range_are_rejected() {
        for k in [0, MAX_LATTICES + 1] {
            let cfg = GridConfig {
                lattices: k,
                ..GridConfig::default()
            };
            assert!(GridLocalizer::new(&table(), &cfg).is_err(), "{k}");
        }
    }
}
