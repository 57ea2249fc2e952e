//! Observation of a known landmark by range, bearing or both, and the update
//! of the grid with it (paper 000 eq. (1) and §5).
//!
//! A range reading `r` becomes `S(x, y | r) = μ_⟨r,Δ,α,1,b⟩(d(x, y))`, with
//! `d` the distance from the cell centre to the landmark. A bearing reading
//! `β` (robot frame, counter-clockwise) tells each cell which heading the
//! robot must have there: `θ = atan2(l_y − y, l_x − x) − β`; that heading set
//! is intersected with the cell's own by [`Trapezoid::intersect_angle`], and
//! the consistency of the two, `sup_θ min(A, B)`, is the bearing's
//! possibility for the cell. The plane is combined with the product of the
//! two factors (or with `min`, see [`Combine`]).
//!
//! Range-only updates are exact and cheap: per row, the annulus where the
//! trapezoid is above its bias is found in closed form, and the cells outside
//! it are multiplied by the bias in a tight loop that the compiler vectorises.
//! The annulus itself is two plain column ranges per row (left and right of
//! the hole) evaluated branch-free, so that loop vectorises too, square root
//! included: one `sqrtps` per four cells is cheaper than tabulating
//! distances, and comparing squared distances against the breakpoints would
//! still need the root for the flank's value.
//!
//! # Complexity
//!
//! Range only: O(cells) with a small constant (O(annulus) vectorised
//! membership evaluations). With a bearing: O(cells) scalar angle-set
//! intersections.
//!
//! # Example
//!
//! ```
//! use lplace::grid::{FuzzyGrid, GridConfig};
//! let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 3.0, 2.0]).unwrap();
//! g.update_range(0.0, 0.0, 1.0).unwrap();
//! let (c, r) = g.cell_of(1.0, 0.05).unwrap();   // 1 m from the landmark
//! assert_eq!(g.possibility(c, r), 1.0);
//! let (c, r) = g.cell_of(2.5, 1.5).unwrap();    // far off the circle
//! assert!(g.possibility(c, r) < 0.2);
//! ```

use super::{Combine, FuzzyGrid, GridError, Trapezoid};
use serde::{Deserialize, Serialize};
use std::f32::consts::{FRAC_PI_2, PI};

/// A landmark at a known position.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Landmark {
    /// Identifier used by observations (MRCLAM: subject id 6–20).
    pub id: u32,
    /// Position x (metres).
    pub x: f32,
    /// Position y (metres).
    pub y: f32,
}

/// Landmarks sorted by id, looked up by binary search.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct LandmarkTable {
    marks: Vec<Landmark>,
}

impl LandmarkTable {
    /// Builds a table; rejects non-finite positions. Duplicate ids keep the
    /// last entry.
    pub fn new(mut marks: Vec<Landmark>) -> Result<Self, GridError> {
        for m in &marks {
            for (what, v) in [("landmark x", m.x), ("landmark y", m.y)] {
                if !v.is_finite() {
                    return Err(GridError::NonFinite {
                        what,
                        landmark: m.id,
                        value: v,
                    });
                }
            }
        }
        marks.reverse(); // so that dedup keeps the last of equal ids
        marks.sort_by_key(|m| m.id);
        marks.dedup_by_key(|m| m.id);
        Ok(LandmarkTable { marks })
    }
    /// The landmark with this id.
    pub fn get(&self, id: u32) -> Option<&Landmark> {
        self.marks
            .binary_search_by_key(&id, |m| m.id)
            .ok()
            .map(|i| &self.marks[i])
    }
    /// All landmarks, sorted by id.
    pub fn landmarks(&self) -> &[Landmark] {
        &self.marks
    }
    /// Bounding box `[x_min, y_min, x_max, y_max]` grown by `margin`.
    pub fn bounds(&self, margin: f32) -> Option<[f32; 4]> {
        let first = self.marks.first()?;
        let mut b = [first.x, first.y, first.x, first.y];
        for m in &self.marks {
            b = [b[0].min(m.x), b[1].min(m.y), b[2].max(m.x), b[3].max(m.y)];
        }
        Some([b[0] - margin, b[1] - margin, b[2] + margin, b[3] + margin])
    }
}

