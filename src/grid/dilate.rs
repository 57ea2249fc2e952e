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
//! # The same pass by offsets, in blocks that stop early
//!
//! For offsets `k = 0, 1, …` the element's profile `B(k)` falls, so
//! `out(x) = max_k min(max(g(x − k), g(x + k)), B(k))` (the brute-force
//! definition, offset by offset; only min and max, so the same floats as the
//! deque's definition up to its flank rounding, and as the running-maximum
//! form `max_k min(M_k, B(k))` of the previous code exactly). Along any of
//! the four directions the neighbours of 16 adjacent cells of a row at
//! offset `k` are 16 adjacent cells of another row, shifted, so a block of
//! 16 cells (four SSE2 vectors) takes each offset in a dozen vector
//! instructions, lane by lane.
//!
//! Three exact shortcuts make the work follow the belief rather than the
//! radius:
//!
//! * **A block stops early.** With `u` an upper bound on every value within
//!   reach of the block, every term at offset `k' ≥ k` is at most
//!   `min(B(k), u)`; once every lane holds that much, no later offset can
//!   raise one. A block on a plateau or at its window's maximum stops before
//!   the first offset, one beside a peak once it has met it (offset = its
//!   distance to it).
//! * **A group is left alone.** The plane is tiled in groups of 8 rows × 16
//!   columns with their maxima and minima. A group whose minimum reaches the
//!   largest maximum within reach keeps every value (each cell is already
//!   the maximum within its reach) and is not visited: on a belief mostly
//!   at the floor, most of the plane. The extrema are measured once per
//!   dilation and kept up to date pass by pass, for the groups worked on.
//! * **A flat group takes its window maxima.** When every value within
//!   reach of a group is at most the element's lowest level `B(K)`, each
//!   term is `min(M_k, B(k)) = M_k` (`M_k` the maximum within `k` samples),
//!   so every cell becomes its window maximum `M_K`: van Herk / Gil–Werman
//!   along columns and diagonals (suffix maxima a chunk of `2K + 1` rows at
//!   a time, in the scratch plane after the ring; prefix maxima one row
//!   ahead),
//!   doubling widths along rows; O(1) per cell whatever `K`. Used when the
//!   reach is at least 4 samples (below, the offsets are cheaper) and at
//!   least a quarter of the groups are flat (else the plane is not worth
//!   computing): low noise everywhere, the worst case of the two shortcuts
//!   above, so costs the same at every radius. A row of groups all flat is
//!   written as whole rows, without the blocks' bookkeeping.
//!
//! Cost: O(cells) for the extrema (and the window maxima, when used), then
//! per block the offsets it needs — at most the reach `K` (≤ `LEVEL_MAX` =
//! 24 samples; longer passes run by deques). On a concentrated belief
//! nearly flat in the radius, on low noise flat; in the worst remaining case
//! (values that differ within reach and reach above `B(K)`: rings, flanks)
//! a block runs up to every offset, O(K · cells).
//!
//! No exact O(1)-per-cell vector form is known to us for that case: the
//! flank makes each sample's contribution a trapezoid whose flat width
//! depends on its own value (`min(g, 1 − d/R)` is flat while `1 − d/R ≥
//! g`), so the element is not a translation-invariant max-plus one and the
//! two-pass distance-transform recurrence does not hold; van Herk/Gil-Werman
//! applies where the flank cannot act (the flat groups above) and to the
//! flat core.
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

use super::cells::{fmax, fmin};
use super::{ElementShape, FuzzyGrid};
use std::f32::consts::{PI, SQRT_2};

/// Lines gathered together by the column and diagonal passes: 16 samples
/// fill one 64-byte cache line.
const BLOCK: usize = 16;

/// Largest reach (samples) for which a pass runs by offsets, at most that
/// many vector steps per block; beyond it the O(1)-per-cell deque sweeps
/// bound the worst case.
const LEVEL_MAX: usize = 24;

/// Length of the line buffer a row of `nx` cells needs in the offset pass:
/// whole blocks and [`LEVEL_MAX`] zeros on either side.
pub(crate) fn padded_row(nx: usize) -> usize {
    nx.div_ceil(LANES) * LANES + 2 * LEVEL_MAX
}

/// Length of the block-bound buffer of an `nx × ny` grid: three values
/// (maximum, minimum, bound) per 16-column chunk of every group of
/// [`GROUP`] rows.
pub(crate) fn chunk_len(nx: usize, ny: usize) -> usize {
    3 * nx.div_ceil(LANES) * ny.div_ceil(GROUP)
}

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

/// Cells per block of the offset passes: four SSE2 vectors, one 64-byte
/// cache line; a block's exit test is one branch for all of them.
const LANES: usize = 16;

