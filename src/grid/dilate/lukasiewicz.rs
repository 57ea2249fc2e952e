//! Dilation under the Łukasiewicz t-norm, `(G ⊕ B)(p) = sup_q max(0, G(q) + B(p − q) − 1)`,
//! by paper 000's trapezoid element (flat core `c`, flank `s`, bias `b`): a cost per cell that
//! does not depend on the radius.
//!
//! # Why it splits
//!
//! With `B(v) = max(b, 1 − dist(v, C)/s)` (`C` the flat core, `dist` the distance to it, so the
//! flank falls from 1 on `C` to 0 at distance `s`), `G(q) + B(v) − 1` is the larger of
//! `G(q) + b − 1` and `G(q) − dist(v, C)/s`, and the supremum over `q` splits into:
//!
//! 1. the global floor `max g + b − 1`;
//! 2. `sup_q G(q) − dist(p − q, C)/s`. Since `dist(v, C) = inf_{c ∈ C} ‖v − c‖`, this is a flat
//!    dilation of `G` by `C` followed by a max-plus dilation by the cone `−‖v‖/s`.
//!
//! (The term `G(q) − 1` of a cell outside the support is ≤ 0 and the final `max(0, ·)` drops
//! it.) Every piece is exact, so the split is exact; `tests.rs` checks it against the definition
//! evaluated by brute force.
//!
//! # The pieces on the grid
//!
//! * The flat core is the Minkowski sum of four segments (rows, columns and, for the octagon,
//!   both diagonals) of the same integer half widths as the sup-min element's core; each
//!   segment's flat dilation is a running maximum built by doubling (`⌈log₂(m + 1)⌉` in-place
//!   sweeps each way; the core is small, a tenth of the distance travelled by default).
//! * The cone's norm is the chamfer norm whose steps cost `1/s_x`, `1/s_y` along rows and
//!   columns and `√2·2/(s_x + s_y)` along a diagonal (octagon; `2/(s_x + s_y)` for the square,
//!   whose cone is then Chebyshev's). Its unit ball is the octagon with its vertices on the
//!   axes and diagonals (inscribed in the disc of radius `s`, within 8 % of it, where the
//!   sup-min element's octagon is circumscribed). A max-plus dilation by such a cone is four
//!   1-D ones, one per step direction, and each 1-D one is a forward and a backward sweep
//!   `u ← max(u, u_prev − step)`: O(1) per cell at any radius. The diagonal cost is raised to
//!   at least the axis costs, so that a shortest path is monotone in both coordinates and stays
//!   in the grid: the passes then give the exact supremum over the grid's cells.
//! * Columns and diagonals sweep whole rows at a time (vector code); rows sweep eight rows side
//!   by side, so that eight independent chains hide the latency of the serial recurrence.
//!
//! Near the border the flat core's segments only see cells of the grid (as the sup-min
//! passes' do); the cone is exact up to the border.
//!
//! # Complexity
//!
//! O(cells) for the cone (eight sweeps) and O(cells · log core) for the core, whatever the
//! flank; no allocation, no workspace.

use super::super::ElementShape;
use std::f32::consts::SQRT_2;

/// Radii of an element in cells: flat core and flank along x and y.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Radii {
    /// Flat core (apothem, cells) along x and y.
    pub core: [f32; 2],
    /// Flank (cells) along x and y.
    pub flank: [f32; 2],
}

/// The discrete element the passes apply: integer half widths of the core's segments and the
/// step costs of the cone (`∞` when the flank is 0: a crisp element).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Steps {
    /// Half widths (samples) of the core along rows, columns, each diagonal.
    pub half: [usize; 3],
    /// Cost of one step along a row, a column, a diagonal.
    pub cost: [f32; 3],
}

/// The element's segments and step costs for `element` with radii in cells.
pub(crate) fn steps(element: ElementShape, r: Radii) -> Steps {
    let clean = |v: f32| if v.is_finite() { v.max(0.0) } else { 0.0 };
    let (cx, cy) = (clean(r.core[0]), clean(r.core[1]));
    let (fx, fy) = (clean(r.flank[0]), clean(r.flank[1]));
    let (k, diag_core, diag_len) = match element {
        ElementShape::Octagon => {
            let k = 1.0 / (1.0 + SQRT_2);
            (k, 0.5 * (cx + cy) * k / SQRT_2, SQRT_2)
        }
        ElementShape::Square => (1.0, 0.0, 1.0),
    };
    let whole = |v: f32| v.min(1e6).floor() as usize;
    let rate = |f: f32| if f > 0.0 { 1.0 / f } else { f32::INFINITY };
    let (ax, ay) = (rate(fx), rate(fy));
    let ad = (diag_len * rate(0.5 * (fx + fy))).max(ax).max(ay);
    Steps {
        half: [whole(cx * k), whole(cy * k), whole(diag_core)],
        cost: [ax, ay, ad],
    }
}

/// Dilates the plane `h` (`nx × ny`, row-major) in place by the element of `steps` with
/// element bias `bias`, under the Łukasiewicz t-norm (module docs).
pub(crate) fn dilate(h: &mut [f32], (nx, ny): (usize, usize), steps: Steps, bias: f32) {
    if nx == 0 || ny == 0 || h.len() != nx * ny {
        return;
    }
    let mut top = 0.0f32;
    for v in h.iter_mut() {
        // Values in [0, 1], NaN to 0 (as the sup-min passes assume).
        let c = if *v < 1.0 { *v } else { 1.0 };
        *v = if *v >= 0.0 { c } else { 0.0 };
        top = top.max(*v);
    }
    let [mx, my, md] = steps.half;
    flat_rows(h, nx, mx);
    flat_lines(h, nx, 0, my);
    flat_lines(h, nx, 1, md);
    flat_lines(h, nx, -1, md);
    let [ax, ay, ad] = steps.cost;
    cone_rows(h, nx, ax);
    cone_lines(h, nx, 0, ay);
    cone_lines(h, nx, 1, ad);
    cone_lines(h, nx, -1, ad);
    let floor = if bias.is_finite() {
        top + bias.clamp(0.0, 1.0) - 1.0
    } else {
        0.0
    };
    if floor > 0.0 {
        for v in h.iter_mut() {
            *v = v.max(floor);
        }
    }
}

