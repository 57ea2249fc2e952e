//! The place cap: the place engine's possibilities bound the cells of each
//! place's extent (DESIGN §7: "inside a chosen place, the place possibilities
//! act as a prior mask over the cells of each place's extent").
//!
//! Each region (an axis-aligned box or a disc, in metres) comes with a
//! possibility; a cell's cap is the largest value among the regions that
//! contain its centre (places may overlap, and being in either is possible to
//! the larger degree), or `outside` when no region contains it. Every cell
//! becomes `min(h, cap)`. Heading sets are untouched, and the plane is not
//! renormalised here (the next update does it), so the caller can read how
//! much of the belief survived from [`FuzzyGrid::estimate`]'s height.
//!
//! # Complexity
//!
//! O(cells + Σ cells covered by the regions' bounding boxes); uses the
//! grid's scratch plane, no allocation.
//!
//! # Example
//!
//! ```
//! use lplace::grid::{FuzzyGrid, GridConfig, Region};
//! let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 2.0, 1.0]).unwrap();
//! let rooms = [(Region::Box { x_min: 0.0, y_min: 0.0, x_max: 1.0, y_max: 1.0 }, 0.8)];
//! g.cap_places(&rooms, 0.1).unwrap();
//! assert_eq!(g.possibility(2, 2), 0.8);
//! assert_eq!(g.possibility(15, 2), 0.1);
//! ```

use super::{FuzzyGrid, GridError};
use serde::{Deserialize, Serialize};

/// A place's extent in the metric frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Region {
    /// Axis-aligned box (bounds inclusive).
    Box {
        /// Left edge.
        x_min: f32,
        /// Bottom edge.
        y_min: f32,
        /// Right edge.
        x_max: f32,
        /// Top edge.
        y_max: f32,
    },
    /// Disc (boundary inclusive).
    Disc {
        /// Centre x.
        x: f32,
        /// Centre y.
        y: f32,
        /// Radius (≥ 0).
        r: f32,
    },
}

impl Region {
    fn check(&self, index: usize) -> Result<[f32; 4], GridError> {
        let bad = |reason| GridError::BadRegion { index, reason };
        match *self {
            Region::Box {
                x_min,
                y_min,
                x_max,
                y_max,
            } => {
                if ![x_min, y_min, x_max, y_max].iter().all(|v| v.is_finite()) {
                    return Err(bad("non-finite coordinate"));
                }
                if x_max < x_min || y_max < y_min {
                    return Err(bad("box with max < min"));
                }
                Ok([x_min, y_min, x_max, y_max])
            }
            Region::Disc { x, y, r } => {
                if ![x, y, r].iter().all(|v| v.is_finite()) {
                    return Err(bad("non-finite coordinate"));
                }
                if r < 0.0 {
                    return Err(bad("negative radius"));
                }
                Ok([x - r, y - r, x + r, y + r])
            }
        }
    }

    /// Does the region contain the point?
    pub fn contains(&self, px: f32, py: f32) -> bool {
        match *self {
            Region::Box {
                x_min,
                y_min,
                x_max,
                y_max,
            } => px >= x_min && px <= x_max && py >= y_min && py <= y_max,
            Region::Disc { x, y, r } => (px - x) * (px - x) + (py - y) * (py - y) <= r * r,
        }
    }
}

impl FuzzyGrid {
    /// Caps every cell by its places' possibility (see the module docs).
    /// Values must be in [0, 1]; on any error the grid is left unchanged.
    pub fn cap_places(&mut self, regions: &[(Region, f32)], outside: f32) -> Result<(), GridError> {
        if !(0.0..=1.0).contains(&outside) {
            return Err(GridError::BadRegion {
                index: regions.len(),
                reason: "outside value not in [0, 1]",
            });
        }
        for (k, (r, v)) in regions.iter().enumerate() {
            r.check(k)?;
            if !(0.0..=1.0).contains(v) {
                return Err(GridError::BadRegion {
                    index: k,
                    reason: "possibility not in [0, 1]",
                });
            }
        }
        // -1 marks "in no region yet".
        self.work.plane.fill(-1.0);
        for (k, (r, v)) in regions.iter().enumerate() {
            let [x0, y0, x1, y1] = r.check(k)?;
            let s = self.cell;
            let col = |x: f32| ((x - self.x0) / s - 0.5).clamp(-1.0, self.nx as f32);
            let row = |y: f32| ((y - self.y0) / s - 0.5).clamp(-1.0, self.ny as f32);
            let c0 = col(x0).ceil().max(0.0) as usize;
            let c1 = (col(x1).floor() + 1.0).max(0.0) as usize;
            let r0 = row(y0).ceil().max(0.0) as usize;
            let r1 = (row(y1).floor() + 1.0).max(0.0) as usize;
            for j in r0..r1.min(self.ny) {
                for c in c0..c1.min(self.nx) {
                    let (px, py) = self.cell_center(c, j);
                    if r.contains(px, py) {
                        let cell = &mut self.work.plane[j * self.nx + c];
                        *cell = cell.max(*v);
                    }
                }
            }
        }
        for (h, &c) in self.h.iter_mut().zip(&self.work.plane) {
            let cap = if c < 0.0 { outside } else { c };
            *h = h.min(cap);
        }
        Ok(())
    }
}
