//! The grid itself: geometry (cell ↔ metric coordinates), the planes that
//! hold each cell's possibility and heading set, total ignorance, and the
//! bookkeeping shared by the update, prediction and estimate modules.
//!
//! Planes are flat `Vec<f32>` in row-major order (`index = row · nx + col`,
//! row 0 at `y_min`), so every pass is a linear sweep; scratch buffers are
//! allocated once here so that stepping allocates nothing.
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

use super::predict::Pending;
use super::{GridConfig, GridError, Trapezoid};
use std::f32::consts::PI;

/// Largest number of cells a grid may have (about 1.5 GB of planes).
pub const MAX_CELLS: usize = 64 << 20;

/// The Fuzzy Position Grid of paper 000.
#[derive(Debug, Clone)]
pub struct FuzzyGrid {
    pub(crate) cfg: GridConfig,
    pub(crate) nx: usize,
    pub(crate) ny: usize,
    pub(crate) x0: f32,
    pub(crate) y0: f32,
    pub(crate) cell: f32,
    /// Possibility plane `G(x, y)`.
    pub(crate) h: Vec<f32>,
    /// Heading set of each cell, stored with height 1 (its height is `h`).
    pub(crate) theta: Vec<f32>,
    pub(crate) delta: Vec<f32>,
    pub(crate) alpha: Vec<f32>,
    pub(crate) bias: Vec<f32>,
    /// Scratch plane for dilation and shifting (same size as `h`).
    pub(crate) scratch: Vec<f32>,
    /// Scratch for the 1-D passes: one line of values (room for a padded
    /// row of dilation blocks), and a deque of indices.
    pub(crate) line: Vec<f32>,
    pub(crate) line_out: Vec<f32>,
    pub(crate) deque: Vec<u32>,
    /// Chunk maxima and block bounds of the dilation's column and diagonal
    /// passes.
    pub(crate) cm: Vec<f32>,
    pub(crate) pending: Pending,
    /// Height of the plane before the last normalisation.
    pub(crate) last_height: f32,
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
        let longest = nx.max(ny) + nx.min(ny); // a diagonal is never longer
        let mut g = FuzzyGrid {
            cell: cfg.cell_size,
            cfg,
            nx,
            ny,
            x0: x_min,
            y0: y_min,
            h: vec![1.0; n],
            theta: vec![0.0; n],
            delta: vec![2.0 * PI; n],
            alpha: vec![0.0; n],
            bias: vec![1.0; n],
            scratch: vec![0.0; n],
            line: vec![0.0; longest.max(super::dilate::padded_row(nx))],
            line_out: vec![0.0; longest],
            deque: vec![0; longest],
            cm: vec![0.0; super::dilate::chunk_len(nx, ny)],
            pending: Pending::default(),
            last_height: 1.0,
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
        self.last_height = 1.0;
    }

