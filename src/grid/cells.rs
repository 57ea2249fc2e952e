//! The grid itself: geometry (cell ↔ metric coordinates), the planes that
//! hold each cell's possibility and heading set, total ignorance, and the
//! bookkeeping shared by the update, prediction and estimate modules.
//!
//! Planes are flat `Vec<f32>` in row-major order (`index = row · nx + col`,
//! row 0 at `y_min`), so every pass is a linear sweep. The grid's state is
//! visible to the `grid` module only (the files that implement its update,
//! prediction and estimate); everything else goes through methods. Scratch
//! buffers live in a separate workspace (`grid/workspace.rs`), allocated once here
//! so that stepping allocates nothing.
//!
//! # Complexity
//!
//! Construction and [`FuzzyGrid::reset`] are O(cells); accessors are O(1).
//!
//! # Example
//!
//! ```
//! use lplace::grid::{FuzzyGrid, GridConfig};
//! let g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 3.0, 2.0]).unwrap();
//! assert_eq!((g.nx(), g.ny()), (30, 20));
//! assert!(g.possibilities().iter().all(|&h| h == 1.0)); // total ignorance
//! ```

use super::predict::{MotionTrace, Pending};
use super::workspace::Workspace;
use super::{GridConfig, GridError, Trapezoid};
use std::f32::consts::PI;

/// Largest number of cells a grid may have (about 1.5 GB of planes).
pub const MAX_CELLS: usize = 64 << 20;

/// The Fuzzy Position Grid of paper 000.
#[derive(Debug, Clone)]
pub struct FuzzyGrid {
    pub(super) cfg: GridConfig,
    pub(super) nx: usize,
    pub(super) ny: usize,
    /// Lower-left corner of the cell lattice: `corner`, plus the carried sub-cell
    /// displacement under [`Shift::Lattice`](super::Shift).
    pub(super) x0: f32,
    pub(super) y0: f32,
    /// Lower-left corner of the extent the grid was made for.
    pub(super) corner: [f32; 2],
    pub(super) cell: f32,
    /// Possibility plane `G(x, y)`.
    pub(super) h: Vec<f32>,
    /// Heading set of each cell, stored with height 1 (its height is `h`).
    pub(super) theta: Vec<f32>,
    pub(super) delta: Vec<f32>,
    pub(super) alpha: Vec<f32>,
    pub(super) bias: Vec<f32>,
    pub(super) pending: Pending,
    /// Sub-cell displacement carried per heading class under
    /// [`CellMotion::HeadingClasses`](super::CellMotion) (empty otherwise), metres along x, y.
    pub(super) class_rem: Vec<[f32; 2]>,
    /// Decisions of the last motion application (diagnostics only).
    pub(super) trace: MotionTrace,
    /// Height of the plane before the last normalisation.
    pub(super) last_height: f32,
    /// Scratch space of the passes: not part of the belief.
    pub(super) work: Workspace,
}

impl FuzzyGrid {
    /// A grid covering `bounds = [x_min, y_min, x_max, y_max]` (metres) in
    /// total ignorance. The extent is rounded up to whole cells.
    pub fn new(cfg: GridConfig, bounds: [f32; 4]) -> Result<Self, GridError> {
        cfg.validate()?;
        let [x_min, y_min, x_max, y_max] = bounds;
        if bounds.iter().any(|v| !v.is_finite()) || x_max <= x_min || y_max <= y_min {
            return Err(GridError::BadConfig {
                field: "bounds",
                reason: "need finite x_min < x_max, y_min < y_max",
            });
        }
        let nxf = ((x_max - x_min) / cfg.cell_size - 1e-4).ceil().max(1.0);
        let nyf = ((y_max - y_min) / cfg.cell_size - 1e-4).ceil().max(1.0);
        if nxf * nyf > MAX_CELLS as f32 {
            return Err(GridError::TooLarge {
                nx: nxf as usize,
                ny: nyf as usize,
                limit: MAX_CELLS,
            });
        }
        let (nx, ny) = (nxf as usize, nyf as usize);
        let n = nx * ny;
        let bins = super::classes::bins(&cfg);
        let mut g = FuzzyGrid {
            cell: cfg.cell_size,
            cfg,
            nx,
            ny,
            x0: x_min,
            y0: y_min,
            corner: [x_min, y_min],
            h: vec![1.0; n],
            theta: vec![0.0; n],
            delta: vec![2.0 * PI; n],
            alpha: vec![0.0; n],
            bias: vec![1.0; n],
            pending: Pending::default(),
            class_rem: vec![[0.0; 2]; bins],
            trace: MotionTrace::default(),
            last_height: 1.0,
            work: Workspace::for_grid(nx, ny),
        };
        g.reset();
        Ok(g)
    }

