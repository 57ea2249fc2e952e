//! Tracking over time (DESIGN §3 "Over time"): place possibilities carried along the map graph
//! from frame to frame, gated by odometry against path lengths, then intersected with each
//! frame's evidence — paper 000's "blur, then intersect" cycle on the topological graph, and
//! paper 003's "odometry used for consistency checks with the metrics of the map".
//!
//! # The model
//! The tracker keeps, per place `i`, an **anchor**: a possibility `m_i` that the robot was at
//! `P_i` when it last had evidence of it, and the odometry distance `s_i` travelled since then.
//! Each step, with `ds` the length of the odometry increment and `e_j` the frame's normalised
//! possibility `Π'_j` (taken to the power `w ≤ 1` of the distance moved when
//! `evidence_length_m` is set, so that evidence counts per metre, not per frame), `α_j` its
//! support:
//!
//! ```text
//! s_i  ← s_i + ds
//! R_ij = μ(s_i; L'_ij)                   trapezoid centred on L'_ij, the shortest path length
//!                                         between P_i and P_j less the radii of both extents
//!                                         (evidence starts at the edge of a place, not its centre)
//! pred_j = max_i min(m_i, R_ij)          blur: carried along the graph
//! c_j    = T(max(pred_j, b), e_j)        intersect with the evidence; b is the bias floor
//! π'_j   = c_j / max c                   (product normalisation; min-based selectable)
//! N_j    = 1 − max_{k≠j} π'_k,   Inc = 1 − max c
//! ```
//!
//! # With a heading: displacement gates
//! A frame may carry the robot's heading in the map frame (a compass, or the axis-locked estimate
//! of [`crate::percept::compass`]). Then each anchor also integrates the **displacement**
//! `D_i` since it was set, each odometry increment rotated by the heading of the frame it
//! started from, and its gate compares *where* the robot went, not only how far:
//!
//! ```text
//! D_i  ← D_i + Rot(θ_prev)·(dx, dy)
//! d_ij = distance between the extent of P_i moved by D_i and the extent of P_j (0 if they meet)
//! R_ij = μ(d_ij)                          1 up to tolerance_d + tolerance_d_rel·s_i, then falling
//!                                         to 0 over slope_d + slope_d_rel·s_i (odometry drifts
//!                                         with the distance travelled)
//! ```
//!
//! This is the DESIGN's "odometry used for consistency checks with the metrics of the map" with
//! the map's metric layer (place extents) rather than its path lengths: a robot that takes the
//! long way round a ring corridor is not lost by it, and two places equally far along the graph
//! but in different directions are told apart. The extent of `P_i` stands for where the robot
//! was when it last had evidence of `P_i` (anywhere in it). Boxes and discs are both taken as
//! boxes with a rounding radius (a disc: its centre, rounded by its radius), so one gap formula
//! serves every pair. An anchor whose displacement is unknown — an increment
//! arrived with no heading for it — falls back to the path gate above until it is set again.
//! Between two frames with headings the increment is rotated by the earlier one; a missing
//! heading is bridged by the odometry's turn from the last known one.
//!
//! When `max c` falls below `conflict`, belief and evidence do not overlap; as paper 000 does
//! for incompatible fuzzy sets, the tracker then keeps their union, `c_j = max(pred_j, e_j)`, and
//! reports the conflict as `Inc` (so the frame is *disoriented, inconsistent*).
//!
//! The **bias floor** `b` (paper 000's trapezoid bias: the possibility that the belief is "somewhere
//! else") keeps every place possible to degree `b`, so evidence that contradicts the carried belief
//! — a kidnap — wins within a frame or two instead of being vetoed forever.
//!
//! Anchors are then revised: each is intersected with how well the frame agrees with it
//! (`max(1 − max_j α_j, max_j min(R_ij, e_j))`: the robot is between places, or at a place the
//! anchor predicts), floored by `b`; a place whose support reaches `anchor_support` re-anchors
//! (`m_j = π'_j`, `s_j = 0`); the anchors are renormalised to height 1. A tracked decision is
//! the rule file's decision (threshold, margin) on `π'`, `N`, `Inc`, except that it is
//! *disoriented, nothing above threshold* when no place has support `≥ min_support` in the
//! frame: tracking sharpens evidence, it does not announce a place from odometry alone.
//!
//! # Sparse: the horizon
//! Both gates look only at the places within `horizon_m` (default 50 m) of `P_i` along the
//! graph (`L'_ij ≤ horizon_m`); the others — and places with no path at all — get `R_ij = 0`.
//! Construction runs one bounded search per place ([`crate::map::dijkstra`]); a step visits, per
//! anchor, only the pairs its gate can reach (a path gate: a window of the row sorted by `L'`).
//! Memory and time grow with `n` times the places within the horizon, not with `n²`. Within
//! that, a step reads only what can change its result: the blur carries the anchors at or above
//! the bias floor, and the revision reads pairs only from the places that can raise an anchor
//! (see `Tracker::blur` and `Tracker::revise`); `R_ij` is computed where it is read.
//!
//! `step` allocates nothing and cannot panic: all buffers are sized at construction, and
//! evidence of the wrong length reads its missing places as "no evidence". Depends on `logic`
//! and `map` (path lengths, extents) only.

use super::grid_tracker::{GridTrackConfig, GridTracker};
use crate::core::Odometry;
#[cfg(test)]
use crate::logic::decide;
use crate::logic::{
    clamp_degree, Decision, DecisionParams, Disoriented, Normalisation, PlaceDistribution,
    Similarity, TNorm, TIE_TOLERANCE,
};

mod pass;
use crate::map::dijkstra::BoundedDijkstra;
use crate::map::{Extent, Map};
use serde::{Deserialize, Serialize};

/// Either tracker, as the configuration chooses: along the map graph ([`Tracker`]) or on a
/// metric grid over the place extents ([`GridTracker`], when `grid` is set).
#[derive(Debug, Clone)]
pub enum PlaceTracker {
    /// Along the map graph.
    Graph(Box<Tracker>),
    /// On a metric grid.
    Grid(Box<GridTracker>),
}

impl PlaceTracker {
    /// The tracker `cfg` asks for over `map`, deciding with `params`.
    pub fn new(map: &Map, params: DecisionParams, cfg: TrackerConfig) -> PlaceTracker {
        match cfg.grid {
            Some(_) => PlaceTracker::Grid(Box::new(GridTracker::new(map, params, &cfg))),
            None => PlaceTracker::Graph(Box::new(Tracker::new(map, params, cfg))),
        }
    }

    /// One frame (see [`Tracker::step`] and [`GridTracker::step`]). Allocates nothing.
    pub fn step(
        &mut self,
        evidence: &PlaceDistribution,
        odometry: Odometry,
        heading: Option<f64>,
    ) -> Decision {
        match self {
            PlaceTracker::Graph(t) => t.step(evidence, odometry, heading),
            PlaceTracker::Grid(t) => t.step(evidence, odometry, heading),
        }
    }

    /// The tracked distribution of the last step.
    pub fn distribution(&self) -> &PlaceDistribution {
        match self {
            PlaceTracker::Graph(t) => t.distribution(),
            PlaceTracker::Grid(t) => t.distribution(),
        }
    }

    /// The decision of the last step.
    pub fn decision(&self) -> Decision {
        match self {
            PlaceTracker::Graph(t) => t.decision(),
            PlaceTracker::Grid(t) => t.decision(),
        }
    }
}

/// A tracker's decision before any frame: disoriented (no place at all if the map has none).
/// How a frame carries the heading over (radians, map frame), for both trackers: the heading
/// the frame's motion started from and the one after it, from the last carried heading `prev`,
/// the frame's own `now` (finite, if it has one) and the odometry's turn `dtheta`. Before the
/// first heading the start is the first one turned back by the turn; a frame without a heading
/// is bridged by the turn from the last one.
pub(super) fn carry_heading(
    prev: Option<f64>,
    now: Option<f64>,
    dtheta: f64,
) -> (Option<f64>, Option<f64>) {
    let start = match (prev, now) {
        (Some(p), _) => Some(p),
        (None, Some(h)) if dtheta.is_finite() => Some(h - dtheta),
        _ => None,
    };
    let next = now.or_else(|| {
        prev.map(|h| h + dtheta)
            .filter(|h| h.is_finite())
            .map(|h| h.rem_euclid(std::f64::consts::TAU))
    });
    (start, next)
}

pub(super) fn undecided(n: usize) -> Decision {
    if n == 0 {
        Decision::Disoriented(Disoriented::NoPlaces)
    } else {
        Decision::Disoriented(Disoriented::NothingAboveThreshold {
            best: 0,
            support: 0.0,
        })
    }
}

/// A tracked decision stands only if some place has support ≥ `min_support` in the frame:
/// tracking sharpens evidence, it does not announce a place from odometry alone. `support` is
/// the chosen place's support.
pub(super) fn unless_unsupported(
    d: Decision,
    max_support: f64,
    min_support: f64,
    support: impl Fn(usize) -> f64,
) -> Decision {
    match d {
        Decision::Place { place, .. } if max_support < min_support => {
            Decision::Disoriented(Disoriented::NothingAboveThreshold {
                best: place,
                support: support(place),
            })
        }
        d => d,
    }
}

/// Hysteresis on the decision ([`TrackerConfig::hold`]): the place decided in the previous
/// frame, `prev`, stays decided while its necessity in `dist` is still at least `hold`, where
/// `now` would have named no place for another reason than inconsistency. `hold ≥ 1` turns it
/// off. A place that was chosen because it was necessary is not given up the moment a
/// neighbour's possibility creeps over `1 − θ`: when the belief straddles the boundary of two
/// places (it does over the last metre or so before every boundary) the place the robot was
/// in is still the better answer, and a new place must still meet the threshold to be chosen.
pub(super) fn held(prev: Decision, now: Decision, dist: &PlaceDistribution, hold: f64) -> Decision {
    match (prev, now) {
        (Decision::Place { place, .. }, Decision::Disoriented(why))
            if hold < 1.0 && !matches!(why, Disoriented::Inconsistent { .. }) =>
        {
            let necessity = dist.necessity.get(place).copied().unwrap_or(0.0);
            if necessity >= hold - TIE_TOLERANCE {
                Decision::Place { place, necessity }
            } else {
                now
            }
        }
        _ => now,
    }
}

