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
//! # The same pass by levels, row-parallel
//!
//! For offsets `k = 0, 1, …` the element's profile `B(k)` falls while the
//! running maximum `M_k(x) = max_{|x−y| ≤ k} g(y)` grows, so
//! `out(x) = max_k min(M_k(x), B(k))` exactly (same floats: only min and
//! max). Each step raises `M` by two shifted copies of the plane and folds it
//! into the output: element-wise operations over whole rows, along any of
//! the four directions (a column or diagonal neighbour of a row is another
//! row, shifted), so every lane is independent and the loops vectorise. It
//! costs O(reach) per cell, where the deque costs O(1) but branches on
//! data; passes reaching at most `LEVEL_MAX` samples (24; the bench's 3 m
//! cone reaches 13) run by levels, longer ones by deques.
//!
//! No exact O(1)-per-cell vector form is used: the flank makes each sample's
//! contribution a trapezoid whose flat width depends on its own value
//! (`min(g, 1 − d/R)` is flat while `1 − d/R ≥ g`), so the element is not a
//! translation-invariant max-plus one and the two-pass distance-transform
//! recurrence does not hold; van Herk/Gil-Werman applies only to the flat
//! core.
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
//! 4 passes (2 for [`ElementShape::Square`]). A pass reaching `k ≤ 24`
//! samples costs O(k · cells) vector steps (about 0.3 ns per cell and step
//! on one core); a longer one O(cells) with two deque sweeps (every sample
//! pushed and popped at most once per sweep, about 7 ns per cell), its
//! columns and diagonals gathered 16 lines at a time so that each cache line
//! is fetched once. No allocation (the buffers live in the grid).
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

/// Lines gathered together by the column and diagonal passes: 16 samples
/// fill one 64-byte cache line.
const BLOCK: usize = 16;

/// Largest reach (samples) for which a pass runs by levels, O(reach) cheap
/// vector steps per cell; beyond it the O(1)-per-cell deque sweeps win.
const LEVEL_MAX: usize = 24;