    /// Back to total ignorance: every cell possibility 1, every heading possible.
    pub fn reset(&mut self) {
        self.h.fill(1.0);
        self.theta.fill(0.0);
        self.delta.fill(2.0 * PI);
        self.alpha.fill(0.0);
        self.bias.fill(1.0);
        self.pending = Pending::default();
        self.class_rem.fill([0.0; 2]);
        self.place_lattice();
        self.trace = MotionTrace::default();
        self.last_height = 1.0;
    }

    /// The configuration in use.
    #[inline]
    pub fn config(&self) -> &GridConfig {
        &self.cfg
    }
    /// Number of columns (x direction).
    #[inline]
    pub fn nx(&self) -> usize {
        self.nx
    }
    /// Number of rows (y direction).
    #[inline]
    pub fn ny(&self) -> usize {
        self.ny
    }
    /// Cell side in metres.
    #[inline]
    pub fn cell_size(&self) -> f32 {
        self.cell
    }
    /// Lower-left corner `(x_min, y_min)` of the grid's cell lattice: the extent's corner, moved
    /// by under half a cell per axis under [`Shift::Lattice`](super::Shift).
    #[inline]
    pub fn origin(&self) -> (f32, f32) {
        (self.x0, self.y0)
    }
    /// The possibility plane, row-major (`row · nx + col`, row 0 at `y_min`).
    #[inline]
    pub fn possibilities(&self) -> &[f32] {
        &self.h
    }
    /// Mutable possibility plane, for callers that build priors. Values written
    /// outside [0, 1] (or NaN) are clamped (NaN → 0) by the next operation.
    #[inline]
    pub fn possibilities_mut(&mut self) -> &mut [f32] {
        &mut self.h
    }
    /// Height of the plane measured just before the last normalisation: 1 −
    /// this is the inconsistency of the last observation with the belief.
    pub fn last_height(&self) -> f32 {
        self.last_height
    }
    /// Centre of cell `(col, row)` in metres.
    #[inline]
    pub fn cell_center(&self, col: usize, row: usize) -> (f32, f32) {
        (
            self.x0 + (col as f32 + 0.5) * self.cell,
            self.y0 + (row as f32 + 0.5) * self.cell,
        )
    }
    /// The cell containing a metric point, if inside the grid.
    pub fn cell_of(&self, x: f32, y: f32) -> Option<(usize, usize)> {
        let c = ((x - self.x0) / self.cell).floor();
        let r = ((y - self.y0) / self.cell).floor();
        if c >= 0.0 && r >= 0.0 && (c as usize) < self.nx && (r as usize) < self.ny {
            Some((c as usize, r as usize))
        } else {
            None
        }
    }
    /// Possibility of cell `(col, row)` (0 outside the grid).
    #[inline]
    pub fn possibility(&self, col: usize, row: usize) -> f32 {
        if col < self.nx && row < self.ny {
            self.h[row * self.nx + col]
        } else {
            0.0
        }
    }
    /// Heading set of cell `(col, row)`, with the cell's possibility as height.
    #[inline]
    pub fn heading_set(&self, col: usize, row: usize) -> Option<Trapezoid> {
        if col < self.nx && row < self.ny {
            let i = row * self.nx + col;
            Some(Trapezoid::new(
                self.theta[i],
                self.delta[i],
                self.alpha[i],
                self.h[i],
                self.bias[i],
            ))
        } else {
            None
        }
    }
    /// Replaces the heading set of a cell (height ignored: it is the plane).
    #[inline]
    pub fn set_heading_set(&mut self, col: usize, row: usize, t: Trapezoid) {
        if col < self.nx && row < self.ny {
            let i = row * self.nx + col;
            self.theta[i] = t.center;
            self.delta[i] = t.shape.core;
            self.alpha[i] = t.shape.slope;
            self.bias[i] = t.shape.bias;
        }
    }

