//! Parameters of the Fuzzy Position Grid, loadable from RON.
//!
//! Every number the grid uses lives here so that it can be changed in a file
//! (`config/grid-*.ron`) without touching code. [`GridConfig::default`]
//! documents the defaults, which were chosen for a camera measuring range and
//! bearing to landmarks a few metres away (MRCLAM dataset 7).

use super::{Blur, GridError, Trapezoid};
use serde::{Deserialize, Serialize};

/// How an observation's possibility distribution is combined with the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Combine {
    /// `G · S` — paper 000's choice: independent observations reinforce.
    #[default]
    Product,
    /// `min(G, S)` — idempotent; use when observations may repeat each other.
    Min,
}

/// Shape of the dilation's structuring element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum ElementShape {
    /// Regular octagon (row, column and both diagonal passes): the closest
    /// decomposable shape to a disc, at most 8 % wider than it.
    #[default]
    Octagon,
    /// Square (row and column passes only): half the cost, 41 % wider along
    /// the diagonals.
    Square,
}

/// The t-norm of the prediction's dilation `sup_q T(G(q), B(p − q))` ([`crate::grid::dilate`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Dilation {
    /// `T = min`: paper 000's eq. (3). Exact by one shifted maximum per level of the element,
    /// so its cost grows with the radius where the belief varies within reach.
    #[default]
    SupMin,
    /// `T(a, b) = max(0, a + b − 1)`: splits exactly into a flat dilation by the core and a
    /// max-plus dilation by a cone, O(1) per cell at every radius
    /// (`grid::dilate::lukasiewicz`). A cell at distance `d` into the flank loses `d/s`
    /// instead of being capped at `1 − d/s`, so high plateaus spread less far than under min.
    Lukasiewicz,
}

/// How the estimate's cuts (`cog_cut`, `top_cut`) select cells ([`crate::grid::estimate`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Cuts {
    /// A cell counts whole at or above the cut and not at all below it: the estimate jumps when
    /// a cell's possibility crosses a cut, so a change of the inputs far below what they are
    /// known to (a landmark moved by a millimetre) can move the run by a cell.
    #[default]
    Hard,
    /// Weights fall linearly to 0 at the cut: the centre of gravity weighs `h − cut` (not `h`),
    /// and a cell's share of the top region (its area, and its weight in the heading) is
    /// `(h − top)/(max − top)` clamped to [0, 1]. Every step from the belief to the estimate is
    /// then continuous in the belief.
    Ramp,
}

/// What becomes of the part of the predicted displacement below a whole cell
/// ([`crate::grid::predict`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Shift {
    /// The plane moves by whole cells and the rest is carried to the next prediction: a change
    /// of the inputs far below what they are known to (a landmark moved by a millimetre, a value
    /// by 1 %) can round one displacement the other way and move the whole belief by a cell,
    /// and the run goes on from there.
    #[default]
    Cells,
    /// The plane moves by whole cells and the cell lattice by the rest: the grid's origin is
    /// the extent's corner plus the carried sub-cell displacement (under half a cell per axis),
    /// so the belief moves exactly with the displacement and a rounding the other way gives the
    /// same belief on the same points of the plane.
    Lattice,
}

/// The heading sets of the cells whose possibility the motion blur raises
/// ([`crate::grid::blur`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum RaisedHeadings {
    /// Each cell keeps its own set (the dilation acts on the plane only, paper 000): a cell
    /// that sat at the floor, its heading forgotten or its bias raised near 1, comes out of a
    /// long blur at the top, saying that any heading is possible, and the next bearing reading
    /// then favours it over its neighbours that know the heading. Which cells sat at the floor
    /// turns on values near 1e-8, which a millimetre or 1 % of a value changes.
    #[default]
    Keep,
    /// A raised cell's set moves towards the belief's heading (the estimate's, turned by the
    /// odometry, core `bearing.core_abs` plus the prediction's widening, flank
    /// `bearing.slope_abs`, bias `1 − R̄`) by the share of its new possibility that the blur
    /// brought, `(h′ − h)/h′`: continuous in the belief, and the possibility moved by the blur
    /// carries the heading it came with.
    Inherit,
}

