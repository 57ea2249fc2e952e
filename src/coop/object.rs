//! The object grid of one robot: paper 002's sup formula (§2.3, algorithm (3)),
//!
//! `μ(p) = max(β, sup{ μ_r(q, θ) | d(p, q) = ρ, ∠(pq) = φ + θ })`, with `β = 1 − reliability`,
//!
//! extended to an imprecise reading by the extension principle: the crisp conditions become the
//! trapezoids `R = range.around(ρ)` and `B = bearing.around(φ)` of [`CoopConfig`] (their biases
//! are not used pointwise: they make up the floor β, see [`CoopConfig::observation_reliability`]),
//!
//! `μ(p) = max(β, sup_{q, θ} min(μ_r(q, θ), R⁺(d(p, q)), B⁺(∠(pq) − θ)))`.
//!
//! A cell is an area, not a point: `R⁺` is `R` widened by one cell (the sup of `R` over the
//! distances `d ± s/2` that cell `p` spans seen from the centre of `q`), and `B⁺` is `B` widened
//! by the half angle `atan(s/2 / d)` the cell subtends. With a crisp reading `R⁺` is the digital
//! circle `|d − ρ| ≤ s/2` (Andres' ring, the hole-free generalisation of Bresenham's circle that
//! paper 002 rasterises).
//!
//! The self grid's joint possibility is `μ_r(q, θ) = h_q · max(b_q, ramp_q(θ))` (the heading set
//! is stored with height 1, its height being the cell's `h`, see [`crate::grid::cells`]), so
//! `sup_θ min(μ_r(q, θ), B⁺(ψ − θ)) = max(h_q·b_q, overlap(h_q·ramp_q, B⁺ centred at ψ − φ))`,
//! with `ψ` the direction from `q` to `p` — closed form by [`Trapezoid::overlap_level`].
//!
//! As in paper 002 §4.1, the loop runs over the self cells `q` and visits, for each, the cells on
//! the ring of radius ρ around it: a stencil of offsets built once per reading. A self cell with
//! `h_q ≤ β` cannot raise any object cell above the floor and is skipped, which keeps the result
//! exact.
//!
//! # Complexity
//!
//! O(cells) to fill the floor, plus O(k · m) for the `k` self cells above the floor and the `m`
//! cells of the ring (≈ 2πρ · width / s²); memory O(cells + m).
//!
//! # Example
//!
//! ```
//! use lplace::coop::{object_grid, CoopConfig, ObjectReading};
//! use lplace::grid::{FuzzyGrid, GridConfig, Trapezoid};
//! let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 3.0, 2.0]).unwrap();
//! // The robot is certainly in cell (5, 10), centre (0.55, 1.05), facing +x.
//! g.possibilities_mut().fill(0.0);
//! g.possibilities_mut()[10 * 30 + 5] = 1.0;
//! g.set_heading_set(5, 10, Trapezoid::new(0.0, 0.1, 0.1, 1.0, 0.0));
//! let obj = object_grid(&g, 1.0, ObjectReading { range: 1.0, bearing: 0.0 }, &CoopConfig::default()).unwrap();
//! let e = obj.centre_of_gravity(0.5).unwrap();
//! assert!((e.0 - 1.55).abs() < 0.05 && (e.1 - 1.05).abs() < 0.05); // one metre ahead
//! assert!((obj.floor() - 0.1).abs() < 1e-6);                      // 1 − reliability
//! ```

use super::{CoopConfig, CoopError};
use crate::grid::{FuzzyGrid, Trapezoid};
use serde::{Deserialize, Serialize};

/// Where a grid lies in the global frame F_g: every robot's grids share it (paper 002 §2.3), so
/// only the cell values need to be exchanged.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GridGeometry {
    /// Columns.
    pub nx: usize,
    /// Rows.
    pub ny: usize,
    /// `x` of the lower-left corner (m).
    pub x0: f32,
    /// `y` of the lower-left corner (m).
    pub y0: f32,
    /// Side of a cell (m).
    pub cell: f32,
}

