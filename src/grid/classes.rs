//! Moving each cell along its own heading ([`CellMotion::HeadingClasses`]), after the plane's
//! shift along the estimate's heading ([`crate::grid::predict`]).
//!
//! Why: the plane's shift moves every cell as if its heading were the estimate's, so a cell
//! whose own heading set disagrees never loses possibility for it, and a bearing read through
//! its wrong set keeps cutting the cells around the truth down (`docs/compare.md`, "The
//! per-cell heading sets"). A particle with a wrong heading drives away from where the ranges
//! put it; this gives the grid's cells the same coupling of heading and motion.
//!
//! How: a cell above the floor whose set is clear (bias ≤ `max_bias`, support `Δ + 2α` ≤
//! `max_width`) falls in class `k = round(wrap(θ − θ̂) / (2π/bins)) mod bins`, θ̂ the estimate's
//! heading; the classes are measured from θ̂ so that class 0 is the estimate's own and moves
//! exactly as the plane did. Class `k`'s heading is `θ̂ + 2πk/bins`, its displacement the
//! pending odometry turned by it; what the plane's shift has not already moved it (`w` times
//! the odometry turned by θ̂, [`FuzzyGrid::directed_weight`]) is added to the class's carried
//! remainder and moved in whole cells, the rest carried, as the plane's shift carries its own.
//! Every cell of a class that moves leaves its cell empty (possibility 0, heading unknown) and
//! lands with its heading set where it goes; where it lands on a cell already holding more or
//! as much possibility, that cell stays as it is (the maximum, as the dilation combines). Cells
//! without a clear heading move with the plane alone and are blurred as before.
//!
//! When every cell above the floor agrees with the estimate (class 0) and the shift is directed
//! (`w = 1`), nothing more moves and the prediction is the plane's to the bit.
//!
//! # Complexity
//!
//! `move_classes`: O(bins) for the classes' shifts, one pass over the possibility plane (the
//! heading planes read only for cells above the floor) and O(m) for the m cells that move.
//! No allocation after the first motion (the movers' buffer keeps its capacity).

use super::config::MAX_HEADING_BINS;
use super::{CellMotion, FuzzyGrid, GridConfig};
use crate::core::angle::wrap_pi_f32;
use std::f32::consts::PI;

/// How many heading classes `cfg` asks for (0 under [`CellMotion::Plane`]).
pub(crate) fn bins(cfg: &GridConfig) -> usize {
    match cfg.cell_motion {
        CellMotion::Plane => 0,
        CellMotion::HeadingClasses { bins, .. } => bins as usize,
    }
}

/// A cell on its way: where it lands (`None` outside the grid) and what it carries.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Mover {
    target: Option<usize>,
    h: f32,
    theta: f32,
    delta: f32,
    alpha: f32,
    bias: f32,
}

impl FuzzyGrid {
    /// Moves the cells with a clear heading along it (module docs). `theta` is the estimate's
    /// heading θ̂, `w` the share of the displacement the plane was shifted by along it, `(px,
    /// py)` the pending displacement in the frame of θ̂. Call after the plane's shift and
    /// before the heading sets are turned by the odometry.
    pub(crate) fn move_classes(&mut self, theta: f32, w: f32, px: f32, py: f32) {
        let CellMotion::HeadingClasses {
            bins,
            max_bias,
            max_width,
        } = self.cfg.cell_motion
        else {
            return;
        };
        let Some(offsets) = self.class_offsets(theta, w, px, py, bins as usize) else {
            return;
        };
        let step = 2.0 * PI / bins as f32;
        let (nx, ny) = (self.nx as isize, self.ny as isize);
        let floor = self.cfg.floor;
        let mut movers = std::mem::take(&mut self.work.movers);
        movers.clear();
        for i in 0..self.h.len() {
            let h = self.h[i];
            if h <= floor
                || self.bias[i] > max_bias
                || self.delta[i] + 2.0 * self.alpha[i] > max_width
            {
                continue;
            }
            let k = (wrap_pi_f32(self.theta[i] - theta) / step).round() as i64;
            let (ox, oy) = offsets[k.rem_euclid(bins as i64) as usize];
            if ox == 0 && oy == 0 {
                continue;
            }
            let (c, r) = ((i % self.nx) as isize + ox, (i / self.nx) as isize + oy);
            let inside = c >= 0 && c < nx && r >= 0 && r < ny;
            movers.push(Mover {
                target: inside.then_some((r * nx + c) as usize),
                h,
                theta: self.theta[i],
                delta: self.delta[i],
                alpha: self.alpha[i],
                bias: self.bias[i],
            });
            self.h[i] = 0.0;
            self.theta[i] = 0.0;
            self.delta[i] = 2.0 * PI;
            self.alpha[i] = 0.0;
            self.bias[i] = 1.0;
        }
        for m in &movers {
            if let Some(t) = m.target {
                if m.h > self.h[t] {
                    self.h[t] = m.h;
                    self.theta[t] = m.theta;
                    self.delta[t] = m.delta;
                    self.alpha[t] = m.alpha;
                    self.bias[t] = m.bias;
                }
            }
        }
        self.work.movers = movers;
    }

