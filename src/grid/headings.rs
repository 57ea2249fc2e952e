//! The belief's heading set, and how cells take it: after a blur, in the share the blur
//! brought ([`RaisedHeadings::Inherit`](super::RaisedHeadings), `crate::grid::blur`), or all of
//! it once the heading is known ([`HeadingSets::Shared`](super::HeadingSets)).
//!
//! The belief's set is the estimate's heading turned by the odometry since, with core
//! `bearing.core_abs` plus the prediction's widening, flank `bearing.slope_abs` and bias
//! `1 − R̄`: as wide as one bearing reading makes a heading, and as doubtful as the estimate.
//!
//! Why share it: a cell's own set, narrowed by every reading there, is often far more wrong
//! than the estimate's heading, a mean over the top region (on MRCLAM robot 1, off by more
//! than 0.5 rad on 13 % of the frames at the truth's cell, against 1 % for the estimate), and a
//! bearing read through a wrong narrow set cuts the cell down whoever is right. The prediction
//! shifts the whole plane along the estimate's heading, so such a cell is moved as if it
//! agreed. On robot 1 (`docs/compare.md`) every cell given the true heading removed a quarter
//! of the ATE, while the motion alone driven by the true heading removed none. Sharing the estimate's heading makes it one hypothesis,
//! though: on two of five robots a heading wrong at the first fix became every cell's for
//! minutes, so no default uses it.
//!
//! # Complexity
//!
//! `share_headings`: O(cells), one pass per plane.

use super::{Estimate, FuzzyGrid};
use crate::core::angle::wrap_pi_f32;
use std::f32::consts::PI;

/// A heading set of height 1: centre, core, flank, bias.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HeadingSet {
    pub(crate) theta: f32,
    pub(crate) delta: f32,
    pub(crate) alpha: f32,
    pub(crate) bias: f32,
}

impl FuzzyGrid {
    /// The belief's heading set (module docs): `est` is the estimate before the motion,
    /// `turn` the odometry rotation since, `widen` the prediction's widening of the cores.
    pub(crate) fn belief_set(&self, est: &Estimate, turn: f32, widen: f32) -> HeadingSet {
        HeadingSet {
            theta: wrap_pi_f32(est.theta + turn),
            delta: self.cfg.bearing.core_abs + widen,
            alpha: self.cfg.bearing.slope_abs,
            bias: (1.0 - est.heading_reliability).clamp(0.0, 1.0),
        }
    }