    /// After an update: flush tiny values, measure the height, rescale to
    /// height 1 when configured, and raise cells to the configured floor
    /// (forgetting their heading). A plane driven to 0 everywhere (possible only
    /// with zero biases) carries no information and restarts from ignorance.
    pub(crate) fn finish_update(&mut self) -> f32 {
        let raw = raw_max(&self.h);
        self.finish_update_from(raw)
    }

    /// [`FuzzyGrid::finish_update`] given `raw = raw_max(plane)`, which the
    /// update passes measure row by row while the row is in cache: flushing
    /// and clamping then happen in the same sweep as the normalisation, one
    /// sweep over the plane instead of two.
    pub(crate) fn finish_update_from(&mut self, raw: f32) -> f32 {
        let s = match self.settle_for(raw) {
            Ok(s) => s,
            Err(height) => return height,
        };
        let FuzzyGrid { h, bias, delta, .. } = self;
        s.settle_cells(h, bias, delta);
        self.last_height
    }

    /// The [`Settle`] of an update whose plane has the raw maximum `raw`
    /// ([`raw_max`]), and records the height. The height is the flushed and
    /// clamped maximum, `min(raw, 1)` if `raw ≥ flush`, else 0: the maximum of
    /// the flushed, clamped cells (NaN cells, never selected by [`raw_max`],
    /// are flushed to 0). `Err(height)` when there is nothing to settle: the
    /// plane was driven to 0 and has been reset (height 0).
    pub(crate) fn settle_for(&mut self, raw: f32) -> Result<Settle, f32> {
        let flush = self.cfg.flush_below;
        let max = if raw >= flush { raw.min(1.0) } else { 0.0 };
        self.last_height = max;
        if max <= 0.0 {
            let pending = self.pending;
            self.reset();
            self.pending = pending;
            self.place_lattice();
            self.last_height = 0.0;
            return Err(0.0);
        }
        let k = if self.cfg.normalize && max < 1.0 {
            1.0 / max
        } else {
            1.0
        };
        Ok(Settle::new(flush, k, self.cfg.floor))
    }
}

/// Cells per block of the settle passes' floor shortcut
/// ([`Settle::all_under_floor`]): four SSE2 vectors, one branch.
pub(crate) const SETTLE_BLOCK: usize = 16;

/// Cells per chunk of the settle passes: 64 blocks, one `u64` of marks for
/// [`Settle::floor_sets`].
pub(crate) const SETTLE_CHUNK: usize = 64 * SETTLE_BLOCK;

/// How an update leaves each cell, from its raw value (the plane combined
/// with the observation): flushed under `flush`, scaled by `k` (≥ 1, the
/// normalisation), clamped to 1, and kept at `floor`.
///
/// The floor shortcut tests `v ≤ low_max`: every raw value up to it ends
/// under the floor (flushed, or `v·k < floor`), and the threshold is as
/// large as the two conditions allow, so one comparison per cell replaces
/// three operations. `v·k` rounds monotonically in `v` (`k > 0`), so the
/// values under the floor are all those up to the largest `t` with `t·k <
/// floor`, found from `floor / k` a few ulps either way ([`last_true`]).
/// NaN fails the test and takes the full path, which flushes it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Settle {
    flush: f32,
    k: f32,
    /// 0 disables the floor ([`Settle::height`] is then the whole story).
    pub(crate) floor: f32,
    /// A raw value `v ≤ low_max` ends under the floor (see above).
    low_max: f32,
}

