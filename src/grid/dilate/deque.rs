//! The 1-D dilation by monotone deques, and the row and skewed passes of the
//! plane built on it (the passes whose reach is beyond the offsets' limit,
//! and the reference the offset passes are tested against).
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
//! # Complexity
//!
//! O(n) per line of n samples whatever the profile (every sample pushed and
//! popped at most once per sweep, two sweeps): O(cells) per plane pass. The
//! column and diagonal passes gather [`BLOCK`] lines at a time so that each
//! cache line of the plane is fetched once.

use super::super::workspace::Workspace;
use super::Profile;

/// Lines gathered together by the column and diagonal passes: 16 samples
/// fill one 64-byte cache line.
const BLOCK: usize = 16;

/// Inverse flank used for a zero flank: lines fall off at once, without
/// producing `0 · ∞`.
const STEEP: f32 = 1e30;

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

/// The x pass: rows are contiguous, so each is dilated in place through
/// the line buffer.
pub(super) fn row_pass(h: &mut [f32], nx: usize, p: Profile, work: &mut Workspace) {
    if nx < 2 {
        return;
    }
    for row in h.chunks_exact_mut(nx) {
        let out = &mut work.line_out[..nx];
        dilate_line(row, out, p, &mut work.deque);
        row.copy_from_slice(out);
    }
}

/// Range of line numbers `d` with at least one cell, and the rows `[j0, j1)`
/// of line `d` (those with `0 ≤ d + s·j < nx`), for the skew `s`.
fn line_rows(
    s: isize,
    (nx, ny): (isize, isize),
) -> ((isize, isize), impl Fn(isize) -> (isize, isize)) {
    let span = match s {
        0 => (0, nx),
        1 => (1 - ny, nx),
        _ => (0, nx + ny - 1),
    };
    let rows = move |d: isize| -> (isize, isize) {
        match s {
            0 => (0, ny),
            1 => ((-d).max(0), (nx - d).min(ny)),
            _ => ((d - nx + 1).max(0), (d + 1).min(ny)),
        }
    };
    (span, rows)
}

/// The column (`s = 0`), diagonal (`s = 1`) or anti-diagonal (`s = −1`)
/// pass. Line `d` holds the cells `(d + s·j, j)`, so at any row the lines
/// `d, d+1, …` sit in adjacent columns: lines are gathered [`BLOCK`] at a
/// time row by row (one cache line serves the whole block) into the
/// workspace's plane, where each is contiguous, dilated there, and scattered
/// back the same way. Strided per-line gathers would instead touch a new
/// cache line for every sample.
pub(super) fn skew_pass(
    h: &mut [f32],
    (nx, ny): (usize, usize),
    p: Profile,
    s: isize,
    work: &mut Workspace,
) {
    let (nx, ny) = (nx as isize, ny as isize);
    if ny < 2 {
        return;
    }
    let block = (BLOCK as isize).min(nx);
    let ((d_lo, d_hi), rows) = line_rows(s, (nx, ny));
    let stride = ny as usize;
    let Workspace {
        plane: scratch,
        line_out,
        deque,
        ..
    } = work;
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
                scratch[l as usize * stride + j as usize] = h[(base + l) as usize];
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
            dilate_line(&scratch[a..b], &mut line_out[..len], p, deque);
            scratch[a..b].copy_from_slice(&line_out[..len]);
        }
        for j in j_lo..j_hi {
            let c0 = d0 + s * j;
            let l_lo = (-c0).max(0);
            let l_hi = (nx - c0).min(d1 - d0);
            let base = j * nx + c0;
            for l in l_lo..l_hi {
                h[(base + l) as usize] = scratch[l as usize * stride + j as usize];
            }
        }
        d0 = d1;
    }
}
