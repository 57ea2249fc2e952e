//! The point estimate of the grid and its reliability (paper 000 §3–4).
//!
//! * Position: centre of gravity of the cells whose possibility is at least
//!   `cog_cut · h_max`, weighted by possibility. Cutting first keeps the long
//!   low tail of a product-updated grid from pulling the estimate towards the
//!   middle of the map.
//! * Under [`Cuts::Ramp`](super::Cuts) the cuts weigh instead of select: the
//!   centre of gravity weighs `h − cut` (0 below the cut), and a cell counts in
//!   the top region (below) by its share `(h − top) / (h_max − top)` in [0, 1].
//!   A cell crossing a cut then moves the estimate by as little as its
//!   possibility moved, where a hard cut moves it by up to a cell.
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
use super::{Cuts, FuzzyGrid, GridConfig};

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
        let cuts = Cut::new(&self.cfg, max);
        let whole = |v: f32, cut: f32| if v >= cut { 1.0 } else { 0.0 };
        let hard = |v: f32| (if v >= cuts.cog { v } else { 0.0 }, whole(v, cuts.top));
        let s = match (self.cfg.cuts, cuts.ramp) {
            (Cuts::Ramp, Some(inv)) => self.sums(&row_max, &cuts, |v| {
                (
                    (v - cuts.cog).max(0.0),
                    ((v - cuts.top) * inv).clamp(0.0, 1.0),
                )
            }),
            (Cuts::Ramp, None) => self.sums(&row_max, &cuts, |v| {
                ((v - cuts.cog).max(0.0), whole(v, cuts.top))
            }),
            (Cuts::Hard, _) => self.sums(&row_max, &cuts, hard),
        };
        // A ramp from the maximum itself (`cog_cut` 1) weighs every cell 0: the cells at the
        // maximum are then the region, whole.
        let s = if s.w > 0.0 {
            s
        } else {
            self.sums(&row_max, &cuts, hard)
        };
        let c = self.cell as f64;
        let x = self.x0 as f64 + (s.x / s.w + 0.5) * c;
        let y = self.y0 as f64 + (s.y / s.w + 0.5) * c;
        let hw: f64 = s.cos.hypot(s.sin);
        // Normalise the resultant by the weight it could have had at most.
        let heading_reliability = if s.heading_max > 0.0 {
            (hw / s.heading_max).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let theta = if hw > 0.0 {
            s.sin.atan2(s.cos) as f32
        } else {
            0.0
        };
        let top_area = s.top as f32 * self.cell * self.cell;
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

    /// Pass 2: the sums over the rows that reach a cut. `weigh(h)` gives a cell's weight in the
    /// centre of gravity and its share of the top region.
    fn sums(&self, row_max: &[f32; ROWS], cuts: &Cut, weigh: impl Fn(f32) -> (f32, f32)) -> Sums {
        let mut s = Sums::default();
        let low_cut = cuts.cog.min(cuts.top);
        for j in 0..self.ny {
            if row_max.get(j).is_some_and(|&m| m < low_cut) {
                continue;
            }
            let base = j * self.nx;
            let row = &self.h[base..base + self.nx];
            let (rw, rx, rt) = row_sums(row, &weigh);
            if rt > 0.0 {
                for (c, &v) in row.iter().enumerate() {
                    let share = weigh(v).1;
                    if share > 0.0 {
                        let i = base + c;
                        let wh = v * share * (1.0 - self.bias[i]);
                        let (sn, co) = self.theta[i].sin_cos();
                        s.cos += (wh * co) as f64;
                        s.sin += (wh * sn) as f64;
                        s.heading_max += (v * share) as f64;
                    }
                }
            }
            s.top += rt as f64;
            s.w += rw as f64;
            s.x += rx as f64;
            s.y += rw as f64 * j as f64;
        }
        s
    }
}

/// The estimate's cuts, as possibilities.
struct Cut {
    /// `cog_cut · max`.
    cog: f32,
    /// `top_cut · max`.
    top: f32,
    /// `1 / (max − top)`: the slope of a cell's share of the top region under [`Cuts::Ramp`];
    /// `None` when the top region is the maximum alone (`top_cut` 1), where a cell at the
    /// maximum counts whole.
    ramp: Option<f32>,
}

impl Cut {
    fn new(cfg: &GridConfig, max: f32) -> Self {
        let (cog, top) = (cfg.cog_cut * max, cfg.top_cut * max);
        let ramp = (max > top).then(|| 1.0 / (max - top));
        Cut { cog, top, ramp }
    }
}

/// Pass 2's sums: centre-of-gravity weight and moments (columns, rows), top-region share (in
/// cells), and the heading resultant with the weight it could have had at most.
#[derive(Default)]
struct Sums {
    w: f64,
    x: f64,
    y: f64,
    top: f64,
    cos: f64,
    sin: f64,
    heading_max: f64,
}