    /// Under [`HeadingSets::Shared`](super::HeadingSets): every cell above the floor takes the
    /// belief's set (arguments as [`FuzzyGrid::belief_set`]), its bias raised to `floor / h` as
    /// the floor's rule has it; a cell at or under the floor (or empty) knows no heading (bias
    /// 1, core 2π), as after any update — which also keeps the bearing update's fast path for
    /// such cells (`crate::grid::observe`).
    pub(crate) fn share_headings(&mut self, est: &Estimate, turn: f32, widen: f32) {
        let set = self.belief_set(est, turn, widen);
        let floor = self.cfg.floor;
        let core = set.delta.min(2.0 * PI);
        for (i, &h) in self.h.iter().enumerate() {
            if h > floor {
                self.theta[i] = set.theta;
                self.delta[i] = core;
                self.alpha[i] = set.alpha;
                self.bias[i] = set.bias.max(floor / h).min(1.0);
            } else {
                self.delta[i] = 2.0 * PI;
                self.bias[i] = 1.0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::core::Odometry;
    use crate::grid::{FuzzyGrid, GridConfig, HeadingSets, Trapezoid};

    /// A peak at (2.05, 2.05) heading 1 rad, and a second cell of possibility 0.5 whose set
    /// says −2 rad (core 0.1, flank 0.05, bias 0.2); then 0.3 m forward while turning 0.2 rad
    /// in 1 s, applied. Blur `Drop` with the default widths: 0.03 m of core and under 0.08 m of
    /// flank, below a cell, so the plane is only shifted.
    fn moved(sets: HeadingSets) -> FuzzyGrid {
        let cfg = GridConfig {
            heading_sets: sets,
            ..GridConfig::default()
        };
        let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, 4.0, 4.0]).unwrap();
        g.start_at(2.05, 2.05, 1.0).unwrap();
        g.possibilities_mut()[10 * 40 + 30] = 0.5;
        g.set_heading_set(30, 10, Trapezoid::new(-2.0, 0.1, 0.05, 1.0, 0.2));
        drive(g)
    }

    /// 0.3 m forward while turning 0.2 rad in 1 s, applied.
    fn drive(mut g: FuzzyGrid) -> FuzzyGrid {
        let o = Odometry {
            forward: 0.3,
            left: 0.0,
            turn: 0.2,
        };
        g.predict(&o, 1.0).unwrap();
        g.apply_pending();
        g
    }

    /// The heading set of the only cell whose possibility is `h`.
    fn set_at(g: &FuzzyGrid, h: f32) -> Trapezoid {
        let cells: Vec<usize> = (0..g.possibilities().len())
            .filter(|&i| g.possibilities()[i] == h)
            .collect();
        assert_eq!(cells.len(), 1, "{h}");
        g.heading_set(cells[0] % g.nx(), cells[0] / g.nx()).unwrap()
    }

    #[test]
    fn a_known_heading_is_shared_by_every_cell() {
        // The top region is the peak alone (0.5 < 0.9 of the maximum), whose bias is 0: R̄ = 1,
        // the shift is directed. Belief's set, by hand: centre 1 + 0.2, core 0.06 (bearing
        // model) + 0.1 · 0.2 + 0.01 · 1 (widening), flank 0.1, bias 1 − R̄ = 0.
        let shared = moved(HeadingSets::Shared);
        for h in [1.0, 0.5] {
            let t = set_at(&shared, h);
            assert!((t.center - 1.2).abs() < 1e-5, "{h}: {t:?}");
            assert!((t.shape.core - 0.09).abs() < 1e-5, "{h}: {t:?}");
            assert!((t.shape.slope - 0.1).abs() < 1e-6, "{h}: {t:?}");
            assert!(t.shape.bias.abs() < 1e-6, "{h}: {t:?}");
        }
        // An empty cell knows no heading: the full circle, bias 1.
        let empty = (0..shared.possibilities().len())
            .find(|&i| shared.possibilities()[i] == 0.0)
            .unwrap();
        let t = shared
            .heading_set(empty % shared.nx(), empty / shared.nx())
            .unwrap();
        assert_eq!(
            (t.shape.core, t.shape.bias),
            (2.0 * std::f32::consts::PI, 1.0)
        );
        // Per cell, the second cell keeps its own set, turned by 0.2 and widened by 0.03.
        let own = set_at(&moved(HeadingSets::PerCell), 0.5);
        assert!((own.center + 1.8).abs() < 1e-5, "{own:?}");
        assert!((own.shape.core - 0.13).abs() < 1e-5, "{own:?}");
        assert!((own.shape.bias - 0.2).abs() < 1e-6, "{own:?}");
    }

    #[test]
    fn an_unknown_heading_leaves_the_sets_per_cell() {
        // Total ignorance: R̄ = 0, the motion is undirected, nothing is shared.
        let run = |sets: HeadingSets| {
            let cfg = GridConfig {
                heading_sets: sets,
                ..GridConfig::default()
            };
            let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, 4.0, 4.0]).unwrap();
            g.set_heading_set(7, 9, Trapezoid::new(0.4, 0.1, 0.05, 1.0, 0.0));
            drive(g)
        };
        let (a, b) = (run(HeadingSets::PerCell), run(HeadingSets::Shared));
        assert!(a.estimate().heading_reliability < 0.8);
        for (c, r) in [(7, 9), (0, 0), (20, 20)] {
            assert_eq!(a.heading_set(c, r), b.heading_set(c, r), "({c}, {r})");
        }
        assert_eq!(b.heading_set(7, 9).unwrap().center, 0.6);
    }
}