    /// The configuration in use.
    pub fn config(&self) -> &GridConfig {
        &self.cfg
    }
    /// Number of columns (x direction).
    pub fn nx(&self) -> usize {
        self.nx
    }
    /// Number of rows (y direction).
    pub fn ny(&self) -> usize {
        self.ny
    }
    /// Cell side in metres.
    pub fn cell_size(&self) -> f32 {
        self.cell
    }
    /// Lower-left corner `(x_min, y_min)` of the grid.
    pub fn origin(&self) -> (f32, f32) {
        (self.x0, self.y0)
    }
    /// The possibility plane, row-major (`row · nx + col`, row 0 at `y_min`).
    pub fn possibilities(&self) -> &[f32] {
        &self.h
    }
    /// Mutable possibility plane, for callers that build priors. Values written
    /// outside [0, 1] (or NaN) are clamped (NaN → 0) by the next operation.
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
    pub fn possibility(&self, col: usize, row: usize) -> f32 {
        if col < self.nx && row < self.ny {
            self.h[row * self.nx + col]
        } else {
            0.0
        }
    }
    /// Heading set of cell `(col, row)`, with the cell's possibility as height.
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
    pub fn set_heading_set(&mut self, col: usize, row: usize, t: Trapezoid) {
        if col < self.nx && row < self.ny {
            let i = row * self.nx + col;
            self.theta[i] = t.center;
            self.delta[i] = t.core;
            self.alpha[i] = t.slope;
            self.bias[i] = t.bias;
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
    /// sweep over the plane instead of two. The height is the flushed and
    /// clamped maximum, `min(raw, 1)` if `raw ≥ flush`, else 0: the maximum of
    /// the flushed, clamped cells (NaN cells, never selected by
    /// [`raw_max`], are flushed to 0).
    pub(crate) fn finish_update_from(&mut self, raw: f32) -> f32 {
        let flush = self.cfg.flush_below;
        let max = if raw >= flush { raw.min(1.0) } else { 0.0 };
        self.last_height = max;
        if max <= 0.0 {
            let pending = self.pending;
            self.reset();
            self.pending = pending;
            self.last_height = 0.0;
            return 0.0;
        }
        let k = if self.cfg.normalize && max < 1.0 {
            1.0 / max
        } else {
            1.0
        };
        let floor = self.cfg.floor;
        if floor > 0.0 {
            // Pass 2: normalise and keep π(x, y, θ) = h · max(b, ramp) ≥ floor
            // for every θ: cells under the floor rise to it with a full-circle
            // heading (bias 1, Δ = 2π), the others get b ≥ floor / h.
            // Selects on the bits ([`blend`]) over zipped iterators, so that
            // the pass vectorises (with plain `if`s and indices it was
            // compiled scalar and branchy, ~70 % of a range update).
            let cells = self
                .h
                .iter_mut()
                .zip(self.bias.iter_mut())
                .zip(self.delta.iter_mut());
            for ((h, b), d) in cells {
                let m = flush_clamp(*h, flush) * k;
                let n = if m < 1.0 { m } else { 1.0 }; // f32::min's NaN rule blocks SIMD
                let low = n < floor;
                // Computed unconditionally (n > 0 whenever it is used).
                let raised = floor / if n > 0.0 { n } else { 1.0 };
                let nb = blend(n * *b < floor, raised, *b);
                *b = blend(low, 1.0, nb);
                *d = blend(low, 2.0 * PI, *d);
                *h = blend(low, floor, n);
            }
        } else {
            for v in self.h.iter_mut() {
                let m = flush_clamp(*v, flush) * k;
                *v = if m < 1.0 { m } else { 1.0 };
            }
        }
        max
    }
}

/// `if c { a } else { b }` on the bits. A plain `if` with a constant arm let
/// the compiler turn the store of that constant into a branch, which blocked
/// vectorising `finish_update`'s second pass; masks cannot be sunk.
#[inline(always)]
fn blend(c: bool, a: f32, b: f32) -> f32 {
    let m = (c as u32).wrapping_neg();
    f32::from_bits((a.to_bits() & m) | (b.to_bits() & !m))
}

/// Flushes values under `flush` (NaN too: it fails `>=`) to 0 and clamps to
/// 1, with selects (`f32::min`'s NaN rule blocks SIMD).
#[inline(always)]
fn flush_clamp(v: f32, flush: f32) -> f32 {
    if v >= flush {
        if v < 1.0 {
            v
        } else {
            1.0
        }
    } else {
        0.0
    }
}

/// Largest value of a slice, at least 0, NaN ignored; eight independent
/// select-maxima so that it vectorises.
#[inline]
pub(crate) fn raw_max(v: &[f32]) -> f32 {
    let mut lanes = [0.0f32; 8];
    let chunks = v.chunks_exact(8);
    let rest = chunks.remainder();
    for ch in chunks {
        for l in 0..8 {
            lanes[l] = if ch[l] > lanes[l] { ch[l] } else { lanes[l] };
        }
    }
    rest.iter()
        .chain(lanes.iter())
        .fold(0.0f32, |a, &b| if b > a { b } else { a })
}