impl Settle {
    pub(crate) fn new(flush: f32, k: f32, floor: f32) -> Self {
        let by_flush = if flush > f32::NEG_INFINITY {
            next_down(flush) // `v < flush` is `v ≤ prev(flush)`
        } else {
            f32::NEG_INFINITY
        };
        let by_floor = last_true(floor / k, |t| t * k < floor);
        Settle {
            flush,
            k,
            floor,
            low_max: fmax(by_flush, by_floor),
        }
    }

    /// The normalised value of a raw cell value: 0 under `flush` (NaN too:
    /// it fails `>=`), else `min(raw · k, 1)`. That is `min(min(raw, 1) · k,
    /// 1)`, the clamp-then-scale of the definition, in fewer operations:
    /// the two agree for `raw < 1` and both give 1 above, since `k ≥ 1`.
    #[inline(always)]
    fn scaled(&self, raw: f32) -> f32 {
        let m = raw * self.k;
        let n = if m < 1.0 { m } else { 1.0 }; // f32::min's NaN rule blocks SIMD
        blend(raw >= self.flush, n, 0.0)
    }

    /// True when every cell of `raw` (a block of [`SETTLE_BLOCK`] raw
    /// values) ends under the floor, where [`Settle::cell`] gives `(floor,
    /// 1, 2π)` whatever the cell's heading set was: the block can take those
    /// three constants without its bias and Δ being read, and without the
    /// division (most of a converged grid, whose cells sit at the floor).
    #[inline(always)]
    pub(crate) fn all_under_floor(&self, raw: &[f32]) -> bool {
        let mut low = [0u32; SETTLE_BLOCK];
        for (l, &v) in low.iter_mut().zip(raw) {
            // `scaled(v) < floor`: 0 under the flush, else `min(v·k, 1)`,
            // which is under `floor ≤ 1` exactly when `v·k` is; both are
            // `v ≤ low_max` (NaN, flushed too, fails it: the full path).
            *l = (v <= self.low_max) as u32;
        }
        raw.len() == SETTLE_BLOCK && low.iter().fold(1, |a, &l| a & l) == 1
    }

    /// What [`Settle::cell`] makes of the bias and Δ of the blocks marked
    /// in `low` (bit `i`: block `i` of [`SETTLE_BLOCK`] cells of `b` and `d`,
    /// whose cells ended under the floor): 1 and 2π, the full circle. One
    /// plane after the other, by runs of marked blocks: stores interleaved
    /// block by block over the three planes ran at half the speed of the
    /// same stores plane by plane (measured: 47 against 19 µs for three
    /// 60,000-cell planes), hence the chunks of [`SETTLE_CHUNK`] cells.
    #[inline(always)]
    pub(crate) fn floor_sets(low: u64, b: &mut [f32], d: &mut [f32]) {
        for (plane, v) in [(b, 1.0), (d, 2.0 * PI)] {
            let (mut m, mut at) = (low, 0);
            while m != 0 {
                let skip = m.trailing_zeros() as usize; // < 64: m ≠ 0
                m >>= skip;
                let run = m.trailing_ones() as usize;
                at += skip;
                plane[at * SETTLE_BLOCK..(at + run) * SETTLE_BLOCK].fill(v);
                at += run;
                m = m.checked_shr(run as u32).unwrap_or(0); // run = 64: done
            }
        }
    }

    /// Settles cells from their raw values `h` (the plane combined with an
    /// observation), biases `b` and widths `d`, in place, by
    /// [`Settle::cell`] (or [`Settle::height`] with no floor). Blocks of
    /// cells all ending under the floor take its three constants
    /// ([`Settle::all_under_floor`]): the possibility at once, bias and Δ
    /// per chunk ([`Settle::floor_sets`]).
    #[inline(always)]
    pub(crate) fn settle_cells(&self, h: &mut [f32], b: &mut [f32], d: &mut [f32]) {
        if self.floor <= 0.0 {
            for v in h.iter_mut() {
                *v = self.height(*v);
            }
            return;
        }
        self.settle_chunks(h, b, d, |h, b, d, _| {
            match (as_block(h), as_block(b), as_block(d)) {
                // Fixed-length loop: the form that vectorises.
                (Some(hb), Some(bb), Some(db)) => {
                    for i in 0..SETTLE_BLOCK {
                        (hb[i], bb[i], db[i]) = self.cell(hb[i], bb[i], db[i]);
                    }
                }
                _ => {
                    for ((h, b), d) in h.iter_mut().zip(b.iter_mut()).zip(d.iter_mut()) {
                        (*h, *b, *d) = self.cell(*h, *b, *d);
                    }
                }
            }
        });
    }