/// Where a cell's heading set comes from once the belief's heading is known
/// ([`crate::grid::headings`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum HeadingSets {
    /// Each cell keeps its own set, narrowed by every bearing reading there and moved with the
    /// cell (paper 000's 2½-D grid). The plane is shifted along the *estimate's* heading, not
    /// along each cell's, so a cell whose set is wrong is moved as if it were right, and a
    /// bearing read through a wrong narrow set cuts the cell down whoever is right.
    #[default]
    PerCell,
    /// Whenever the prediction shifts the plane along the estimate's heading (its weight is 1,
    /// see [`FuzzyGrid::directed_weight`](crate::grid::FuzzyGrid::directed_weight)), every
    /// cell's set becomes the belief's (the heading the shift used, turned by the odometry,
    /// core `bearing.core_abs` plus the prediction's widening, flank `bearing.slope_abs`, bias
    /// `1 − R̄`): a bearing reading is then read with the heading the motion assumed, and only
    /// its position information is new. Before the heading is known the sets stay per cell.
    /// The heading is then one hypothesis: one that is wrong when it first passes the gate is
    /// every cell's, and the bearings pull the position sideways to agree with it.
    Shared,
}

/// How the prediction moves each cell ([`crate::grid::classes`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub enum CellMotion {
    /// The whole plane is shifted along the estimate's heading (paper 000): a cell whose own
    /// heading set disagrees is moved as if it agreed.
    #[default]
    Plane,
    /// After the plane's shift, each cell whose heading set is clear (bias ≤ `max_bias`,
    /// support `Δ + 2α` ≤ `max_width` radians) is moved further, so that in all it moves along
    /// its own heading: cells are put in `bins` classes by their set's centre relative to the
    /// estimate's heading, each class moved by the odometry turned by its heading, less what
    /// the plane's shift already moved it (sub-cell remainders carried per class), taking the
    /// maximum where cells land. Cells without a clear heading move with the plane, as before.
    HeadingClasses {
        /// Classes over the circle, from 2 to [`MAX_HEADING_BINS`].
        bins: u32,
        /// Largest heading bias of a cell that moves along its own heading, in [0, 1].
        max_bias: f32,
        /// Largest support `Δ + 2α` (radians) of a cell that moves along its own heading.
        max_width: f32,
    },
}

/// The largest [`CellMotion::HeadingClasses`] `bins` accepted.
pub const MAX_HEADING_BINS: u32 = 64;

impl CellMotion {
    /// Whether the values are usable (see the variants).
    fn is_valid(&self) -> bool {
        match *self {
            CellMotion::Plane => true,
            CellMotion::HeadingClasses {
                bins,
                max_bias,
                max_width,
            } => {
                (2..=MAX_HEADING_BINS).contains(&bins)
                    && (0.0..=1.0).contains(&max_bias)
                    && max_width.is_finite()
                    && max_width >= 0.0
            }
        }
    }
}

/// A sensor model: the trapezoid `⟨r, Δ, α, 1, b⟩` put around a reading `r`.
///
/// Widths grow with the reading (`core = core_abs + core_rel · |r|`, same for
/// the flank) because camera range errors grow with distance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorModel {
    /// Constant part of the core width Δ (metres or radians).
    pub core_abs: f32,
    /// Part of the core width proportional to the reading.
    pub core_rel: f32,
    /// Constant part of the flank width α.
    pub slope_abs: f32,
    /// Part of the flank width proportional to the reading.
    pub slope_rel: f32,
    /// Bias b: possibility that the reading is an outlier.
    pub bias: f32,
}

impl SensorModel {
    /// The fuzzy set around a reading. `reading` is assumed finite.
    pub fn around(&self, reading: f32) -> Trapezoid {
        let m = reading.abs();
        Trapezoid::new(
            reading,
            self.core_abs + self.core_rel * m,
            self.slope_abs + self.slope_rel * m,
            1.0,
            self.bias,
        )
    }

    fn validate(&self, which: &'static str) -> Result<(), GridError> {
        let vals = [self.core_abs, self.core_rel, self.slope_abs, self.slope_rel];
        if vals.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return Err(GridError::BadConfig {
                field: which,
                reason: "widths must be finite and ≥ 0",
            });
        }
        if !(0.0..=1.0).contains(&self.bias) {
            return Err(GridError::BadConfig {
                field: which,
                reason: "bias must be in [0, 1]",
            });
        }
        Ok(())
    }
}