/// Four lanes: the operations on it are written lane by lane on
/// `[f32; 4]`, the shape LLVM turns into one SSE2 instruction each.
type V = [f32; 4];

/// One block of lanes, as four vectors.
type Block = [V; 4];

/// A block outside the grid.
const ZERO: Block = [[0.0; 4]; 4];

/// Band rows per group of the band passes' block bounds.
const GROUP: usize = 8;

/// The element's levels `b[k] = B(k)` for `k = 0..=K`, `K` the reach capped
/// at `cap − 1` (offsets beyond a line's length reach no cell), on the
/// stack; returns them and `K` (≤ [`LEVEL_MAX`]).
fn levels(p: Profile, cap: usize) -> ([f32; LEVEL_MAX + 1], usize) {
    let k = reach(p).min(cap.saturating_sub(1)).min(LEVEL_MAX);
    let mut b = [0.0; LEVEL_MAX + 1];
    for (i, v) in b.iter_mut().enumerate().take(k + 1) {
        *v = p.at(i as f32);
    }
    (b, k)
}

#[inline(always)]
fn vmax(a: V, b: V) -> V {
    [
        fmax(a[0], b[0]),
        fmax(a[1], b[1]),
        fmax(a[2], b[2]),
        fmax(a[3], b[3]),
    ]
}

#[inline(always)]
fn vmin(a: V, b: V) -> V {
    [
        fmin(a[0], b[0]),
        fmin(a[1], b[1]),
        fmin(a[2], b[2]),
        fmin(a[3], b[3]),
    ]
}

/// The block of `v` starting at `at`.
#[inline(always)]
fn load(v: &[f32], at: usize) -> Block {
    let s: &[f32; LANES] = v[at..at + LANES]
        .try_into()
        .expect("a slice of LANES values");
    let q = |i: usize| [s[4 * i], s[4 * i + 1], s[4 * i + 2], s[4 * i + 3]];
    [q(0), q(1), q(2), q(3)]
}

/// Writes the first `n` lanes of `acc` to `v[at..]` (fewer than 16 through
/// a copy, so that the lanes are never picked one by one: that made the
/// compiler keep every block in scalars).
#[inline(always)]
fn store(v: &mut [f32], at: usize, acc: &Block, n: usize) {
    let mut tmp = [0.0f32; LANES];
    let d: &mut [f32; LANES] = if n == LANES {
        (&mut v[at..at + LANES])
            .try_into()
            .expect("a slice of LANES values")
    } else {
        &mut tmp
    };
    for i in 0..4 {
        d[4 * i..4 * i + 4].copy_from_slice(&acc[i]);
    }
    if n < LANES {
        v[at..at + n].copy_from_slice(&tmp[..n]);
    }
}

/// The 16 cells of `row` from column `c` on, zeros outside the row (a
/// whole block inside it is one load per vector; any other goes through a
/// zeroed copy, so both are vector loads).
#[inline(always)]
fn fetch(row: &[f32], c: isize) -> Block {
    let nx = row.len() as isize;
    if c >= 0 && c + LANES as isize <= nx {
        return load(row, c as usize);
    }
    let mut tmp = [0.0f32; LANES];
    let lo = (-c).clamp(0, LANES as isize);
    let hi = (nx - c).clamp(lo, LANES as isize);
    if lo < hi {
        tmp[lo as usize..hi as usize].copy_from_slice(&row[(c + lo) as usize..(c + hi) as usize]);
    }
    load(&tmp, 0)
}

/// True when every lane of a block is at least `lim`: three vector
/// minima, one compare, one mask test (the lane-wise `&` of four compares
/// is the form LLVM turns into `cmpps` + `movmskps`).
#[inline(always)]
fn all_at_least(c: &Block, lim: f32) -> bool {
    let m = vmin(vmin(c[0], c[1]), vmin(c[2], c[3]));
    (m[0] >= lim) & (m[1] >= lim) & (m[2] >= lim) & (m[3] >= lim)
}

/// First columns of the blocks of a row of `nx` cells: whole blocks from 0,
/// and when `nx` is not a multiple of 16 a last one ending at `nx`, which
/// overlaps the one before (its cells get the same values twice: every
/// pass reads one buffer and writes another, or a copy of the row), so that
/// no block but that of a row shorter than 16 cells is partial.
fn block_starts(nx: usize) -> impl Iterator<Item = usize> {
    let tail = (nx % LANES != 0).then(|| nx.saturating_sub(LANES));
    (0..nx / LANES).map(|q| q * LANES).chain(tail)
}