    /// The walk of both settle passes over planes `h`, `b`, `d` (floor > 0),
    /// [`SETTLE_CHUNK`] cells at a time: the blocks that all end under the
    /// floor take it ([`Settle::floor_blocks`], [`Settle::floor_sets`]);
    /// `rest(h, b, d, at)` settles the others — each other whole block, then
    /// the cells after the last one — given the cells at offset `at` of the
    /// planes.
    #[inline(always)]
    pub(crate) fn settle_chunks(
        &self,
        h: &mut [f32],
        b: &mut [f32],
        d: &mut [f32],
        mut rest: impl FnMut(&mut [f32], &mut [f32], &mut [f32], usize),
    ) {
        let chunks = (h.chunks_mut(SETTLE_CHUNK))
            .zip(b.chunks_mut(SETTLE_CHUNK))
            .zip(d.chunks_mut(SETTLE_CHUNK));
        for (c, ((hc, bc), dc)) in chunks.enumerate() {
            let low = self.floor_blocks(hc);
            let whole = hc.len() / SETTLE_BLOCK;
            let mut others = match whole {
                0 => 0,
                w => !low & (u64::MAX >> (64 - w)),
            };
            let base = c * SETTLE_CHUNK;
            while others != 0 {
                let at = others.trailing_zeros() as usize * SETTLE_BLOCK;
                others &= others - 1;
                let r = at..at + SETTLE_BLOCK;
                rest(
                    &mut hc[r.clone()],
                    &mut bc[r.clone()],
                    &mut dc[r],
                    base + at,
                );
            }
            let tail = whole * SETTLE_BLOCK;
            if tail < hc.len() {
                rest(
                    &mut hc[tail..],
                    &mut bc[tail..],
                    &mut dc[tail..],
                    base + tail,
                );
            }
            Self::floor_sets(low, bc, dc);
        }
    }

    /// Puts at the floor the possibility of the whole blocks of a chunk
    /// (at most 64 blocks of [`SETTLE_BLOCK`] cells) that all end under it
    /// ([`Settle::all_under_floor`]), and returns them as bits. This loop
    /// reads and writes the possibility plane only: with the bias and Δ in
    /// it too, the compiler re-checked the three slices for overlap at
    /// every block.
    #[inline(always)]
    pub(crate) fn floor_blocks(&self, h: &mut [f32]) -> u64 {
        let mut low = 0u64;
        for (i, hb) in h.chunks_exact_mut(SETTLE_BLOCK).enumerate() {
            if self.all_under_floor(hb) {
                hb.fill(self.floor);
                low |= 1 << i;
            }
        }
        low
    }

    /// The cell's new possibility with no floor (`floor = 0`).
    #[inline(always)]
    pub(crate) fn height(&self, raw: f32) -> f32 {
        self.scaled(raw)
    }

    /// The cell's new `(h, b, Δ)` with the floor: `π(x, y, θ) = h · max(b,
    /// ramp) ≥ floor` for every θ. A cell under the floor rises to it with a
    /// full-circle heading (bias 1, Δ = 2π); another keeps `b ≥ floor / h`.
    /// Selects on the bits ([`blend`]) so that loops calling it vectorise
    /// (with plain `if`s it was compiled scalar and branchy).
    #[inline(always)]
    pub(crate) fn cell(&self, raw: f32, b: f32, d: f32) -> (f32, f32, f32) {
        let n = self.scaled(raw);
        let low = n < self.floor;
        let h = fmax(self.floor, n);
        // floor / h is the raised bias floor / n above the floor, and
        // exactly 1 under it (h = floor there): one division and one
        // select serve both cases, and no guard is needed against n = 0.
        let raised = self.floor / h;
        let b = blend(low | (n * b < self.floor), raised, b);
        (h, b, blend(low, 2.0 * PI, d))
    }
}