/// All parameters of the grid, its update, prediction and estimate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GridConfig {
    /// Side of a square cell in metres. Default 0.1 (paper 000 uses 10 cm).
    pub cell_size: f32,
    /// Margin in metres added around the landmarks' bounding box when the
    /// extent of the grid is derived from a landmark table. Default 1.5.
    pub margin: f32,
    /// Explicit extent `[x_min, y_min, x_max, y_max]` in metres; overrides the
    /// landmark box when set. Default none.
    pub bounds: Option<[f32; 4]>,
    /// Range sensor model. Default core 0.1 m + 5 % of r, flank 0.2 m + 15 %
    /// (MRCLAM's camera under-reads by up to 10 % at the edge of its field of
    /// view, repeatedly), bias 0.1.
    pub range: SensorModel,
    /// Bearing sensor model. Default core 0.06 rad, flank 0.1 rad, bias 0.1.
    pub bearing: SensorModel,
    /// Plane combination. Default product.
    pub combine: Combine,
    /// Rescale the plane so its maximum is 1 after each update (possibilistic
    /// normalisation). Without it a long run under product drives every cell
    /// towards 0 and the top region loses meaning. Default true.
    pub normalize: bool,
    /// Structuring element shape. Default octagon.
    pub element: ElementShape,
    /// T-norm of the dilation. Default sup-min (paper 000).
    pub dilation: Dilation,
    /// When a motion blur too small for the dilation's passes to reach a neighbour is applied
    /// ([`crate::grid::blur`]): `Drop` (default) spends it, `Carry(level: …)` keeps it pending
    /// until it moves possibility one cell.
    pub blur: Blur,
    /// Whether the sub-cell part of a shift moves the cell lattice ([`Shift`]). Default
    /// `Cells` (it is carried only).
    pub shift: Shift,
    /// The heading sets of cells the blur raises ([`RaisedHeadings`]). Default `Keep`.
    pub raised_headings: RaisedHeadings,
    /// Where the cells' heading sets come from once the heading is known ([`HeadingSets`]).
    /// Default `PerCell`.
    pub heading_sets: HeadingSets,
    /// How the prediction moves each cell ([`CellMotion`]). Default `Plane`.
    pub cell_motion: CellMotion,
    /// Factor on the odometry's translation (forward and left) before the grid uses it: a
    /// calibration of the odometry against ground truth. Default 1. (MRCLAM's velocity
    /// commands over-read the distance travelled by 9–13 % on every robot.)
    pub forward_scale: f32,
    /// Factor on the odometry's rotation, likewise. Default 1.
    pub turn_scale: f32,
    /// Radius (metres) at which the element's possibility is still 1, per
    /// metre travelled: odometry can be trusted to this fraction. Default 0.1.
    pub core_per_metre: f32,
    /// Extra radius (metres, flank of the element) per metre travelled.
    /// Default 0.2.
    pub flank_per_metre: f32,
    /// Flank radius (metres) added per second regardless of odometry, for
    /// slippage and unmodelled pushes. Default 0.02.
    pub flank_per_second: f32,
    /// Flank radius (metres) per metre travelled that is added when the
    /// heading is unreliable and the odometry cannot be given a direction:
    /// the motion then blurs isotropically by this much. Default 1.0.
    pub undirected_per_metre: f32,
    /// Widening of every cell's heading core Δ per radian turned. Default 0.1.
    pub delta_per_radian: f32,
    /// Widening of Δ per second. Default 0.01 rad.
    pub delta_per_second: f32,
    /// Heading reliability (mean resultant length of the top region's
    /// headings, in [0, 1]) above which odometry shifts the grid along the
    /// estimated heading. Default 0.8.
    pub directed_min_reliability: f32,
    /// Width of the ramp below `directed_min_reliability` over which the share of the
    /// displacement shifted along the estimated heading rises from 0 to 1 (the rest blurs
    /// undirected, [`crate::grid::predict`]). 0 (default): a step, the whole displacement or
    /// none, which a heading reliability moving by a hair across the threshold flips.
    pub directed_ramp: f32,
    /// Values below this are flushed to 0 after an update, which keeps the
    /// arithmetic out of subnormal floats. Default 1e-9.
    pub flush_below: f32,
    /// Possibility every cell keeps after normalisation: the robot may have
    /// been carried anywhere (paper 000 §1: "the robot can be pushed … in
    /// unexpected locations"). A cell raised to the floor forgets its heading
    /// (its set becomes the full circle), and a cell above it gets its heading
    /// bias raised to `floor / h`, so that `π(x, y, θ) ≥ floor` for every
    /// heading; fresh consistent observations can
    /// build a new peak there within a few updates: this is what makes the
    /// grid recover from a kidnap. 0 disables it. Default 1e-8: on MRCLAM,
    /// 1e-3…1e-5 let a run of biased readings of one landmark cluster pull
    /// the estimate onto a distant ring of floor cells.
    pub floor: f32,
    /// Fraction of the maximum that defines the region whose centre of
    /// gravity is the position estimate. Default 0.5.
    pub cog_cut: f32,
    /// Whether `cog_cut` and `top_cut` select cells whole or by a ramp ([`Cuts`]). Default
    /// `Hard`.
    pub cuts: Cuts,
    /// Fraction of the maximum that defines the *top region* whose area
    /// drives the reliability. Default 0.9.
    pub top_cut: f32,
    /// Reference area (m²) in the reliability `h_max · A_ref / (A_ref + A_top)`.
    /// Default 0.25.
    pub reliability_area: f32,
    /// Reliability from which the estimate counts as a *fix*. Default 0.5.
    pub fix_reliability: f32,
    /// Shortest time (s) between two readings of the same landmark that the
    /// driver (in `localize`, a layer above) feeds to the grid; readings in between
    /// are skipped. A camera rereads the same landmark several times a second
    /// with the same error, and the product update assumes independent
    /// readings: without thinning, one biased landmark counts many times.
    /// 0 keeps every reading. Default 1 s: on MRCLAM it removes the multi-metre
    /// jumps that runs of biased readings caused (worst error 5 m → 1.2 m).
    pub reobserve_interval: f32,
    /// How many grids the localizer (`localize::grid`, a layer above) runs side by side, each
    /// on the cell lattice moved by a different fraction of a cell, averaging their estimates
    /// (averaged shifted histograms). One grid's estimate depends on where the cell boundaries
    /// fall: a reading crossing a cut, or a shift rounding the other way, moves it by a cell,
    /// and a landmark moved by a millimetre can do that. Averaging over lattices that place the
    /// boundaries evenly within a cell smooths this out, at `lattices` times the cost.
    /// Default 1 (one grid). At most [`MAX_LATTICES`].
    pub lattices: u32,
}