/// Maxima and minima of the 16-column chunks `q_lo..q_hi` of `rows` (a
/// group: whole rows of `nx` cells) into `gmax`, `gmin` (one value per
/// chunk of the row): down the rows into `buf` first, in loops over slices
/// (the form the compiler vectorises cleanly), then across each chunk.
fn group_extrema(
    rows: &[f32],
    nx: usize,
    (q_lo, q_hi): (usize, usize),
    gmax: &mut [f32],
    gmin: &mut [f32],
    buf: &mut [f32],
) {
    let (c_lo, c_hi) = (q_lo * LANES, (q_hi * LANES).min(nx));
    let buf = &mut buf[c_lo..c_hi];
    let mut lines = rows.chunks_exact(nx).map(|r| &r[c_lo..c_hi]);
    let Some(first) = lines.next() else { return };
    buf.copy_from_slice(first);
    for line in lines.clone() {
        for (m, &v) in buf.iter_mut().zip(line) {
            *m = fmax(*m, v);
        }
    }
    for (m, ch) in gmax[q_lo..q_hi].iter_mut().zip(buf.chunks(LANES)) {
        *m = ch.iter().fold(0.0, |a, &v| fmax(a, v));
    }
    buf.copy_from_slice(first);
    for line in lines {
        for (m, &v) in buf.iter_mut().zip(line) {
            *m = fmin(*m, v);
        }
    }
    for (m, ch) in gmin[q_lo..q_hi].iter_mut().zip(buf.chunks(LANES)) {
        *m = ch.iter().fold(f32::INFINITY, |a, &v| fmin(a, v));
    }
}

/// One offset pass over a block (see the module docs): `acc` holds the
/// block's own values and leaves with `max_k min(max(up_k, down_k), b[k])`
/// over `k < b.len()`, where `ring(k)` gives the blocks `k` samples up and
/// down the line and `u` bounds every value within reach of the block.
///
/// Offsets stop as soon as every lane holds at least `min(b[k], u)`: every
/// later term `min(ring, b[k'])` is at most that (`b` falls, no value
/// exceeds `u`), so it could not raise a lane, and the result is exactly
/// that of all offsets. A block on a plateau (or at its window's maximum)
/// stops before the first offset, one near a peak once it has met it.
#[inline(always)]
fn run_block(acc: &mut Block, u: f32, b: &[f32], ring: impl Fn(usize) -> (Block, Block)) {
    for (k, &bk) in b.iter().enumerate().skip(1) {
        if all_at_least(acc, fmin(bk, u)) {
            return;
        }
        let (up, dn) = ring(k);
        let bv = [bk; 4];
        for i in 0..4 {
            acc[i] = vmax(acc[i], vmin(vmax(up[i], dn[i]), bv));
        }
    }
}

/// Columns of padding on either side of the window-maximum rows: a line
/// within reach of the grid stays within [`LEVEL_MAX`] columns of it.
const PAD: usize = LEVEL_MAX;