    /// Each class's whole-cell move beyond the plane's shift, the classes' remainders carried;
    /// `None` when no class moves.
    fn class_offsets(
        &mut self,
        theta: f32,
        w: f32,
        px: f32,
        py: f32,
        bins: usize,
    ) -> Option<[(isize, isize); MAX_HEADING_BINS as usize]> {
        let (s0, c0) = theta.sin_cos();
        let plane = [w * (c0 * px - s0 * py), w * (s0 * px + c0 * py)];
        let step = 2.0 * PI / bins as f32;
        let mut offsets = [(0isize, 0isize); MAX_HEADING_BINS as usize];
        let mut any = false;
        for (k, off) in offsets.iter_mut().enumerate().take(bins) {
            // Class 0 is turned by exactly θ̂, so under w = 1 it owes nothing, to the bit.
            let (s, c) = if k == 0 {
                (s0, c0)
            } else {
                (theta + k as f32 * step).sin_cos()
            };
            let own = [c * px - s * py, s * px + c * py];
            let [rx, ry] = self.class_rem[k];
            let (ox, rem_x) = self.whole_cells(rx + (own[0] - plane[0]));
            let (oy, rem_y) = self.whole_cells(ry + (own[1] - plane[1]));
            self.class_rem[k] = [rem_x, rem_y];
            *off = (ox as isize, oy as isize);
            any |= ox != 0.0 || oy != 0.0;
        }
        any.then_some(offsets)
    }
}

#[cfg(test)]
mod tests {
    use crate::core::Odometry;
    use crate::grid::{CellMotion, FuzzyGrid, GridConfig, Trapezoid};
    use std::f32::consts::PI;

    fn classes(bins: u32) -> CellMotion {
        CellMotion::HeadingClasses {
            bins,
            max_bias: 0.5,
            max_width: 1.0,
        }
    }

    /// The default configuration with `motion` and no blur at all: only the shifts move
    /// possibility.
    fn unblurred(motion: CellMotion) -> GridConfig {
        GridConfig {
            cell_motion: motion,
            core_per_metre: 0.0,
            flank_per_metre: 0.0,
            flank_per_second: 0.0,
            undirected_per_metre: 0.0,
            ..GridConfig::default()
        }
    }

    /// A 4 m × 4 m grid, empty, with no blur at all.
    fn still(motion: CellMotion) -> FuzzyGrid {
        let mut g = FuzzyGrid::new(unblurred(motion), [0.0, 0.0, 4.0, 4.0]).unwrap();
        g.possibilities_mut().fill(0.0);
        g
    }

    /// Puts possibility `h` at `(col, row)` with the heading set `⟨theta, core, flank, bias⟩`.
    fn put(g: &mut FuzzyGrid, (c, r): (usize, usize), h: f32, set: [f32; 4]) {
        let nx = g.nx();
        g.possibilities_mut()[r * nx + c] = h;
        g.set_heading_set(c, r, Trapezoid::new(set[0], set[1], set[2], 1.0, set[3]));
    }

    fn forward(g: &mut FuzzyGrid, metres: f64) {
        let o = Odometry {
            forward: metres,
            left: 0.0,
            turn: 0.0,
        };
        g.predict(&o, 0.5).unwrap();
        g.apply_pending();
    }

    /// The cells holding possibility, as `(col, row, h)`.
    fn occupied(g: &FuzzyGrid) -> Vec<(usize, usize, f32)> {
        let nx = g.nx();
        (0..g.possibilities().len())
            .filter(|&i| g.possibilities()[i] > 0.0)
            .map(|i| (i % nx, i / nx, g.possibilities()[i]))
            .collect()
    }

