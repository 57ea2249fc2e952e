//! Prediction: blur the grid for the motion since the last update (paper 000
//! eq. (2)), optionally shaped by odometry.
//!
//! [`FuzzyGrid::predict`] only *accumulates* motion (robot-frame odometry
//! increments composed into one displacement, distance travelled, angle
//! turned, time elapsed); the work happens once, in
//! [`FuzzyGrid::apply_pending`], which every update calls first. Composing
//! first is exact for the blur — the sup-min sum of two trapezoid elements is
//! the trapezoid element with summed radii — and it keeps sub-cell motions
//! from being lost: a radius below one cell is carried over, not dropped.
//! With [`Blur::Drop`](super::Blur) (the default) a radius of a cell or more
//! is applied and consumed even when it is too small for the octagon's 1-D
//! passes to reach a neighbour (each pass gets ≈ 0.41 of it, the diagonal ones
//! ≈ 0.29 of a diagonal step: below ≈ 2.4 cells the dilation is the
//! identity), so such a radius has no effect — at MRCLAM's step sizes the blur
//! hardly ever acts. [`Blur::Carry`](super::Blur) keeps it pending until the
//! passes move possibility one cell ([`crate::grid::blur`]). On MRCLAM
//! carrying was measured and made the ATE worse, with the tuned sensor models
//! and with ones derived from the readings' measured spread (a belief that
//! spreads follows biased readings; `docs/compare.md`), so `Drop` stays the
//! default; the MRCLAM file carries it since it was refitted, with ramped
//! estimate cuts, for robustness to its map and values.
//!
//! The fractional remainder of a shift is carried in both forms of
//! [`GridConfig::shift`](super::GridConfig::shift); under [`Shift::Lattice`] it also moves the
//! cell lattice (`FuzzyGrid::place_lattice`), so that the belief follows the displacement
//! exactly instead of lagging or leading it by up to half a cell, and a remainder rounded the
//! other way (by a millimetre's difference) leaves the same belief on the same points.
//!
//! Applying the pending motion:
//! 1. If the heading estimate is reliable (`R̄ ≥ directed_min_reliability`),
//!    the plane and the heading sets are shifted by the displacement rotated
//!    into the world frame by the estimated heading (whole cells; the
//!    fractional remainder is carried over), and every heading centre turns by
//!    the odometry rotation. The element is then anisotropic: its flank along
//!    x and y grows with the x and y components of the displacement.
//! 2. Otherwise the displacement has no usable direction: nothing is shifted
//!    and the element grows by `undirected_per_metre` per metre in every
//!    direction (paper 000's odometry-free blur).
//! 3. With `directed_ramp` > 0 the choice is a weight `w` ([`FuzzyGrid::directed_weight`]),
//!    rising from 0 at `R̄ = directed_min_reliability − directed_ramp` to 1 at the threshold:
//!    the plane is shifted by `w` times the displacement and the flank is `w` times case 1's
//!    plus `1 − w` times case 2's, so a heading reliability moving by a hair moves the
//!    prediction by as little.
//!
//! 4. Under [`CellMotion::HeadingClasses`](super::CellMotion), each cell whose heading set is
//!    clear is then moved further, so that it moves along its own heading
//!    ([`crate::grid::classes`]).
//!
//! The increments are first scaled by `forward_scale` and `turn_scale` (an odometry
//! calibration; 1 by default).
//!
//! In both cases the element's flat core is `core_per_metre · d`, its flank
//! gets `flank_per_metre · d + flank_per_second · t`, and every heading core Δ
//! widens by `delta_per_radian · |turn| + delta_per_second · t`.
//!
//! # Complexity
//!
//! [`FuzzyGrid::predict`] is O(1); [`FuzzyGrid::apply_pending`] is O(cells)
//! (heading estimate, shift, dilation — see [`crate::grid::dilate`]).
//!
//! # Example
//!
//! ```
//! use lplace::core::Odometry;
//! use lplace::grid::{FuzzyGrid, GridConfig};
//! let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 4.0, 4.0]).unwrap();
//! g.possibilities_mut().fill(0.0);
//! g.possibilities_mut()[20 * 40 + 20] = 1.0;
//! g.predict(&Odometry { forward: 1.0, left: 0.0, turn: 0.0 }, 5.0).unwrap();
//! g.apply_pending();
//! // Heading unknown: blurred isotropically, never lowered where it was.
//! assert_eq!(g.possibility(20, 20), 1.0);
//! assert!(g.possibility(26, 20) > 0.0 && g.possibility(20, 14) > 0.0);
//! ```

