//! Window maxima (van Herk / Gil–Werman) for the offset pass's flat groups:
//! where every value within reach of a group is at most the element's lowest
//! level `B(K)`, each term `min(M_k, B(k))` is `M_k`, so every cell becomes
//! the maximum of its window of `2K + 1` samples. Along columns and
//! diagonals: suffix maxima a chunk of `2K + 1` rows at a time and prefix
//! maxima one row ahead ([`chunk_suffix`], [`line_prefix_step`],
//! [`window_max_row`]); along rows, doubling widths ([`window_max_padded`]).
//!
//! # Complexity
//!
//! O(1) per cell whatever `K` along columns and diagonals (three sweeps of
//! the plane); O(log K) per cell along rows, in 16-lane blocks.

use super::super::cells::fmax;
use super::block::max_into;
use super::{LANES, LEVEL_MAX};

/// Columns of padding on either side of the window-maximum rows: a line
/// within reach of the grid stays within [`LEVEL_MAX`] columns of it.
pub(super) const PAD: usize = LEVEL_MAX;

/// `cur[i] = max(cur[i], prev[i − dx])` where `i − dx` is a column of
/// `prev` (`dx` ∈ {−1, 0, 1}): one step along the lines `(dx, 1)`.
#[inline(always)]
pub(super) fn max_shifted(cur: &mut [f32], prev: &[f32], dx: isize) {
    let n = cur.len();
    let (c, p) = match dx {
        0 => (&mut cur[..], &prev[..n]),
        1 => (&mut cur[1..], &prev[..n - 1]),
        _ => (&mut cur[..n - 1], &prev[1..n]),
    };
    for (c, &p) in c.iter_mut().zip(p) {
        *c = fmax(*c, p);
    }
}

/// `row` between [`PAD`] zeros either side (`row.len() + 2·PAD` values).
#[inline(always)]
pub(super) fn padded(dst: &mut [f32], row: &[f32]) {
    let nx = row.len();
    dst[..PAD].fill(0.0);
    dst[PAD..PAD + nx].copy_from_slice(row);
    dst[PAD + nx..].fill(0.0);
}

/// Suffix maxima along the lines `(dx, 1)` of the chunk of `w` rows from
/// `c0` (van Herk / Gil–Werman), rows `row(r)` padded by [`PAD`] zeros
/// either side (`pw = nx + 2·PAD` values per row): row `r − c0` of `s`
/// holds, for each padded column, the maximum of its line from row `r` to
/// the chunk's last row (or the grid's). Each row is one vector step from
/// the one below.
///
/// # Complexity
///
/// O(pw · w).
pub(super) fn chunk_suffix<'a>(
    row: impl Fn(usize) -> &'a [f32],
    (nx, ny): (usize, usize),
    (w, dx): (usize, isize),
    c0: usize,
    s: &mut [f32],
) {
    let pw = nx + 2 * PAD;
    let end = (c0 + w).min(ny);
    for r in (c0..end).rev() {
        let (cur, next) = s.split_at_mut((r - c0 + 1) * pw);
        let cur = &mut cur[(r - c0) * pw..];
        padded(cur, row(r));
        if r + 1 < end {
            max_shifted(cur, &next[..pw], -dx);
        }
    }
}

/// The prefix maxima of row `r` (values `row`) along the lines `(dx, 1)`,
/// chunks of `w` rows, padded as in [`chunk_suffix`], into `dst`, from
/// those of row `r − 1` in `prev`: the maximum of each line from the first
/// row of `r`'s chunk to `r`.
#[inline]
pub(super) fn line_prefix_step(
    row: &[f32],
    (w, dx): (usize, isize),
    r: usize,
    dst: &mut [f32],
    prev: &[f32],
) {
    padded(dst, row);
    if r % w != 0 {
        max_shifted(dst, prev, dx);
    }
}

/// The window maxima of row `j` along the lines `(dx, 1)`, reach `k`
/// samples (`w = 2k + 1`), into `out[..nx]`: `max(s[a], p)` at the
/// window's ends `a = j − k` and `b = j + k` (clipped to the grid), `p` the
/// prefix maxima of row `b` ([`line_prefix_step`]) and `s` the suffix
/// maxima of `a`'s chunk ([`chunk_suffix`]); one of them when both ends
/// share a chunk (then `a` starts it, or `b` is the grid's last row).
pub(super) fn window_max_row(
    p: &[f32],
    s: &[f32],
    (nx, ny): (usize, usize),
    k: usize,
    dx: isize,
    j: usize,
    out: &mut [f32],
) {
    let (pw, w) = (nx + 2 * PAD, 2 * k + 1);
    let (a, b) = (j.saturating_sub(k), (j + k).min(ny - 1));
    // Where the line of column 0 of row j crosses row r, padded.
    let col = |r: usize| (PAD as isize + dx * (r as isize - j as isize)) as usize;
    let sa = &s[(a % w) * pw + col(a)..][..nx];
    let pb = &p[col(b)..][..nx];
    let out = &mut out[..nx];
    if a / w == b / w {
        out.copy_from_slice(if a % w == 0 { pb } else { sa });
    } else {
        for ((o, &x), &y) in out.iter_mut().zip(sa).zip(pb) {
            *o = fmax(x, y);
        }
    }
}

/// The window maxima of a padded row `lp` (the row at `kmax`, zeros
/// around), reach `kmax`: `out[c] = max lp[c ..= c + 2·kmax]` for the
/// `n` first columns (a whole number of blocks), by doubling widths in
/// blocks (`out` needs [`LANES`] values of slack past `lp`'s length).
///
/// # Complexity
///
/// O(`lp.len()` · log `kmax`).
pub(super) fn window_max_padded(lp: &[f32], kmax: usize, n: usize, out: &mut [f32]) {
    let len = lp.len();
    out[..len].copy_from_slice(lp);
    let wlen = 2 * kmax + 1;
    let mut w = 1;
    // `out[i]` holds max lp[i .. i + w] for every i ≤ len − w.
    while 2 * w <= wlen {
        let mut i = 0;
        while i + w < len {
            // The loads of a block come before its store, and later blocks
            // read only cells after it: in place is safe.
            max_into(out, i, i + w);
            i += LANES;
        }
        w *= 2;
    }
    let mut c = 0;
    while c < n {
        max_into(out, c, c + wlen - w);
        c += LANES;
    }
}

/// Smallest reach (samples) at which window maxima beat running the
/// offsets on flat groups (measured: at 2 the offsets are cheaper, at 4
/// the maxima).
pub(super) const EXACT_REACH: usize = 4;

/// Share of a pass's group-chunks that must be worked on before exact
/// window maxima pay: they cost about three sweeps over the plane, which a
/// pass leaving most groups alone does not spend on its blocks.
pub(super) const EXACT_SHARE: usize = 4;