    #[test]
    fn cells_with_opposite_headings_move_apart() {
        // A: the peak, heading 0 exactly (so θ̂ = 0, R̄ = 1, the shift directed). B: h 0.5,
        // 1 m to A's left, heading π, clear (support 0.1 + 2 · 0.05 = 0.2, bias 0.2). 0.3 m
        // forward. Plane: both 3 cells along +x. Classes (16, step π/8): B is in class
        // round(π / (π/8)) = 8, heading π, its own move −3 cells, i.e. −6 beyond the plane's.
        let run = |motion| {
            let mut g = still(motion);
            put(&mut g, (25, 20), 1.0, [0.0, 0.0, 0.0, 0.0]);
            put(&mut g, (15, 20), 0.5, [PI, 0.1, 0.05, 0.2]);
            forward(&mut g, 0.3);
            g
        };
        let plane = run(CellMotion::Plane);
        assert_eq!(occupied(&plane), vec![(18, 20, 0.5), (28, 20, 1.0)]);
        let own = run(classes(16));
        assert_eq!(occupied(&own), vec![(12, 20, 0.5), (28, 20, 1.0)]);
        // B carries its set; its old cell and the one the plane would have put it in know none.
        let t = own.heading_set(12, 20).unwrap();
        assert_eq!((t.center, t.shape.bias), (PI, 0.2));
        assert!((t.shape.core - 0.105).abs() < 1e-6, "{t:?}"); // + 0.01 rad/s · 0.5 s
        for c in [15, 18] {
            assert_eq!(own.heading_set(c, 20).unwrap().shape.core, 2.0 * PI);
        }
    }

    #[test]
    fn an_unclear_cell_moves_with_the_plane() {
        // As above, but B's bias 0.6 > max_bias 0.5: it is moved as the plane is.
        let mut g = still(classes(16));
        put(&mut g, (25, 20), 1.0, [0.0, 0.0, 0.0, 0.0]);
        put(&mut g, (15, 20), 0.5, [PI, 0.1, 0.05, 0.6]);
        forward(&mut g, 0.3);
        assert_eq!(occupied(&g), vec![(18, 20, 0.5), (28, 20, 1.0)]);
    }

    #[test]
    fn a_class_carries_its_sub_cell_remainder() {
        // Four classes (step π/2); B heads π/2, class 1. Steps of 4 cm along θ̂ = 0. The plane
        // carries 0.04 (0 cells), then 0.08 → 1 cell. B's own move is (0, 0.04) per step, so
        // beyond the plane's it owes (−0.04, +0.04): 0 cells after one step, then (−1, +1)
        // after two, the −1 cancelling the plane's +1: B goes straight up by one cell.
        let mut g = still(classes(4));
        put(&mut g, (10, 10), 1.0, [0.0, 0.0, 0.0, 0.0]);
        put(&mut g, (30, 10), 0.5, [0.5 * PI, 0.1, 0.05, 0.0]);
        forward(&mut g, 0.04);
        assert_eq!(occupied(&g), vec![(10, 10, 1.0), (30, 10, 0.5)]);
        forward(&mut g, 0.04);
        assert_eq!(occupied(&g), vec![(11, 10, 1.0), (30, 11, 0.5)]);
    }

    #[test]
    fn where_cells_land_together_the_larger_stays() {
        // C (20, 20) heads π/2 (class 1 of 4), D (19, 21) knows no heading. 0.1 m along θ̂ = 0:
        // the plane moves both one cell along +x, C one more up and one back: both end at
        // (20, 21). The larger possibility keeps the cell, with its own heading set.
        for (hc, hd) in [(0.6, 0.4), (0.3, 0.7)] {
            let mut g = still(classes(4));
            put(&mut g, (5, 5), 1.0, [0.0, 0.0, 0.0, 0.0]);
            put(&mut g, (20, 20), hc, [0.5 * PI, 0.1, 0.0, 0.0]);
            put(&mut g, (19, 21), hd, [0.0, 2.0 * PI, 0.0, 1.0]);
            forward(&mut g, 0.1);
            assert_eq!(occupied(&g), vec![(6, 5, 1.0), (20, 21, hc.max(hd))]);
            let t = g.heading_set(20, 21).unwrap();
            let want = if hc > hd { 0.5 * PI } else { 0.0 };
            assert_eq!(t.center, want, "{hc} {hd}");
        }
    }

