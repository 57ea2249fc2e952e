//! When the motion blur's pending radius is applied: the rule [`FuzzyGrid::apply_pending`]
//! asks before it dilates, chosen by [`GridConfig::blur`](super::GridConfig::blur).
//!
//! The dilation runs as 1-D passes (rows, columns, and for the octagon both diagonals), each
//! with a share of the element's radius: 1/(1 + √2) ≈ 0.41 of it for the octagon's row and
//! column passes, all of it for the square's. A pass whose profile is 0 one cell away is the
//! identity. [`Blur::Drop`] applies (and so consumes) any radius of a cell or more, so below
//! ≈ 2.4 cells (octagon) the radius is spent and nothing moves; [`Blur::Carry`] keeps the
//! radius pending until the row or column pass would give the neighbouring cell at least
//! `level` times its source's possibility, i.e. until applying it moves possibility one cell.
//!
//! With [`RaisedHeadings::Inherit`](super::RaisedHeadings) a blur also moves the heading sets
//! of the cells it raises towards the belief's heading (`FuzzyGrid::inherit_headings`).
//!
//! # Complexity
//!
//! `blur_due`: O(1); `inherit_headings`: O(cells).

use super::dilate::Profile;
use super::{ElementShape, Estimate, FuzzyGrid};
use crate::core::angle::wrap_pi_f32;
use serde::{Deserialize, Serialize};
use std::f32::consts::PI;
use std::f32::consts::SQRT_2;

/// What happens to a blur radius too small for the dilation's passes to reach a neighbour.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub enum Blur {
    /// Applied, and so consumed, from one cell of radius on: below ≈ 2.4 cells (octagon) the
    /// passes reach no neighbour and the radius is lost. The grid's behaviour before `Carry`.
    #[default]
    Drop,
    /// Carried over until the row or column pass gives the neighbouring cell a possibility of
    /// at least `level` (in (0, 1]) times its source's, then applied whole: every motion
    /// eventually blurs, however short its steps.
    Carry {
        /// The element's value one cell away from which the radius is applied.
        level: f32,
    },
}

impl Blur {
    /// Whether `level` is usable: `Drop`, or `Carry` with `level` in (0, 1].
    pub(crate) fn is_valid(&self) -> bool {
        match *self {
            Blur::Drop => true,
            Blur::Carry { level } => level > 0.0 && level <= 1.0,
        }
    }
}

impl FuzzyGrid {
    /// Whether the pending radii (metres, along x and y) are applied now (module docs).
    pub(crate) fn blur_due(&self, core: [f32; 2], flank: [f32; 2]) -> bool {
        match self.cfg.blur {
            Blur::Drop => (0..2).any(|k| core[k] + flank[k] >= self.cell),
            Blur::Carry { level } => {
                let share = match self.cfg.element {
                    ElementShape::Octagon => 1.0 / (1.0 + SQRT_2),
                    ElementShape::Square => 1.0,
                };
                (0..2).any(|k| {
                    let pass = Profile {
                        core: share * core[k] / self.cell,
                        flank: share * flank[k] / self.cell,
                    };
                    pass.at(1.0) >= level
                })
            }
        }
    }
}

