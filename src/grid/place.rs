//! Place-constrained refinement: the place engine says *which place*, the grid says *where in
//! it* (DESIGN §7, issue 5 item 2).
//!
//! Each frame, the engine's possibility Π of every place caps the cells of that place's extent
//! ([`FuzzyGrid::cap_places`], cells in no place capped by `outside`), and the pose is the centre
//! of gravity of the capped plane *restricted to the chosen place's extent*. The cap is applied
//! to a scratch copy, never to the tracking grid: between places (where the robot spends much of
//! its time) a persistent cap by the small `outside` value would erase the belief the grid needs
//! to keep tracking. Extents are convex (discs and boxes), so a centre of gravity of cells inside
//! one lies inside it: the refined pose is in the chosen place by construction, and the question
//! the tests ask is whether the chosen place and the grid agree with the truth.
//!
//! Also here, because the place layer's maps need them: the map's landmarks as a
//! [`LandmarkTable`], its extents as [`Region`]s, and [`FuzzyGrid::update_position`], an update
//! by a direct, fuzzy position reading (what the office map's structured beacon gives: its
//! direction and distance put the robot at one point).
//!
//! # Complexity
//!
//! [`Refiner::refine`] is O(cells) (a copy, the cap, one sweep over the chosen extent's bounding
//! box); after the first call it allocates nothing.
//!
//! # Example
//!
//! ```
//! use lplace::grid::{FuzzyGrid, GridConfig, Region};
//! use lplace::grid::place::Refiner;
//! let g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 4.0, 2.0]).unwrap();
//! let places = vec![
//!     Region::Box { x_min: 0.0, y_min: 0.0, x_max: 1.0, y_max: 2.0 },
//!     Region::Disc { x: 3.0, y: 1.0, r: 0.5 },
//! ];
//! let mut r = Refiner::new(places, 0.1);
//! // Total ignorance in the grid: the pose is the middle of the chosen place.
//! let p = r.refine(&g, &[0.2, 1.0], 1).unwrap();
//! assert!((p.x - 3.0).abs() < 0.06 && (p.y - 1.0).abs() < 0.06);
//! ```

use super::{Cuts, FuzzyGrid, GridError, Landmark, LandmarkTable, Region, SensorModel};
use crate::map::{Extent, Map};
use serde::{Deserialize, Serialize};

/// A surveyed landmark with the survey's uncertainty (e.g. MRCLAM's `Landmark_Groundtruth.dat`),
/// the input of [`survey_landmarks`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LandmarkTruth {
    /// Subject id (6–20).
    pub subject: u32,
    /// x (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// Standard deviation of x (m).
    pub x_std: f64,
    /// Standard deviation of y (m).
    pub y_std: f64,
}

/// The map's places as cap regions, in place order.
pub fn place_regions(map: &Map) -> Vec<Region> {
    map.places()
        .iter()
        .map(|p| match p.extent {
            Extent::Radius(r) => Region::Disc {
                x: p.pose.0 as f32,
                y: p.pose.1 as f32,
                r: r as f32,
            },
            Extent::Box { x0, y0, x1, y1 } => Region::Box {
                x_min: x0 as f32,
                y_min: y0 as f32,
                x_max: x1 as f32,
                y_max: y1 as f32,
            },
        })
        .collect()
}

/// The map's landmarks and beacons that carry an `id` (the number sensors report), as a
/// landmark table, with each one's name. Landmarks without an id, or with one that does not fit
/// a `u32`, are left out: no reading can name them.
///
/// # Errors
/// [`GridError`] when the table rejects the positions or ids (e.g. two landmarks with one id).
pub fn map_landmarks(map: &Map) -> Result<(LandmarkTable, Vec<(String, u32)>), GridError> {
    let mut marks = Vec::new();
    let mut names = Vec::new();
    for l in map.landmarks() {
        let Some(id) = l.id.and_then(|i| u32::try_from(i).ok()) else {
            continue;
        };
        marks.push(Landmark {
            id,
            x: l.position.0 as f32,
            y: l.position.1 as f32,
        });
        names.push((l.name.clone(), id));
    }
    Ok((LandmarkTable::new(marks)?, names))
}