/// Shifts of the doubling sweeps that turn a value into the maximum over `m` more samples:
/// after sweeps of `s₁, s₂, …` a sample covers `1 + s₁ + s₂ + …` samples.
fn doubling(m: usize) -> impl Iterator<Item = usize> {
    let mut cover = 1usize;
    std::iter::from_fn(move || {
        (cover <= m).then(|| {
            let s = cover.min(m + 1 - cover);
            cover += s;
            s
        })
    })
}

/// Flat dilation of every row by the segment `[−m, m]`.
fn flat_rows(h: &mut [f32], nx: usize, m: usize) {
    if m == 0 {
        return;
    }
    for row in h.chunks_exact_mut(nx) {
        for s in doubling(m) {
            if s >= nx {
                break;
            }
            // Ahead: row[x] = max(row[x..=x+span]); ascending x reads unchanged samples.
            for x in 0..nx - s {
                row[x] = row[x].max(row[x + s]);
            }
        }
        for s in doubling(m) {
            if s >= nx {
                break;
            }
            for x in (s..nx).rev() {
                row[x] = row[x].max(row[x - s]);
            }
        }
    }
}

/// Flat dilation along the lines of step `(dx, 1)` (columns for `dx = 0`, diagonals for ±1) by
/// `[−m, m]` steps, one whole row at a time.
fn flat_lines(h: &mut [f32], nx: usize, dx: isize, m: usize) {
    let ny = h.len() / nx;
    if m == 0 {
        return;
    }
    for s in doubling(m) {
        if s >= ny {
            break;
        }
        // Ahead: row y takes row y + s shifted by s·dx, read before it changes.
        for y in 0..ny - s {
            let (head, tail) = h.split_at_mut((y + s) * nx);
            max_shifted(&mut head[y * nx..], &tail[..nx], dx * s as isize, f32::max);
        }
    }
    for s in doubling(m) {
        if s >= ny {
            break;
        }
        for y in (s..ny).rev() {
            let (head, tail) = h.split_at_mut(y * nx);
            max_shifted(
                &mut tail[..nx],
                &head[(y - s) * nx..(y - s + 1) * nx],
                -dx * s as isize,
                f32::max,
            );
        }
    }
}

/// `dst[x] = f(dst[x], src[x + shift])` where `x + shift` is in the row.
#[inline(always)]
fn max_shifted(dst: &mut [f32], src: &[f32], shift: isize, f: impl Fn(f32, f32) -> f32) {
    let n = src.len();
    let sh = shift.unsigned_abs().min(n);
    if shift >= 0 {
        for (d, s) in dst[..n - sh].iter_mut().zip(&src[sh..]) {
            *d = f(*d, *s);
        }
    } else {
        for (d, s) in dst[sh..n].iter_mut().zip(&src[..n - sh]) {
            *d = f(*d, *s);
        }
    }
}

/// Max-plus dilation along the lines of step `(dx, 1)` by the 1-D cone of `cost` per step: a
/// forward and a backward sweep of whole rows.
fn cone_lines(h: &mut [f32], nx: usize, dx: isize, cost: f32) {
    let ny = h.len() / nx;
    if !cost.is_finite() || ny < 2 {
        return;
    }
    let step = |d: f32, s: f32| d.max(s - cost);
    for y in 1..ny {
        let (head, tail) = h.split_at_mut(y * nx);
        // Row y from row y − 1, one step of (dx, 1) back: src at x − dx.
        max_shifted(&mut tail[..nx], &head[(y - 1) * nx..], -dx, step);
    }
    for y in (0..ny - 1).rev() {
        let (head, tail) = h.split_at_mut((y + 1) * nx);
        max_shifted(&mut head[y * nx..], &tail[..nx], dx, step);
    }
}

/// Rows swept side by side in [`cone_rows`].
const BAND: usize = 8;

/// Max-plus dilation of every row by the 1-D cone of `cost` per step. The recurrence is serial
/// along a row, so [`BAND`] rows advance together.
fn cone_rows(h: &mut [f32], nx: usize, cost: f32) {
    if !cost.is_finite() || nx < 2 {
        return;
    }
    for band in h.chunks_mut(nx * BAND) {
        let rows = band.len() / nx;
        let mut run = [0.0f32; BAND];
        for (r, v) in run.iter_mut().enumerate().take(rows) {
            *v = band[r * nx];
        }
        for x in 1..nx {
            for (r, v) in run.iter_mut().enumerate().take(rows) {
                let cell = &mut band[r * nx + x];
                *v = cell.max(*v - cost);
                *cell = *v;
            }
        }
        for (r, v) in run.iter_mut().enumerate().take(rows) {
            *v = band[r * nx + nx - 1];
        }
        for x in (0..nx - 1).rev() {
            for (r, v) in run.iter_mut().enumerate().take(rows) {
                let cell = &mut band[r * nx + x];
                *v = cell.max(*v - cost);
                *cell = *v;
            }
        }
    }
}
