//! The 16-lane blocks the offset and window-maximum passes are written in:
//! four `[f32; 4]` vectors, each operation written lane by lane in the shape
//! LLVM turns into one SSE2 instruction, with loads and stores that never
//! pick lanes one by one.
//!
//! # Complexity
//!
//! Every function is O(1) (16 lanes), except [`run_block`]: O(`b.len()`)
//! block steps at most, fewer when it stops early.

use super::super::cells::{fmax, fmin};
use super::LANES;

/// Four lanes: the operations on it are written lane by lane on
/// `[f32; 4]`, the shape LLVM turns into one SSE2 instruction each.
pub(super) type V = [f32; 4];

/// One block of lanes, as four vectors.
pub(super) type Block = [V; 4];

/// A block outside the grid.
pub(super) const ZERO: Block = [[0.0; 4]; 4];

#[inline(always)]
pub(super) fn vmax(a: V, b: V) -> V {
    [
        fmax(a[0], b[0]),
        fmax(a[1], b[1]),
        fmax(a[2], b[2]),
        fmax(a[3], b[3]),
    ]
}

#[inline(always)]
pub(super) fn vmin(a: V, b: V) -> V {
    [
        fmin(a[0], b[0]),
        fmin(a[1], b[1]),
        fmin(a[2], b[2]),
        fmin(a[3], b[3]),
    ]
}

/// The block of `v` starting at `at`.
#[inline(always)]
pub(super) fn load(v: &[f32], at: usize) -> Block {
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
pub(super) fn store(v: &mut [f32], at: usize, acc: &Block, n: usize) {
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
pub(super) fn fetch(row: &[f32], c: isize) -> Block {
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
pub(super) fn all_at_least(c: &Block, lim: f32) -> bool {
    let m = vmin(vmin(c[0], c[1]), vmin(c[2], c[3]));
    (m[0] >= lim) & (m[1] >= lim) & (m[2] >= lim) & (m[3] >= lim)
}

/// First columns of the blocks of a row of `nx` cells: whole blocks from 0,
/// and when `nx` is not a multiple of 16 a last one ending at `nx`, which
/// overlaps the one before (its cells get the same values twice: every
/// pass reads one buffer and writes another, or a copy of the row), so that
/// no block but that of a row shorter than 16 cells is partial.
pub(super) fn block_starts(nx: usize) -> impl Iterator<Item = usize> {
    let tail = (nx % LANES != 0).then(|| nx.saturating_sub(LANES));
    (0..nx / LANES).map(|q| q * LANES).chain(tail)
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
pub(super) fn run_block(
    acc: &mut Block,
    u: f32,
    b: &[f32],
    ring: impl Fn(usize) -> (Block, Block),
) {
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

/// `v[at..at + 16] = max(v[at..at + 16], v[from..from + 16])`, both blocks
/// loaded before the store.
#[inline(always)]
pub(super) fn max_into(v: &mut [f32], at: usize, from: usize) {
    let (x, y) = (load(v, at), load(v, from));
    let mut r = [[0.0; 4]; 4];
    for q in 0..4 {
        r[q] = vmax(x[q], y[q]);
    }
    store(v, at, &r, LANES);
}