/// Tracker parameters, loadable from RON (every field optional; defaults below).
///
/// ```ron
/// (bias: 0.1, tnorm: product, tolerance: 0.8, tolerance_rel: 0.1, slope: 1.0, slope_rel: 0.1,
///  anchor_support: 0.5, min_support: 0.3, normalisation: product, conflict: 0.3,
///  use_heading: true, tolerance_d: 0.5, tolerance_d_rel: 0.05, slope_d: 1.0, slope_d_rel: 0.05,
///  horizon_m: 50.0)
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TrackerConfig {
    /// Bias floor `b` under the carried belief (default 0.1).
    pub bias: f64,
    /// T-norm intersecting carried belief and evidence (default product).
    pub tnorm: TNorm,
    /// Half-width of the core of `R_ij`, metres: odometry within this of the path length is a
    /// full match (default 0.8).
    pub tolerance: f64,
    /// Extra half-core per metre of path (odometry drifts with distance; default 0.1).
    pub tolerance_rel: f64,
    /// Run of each slope of `R_ij`, metres (default 1.0).
    pub slope: f64,
    /// Extra slope per metre of path (default 0.1).
    pub slope_rel: f64,
    /// Support at which a place re-anchors (default 0.5).
    pub anchor_support: f64,
    /// Support some place needs in a frame for the tracker to choose any place (default 0.3).
    pub min_support: f64,
    /// Necessity the place decided in the previous frame needs to stay decided, below the rule
    /// file's threshold that a newly chosen place must meet: hysteresis. Default 1:
    /// none, every frame decides afresh.
    pub hold: f64,
    /// Normalisation of the tracked distribution (default product).
    pub normalisation: Normalisation,
    /// Height of the intersection below which belief and evidence are taken not to overlap,
    /// and their union is used instead (paper 000's rule for incompatible sets; default 0.3).
    pub conflict: f64,
    /// Use displacement gates when frames carry a heading (default true; false keeps the path
    /// gates whatever the stream carries).
    pub use_heading: bool,
    /// Displacement gate: distance between the moved extent and the target extent that is
    /// still a full match, metres (default 0.5).
    pub tolerance_d: f64,
    /// Extra full-match distance per metre travelled since the anchor (default 0.05).
    pub tolerance_d_rel: f64,
    /// Displacement gate: run of its slope, metres (default 1.0).
    pub slope_d: f64,
    /// Extra slope per metre travelled since the anchor (default 0.05).
    pub slope_d_rel: f64,
    /// Metres of travel one frame's evidence stands for, along the graph: the frame takes
    /// `e_j^w` for `e_j`, `w = min(1, d / evidence_length_m)` with `d` the distance moved since
    /// evidence was last taken, so that a dense log is not surer than a sparse one (DESIGN §12;
    /// the grid tracker has its own, [`GridTrackConfig::evidence_length_m`]). Default 0: every
    /// frame's evidence whole, as the bundled office recording (3–4 frames per metre) was
    /// tuned with.
    pub evidence_length_m: f64,
    /// Longest path, metres (less the radii of both extents, as `L'_ij`), along which an
    /// anchor's belief is carried: places farther from `P_i` along the graph get `R_ij = 0`
    /// from it, by either gate. This is what keeps the tracker sparse on large maps (issue 16):
    /// its memory and time grow with the places within the horizon, not with `n²`. Default
    /// 50 m, beyond any path of the bundled maps, and beyond where the default gates, widening
    /// 0.2 m per metre, still tell a path from its neighbours.
    pub horizon_m: f64,
    /// Track on a metric grid over the place extents instead of along the graph
    /// ([`super::grid_tracker`]); then only `bias` and `min_support` of the fields above apply.
    /// Default `None` (the graph).
    pub grid: Option<GridTrackConfig>,
}

impl Default for TrackerConfig {
    fn default() -> Self {
        TrackerConfig {
            bias: 0.1,
            tnorm: TNorm::Product,
            tolerance: 0.8,
            tolerance_rel: 0.1,
            slope: 1.0,
            slope_rel: 0.1,
            anchor_support: 0.5,
            min_support: 0.3,
            hold: 1.0,
            normalisation: Normalisation::Product,
            conflict: 0.3,
            use_heading: true,
            tolerance_d: 0.5,
            tolerance_d_rel: 0.05,
            slope_d: 1.0,
            slope_d_rel: 0.05,
            evidence_length_m: 0.0,
            horizon_m: DEFAULT_HORIZON_M,
            grid: None,
        }
    }
}

/// The default [`TrackerConfig::horizon_m`], metres.
pub const DEFAULT_HORIZON_M: f64 = 50.0;

/// Why a tracker configuration could not be read.
#[derive(Debug, thiserror::Error)]
pub enum TrackerConfigError {
    /// Not valid RON for [`TrackerConfig`].
    #[error("tracker config: {0}")]
    Ron(#[from] crate::core::config::RonError),
    /// A value out of its range.
    #[error("tracker config: `{field}` = {value} is out of range ({range})")]
    Range {
        /// The field.
        field: &'static str,
        /// Its value.
        value: f64,
        /// The allowed range.
        range: &'static str,
    },
}

impl TrackerConfig {
    /// Parses and validates a RON configuration.
    pub fn from_ron(text: &str) -> Result<TrackerConfig, TrackerConfigError> {
        let c: TrackerConfig = crate::core::config::from_ron(text)?;
        c.validate()?;
        Ok(c)
    }

    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), TrackerConfigError> {
        let unit = [
            ("bias", self.bias),
            ("anchor_support", self.anchor_support),
            ("min_support", self.min_support),
            ("hold", self.hold),
            ("conflict", self.conflict),
        ];
        for (field, value) in unit {
            if !(0.0..=1.0).contains(&value) {
                return Err(TrackerConfigError::Range {
                    field,
                    value,
                    range: "[0, 1]",
                });
            }
        }
        let lengths = [
            ("tolerance", self.tolerance),
            ("tolerance_rel", self.tolerance_rel),
            ("slope", self.slope),
            ("slope_rel", self.slope_rel),
            ("tolerance_d", self.tolerance_d),
            ("tolerance_d_rel", self.tolerance_d_rel),
            ("slope_d", self.slope_d),
            ("slope_d_rel", self.slope_d_rel),
            ("evidence_length_m", self.evidence_length_m),
        ];
        for (field, value) in lengths {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(TrackerConfigError::Range {
                    field,
                    value,
                    range: "finite, ≥ 0",
                });
            }
        }
        if self.horizon_m.is_nan() || self.horizon_m < 0.0 {
            return Err(TrackerConfigError::Range {
                field: "horizon_m",
                value: self.horizon_m,
                range: "≥ 0",
            });
        }
        if let Some(g) = &self.grid {
            g.validate()
                .map_err(|(field, value, range)| TrackerConfigError::Range {
                    field,
                    value,
                    range,
                })?;
        }
        Ok(())
    }
}

/// The tracker's running state, for saving and restoring a belief across restarts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrackerState {
    /// Anchor possibility per place.
    pub anchor: Vec<f64>,
    /// Odometry distance since each anchor, metres.
    pub since: Vec<f64>,
    /// Displacement since each anchor in the map frame, metres, where known (absent in states
    /// saved before displacement gates existed: then unknown).
    #[serde(default)]
    pub displacement: Vec<Option<[f64; 2]>>,
    /// The heading of the last frame, degrees, if known.
    #[serde(default)]
    pub heading: Option<f64>,
}

/// Distances are capped so that they never overflow (far beyond any map's diameter).
const MAX_DISTANCE: f64 = 1e9;

/// Carries place possibilities along the map graph. See the module docs.
#[derive(Debug, Clone)]
pub struct Tracker {
    cfg: TrackerConfig,
    params: DecisionParams,
    n: usize,
    /// `R_ij`'s trapezoid per pair within the horizon, sparse rows (see [`Gates`]).
    gates: Gates,
    anchor: Vec<f64>,
    since: Vec<f64>,
    /// `D_i`, map frame, metres; `None` once a move without a heading made it unknown.
    disp: Vec<Option<[f64; 2]>>,
    /// Heading of the previous frame, radians, once some frame carried one.
    heading: Option<f64>,
    pred: Vec<f64>,
    /// The places whose `pred` the last blur made other than `+0` (the first `dirty_len`), so
    /// that the next blur resets only those; `dirty_all` when they did not fit (or after a
    /// reset), and the whole column is reset.
    dirty: Vec<u32>,
    dirty_len: usize,
    dirty_all: bool,
    /// What the distribution's necessity column holds, so that a step writes only the entries
    /// that change ([`pass::Necessity`]).
    nec: pass::Necessity,
    /// Per row, where its path-gate window was last found ([`Gates::window`]).
    cursor: Vec<Cursor>,
    /// Distance moved whose evidence has not been taken yet, metres; `None` before the first
    /// frame (see [`TrackerConfig::evidence_length_m`]). Not part of [`TrackerState`]: after a
    /// restore the first frame's evidence is taken whole.
    pending_evidence: Option<f64>,
    /// `e_j`, the frame's clamped possibility, read once per step rather than once per pair.
    evid: Vec<f64>,
    /// The anchors below the bias floor with pairs in reach that the last blur did not carry
    /// into `pred` (the first `low_len`, each as it was at the blur); see [`Tracker::blur`].
    /// Sized `n` at construction, so that a step never grows it.
    low: Vec<Low>,
    low_len: usize,
    /// The highest of those anchors (0 if none).
    low_max: f64,
    /// Whether `pred` holds those anchors' terms too (after a conflict union, or a reset).
    pred_full: bool,
    /// The places whose agreement with the frame exceeds the revision's floor, with it (the
    /// first `hot_len`; see [`Tracker::revise`]).
    hot: Vec<(u32, f64)>,
    hot_len: usize,
    /// Per anchor, the highest term a hot place raised its `compat` to this step, then its
    /// revised value; −1 when untouched (every entry between steps).
    raised: Vec<f64>,
    /// The anchors `raised` holds a value for (the first `touched_len`).
    touched: Vec<u32>,
    touched_len: usize,
    /// The places whose support reaches `anchor_support` this frame (the first `supported_len`).
    supported: Vec<u32>,
    supported_len: usize,
    /// Whether the highest anchor is exactly 1 (after the renormalisation every step ends with).
    top_is_one: bool,
    /// The anchors the blur visits (the first `near_len`), and whether each is among them:
    /// every anchor but those known to raise nothing until they are re-anchored — dead ones
    /// (`T(0, x) = 0` keeps them 0) and path-gated ones past their row's bound (`s_i` only
    /// grows, and a displacement once unknown stays so, until the place is re-anchored).
    near: Vec<u32>,
    near_len: usize,
    in_near: Vec<bool>,
    /// Whether some displacement is known (so that a move without a heading has any to forget).
    disp_known: bool,
    /// The places whose displacement was set since it was last forgotten (the first
    /// `set_len`), so that a move without a heading forgets only those; `set_all` when they did
    /// not fit (or after a reset, a restore or a refill), and every entry is forgotten. In a
    /// walk without headings only the re-anchored places have one.
    set: Vec<u32>,
    set_len: usize,
    set_all: bool,
    dist: PlaceDistribution,
    decision: Decision,
}