impl GridGeometry {
    /// The geometry of a self grid.
    pub fn of(g: &FuzzyGrid) -> Self {
        let (x0, y0) = g.origin();
        GridGeometry {
            nx: g.nx(),
            ny: g.ny(),
            x0,
            y0,
            cell: g.cell_size(),
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// True for a grid without cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Centre of cell `(col, row)` (m).
    pub fn cell_center(&self, col: usize, row: usize) -> (f32, f32) {
        (
            self.x0 + (col as f32 + 0.5) * self.cell,
            self.y0 + (row as f32 + 0.5) * self.cell,
        )
    }
}

/// A robot's reading of the object in its own frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ObjectReading {
    /// Distance ρ (m).
    pub range: f32,
    /// Bearing φ (rad, counter-clockwise from the robot's heading).
    pub bearing: f32,
}

/// A 2-D possibility grid over the object's position, in [0, 1], row-major like the self grid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObjectGrid {
    geometry: GridGeometry,
    values: Vec<f32>,
}

impl ObjectGrid {
    /// A grid with the given values; `None` when their number is not `geometry.len()`.
    /// Values are clamped to [0, 1] (NaN → 0).
    pub fn new(geometry: GridGeometry, mut values: Vec<f32>) -> Option<Self> {
        if values.len() != geometry.len() {
            return None;
        }
        for v in &mut values {
            *v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
        }
        Some(ObjectGrid { geometry, values })
    }

    /// Total ignorance: every position fully possible.
    pub fn ignorance(geometry: GridGeometry) -> Self {
        ObjectGrid {
            geometry,
            values: vec![1.0; geometry.len()],
        }
    }

    /// Where the grid lies.
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    /// The possibilities, row-major (`row · nx + col`).
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// Possibility of cell `(col, row)`, 0 outside.
    pub fn value(&self, col: usize, row: usize) -> f32 {
        if col < self.geometry.nx && row < self.geometry.ny {
            self.values[row * self.geometry.nx + col]
        } else {
            0.0
        }
    }

    /// Smallest value: the grid's bias (paper 002 §2.3), its unreliability.
    pub fn floor(&self) -> f32 {
        self.values.iter().copied().fold(1.0, f32::min)
    }

    /// Largest value: the grid's height.
    pub fn height(&self) -> f32 {
        self.values.iter().copied().fold(0.0, f32::max)
    }

    /// Centre of gravity (paper 002 eq. (2)) of the cells with `μ ≥ min + cut · (max − min)`,
    /// weighted by `μ − min` so that the uniform bias does not pull the estimate towards the
    /// middle of the grid. `None` for a flat grid (no information: every position as possible).
    ///
    /// # Complexity
    /// O(cells).
    pub fn centre_of_gravity(&self, cut: f32) -> Option<(f32, f32)> {
        let (lo, hi) = (self.floor(), self.height());
        if hi <= lo {
            return None;
        }
        let level = lo + cut.clamp(0.0, 1.0) * (hi - lo);
        let (mut sw, mut sx, mut sy) = (0.0f64, 0.0f64, 0.0f64);
        let nx = self.geometry.nx;
        for (i, &v) in self.values.iter().enumerate() {
            if v >= level && v > lo {
                let w = (v - lo) as f64;
                sw += w;
                sx += w * (i % nx) as f64;
                sy += w * (i / nx) as f64;
            }
        }
        if sw <= 0.0 {
            return None;
        }
        let s = self.geometry.cell as f64;
        Some((
            (self.geometry.x0 as f64 + (sx / sw + 0.5) * s) as f32,
            (self.geometry.y0 as f64 + (sy / sw + 0.5) * s) as f32,
        ))
    }
}

/// One cell of the ring stencil: offset, distance membership `R⁺(d)`, direction ψ and the half
/// angle the cell subtends.
#[derive(Debug, Clone, Copy)]
struct RingCell {
    dc: isize,
    dr: isize,
    range: f32,
    psi: f32,
    half_angle: f32,
}