/// A surveyed landmark list (MRCLAM's `Landmark_Groundtruth.dat`) as a landmark table.
///
/// # Errors
/// [`GridError`] when the table rejects the positions or ids.
pub fn survey_landmarks(marks: &[LandmarkTruth]) -> Result<LandmarkTable, GridError> {
    LandmarkTable::new(
        marks
            .iter()
            .map(|m| Landmark {
                id: m.subject,
                x: m.x as f32,
                y: m.y as f32,
            })
            .collect(),
    )
}

/// A refined pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refined {
    /// The place it lies in.
    pub place: usize,
    /// x (metres).
    pub x: f32,
    /// y (metres).
    pub y: f32,
    /// Highest possibility of the uncapped grid inside the place: how far the metric belief
    /// agrees with the engine's choice (0 = not at all).
    pub agreement: f32,
    /// False when the grid had no belief left inside the place and the pose is the extent's
    /// centre.
    pub from_grid: bool,
}

/// Caps a copy of the grid by the place possibilities and estimates inside the chosen place.
#[derive(Debug, Clone)]
pub struct Refiner {
    regions: Vec<Region>,
    caps: Vec<(Region, f32)>,
    outside: f32,
    scratch: Option<FuzzyGrid>,
}

impl Refiner {
    /// A refiner for these place extents (index = place id); cells in no place are capped by
    /// `outside` (clamped to [0, 1]).
    pub fn new(regions: Vec<Region>, outside: f32) -> Self {
        let outside = if outside.is_nan() {
            0.0
        } else {
            outside.clamp(0.0, 1.0)
        };
        Refiner {
            caps: Vec::with_capacity(regions.len()),
            regions,
            outside,
            scratch: None,
        }
    }

    /// The place extents.
    pub fn regions(&self) -> &[Region] {
        &self.regions
    }

    /// The refined pose in place `chosen`, given every place's possibility (missing entries read
    /// as 0, values clamped to [0, 1], NaN as 0).
    ///
    /// # Errors
    /// [`GridError::BadRegion`] when `chosen` is not a place or a region is malformed.
    pub fn refine(
        &mut self,
        grid: &FuzzyGrid,
        possibility: &[f64],
        chosen: usize,
    ) -> Result<Refined, GridError> {
        let Some(&region) = self.regions.get(chosen) else {
            return Err(GridError::BadRegion {
                index: chosen,
                reason: "chosen place has no extent",
            });
        };
        self.caps.clear();
        for (k, r) in self.regions.iter().enumerate() {
            let p = possibility.get(k).copied().unwrap_or(0.0);
            let p = if p.is_nan() { 0.0 } else { p.clamp(0.0, 1.0) };
            self.caps.push((*r, p as f32));
        }
        let scratch = match &mut self.scratch {
            Some(s) if s.nx == grid.nx && s.ny == grid.ny => {
                s.h.copy_from_slice(&grid.h);
                s
            }
            slot => slot.insert(grid.clone()),
        };
        let agreement = max_in(grid, &region);
        scratch.cap_places(&self.caps, self.outside)?;
        let (x, y, from_grid) = match cog_in(scratch, &region) {
            Some((x, y)) => (x, y, true),
            None => {
                let (x, y) = centre(&region);
                (x, y, false)
            }
        };
        Ok(Refined {
            place: chosen,
            x,
            y,
            agreement,
            from_grid,
        })
    }
}

fn centre(r: &Region) -> (f32, f32) {
    match *r {
        Region::Box {
            x_min,
            y_min,
            x_max,
            y_max,
        } => (0.5 * (x_min + x_max), 0.5 * (y_min + y_max)),
        Region::Disc { x, y, .. } => (x, y),
    }
}