/// Rough radius of a place's extent: where its evidence starts along a path.
fn extent_radius(e: Extent) -> f64 {
    match e {
        Extent::Radius(r) => r.max(0.0),
        Extent::Box { x0, y0, x1, y1 } => 0.25 * ((x1 - x0).abs() + (y1 - y0).abs()),
    }
}

/// `R_ij`'s trapezoid per pair, kept sparse (issue 16): row `i` holds only the places within
/// [`TrackerConfig::horizon_m`] of `P_i` along the graph (a bounded search per place, see
/// [`crate::map::dijkstra`]), sorted by `L'_ij` so that the pairs a path gate can reach at
/// distance `s` are one contiguous window ([`Gates::window`]). Pairs outside a row have
/// `R_ij = 0`, as pairs with no path always had.
///
/// One branch-free expression ([`path_reach`]) gives exactly
/// [`Similarity::degree`](crate::logic::Similarity::degree)`(s, L'_ij)` of the shape `core =
/// 2(tolerance + tolerance_rel·L)`, `slope = slope + slope_rel·L`, height 1, bias 0: `half =
/// tolerance + tolerance_rel·L` is `0.5 · core` exactly (scaling by 2 and ½ is exact), and a
/// slope that is not positive (only from an unvalidated config) is taken as `+0`, so that beyond
/// the core `(d − half)/0 = +∞` and `max(0, 1 − ∞) = 0`, as `degree` returns there. `d = |s − L|`
/// is always finite (`s` is capped, `L` finite), so `degree`'s non-finite branch is never taken.
#[derive(Debug, Clone)]
struct Gates {
    /// Row `i` is `start[i]..start[i + 1]` of `target` and `length`.
    start: Vec<usize>,
    /// `j` of each pair.
    target: Vec<u32>,
    /// `L'_ij` of each pair, ascending within a row (ties by `j`).
    length: Vec<f64>,
    /// Per row `i`, a distance beyond which every path gate `R_ij` is 0: past `L + half +
    /// slope` of its farthest pair, with a margin (10⁻⁶ relative and absolute) far above the
    /// rounding of `d − half` and the division. Read before the row itself, so that the many
    /// anchors far past every path from them (`s_i` grows until the place is seen again) cost
    /// one comparison. NaN (an unvalidated NaN config) compares false: the row is never skipped.
    bound: Vec<f64>,
    /// `tolerance`, `tolerance_rel`, `slope`, `slope_rel` of the configuration.
    shape: [f64; 4],
    /// Each place's extent as a rounded box, for the displacement gates.
    extents: Vec<([f64; 4], f64)>,
    /// The rows transposed: column `j` is `col_start[j]..col_start[j + 1]` of `col` and
    /// `col_length`, each entry the row `i` of a pair whose target is `j` and the pair's
    /// `L'_ij`, so that the anchors a place can raise are found from the place
    /// ([`Tracker::revise`]). The length is kept beside the row (4 bytes more per pair than a
    /// pair index) because reading it through the pair index was a cache miss per pair, the
    /// revision's largest cost at 10,000 places.
    col_start: Vec<usize>,
    col: Vec<u32>,
    col_length: Vec<f64>,
}

/// An extent as a box `[x_lo, x_hi, y_lo, y_hi]` with a rounding radius: a box is itself with
/// radius 0, a disc its centre with the disc's radius, so that one distance serves all pairs.
fn rounded_box(pose: (f64, f64), e: Extent) -> ([f64; 4], f64) {
    match e {
        Extent::Radius(r) => ([pose.0, pose.0, pose.1, pose.1], r.max(0.0)),
        Extent::Box { x0, y0, x1, y1 } => ([x0.min(x1), x0.max(x1), y0.min(y1), y0.max(y1)], 0.0),
    }
}

/// How one anchor's pairs are gated in a step: by path length at its distance `s`, or by its
/// displacement (its extent moved, and the gate at its distance, see [`displacement_gate`]).
enum Gate {
    Path(f64),
    Displacement(([f64; 4], f64), Similarity),
}

impl Gates {
    fn new(map: &Map, cfg: &TrackerConfig) -> Gates {
        let places = map.places();
        let n = places.len();
        let radius: Vec<f64> = places.iter().map(|p| extent_radius(p.extent)).collect();
        let widest = radius.iter().copied().fold(0.0, f64::max);
        let horizon = if cfg.horizon_m.is_nan() {
            f64::INFINITY
        } else {
            cfg.horizon_m
        };
        let mut g = Gates {
            start: Vec::with_capacity(n + 1),
            target: Vec::new(),
            length: Vec::new(),
            bound: vec![0.0; n],
            shape: [cfg.tolerance, cfg.tolerance_rel, cfg.slope, cfg.slope_rel],
            extents: places
                .iter()
                .map(|p| rounded_box((p.pose.0, p.pose.1), p.extent))
                .collect(),
            col_start: Vec::new(),
            col: Vec::new(),
            col_length: Vec::new(),
        };
        let mut search = BoundedDijkstra::new();
        let mut row: Vec<(f64, usize)> = Vec::new();
        for i in 0..n {
            g.start.push(g.target.len());
            // `L' ≤ horizon` needs `L ≤ horizon + r_i + r_j`; the search goes that far with the
            // widest `r_j`, the filter below keeps the exact set.
            let reach = horizon + radius[i] + widest;
            row.clear();
            for (j, l) in map.path_lengths_within(i, reach, &mut search) {
                let l = if i == j {
                    0.0
                } else {
                    (l - radius[i] - radius[j]).max(0.0)
                };
                if l.is_finite() && l <= horizon {
                    row.push((l, j));
                }
            }
            // Keys are distinct (`j` breaks ties), so an unstable sort gives the same order, cheaper.
            row.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            for &(l, j) in &row {
                g.target.push(u32::try_from(j).unwrap_or(u32::MAX));
                g.length.push(l);
                let (half, slope) = (
                    cfg.tolerance + cfg.tolerance_rel * l,
                    cfg.slope + cfg.slope_rel * l,
                );
                let far = (l + half + slope.max(0.0)) * (1.0 + 1e-6) + 1e-6;
                // Not `f64::max`: a NaN must stick, so that the row is never skipped.
                g.bound[i] = if far > g.bound[i] || far.is_nan() {
                    far
                } else {
                    g.bound[i]
                };
            }
        }
        g.start.push(g.target.len());
        g.transpose(n);
        g
    }

    /// Fills the columns from the rows (a counting sort by target; each column in row order).
    fn transpose(&mut self, n: usize) {
        let mut start = vec![0usize; n + 1];
        for &j in &self.target {
            if let Some(c) = start.get_mut(j as usize + 1) {
                *c += 1;
            }
        }
        for j in 0..n {
            start[j + 1] += start[j];
        }
        let mut next = start.clone();
        self.col = vec![0; start[n]];
        self.col_length = vec![0.0; start[n]];
        for i in 0..n {
            for k in self.row(i) {
                let Some(at) = next.get_mut(self.target[k] as usize) else {
                    continue;
                };
                if let (Some(e), Some(l)) = (self.col.get_mut(*at), self.col_length.get_mut(*at)) {
                    (*e, *l) = (i as u32, self.length[k]);
                }
                *at += 1;
            }
        }
        self.col_start = start;
    }

    /// The rows `i` of column `j` and their pairs' lengths `L'_ij` (empty when out of range).
    fn column(&self, j: usize) -> (&[u32], &[f64]) {
        match (self.col_start.get(j), self.col_start.get(j + 1)) {
            (Some(&a), Some(&b)) => (
                self.col.get(a..b).unwrap_or(&[]),
                self.col_length.get(a..b).unwrap_or(&[]),
            ),
            _ => (&[], &[]),
        }
    }

    /// Whether every path gate of row `i` is 0 at distance `s` (and at every larger one).
    fn beyond(&self, i: usize, s: f64) -> bool {
        self.bound.get(i).is_some_and(|&b| s > b)
    }

    /// The index range of row `i` (empty when out of range).
    fn row(&self, i: usize) -> std::ops::Range<usize> {
        match (self.start.get(i), self.start.get(i + 1)) {
            (Some(&a), Some(&b)) => a..b,
            _ => 0..0,
        }
    }