/// The largest [`GridConfig::lattices`] accepted.
pub const MAX_LATTICES: u32 = 64;

impl Default for GridConfig {
    fn default() -> Self {
        GridConfig {
            cell_size: 0.1,
            margin: 1.5,
            bounds: None,
            range: SensorModel {
                core_abs: 0.1,
                core_rel: 0.05,
                slope_abs: 0.2,
                slope_rel: 0.15,
                bias: 0.1,
            },
            bearing: SensorModel {
                core_abs: 0.06,
                core_rel: 0.0,
                slope_abs: 0.1,
                slope_rel: 0.0,
                bias: 0.1,
            },
            combine: Combine::Product,
            normalize: true,
            element: ElementShape::Octagon,
            dilation: Dilation::SupMin,
            blur: Blur::Drop,
            shift: Shift::Cells,
            raised_headings: RaisedHeadings::Keep,
            heading_sets: HeadingSets::PerCell,
            cell_motion: CellMotion::Plane,
            forward_scale: 1.0,
            turn_scale: 1.0,
            core_per_metre: 0.1,
            flank_per_metre: 0.2,
            flank_per_second: 0.02,
            undirected_per_metre: 1.0,
            delta_per_radian: 0.1,
            delta_per_second: 0.01,
            directed_min_reliability: 0.8,
            directed_ramp: 0.0,
            flush_below: 1e-9,
            floor: 1e-8,
            cog_cut: 0.5,
            cuts: Cuts::Hard,
            top_cut: 0.9,
            reliability_area: 0.25,
            fix_reliability: 0.5,
            reobserve_interval: 1.0,
            lattices: 1,
        }
    }
}