/// One landmark reading: range, bearing, or both.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Observation {
    /// Landmark id.
    pub landmark: u32,
    /// Measured distance (metres).
    pub range: Option<f32>,
    /// Measured bearing in the robot frame (radians, CCW, 0 = ahead).
    pub bearing: Option<f32>,
}

/// `atan2` to within 1e-5 rad, several times faster than `f32::atan2`; the
/// bearing update calls it once per cell.
#[inline]
pub fn fast_atan2(y: f32, x: f32) -> f32 {
    let ax = x.abs();
    let ay = y.abs();
    let (num, den, swap) = if ay > ax {
        (ax, ay, true)
    } else {
        (ay, ax, false)
    };
    if den == 0.0 {
        return 0.0;
    }
    let z = num / den;
    let z2 = z * z;
    let mut a = z
        * (0.999_977_3
            + z2 * (-0.332_623_5
                + z2 * (0.193_543_5
                    + z2 * (-0.116_432_9 + z2 * (0.052_653_3 + z2 * -0.011_721_2)))));
    if swap {
        a = FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y < 0.0 {
        -a
    } else {
        a
    }
}

/// A float column bound clamped into `[lo, hi]` (NaN gives `lo`).
#[inline]
fn to_col(v: f32, lo: usize, hi: usize) -> usize {
    if v.is_nan() {
        lo
    } else {
        v.clamp(lo as f32, hi as f32) as usize
    }
}

/// What [`ring`] needs to evaluate the range membership of a cell.
struct Ring {
    /// Left edge of the grid and landmark x (metres).
    x0: f32,
    lx: f32,
    /// Cell side (metres).
    s: f32,
    /// The range's trapezoid.
    t: Trapezoid,
}

/// Combines cells `first..first + row.len()` of a row (at squared vertical
/// distance `dy2` from the landmark) with the range membership. Written
/// branch-free (selects, no `f32::max`/`min`, whose NaN rules block SIMD) so
/// that the loop vectorises, sqrt included; the value is
/// [`Trapezoid::linear`]'s, NaN distance giving the bias as there.
#[inline]
fn ring(row: &mut [f32], first: usize, k: &Ring, dy2: f32, combine: Combine) {
    let t = k.t;
    let half = 0.5 * t.core;
    let end = half + t.slope;
    let has_flank = t.slope > 0.0;
    let slope = if has_flank { t.slope } else { 1.0 };
    let member = |c: usize| {
        let dx = k.x0 + (c as f32 + 0.5) * k.s - k.lx;
        let u = ((dx * dx + dy2).sqrt() - t.center).abs();
        let flank = 1.0 - (u - half) / slope;
        let flank = if has_flank && u < end { flank } else { 0.0 };
        let v = if u <= half {
            t.height
        } else {
            t.height * flank
        };
        if v > t.bias {
            v
        } else {
            t.bias
        }
    };
    match combine {
        Combine::Product => {
            for (i, v) in row.iter_mut().enumerate() {
                *v *= member(first + i);
            }
        }
        Combine::Min => {
            for (i, v) in row.iter_mut().enumerate() {
                let f = member(first + i);
                *v = if f < *v { f } else { *v };
            }
        }
    }
}

impl FuzzyGrid {
    fn check_obs(
        landmark: (f32, f32),
        range: Option<f32>,
        bearing: Option<f32>,
    ) -> Result<(), GridError> {
        if !landmark.0.is_finite() {
            return Err(GridError::NonFinite {
                what: "landmark x",
                landmark: 0,
                value: landmark.0,
            });
        }
        if !landmark.1.is_finite() {
            return Err(GridError::NonFinite {
                what: "landmark y",
                landmark: 0,
                value: landmark.1,
            });
        }
        if let Some(r) = range {
            if !r.is_finite() {
                return Err(GridError::NonFinite {
                    what: "range",
                    landmark: 0,
                    value: r,
                });
            }
            if r < 0.0 {
                return Err(GridError::NegativeRange {
                    landmark: 0,
                    range: r,
                });
            }
        }
        if let Some(b) = bearing {
            if !b.is_finite() {
                return Err(GridError::NonFinite {
                    what: "bearing",
                    landmark: 0,
                    value: b,
                });
            }
        }
        Ok(())
    }

    /// Updates with a range reading `r` to a landmark at `(lx, ly)`. Returns
    /// the height of the plane before normalisation (1 − inconsistency).
    /// Rejects (and leaves the grid untouched on) non-finite or negative input.
    pub fn update_range(&mut self, lx: f32, ly: f32, r: f32) -> Result<f32, GridError> {
        Self::check_obs((lx, ly), Some(r), None)?;
        self.apply_pending();
        self.range_pass(lx, ly, r);
        Ok(self.finish_update())
    }

    /// Updates with a bearing reading only (needs the heading sets).
    pub fn update_bearing(&mut self, lx: f32, ly: f32, bearing: f32) -> Result<f32, GridError> {
        Self::check_obs((lx, ly), None, Some(bearing))?;
        self.apply_pending();
        self.bearing_pass(lx, ly, None, bearing);
        Ok(self.finish_update())
    }

    /// Updates with range and bearing of the same sighting; the two factors are
    /// independent and multiply before the combination with the plane.
    pub fn update_range_bearing(
        &mut self,
        lx: f32,
        ly: f32,
        r: f32,
        bearing: f32,
    ) -> Result<f32, GridError> {
        Self::check_obs((lx, ly), Some(r), Some(bearing))?;
        self.apply_pending();
        self.bearing_pass(lx, ly, Some(r), bearing);
        Ok(self.finish_update())
    }

    /// Updates with an [`Observation`] of a landmark from `table`.
    pub fn observe(&mut self, table: &LandmarkTable, obs: &Observation) -> Result<f32, GridError> {
        let m = table
            .get(obs.landmark)
            .ok_or(GridError::UnknownLandmark(obs.landmark))?;
        let tag = |e: GridError| match e {
            GridError::NonFinite { what, value, .. } => GridError::NonFinite {
                what,
                landmark: obs.landmark,
                value,
            },
            GridError::NegativeRange { range, .. } => GridError::NegativeRange {
                landmark: obs.landmark,
                range,
            },
            other => other,
        };
        match (obs.range, obs.bearing) {
            (Some(r), Some(b)) => self.update_range_bearing(m.x, m.y, r, b).map_err(tag),
            (Some(r), None) => self.update_range(m.x, m.y, r).map_err(tag),
            (None, Some(b)) => self.update_bearing(m.x, m.y, b).map_err(tag),
            (None, None) => Ok(self.last_height),
        }
    }

    fn range_pass(&mut self, lx: f32, ly: f32, r: f32) {
        let t = self.cfg.range.around(r);
        let w = 0.5 * t.core + t.slope;
        let r_out = r + w;
        let r_in = (r - w).max(0.0);
        let s = self.cell;
        let bias = t.bias;
        let combine = self.cfg.combine;
        let outside = |row: &mut [f32]| match combine {
            Combine::Product => row.iter_mut().for_each(|v| *v *= bias),
            Combine::Min => row.iter_mut().for_each(|v| *v = v.min(bias)),
        };
        let col_of = |x: f32| (x - self.x0) / s - 0.5; // fractional column of a centre
        let ring_ctx = Ring {
            x0: self.x0,
            lx,
            s,
            t,
        };
        for j in 0..self.ny {
            let y = self.y0 + (j as f32 + 0.5) * s;
            let dy = y - ly;
            let row = &mut self.h[j * self.nx..(j + 1) * self.nx];
            if dy.abs() > r_out {
                outside(row);
                continue;
            }
            let ox = (r_out * r_out - dy * dy).max(0.0).sqrt();
            // Column bounds are clamped as floats, so huge readings cannot
            // overflow an integer.
            let c_lo = to_col(col_of(lx - ox).floor() - 1.0, 0, self.nx);
            let c_hi = to_col(col_of(lx + ox).ceil() + 2.0, 0, self.nx); // exclusive
                                                                         // The hole of the annulus (cells certainly closer than r_in).
            let (mut h_lo, mut h_hi) = (c_lo, c_lo);
            if dy.abs() < r_in {
                let ix = (r_in * r_in - dy * dy).max(0.0).sqrt();
                let a = to_col(col_of(lx - ix).ceil() + 1.0, c_lo, c_hi);
                let b = to_col(col_of(lx + ix).floor(), a, c_hi);
                (h_lo, h_hi) = (a, b);
            }
            outside(&mut row[..c_lo]);
            outside(&mut row[c_hi..]);
            outside(&mut row[h_lo..h_hi]);
            let dy2 = dy * dy;
            // The annulus minus its hole, as two plain ranges so that the
            // membership loop has no skip test and vectorises.
            for (a, b) in [(c_lo, h_lo), (h_hi, c_hi)] {
                if a < b {
                    ring(&mut row[a..b], a, &ring_ctx, dy2, combine);
                }
            }
        }
    }

    fn bearing_pass(&mut self, lx: f32, ly: f32, range: Option<f32>, bearing: f32) {
        let rt = range.map(|r| self.cfg.range.around(r));
        let obs = self.cfg.bearing.around(0.0);
        let s = self.cell;
        let combine = self.cfg.combine;
        for j in 0..self.ny {
            let y = self.y0 + (j as f32 + 0.5) * s;
            let dy = ly - y;
            let base = j * self.nx;
            for c in 0..self.nx {
                let i = base + c;
                let dx = lx - (self.x0 + (c as f32 + 0.5) * s);
                let mut f = match rt {
                    Some(t) => t.linear((dx * dx + dy * dy).sqrt()),
                    None => 1.0,
                };
                let mut o = obs;
                o.center = super::wrap_pi(fast_atan2(dy, dx) - bearing);
                if self.delta[i] >= 2.0 * PI {
                    // Heading unknown: the intersection is the observation's
                    // set and the consistency is 1 (exactly what
                    // `intersect_angle` gives, without its work).
                    self.theta[i] = o.center;
                    self.delta[i] = o.core;
                    self.alpha[i] = o.slope;
                    self.bias[i] *= o.bias;
                    let v = &mut self.h[i];
                    *v = match combine {
                        Combine::Product => *v * f,
                        Combine::Min => v.min(f),
                    };
                    continue;
                }
                let a = Trapezoid {
                    center: self.theta[i],
                    core: self.delta[i],
                    slope: self.alpha[i],
                    height: 1.0,
                    bias: self.bias[i],
                };
                let (n, cons) = a.intersect_with_consistency(&o);
                f *= cons;
                self.theta[i] = n.center;
                self.delta[i] = n.core;
                self.alpha[i] = n.slope;
                self.bias[i] = n.bias;
                let v = &mut self.h[i];
                *v = match combine {
                    Combine::Product => *v * f,
                    Combine::Min => v.min(f),
                };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_atan2_matches_std() {
        let mut worst = 0.0f32;
        for i in -50..=50 {
            for j in -50..=50 {
                let (y, x) = (i as f32 * 0.37, j as f32 * 0.41);
                if x == 0.0 && y == 0.0 {
                    continue;
                }
                worst = worst.max(super::super::wrap_pi(fast_atan2(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(worst < 2e-5, "worst error {worst}");
    }
}