    /// The pairs of row `i` whose path gate can be non-zero at distance `s`: those with
    /// `|s − L| ≤ half + slope`, widened by a margin (10⁻⁶ relative and absolute) far above the
    /// rounding of `d − half` and the division, so every pair left out surely has `R_ij = 0`.
    /// With `a = tolerance_rel + slope_rel` and `c = tolerance + slope`, that is `L(1 − a) ≤ s + c`
    /// and `L(1 + a) ≥ s − c`, both monotone in `L`, hence a window of the sorted row. A NaN
    /// (an unvalidated config) keeps the whole row.
    ///
    /// Both ends are found from `cur`, the window of the row at an earlier distance: each end's
    /// test holds on a prefix of the row that only grows with `s`, so an end found at a smaller
    /// `s` is a valid start for the search at `s` — usually a step or two forward (`s_i` grows
    /// by a frame's move), instead of two binary searches per live anchor and frame. A cursor
    /// from a larger `s` (a re-anchored place) is dropped. The result is exactly the window a
    /// search of the whole row finds.
    fn window(&self, i: usize, s: f64, cur: &mut Cursor) -> std::ops::Range<usize> {
        if self.beyond(i, s) {
            return 0..0;
        }
        let row = self.row(i);
        let [tol, tol_rel, slope, slope_rel] = self.shape;
        let (a, c) = (tol_rel + slope_rel.max(0.0), tol + slope.max(0.0));
        if !(a.is_finite() && c.is_finite()) {
            return row;
        }
        let lengths = &self.length[row.clone()];
        let near = |x: f64| x * (1.0 + 1e-6) + 1e-6;
        let far = |x: f64| x * (1.0 - 1e-6) - 1e-6;
        // A smaller distance (or a NaN on either side) drops the cursor.
        if !s.partial_cmp(&cur.s).is_some_and(|o| o.is_ge()) {
            *cur = Cursor::default();
        }
        cur.s = s;
        advance(lengths, &mut cur.lo, |l| near(l * (1.0 + a)) < s - c);
        let hi = if a < 1.0 {
            advance(lengths, &mut cur.hi, |l| far(l * (1.0 - a)) <= s + c);
            cur.hi.at
        } else {
            lengths.len()
        };
        row.start + cur.lo.at..row.start + hi.max(cur.lo.at)
    }

    /// The gate of anchor `i` at distance `s` with displacement `disp` (see [`Gate`]).
    fn gate(&self, cfg: &TrackerConfig, i: usize, s: f64, disp: Option<[f64; 2]>) -> Gate {
        match (disp, self.extents.get(i)) {
            (Some(d), Some(&(a, ra))) => {
                let moved = [a[0] + d[0], a[1] + d[0], a[2] + d[1], a[3] + d[1]];
                Gate::Displacement((moved, ra), displacement_gate(cfg, s))
            }
            _ => Gate::Path(s),
        }
    }

    /// `R_ij` by displacement: the moved extent `(m, ra)` of the anchor against extent `j`.
    #[inline]
    fn displacement_reach(&self, (m, ra): &([f64; 4], f64), j: u32, shape: &Similarity) -> f64 {
        let Some((b, rb)) = self.extents.get(j as usize) else {
            return 0.0;
        };
        let gx = (b[0] - m[1]).max(m[0] - b[1]).max(0.0);
        let gy = (b[2] - m[3]).max(m[2] - b[3]).max(0.0);
        let gap = (gx.hypot(gy) - ra - rb).max(0.0);
        shape.degree(gap, 0.0)
    }

    /// `R_ij` of pair `k` through `gate` (0 for a pair out of range): the reference the step's
    /// own reads of `R_ij` are tested against.
    #[cfg(test)]
    fn reach(&self, gate: &Gate, k: usize) -> f64 {
        match gate {
            Gate::Path(s) => self
                .length
                .get(k)
                .map_or(0.0, |&l| path_reach(self.shape, *s, l)),
            Gate::Displacement(moved, shape) => self
                .target
                .get(k)
                .map_or(0.0, |&j| self.displacement_reach(moved, j, shape)),
        }
    }

    /// `pred_j = max(pred_j, min(a, R_ij))` over the pairs `range` of an anchor of value `a`
    /// gated by `gate`. `R_ij` is computed here, pair by pair, rather than stored: each pair is
    /// read once per step, by the anchors that can raise `pred`. `mark` is told each place
    /// whose `pred` leaves `+0`, so that the next blur can reset only those.
    fn carry(
        &self,
        pred: &mut [f64],
        gate: &Gate,
        range: std::ops::Range<usize>,
        a: f64,
        mut mark: impl FnMut(u32),
    ) {
        let targets = self.target.get(range.clone()).unwrap_or(&[]);
        let mut raise = |j: u32, r: f64| {
            if let Some(p) = pred.get_mut(j as usize) {
                let old = *p;
                *p = old.max(a.min(r));
                if old.to_bits() == 0 && p.to_bits() != 0 {
                    mark(j);
                }
            }
        };
        match gate {
            Gate::Path(s) => {
                let lengths = self.length.get(range).unwrap_or(&[]);
                for (&j, &l) in targets.iter().zip(lengths) {
                    raise(j, path_reach(self.shape, *s, l));
                }
            }
            Gate::Displacement(moved, shape) => {
                for &j in targets {
                    raise(j, self.displacement_reach(moved, j, shape));
                }
            }
        }
    }
}

/// Where a row's path-gate window ended at distance `s` ([`Gates::window`]), relative to the
/// row's start; the default (distance 0, both ends at the start) is valid for every distance.
#[derive(Debug, Clone, Copy, Default)]
struct Cursor {
    s: f64,
    lo: End,
    hi: End,
}

/// One end of a window: its index in the row, and the length found there (+∞ past the row's
/// end), kept beside it so that an end that does not move costs no read of the row — the rows
/// are the tracker's largest array, and most ends stay put from one frame to the next.
#[derive(Debug, Clone, Copy)]
struct End {
    at: usize,
    next: f64,
}

impl Default for End {
    /// The start of the row, its length not yet read (−∞ passes every test, so it is read).
    fn default() -> End {
        End {
            at: 0,
            next: f64::NEG_INFINITY,
        }
    }
}

/// An anchor below the bias floor as the blur found it: its place, value, gate and the pairs
/// its gate can reach (see [`Tracker::carry_low`]).
#[derive(Debug, Clone, Copy, Default)]
struct Low {
    i: u32,
    a: f64,
    s: f64,
    disp: Option<[f64; 2]>,
    lo: usize,
    hi: usize,
}

/// Moves `end` to the first index of `xs` where `holds` fails, `holds` being true on a prefix of
/// `xs` that contains `..end.at`: a few steps forward, then probes 8, 16, 32, … places further
/// until one fails, and a binary search between the last two probes — the index
/// [`slice::partition_point`] finds on the whole of `xs`. Probing near the cursor rather than
/// halving the rest of the row keeps the reads in a few cache lines: a row's far end holds
/// dozens of places per metre, so an end often moves past the eight steps in one frame.
fn advance(xs: &[f64], end: &mut End, holds: impl Fn(f64) -> bool) {
    if !holds(end.next) {
        return;
    }
    let mut k = end.at.min(xs.len());
    let mut steps = 0;
    while let Some(&x) = xs.get(k) {
        if !holds(x) {
            break;
        }
        k += 1;
        steps += 1;
        if steps == 8 {
            // `holds` is true before `k`; find `hi` where it fails (or the end), then search
            // between.
            let mut span = 8;
            let hi = loop {
                match xs.get(k + span) {
                    Some(&x) if holds(x) => (k, span) = (k + span + 1, 2 * span),
                    _ => break (k + span).min(xs.len()),
                }
            };
            k += xs
                .get(k..hi)
                .map_or(0, |part| part.partition_point(|&x| holds(x)));
            break;
        }
    }
    end.at = k;
    end.next = xs.get(k).copied().unwrap_or(f64::INFINITY);
}

/// Adds `j` to the places whose `pred` a blur raised (`list[..len]`), or sets `all` when the
/// list is full.
fn mark(list: &mut [u32], len: &mut usize, all: &mut bool, j: u32) {
    match list.get_mut(*len) {
        Some(slot) => (*slot, *len) = (j, *len + 1),
        None => *all = true,
    }
}

/// The displacement gate `s` metres after its anchor: full match within `tolerance_d +
/// tolerance_d_rel·s` of the target extent, falling to 0 over `slope_d + slope_d_rel·s`.
pub fn displacement_gate(cfg: &TrackerConfig, s: f64) -> Similarity {
    Similarity::new(
        2.0 * (cfg.tolerance_d + cfg.tolerance_d_rel * s),
        cfg.slope_d + cfg.slope_d_rel * s,
        1.0,
        0.0,
        None,
    )
}

/// `R_ij` of a path gate of `shape` (`tolerance`, `tolerance_rel`, `slope`, `slope_rel`) at
/// distance `s` for a pair of length `l`: the branch-free trapezoid of [`Gates`].
#[inline]
fn path_reach(shape: [f64; 4], s: f64, l: f64) -> f64 {
    let [tol, tol_rel, slope0, slope_rel] = shape;
    let half = tol + tol_rel * l;
    let slope = slope0 + slope_rel * l;
    let slope = if slope > 0.0 { slope } else { 0.0 };
    let d = (s - l).abs();
    let f = (1.0 - (d - half) / slope).max(0.0);
    if d <= half {
        1.0
    } else {
        f
    }
}

impl Tracker {
    /// A tracker over `map`, deciding with `params` (the rule file's threshold and margin).
    pub fn new(map: &Map, params: DecisionParams, cfg: TrackerConfig) -> Tracker {
        let n = map.places().len();
        let gates = Gates::new(map, &cfg);
        let mut t = Tracker {
            cfg,
            params,
            n,
            gates,
            anchor: vec![1.0; n],
            since: vec![0.0; n],
            disp: vec![Some([0.0; 2]); n],
            heading: None,
            pred: vec![1.0; n],
            dirty: vec![0; n],
            dirty_len: 0,
            dirty_all: true,
            nec: pass::Necessity::default(),
            cursor: vec![Cursor::default(); n],
            pending_evidence: None,
            evid: vec![0.0; n],
            low: vec![Low::default(); n],
            low_len: 0,
            low_max: 0.0,
            pred_full: true,
            hot: vec![(0, 0.0); n],
            hot_len: 0,
            raised: vec![-1.0; n],
            touched: vec![0; n],
            touched_len: 0,
            supported: vec![0; n],
            supported_len: 0,
            top_is_one: true,
            near: (0..n)
                .map(|i| u32::try_from(i).unwrap_or(u32::MAX))
                .collect(),
            near_len: n,
            in_near: vec![true; n],
            disp_known: true,
            set: vec![0; n],
            set_len: 0,
            set_all: true,
            dist: PlaceDistribution::new(n),
            decision: Decision::Disoriented(Disoriented::NoPlaces),
        };
        t.reset();
        t
    }