use super::{Estimate, FuzzyGrid, GridError, HeadingSets, RaisedHeadings, Shift};
use crate::core::Odometry;
use std::f32::consts::PI;

/// Checks an odometry increment and its elapsed time `dt` (seconds), as every localizer must
/// before it moves its belief: each value finite at the single precision the metric methods share
/// (see [`Odometry::to_single_precision`]), and `dt ≥ 0`.
///
/// # Errors
/// [`GridError::BadMotion`] carrying the increment.
///
/// # Example
/// ```
/// use lplace::core::Odometry;
/// use lplace::grid::check_motion;
/// let o = Odometry { forward: 1.0, left: 0.0, turn: 0.1 };
/// assert!(check_motion(&o, 0.5).is_ok());
/// assert!(check_motion(&o, -0.5).is_err());
/// assert!(check_motion(&Odometry { forward: 1e39, ..o }, 0.5).is_err());
/// ```
pub fn check_motion(odometry: &Odometry, dt: f64) -> Result<(), GridError> {
    let finite = [odometry.forward, odometry.left, odometry.turn, dt]
        .iter()
        .all(|&v| (v as f32).is_finite());
    if finite && dt >= 0.0 {
        Ok(())
    } else {
        Err(GridError::BadMotion {
            forward: odometry.forward,
            left: odometry.left,
            turn: odometry.turn,
            dt,
        })
    }
}

/// Motion accumulated since the last application.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Pending {
    /// Composed displacement in the frame of the first increment.
    px: f32,
    py: f32,
    /// Composed rotation.
    turn: f32,
    /// Path length and total |rotation|.
    dist: f32,
    turned: f32,
    dt: f32,
    /// Sub-cell shift carried over (world metres).
    rx: f32,
    ry: f32,
    /// Blur radii too small to act on yet (metres).
    core: [f32; 2],
    flank: [f32; 2],
}

/// The discrete decisions of the last [`FuzzyGrid::apply_pending`] that did anything, for
/// tracing where two runs that should agree part ([`FuzzyGrid::last_motion`]). Recording them
/// changes nothing in the belief.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MotionTrace {
    /// How many applications there have been since the grid was made or reset.
    pub applied: u64,
    /// Share of the displacement shifted along the estimated heading
    /// ([`FuzzyGrid::directed_weight`]; 0 or 1 unless `directed_ramp` > 0).
    pub directed: f32,
    /// The whole-cell shift along x and y (0 when undirected).
    pub shift: [i32; 2],
    /// Whether the pending blur was applied ([`crate::grid::blur`]).
    pub blurred: bool,
}

impl MotionTrace {
    /// The record of the next application, before its shift and blur are known.
    fn next(self, directed: f32) -> Self {
        MotionTrace {
            applied: self.applied + 1,
            directed,
            ..MotionTrace::default()
        }
    }
}

impl FuzzyGrid {
    /// The decisions of the last motion application ([`MotionTrace`]).
    pub fn last_motion(&self) -> MotionTrace {
        self.trace
    }

    /// Accumulates an odometry increment (robot frame at the start of the
    /// interval) and its elapsed time `dt` (seconds), in the grid's single
    /// precision. Rejects what [`check_motion`] rejects without changing
    /// anything.
    pub fn predict(&mut self, odometry: &Odometry, dt: f64) -> Result<(), GridError> {
        check_motion(odometry, dt)?;
        let [forward, left, turn] = self.scaled(odometry);
        let p = &mut self.pending;
        let (s, c) = p.turn.sin_cos();
        p.px += c * forward - s * left;
        p.py += s * forward + c * left;
        p.turn += turn;
        p.dist += forward.hypot(left);
        p.turned += turn.abs();
        p.dt += dt as f32;
        Ok(())
    }