/// Sums of one row: centre-of-gravity weight `Σ w`, first moment `Σ w·c` and the top-region
/// share, in four independent lanes so that the loop vectorises (a
/// single f32 accumulator forces sequential adds). The moment needs no
/// per-lane column index: `run` accumulates each lane's running weight once
/// per chunk, so it counts every weight once for each chunk from its own to
/// the last, and `Σ w·chunk = chunks · Σ w − run`; only adds remain in the
/// loop, which keeps it in registers.
#[inline]
fn row_sums(row: &[f32], weigh: impl Fn(f32) -> (f32, f32)) -> (f32, f32, f32) {
    const L: usize = 4;
    let (mut lw, mut run, mut lt) = ([0.0f32; L], [0.0f32; L], [0.0f32; L]);
    let chunks = row.chunks_exact(L);
    let rest = chunks.remainder();
    let n = chunks.len() as f32;
    for ch in chunks {
        for l in 0..L {
            let (w, t) = weigh(ch[l]);
            lw[l] += w;
            run[l] += lw[l];
            lt[l] += t;
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
        let (w, t) = weigh(v);
        rw += w;
        rx += w * (off + l) as f32;
        rt += t;
    }
    (rw, rx, rt)
}

#[cfg(test)]
mod tests {
    use crate::grid::{Cuts, FuzzyGrid, GridConfig};

    /// A 20×20 grid of 0.1 m cells (cuts 0.5 and `top_cut`) with cell (7, 5) at 1 and its
    /// right neighbour at `v`.
    fn cut_pair(cuts: Cuts, top_cut: f32, v: f32) -> FuzzyGrid {
        let cfg = GridConfig {
            cuts,
            cog_cut: 0.5,
            top_cut,
            ..GridConfig::default()
        };
        let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, 2.0, 2.0]).unwrap();
        g.possibilities_mut().fill(0.0);
        g.possibilities_mut()[5 * 20 + 7] = 1.0;
        g.possibilities_mut()[5 * 20 + 8] = v;
        g
    }

    fn pair(cuts: Cuts, v: f32) -> FuzzyGrid {
        cut_pair(cuts, 0.9, v)
    }

    #[test]
    fn a_hard_cut_jumps_where_a_ramp_moves_by_the_change() {
        // Hard: just below the cut the neighbour is ignored (x = 0.75), just above it weighs
        // about half: x ≈ 0.75 + 0.1 · 0.5 / 1.5 = 0.783.
        let (lo, hi) = (pair(Cuts::Hard, 0.499), pair(Cuts::Hard, 0.501));
        assert!((lo.estimate().x - 0.75).abs() < 1e-5);
        assert!((hi.estimate().x - (0.75 + 0.1 * 0.501 / 1.501)).abs() < 1e-5);
        // Ramp: weights 1 − 0.5 and v − 0.5, so x = 0.75 + 0.1 · (v − 0.5) / (1 − 0.5 + v − 0.5).
        for v in [0.3f32, 0.499, 0.501, 0.8] {
            let w = (v - 0.5).max(0.0);
            let want = 0.75 + 0.1 * w / (0.5 + w);
            let x = pair(Cuts::Ramp, v).estimate().x;
            assert!((x - want).abs() < 1e-5, "{v}: {x} vs {want}");
        }
        let step =
            (pair(Cuts::Ramp, 0.501).estimate().x - pair(Cuts::Ramp, 0.499).estimate().x).abs();
        assert!(step < 1e-3, "{step}");
    }

    #[test]
    fn a_ramp_from_the_maximum_takes_the_cells_at_the_maximum() {
        let cfg = GridConfig {
            cuts: Cuts::Ramp,
            cog_cut: 1.0,
            ..GridConfig::default()
        };
        let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, 2.0, 2.0]).unwrap();
        g.possibilities_mut().fill(0.2);
        g.possibilities_mut()[5 * 20 + 7] = 1.0;
        g.possibilities_mut()[5 * 20 + 8] = 1.0;
        // Both cells at the maximum, weighed alike: halfway between their centres.
        let e = g.estimate();
        assert!(
            (e.x - 0.8).abs() < 1e-5 && (e.y - 0.55).abs() < 1e-5,
            "{e:?}"
        );
    }

    #[test]
    fn the_top_region_counts_a_cell_by_its_share_under_a_ramp() {
        // Top cut 0.9 of 1: the neighbour at 0.95 counts half a cell under a ramp (1.5 cells of
        // 0.01 m² in all), a whole one under a hard cut; below 0.9 it does not count.
        let cell = 0.01f32;
        for (v, hard, ramp) in [(0.95f32, 2.0f32, 1.5f32), (0.89, 1.0, 1.0), (1.0, 2.0, 2.0)] {
            let h = pair(Cuts::Hard, v).estimate().top_area;
            let r = pair(Cuts::Ramp, v).estimate().top_area;
            assert!((h - hard * cell).abs() < 1e-6, "{v}: {h}");
            assert!((r - ramp * cell).abs() < 1e-6, "{v}: {r}");
        }
        // top_cut 1: only cells at the maximum count, whole.
        let g = cut_pair(Cuts::Ramp, 1.0, 0.999);
        assert!((g.estimate().top_area - cell).abs() < 1e-6);
    }
}
