//! Fuzzy dilation `G ⊕ B (p) = sup_q min(G(q), B(p − q))` (paper 000 eq. (3))
//! with a trapezoid-profiled octagonal (or square) structuring element. Long
//! reaches cost O(1) per cell whatever the radius (deques); short ones
//! (the usual case) run in vector blocks whose work follows the belief:
//! independent of the radius on low noise, nearly so on a concentrated
//! belief, growing with it only where values differ within reach above the
//! element's lowest level (see below).
//!
//! # The element and why it decomposes
//!
//! The element has a flat top and a linear flank: `B(p) = 1` when
//! `‖p‖ ≤ c`, falling to 0 at `‖p‖ = c + R`, where `‖·‖` is the octagonal
//! norm whose unit ball is the regular octagon with apothem 1 (it contains
//! the unit disc and exceeds it by at most 8 %). Its level sets are octagons
//! of apothem `c + R(1 − t)`.
//!
//! Under sup-min, dilating by `B₁` then by `B₂` equals dilating by their
//! sup-min Minkowski sum, whose level-`t` set is the Minkowski sum of the
//! level sets. A regular octagon of apothem `a` is the Minkowski sum of a
//! square of half side `a/(1+√2)` and a diamond of L1 radius `√2·a/(1+√2)`; a
//! square is the sum of a horizontal and a vertical segment, and a diamond
//! the sum of two diagonal segments. Trapezoid profiles scale linearly with
//! the level, so the octagonal element is *exactly* the sup-min sum of four
//! 1-D trapezoid elements along rows, columns and both diagonals.
//!
//! # The algorithms, one per file
//!
//! * `deque.rs`: the 1-D pass by monotone deques, O(1) per cell at any reach
//!   (long reaches, and the reference of the tests); also [`dilate_line`],
//!   which the place engine's grid tracker uses.
//! * `offsets.rs`: the same pass by offsets in vector blocks that stop early,
//!   with groups left alone (short reaches, the usual case).
//! * `window.rs`: window maxima (van Herk / Gil–Werman) for the groups where
//!   the element's flank cannot act.
//! * `block.rs`: the 16-lane block primitives the last two are written in.
//! * `lukasiewicz.rs`: the other rule, [`crate::grid::Dilation::Lukasiewicz`]
//!   (`max(0, G + B − 1)` instead of `min`): a flat core, a chamfer cone and
//!   a floor, O(1) per cell at every radius. [`FuzzyGrid::dilate`] follows
//!   the configuration; sup-min is the default.
//!
//! The buffers live in the grid's workspace (`grid/workspace.rs`), apart
//! from the belief: the passes take the plane and the workspace as
//! arguments.
//!
//! On the grid the diagonal passes move by whole diagonal steps, so the
//! element actually applied is the *discrete* sup-min sum of the four 1-D
//! elements: exact for that element (the brute-force tests enumerate it), but
//! at small radii up to one diagonal step narrower than the continuous
//! octagon between its vertices (a cone of radius 10 cells gives 0.32 instead
//! of 0.5 five cells along an axis). [`ElementShape::Square`] has no such
//! rounding.
//!
//! Near the grid border each 1-D pass only sees cells inside the grid, so a
//! point reachable only through a detour outside the grid is not reached: the
//! result is then between `G` and the unclipped dilation.
//!
//! # Complexity
//!
//! 4 passes (2 for [`ElementShape::Square`]). A pass reaching `K ≤ 24`
//! samples costs O(cells) for the group extrema (and the window maxima when
//! enough groups are flat) plus, for every block not left alone or flat,
//! the offsets until it stops (≤ `K`, about 40 instructions per offset per
//! 16 cells); a longer one O(cells) with two deque sweeps (every
//! sample pushed and popped at most once per sweep, about 7 ns per cell), its
//! columns and diagonals gathered 16 lines at a time so that each cache line
//! is fetched once. No allocation (the buffers live in the grid: a ring of
//! `K + 1` rows in the scratch plane, a padded row, three values per group,
//! and, for the window maxima, a chunk of padded rows after the ring and a
//! row in `line_out`).
//!
//! # Example
//!
//! ```
//! use lplace::grid::{FuzzyGrid, GridConfig};
//! let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 3.0, 3.0]).unwrap();
//! g.possibilities_mut().fill(0.0);
//! g.possibilities_mut()[15 * 30 + 15] = 1.0;
//! g.dilate(0.0, 1.0); // cone of radius 1 m = 10 cells
//! assert_eq!(g.possibility(15, 15), 1.0);
//! let half_way = g.possibility(20, 15); // continuous octagon: 0.5
//! assert!(half_way > 0.3 && half_way <= 0.5);
//! assert_eq!(g.possibility(15, 26), 0.0);
//! ```
//!
//! With [`ElementShape::Square`] the axes carry no diagonal rounding:
//!
//! ```
//! use lplace::grid::{ElementShape, FuzzyGrid, GridConfig};
//! let cfg = GridConfig { element: ElementShape::Square, ..GridConfig::default() };
//! let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, 3.0, 3.0]).unwrap();
//! g.possibilities_mut().fill(0.0);
//! g.possibilities_mut()[15 * 30 + 15] = 1.0;
//! g.dilate(0.0, 1.0);
//! assert!((g.possibility(20, 15) - 0.5).abs() < 1e-5);
//! assert!((g.possibility(20, 20) - 0.5).abs() < 1e-5); // a square's corner
//! ```