/// Largest offset `k` (samples) at which the profile is still above 0.
fn reach(p: Profile) -> usize {
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

/// `m = max(m, src)` element-wise, written so that it vectorises.
#[inline]
fn max_into(m: &mut [f32], src: &[f32]) {
    for (a, &v) in m.iter_mut().zip(src) {
        *a = if v > *a { v } else { *a };
    }
}

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
        if !px.is_identity() {
            if reach(px) <= LEVEL_MAX {
                self.level_pass(px, 1, 0);
            } else {
                self.row_pass(px);
            }
        }
        if !py.is_identity() {
            if reach(py) <= LEVEL_MAX {
                self.level_pass(py, 0, 1);
            } else {
                self.skew_pass(py, 0);
            }
        }
        if diag && !pd.is_identity() {
            if reach(pd) <= LEVEL_MAX {
                self.level_pass(pd, 1, 1);
                self.level_pass(pd, -1, 1);
            } else {
                self.skew_pass(pd, 1); // diagonals (+1, +1)
                self.skew_pass(pd, -1); // anti-diagonals (−1, +1)
            }
        }
    }

    /// One 1-D pass along direction `(dx, dy)` by levels (see the module
    /// docs): for each output row, `m` grows to the running maximum of `G`
    /// over offsets `−k..=k` along the direction, and the output is
    /// `max_k min(m_k, B(k))`. Every step is an element-wise max/min over
    /// whole rows, so every lane is independent and the loops vectorise. The
    /// result goes to the scratch plane, which then becomes the plane.
    fn level_pass(&mut self, p: Profile, dx: isize, dy: isize) {
        let (nx, ny) = (self.nx, self.ny);
        let k_max = reach(p).min(nx.max(ny));
        let FuzzyGrid {
            h,
            scratch,
            line,
            line_out,
            ..
        } = self;
        let m = &mut line[..nx];
        let acc = &mut line_out[..nx];
        for j in 0..ny {
            let row = &h[j * nx..(j + 1) * nx];
            m.copy_from_slice(row);
            acc.copy_from_slice(row);
            for k in 1..=k_max {
                let b = p.at(k as f32);
                let mut any = false;
                for sign in [1isize, -1] {
                    let r = j as isize + sign * dy * k as isize;
                    if r < 0 || r >= ny as isize {
                        continue;
                    }
                    // Sample column c + shift for output column c, inside the grid.
                    let shift = sign * dx * k as isize;
                    let lo = (-shift).max(0) as usize;
                    let hi = (nx as isize - shift).clamp(0, nx as isize) as usize;
                    if lo >= hi {
                        continue;
                    }
                    any = true;
                    let src_lo = (r as usize * nx) as isize + lo as isize + shift;
                    let src = &h[src_lo as usize..src_lo as usize + (hi - lo)];
                    max_into(&mut m[lo..hi], src);
                }
                if !any {
                    break; // no cell further along either: nothing left to add
                }
                // Branch-free max/min (`f32::max`'s NaN rule blocks SIMD).
                for (a, &v) in acc.iter_mut().zip(m.iter()) {
                    let t = if v < b { v } else { b };
                    *a = if t > *a { t } else { *a };
                }
            }
            scratch[j * nx..(j + 1) * nx].copy_from_slice(acc);
        }
        std::mem::swap(h, scratch);
    }

    /// The x pass: rows are contiguous, so each is dilated in place through
    /// the line buffer.
    fn row_pass(&mut self, p: Profile) {
        let nx = self.nx;
        if nx < 2 {
            return;
        }
        for row in self.h.chunks_exact_mut(nx) {
            let out = &mut self.line_out[..nx];
            dilate_line(row, out, p, &mut self.deque);
            row.copy_from_slice(out);
        }
    }

    /// The column (`s = 0`), diagonal (`s = 1`) or anti-diagonal (`s = −1`)
    /// pass. Line `d` holds the cells `(d + s·j, j)`, so at any row the lines
    /// `d, d+1, …` sit in adjacent columns: lines are gathered [`BLOCK`] at a
    /// time row by row (one cache line serves the whole block) into the
    /// scratch plane, where each is contiguous, dilated there, and scattered
    /// back the same way. Strided per-line gathers would instead touch a new
    /// cache line for every sample.
    fn skew_pass(&mut self, p: Profile, s: isize) {
        let (nx, ny) = (self.nx as isize, self.ny as isize);
        if ny < 2 {
            return;
        }
        let block = (BLOCK as isize).min(nx);
        // Range of line numbers d with at least one cell.
        let (d_lo, d_hi) = match s {
            0 => (0, nx),
            1 => (1 - ny, nx),
            _ => (0, nx + ny - 1),
        };
        // Rows [j0, j1) of line d, i.e. those with 0 ≤ d + s·j < nx.
        let rows = |d: isize| -> (isize, isize) {
            match s {
                0 => (0, ny),
                1 => ((-d).max(0), (nx - d).min(ny)),
                _ => ((d - nx + 1).max(0), (d + 1).min(ny)),
            }
        };
        let stride = self.ny;
        let mut d0 = d_lo;
        while d0 < d_hi {
            let d1 = (d0 + block).min(d_hi);
            // Rows touched by any line of the block.
            let (mut j_lo, mut j_hi) = (ny, 0);
            for d in d0..d1 {
                let (a, b) = rows(d);
                j_lo = j_lo.min(a);
                j_hi = j_hi.max(b);
            }
            for j in j_lo..j_hi {
                // Lanes of this block present on row j: columns d + s·j in [0, nx).
                let c0 = d0 + s * j;
                let l_lo = (-c0).max(0);
                let l_hi = (nx - c0).min(d1 - d0);
                // Signed until offset: `c0` is negative left of the grid.
                let base = j * nx + c0;
                for l in l_lo..l_hi {
                    self.scratch[l as usize * stride + j as usize] = self.h[(base + l) as usize];
                }
            }
            for d in d0..d1 {
                let (a, b) = rows(d);
                if b - a < 2 {
                    continue;
                }
                let off = (d - d0) as usize * stride;
                let (a, b) = (off + a as usize, off + b as usize);
                let len = b - a;
                dilate_line(
                    &self.scratch[a..b],
                    &mut self.line_out[..len],
                    p,
                    &mut self.deque,
                );
                self.scratch[a..b].copy_from_slice(&self.line_out[..len]);
            }
            for j in j_lo..j_hi {
                let c0 = d0 + s * j;
                let l_lo = (-c0).max(0);
                let l_hi = (nx - c0).min(d1 - d0);
                let base = j * nx + c0;
                for l in l_lo..l_hi {
                    self.h[(base + l) as usize] = self.scratch[l as usize * stride + j as usize];
                }
            }
            d0 = d1;
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

    /// The level passes (short reach) and the deque passes (long reach)
    /// are two evaluations of the same 1-D dilations: they must agree on
    /// every line, border lines included.
    #[test]
    fn level_and_deque_passes_agree() {
        use crate::grid::GridConfig;
        let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 2.3, 1.7]).unwrap();
        let mut seed = 12345u32;
        for v in g.possibilities_mut() {
            seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12_345);
            *v = (seed >> 8) as f32 / (1u32 << 24) as f32;
        }
        for p in [
            Profile {
                core: 0.0,
                flank: 2.5,
            },
            Profile {
                core: 1.3,
                flank: 0.0,
            },
            Profile {
                core: 0.7,
                flank: 4.2,
            },
            Profile {
                core: 3.0,
                flank: 9.0,
            },
        ] {
            for (dx, dy, s) in [
                (1, 0, None),
                (0, 1, Some(0)),
                (1, 1, Some(1)),
                (-1, 1, Some(-1)),
            ] {
                let (mut a, mut b) = (g.clone(), g.clone());
                a.level_pass(p, dx, dy);
                match s {
                    None => b.row_pass(p),
                    Some(s) => b.skew_pass(p, s),
                }
                for (x, y) in a.possibilities().iter().zip(b.possibilities()) {
                    assert!((x - y).abs() < 1e-6, "{p:?} ({dx},{dy}): {x} vs {y}");
                }
            }
        }
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