/// The cells around `q` whose distance membership `R⁺(d)` exceeds `floor`.
/// Offsets reach at most `max_k` cells: farther ones fall outside any grid of that size.
fn ring(range: &Trapezoid, cell: f32, floor: f32, max_k: usize) -> Vec<RingCell> {
    let outer = range.center + 0.5 * range.shape.core + range.shape.slope;
    let k = (outer / cell).ceil().min(max_k as f32) as isize;
    let mut out = Vec::new();
    for dr in -k..=k {
        for dc in -k..=k {
            let (x, y) = (dc as f32 * cell, dr as f32 * cell);
            let d = x.hypot(y);
            let m = range.linear(d);
            if m > floor {
                out.push(RingCell {
                    dc,
                    dr,
                    range: m,
                    psi: y.atan2(x),
                    half_angle: (0.5 * cell).atan2(d),
                });
            }
        }
    }
    out
}

/// The object grid of one robot (see the module docs): self grid `g`, the reliability of its
/// self-localization (`self_reliability`, e.g. [`crate::grid::Estimate::reliability`]) and its
/// reading of the object.
///
/// # Errors
/// [`CoopError::BadReading`] for a non-finite or negative range, a non-finite bearing or a
/// reliability outside [0, 1].
pub fn object_grid(
    g: &FuzzyGrid,
    self_reliability: f32,
    reading: ObjectReading,
    cfg: &CoopConfig,
) -> Result<ObjectGrid, CoopError> {
    let bad = |what, value, extra| Err(CoopError::BadReading { what, value, extra });
    if !(reading.range.is_finite() && reading.range >= 0.0) {
        return bad("range", reading.range, " and ≥ 0");
    }
    if !reading.bearing.is_finite() {
        return bad("bearing", reading.bearing, "");
    }
    if !(0.0..=1.0).contains(&self_reliability) {
        return bad("self reliability", self_reliability, " and in [0, 1]");
    }
    let geometry = GridGeometry::of(g);
    let rel = if cfg.self_reliability_in_floor {
        cfg.observation_reliability().min(self_reliability)
    } else {
        cfg.observation_reliability()
    };
    let floor = (1.0 - rel).clamp(0.0, 1.0);
    let mut values = vec![floor; geometry.len()];
    if floor >= 1.0 {
        return Ok(ObjectGrid { geometry, values });
    }
    let s = geometry.cell;
    let r = cfg.range.around(reading.range);
    // R⁺: widened by one cell (± s/2), no pointwise bias (it is in the floor).
    let r_plus = Trapezoid::new(r.center, r.shape.core + s, r.shape.slope, 1.0, 0.0);
    let stencil = ring(&r_plus, s, floor, geometry.nx.max(geometry.ny));
    let b = cfg.bearing.around(reading.bearing);
    let (nx, ny) = (geometry.nx as isize, geometry.ny as isize);
    for row in 0..geometry.ny {
        for col in 0..geometry.nx {
            let Some(hs) = g.heading_set(col, row) else {
                continue;
            };
            let h = hs.shape.height;
            if h <= floor {
                continue;
            }
            let hb = h * hs.shape.bias;
            let a = Trapezoid::new(hs.center, hs.shape.core, hs.shape.slope, h, 0.0);
            for rc in &stencil {
                let (pc, pr) = (col as isize + rc.dc, row as isize + rc.dr);
                if pc < 0 || pr < 0 || pc >= nx || pr >= ny {
                    continue;
                }
                let i = pr as usize * geometry.nx + pc as usize;
                let cap = rc.range.min(h);
                if values[i] >= cap {
                    continue; // this q cannot raise p any further
                }
                // Headings θ for which p lies at bearing φ: centred at ψ − φ.
                let bq = Trapezoid::new(
                    rc.psi - b.center,
                    b.shape.core + 2.0 * rc.half_angle,
                    b.shape.slope,
                    1.0,
                    0.0,
                );
                let v = rc.range.min(hb.max(a.overlap_level(&bq)));
                if v > values[i] {
                    values[i] = v;
                }
            }
        }
    }
    Ok(ObjectGrid { geometry, values })
}