impl FuzzyGrid {
    /// After a blur, under [`RaisedHeadings::Inherit`](super::RaisedHeadings): each cell raised
    /// from `h` (`work.before`) to `h′` takes the share `λ = (h′ − h)/h′` of its heading set from
    /// the belief's (`est`, the estimate before the motion, turned by `turn`; cores widened by
    /// `widen`), keeping the share `1 − λ` of its own: centre, core, flank and bias move
    /// linearly (the centre the short way round). A cell whose heading was forgotten (core
    /// 2π) takes the belief's centre, its core and bias still near the full circle for a small
    /// λ. The floor's bias (`floor / h′`) is kept.
    pub(crate) fn inherit_headings(&mut self, est: &Estimate, turn: f32, widen: f32) {
        let set = self.belief_set(est, turn, widen);
        let (theta, d_in, a_in, b_in) = (set.theta, set.delta, set.alpha, set.bias);
        let floor = self.cfg.floor;
        for i in 0..self.h.len() {
            let (was, now) = (self.work.before[i], self.h[i]);
            if now <= was || now <= 0.0 {
                continue;
            }
            let l = (now - was) / now;
            let k = 1.0 - l;
            let d = self.delta[i];
            self.theta[i] = if d >= 2.0 * PI {
                theta
            } else {
                wrap_pi_f32(self.theta[i] + l * wrap_pi_f32(theta - self.theta[i]))
            };
            self.delta[i] = (k * d + l * d_in).min(2.0 * PI);
            self.alpha[i] = k * self.alpha[i] + l * a_in;
            self.bias[i] = (k * self.bias[i] + l * b_in).max(floor / now).min(1.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::Odometry;
    use crate::grid::GridConfig;

    fn grid(blur: Blur) -> FuzzyGrid {
        let cfg = GridConfig {
            blur,
            directed_min_reliability: 1.0,
            core_per_metre: 0.0,
            flank_per_metre: 0.0,
            flank_per_second: 0.0,
            undirected_per_metre: 1.0,
            ..GridConfig::default()
        };
        let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, 4.0, 4.0]).unwrap();
        g.possibilities_mut().fill(0.0);
        g.possibilities_mut()[20 * 40 + 20] = 1.0;
        g
    }

    /// Ten steps of 3 cm, each applied: 0.3 m of undirected flank in all.
    fn walk(g: &mut FuzzyGrid) {
        for _ in 0..10 {
            let o = Odometry {
                forward: 0.03,
                left: 0.0,
                turn: 0.0,
            };
            g.predict(&o, 0.1).unwrap();
            g.apply_pending();
        }
    }

    #[test]
    fn carried_radius_reaches_the_neighbour_dropped_one_does_not() {
        // Drop: each 3 cm step is below a cell, carried; at 0.12 m the radius is applied, but
        // the octagon's row pass gets 0.41 · 1.2 < 1 cell of it: nothing moves, and it is spent.
        let mut dropped = grid(Blur::Drop);
        walk(&mut dropped);
        assert_eq!(dropped.possibility(21, 20), 0.0);
        // Carry at level 0.25: the pass's flank f = 0.41 · R cells gives the neighbour
        // 1 − 1/f ≥ 0.25 once R ≥ 1/(0.75 · 0.41) = 3.2 cells, i.e. after 11 steps: not yet
        // after 10 (0.3 m), the radius still pending.
        let mut carried = grid(Blur::Carry { level: 0.25 });
        walk(&mut carried);
        assert_eq!(carried.possibility(21, 20), 0.0);
        walk(&mut carried);
        // 0.6 m in all, applied at 0.33 m (11 steps) and pending since: the neighbour has
        // 1 − 1/(0.414 · 3.3) = 0.268.
        let v = carried.possibility(21, 20);
        assert!((v - 0.268).abs() < 0.01, "{v}");
        assert_eq!(carried.possibility(20, 20), 1.0);
    }

    #[test]
    fn raised_cells_inherit_the_heading_under_inherit_only() {
        use crate::grid::RaisedHeadings;
        // One cell known to head at 1 rad, every other cell at 0 with its heading forgotten;
        // a 0.5 m step along the heading blurs (flank 0.5 m) into the neighbours.
        let run = |raised: RaisedHeadings| {
            let cfg = GridConfig {
                raised_headings: raised,
                flank_per_metre: 1.0,
                ..GridConfig::default()
            };
            let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, 4.0, 4.0]).unwrap();
            g.start_at(2.05, 2.05, 1.0).unwrap();
            let o = Odometry {
                forward: 0.5,
                left: 0.0,
                turn: 0.0,
            };
            g.predict(&o, 0.5).unwrap();
            g.apply_pending();
            g
        };
        let keep = run(RaisedHeadings::Keep);
        let inherit = run(RaisedHeadings::Inherit);
        // The peak moved by (0.5 cos 1, 0.5 sin 1) = 3 and 4 cells; (24, 25) is raised beside it.
        let (c, r) = (24, 25);
        assert!(keep.possibility(c, r) > 0.2, "{}", keep.possibility(c, r));
        assert_eq!(keep.possibility(c, r), inherit.possibility(c, r));
        assert!(keep.heading_set(c, r).unwrap().shape.core >= 2.0 * std::f32::consts::PI);
        // Raised from 0: all of it came with the blur, so it takes the belief's set: centre 1,
        // core the bearing model's plus the widening (0.06 + 0.01 · 0.5), bias 1 − R̄ = 0.
        let t = inherit.heading_set(c, r).unwrap();
        assert!((t.center - 1.0).abs() < 1e-5, "{t:?}");
        assert!((t.shape.core - 0.065).abs() < 1e-5, "{t:?}");
        assert!(t.shape.bias < 1e-6, "{t:?}");
        // The peak itself was not raised: its set is the same under both.
        assert_eq!(keep.heading_set(23, 24), inherit.heading_set(23, 24));
    }

    #[test]
    fn level_must_be_in_the_unit_interval() {
        assert!(Blur::Drop.is_valid());
        assert!(Blur::Carry { level: 1.0 }.is_valid());
        for level in [0.0, -0.1, 1.5, f32::NAN] {
            assert!(!Blur::Carry { level }.is_valid(), "{level}");
        }
    }
}
