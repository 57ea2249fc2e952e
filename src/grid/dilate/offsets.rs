//! The 1-D pass by offsets, in vector blocks that stop early: the pass every
//! dilation of the usual, short reach runs (at most [`LEVEL_MAX`] samples).
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
//! # Complexity
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

use super::super::cells::{fmax, fmin};
use super::super::workspace::Workspace;
use super::block::{block_starts, fetch, load, run_block, store, ZERO};
use super::window::{
    chunk_suffix, line_prefix_step, window_max_padded, window_max_row, EXACT_REACH, EXACT_SHARE,
    PAD,
};
use super::{GROUP, LANES, LEVEL_MAX};

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

/// The extrema of every group-chunk of the plane ([`group_extrema`]),
/// which [`offset_pass`] starts from.
pub(super) fn measure_extrema(h: &[f32], (nx, ny): (usize, usize), work: &mut Workspace) {
    let q_n = nx.div_ceil(LANES);
    let n = ny.div_ceil(GROUP) * q_n;
    let (gmax, rest) = work.cm.split_at_mut(n);
    let gmin = &mut rest[..n];
    for (g, rows) in h.chunks(GROUP * nx).enumerate() {
        let at = g * q_n;
        group_extrema(
            rows,
            nx,
            (0, q_n),
            &mut gmax[at..at + q_n],
            &mut gmin[at..at + q_n],
            &mut work.line_out,
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
/// In place. The workspace's `cm` holds the extrema of every group of
/// [`GROUP`] rows × 16 columns ([`group_extrema`]); each group's bound is
/// the largest maximum within reach of any of its cells ([`group_bounds`]).
/// A group whose minimum reaches its bound is left alone (every cell is the
/// maximum within its reach, so it keeps its value): on a belief mostly at
/// the floor, most of the plane. Other blocks run [`run_block`] with their
/// group's bound ([`Pass::rows`], [`Pass::bands`]), and, when
/// `keep_extrema`, the extrema of their groups are measured again for the
/// next pass ([`refresh_extrema`]).
///
/// Blocks of groups whose bound is at most the element's lowest level
/// take their window maxima instead, when the reach is at least
/// [`EXACT_REACH`], enough groups are such, and `maxima_ok` (tests turn
/// it off to compare both ways bit for bit).
pub(super) fn offset_pass(
    h: &mut [f32],
    (nx, ny): (usize, usize),
    work: &mut Workspace,
    b: &[f32],
    (dx, dy): (isize, isize),
    (keep_extrema, maxima_ok): (bool, bool),
) {
    let kmax = b.len() - 1;
    if kmax == 0 {
        return;
    }
    let q_n = nx.div_ceil(LANES);
    let g_n = ny.div_ceil(GROUP);
    let Workspace {
        plane: scratch,
        line,
        line_out,
        cm,
        ..
    } = work;
    let (gmax, rest) = cm.split_at_mut(g_n * q_n);
    let (gmin, rest) = rest.split_at_mut(g_n * q_n);
    // Each group-chunk's bound, negative when it is left alone.
    let ub = &mut rest[..g_n * q_n];
    let (reach_r, reach_c) = (dy as usize * kmax, dx.unsigned_abs() * kmax);
    group_bounds(gmax, gmin, ub, (nx, ny), (reach_r, reach_c));
    // Group-chunks whose every value within reach is at most the
    // element's lowest level: each of their cells becomes its window
    // maximum (every term is `min(M_k, b[k]) = M_k`, the largest `M_K`),
    // computed in O(1) per cell. Worth their sweeps when they are many.
    // Their buffers: a row of maxima in `line_out`; for columns and
    // diagonals, after the ring in the scratch plane, a chunk of suffix
    // maxima and two rows of prefix maxima (padded rows), when they fit.
    let low = b[kmax];
    let (slots, pw, w) = (kmax + 1, nx + 2 * PAD, 2 * kmax + 1);
    let fits = dy == 0 || slots * nx + (w + 2) * pw <= scratch.len();
    let n_flat = ub.iter().filter(|&&u| u >= 0.0 && u <= low).count();
    let exact = maxima_ok && fits && kmax >= EXACT_REACH && EXACT_SHARE * n_flat >= ub.len();
    let pass = Pass {
        b,
        kmax,
        nx,
        ny,
        q_n,
        dx,
        reach_c,
        ub,
        low,
        exact,
    };
    if dy == 0 {
        pass.rows(h, line, line_out);
    } else {
        pass.bands(h, scratch, line_out);
    }
    if keep_extrema {
        refresh_extrema(&pass, h, gmax, gmin, line_out);
    }
}

/// Each group-chunk's bound into `ub`: the largest maximum within reach
/// (`reach_r` rows, `reach_c` columns) of any of its cells, or −1 when its
/// minimum reaches it (the chunk is left alone).
fn group_bounds(
    gmax: &[f32],
    gmin: &[f32],
    ub: &mut [f32],
    (nx, ny): (usize, usize),
    (reach_r, reach_c): (usize, usize),
) {
    let q_n = nx.div_ceil(LANES);
    for g in 0..ny.div_ceil(GROUP) {
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
}

/// One offset pass's plan: the element's levels, the plane's shape and every
/// group-chunk's bound (negative: left alone).
struct Pass<'a> {
    b: &'a [f32],
    kmax: usize,
    nx: usize,
    ny: usize,
    q_n: usize,
    dx: isize,
    reach_c: usize,
    ub: &'a [f32],
    /// The element's lowest level `b[kmax]`.
    low: f32,
    /// Flat groups take their window maxima.
    exact: bool,
}

impl Pass<'_> {
    /// Some chunk of group row `g` is worked on.
    #[inline(always)]
    fn group_active(&self, g: usize) -> bool {
        self.ub[g * self.q_n..(g + 1) * self.q_n]
            .iter()
            .any(|&u| u >= 0.0)
    }

    /// A chunk bound `u` is flat: worked on, and at most the lowest level.
    #[inline(always)]
    fn flat(&self, u: f32) -> bool {
        u >= 0.0 && u <= self.low
    }

    /// A group row whose every chunk is flat: its rows are their window
    /// maxima, cell for cell what the blocks would store, without the
    /// per-block bounds, loads and stores.
    #[inline(always)]
    fn all_flat(&self, g: usize) -> bool {
        self.exact
            && self.ub[g * self.q_n..(g + 1) * self.q_n]
                .iter()
                .all(|&u| self.flat(u))
    }

    /// A block's bound, or None when both its chunks are left alone.
    #[inline(always)]
    fn bound(&self, j: usize, c0: usize) -> Option<f32> {
        let at = (j / GROUP) * self.q_n;
        let (qa, qb) = (
            at + c0 / LANES,
            at + (c0 + LANES - 1).min(self.nx - 1) / LANES,
        );
        let u = fmax(self.ub[qa], self.ub[qb]);
        (u >= 0.0).then_some(u)
    }

    /// The pass along rows: each row worth working on is copied first
    /// between `K` zeros (the line buffer), so that every offset reads
    /// inside the copy; flat blocks take their window maxima
    /// ([`window_max_padded`]) into `mrow`.
    fn rows(&self, h: &mut [f32], line: &mut [f32], mrow: &mut [f32]) {
        let (nx, kmax, b) = (self.nx, self.kmax, self.b);
        let lp = &mut line[..nx.div_ceil(LANES) * LANES + 2 * kmax];
        lp.fill(0.0);
        for (j, row) in h.chunks_exact_mut(nx).enumerate() {
            if !self.group_active(j / GROUP) {
                continue;
            }
            if self.all_flat(j / GROUP) {
                // Every block takes its window maxima: the row at once.
                lp[kmax..kmax + nx].copy_from_slice(row);
                window_max_padded(lp, kmax, nx.div_ceil(LANES) * LANES, mrow);
                row.copy_from_slice(&mrow[..nx]);
                continue;
            }
            let (mut copied, mut maxima) = (false, false);
            for c0 in block_starts(nx) {
                let Some(u) = self.bound(j, c0) else { continue };
                if !copied {
                    lp[kmax..kmax + nx].copy_from_slice(row);
                    copied = true;
                }
                let acc = if self.exact && self.flat(u) {
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
    }

    /// The pass along columns or diagonals: each row that a block may read
    /// is copied before it changes into a ring of the last `K + 1` rows (the
    /// scratch plane: `K < ny`), which serves the row itself and its
    /// neighbours above; those below are still untouched. With window
    /// maxima, the scratch plane after the ring also holds the suffix maxima
    /// of the current chunk ([`chunk_suffix`]) and the prefix maxima of the
    /// row `K` below and the one before ([`line_prefix_step`]).
    fn bands(&self, h: &mut [f32], scratch: &mut [f32], mrow: &mut [f32]) {
        let (nx, ny, kmax, dx, exact) = (self.nx, self.ny, self.kmax, self.dx, self.exact);
        let (slots, pw, w) = (kmax + 1, nx + 2 * PAD, 2 * kmax + 1);
        let (ring, rest) = scratch.split_at_mut(slots * nx);
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
            if !exact && !(g..=g_last).any(|g| self.group_active(g)) {
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
                    let (ring, h) = (&*ring, &*h);
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
            if !self.group_active(g) {
                continue;
            }
            if self.all_flat(g) {
                // Every block takes its window maxima: the row at once.
                let row = &mut h[j * nx..(j + 1) * nx];
                window_max_row(p_now, sp, (nx, ny), kmax, dx, j, row);
                continue;
            }
            self.band_row(j, h, ring, (p_now, sp), mrow);
        }
    }

    /// The blocks of row `j` of a band pass: window maxima (from the prefix
    /// and suffix maxima `p_now`, `sp`) for flat ones, else the offsets,
    /// with plain loads in the interior and zero-padded fetches
    /// ([`fetch`]) where a neighbour block crosses the grid's side.
    fn band_row(
        &self,
        j: usize,
        h: &mut [f32],
        ring: &[f32],
        (p_now, sp): (&[f32], &[f32]),
        mrow: &mut [f32],
    ) {
        let (nx, ny, kmax, dx, b) = (self.nx, self.ny, self.kmax, self.dx, self.b);
        let slots = kmax + 1;
        let slot = (j % slots) * nx;
        let stride = nx as isize + dx; // one step along the line, in the plane
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
            let Some(u) = self.bound(j, c0) else { continue };
            let mut acc;
            if self.exact && self.flat(u) {
                if !maxima {
                    window_max_row(p_now, sp, (nx, ny), kmax, dx, j, mrow);
                    maxima = true;
                }
                acc = load(mrow, c0);
            } else if inner_row && c0 >= self.reach_c && c0 + LANES + self.reach_c <= nx {
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

/// The group extrema after a pass, for a next offset pass. Every output is
/// at most its group's bound and at least its input (dilation is
/// extensive): when most of the plane was worked on, those bounds stand for
/// the extrema (measuring would cost about as much as the pass, and would
/// rarely let a group be left alone); otherwise the group-chunks worked on
/// are measured again (a row's overlapping last block also rewrites cells
/// of the chunk before, with the values they had: that chunk's cells were
/// each the maximum within reach).
fn refresh_extrema(
    pass: &Pass<'_>,
    h: &[f32],
    gmax: &mut [f32],
    gmin: &mut [f32],
    line_out: &mut [f32],
) {
    let (nx, ny, q_n, ub) = (pass.nx, pass.ny, pass.q_n, pass.ub);
    let worked = ub.iter().filter(|&&u| u >= 0.0).count();
    if 2 * worked > ub.len() {
        for (mx, &u) in gmax.iter_mut().zip(ub.iter()) {
            if u >= 0.0 {
                *mx = u;
            }
        }
        return;
    }
    for g in 0..ny.div_ceil(GROUP) {
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