    /// The odometry increment in single precision, calibrated by
    /// [`GridConfig::forward_scale`](super::GridConfig::forward_scale) and `turn_scale`:
    /// forward, left, turn.
    pub fn scaled(&self, odometry: &Odometry) -> [f32; 3] {
        let (k, kt) = (self.cfg.forward_scale, self.cfg.turn_scale);
        [
            odometry.forward as f32 * k,
            odometry.left as f32 * k,
            odometry.turn as f32 * kt,
        ]
    }

    /// Widens every cell's heading core by `by` radians (paper 000: the
    /// prediction "increases the Δ values by a constant").
    pub fn widen_headings(&mut self, by: f32) {
        if by.is_finite() && by > 0.0 {
            for d in self.delta.iter_mut() {
                *d = (*d + by).min(2.0 * PI);
            }
        }
    }

    /// Applies the accumulated motion (see the module docs). Called by every
    /// update; call it yourself before [`FuzzyGrid::estimate`] to see the
    /// predicted belief.
    pub fn apply_pending(&mut self) {
        let p = self.pending;
        if p.dist == 0.0 && p.turned == 0.0 && p.dt == 0.0 {
            return;
        }
        let est = self.estimate();
        let w = if est.height > 0.0 {
            self.directed_weight(&est)
        } else {
            0.0
        };
        self.trace = self.trace.next(w);
        let cfg = &self.cfg;
        let (flank_k, undirected) = (cfg.flank_per_metre, cfg.undirected_per_metre);
        let widen = cfg.delta_per_radian * p.turned + cfg.delta_per_second * p.dt;
        let base_core = cfg.core_per_metre * p.dist;
        let base_flank = cfg.flank_per_second * p.dt;
        let (mut core, mut flank) = (p.core, p.flank);
        let (mut rx, mut ry) = (p.rx, p.ry);
        let loose = base_flank + (flank_k + undirected) * p.dist;
        if w > 0.0 {
            let (s, c) = est.theta.sin_cos();
            let wx = c * p.px - s * p.py;
            let wy = s * p.px + c * p.py;
            let (sx, rem_x) = self.whole_cells(rx + w * wx);
            let (sy, rem_y) = self.whole_cells(ry + w * wy);
            (rx, ry) = (rem_x, rem_y);
            self.shift(sx as isize, sy as isize);
            self.move_classes(est.theta, w, p.px, p.py);
            self.turn_headings(p.turn);
            core[0] += base_core;
            core[1] += base_core;
            // Weight 1 (the step gate, or a reliable heading): exactly the directed flank.
            let along = |a: f32, b: f32| base_flank + flank_k * a.abs() + 0.5 * flank_k * b.abs();
            flank[0] += w * along(wx, wy) + (1.0 - w) * loose;
            flank[1] += w * along(wy, wx) + (1.0 - w) * loose;
        } else {
            self.move_classes(est.theta, 0.0, p.px, p.py);
            self.turn_headings(p.turn);
            core[0] += base_core;
            core[1] += base_core;
            flank[0] += loose;
            flank[1] += loose;
        }
        self.widen_headings(widen);
        // `GridConfig::blur` says whether a radius the passes may not act on
        // is spent or carried (module docs).
        if self.blur_due(core, flank) {
            self.trace.blurred = true;
            let inherit = self.cfg.raised_headings == RaisedHeadings::Inherit;
            if inherit {
                self.work.before.clear();
                self.work.before.extend_from_slice(&self.h);
            }
            self.dilate_xy(core, flank);
            if inherit {
                self.inherit_headings(&est, p.turn, widen);
            }
            core = [0.0; 2];
            flank = [0.0; 2];
        }
        if w >= 1.0 && self.cfg.heading_sets == HeadingSets::Shared {
            self.share_headings(&est, p.turn, widen);
        }
        self.pending = Pending {
            rx,
            ry,
            core,
            flank,
            ..Pending::default()
        };
        self.place_lattice();
    }

    /// How much of the displacement is shifted along the estimated heading `est.theta`, in
    /// [0, 1] (module docs): 1 from `directed_min_reliability` on, 0 below it, or with
    /// `directed_ramp` > 0 rising linearly over the `directed_ramp` below it. (The prediction
    /// shifts nothing for an empty belief, whatever this says.)
    pub fn directed_weight(&self, est: &Estimate) -> f32 {
        let (m, ramp) = (self.cfg.directed_min_reliability, self.cfg.directed_ramp);
        let r = est.heading_reliability;
        if ramp > 0.0 {
            ((r - (m - ramp)) / ramp).clamp(0.0, 1.0)
        } else if r >= m {
            1.0
        } else {
            0.0
        }
    }