    /// A random plane under a clear peak heading `heading`: every cell above the floor either
    /// shares the peak's heading or knows none, kept under the top cut so that the estimate's
    /// heading is the peak's and reliable.
    fn agreeing(motion: CellMotion, heading: f32, seed: u32) -> FuzzyGrid {
        let cfg = GridConfig {
            cell_motion: motion,
            ..GridConfig::default()
        };
        let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, 3.0, 3.0]).unwrap();
        let mut rng = crate::grid::test_rng(seed);
        for r in 0..g.ny() {
            for c in 0..g.nx() {
                let h = 0.85 * rng();
                let set = if rng() < 0.5 {
                    [heading, 0.05, 0.05, 0.0]
                } else {
                    [0.0, 2.0 * PI, 0.0, 1.0]
                };
                put(&mut g, (c, r), h, set);
            }
        }
        put(&mut g, (15, 15), 1.0, [heading, 0.05, 0.05, 0.0]);
        g
    }

    #[test]
    fn classes_equal_the_plane_shift_when_every_cell_shares_the_heading() {
        // The existing path (`Plane`) is the reference: same plane and sets, bit for bit, over
        // steps that shift, turn and blur (the default element).
        for seed in [1, 2, 3] {
            let mut a = agreeing(CellMotion::Plane, 0.7, seed);
            let mut b = agreeing(classes(16), 0.7, seed);
            for step in 0..6 {
                let o = Odometry {
                    forward: 0.07 + 0.05 * step as f64,
                    left: 0.01,
                    turn: 0.1,
                };
                a.predict(&o, 0.3).unwrap();
                b.predict(&o, 0.3).unwrap();
                a.apply_pending();
                b.apply_pending();
                assert!(a.estimate().heading_reliability >= 0.8);
                assert_eq!(a.possibilities(), b.possibilities(), "{seed} {step}");
                for (c, r) in [(15, 15), (3, 4), (20, 9), (29, 29)] {
                    assert_eq!(a.heading_set(c, r), b.heading_set(c, r), "{seed} {step}");
                }
            }
        }
    }

    #[test]
    fn one_step_matches_a_brute_force_scatter() {
        // Random possibilities and headings, some unclear; the heading estimate unreliable, so
        // the plane does not move and every clear cell moves by its class's own displacement.
        // Reference: each cell's target worked out alone, the output the maximum over all the
        // cells landing there (vacated cells 0), by a double loop over the cells.
        let motion = classes(8);
        let mut g = FuzzyGrid::new(unblurred(motion), [0.0, 0.0, 2.0, 1.5]).unwrap();
        let mut rng = crate::grid::test_rng(7);
        for r in 0..g.ny() {
            for c in 0..g.nx() {
                let h = if rng() < 0.3 { 0.0 } else { rng() };
                let set = [2.0 * PI * rng() - PI, 0.6 * rng(), 0.3 * rng(), 0.7 * rng()];
                put(&mut g, (c, r), h, set);
            }
        }
        let est = g.estimate();
        assert!(est.heading_reliability < 0.8, "{est:?}");
        let (nx, ny) = (g.nx() as isize, g.ny() as isize);
        let before: Vec<(f32, Trapezoid)> = (0..g.possibilities().len())
            .map(|i| {
                let (c, r) = (i % g.nx(), i / g.nx());
                (g.possibilities()[i], g.heading_set(c, r).unwrap())
            })
            .collect();
        let d = 0.23f32;
        let target = |i: usize, t: &Trapezoid, h: f32| -> Option<usize> {
            let clear =
                h > 1e-8 && t.shape.bias <= 0.5 && t.shape.core + 2.0 * t.shape.slope <= 1.0;
            let (mut c, mut r) = ((i as isize) % nx, (i as isize) / nx);
            if clear {
                // Nearest of the 8 class headings est.θ + kπ/4 to the cell's own.
                let k = (0..8)
                    .min_by(|&a, &b| {
                        let da = crate::core::angle::wrap_pi_f32(
                            t.center - est.theta - a as f32 * PI / 4.0,
                        );
                        let db = crate::core::angle::wrap_pi_f32(
                            t.center - est.theta - b as f32 * PI / 4.0,
                        );
                        da.abs().total_cmp(&db.abs())
                    })
                    .unwrap();
                let a = est.theta + k as f32 * PI / 4.0;
                c += (d * a.cos() / 0.1).round() as isize;
                r += (d * a.sin() / 0.1).round() as isize;
            }
            (c >= 0 && c < nx && r >= 0 && r < ny).then(|| (r * nx + c) as usize)
        };
        let want: Vec<f32> = (0..before.len())
            .map(|t| {
                (0..before.len())
                    .filter(|&i| target(i, &before[i].1, before[i].0) == Some(t))
                    .map(|i| before[i].0)
                    .fold(0.0, f32::max)
            })
            .collect();
        g.predict(
            &Odometry {
                forward: d as f64,
                left: 0.0,
                turn: 0.0,
            },
            0.5,
        )
        .unwrap();
        g.apply_pending();
        assert_eq!(g.possibilities(), &want[..]);
    }

    #[test]
    fn bad_class_settings_are_rejected() {
        for motion in [
            classes(1),
            classes(65),
            CellMotion::HeadingClasses {
                bins: 8,
                max_bias: 1.5,
                max_width: 1.0,
            },
            CellMotion::HeadingClasses {
                bins: 8,
                max_bias: 0.5,
                max_width: f32::NAN,
            },
        ] {
            let cfg = GridConfig {
                cell_motion: motion,
                ..GridConfig::default()
            };
            assert!(cfg.validate().is_err(), "{motion:?}");
        }
        let ron = "(cell_motion: HeadingClasses(bins: 16, max_bias: 0.5, max_width: 1.0))";
        assert!(GridConfig::from_ron(ron).is_ok());
        let unknown = ron.replace("1.0)", "1.0, bins_x: 2)");
        assert!(GridConfig::from_ron(&unknown).is_err(), "{unknown}");
    }
}
