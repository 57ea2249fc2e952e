//! Fuzzy dilation `G ⊕ B (p) = sup_q min(G(q), B(p − q))` (paper 000 eq. (3))
//! with a trapezoid-profiled octagonal (or square) structuring element, in
//! time independent of the element's radius.
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
//! # The 1-D pass
//!
//! `out(x) = sup_y min(g(y), 1 − max(0, |x − y| − c)/R)` is computed in two
//! sweeps (from the left and from the right) with a monotone deque. In the
//! left sweep a sample `y` contributes `g(y)` until its line
//! `ℓ_y(x) = 1 − (x − y − c)/R` drops below `g(y)` ("expires"), and `ℓ_y(x)`
//! afterwards. A later sample with a value at least as high dominates an
//! earlier one for ever (its value and its line are both higher), so the
//! deque holds strictly decreasing values; expired samples form a prefix, of
//! which only the latest (highest line) matters. Each sample enters and
//! leaves the deque once: O(n) per line, whatever `c` and `R`.
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
//! O(cells) for any radius: 4 passes (2 for [`ElementShape::Square`]) of two
//! sweeps each, every sample pushed and popped at most once per sweep; no
//! allocation (the buffers live in the grid).
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

use super::{ElementShape, FuzzyGrid};
use std::f32::consts::{PI, SQRT_2};

/// Inverse flank used for a zero flank: lines fall off at once, without
/// producing `0 · ∞`.
const STEEP: f32 = 1e30;

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
    fn is_identity(&self) -> bool {
        self.at(1.0) <= 0.0
    }
}

/// 1-D sup-min dilation of `g` into `out` by `p` (both slices of equal
/// length; `deque` at least as long). Values of `g` must be in [0, 1].
///
/// # Complexity
///
/// O(n), independent of `p`.
///
/// # Example
///
/// ```
/// use lplace::grid::dilate::{dilate_line, Profile};
/// let g = [0.0, 0.0, 1.0, 0.0, 0.3];
/// let mut out = [0.0; 5];
/// let mut dq = [0u32; 5];
/// dilate_line(&g, &mut out, Profile { core: 0.0, flank: 2.0 }, &mut dq);
/// assert_eq!(out, [0.0, 0.5, 1.0, 0.5, 0.3]);
/// ```
pub fn dilate_line(g: &[f32], out: &mut [f32], p: Profile, deque: &mut [u32]) {
    let n = g.len().min(out.len()).min(deque.len());
    if n == 0 {
        return;
    }
    let inv = if p.flank > 0.0 { 1.0 / p.flank } else { STEEP };
    sweep::<false>(g, out, n, p.core, inv, deque);
    sweep::<true>(g, out, n, p.core, inv, deque);
}