    /// A displacement `r` (metres) as whole cells and the remainder. A shift beyond the grid
    /// empties it whatever its size: it is clamped so that absurd (but finite) odometry cannot
    /// overflow an index, and the remainder of a clamped or non-finite shift is dropped.
    pub(super) fn whole_cells(&self, r: f32) -> (f32, f32) {
        let lim = (self.nx.max(self.ny) + 1) as f32;
        let c = (r / self.cell).round();
        if c.is_finite() && c.abs() <= lim {
            (c, r - c * self.cell)
        } else if c.is_finite() {
            (c.clamp(-lim, lim), 0.0)
        } else {
            (0.0, 0.0)
        }
    }

    /// Puts the cell lattice where [`GridConfig::shift`](super::GridConfig::shift) says: at the
    /// extent's corner, or under [`Shift::Lattice`] moved by the carried sub-cell displacement.
    pub(super) fn place_lattice(&mut self) {
        let [x, y] = self.corner;
        (self.x0, self.y0) = match self.cfg.shift {
            Shift::Cells => (x, y),
            Shift::Lattice => (x + self.pending.rx, y + self.pending.ry),
        };
    }

    /// Under [`Shift::Lattice`], moves the lattice so that the centre of the cell holding
    /// `(x, y)` is that point (the rest of the belief is the caller's); else nothing.
    pub(super) fn centre_lattice_on(&mut self, x: f32, y: f32) {
        if self.cfg.shift != Shift::Lattice {
            return;
        }
        let [cx, cy] = self.corner;
        let s = self.cell;
        let off = |v: f32, c: f32| v - c - ((v - c) / s - 0.5).round() * s - 0.5 * s;
        self.pending.rx = off(x, cx);
        self.pending.ry = off(y, cy);
        self.place_lattice();
    }

    fn turn_headings(&mut self, by: f32) {
        if by != 0.0 {
            for t in self.theta.iter_mut() {
                *t = crate::core::angle::wrap_pi_f32(*t + by);
            }
        }
    }

    /// Moves every plane by `(sx, sy)` cells; cells entering from outside the
    /// grid get possibility 0 and an unknown heading.
    fn shift(&mut self, sx: isize, sy: isize) {
        self.trace.shift = [sx as i32, sy as i32];
        if sx == 0 && sy == 0 {
            return;
        }
        let (nx, ny) = (self.nx as isize, self.ny as isize);
        let planes: [(&mut Vec<f32>, f32); 5] = [
            (&mut self.h, 0.0),
            (&mut self.theta, 0.0),
            (&mut self.delta, 2.0 * PI),
            (&mut self.alpha, 0.0),
            (&mut self.bias, 1.0),
        ];
        for (plane, fill) in planes {
            self.work.plane.fill(fill);
            for j in 0..ny {
                let tj = j + sy;
                if tj < 0 || tj >= ny {
                    continue;
                }
                let c_lo = 0.max(-sx);
                let c_hi = nx.min(nx - sx);
                if c_lo >= c_hi {
                    continue;
                }
                let src = (j * nx + c_lo) as usize..(j * nx + c_hi) as usize;
                let dst = (tj * nx + c_lo + sx) as usize;
                let len = (c_hi - c_lo) as usize;
                self.work.plane[dst..dst + len].copy_from_slice(&plane[src]);
            }
            std::mem::swap(plane, &mut self.work.plane);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::GridConfig;

    /// A grid started at (1.23, 2.07) heading along +x, with no blur, so only the shift moves
    /// the belief; always directed (the start cell knows its heading: R̄ = 1).
    fn started(shift: Shift, forward_scale: f32) -> FuzzyGrid {
        let cfg = GridConfig {
            shift,
            forward_scale,
            core_per_metre: 0.0,
            flank_per_metre: 0.0,
            flank_per_second: 0.0,
            ..GridConfig::default()
        };
        let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, 4.0, 4.0]).unwrap();
        g.start_at(1.23, 2.07, 0.0).unwrap();
        g
    }