    /// Puts every anchor back in the blur's list (after a reset, a restore or a refill).
    fn all_near(&mut self) {
        for (k, slot) in self.near.iter_mut().enumerate() {
            *slot = u32::try_from(k).unwrap_or(u32::MAX);
        }
        self.near_len = self.near.len();
        self.in_near.fill(true);
        self.disp_known = self.disp.iter().any(Option::is_some);
        (self.set_len, self.set_all) = (0, true);
    }

    /// Forgets everything: every place equally possible.
    pub fn reset(&mut self) {
        self.anchor.fill(1.0);
        self.since.fill(0.0);
        self.disp.fill(Some([0.0; 2]));
        self.heading = None;
        self.pred.fill(1.0);
        self.dirty_all = true;
        self.nec.forget();
        self.low_len = 0;
        self.pred_full = true;
        self.top_is_one = true;
        self.all_near();
        self.pending_evidence = None;
        self.dist = PlaceDistribution::new(self.n);
        self.decision = undecided(self.n);
    }

    /// The configuration.
    pub fn config(&self) -> &TrackerConfig {
        &self.cfg
    }

    /// One frame: carries the belief by the odometry increment, intersects it with `evidence`
    /// (the engine's distribution for this frame) and decides. `heading` is the frame's heading
    /// in the map frame, degrees, if the stream carries one (see the module docs). Allocates
    /// nothing.
    pub fn step(
        &mut self,
        evidence: &PlaceDistribution,
        odometry: Odometry,
        heading: Option<f64>,
    ) -> Decision {
        let b = clamp_degree(self.cfg.bias);
        let ds = odometry.distance();
        let ds = if ds.is_finite() { ds } else { 0.0 };
        for s in &mut self.since {
            // `min` as a select (the same value, a NaN too), which costs less per place.
            let x = *s + ds;
            *s = if x < MAX_DISTANCE { x } else { MAX_DISTANCE };
        }
        self.carry_displacement(odometry, ds, heading);
        let w = self.evidence_weight(ds);

        self.blur(b);

        let (max_support, top) = self.intersect(evidence, b, w);

        // Revise the anchors: keep those the frame agrees with, re-anchor supported places.
        let (changed, top_revised) = self.revise(1.0 - max_support, b);
        self.reanchor(changed, top_revised);

        let now = pass::decide(&self.dist, &top, max_support, self.params);
        self.decision = held(self.decision, now, &self.dist, self.cfg.hold);
        self.decision = unless_unsupported(self.decision, max_support, self.cfg.min_support, |k| {
            clamp_degree(evidence.support.get(k).copied().unwrap_or(0.0))
        });
        self.decision
    }

    /// Re-anchors the supported places (`m_j = π'_j`, `s_j = 0`) and renormalises the anchors
    /// to height 1. When neither the revision (`changed`) nor a re-anchoring changed an anchor
    /// and the highest is already exactly 1, the renormalisation would divide by 1, which
    /// changes nothing: it is skipped (most frames of a walk, the ones with no support).
    /// `revised` is the revision's highest (see [`Tracker::revise`]), when it has one: then only
    /// the anchors set since are read for the highest.
    fn reanchor(&mut self, changed: bool, revised: Option<f64>) {
        for &j in self.supported.iter().take(self.supported_len) {
            let j = j as usize;
            let pi = self.dist.possibility.get(j).copied().unwrap_or(0.0);
            let slots = (self.anchor.get_mut(j), self.since.get_mut(j));
            if let (Some(m), Some(s), Some(d)) = (slots.0, slots.1, self.disp.get_mut(j)) {
                (*m, *s, *d) = (pi, 0.0, Some([0.0; 2]));
                self.disp_known = true;
                mark(
                    &mut self.set,
                    &mut self.set_len,
                    &mut self.set_all,
                    j as u32,
                );
            }
            if let (Some(false), Some(slot)) =
                (self.in_near.get(j), self.near.get_mut(self.near_len))
            {
                (*slot, self.near_len, self.in_near[j]) = (j as u32, self.near_len + 1, true);
            }
        }
        if !changed && self.supported_len == 0 && self.top_is_one {
            return;
        }
        // The same value as the highest of all (its sign at 0 is not read: `top > 0` fails).
        let top = match revised {
            Some(top) => {
                let set = self.touched.iter().take(self.touched_len);
                let set = set.chain(self.supported.iter().take(self.supported_len));
                let values = set.filter_map(|&i| self.anchor.get(i as usize));
                values.fold(top, |x, &y| if y > x { y } else { x })
            }
            None => self.anchor.iter().copied().fold(0.0, f64::max),
        };
        if top > 0.0 {
            // `m / 1 = m`; otherwise the highest becomes `top / top = 1` exactly.
            if top != 1.0 {
                for m in &mut self.anchor {
                    *m /= top;
                }
            }
        } else {
            self.anchor.fill(1.0);
            self.since.fill(0.0);
            self.disp.fill(Some([0.0; 2]));
            self.all_near();
        }
        self.top_is_one = true;
    }

    /// Intersects the carried belief with the evidence (`c_j = T(max(pred_j, b), e_j)`, or
    /// their union when they do not overlap, see the module docs), fills `dist` and normalises
    /// it, and lists the revision's hot places (see [`Tracker::revise`]); returns the frame's
    /// highest support and the two highest `π'`. `w` is the power the evidence is taken to.
    fn intersect(&mut self, evidence: &PlaceDistribution, b: f64, w: f64) -> (f64, pass::Top) {
        let (h, max_support) = self.intersect_terms(evidence, b, w);
        // The height `normalise` divides by: `max c` (or of the union below).
        let mut height = h;
        self.dist.height = h;
        self.dist.inconsistency = 1.0 - h;
        if h < self.cfg.conflict {
            // Belief and evidence do not overlap: keep both (their union) rather than the
            // little their intersection leaves, so that the next frames can tell which was right.
            // The union reads `pred` itself, not above the floor, so the anchors the blur left
            // out count too — unless none of their terms (each at most `low_max`) can exceed
            // the evidence it is joined with (every `e_j ≥ e_min`): max selects exactly.
            let e_min = || self.evid.iter().copied().fold(1.0, f64::min);
            if self.low_len > 0 && self.low_max > e_min() {
                let mut pred = std::mem::take(&mut self.pred);
                let mut dirty = std::mem::take(&mut self.dirty);
                let (mut len, mut all) = (self.dirty_len, self.dirty_all);
                self.carry_low(&mut pred, |j| mark(&mut dirty, &mut len, &mut all, j));
                (self.pred, self.dirty, self.dirty_len, self.dirty_all) = (pred, dirty, len, all);
                self.pred_full = true;
            }
            let raw = self.dist.possibility_raw.iter_mut();
            for (c, (&p, &e)) in raw.zip(self.pred.iter().zip(&self.evid)) {
                *c = p.max(e);
            }
            height = self
                .dist
                .possibility_raw
                .iter()
                .copied()
                .fold(0.0, f64::max);
        }
        // The revision's floor: no place is hot when it is 1 (see `Tracker::revise`).
        let floor = (1.0 - max_support).max(b);
        let hot = (floor < 1.0).then_some(pass::Hot {
            floor,
            evid: &self.evid,
            list: &mut self.hot,
        });
        let d = &mut self.dist;
        let norm = self.cfg.normalisation;
        let (top, hot_len) =
            pass::normalise(&d.possibility_raw, height, norm, &mut d.possibility, hot);
        self.hot_len = hot_len;
        self.nec.write(&mut d.necessity, &top);
        (max_support, top)
    }

    /// `e_j` (the clamped possibility to the power `w`), `c_j`, support and exclusion of every
    /// place into `evid` and `dist`, the places whose support reaches `anchor_support` into
    /// `supported`; returns the height of `c` and the highest support. One pass over the columns
    /// when the evidence has the map's length (what the engine gives, see [`pass::intersect`]);
    /// other lengths read missing places as "no evidence".
    fn intersect_terms(&mut self, evidence: &PlaceDistribution, b: f64, w: f64) -> (f64, f64) {
        let (t, n) = (self.cfg.tnorm, self.n);
        let (pos, sup, exc) = (
            &evidence.possibility,
            &evidence.support,
            &evidence.exclusion,
        );
        let d = &mut self.dist;
        let full = [
            pos.len(),
            sup.len(),
            exc.len(),
            d.support.len(),
            self.pred.len(),
        ];
        let (mut h, max_support) = if full.iter().all(|&l| l == n) {
            let ev = pass::Evidence {
                possibility: pos,
                support: sup,
                exclusion: exc,
            };
            let out = pass::Written {
                support: &mut d.support,
                exclusion: &mut d.exclusion,
                raw: &mut d.possibility_raw,
                evid: &mut self.evid,
            };
            pass::intersect(t, b, w, &self.pred, &ev, out)
        } else {
            let (mut h, mut max_support) = (0.0f64, 0.0f64);
            let ev =
                |v: &[f64], j: usize, miss: f64| clamp_degree(v.get(j).copied().unwrap_or(miss));
            for j in 0..n {
                let a = ev(sup, j, 0.0);
                d.support[j] = a;
                d.exclusion[j] = ev(exc, j, 0.0);
                // `powf(1)` is exact: with evidence per frame nothing changes.
                let v = ev(pos, j, 1.0);
                let e = if w == 1.0 { v } else { v.powf(w) };
                self.evid[j] = e;
                let c = t.apply(self.pred[j].max(b), e);
                d.possibility_raw[j] = c;
                (h, max_support) = (h.max(c), max_support.max(a));
            }
            (h, max_support)
        };
        if h == 0.0 {
            // Every `c` is 0: the height's sign of zero as the maxima in order give it.
            h = d.possibility_raw.iter().copied().fold(0.0, f64::max);
        }
        self.supported_len = 0;
        // Some support reaches `anchor_support` exactly when the highest does.
        if max_support >= self.cfg.anchor_support {
            let least = self.cfg.anchor_support;
            // By blocks, each looked at without a branch per place first: a handful of places
            // reach it.
            for (c, block) in d.support.chunks(16).enumerate() {
                if !block.iter().fold(false, |x, &a| x | (a >= least)) {
                    continue;
                }
                for (j, &a) in block.iter().enumerate() {
                    if a >= least {
                        if let Some(slot) = self.supported.get_mut(self.supported_len) {
                            let k = (16 * c + j) as u32;
                            (*slot, self.supported_len) = (k, self.supported_len + 1);
                        }
                    }
                }
            }
        }
        (h, max_support)
    }