impl GridConfig {
    /// Parses a RON document (missing fields take their defaults) and checks it.
    pub fn from_ron(text: &str) -> Result<Self, GridError> {
        let cfg: GridConfig = crate::core::config::from_ron(text).map_err(|e| GridError::Ron {
            line: e.line,
            column: e.column,
            problem: e.problem,
        })?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Checks ranges; every consumer may assume a validated configuration.
    pub fn validate(&self) -> Result<(), GridError> {
        let pos = |v: f32| v.is_finite() && v > 0.0;
        let nonneg = |v: f32| v.is_finite() && v >= 0.0;
        let unit = |v: f32| (0.0..=1.0).contains(&v);
        if !pos(self.cell_size) {
            return Err(GridError::BadConfig {
                field: "cell_size",
                reason: "must be finite and > 0",
            });
        }
        for (field, v) in [
            ("margin", self.margin),
            ("core_per_metre", self.core_per_metre),
            ("flank_per_metre", self.flank_per_metre),
            ("flank_per_second", self.flank_per_second),
            ("undirected_per_metre", self.undirected_per_metre),
            ("delta_per_radian", self.delta_per_radian),
            ("delta_per_second", self.delta_per_second),
            ("flush_below", self.flush_below),
            ("reobserve_interval", self.reobserve_interval),
            ("directed_ramp", self.directed_ramp),
            ("forward_scale", self.forward_scale),
            ("turn_scale", self.turn_scale),
        ] {
            if !nonneg(v) {
                return Err(GridError::BadConfig {
                    field,
                    reason: "must be finite and ≥ 0",
                });
            }
        }
        for (field, v) in [
            ("directed_min_reliability", self.directed_min_reliability),
            ("floor", self.floor),
            ("cog_cut", self.cog_cut),
            ("top_cut", self.top_cut),
            ("fix_reliability", self.fix_reliability),
        ] {
            if !unit(v) {
                return Err(GridError::BadConfig {
                    field,
                    reason: "must be in [0, 1]",
                });
            }
        }
        if !pos(self.reliability_area) {
            return Err(GridError::BadConfig {
                field: "reliability_area",
                reason: "must be finite and > 0",
            });
        }
        if let Some(b) = self.bounds {
            if b.iter().any(|v| !v.is_finite()) || b[2] <= b[0] || b[3] <= b[1] {
                return Err(GridError::BadConfig {
                    field: "bounds",
                    reason: "need finite x_min < x_max, y_min < y_max",
                });
            }
        }
        if !(1..=MAX_LATTICES).contains(&self.lattices) {
            return Err(GridError::BadConfig {
                field: "lattices",
                reason: "must be from 1 to 64",
            });
        }
        self.validate_modes()?;
        self.range.validate("range")?;
        self.bearing.validate("bearing")?;
        Ok(())
    }

    /// The values inside the enumerated options ([`Blur`], [`CellMotion`]).
    fn validate_modes(&self) -> Result<(), GridError> {
        if !self.blur.is_valid() {
            return Err(GridError::BadConfig {
                field: "blur",
                reason: "Carry's level must be in (0, 1]",
            });
        }
        if !self.cell_motion.is_valid() {
            return Err(GridError::BadConfig {
                field: "cell_motion",
                reason: "HeadingClasses needs bins in 2..=64, max_bias in [0, 1], max_width ≥ 0",
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_unknown_keys_and_defaults_omitted_ones() {
        let ok = GridConfig::from_ron("(cell_size: 0.2)").unwrap();
        assert_eq!(ok.cell_size, 0.2);
        assert_eq!(ok.floor, GridConfig::default().floor);
        for text in [
            "(cell_size: 0.2, totally_bogus_field: 1)",
            "(range: (core_abs: 0.1, core_rel: 0.0, slope_abs: 0.1, slope_rel: 0.0, bias: 0.1, \
             totally_bogus_field: 1))",
        ] {
            match GridConfig::from_ron(text) {
                Err(GridError::Ron { problem, line, .. }) => {
                    let message = problem.to_string();
                    assert!(message.contains("totally_bogus_field"), "{message}");
                    assert_eq!(line, 1);
                }
                other => panic!("{text}: {other:?}"),
            }
        }
        // A misspelt key names the one meant.
        match GridConfig::from_ron("(cell_sise: 0.2)") {
            Err(GridError::Ron {
                problem: crate::core::config::RonProblem::UnknownKey { key, nearest, .. },
                ..
            }) => assert_eq!((key.as_str(), nearest), ("cell_sise", Some("cell_size"))),
            other => panic!("{other:?}"),
        }
    }
}