    fn forward(g: &mut FuzzyGrid, metres: f32) {
        let o = Odometry {
            forward: metres as f64,
            left: 0.0,
            turn: 0.0,
        };
        g.predict(&o, 0.5).unwrap();
        g.apply_pending();
    }

    #[test]
    fn the_lattice_follows_the_displacement_where_whole_cells_round_it() {
        // Three steps of 9, 8 and 7 cm. Cells: the start is the centre of its cell (1.25); the
        // carried sums 0.09, −0.01 + 0.08 and −0.03 + 0.07 round to 1, 1 and 0 cells: 1.45, with
        // 0.04 m carried, 2 cm behind 1.23 + 0.24. Lattice: the start is the point itself and
        // the belief moves by exactly 0.24.
        for (shift, want) in [(Shift::Cells, 1.45f32), (Shift::Lattice, 1.47)] {
            let mut g = started(shift, 1.0);
            for m in [0.09, 0.08, 0.07] {
                forward(&mut g, m);
            }
            let e = g.estimate();
            assert!((e.x - want).abs() < 1e-4, "{shift:?}: {e:?}");
            assert!((e.y - if shift == Shift::Cells { 2.05 } else { 2.07 }).abs() < 1e-4);
        }
    }

    #[test]
    fn a_hair_across_the_rounding_moves_the_lattice_by_a_hair() {
        // From the centre of the start's cell, 0.149 m rounds to one cell and 0.151 m to two:
        // under Cells the two estimates part by a whole cell, under Lattice by the 2 mm of input.
        let moved = |shift: Shift, m: f32| {
            let mut g = started(shift, 1.0);
            forward(&mut g, m);
            (g.estimate().x, g.last_motion().shift[0])
        };
        let (a, b) = (moved(Shift::Lattice, 0.149), moved(Shift::Lattice, 0.151));
        assert!(((b.0 - a.0) - 0.002).abs() < 1e-4, "{a:?} {b:?}");
        let (c, d) = (moved(Shift::Cells, 0.149), moved(Shift::Cells, 0.151));
        assert!(
            (c.0 - 1.35).abs() < 1e-4 && (d.0 - 1.45).abs() < 1e-4,
            "{c:?} {d:?}"
        );
        assert_eq!((c.1, d.1), (1, 2));
    }

    #[test]
    fn forward_scale_calibrates_the_odometry() {
        let mut g = started(Shift::Lattice, 0.5);
        forward(&mut g, 0.4);
        assert!((g.estimate().x - 1.43).abs() < 1e-4, "{:?}", g.estimate());
        assert_eq!(
            g.scaled(&Odometry {
                forward: 0.4,
                left: 0.2,
                turn: 0.1
            }),
            [0.2, 0.1, 0.1]
        );
    }

    #[test]
    fn the_trace_records_each_application() {
        let mut g = started(Shift::Cells, 1.0);
        assert_eq!(g.last_motion(), MotionTrace::default());
        forward(&mut g, 0.31);
        let t = g.last_motion();
        assert_eq!(
            (t.applied, t.directed, t.shift, t.blurred),
            (1, 1.0, [3, 0], false)
        );
        // Nothing pending: nothing applied, nothing recorded.
        g.apply_pending();
        assert_eq!(g.last_motion().applied, 1);
    }

    #[test]
    fn the_directed_weight_is_a_step_or_a_ramp() {
        let est = |r: f32| Estimate {
            x: 0.0,
            y: 0.0,
            theta: 0.0,
            reliability: 1.0,
            heading_reliability: r,
            top_area: 0.0,
            height: 1.0,
        };
        let step = started(Shift::Cells, 1.0);
        assert_eq!(step.directed_weight(&est(0.79)), 0.0);
        assert_eq!(step.directed_weight(&est(0.8)), 1.0);
        let cfg = GridConfig {
            directed_ramp: 0.1,
            ..GridConfig::default()
        };
        let ramp = FuzzyGrid::new(cfg, [0.0, 0.0, 1.0, 1.0]).unwrap();
        for (r, w) in [
            (0.65f32, 0.0f32),
            (0.7, 0.0),
            (0.75, 0.5),
            (0.8, 1.0),
            (0.9, 1.0),
        ] {
            let got = ramp.directed_weight(&est(r));
            assert!((got - w).abs() < 1e-5, "{r}: {got}");
        }
    }
}