    /// Blur: carries each anchor along the graph into `pred`, computing `R_ij` pair by pair
    /// (see [`Gates::carry`]). Only the pairs within the horizon are stored, and of those a path
    /// gate visits only its row's window ([`Gates::window`]): an anchor farther than every path
    /// from it (common, as `s_i` grows until the place is seen again) has an empty window and
    /// raises no `pred`. Max and min select exactly, so neither the order of the terms nor the
    /// pairs left out (all `R_ij = 0`, and `min(m_i, 0) = 0`) change `pred`.
    ///
    /// An anchor below the bias floor (`m_i < b`) is not carried: its terms `min(m_i, R_ij) < b`
    /// cannot change `max(pred_j, b)`, the only form in which the intersection reads `pred`
    /// (for every t-norm). Only the conflict union reads `pred_j` itself, and
    /// [`Tracker::predicted`] shows it: both add those terms from the list kept here
    /// ([`Tracker::carry_low`]). On a large map most anchors are below the floor (the product
    /// t-norm shrinks the unsupported ones every frame), so the blur carries a handful of rows
    /// instead of every live one.
    fn blur(&mut self, b: f64) {
        self.clear_pred();
        (self.low_len, self.low_max, self.pred_full) = (0, 0.0, false);
        let mut k = 0;
        while let Some(&i) = self.near.get(k).filter(|_| k < self.near_len) {
            let i = i as usize;
            let (a, s, disp) = (self.anchor[i], self.since[i], self.disp[i]);
            // `min(0, R) = 0` raises no `pred`, and the revision keeps `T(0, x) = 0` for every
            // t-norm whatever `compat` is: a dead anchor (the product t-norm drives unsupported
            // anchors to exactly 0 in a few hundred frames) costs nothing; nor does a path gate
            // past its bound. Both stay so until re-anchored: out of the list.
            if a == 0.0 || (disp.is_none() && self.gates.beyond(i, s)) {
                self.near_len -= 1;
                self.near.swap(k, self.near_len);
                self.in_near[i] = false;
                continue;
            }
            k += 1;
            let range = match disp {
                Some(_) => self.gates.row(i),
                None => self.gates.window(i, s, &mut self.cursor[i]),
            };
            if range.is_empty() {
                continue;
            }
            if a < b {
                if let Some(slot) = self.low.get_mut(self.low_len) {
                    let (i, lo, hi) = (i as u32, range.start, range.end);
                    *slot = Low {
                        i,
                        a,
                        s,
                        disp,
                        lo,
                        hi,
                    };
                    self.low_len += 1;
                    self.low_max = self.low_max.max(a);
                    continue;
                }
            }
            let gate = self.gates.gate(&self.cfg, i, s, disp);
            let (dirty, len, all) = (&mut self.dirty, &mut self.dirty_len, &mut self.dirty_all);
            self.gates.carry(&mut self.pred, &gate, range, a, |j| {
                mark(dirty, len, all, j)
            });
        }
    }

    /// `pred = 0` before a blur: only the places the last one raised, when they are known.
    fn clear_pred(&mut self) {
        if self.dirty_all {
            self.pred.fill(0.0);
        } else {
            for &j in self.dirty.iter().take(self.dirty_len) {
                if let Some(p) = self.pred.get_mut(j as usize) {
                    *p = 0.0;
                }
            }
        }
        (self.dirty_len, self.dirty_all) = (0, false);
    }

    /// Adds to `pred` the terms of the anchors the last blur left out (see [`Tracker::blur`]),
    /// each as it was at the blur; `mark` is told the places raised from `+0`.
    fn carry_low(&self, pred: &mut [f64], mut mark: impl FnMut(u32)) {
        for l in self.low.iter().take(self.low_len) {
            let gate = self.gates.gate(&self.cfg, l.i as usize, l.s, l.disp);
            self.gates.carry(pred, &gate, l.lo..l.hi, l.a, &mut mark);
        }
    }

    /// Revises each anchor by how well the frame agrees with it: `m_i ← T(m_i, max(compat_i,
    /// b))`, `compat_i = max(between, max_j min(R_ij, agree_j))`, `agree_j = min(π'_j, e_j)`;
    /// returns whether any anchor may have changed.
    ///
    /// Only what can matter is read. A term raises `max(compat_i, b)` above `floor = max(between,
    /// b)` only if it exceeds `floor`, hence only through a place with `agree_j > floor` — a
    /// *hot* place, a handful per frame, none in a frame with no support at all (`floor = 1`).
    /// So the pairs are read from the hot places' columns ([`Gates::column`]), and every other
    /// anchor gets `T(m_i, floor)` — which is `m_i` itself, and skipped, when `floor = 1` with
    /// the min (`m_i ≤ 1`) or product t-norm. Max selects exactly, so the order of the terms
    /// does not matter, and a dead anchor stays `T(0, x) = 0` whatever its terms.
    ///
    /// Also returns, when every anchor was revised, the highest of them but the ones the
    /// revision raised and the supported places, which `reanchor` sets: those are 0 here
    /// (`T(0, x) = 0`, below any value they get), and a raised anchor's `T(m_i, floor)` is below
    /// the value it gets (`T` is monotone, with its roundings, and the term exceeds `floor`).
    fn revise(&mut self, between: f64, b: f64) -> (bool, Option<f64>) {
        let t = self.cfg.tnorm;
        let floor = between.max(b);
        // The hot places were listed with the normalisation (`Tracker::intersect`).
        self.raise(floor);
        let unchanged = floor == 1.0 && t != TNorm::Lukasiewicz;
        let mut top = None;
        if !unchanged {
            for &j in self.supported.iter().take(self.supported_len) {
                if let Some(m) = self.anchor.get_mut(j as usize) {
                    *m = 0.0;
                }
            }
            top = Some(pass::revise(&mut self.anchor, t, floor));
        }
        for &i in self.touched.iter().take(self.touched_len) {
            let i = i as usize;
            if let (Some(m), Some(r)) = (self.anchor.get_mut(i), self.raised.get_mut(i)) {
                (*m, *r) = (*r, -1.0);
            }
        }
        (!unchanged || self.touched_len > 0, top)
    }

    /// For each anchor a hot place raises above `floor`, its revised value `T(m_i, max_j
    /// min(R_ij, agree_j))` into `raised` (see [`Tracker::revise`]), read from the columns.
    fn raise(&mut self, floor: f64) {
        self.touched_len = 0;
        for &(j, g) in self.hot.iter().take(self.hot_len) {
            let (rows, lengths) = self.gates.column(j as usize);
            for (&i, &l) in rows.iter().zip(lengths) {
                let i = i as usize;
                // A dead anchor first: most are, and it needs no more reads.
                if !self.anchor.get(i).is_some_and(|&m| m != 0.0) {
                    continue;
                }
                let (Some(&s), Some(&disp)) = (self.since.get(i), self.disp.get(i)) else {
                    continue;
                };
                let r = match self.gates.gate(&self.cfg, i, s, disp) {
                    // Column `j` holds the pairs whose target is `j`: the pair need not be read.
                    Gate::Displacement(moved, shape) => {
                        self.gates.displacement_reach(&moved, j, &shape)
                    }
                    Gate::Path(s) => path_reach(self.gates.shape, s, l),
                };
                let term = r.min(g);
                let Some(r) = self.raised.get_mut(i) else {
                    continue;
                };
                if term > floor {
                    if *r < 0.0 {
                        if let Some(slot) = self.touched.get_mut(self.touched_len) {
                            (*slot, self.touched_len) = (i as u32, self.touched_len + 1);
                        }
                    }
                    *r = r.max(term);
                }
            }
        }
        let t = self.cfg.tnorm;
        for &i in self.touched.iter().take(self.touched_len) {
            if let (Some(r), Some(&m)) =
                (self.raised.get_mut(i as usize), self.anchor.get(i as usize))
            {
                *r = t.apply(m, *r);
            }
        }
    }

    /// The power this frame's evidence is taken to (see
    /// [`TrackerConfig::evidence_length_m`]); `ds` is the distance moved since the last frame.
    fn evidence_weight(&mut self, ds: f64) -> f64 {
        let len = self.cfg.evidence_length_m;
        let Some(pending) = self.pending_evidence else {
            self.pending_evidence = Some(0.0);
            return 1.0;
        };
        if !(len > 0.0 && len.is_finite()) {
            return 1.0;
        }
        let w = ((pending + ds) / len).min(1.0);
        self.pending_evidence = Some((pending + ds - w * len).clamp(0.0, len));
        w
    }

