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
//! * The cone's column and diagonal steps are one sweep up the rows and one down, whole rows at
//!   a time (vector code); its row steps are taken on each row while the sweep up holds it, by
//!   doubling (`⌈log₂(K + 1)⌉` vector sweeps of the row each way, `K < s` the reach in cells),
//!   since the recurrence along a row is serial.
//!
//! Near the border the flat core's segments only see cells of the grid (as the sup-min
//! passes' do); the cone is exact up to the border.
//!
//! # Complexity
//!
//! O(cells) for the cone's column and diagonal steps (two sweeps of the plane), O(cells · log K)
//! for its row steps on rows held in cache, and O(cells · log core) for the core; no
//! allocation (one line of scratch space).

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
///
/// `line` is scratch space of at least `nx` values.
pub(crate) fn dilate(
    h: &mut [f32],
    (nx, ny): (usize, usize),
    steps: Steps,
    bias: f32,
    line: &mut [f32],
) {
    if nx == 0 || ny == 0 || h.len() != nx * ny || line.len() < nx {
        return;
    }
    // Values in [0, 1], NaN to 0 (as the sup-min passes assume): here when a flat core comes
    // first, else row by row in the cone's first sweep, while the row is in cache.
    let flat = steps.half != [0, 0, 0];
    if flat {
        h.iter_mut().for_each(|v| *v = unit(*v));
    }
    let [hx, my, md] = steps.half;
    flat_rows(h, nx, hx, line);
    flat_lines(h, nx, 0, my);
    flat_lines(h, nx, 1, md);
    flat_lines(h, nx, -1, md);
    cone(h, nx, steps.cost, line, !flat);
    if bias.is_nan() || bias <= 0.0 {
        return; // no floor (also for a NaN bias)
    }
    // Both dilations keep the plane's maximum (every value is some cell's minus a cost ≥ 0,
    // and each cell keeps its own), so the input's `max g` is the output's.
    let top = max_of(h);
    let floor = top + bias.min(1.0) - 1.0;
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

/// Flat dilation of every row by the segment `[−m, m]`, by doubling both ways, each sweep out
/// of place through `line`.
fn flat_rows(h: &mut [f32], nx: usize, m: usize, line: &mut [f32]) {
    if m == 0 {
        return;
    }
    for row in h.chunks_exact_mut(nx) {
        for s in doubling(m) {
            if s >= nx {
                break;
            }
            line[..nx].copy_from_slice(row);
            for (r, &l) in row[s..].iter_mut().zip(&line[..nx - s]) {
                *r = mx(*r, l);
            }
            for (r, &l) in row[..nx - s].iter_mut().zip(&line[s..nx]) {
                *r = mx(*r, l);
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
                mx,
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

/// Largest value of the plane (values in [0, 1]), in eight lanes so that it vectorizes.
fn max_of(h: &[f32]) -> f32 {
    let mut lanes = [0.0f32; 8];
    let mut chunks = h.chunks_exact(8);
    for chunk in &mut chunks {
        for (t, &v) in lanes.iter_mut().zip(chunk) {
            *t = mx(*t, v);
        }
    }
    let rest = chunks.remainder().iter().fold(0.0f32, |a, &b| mx(a, b));
    lanes.iter().fold(rest, |a, &b| mx(a, b))
}

/// `v` clamped to [0, 1], NaN to 0, by selects.
#[inline(always)]
fn unit(v: f32) -> f32 {
    let c = if v < 1.0 { v } else { 1.0 };
    if v >= 0.0 {
        c
    } else {
        0.0
    }
}

/// Larger of two values known not to be NaN: a plain select, which vectorizes to one
/// instruction (`f32::max`'s NaN rule costs three).
#[inline(always)]
fn mx(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// Largest number of steps at which a cone of `cost` per step still leaves a value of at most
/// 1 above 0 (0 when one step already takes it all).
fn cone_reach(cost: f32) -> usize {
    if !cost.is_finite() || cost <= 0.0 {
        return 0;
    }
    // k·cost < 1, counted from the float bound back so that it agrees with the sweeps' own
    // arithmetic.
    let mut k = (1.0 / cost).min(1e6).ceil() as usize;
    while k > 0 && (k as f32) * cost >= 1.0 {
        k -= 1;
    }
    k
}

/// Max-plus dilation by the chamfer cone with step costs `[row, column, diagonal]`: one sweep
/// up the rows taking each row from the one before it (column and diagonal steps) and then
/// along itself (row steps, both ways), and one sweep down taking each row from the one after
/// it. Every shortest step sequence is one axis and one diagonal direction in the same octant
/// (the diagonal costs at least each axis step), which the two sweeps take in that order: the
/// result is exact.
///
/// With `clamp`, the sweep up first clamps each row to [0, 1] (NaN to 0).
fn cone(h: &mut [f32], nx: usize, [ax, ay, ad]: [f32; 3], line: &mut [f32], clamp: bool) {
    let ny = h.len() / nx;
    let reach_x = cone_reach(ax);
    let vertical = cone_reach(ay) > 0 || cone_reach(ad) > 0;
    for y in 0..ny {
        let (head, tail) = h.split_at_mut(y * nx);
        let row = &mut tail[..nx];
        if clamp {
            row.iter_mut().for_each(|v| *v = unit(*v));
        }
        if y > 0 && vertical {
            from_neighbour_row(row, &head[(y - 1) * nx..], ay, ad);
        }
        if reach_x > 0 {
            cone_row(row, ax, reach_x, &mut line[..nx]);
        }
    }
    if !vertical {
        return;
    }
    for y in (0..ny.saturating_sub(1)).rev() {
        let (head, tail) = h.split_at_mut((y + 1) * nx);
        from_neighbour_row(&mut head[y * nx..], &tail[..nx], ay, ad);
    }
}

/// `row[x] = max(row[x], near[x] − ay, near[x ± 1] − ad)`: one column or diagonal step from
/// the neighbouring row `near`.
fn from_neighbour_row(row: &mut [f32], near: &[f32], ay: f32, ad: f32) {
    let n = row.len();
    let ay = if ay.is_finite() { ay } else { 2.0 };
    let ad = if ad.is_finite() { ad } else { 2.0 };
    if n < 3 {
        for x in 0..n {
            let mut v = mx(row[x], near[x] - ay);
            if x > 0 {
                v = mx(v, near[x - 1] - ad);
            }
            if x + 1 < n {
                v = mx(v, near[x + 1] - ad);
            }
            row[x] = v;
        }
        return;
    }
    row[0] = mx(mx(row[0], near[0] - ay), near[1] - ad);
    row[n - 1] = mx(mx(row[n - 1], near[n - 1] - ay), near[n - 2] - ad);
    let mid = row[1..n - 1]
        .iter_mut()
        .zip(&near[1..n - 1])
        .zip(near[..n - 2].iter().zip(&near[2..n]));
    for ((r, &c), (&l, &rr)) in mid {
        *r = mx(mx(*r, c - ay), mx(l, rr) - ad);
    }
}

/// The 1-D cone along one row (both ways), reaching `reach` steps: sweeps by doubling,
/// `u[x] = max(u[x], u[x − s] − s·cost, u[x + s] − s·cost)`, `⌈log₂(reach + 1)⌉` of them, each
/// out of place (between `row` and `line`, in turn) so that it vectorizes.
fn cone_row(row: &mut [f32], cost: f32, reach: usize, line: &mut [f32]) {
    let n = row.len();
    let mut in_line = false;
    for s in doubling(reach) {
        if s >= n {
            break;
        }
        let drop = s as f32 * cost;
        let (src, dst): (&[f32], &mut [f32]) = if in_line {
            (&*line, &mut *row)
        } else {
            (&*row, &mut *line)
        };
        both_ways(src, dst, s, drop);
        in_line = !in_line;
    }
    if in_line {
        row.copy_from_slice(line);
    }
}

/// `dst[x] = max(src[x], src[x − s] − drop, src[x + s] − drop)` over the samples that exist.
#[inline(always)]
fn both_ways(src: &[f32], dst: &mut [f32], s: usize, drop: f32) {
    let n = src.len();
    // Ends: one neighbour only (or none when the row is shorter than 2s).
    for x in (0..s.min(n)).chain(n.saturating_sub(s).max(s)..n) {
        let mut v = src[x];
        if x >= s {
            v = mx(v, src[x - s] - drop);
        }
        if x + s < n {
            v = mx(v, src[x + s] - drop);
        }
        dst[x] = v;
    }
    if n > 2 * s {
        let mid = dst[s..n - s]
            .iter_mut()
            .zip(&src[s..n - s])
            .zip(src[..n - 2 * s].iter().zip(&src[2 * s..]));
        for ((d, &c), (&l, &r)) in mid {
            *d = mx(c, mx(l, r) - drop);
        }
    }
}