/// The largest float `t` near `start` with `pred(t)`, for a `pred` true on
/// a down-set of floats (every value under a true one is true); searched a
/// few ulps either way. −∞ when `start` is NaN or `pred` fails there and a
/// few ulps under it: the shortcut built on it is then never taken, which
/// is slower but exact.
fn last_true(start: f32, pred: impl Fn(f32) -> bool) -> f32 {
    let mut t = start;
    let mut steps = 0;
    while !t.is_nan() && !pred(t) && steps < 8 {
        t = next_down(t);
        steps += 1;
    }
    if t.is_nan() || !pred(t) {
        return f32::NEG_INFINITY;
    }
    while next_up(t) != t && pred(next_up(t)) && steps < 16 {
        t = next_up(t);
        steps += 1;
    }
    t
}

/// The next float towards +∞ (`f32::next_up`, which is newer than the
/// crate's minimum Rust); NaN and +∞ stay.
fn next_up(v: f32) -> f32 {
    if v.is_nan() || v == f32::INFINITY {
        return v;
    }
    let b = v.to_bits();
    f32::from_bits(match v {
        0.0 => 1, // from ±0, the smallest positive subnormal
        _ if v > 0.0 => b + 1,
        _ => b - 1,
    })
}

/// The next float towards −∞.
fn next_down(v: f32) -> f32 {
    -next_up(-v)
}

/// `v` as an array when it is a whole block of [`SETTLE_BLOCK`] cells.
#[inline(always)]
pub(crate) fn as_block(v: &mut [f32]) -> Option<&mut [f32; SETTLE_BLOCK]> {
    v.try_into().ok()
}

/// `max(a, b)` as a select (`f32::max`'s NaN rule blocks SIMD): `a` unless
/// `b` is larger, so `a` when `b` is NaN. One definition for the grid's
/// vector passes, whose "same floats" claims rest on its exact rule.
#[inline(always)]
pub(crate) fn fmax(a: f32, b: f32) -> f32 {
    if b > a {
        b
    } else {
        a
    }
}

/// `min(a, b)` as a select: `a` unless `b` is smaller.
#[inline(always)]
pub(crate) fn fmin(a: f32, b: f32) -> f32 {
    if b < a {
        b
    } else {
        a
    }
}

/// `if c { a } else { b }` on the bits. A plain `if` with a constant arm let
/// the compiler turn the store of that constant into a branch, which blocked
/// vectorising `finish_update`'s second pass; masks cannot be sunk.
#[inline(always)]
pub(crate) fn blend(c: bool, a: f32, b: f32) -> f32 {
    let m = (c as u32).wrapping_neg();
    f32::from_bits((a.to_bits() & m) | (b.to_bits() & !m))
}

/// Independent running maxima of [`raw_max`] and [`scale_max_by`]: four
/// vectors, so that the sweep is not held up by the latency of a chain of
/// `maxps` (two vectors read measurably slower).
const MAX_LANES: usize = 16;

/// Largest value of a slice, at least 0, NaN ignored; [`MAX_LANES`]
/// independent select-maxima so that it vectorises.
#[inline]
pub(crate) fn raw_max(v: &[f32]) -> f32 {
    let mut lanes = [0.0f32; MAX_LANES];
    let chunks = v.chunks_exact(MAX_LANES);
    let rest = chunks.remainder();
    for ch in chunks {
        for l in 0..MAX_LANES {
            lanes[l] = if ch[l] > lanes[l] { ch[l] } else { lanes[l] };
        }
    }
    rest.iter()
        .chain(lanes.iter())
        .fold(0.0f32, |a, &b| if b > a { b } else { a })
}

