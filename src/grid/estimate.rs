//! The point estimate of the grid and its reliability (paper 000 §3–4).
//!
//! * Position: centre of gravity of the cells whose possibility is at least
//!   `cog_cut · h_max`, weighted by possibility. Cutting first keeps the long
//!   low tail of a product-updated grid from pulling the estimate towards the
//!   middle of the map.
//! * Heading: circular mean of the heading-set centres of the *top region*
//!   (below), weighted by `h · (1 − b)` (a cell that thinks its heading may be
//!   anywhere says little); its mean resultant length `R̄ ∈ [0, 1]`
//!   (resultant over `Σ h`) is the heading reliability.
//! * Reliability: the *top region* is the set of cells with
//!   `h ≥ top_cut · h_max`, of area `A_top`; the reliability is
//!   `h_max · A_ref / (A_ref + A_top)` with `A_ref = reliability_area`. A
//!   single sharp peak gives nearly `h_max`; a top region as big as `A_ref`
//!   gives half of it; two distant peaks count their areas together, so
//!   ambiguity lowers the reliability as the paper asks.
//!
//! # Complexity
//!
//! O(cells): one pass for the maximum (per row, vectorised), one for the
//! sums (four-lane, adds only, so it vectorises) over the rows that reach
//! the cut, plus a heading pass over the rows that hold top cells.
//!
//! # Example
//!
//! ```
//! use lplace::grid::{FuzzyGrid, GridConfig};
//! let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 2.0, 2.0]).unwrap();
//! g.possibilities_mut().fill(0.0);
//! g.possibilities_mut()[5 * 20 + 7] = 1.0; // cell centre (0.75, 0.55)
//! let e = g.estimate();
//! assert!((e.x - 0.75).abs() < 1e-5 && (e.y - 0.55).abs() < 1e-5);
//! assert!(e.reliability > 0.9);
//! ```

use super::cells::raw_max;
use super::FuzzyGrid;

/// Rows whose maxima [`FuzzyGrid::estimate`] keeps on the stack (16 KiB);
/// rows beyond are always summed.
const ROWS: usize = 4096;
use serde::{Deserialize, Serialize};

/// A point estimate with its reliabilities.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// x (metres).
    pub x: f32,
    /// y (metres).
    pub y: f32,
    /// Heading (radians, in (−π, π]).
    pub theta: f32,
    /// Position reliability in [0, 1] (see the module docs).
    pub reliability: f32,
    /// Mean resultant length of the headings, in [0, 1].
    pub heading_reliability: f32,
    /// Area of the top region (m²).
    pub top_area: f32,
    /// Maximum of the plane.
    pub height: f32,
}

impl FuzzyGrid {
    /// Computes the [`Estimate`]. Pending motion is not applied (the estimate
    /// is of the belief as last updated); use [`FuzzyGrid::apply_pending`]
    /// first if the prediction should be included.
    pub fn estimate(&self) -> Estimate {
        // Pass 1: the maximum, and each row's maximum (kept for the first
        // `ROWS` rows) so that pass 2 can skip rows with no cell at or above
        // either cut: they add exactly 0 to every sum. A concentrated belief
        // leaves only a few rows for pass 2.
        let mut row_max = [0.0f32; ROWS];
        let mut max = 0.0f32;
        for (j, row) in self.h.chunks_exact(self.nx).enumerate() {
            let m = raw_max(row);
            if j < ROWS {
                row_max[j] = m;
            }
            max = if m > max { m } else { max };
        }
        if max <= 0.0 {
            let (cx, cy) = self.cell_center(self.nx / 2, self.ny / 2);
            return Estimate {
                x: cx,
                y: cy,
                theta: 0.0,
                reliability: 0.0,
                heading_reliability: 0.0,
                top_area: 0.0,
                height: 0.0,
            };
        }
        let cut = self.cfg.cog_cut * max;
        let top = self.cfg.top_cut * max;
        let mut hw_max = 0.0f64;
        let (mut sw, mut sx, mut sy, mut sc, mut ss) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
        let mut n_top = 0usize;
        let low_cut = if cut < top { cut } else { top };
        for j in 0..self.ny {
            if row_max.get(j).is_some_and(|&m| m < low_cut) {
                continue;
            }
            let base = j * self.nx;
            let row = &self.h[base..base + self.nx];
            let (rw, rx, rt) = row_sums(row, cut, top);
            if rt > 0 {
                for (c, &v) in row.iter().enumerate() {
                    if v >= top {
                        let i = base + c;
                        let wh = v * (1.0 - self.bias[i]);
                        let (s, co) = self.theta[i].sin_cos();
                        sc += (wh * co) as f64;
                        ss += (wh * s) as f64;
                        hw_max += v as f64;
                    }
                }
            }
            n_top += rt as usize;
            sw += rw as f64;
            sx += rx as f64;
            sy += rw as f64 * j as f64;
        }
        let s = self.cell as f64;
        let x = self.x0 as f64 + (sx / sw + 0.5) * s;
        let y = self.y0 as f64 + (sy / sw + 0.5) * s;
        let hw: f64 = sc.hypot(ss);
        // Normalise the resultant by the weight it could have had at most.
        let heading_reliability = if hw_max > 0.0 {
            (hw / hw_max).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let theta = if hw > 0.0 { ss.atan2(sc) as f32 } else { 0.0 };
        let top_area = n_top as f32 * self.cell * self.cell;
        let a = self.cfg.reliability_area;
        Estimate {
            x: x as f32,
            y: y as f32,
            theta,
            reliability: (max * a / (a + top_area)).clamp(0.0, 1.0),
            heading_reliability: heading_reliability as f32,
            top_area,
            height: max,
        }
    }
}

/// Sums of one row: cut weight `Σ w`, first moment `Σ w·c` and the number of
/// top cells, in four independent lanes so that the loop vectorises (a
/// single f32 accumulator forces sequential adds). The moment needs no
/// per-lane column index: `run` accumulates each lane's running weight once
/// per chunk, so it counts every weight once for each chunk from its own to
/// the last, and `Σ w·chunk = chunks · Σ w − run`; only adds remain in the
/// loop, which keeps it in registers.
#[inline]
fn row_sums(row: &[f32], cut: f32, top: f32) -> (f32, f32, u32) {
    const L: usize = 4;
    let (mut lw, mut run, mut lt) = ([0.0f32; L], [0.0f32; L], [0.0f32; L]);
    let chunks = row.chunks_exact(L);
    let rest = chunks.remainder();
    let n = chunks.len() as f32;
    for ch in chunks {
        for l in 0..L {
            let v = ch[l];
            lw[l] += if v >= cut { v } else { 0.0 };
            run[l] += lw[l];
            lt[l] += if v >= top { 1.0 } else { 0.0 };
        }
    }
    let (mut rw, mut rx, mut rt) = (0.0f32, 0.0f32, 0.0f32);
    for l in 0..L {
        // Σ w·c over the lane, with c = L·chunk + l and Σ w·chunk = n·Σ w − run.
        let chunk_moment = n * lw[l] - run[l];
        rx += L as f32 * chunk_moment + l as f32 * lw[l];
        rw += lw[l];
        rt += lt[l];
    }
    let off = row.len() - rest.len();
    for (l, &v) in rest.iter().enumerate() {
        let w = if v >= cut { v } else { 0.0 };
        rw += w;
        rx += w * (off + l) as f32;
        rt += if v >= top { 1.0 } else { 0.0 };
    }
    (rw, rx, rt as u32)
}