mod block;
mod deque;
pub(crate) mod lukasiewicz;
mod offsets;
mod window;

#[cfg(test)]
mod tests;

pub use deque::dilate_line;

use super::workspace::Workspace;
use super::{ElementShape, FuzzyGrid};
use std::f32::consts::SQRT_2;

/// Largest reach (samples) for which a pass runs by offsets, at most that
/// many vector steps per block; beyond it the O(1)-per-cell deque sweeps
/// bound the worst case.
pub(super) const LEVEL_MAX: usize = 24;

/// Length of the line buffer a row of `nx` cells needs in the offset pass:
/// whole blocks and [`LEVEL_MAX`] zeros on either side.
pub(super) fn padded_row(nx: usize) -> usize {
    nx.div_ceil(LANES) * LANES + 2 * LEVEL_MAX
}

/// Length of the block-bound buffer of an `nx × ny` grid: three values
/// (maximum, minimum, bound) per 16-column chunk of every group of
/// [`GROUP`] rows.
pub(super) fn chunk_len(nx: usize, ny: usize) -> usize {
    3 * nx.div_ceil(LANES) * ny.div_ceil(GROUP)
}

/// Largest offset `k` (samples) at which the profile is still above 0.
pub(super) fn reach(p: Profile) -> usize {
    let span = p.core + p.flank;
    if span.is_nan() || span <= 0.0 {
        return 0;
    }
    // Start at the float bound and step back over offsets where it is 0, so
    // the count agrees with `Profile::at` exactly.
    let mut k = span.min(1e9).ceil() as usize;
    while k > 0 && p.at(k as f32) <= 0.0 {
        k -= 1;
    }
    k
}

/// Cells per block of the offset passes: four SSE2 vectors, one 64-byte
/// cache line; a block's exit test is one branch for all of them.
pub(super) const LANES: usize = 16;

/// Band rows per group of the band passes' block bounds.
pub(super) const GROUP: usize = 8;

/// The element's levels `b[k] = B(k)` for `k = 0..=K`, `K` the reach capped
/// at `cap − 1` (offsets beyond a line's length reach no cell), on the
/// stack; returns them and `K` (≤ [`LEVEL_MAX`]).
pub(super) fn levels(p: Profile, cap: usize) -> ([f32; LEVEL_MAX + 1], usize) {
    let k = reach(p).min(cap.saturating_sub(1)).min(LEVEL_MAX);
    let mut b = [0.0; LEVEL_MAX + 1];
    for (i, v) in b.iter_mut().enumerate().take(k + 1) {
        *v = p.at(i as f32);
    }
    (b, k)
}

/// One 1-D trapezoid element, in samples along its line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Profile {
    /// Half width of the flat top (samples).
    pub core: f32,
    /// Width of the flank (samples).
    pub flank: f32,
}

impl Profile {
    /// Value of the element at offset `u` (samples).
    #[inline]
    pub fn at(&self, u: f32) -> f32 {
        let over = (u.abs() - self.core).max(0.0);
        if over == 0.0 {
            1.0
        } else if self.flank > 0.0 {
            (1.0 - over / self.flank).max(0.0)
        } else {
            0.0
        }
    }
    /// True when the element reaches no neighbour (value 0 one sample away).
    pub(super) fn is_identity(&self) -> bool {
        self.at(1.0) <= 0.0
    }
}

impl FuzzyGrid {
    /// Dilates the plane by the configured element with flat-top radius
    /// `core` and flank `flank` (metres, apothem of the octagon), and leaves
    /// the heading sets alone. Negative or non-finite radii count as 0.
    pub fn dilate(&mut self, core: f32, flank: f32) {
        self.dilate_xy([core, core], [flank, flank]);
    }