/// One sweep; `REV` runs right to left and max-combines into `out`. The
/// deque keeps (position, value) pairs so the hot loop reads no index twice.
#[inline(always)]
fn sweep<const REV: bool>(
    g: &[f32],
    out: &mut [f32],
    n: usize,
    core: f32,
    inv: f32,
    dq: &mut [u32],
) {
    let at = |k: usize| if REV { n - 1 - k } else { k };
    let line = |y: usize, x: usize| 1.0 - ((x - y) as f32 - core).max(0.0) * inv;
    let (mut head, mut tail) = (0usize, 0usize); // deque = dq[head..tail]
    let mut last_expired = usize::MAX;
    for x in 0..n {
        let gx = g[at(x)];
        while tail > head && g[at(dq[tail - 1] as usize)] <= gx {
            tail -= 1;
        }
        dq[tail] = x as u32;
        tail += 1;
        while tail > head {
            let y = dq[head] as usize;
            if line(y, x) <= g[at(y)] {
                last_expired = y;
                head += 1;
            } else {
                break;
            }
        }
        let mut v = if tail > head {
            g[at(dq[head] as usize)]
        } else {
            0.0
        };
        if last_expired != usize::MAX {
            v = v.max(line(last_expired, x));
        }
        let o = &mut out[at(x)];
        *o = if REV { o.max(v) } else { v.max(0.0) };
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
        // Clamp the plane first: the passes assume values in [0, 1].
        for v in self.h.iter_mut() {
            *v = if *v >= 0.0 { v.min(1.0) } else { 0.0 };
        }
        let (k, diag) = match self.cfg.element {
            ElementShape::Octagon => (1.0 / (1.0 + SQRT_2), true),
            ElementShape::Square => (1.0, false),
        };
        let px = Profile {
            core: cx * k,
            flank: fx * k,
        };
        let py = Profile {
            core: cy * k,
            flank: fy * k,
        };
        let pd = Profile {
            core: 0.5 * (px.core + py.core) / SQRT_2,
            flank: 0.5 * (px.flank + py.flank) / SQRT_2,
        };
        let (nx, ny) = (self.nx, self.ny);
        if !px.is_identity() {
            self.pass(px, (0..ny).map(|j| (j * nx, 1usize, nx)));
        }
        if !py.is_identity() {
            self.pass(py, (0..nx).map(|i| (i, nx, ny)));
        }
        if diag && !pd.is_identity() {
            // Diagonals (+1, +1): start on the bottom row, then the left column.
            let starts = (0..nx)
                .map(|i| (i, nx + 1, (nx - i).min(ny)))
                .chain((1..ny).map(|j| (j * nx, nx + 1, (ny - j).min(nx))));
            self.pass(pd, starts);
            // Anti-diagonals (−1, +1): start on the bottom row, then the right column.
            let starts = (0..nx)
                .map(|i| (i, nx - 1, (i + 1).min(ny)))
                .chain((1..ny).map(|j| (j * nx + nx - 1, nx - 1, (ny - j).min(nx))));
            self.pass(pd, starts);
        }
    }

    /// Runs the 1-D dilation along each line `(start, stride, len)`.
    fn pass(&mut self, p: Profile, lines: impl Iterator<Item = (usize, usize, usize)>) {
        for (start, stride, len) in lines {
            if len < 2 {
                continue;
            }
            if stride == 1 {
                let row = &self.h[start..start + len];
                dilate_line(row, &mut self.line_out[..len], p, &mut self.deque);
                self.h[start..start + len].copy_from_slice(&self.line_out[..len]);
            } else {
                for k in 0..len {
                    self.line[k] = self.h[start + k * stride];
                }
                dilate_line(
                    &self.line[..len],
                    &mut self.line_out[..len],
                    p,
                    &mut self.deque,
                );
                for k in 0..len {
                    self.h[start + k * stride] = self.line_out[k];
                }
            }
        }
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
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute(g: &[f32], p: Profile) -> Vec<f32> {
        (0..g.len())
            .map(|x| {
                (0..g.len())
                    .map(|y| g[y].min(p.at(x as f32 - y as f32)))
                    .fold(0.0, f32::max)
            })
            .collect()
    }

    #[test]
    fn line_matches_brute_force_on_fixed_cases() {
        let g = [0.1, 0.9, 0.2, 0.0, 0.7, 0.7, 0.3, 1.0, 0.0, 0.05, 0.5];
        for p in [
            Profile {
                core: 0.0,
                flank: 0.0,
            },
            Profile {
                core: 0.0,
                flank: 3.0,
            },
            Profile {
                core: 1.5,
                flank: 0.0,
            },
            Profile {
                core: 1.0,
                flank: 2.5,
            },
            Profile {
                core: 20.0,
                flank: 20.0,
            },
        ] {
            let mut out = vec![0.0; g.len()];
            let mut dq = vec![0u32; g.len()];
            dilate_line(&g, &mut out, p, &mut dq);
            let b = brute(&g, p);
            for (a, e) in out.iter().zip(&b) {
                assert!((a - e).abs() < 1e-6, "{p:?}: {out:?} vs {b:?}");
            }
        }
    }
}