    /// Adds the increment to every anchor's displacement, rotated by the heading it started
    /// from; without one (or with `use_heading` off) the displacements become unknown.
    fn carry_displacement(&mut self, odometry: Odometry, ds: f64, heading: Option<f64>) {
        let dtheta = odometry.turn;
        let now = heading
            .filter(|h| self.cfg.use_heading && h.is_finite())
            .map(f64::to_radians);
        let (start, next) = carry_heading(self.heading, now, dtheta);
        if ds > 0.0 {
            match start {
                Some(th) => {
                    let (sn, cs) = th.sin_cos();
                    let step = [
                        cs * odometry.forward - sn * odometry.left,
                        sn * odometry.forward + cs * odometry.left,
                    ];
                    let known = self
                        .disp
                        .iter_mut()
                        .take(if self.disp_known { self.n } else { 0 });
                    for d in known.flatten() {
                        d[0] = (d[0] + step[0]).clamp(-MAX_DISTANCE, MAX_DISTANCE);
                        d[1] = (d[1] + step[1]).clamp(-MAX_DISTANCE, MAX_DISTANCE);
                    }
                }
                None if self.disp_known => {
                    if self.set_all {
                        self.disp.fill(None);
                    } else {
                        for &j in self.set.iter().take(self.set_len) {
                            if let Some(d) = self.disp.get_mut(j as usize) {
                                *d = None;
                            }
                        }
                    }
                    (self.set_len, self.set_all) = (0, false);
                    self.disp_known = false;
                }
                None => {}
            }
        }
        self.heading = next;
    }

    /// The tracked distribution of the last step (support and exclusion are the evidence's).
    pub fn distribution(&self) -> &PlaceDistribution {
        &self.dist
    }

    /// The decision of the last step.
    pub fn decision(&self) -> Decision {
        self.decision
    }

    /// The carried (predicted) possibility of each place before the last frame's evidence,
    /// computed on demand: the step's blur keeps only the terms that can change its decisions
    /// (those of anchors at or above the bias floor), and this adds the others.
    pub fn predicted(&self) -> Vec<f64> {
        let mut pred = self.pred.clone();
        if !self.pred_full {
            self.carry_low(&mut pred, |_| {});
        }
        pred
    }

    /// A copy of the running state.
    pub fn state(&self) -> TrackerState {
        TrackerState {
            anchor: self.anchor.clone(),
            since: self.since.clone(),
            displacement: self.disp.clone(),
            heading: self.heading.map(f64::to_degrees),
        }
    }