    /// Dilation with different radii along x and y (the diagonal passes use
    /// their mean): the odometry-shaped element of [`crate::grid::predict`].
    pub fn dilate_xy(&mut self, core: [f32; 2], flank: [f32; 2]) {
        let clean = |v: f32| {
            if v.is_finite() {
                v.max(0.0) / self.cell
            } else {
                0.0
            }
        };
        let (cx, cy) = (clean(core[0]), clean(core[1]));
        let (fx, fy) = (clean(flank[0]), clean(flank[1]));
        let dims = (self.nx, self.ny);
        let element = self.cfg.element;
        if self.cfg.dilation == super::Dilation::Lukasiewicz {
            let radii = lukasiewicz::Radii {
                core: [cx, cy],
                flank: [fx, fy],
            };
            // The motion element has no bias: no floor.
            let steps = lukasiewicz::steps(element, radii);
            lukasiewicz::dilate(&mut self.h, dims, steps, 0.0, &mut self.work.line);
            return;
        }
        dilate_plane(
            &mut self.h,
            dims,
            element,
            ([cx, cy], [fx, fy]),
            &mut self.work,
        );
    }
}

/// The three 1-D profiles of an element with radii `core`, `flank` (cells)
/// along x and y: rows, columns, diagonals (the mean of the two, along the
/// diagonal step); and whether the diagonal passes run.
fn profiles(
    element: ElementShape,
    (core, flank): ([f32; 2], [f32; 2]),
) -> (Profile, Profile, Profile, bool) {
    let (k, diag) = match element {
        ElementShape::Octagon => (1.0 / (1.0 + SQRT_2), true),
        ElementShape::Square => (1.0, false),
    };
    let px = Profile {
        core: core[0] * k,
        flank: flank[0] * k,
    };
    let py = Profile {
        core: core[1] * k,
        flank: flank[1] * k,
    };
    let pd = Profile {
        core: 0.5 * (px.core + py.core) / SQRT_2,
        flank: 0.5 * (px.flank + py.flank) / SQRT_2,
    };
    (px, py, pd, diag)
}

/// Dilates the plane `h` (`nx × ny`, row-major) by `element` with radii
/// `(core, flank)` in cells along x and y, in place, with `work`'s buffers:
/// each 1-D pass by offsets when its reach is at most [`LEVEL_MAX`], else by
/// deques.
pub(super) fn dilate_plane(
    h: &mut [f32],
    (nx, ny): (usize, usize),
    element: ElementShape,
    radii: ([f32; 2], [f32; 2]),
    work: &mut Workspace,
) {
    // Clamp the plane first: the passes assume values in [0, 1].
    // (Selects, the same values as `v.min(1.0)` with NaN to 0: `f32::min`'s
    // NaN rule kept this loop scalar.)
    for v in h.iter_mut() {
        let c = if *v < 1.0 { *v } else { 1.0 };
        *v = if *v >= 0.0 { c } else { 0.0 };
    }
    let (px, py, pd, diag) = profiles(element, radii);
    // The 1-D passes: (profile, direction, line length capping the reach).
    let mut passes = [None; 4];
    let mut n = 0;
    let mut plan = |p: Profile, dx: isize, dy: isize, cap: usize| {
        if !p.is_identity() {
            passes[n] = Some((p, dx, dy, cap));
            n += 1;
        }
    };
    plan(px, 1, 0, nx);
    plan(py, 0, 1, ny);
    if diag {
        plan(pd, 1, 1, nx.min(ny)); // diagonals (+1, +1)
        plan(pd, -1, 1, nx.min(ny)); // anti-diagonals (−1, +1)
    }
    let by_offsets = |p: Profile| reach(p) <= LEVEL_MAX;
    // The group extrema the offset passes rely on and keep up to date
    // for a next one; a deque pass invalidates them.
    let mut extrema = false;
    for i in 0..n {
        let Some((p, dx, dy, cap)) = passes[i] else {
            continue;
        };
        if by_offsets(p) {
            if !extrema {
                offsets::measure_extrema(h, (nx, ny), work);
            }
            let (b, k) = levels(p, cap);
            let next = passes.get(i + 1).copied().flatten();
            extrema = next.is_some_and(|(q, ..)| by_offsets(q));
            offsets::offset_pass(h, (nx, ny), work, &b[..=k], (dx, dy), (extrema, true));
        } else {
            match dy {
                0 => deque::row_pass(h, nx, p, work),
                _ => deque::skew_pass(h, (nx, ny), p, dx, work),
            }
            extrema = false;
        }
    }
}