/// Multiplies every cell of `v` by `k` and returns [`raw_max`] of the
/// products, measured in the same sweep: the same value, as a maximum does
/// not depend on the order it is taken in (and neither selects NaN).
#[inline]
pub(crate) fn scale_max_by(v: &mut [f32], k: f32) -> f32 {
    let mut lanes = [0.0f32; MAX_LANES];
    let mut vs = v.chunks_exact_mut(MAX_LANES);
    for c in &mut vs {
        for l in 0..MAX_LANES {
            c[l] *= k;
            lanes[l] = if c[l] > lanes[l] { c[l] } else { lanes[l] };
        }
    }
    let mut m = lanes.iter().fold(0.0f32, |a, &b| if b > a { b } else { a });
    for c in vs.into_remainder() {
        *c *= k;
        m = if *c > m { *c } else { m };
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The normalise/floor step as it was first written (clamp, scale,
    /// clamp again; a guarded division; three separate selects), kept as
    /// the reference that [`Settle::cell`] and [`Settle::height`] must match
    /// bit for bit: the MRCLAM figures rest on these floats.
    fn reference(raw: f32, b: f32, d: f32, s: Settle) -> (f32, f32, f32) {
        let clamped = if raw >= s.flush {
            if raw < 1.0 {
                raw
            } else {
                1.0
            }
        } else {
            0.0
        };
        let m = clamped * s.k;
        let n = if m < 1.0 { m } else { 1.0 };
        if s.floor <= 0.0 {
            return (n, b, d);
        }
        let low = n < s.floor;
        let raised = s.floor / if n > 0.0 { n } else { 1.0 };
        let nb = if n * b < s.floor { raised } else { b };
        if low {
            (s.floor, 1.0, 2.0 * PI)
        } else {
            (n, nb, d)
        }
    }

    #[test]
    fn settling_matches_the_reference_bit_for_bit() {
        let same = |x: f32, y: f32| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan());
        let mut rnd = crate::grid::test_rng(77u32);
        let specials = [
            f32::NAN,
            f32::INFINITY,
            -1.0,
            -0.0,
            0.0,
            1e-40,
            1e-9,
            1e-8,
            0.5,
            1.0,
            1.0 + f32::EPSILON,
            3.0,
        ];
        for k in [1.0, 1.000_000_1, 2.0, 1e3, 1e8] {
            for flush in [0.0, 1e-9] {
                for floor in [0.0, 1e-8, 1e-3, 0.5] {
                    let s = Settle::new(flush, k, floor);
                    for i in 0..4000 {
                        let pick = |i: usize, r: f32| {
                            if i < specials.len() {
                                specials[i]
                            } else {
                                r
                            }
                        };
                        let raw = pick(i % 40, rnd() * rnd());
                        let b = pick((i / 40) % 40, rnd());
                        let d = 6.0 * rnd();
                        let want = reference(raw, b, d, s);
                        if floor > 0.0 {
                            let got = s.cell(raw, b, d);
                            assert!(
                                same(got.0, want.0) && same(got.1, want.1) && same(got.2, want.2),
                                "raw {raw} b {b} k {k} flush {flush} floor {floor}: {got:?} vs {want:?}"
                            );
                        } else {
                            let got = s.height(raw);
                            assert!(same(got, want.0), "raw {raw} k {k}: {got} vs {}", want.0);
                        }
                    }
                }
            }
        }
    }

    /// Our `next_up`/`next_down` against the standard library's (newer than
    /// the crate's minimum Rust, fine in a test).
    #[test]
    #[allow(clippy::incompatible_msrv)]
    fn next_float_matches_std() {
        let mut rnd = crate::grid::test_rng(5u32);
        let specials = [0.0, -0.0, 1e-45, -1e-45, 1.0, -1.0, f32::MAX, -f32::MAX];
        let inf = [f32::INFINITY, f32::NEG_INFINITY, f32::NAN];
        for v in specials
            .into_iter()
            .chain(inf)
            .chain((0..1000).map(|_| (rnd() - 0.5) * 1e3))
        {
            let same = |a: f32, b: f32| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
            assert!(same(next_up(v), v.next_up()), "next_up({v})");
            assert!(same(next_down(v), v.next_down()), "next_down({v})");
        }
    }

    /// The floor test by threshold: every value up to [`Settle::low_max`]
    /// ends under the floor by the definition (flushed, or `v·k < floor`),
    /// and the next float up does not (the threshold is as large as it may
    /// be), for normalisations from none to extreme, with and without a
    /// flush above the floor's threshold.
    #[test]
    fn the_floor_threshold_is_exact() {
        // Flushed (`v ≥ flush` fails, NaN too) or scaled under the floor.
        let low = |v: f32, flush: f32, k: f32, floor: f32| {
            v.partial_cmp(&flush).map_or(true, |o| o.is_lt()) | (v * k < floor)
        };
        let mut rnd = crate::grid::test_rng(99u32);
        for k in [1.0, 1.000_000_1, 1.25, 3.0, 1e3, 1e8, 1.0 / 1e-30] {
            for flush in [0.0, 1e-9, 1e-3, 0.2] {
                for floor in [1e-8, 1e-3, 0.05, 0.5, 1.0] {
                    let s = Settle::new(flush, k, floor);
                    let t = s.low_max;
                    assert!(
                        low(t, flush, k, floor),
                        "k {k} flush {flush} floor {floor}: T = {t}"
                    );
                    assert!(
                        !low(next_up(t), flush, k, floor),
                        "k {k} flush {flush} floor {floor}: T = {t} not the largest"
                    );
                    for _ in 0..200 {
                        let v = t * rnd();
                        assert!(low(v, flush, k, floor) && v <= t);
                    }
                }
            }
        }
        // An infinite normalisation (a plane of denormals with no flush):
        // the threshold stays below 0, where `v·k` is −∞.
        let s = Settle::new(0.0, f32::INFINITY, 1e-3);
        assert!(s.low_max < 0.0 && low(s.low_max, 0.0, f32::INFINITY, 1e-3));
        assert!(!s.all_under_floor(&[0.0; SETTLE_BLOCK]));
    }

    /// The block shortcut ([`Settle::all_under_floor`]) must not change a
    /// bit: planes whose 16-cell blocks are all under the floor, all above,
    /// mixed by one cell, with NaN or infinite cells, and a remainder that
    /// is not a whole block, settled by [`Settle::settle_cells`] against
    /// the reference cell by cell.
    #[test]
    fn settling_in_blocks_matches_the_reference_bit_for_bit() {
        let same = |x: f32, y: f32| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan());
        let mut rnd = crate::grid::test_rng(4242u32);
        for floor in [0.0, 1e-8, 1e-3, 0.5, 1.0] {
            let s = Settle::new(1e-9, 1.25, floor);
            for n in [
                0usize,
                5,
                16,
                37,
                200,
                SETTLE_CHUNK,
                SETTLE_CHUNK + 37,
                3000,
            ] {
                let mut h: Vec<f32> = (0..n)
                    .map(|i| match (i / SETTLE_BLOCK) % 5 {
                        0 => floor * 0.5 * rnd(),           // whole block under the floor
                        1 => floor + (1.0 - floor) * rnd(), // above it
                        2 if i % SETTLE_BLOCK == 7 => 0.9,  // one cell above in a low block
                        // Within a few ulps of the threshold `floor / k`.
                        3 => {
                            let mut v = floor / 1.25;
                            for _ in 0..(i % 7) {
                                v = next_down(v);
                            }
                            for _ in 0..(i % 3) {
                                v = next_up(v);
                            }
                            v
                        }
                        _ => [f32::NAN, f32::INFINITY, 0.0, 1e-12][i % 4] + floor * 0.1 * rnd(),
                    })
                    .collect();
                let mut b: Vec<f32> = (0..n).map(|_| rnd()).collect();
                let mut d: Vec<f32> = (0..n).map(|_| 6.0 * rnd()).collect();
                let want: Vec<_> = (0..n).map(|i| reference(h[i], b[i], d[i], s)).collect();
                s.settle_cells(&mut h, &mut b, &mut d);
                for (i, w) in want.iter().enumerate() {
                    let (wh, wb, wd) = if floor > 0.0 { *w } else { (w.0, b[i], d[i]) };
                    assert!(
                        same(h[i], wh) && same(b[i], wb) && same(d[i], wd),
                        "floor {floor} n {n} cell {i}: {:?} vs {w:?}",
                        (h[i], b[i], d[i])
                    );
                }
            }
        }
    }
}