/// Cells whose centre lies in `r`, as `(index, x, y)`.
fn cells_in<'a>(g: &'a FuzzyGrid, r: &'a Region) -> impl Iterator<Item = (usize, f32, f32)> + 'a {
    let (x0, y0, x1, y1) = match *r {
        Region::Box {
            x_min,
            y_min,
            x_max,
            y_max,
        } => (x_min, y_min, x_max, y_max),
        Region::Disc { x, y, r } => (x - r, y - r, x + r, y + r),
    };
    let s = g.cell;
    // Bounding box in cells, clamped as floats so huge or NaN extents cannot overflow.
    let col = |v: f32| ((v - g.x0) / s).floor().clamp(0.0, g.nx as f32) as usize;
    let row = |v: f32| ((v - g.y0) / s).floor().clamp(0.0, g.ny as f32) as usize;
    let (c0, c1) = (col(x0), (col(x1) + 1).min(g.nx));
    let (r0, r1) = (row(y0), (row(y1) + 1).min(g.ny));
    (r0..r1).flat_map(move |j| {
        (c0..c1).filter_map(move |c| {
            let (px, py) = g.cell_center(c, j);
            r.contains(px, py).then_some((j * g.nx + c, px, py))
        })
    })
}

fn max_in(g: &FuzzyGrid, r: &Region) -> f32 {
    cells_in(g, r).fold(0.0f32, |m, (i, _, _)| m.max(g.h[i]))
}

/// Centre of gravity of the cells of `r` at or above the grid's `cog_cut` of their maximum,
/// weighted as the grid's own estimate weighs them ([`Cuts`]).
fn cog_in(g: &FuzzyGrid, r: &Region) -> Option<(f32, f32)> {
    let max = max_in(g, r);
    // The grid never goes below its floor; at the floor there is no belief left to weigh.
    if max <= g.cfg.floor {
        return None;
    }
    let cut = g.cfg.cog_cut * max;
    let (mut sw, mut sx, mut sy) = (0.0f64, 0.0f64, 0.0f64);
    for (i, x, y) in cells_in(g, r) {
        let v = g.h[i];
        let w = match g.cfg.cuts {
            Cuts::Hard if v >= cut => v,
            Cuts::Hard => 0.0,
            Cuts::Ramp => (v - cut).max(0.0),
        };
        sw += w as f64;
        sx += (w * x) as f64;
        sy += (w * y) as f64;
    }
    (sw > 0.0).then(|| ((sx / sw) as f32, (sy / sw) as f32))
}

impl FuzzyGrid {
    /// Updates with a direct reading of the position `(x, y)`: every cell is combined with the
    /// sensor model's trapezoid around 0 evaluated at the cell's distance from the point (the
    /// model's `*_rel` widths scale with `spread`, e.g. the distance the reading was derived
    /// over). Heading sets are untouched. Returns the height before normalisation.
    ///
    /// # Errors
    /// [`GridError::NonFinite`] on a non-finite point or spread; the grid is then unchanged.
    pub fn update_position(
        &mut self,
        x: f32,
        y: f32,
        model: &SensorModel,
        spread: f32,
    ) -> Result<f32, GridError> {
        for (what, v) in [("position x", x), ("position y", y), ("spread", spread)] {
            if !v.is_finite() {
                return Err(GridError::NonFinite {
                    what,
                    landmark: 0,
                    value: v,
                });
            }
        }
        self.apply_pending();
        let m = spread.abs();
        let t = super::Trapezoid::new(
            0.0,
            2.0 * (model.core_abs + model.core_rel * m),
            model.slope_abs + model.slope_rel * m,
            1.0,
            model.bias,
        );
        let combine = self.cfg.combine;
        for j in 0..self.ny {
            for c in 0..self.nx {
                let (px, py) = self.cell_center(c, j);
                let f = t.linear((px - x).hypot(py - y));
                let v = &mut self.h[j * self.nx + c];
                *v = match combine {
                    super::Combine::Product => *v * f,
                    super::Combine::Min => v.min(f),
                };
            }
        }
        Ok(self.finish_update())
    }
}