/// `cur[i] = max(cur[i], prev[i − dx])` where `i − dx` is a column of
/// `prev` (`dx` ∈ {−1, 0, 1}): one step along the lines `(dx, 1)`.
#[inline(always)]
fn max_shifted(cur: &mut [f32], prev: &[f32], dx: isize) {
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
fn padded(dst: &mut [f32], row: &[f32]) {
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
fn chunk_suffix<'a>(
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
fn line_prefix_step(row: &[f32], (w, dx): (usize, isize), r: usize, dst: &mut [f32], prev: &[f32]) {
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
fn window_max_row(
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

/// `v[at..at + 16] = max(v[at..at + 16], v[from..from + 16])`, both blocks
/// loaded before the store.
#[inline(always)]
fn max_into(v: &mut [f32], at: usize, from: usize) {
    let (x, y) = (load(v, at), load(v, from));
    let mut r = [[0.0; 4]; 4];
    for q in 0..4 {
        r[q] = vmax(x[q], y[q]);
    }
    store(v, at, &r, LANES);
}

/// The window maxima of a padded row `lp` (the row at `kmax`, zeros
/// around), reach `kmax`: `out[c] = max lp[c ..= c + 2·kmax]` for the
/// `n` first columns (a whole number of blocks), by doubling widths in
/// blocks (`out` needs [`LANES`] values of slack past `lp`'s length).
///
/// # Complexity
///
/// O(`lp.len()` · log `kmax`).
fn window_max_padded(lp: &[f32], kmax: usize, n: usize, out: &mut [f32]) {
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
const EXACT_REACH: usize = 4;

/// Share of a pass's group-chunks that must be worked on before exact
/// window maxima pay: they cost about three sweeps over the plane, which a
/// pass leaving most groups alone does not spend on its blocks.
const EXACT_SHARE: usize = 4;

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
        // (Selects, the same values as `v.min(1.0)` with NaN to 0: `f32::min`'s
        // NaN rule kept this loop scalar.)
        for v in self.h.iter_mut() {
            let c = if *v < 1.0 { *v } else { 1.0 };
            *v = if *v >= 0.0 { c } else { 0.0 };
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
        // The 1-D passes: (profile, direction, line length capping the reach).
        let (nx, ny) = (self.nx, self.ny);
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
                    self.measure_extrema();
                }
                let (b, k) = levels(p, cap);
                let next = passes.get(i + 1).copied().flatten();
                extrema = next.is_some_and(|(q, ..)| by_offsets(q));
                self.offset_pass(&b[..=k], (dx, dy), extrema, true);
            } else {
                match dy {
                    0 => self.row_pass(p),
                    _ => self.skew_pass(p, dx),
                }
                extrema = false;
            }
        }
    }

    /// The extrema of every group-chunk of the plane ([`group_extrema`]),
    /// which [`FuzzyGrid::offset_pass`] starts from.
    fn measure_extrema(&mut self) {
        let (nx, q_n) = (self.nx, self.nx.div_ceil(LANES));
        let n = self.ny.div_ceil(GROUP) * q_n;
        let (gmax, rest) = self.cm.split_at_mut(n);
        let gmin = &mut rest[..n];
        for (g, rows) in self.h.chunks(GROUP * nx).enumerate() {
            let at = g * q_n;
            group_extrema(
                rows,
                nx,
                (0, q_n),
                &mut gmax[at..at + q_n],
                &mut gmin[at..at + q_n],
                &mut self.line_out,
            );
        }
    }

    /// One 1-D pass by offsets (see the module docs) along `(dx, dy)`: the
    /// rows (`(1, 0)`), the columns (`(0, 1)`), the diagonals (`(1, 1)`)
    /// or the anti-diagonals (`(−1, 1)`). The neighbours of cell `(c, j)`
    /// at offset `k` are `(c ∓ dx·k, j ∓ dy·k)`, so the blocks of row `j`
    /// (16 adjacent cells) meet their neighbours as 16 adjacent cells of
    /// rows `j ∓ dy·k`, shifted by `∓ dx·k`: every lane is a line and every
    /// step is lane-wise.
    ///
    /// In place. `cm` holds the extrema of every group of [`GROUP`] rows ×
    /// 16 columns ([`group_extrema`]); each group's bound is the largest
    /// maximum within reach of any of its cells. A group whose minimum
    /// reaches its bound is left alone (every cell is the maximum within
    /// its reach, so it keeps its value): on a belief mostly at the floor,
    /// most of the plane. Other blocks run [`run_block`] with their group's
    /// bound, and the extrema of their groups are measured again for the
    /// next pass. Along rows, each row worth working on is copied first
    /// between `K` zeros (the line buffer), so that every offset reads
    /// inside the copy. Along columns and diagonals, each row that a block
    /// may read is copied before it changes into a ring of the last `K + 1`
    /// rows (the scratch plane: `K < ny`), which serves the row itself and
    /// its neighbours above; those below are still untouched. A neighbour
    /// block crossing the grid's side is fetched with zeros outside
    /// ([`fetch`]).
    ///
    /// Blocks of groups whose bound is at most the element's lowest level
    /// take their window maxima instead ([`window_max_padded`] along rows,
    /// [`window_max_row`] otherwise), when the reach is at least
    /// [`EXACT_REACH`], enough groups are such, and `maxima_ok` (tests turn
    /// it off to compare both ways bit for bit).
    fn offset_pass(
        &mut self,
        b: &[f32],
        (dx, dy): (isize, isize),
        keep_extrema: bool,
        maxima_ok: bool,
    ) {
        let (nx, ny) = (self.nx, self.ny);
        let kmax = b.len() - 1;
        if kmax == 0 {
            return;
        }
        let q_n = nx.div_ceil(LANES);
        let g_n = ny.div_ceil(GROUP);
        let FuzzyGrid {
            h,
            scratch,
            line,
            line_out,
            cm,
            ..
        } = self;
        let (gmax, rest) = cm.split_at_mut(g_n * q_n);
        let (gmin, rest) = rest.split_at_mut(g_n * q_n);
        // Each group-chunk's bound, negative when it is left alone.
        let ub = &mut rest[..g_n * q_n];
        let (reach_r, reach_c) = (dy as usize * kmax, dx.unsigned_abs() * kmax);
        for g in 0..g_n {
            let g_lo = (g * GROUP).saturating_sub(reach_r) / GROUP;
            let g_hi = ((g + 1) * GROUP - 1 + reach_r).min(ny - 1) / GROUP;
            for q in 0..q_n {
                let q_lo = (q * LANES).saturating_sub(reach_c) / LANES;
                let q_hi = ((q + 1) * LANES - 1 + reach_c).min(nx - 1) / LANES;
                let mut u = 0.0f32;
                for gg in g_lo..=g_hi {
                    for &v in &gmax[gg * q_n + q_lo..=gg * q_n + q_hi] {
                        u = fmax(u, v);
                    }
                }
                let i = g * q_n + q;
                ub[i] = if gmin[i] >= u { -1.0 } else { u };
            }
        }
        let group_active = |g: usize| ub[g * q_n..(g + 1) * q_n].iter().any(|&u| u >= 0.0);
        // Group-chunks whose every value within reach is at most the
        // element's lowest level: each of their cells becomes its window
        // maximum (every term is `min(M_k, b[k]) = M_k`, the largest `M_K`),
        // computed in O(1) per cell. Worth their sweeps when they are many.
        let low = b[kmax];
        let flat = |u: f32| u >= 0.0 && u <= low;
        // Their buffers: a row of maxima in `line_out`; for columns and
        // diagonals, after the ring in the scratch plane, a chunk of suffix
        // maxima and two rows of prefix maxima (padded rows), when they fit.
        let (slots, pw, w) = (kmax + 1, nx + 2 * PAD, 2 * kmax + 1);
        let fits = dy == 0 || slots * nx + (w + 2) * pw <= scratch.len();
        let exact = maxima_ok
            && fits
            && kmax >= EXACT_REACH
            && EXACT_SHARE * ub.iter().filter(|&&u| flat(u)).count() >= ub.len();
        let mrow = &mut line_out[..];
        // A group row whose every chunk is flat: its rows are their window
        // maxima, cell for cell what the blocks would store, without the
        // per-block bounds, loads and stores.
        let all_flat = |g: usize| exact && ub[g * q_n..(g + 1) * q_n].iter().all(|&u| flat(u));
        // A block's bound, or None when both its chunks are left alone.
        let bound = |j: usize, c0: usize| {
            let at = (j / GROUP) * q_n;
            let (qa, qb) = (at + c0 / LANES, at + (c0 + LANES - 1).min(nx - 1) / LANES);
            let u = fmax(ub[qa], ub[qb]);
            (u >= 0.0).then_some(u)
        };
        if dy == 0 {
            let lp = &mut line[..nx.div_ceil(LANES) * LANES + 2 * kmax];
            lp.fill(0.0);
            for (j, row) in h.chunks_exact_mut(nx).enumerate() {
                if !group_active(j / GROUP) {
                    continue;
                }
                if all_flat(j / GROUP) {
                    // Every block takes its window maxima: the row at once.
                    lp[kmax..kmax + nx].copy_from_slice(row);
                    window_max_padded(lp, kmax, nx.div_ceil(LANES) * LANES, mrow);
                    row.copy_from_slice(&mrow[..nx]);
                    continue;
                }
                let (mut copied, mut maxima) = (false, false);
                for c0 in block_starts(nx) {
                    let Some(u) = bound(j, c0) else { continue };
                    if !copied {
                        lp[kmax..kmax + nx].copy_from_slice(row);
                        copied = true;
                    }
                    let acc = if exact && flat(u) {
                        if !maxima {
                            window_max_padded(lp, kmax, nx.div_ceil(LANES) * LANES, mrow);
                            maxima = true;
                        }
                        load(mrow, c0)
                    } else {
                        let x = kmax + c0; // the block's first cell in `lp`
                        let mut acc = load(lp, x);
                        run_block(&mut acc, u, b, |k| (load(lp, x - k), load(lp, x + k)));
                        acc
                    };
                    store(row, c0, &acc, LANES.min(nx - c0));
                }
            }
        } else {
            let (ring, rest) = scratch.split_at_mut(slots * nx);
            let stride = nx as isize + dx; // one step along the line, in the plane
                                           // The suffix maxima of the chunk of row j − K, and the prefix
                                           // maxima of row min(j + K, ny − 1) (`p_now`) and the one before.
            let (sp, rows) = rest.split_at_mut(if exact { w * pw } else { 0 });
            let rows = &mut rows[..if exact { 2 * pw } else { 0 }];
            let (mut p_now, mut p_old) = rows.split_at_mut(rows.len() / 2);
            let wk = (w, dx);
            if exact {
                for r in 0..=kmax.min(ny - 1) {
                    line_prefix_step(&h[r * nx..(r + 1) * nx], wk, r, p_old, p_now);
                    std::mem::swap(&mut p_now, &mut p_old);
                }
            }
            for j in 0..ny {
                // Row j is read by blocks of rows j..=j + kmax (and by the
                // window maxima of rows j..=j + 2K, which need every row).
                let (g, g_last) = (j / GROUP, (j + kmax).min(ny - 1) / GROUP);
                if !exact && !(g..=g_last).any(group_active) {
                    continue;
                }
                let slot = (j % slots) * nx;
                ring[slot..slot + nx].copy_from_slice(&h[j * nx..(j + 1) * nx]);
                if exact {
                    // Rows below j are untouched yet: row j + K's prefix
                    // maxima follow from the row before's.
                    if j > 0 && j + kmax < ny {
                        let r = j + kmax;
                        line_prefix_step(&h[r * nx..(r + 1) * nx], wk, r, p_old, p_now);
                        std::mem::swap(&mut p_now, &mut p_old);
                    }
                    // Row j − K starts a chunk: its suffix maxima, from the
                    // rows' values before this pass (rows up to j in the
                    // ring, the others untouched in the plane).
                    if j >= kmax && (j - kmax) % w == 0 {
                        let ring = &*ring;
                        let h = &*h;
                        let row = |r: usize| {
                            if r <= j {
                                &ring[(r % slots) * nx..(r % slots + 1) * nx]
                            } else {
                                &h[r * nx..(r + 1) * nx]
                            }
                        };
                        chunk_suffix(row, (nx, ny), wk, j - kmax, sp);
                    }
                }
                if !group_active(g) {
                    continue;
                }
                if all_flat(g) {
                    // Every block takes its window maxima: the row at once.
                    let row = &mut h[j * nx..(j + 1) * nx];
                    window_max_row(p_now, sp, (nx, ny), kmax, dx, j, row);
                    continue;
                }
                let mut maxima = false;
                let inner_row = j >= kmax && j + kmax < ny;
                // Offsets beyond both ends of the grid add nothing.
                let k_end = kmax.min(j.max(ny - 1 - j));
                // Where the rows above sit in the ring.
                let mut up_at = [0usize; LEVEL_MAX + 1];
                let mut slot_k = j % slots; // of row j − k, stepping back
                for at in up_at.iter_mut().take(kmax.min(j) + 1) {
                    *at = slot_k * nx;
                    slot_k = if slot_k == 0 { slots - 1 } else { slot_k - 1 };
                }
                let above = |k: usize| &ring[up_at[k]..up_at[k] + nx];
                for c0 in block_starts(nx) {
                    let Some(u) = bound(j, c0) else { continue };
                    let mut acc;
                    if exact && flat(u) {
                        if !maxima {
                            window_max_row(p_now, sp, (nx, ny), kmax, dx, j, mrow);
                            maxima = true;
                        }
                        acc = load(mrow, c0);
                    } else if inner_row && c0 >= reach_c && c0 + LANES + reach_c <= nx {
                        let at = j * nx + c0;
                        acc = load(ring, slot + c0);
                        run_block(&mut acc, u, b, |k| {
                            let up = (up_at[k] + c0) as isize - dx * k as isize;
                            (
                                load(ring, up as usize),
                                load(h, at + (k as isize * stride) as usize),
                            )
                        });
                    } else {
                        let c = c0 as isize;
                        acc = fetch(&ring[slot..slot + nx], c);
                        run_block(&mut acc, u, &b[..=k_end], |k| {
                            let d = dx * k as isize;
                            let up = if j >= k { fetch(above(k), c - d) } else { ZERO };
                            let dn = if j + k < ny {
                                fetch(&h[(j + k) * nx..(j + k + 1) * nx], c + d)
                            } else {
                                ZERO
                            };
                            (up, dn)
                        });
                    }
                    store(&mut h[j * nx..(j + 1) * nx], c0, &acc, LANES.min(nx - c0));
                }
            }
        }
        if !keep_extrema {
            return;
        }
        let worked = ub.iter().filter(|&&u| u >= 0.0).count();
        // For a next offset pass. Every output is at most its group's bound
        // and at least its input (dilation is extensive): when most of the
        // plane was worked on, those bounds stand for the extrema (measuring
        // would cost about as much as the pass, and would rarely let a
        // group be left alone); otherwise the group-chunks worked on are
        // measured again (a row's overlapping last block also rewrites
        // cells of the chunk before, with the values they had: that chunk's
        // cells were each the maximum within reach).
        if 2 * worked > ub.len() {
            for (mx, &u) in gmax.iter_mut().zip(ub.iter()) {
                if u >= 0.0 {
                    *mx = u;
                }
            }
            return;
        }
        for g in 0..g_n {
            let ubg = &ub[g * q_n..(g + 1) * q_n];
            let Some(q_lo) = ubg.iter().position(|&u| u >= 0.0) else {
                continue;
            };
            let q_hi = q_n - ubg.iter().rev().position(|&u| u >= 0.0).unwrap_or(0);
            let rows = &h[g * GROUP * nx..((g + 1) * GROUP).min(ny) * nx];
            let at = g * q_n;
            group_extrema(
                rows,
                nx,
                (q_lo, q_hi),
                &mut gmax[at..at + q_n],
                &mut gmin[at..at + q_n],
                line_out,
            );
        }
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
impl FuzzyGrid {
    /// [`FuzzyGrid::dilate_xy`] with every pass by deques: the reference
    /// the offset passes are tested against.
    fn dilate_by_deques(&mut self, core: [f32; 2], flank: [f32; 2]) {
        let cells = |v: f32| v.max(0.0) / self.cell;
        let (k, diag) = match self.cfg.element {
            ElementShape::Octagon => (1.0 / (1.0 + SQRT_2), true),
            ElementShape::Square => (1.0, false),
        };
        let px = Profile {
            core: cells(core[0]) * k,
            flank: cells(flank[0]) * k,
        };
        let py = Profile {
            core: cells(core[1]) * k,
            flank: cells(flank[1]) * k,
        };
        let pd = Profile {
            core: 0.5 * (px.core + py.core) / SQRT_2,
            flank: 0.5 * (px.flank + py.flank) / SQRT_2,
        };
        for v in self.h.iter_mut() {
            *v = v.clamp(0.0, 1.0);
        }
        self.row_pass(px);
        self.skew_pass(py, 0);
        if diag {
            self.skew_pass(pd, 1);
            self.skew_pass(pd, -1);
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

    /// The offset passes (short reach) and the deque passes (long reach)
    /// are two evaluations of the same 1-D dilations: they must agree on
    /// every line, border lines included, on random values and on plateaus
    /// with spikes (where blocks stop early, at different offsets).
    #[test]
    fn offset_and_deque_passes_agree() {
        use crate::grid::GridConfig;
        let mut rnd = crate::grid::test_rng(12345u32);
        for (w, h) in [(2.3, 1.7), (0.7, 3.1), (4.1, 0.3)] {
            let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, w, h]).unwrap();
            for pattern in 0..3 {
                for v in g.possibilities_mut() {
                    let r = rnd();
                    *v = match pattern {
                        0 => r,
                        1 => 0.03 * r,
                        _ if r < 0.03 => 1.0,
                        _ if r < 0.1 => 0.4,
                        _ => 0.02,
                    };
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
                    Profile {
                        core: 0.0,
                        flank: 24.9,
                    },
                ] {
                    for s in [None, Some(0), Some(1), Some(-1)] {
                        let (mut a, mut b) = (g.clone(), g.clone());
                        let cap = match s {
                            None => g.nx(),
                            Some(0) => g.ny(),
                            _ => g.nx().min(g.ny()),
                        };
                        let (lv, k) = levels(p, cap);
                        match s {
                            None => {
                                {
                                    a.measure_extrema();
                                    a.offset_pass(&lv[..=k], (1, 0), false, true);
                                }
                                b.row_pass(p);
                            }
                            Some(s) => {
                                {
                                    a.measure_extrema();
                                    a.offset_pass(&lv[..=k], (s, 1), false, true);
                                }
                                b.skew_pass(p, s);
                            }
                        }
                        for (x, y) in a.possibilities().iter().zip(b.possibilities()) {
                            assert!((x - y).abs() < 1e-6, "{p:?} {s:?}: {x} vs {y}");
                        }
                    }
                }
            }
        }
    }

    /// Window maxima (flat groups) against the offsets on the same
    /// blocks, bit for bit: low noise (every group flat), noise with a few
    /// peaks (flat groups beside others), along all four directions, reaches
    /// from below [`EXACT_REACH`] to [`LEVEL_MAX`], grids narrower than a
    /// block and shorter than a window.
    #[test]
    fn window_maxima_match_the_offsets_bit_for_bit() {
        use crate::grid::GridConfig;
        let mut rnd = crate::grid::test_rng(777u32);
        for (w, h) in [(20.0, 30.0), (3.3, 1.2), (1.1, 4.0), (6.4, 2.5)] {
            let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, w, h]).unwrap();
            for pattern in 0..2 {
                for v in g.possibilities_mut() {
                    let r = rnd();
                    *v = match pattern {
                        0 => 0.01 * r,
                        _ if r < 0.001 => 1.0,
                        _ => 0.01 * r,
                    };
                }
                for flank in [3.5f32, 5.0, 9.0, 14.0, 40.0] {
                    let p = Profile { core: 0.0, flank };
                    for (dx, dy) in [(1, 0), (0, 1), (1, 1), (-1, 1)] {
                        let cap = match (dx, dy) {
                            (_, 0) => g.nx(),
                            (0, _) => g.ny(),
                            _ => g.nx().min(g.ny()),
                        };
                        let (lv, k) = levels(p, cap);
                        let (mut a, mut b) = (g.clone(), g.clone());
                        a.measure_extrema();
                        a.offset_pass(&lv[..=k], (dx, dy), false, true);
                        b.measure_extrema();
                        b.offset_pass(&lv[..=k], (dx, dy), false, false);
                        for (i, (x, y)) in
                            a.possibilities().iter().zip(b.possibilities()).enumerate()
                        {
                            assert!(
                                x.to_bits() == y.to_bits(),
                                "{w}×{h} pattern {pattern} flank {flank} ({dx}, {dy}) cell {i}: {x} vs {y}"
                            );
                        }
                    }
                }
            }
        }
    }

    /// Whole dilations (every pass, the group extrema carried from pass to
    /// pass, groups left alone) against the same 1-D elements applied by
    /// the deque passes alone, borders included, on beliefs where groups
    /// are left alone, where blocks stop early and where none do, with
    /// anisotropic elements and both shapes.
    #[test]
    fn whole_dilations_match_the_deque_passes() {
        use crate::grid::GridConfig;
        let mut rnd = crate::grid::test_rng(4242u32);
        for element in [ElementShape::Octagon, ElementShape::Square] {
            for (w, h) in [(12.0, 10.3), (5.3, 4.1), (1.3, 2.9), (2.0, 0.9)] {
                let cfg = GridConfig {
                    element,
                    ..GridConfig::default()
                };
                let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, w, h]).unwrap();
                for pattern in 0..6 {
                    for v in g.possibilities_mut() {
                        let r = rnd();
                        *v = match pattern {
                            0 => r,
                            1 => 0.03 * r,
                            // A few peaks on the floor: most groups left alone.
                            2 if r < 0.002 => 1.0,
                            2 if r < 0.005 => 0.3,
                            2 => 1e-8,
                            3 if r < 0.2 => 0.2 + 0.8 * r,
                            3 => 0.016,
                            4 => 0.9 + 0.1 * r,
                            // Groups whose minimum is just under their bound.
                            _ if r < 0.03 => 0.504,
                            _ => 0.5,
                        };
                    }
                    for (core, flank) in [
                        ([0.0, 0.0], [0.3, 0.3]),
                        ([0.05, 0.0], [1.0, 0.4]),
                        ([0.2, 0.3], [2.5, 2.5]),
                        ([0.0, 0.1], [0.0, 3.0]),
                    ] {
                        let mut a = g.clone();
                        a.dilate_xy(core, flank);
                        let mut b = g.clone();
                        b.dilate_by_deques(core, flank);
                        for (i, (x, y)) in
                            a.possibilities().iter().zip(b.possibilities()).enumerate()
                        {
                            assert!(
                                (x - y).abs() < 1e-6,
                                "{element:?} {w}×{h} pattern {pattern} {core:?} {flank:?} cell {i}: {x} vs {y}"
                            );
                        }
                    }
                }
            }
        }
    }

    /// A lone peak next to a chunk edge on a floor: its rise into the next
    /// chunk must reach the next passes' bounds (the extrema they measure
    /// again), or the groups around would be left alone wrongly.
    #[test]
    fn lone_peaks_spread_across_chunk_edges() {
        use crate::grid::GridConfig;
        for element in [ElementShape::Octagon, ElementShape::Square] {
            let cfg = GridConfig {
                element,
                ..GridConfig::default()
            };
            lone_peaks(FuzzyGrid::new(cfg, [0.0, 0.0, 12.0, 10.3]).unwrap());
        }
    }

    fn lone_peaks(mut g: FuzzyGrid) {
        for (c, r) in [(14usize, 20usize), (47, 63), (80, 7), (112, 95)] {
            g.possibilities_mut().fill(1e-8);
            let nx = g.nx();
            g.possibilities_mut()[r * nx + c] = 1.0;
            for flank in [0.6, 1.0, 2.0, 3.0] {
                let mut a = g.clone();
                a.dilate(0.0, flank);
                let mut b = g.clone();
                b.dilate_by_deques([0.0; 2], [flank; 2]);
                for (i, (x, y)) in a.possibilities().iter().zip(b.possibilities()).enumerate() {
                    assert!(
                        (x - y).abs() < 1e-6,
                        "peak ({c}, {r}) flank {flank} cell {i}: {x} vs {y}"
                    );
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