    /// Restores a saved state; a state for a different number of places is ignored (`false`).
    pub fn restore(&mut self, state: &TrackerState) -> bool {
        if state.anchor.len() != self.n || state.since.len() != self.n {
            return false;
        }
        for (d, s) in self.anchor.iter_mut().zip(&state.anchor) {
            *d = clamp_degree(*s);
        }
        for (d, s) in self.since.iter_mut().zip(&state.since) {
            *d = if s.is_finite() && *s >= 0.0 {
                s.min(MAX_DISTANCE)
            } else {
                0.0
            };
        }
        for (i, d) in self.disp.iter_mut().enumerate() {
            *d = state
                .displacement
                .get(i)
                .copied()
                .flatten()
                .filter(|v| v.iter().all(|c| c.is_finite()))
                .map(|v| v.map(|c| c.clamp(-MAX_DISTANCE, MAX_DISTANCE)));
        }
        self.heading = state
            .heading
            .filter(|h| h.is_finite())
            .map(|h| h.to_radians().rem_euclid(std::f64::consts::TAU));
        self.top_is_one = self.anchor.iter().copied().fold(0.0, f64::max) == 1.0;
        self.all_near();
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::parse_map;

    /// π'_B after a first frame with no information and `steps` frames of `metres` each with
    /// evidence for A (A 1, B 0.25) and no support (the anchors stay at 1, so each frame's π'
    /// is its own evidence to the power w), evidence taken per `length` metres.
    fn pi_b_after(steps: usize, metres: f64, length: f64) -> f64 {
        let text = "place A corridor at (0, 0) extent radius 1; \
                    place B corridor at (10, 0) extent radius 1; path A -- B;";
        let map = Map::from_ast(&parse_map(text).unwrap()).unwrap();
        let cfg = TrackerConfig {
            evidence_length_m: length,
            ..TrackerConfig::default()
        };
        let params = DecisionParams {
            threshold: 0.5,
            margin: 0.1,
        };
        let mut t = Tracker::new(&map, params, cfg);
        let mut ev = PlaceDistribution::new(2);
        ev.possibility = vec![1.0, 1.0];
        t.step(&ev, Odometry::default(), None);
        ev.possibility = vec![1.0, 0.25];
        let go = Odometry {
            forward: metres,
            left: 0.0,
            turn: 0.0,
        };
        for _ in 0..steps {
            t.step(&ev, go, None);
        }
        t.distribution().possibility[1]
    }

    /// The window of row `i` at `s` by two binary searches of the whole row.
    fn searched(gates: &Gates, i: usize, s: f64) -> std::ops::Range<usize> {
        let row = gates.row(i);
        if s > gates.bound[i] {
            return 0..0;
        }
        let [tol, tol_rel, slope, slope_rel] = gates.shape;
        let (a, c) = (tol_rel + slope_rel, tol + slope);
        let lengths = &gates.length[row.clone()];
        let lo = lengths.partition_point(|&l| l * (1.0 + a) * (1.0 + 1e-6) + 1e-6 < s - c);
        let hi = lengths.partition_point(|&l| l * (1.0 - a) * (1.0 - 1e-6) - 1e-6 <= s + c);
        row.start + lo..row.start + hi.max(lo)
    }

    #[test]
    fn a_window_found_from_its_cursor_is_the_window_searched_afresh() {
        // A 20 × 20 lattice 3 m apart, joined east and north: rows of a few hundred pairs.
        let mut text = String::new();
        for k in 0..400 {
            let (x, y) = (3 * (k % 20), 3 * (k / 20));
            text += &format!("place P{k} corridor at ({x}, {y}) extent radius 1;\n");
            if k % 20 != 19 {
                text += &format!("path P{k} -- P{};\n", k + 1);
            }
            if k + 20 < 400 {
                text += &format!("path P{k} -- P{};\n", k + 20);
            }
        }
        let map = Map::from_ast(&parse_map(&text).unwrap()).unwrap();
        let gates = Gates::new(&map, &TrackerConfig::default());
        let mut rng = crate::core::rng::SplitMix64::new(7);
        for i in [0, 37, 210, 399] {
            let (mut cur, mut s, mut moved) = (Cursor::default(), 0.0, 0);
            for _ in 0..2000 {
                // Mostly small moves, now and then a jump forward or a re-anchoring.
                s = match rng.unit() {
                    u if u < 0.02 => 0.0,
                    u if u < 0.05 => s + 40.0 * rng.unit(),
                    _ => s + 0.4 * rng.unit(),
                };
                let fresh = searched(&gates, i, s);
                let from = gates.window(i, s, &mut cur);
                assert_eq!(from, fresh, "row {i} at s = {s}");
                moved += usize::from(!fresh.is_empty());
            }
            assert!(moved > 100, "row {i}: the windows were mostly empty");
        }
    }

    /// `R_ij` of every pair of every live anchor's whole row (no window, no bound): `(j, R_ij)`.
    fn plain_reach(t: &Tracker) -> Vec<Vec<(usize, f64)>> {
        (0..t.n)
            .map(|i| {
                if t.anchor[i] == 0.0 {
                    return Vec::new();
                }
                let gate = t.gates.gate(&t.cfg, i, t.since[i], t.disp[i]);
                let row = t.gates.row(i);
                let reach = row.clone().map(|k| t.gates.reach(&gate, k));
                let targets = t.gates.target[row].iter().map(|&j| j as usize);
                targets.zip(reach).collect()
            })
            .collect()
    }

    /// The displacements carried as the module docs say (see `carry_displacement`).
    fn plain_displacement(t: &mut Tracker, odo: Odometry, ds: f64, heading: Option<f64>) {
        let now = heading
            .filter(|h| t.cfg.use_heading && h.is_finite())
            .map(f64::to_radians);
        let (start, next) = carry_heading(t.heading, now, odo.turn);
        if ds > 0.0 {
            for d in &mut t.disp {
                *d = match (start, *d) {
                    (Some(th), Some(d)) => {
                        let (sn, cs) = th.sin_cos();
                        let x = cs * odo.forward - sn * odo.left;
                        let y = sn * odo.forward + cs * odo.left;
                        Some([
                            (d[0] + x).clamp(-MAX_DISTANCE, MAX_DISTANCE),
                            (d[1] + y).clamp(-MAX_DISTANCE, MAX_DISTANCE),
                        ])
                    }
                    _ => None,
                };
            }
        }
        t.heading = next;
    }

    /// One step as the module docs state it, place by place and pair by pair: every anchor
    /// carried over its whole row, every place intersected, every anchor revised against every
    /// pair. The reference the tracker's shortcuts are compared with, bit for bit. Returns the
    /// decision and the whole `pred`.
    fn plain_step(
        t: &mut Tracker,
        ev: &PlaceDistribution,
        odo: Odometry,
        heading: Option<f64>,
    ) -> (Decision, Vec<f64>) {
        let (n, b, tn) = (t.n, clamp_degree(t.cfg.bias), t.cfg.tnorm);
        let ds = Some(odo.distance())
            .filter(|d| d.is_finite())
            .unwrap_or(0.0);
        for s in &mut t.since {
            *s = (*s + ds).min(MAX_DISTANCE);
        }
        plain_displacement(t, odo, ds, heading);
        let w = t.evidence_weight(ds);
        let get = |v: &[f64], j: usize, miss: f64| clamp_degree(v.get(j).copied().unwrap_or(miss));
        let e: Vec<f64> = (0..n)
            .map(|j| get(&ev.possibility, j, 1.0))
            .map(|v| if w == 1.0 { v } else { v.powf(w) })
            .collect();
        let reach = plain_reach(t);
        let mut pred = vec![0.0f64; n];
        for (i, row) in reach.iter().enumerate() {
            for &(j, r) in row {
                pred[j] = pred[j].max(t.anchor[i].min(r));
            }
        }
        let (mut h, mut max_support) = (0.0f64, 0.0f64);
        for j in 0..n {
            let a = get(&ev.support, j, 0.0);
            max_support = max_support.max(a);
            let c = tn.apply(pred[j].max(b), e[j]);
            t.dist.support[j] = a;
            t.dist.exclusion[j] = get(&ev.exclusion, j, 0.0);
            t.dist.possibility_raw[j] = c;
            h = h.max(c);
        }
        (t.dist.height, t.dist.inconsistency) = (h, 1.0 - h);
        if h < t.cfg.conflict {
            for j in 0..n {
                t.dist.possibility_raw[j] = pred[j].max(e[j]);
            }
        }
        t.dist.normalise(t.cfg.normalisation);
        for (i, row) in reach.iter().enumerate() {
            let mut compat = 1.0 - max_support;
            for &(j, r) in row {
                compat = compat.max(r.min(t.dist.possibility[j].min(e[j])));
            }
            t.anchor[i] = tn.apply(t.anchor[i], compat.max(b));
        }
        for j in 0..n {
            if get(&ev.support, j, 0.0) >= t.cfg.anchor_support {
                (t.anchor[j], t.since[j]) = (t.dist.possibility[j], 0.0);
                t.disp[j] = Some([0.0; 2]);
            }
        }
        let top = t.anchor.iter().copied().fold(0.0, f64::max);
        if top > 0.0 {
            t.anchor.iter_mut().for_each(|m| *m /= top);
        } else {
            t.anchor.fill(1.0);
            t.since.fill(0.0);
            t.disp.fill(Some([0.0; 2]));
        }
        let d = held(t.decision, decide(&t.dist, t.params), &t.dist, t.cfg.hold);
        let d = unless_unsupported(d, max_support, t.cfg.min_support, |k| {
            get(&ev.support, k, 0.0)
        });
        t.decision = d;
        (d, pred)
    }

    /// Hand-worked hysteresis: three places, A decided in the previous frame.
    #[test]
    fn a_decided_place_is_held_while_its_necessity_stays_at_hold() {
        let a = Decision::Place {
            place: 0,
            necessity: 0.7,
        };
        let mut dist = PlaceDistribution::new(3);
        dist.necessity = vec![0.45, 0.0, 0.0];
        let close = Decision::Disoriented(Disoriented::TooClose {
            best: 0,
            runner_up: 1,
            necessity: 0.45,
        });
        let held_a = Decision::Place {
            place: 0,
            necessity: 0.45,
        };
        // N_A = 0.45 ≥ 0.4: A stays, with its necessity of this frame.
        assert_eq!(held(a, close, &dist, 0.4), held_a);
        // 0.45 < 0.5, or hysteresis off (1): the frame's own decision.
        assert_eq!(held(a, close, &dist, 0.5), close);
        assert_eq!(held(a, close, &dist, 1.0), close);
        // Nothing was decided before: nothing to hold, however necessary.
        assert_eq!(held(close, close, &dist, 0.4), close);
        // Inconsistency is never held over.
        let inc = Decision::Disoriented(Disoriented::Inconsistent { inconsistency: 0.6 });
        assert_eq!(held(a, inc, &dist, 0.4), inc);
        // A new place the frame chooses is taken: hold never keeps one against another.
        let c = Decision::Place {
            place: 2,
            necessity: 0.8,
        };
        assert_eq!(held(a, c, &dist, 0.4), c);
        // The tie tolerance of the decision's own thresholds.
        dist.necessity[0] = 0.4 - 1e-12;
        assert!(matches!(
            held(a, close, &dist, 0.4),
            Decision::Place { place: 0, .. }
        ));
    }

    /// A random map of `k` places: discs and boxes scattered over 40 m, joined by a random tree
    /// and a few more paths.
    fn random_map(rng: &mut crate::core::rng::SplitMix64, k: usize) -> Map {
        let mut text = String::new();
        for i in 0..k {
            let (x, y) = (40.0 * rng.unit(), 40.0 * rng.unit());
            let extent = if rng.chance(0.5) {
                format!("radius {:.2}", 0.2 + 2.0 * rng.unit())
            } else {
                let (w, h) = (0.5 + 3.0 * rng.unit(), 0.5 + 3.0 * rng.unit());
                format!("box ({x:.2}, {y:.2}, {:.2}, {:.2})", x + w, y + h)
            };
            text += &format!("place P{i} corridor at ({x:.2}, {y:.2}) extent {extent};\n");
        }
        let mut joined = std::collections::HashSet::new();
        for i in 1..k {
            let extra = rng.chance(0.3).then(|| rng.below(i));
            for j in [Some(rng.below(i)), extra].into_iter().flatten() {
                if joined.insert((j, i)) {
                    text += &format!("path P{j} -- P{i};\n");
                }
            }
        }
        Map::from_ast(&parse_map(&text).unwrap()).unwrap()
    }

    /// A degree from a few levels (ties and exact 0 and 1 are common).
    fn level(rng: &mut crate::core::rng::SplitMix64) -> f64 {
        match rng.below(8) {
            0 | 1 => 0.0,
            2 | 3 => 1.0,
            k => 0.1 * k as f64 + 0.05 * rng.unit(),
        }
    }

    /// A frame's evidence: flat (one level everywhere) or varied, support mostly 0 with a few
    /// places up, now and then no support at all or evidence of the wrong length.
    fn random_evidence(rng: &mut crate::core::rng::SplitMix64, n: usize) -> PlaceDistribution {
        let n = if rng.chance(0.03) {
            rng.below(n + 2)
        } else {
            n
        };
        let mut ev = PlaceDistribution::new(n);
        let flat = rng.chance(0.5).then(|| level(rng));
        let quiet = rng.chance(0.3);
        for j in 0..n {
            ev.possibility[j] = flat.unwrap_or_else(|| level(rng));
            if !quiet && rng.chance(0.15) {
                ev.support[j] = level(rng);
            }
            if rng.chance(0.3) {
                ev.exclusion[j] = level(rng);
            }
        }
        ev
    }

    /// A random configuration: every t-norm and normalisation, floors, gates and horizons.
    fn random_config(rng: &mut crate::core::rng::SplitMix64) -> TrackerConfig {
        let tnorm = [TNorm::Min, TNorm::Product, TNorm::Lukasiewicz][rng.below(3)];
        let normalisation = [Normalisation::Min, Normalisation::Product][rng.below(2)];
        TrackerConfig {
            bias: [0.0, 0.1, 0.3, 0.05 + 0.2 * rng.unit()][rng.below(4)],
            tnorm,
            normalisation,
            anchor_support: [0.0, 0.5, 0.8, 1.0][rng.below(4)],
            min_support: 0.3 * rng.unit(),
            hold: [1.0, 1.0, 0.3, rng.unit()][rng.below(4)],
            conflict: [0.0, 0.3, 0.6][rng.below(3)],
            use_heading: rng.chance(0.7),
            evidence_length_m: [0.0, 0.0, 0.7][rng.below(3)],
            horizon_m: [5.0, 15.0, 50.0][rng.below(3)],
            tolerance: 0.3 + rng.unit(),
            slope: [0.0, 1.0, 2.0 * rng.unit()][rng.below(3)],
            ..TrackerConfig::default()
        }
    }

    /// Everything a step leaves observable, as exact text: the decision, the distribution,
    /// the state and the predicted possibilities (`{:?}` of an `f64` round-trips, signs of
    /// zeros included).
    fn observed(t: &Tracker, d: Decision, pred: &[f64]) -> String {
        let dist = &t.dist;
        format!(
            "{d:?} {:?} {:?} {:?} {:?} {:?} {} {} {:?} {pred:?}",
            dist.support,
            dist.exclusion,
            dist.possibility_raw,
            dist.possibility,
            dist.necessity,
            dist.height,
            dist.inconsistency,
            t.state()
        )
    }

    #[test]
    fn the_step_is_the_plain_formulas_bit_for_bit() {
        let mut rng = crate::core::rng::SplitMix64::new(16);
        let params = DecisionParams {
            threshold: 0.5,
            margin: 0.1,
        };
        for case in 0..60 {
            let k = 2 + rng.below(40);
            let map = random_map(&mut rng, k);
            let cfg = random_config(&mut rng);
            let mut fast = Tracker::new(&map, params, cfg);
            let mut plain = fast.clone();
            for k in 0..300 {
                if rng.chance(0.01) {
                    let state = fast.state();
                    let mut odd = state.clone();
                    odd.anchor.iter_mut().for_each(|m| *m *= 0.5 * rng.unit());
                    fast.restore(&odd);
                    plain.restore(&odd);
                }
                let ev = random_evidence(&mut rng, fast.n);
                let moving = rng.chance(0.8);
                let odo = Odometry {
                    forward: if moving { 1.5 * rng.unit() } else { 0.0 },
                    left: if rng.chance(0.2) {
                        0.3 * rng.unit()
                    } else {
                        0.0
                    },
                    turn: 0.2 * (rng.unit() - 0.5),
                };
                let heading = rng.chance(0.5).then(|| 360.0 * rng.unit());
                let d = fast.step(&ev, odo, heading);
                let (pd, pred) = plain_step(&mut plain, &ev, odo, heading);
                let (a, b) = (
                    observed(&fast, d, &fast.predicted()),
                    observed(&plain, pd, &pred),
                );
                assert_eq!(a, b, "case {case}, step {k}, {cfg:?}");
            }
        }
    }

    #[test]
    fn evidence_per_metre_tempers_each_frame_by_the_distance() {
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        // Per frame (the default): 0.25 whatever the distance.
        assert!(close(pi_b_after(2, 0.25, 0.0), 0.25));
        // Per 0.5 m: 0.25 m takes 0.25^0.5 = 0.5; 0.5 m or more takes it whole; standing still
        // takes none.
        assert!(close(pi_b_after(2, 0.25, 0.5), 0.5));
        assert!(close(pi_b_after(1, 2.0, 0.5), 0.25));
        assert!(close(pi_b_after(2, 0.0, 0.5), 1.0));
    }
}
