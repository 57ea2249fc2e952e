//! Metric tracking of place possibilities: paper 000's "blur, then intersect" cycle on a
//! possibility grid over the map's place extents, with each frame's place evidence painted onto
//! the cells of each place. The graph tracker ([`super::tracker`]) carries one possibility per
//! place, so it forgets *where* in a place the robot was; along a ring of look-alike corridors
//! that is what tells them apart. This tracker keeps it, at the price of a grid.
//!
//! # The model
//! Cells of side `cell_size` cover the extents' bounding box grown by `margin`; each cell
//! belongs to the first place (in map order, as ground truth does) whose extent holds its
//! centre, or to none ("between places"). The plane `g` starts at 1 everywhere (total
//! ignorance). Each frame, with `e_j = Π'_j` the engine's normalised possibility of place `j`
//! and `α_j` its support:
//!
//! ```text
//! predict   g ← shift(g, D)                D = Rot(θ_prev)·(dx, dy): the odometry increment
//!                                          turned into the map frame by the previous heading;
//!                                          whole cells, the remainder carried to the next frame
//!           g ← g ⊕ B(f)                   sup-min dilation by the square element of flank
//!                                          f = flank + flank_per_metre·|D| (accumulated until it
//!                                          reaches a cell), B(u, v) = max(0, 1 − max(|u|,|v|)/f)
//! evidence  c(x) = g(x) · max(b, e(x))^w   e(x) = e_j in place j's cells, and
//!                                          max(b, 1 − max_j α_j) between places;
//!                                          w = (distance since evidence was last taken) /
//!                                          evidence_length_m, at most evidence_max_weight (1);
//!                                          place j's own e_j is taken to w·r_j, r_j below
//! normalise h = max c,   g = max(c / h, floor)          (g = 1 everywhere if h = 0)
//! places    π_j = max_{x ∈ P_j} g(x),   π_∅ = max over the cells between places
//!           N_j = 1 − max(max_{k≠j} π_k, π_∅),   Inc = 1 − h
//! ```
//!
//! The power `w` makes the evidence *per metre*, not per frame (DESIGN §12): scans a few
//! centimetres apart are not independent looks, and a log at 11 scans per metre must not make
//! the tracker eleven times as sure as one at 2. Two frames of evidence `e` each taken at `w/2`
//! give `e^w`, what one frame over the same distance gives; a robot standing still takes none
//! (the first frame's evidence is taken whole).
//!
//! `r_j = n_j / (n_j + evidence_scans)` weighs place `j`'s evidence by the scans its
//! expectations were fitted from (`param scans = n_j;`, which `lplace survey` writes; 1 for a
//! place without it, described or written by hand). A range fitted from a few scans holds only
//! what those few saw — one line through the place, in one direction of travel — so a later
//! scan that misses it says little against the place, and one that matches it little for it:
//! its factor is drawn towards 1 either way. Widening the range instead makes the place match
//! everywhere, and with it the place's support, which then outweighs the places fitted well.
//!
//! `b` is the tracker's bias (as in the graph tracker: evidence never rules a cell out
//! entirely) and `floor` paper 000's bias on the belief itself, which lets a kidnapped robot
//! relocalize when the evidence keeps contradicting the belief. Being between places is a
//! world of its own: a belief that sits in a doorway between two extents makes neither place
//! necessary. A frame with no heading (and none earlier to carry over) cannot be shifted; it is
//! blurred by the whole distance moved instead (paper 000's blur without odometry direction).
//! The decision is the rule file's (threshold, margin) on `N` and `Inc`, except that, as for the
//! graph tracker, no place is chosen in a frame in which no place has support ≥ `min_support`.
//!
//! # Complexity
//! `O(cells)` per step: one shift, at most one dilation, one pass for the evidence and one for
//! the places. The plane is stored as runs of cells of one place (or none) along the rows, so
//! the evidence and the places' maxima are plain loops over slices. The dilation is by levels
//! for a flank of a few cells (`out = max_k min(M_k, B(k))` with `M_k` the running maximum over
//! offsets `−k..=k`, a row at a time), and by
//! [`crate::grid::dilate::dilate_line`]'s `O(n)` deques beyond. All buffers are sized at
//! construction; [`GridTracker::step`] allocates nothing and cannot panic.
//!
//! # Example
//! ```
//! use lplace::engine::grid_tracker::{GridTrackConfig, GridTracker};
//! use lplace::engine::tracker::TrackerConfig;
//! use lplace::core::Odometry;
//! use lplace::logic::{DecisionParams, PlaceDistribution};
//! use lplace::map::Map;
//! use lplace::syntax::parse_map;
//! // Two boxes in a row along x: A = [0, 2] × [0, 1], B = [2, 4] × [0, 1].
//! let text = "map m; place A corridor at (1, 0.5) extent box (0, 0, 2, 1); \
//!             place B corridor at (3, 0.5) extent box (2, 0, 4, 1); path A -- B;";
//! let map = Map::from_ast(&parse_map(text).unwrap()).unwrap();
//! let cfg = TrackerConfig { grid: Some(GridTrackConfig::default()), ..TrackerConfig::default() };
//! let params = DecisionParams { threshold: 0.5, margin: 0.1 };
//! let mut t = GridTracker::new(&map, params, &cfg);
//! // Evidence for A, standing still: A is chosen.
//! let mut ev = PlaceDistribution::new(2);
//! ev.support = vec![0.8, 0.0];
//! ev.possibility = vec![1.0, 0.2];
//! let still = Odometry::default();
//! assert_eq!(t.step(&ev, still, Some(0.0)).place(), Some(0));
//! // Drive 2 m east with evidence that both places share: the belief moved with the robot.
//! ev.support = vec![0.4, 0.4];
//! ev.possibility = vec![1.0, 1.0];
//! let east = Odometry { forward: 1.0, left: 0.0, turn: 0.0 };
//! t.step(&ev, east, Some(0.0));
//! assert_eq!(t.step(&ev, east, Some(0.0)).place(), Some(1));
//! ```

use super::tracker::{carry_heading, held, undecided, unless_unsupported, TrackerConfig};
use crate::core::Odometry;
use crate::grid::cells::scale_max_by;
use crate::grid::dilate::{dilate_line, Profile};
use crate::logic::{
    clamp_degree, decide, Decision, DecisionParams, Disoriented, PlaceDistribution,
};
use crate::map::{Extent, Map, Place};
use serde::{Deserialize, Serialize};

/// Parameters of the metric tracker (the `grid` field of a tracker RON file). Every field is
/// optional; defaults below.
///
/// ```ron
/// (grid: Some((cell_size: 0.25, margin: 1.0, flank: 0.0, flank_per_metre: 0.1, floor: 0.001,
///                evidence_length_m: 0.5, evidence_max_weight: 1.0, evidence_scans: 10.0,
///                relative_floor: 1.0, start_radius: 1.0)))
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GridTrackConfig {
    /// Side of a cell, metres (default 0.25). Raised if the map would need more than
    /// [`MAX_CELLS`] cells.
    pub cell_size: f64,
    /// Margin around the extents' bounding box, metres (default 1).
    pub margin: f64,
    /// Flank of the motion blur per moving frame, metres (default 0).
    pub flank: f64,
    /// Flank of the motion blur per metre moved: the odometry's drift (default 0.1).
    pub flank_per_metre: f64,
    /// Least possibility of any cell after normalisation (paper 000's bias; default 0.001).
    pub floor: f64,
    /// Metres of travel one frame's evidence stands for (default 0.5): a frame takes its
    /// evidence to the power `w = d / evidence_length_m`, `d` the distance moved since the last
    /// frame, so that a log at 11 frames per metre and one at 2 take the same evidence per
    /// metre (DESIGN §12). 0 takes every frame's evidence whole (`w = 1`), as before.
    pub evidence_length_m: f64,
    /// Largest `w` of one frame (default 1): a frame is one look, however far it is from the
    /// last one, so a log sparser than one frame per `evidence_length_m` takes less evidence
    /// per metre (it is never made surer by a gap). On the Intel log (about 0.55 m per
    /// frame), a cap of 8 decided no more and named a wrong place more often when thinned.
    pub evidence_max_weight: f64,
    /// How many scans' worth of doubt a fitted place's evidence is weighed against (default
    /// 10, the count below which `lplace survey` warns that a fit is unreliable): a place
    /// fitted from `n` scans (`param scans = n;`) takes its evidence to the power
    /// `n / (n + evidence_scans)`. 0 takes every place's evidence whole.
    pub evidence_scans: f64,
    /// How far a surveyed place's evidence may fall for fitting worse than the best-fitting
    /// place (default 1: not at all). A place with `param scans` takes
    /// `min(Π'_j, max(relative_floor, α_j / max_k α_k))`, `α` the support: the frame's
    /// normalised possibility `Π'` gives every place but the best the same degree, so it
    /// cannot tell a place that nearly fits from one that does not fit at all.
    pub relative_floor: f64,
    /// Radius of the belief around the map's `start (x, y);`, metres (default 1): the cells
    /// whose centres lie within it start at 1, the others at `floor`. Without a `start` (or
    /// with no cell within the radius) every cell starts at 1.
    pub start_radius: f64,
}

impl Default for GridTrackConfig {
    fn default() -> Self {
        GridTrackConfig {
            cell_size: 0.25,
            margin: 1.0,
            flank: 0.0,
            flank_per_metre: 0.1,
            floor: 0.001,
            evidence_length_m: 0.5,
            evidence_max_weight: 1.0,
            evidence_scans: 10.0,
            relative_floor: 1.0,
            start_radius: 1.0,
        }
    }
}

/// Most cells a tracker grid may have (16 M: 64 MB of `f32`); a larger map gets coarser cells.
pub const MAX_CELLS: usize = 1 << 24;

impl GridTrackConfig {
    /// Checks every field's range; the error names the field, its value and the range.
    pub fn validate(&self) -> Result<(), (&'static str, f64, &'static str)> {
        if !(self.cell_size > 0.0 && self.cell_size.is_finite()) {
            return Err(("grid.cell_size", self.cell_size, "finite, > 0"));
        }
        for (field, value) in [
            ("grid.margin", self.margin),
            ("grid.flank", self.flank),
            ("grid.flank_per_metre", self.flank_per_metre),
            ("grid.evidence_length_m", self.evidence_length_m),
            ("grid.evidence_max_weight", self.evidence_max_weight),
            ("grid.evidence_scans", self.evidence_scans),
            ("grid.start_radius", self.start_radius),
        ] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err((field, value, "finite, ≥ 0"));
            }
        }
        if !(0.0..=1.0).contains(&self.floor) {
            return Err(("grid.floor", self.floor, "[0, 1]"));
        }
        if !(0.0..=1.0).contains(&self.relative_floor) {
            return Err(("grid.relative_floor", self.relative_floor, "[0, 1]"));
        }
        Ok(())
    }
}

/// Longest reach (cells) dilated by levels; longer ones go to the deques of
/// [`crate::grid::dilate`], whose cost does not grow with the reach.
const LEVELS: usize = 8;

/// The place parameter holding how many scans its expectations were fitted from.
pub const SCANS_PARAM: &str = "scans";

/// Label of a cell between places.
const NONE: u32 = u32::MAX;

/// Shifts larger than this many cells empty the grid whatever its size; clamping keeps absurd
/// (but finite) odometry from overflowing an index.
const MAX_SHIFT: f64 = 1e7;

/// Carries place possibilities on a metric grid. See the module docs.
#[derive(Debug, Clone)]
pub struct GridTracker {
    cfg: GridTrackConfig,
    bias: f64,
    min_support: f64,
    /// [`TrackerConfig::hold`].
    hold: f64,
    params: DecisionParams,
    n: usize,
    nx: usize,
    ny: usize,
    cell: f64,
    /// Lower-left corner of the grid, metres.
    origin: (f64, f64),
    /// The place of each cell, row-major (row = y), or [`NONE`].
    label: Vec<u32>,
    /// Maximal runs `(start, end, place)` of cells with one label, in order, covering the plane;
    /// `place` is `n` between places.
    runs: Vec<(usize, usize, usize)>,
    /// Per place (and, last, between places), the evidence factor of its cells.
    factor: Vec<f32>,
    /// Per place (and, last, between places), `r_j`: the share of its evidence it takes.
    reliance: Vec<f32>,
    /// Per place, whether it was surveyed (has `param scans`): only those take
    /// [`GridTrackConfig::relative_floor`].
    surveyed: Vec<bool>,
    /// The map's `start (x, y);`.
    start: Option<(f64, f64)>,
    /// Per place (and, last, between places), the largest cell after normalisation.
    top: Vec<f32>,
    /// Per run, its largest cell after the evidence.
    run_top: Vec<f32>,
    /// The belief `g`, row-major.
    g: Vec<f32>,
    scratch: Vec<f32>,
    line: Vec<f32>,
    line_out: Vec<f32>,
    deque: Vec<u32>,
    /// Heading of the previous frame, radians.
    heading: Option<f64>,
    /// Shift not yet applied (less than half a cell), metres.
    remainder: (f64, f64),
    /// Flank not yet applied (less than a cell), metres.
    pending_flank: f64,
    /// Distance moved whose evidence has not been taken yet, metres; `None` before the first
    /// frame (whose evidence is taken whole).
    pending_evidence: Option<f64>,
    /// Per place `max g` scratch for the evidence step (`π_j`), and the between-places one.
    between: f64,
    dist: PlaceDistribution,
    decision: Decision,
}

/// The bounding box `[x0, y0, x1, y1]` of an extent.
fn extent_box(pose: (f64, f64), e: Extent) -> [f64; 4] {
    match e {
        Extent::Radius(r) => {
            let r = r.max(0.0);
            [pose.0 - r, pose.1 - r, pose.0 + r, pose.1 + r]
        }
        Extent::Box { x0, y0, x1, y1 } => [x0.min(x1), y0.min(y1), x0.max(x1), y0.max(y1)],
    }
}

/// Entry `j` of an evidence vector as a degree, `missing` when the vector is short.
fn degree_at(v: &[f64], j: usize, missing: f64) -> f64 {
    clamp_degree(v.get(j).copied().unwrap_or(missing))
}

/// Per place, `n / (n + prior)` for a place fitted from `n` scans (its `param scans = n;`), 1
/// for one without a usable count or with `prior` 0; and 1 for between places, last.
fn reliance(places: &[Place], prior: f64) -> Vec<f32> {
    let prior = if prior.is_finite() {
        prior.max(0.0)
    } else {
        0.0
    };
    let of = |p: &Place| match p.param(SCANS_PARAM, None) {
        Some(n) if n >= 0.0 && n.is_finite() && prior > 0.0 => (n / (n + prior)) as f32,
        _ => 1.0,
    };
    places.iter().map(of).chain(std::iter::once(1.0)).collect()
}

/// The lower-left and upper-right corners of the places' extents; the origin alone when no
/// place has a finite extent, so that the plane stays finite.
fn places_bounds(places: &[Place]) -> ((f64, f64), (f64, f64)) {
    let mut lo = (f64::INFINITY, f64::INFINITY);
    let mut hi = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for p in places {
        let b = extent_box((p.pose.0, p.pose.1), p.extent);
        if b.iter().all(|v| v.is_finite()) {
            lo = (lo.0.min(b[0]), lo.1.min(b[1]));
            hi = (hi.0.max(b[2]), hi.1.max(b[3]));
        }
    }
    if !(lo.0 <= hi.0 && lo.1 <= hi.1) {
        lo = (0.0, 0.0);
        hi = (0.0, 0.0);
    }
    (lo, hi)
}

/// The configured cell size (the default when unusable), doubled until a `w` × `h` plane fits
/// in [`MAX_CELLS`] cells.
fn cell_size(grid: &GridTrackConfig, w: f64, h: f64) -> f64 {
    let mut cell = if grid.cell_size > 0.0 && grid.cell_size.is_finite() {
        grid.cell_size
    } else {
        GridTrackConfig::default().cell_size
    };
    let fits = |c: f64| (w / c).ceil().max(1.0) * (h / c).ceil().max(1.0) <= MAX_CELLS as f64;
    while !fits(cell) {
        cell *= 2.0;
    }
    cell
}

/// The place of each cell's centre, row-major (the first place containing it), or [`NONE`].
///
/// # Complexity
/// Each place tests only the cells of its extent's box, widened by a cell: O(cells + Σ box
/// cells) `contains` calls, not O(cells · places). A place whose box is not finite tests every
/// cell.
fn label_cells(
    places: &[Place],
    (nx, ny): (usize, usize),
    origin: (f64, f64),
    cell: f64,
) -> Vec<u32> {
    let mut label = vec![NONE; nx * ny];
    // The last place first, so that the first place containing a centre is the one kept.
    for (k, p) in places.iter().enumerate().rev() {
        let ((c0, c1), (r0, r1)) = cell_span(p, (nx, ny), origin, cell);
        for r in r0..r1 {
            let y = origin.1 + (r as f64 + 0.5) * cell;
            for c in c0..c1 {
                let x = origin.0 + (c as f64 + 0.5) * cell;
                if p.contains(x, y) {
                    label[r * nx + c] = k as u32;
                }
            }
        }
    }
    label
}

/// The columns and rows `[start, end)` of the cells whose centres may lie in `p`: those within
/// a cell of its box; every cell when the box is not finite.
fn cell_span(
    p: &Place,
    (nx, ny): (usize, usize),
    origin: (f64, f64),
    cell: f64,
) -> ((usize, usize), (usize, usize)) {
    // A rotated box's or a polygon's extent is its outline's bounding box.
    let b = extent_box((p.pose.0, p.pose.1), p.extent);
    if !(b.iter().all(|v| v.is_finite()) && cell > 0.0) {
        return ((0, nx), (0, ny));
    }
    let span = |lo: f64, hi: f64, o: f64, n: usize| {
        let first = ((lo - o) / cell - 1.5).floor().max(0.0);
        let last = ((hi - o) / cell + 1.5).ceil().max(0.0);
        ((first as usize).min(n), (last as usize).min(n))
    };
    (
        span(b[0], b[2], origin.0, nx),
        span(b[1], b[3], origin.1, ny),
    )
}

/// The maximal runs `(start, end, place)` of equal labels, `place` = `n` between places.
fn label_runs(label: &[u32], n: usize) -> Vec<(usize, usize, usize)> {
    let mut runs = Vec::new();
    let mut start = 0;
    for k in 1..=label.len() {
        if k == label.len() || label[k] != label[start] {
            let l = label[start];
            runs.push((start, k, if l == NONE { n } else { l as usize }));
            start = k;
        }
    }
    runs
}

impl GridTracker {
    /// A tracker over `map`'s place extents with `cfg.grid` (defaults if `None`), `cfg.bias`
    /// and `cfg.min_support`, deciding with `params`. Non-finite extents are left out of the
    /// bounds.
    pub fn new(map: &Map, params: DecisionParams, cfg: &TrackerConfig) -> GridTracker {
        let grid = cfg.grid.unwrap_or_default();
        let places = map.places();
        let n = places.len();
        let (lo, hi) = places_bounds(places);
        let margin = if grid.margin.is_finite() {
            grid.margin.max(0.0)
        } else {
            0.0
        };
        let (w, h) = (hi.0 - lo.0 + 2.0 * margin, hi.1 - lo.1 + 2.0 * margin);
        let cell = cell_size(&grid, w, h);
        let nx = ((w / cell).ceil() as usize).max(1);
        let ny = ((h / cell).ceil() as usize).max(1);
        let origin = (lo.0 - margin, lo.1 - margin);
        let label = label_cells(places, (nx, ny), origin, cell);
        let runs = label_runs(&label, n);
        let n_runs = runs.len();
        let longest = nx.max(ny);
        let mut t = GridTracker {
            cfg: grid,
            bias: clamp_degree(cfg.bias),
            min_support: cfg.min_support,
            hold: cfg.hold,
            params,
            n,
            nx,
            ny,
            cell,
            origin,
            label,
            runs,
            factor: vec![1.0; n + 1],
            reliance: reliance(places, grid.evidence_scans),
            surveyed: places
                .iter()
                .map(|p| p.param(SCANS_PARAM, None).is_some())
                .collect(),
            start: map.start(),
            top: vec![1.0; n + 1],
            run_top: vec![0.0; n_runs],
            g: vec![1.0; nx * ny],
            scratch: vec![0.0; nx * ny],
            line: vec![0.0; longest],
            line_out: vec![0.0; longest],
            deque: vec![0; longest],
            heading: None,
            remainder: (0.0, 0.0),
            pending_flank: 0.0,
            pending_evidence: None,
            between: 1.0,
            dist: PlaceDistribution::new(n),
            decision: Decision::Disoriented(Disoriented::NoPlaces),
        };
        t.reset();
        t
    }

    /// Forgets everything but the map's start: every cell equally possible, or, with a
    /// `start`, the cells within `start_radius` of it.
    pub fn reset(&mut self) {
        self.start_belief();
        self.heading = None;
        self.remainder = (0.0, 0.0);
        self.pending_flank = 0.0;
        self.pending_evidence = None;
        self.between = 1.0;
        self.dist = PlaceDistribution::new(self.n);
        self.decision = undecided(self.n);
    }

    /// The belief before any frame: 1 within `start_radius` of the map's start and `floor`
    /// elsewhere; 1 everywhere without a start or when no cell centre lies within the radius
    /// (a start off the grid says nothing about where on it the robot is).
    fn start_belief(&mut self) {
        self.g.fill(1.0);
        let Some((sx, sy)) = self.start.filter(|s| s.0.is_finite() && s.1.is_finite()) else {
            return;
        };
        let r = self.cfg.start_radius;
        let (nx, cell, (ox, oy)) = (self.nx, self.cell, self.origin);
        let near = |i: usize| {
            let x = ox + ((i % nx) as f64 + 0.5) * cell;
            let y = oy + ((i / nx) as f64 + 0.5) * cell;
            (x - sx).hypot(y - sy) <= r
        };
        if !(0..self.g.len()).any(near) {
            return;
        }
        let floor = self.cfg.floor as f32;
        for (i, v) in self.g.iter_mut().enumerate() {
            *v = if near(i) { 1.0 } else { floor };
        }
    }

    /// Grid size in cells `(nx, ny)`, the cell side and the lower-left corner (metres).
    pub fn geometry(&self) -> (usize, usize, f64, (f64, f64)) {
        (self.nx, self.ny, self.cell, self.origin)
    }

    /// The belief plane, row-major from the lower-left corner (row = y).
    pub fn belief(&self) -> &[f32] {
        &self.g
    }

    /// The place of each cell (row-major), `None` between places.
    pub fn cell_place(&self, col: usize, row: usize) -> Option<usize> {
        let l = *self
            .label
            .get(row.checked_mul(self.nx)?.checked_add(col)?)?;
        (l != NONE && col < self.nx).then_some(l as usize)
    }

    /// The tracked distribution of the last step (support and exclusion are the evidence's;
    /// `possibility` is `π_j` of the module docs).
    pub fn distribution(&self) -> &PlaceDistribution {
        &self.dist
    }

    /// The possibility of being between places after the last step (`π_∅`).
    pub fn between_places(&self) -> f64 {
        self.between
    }

    /// The decision of the last step.
    pub fn decision(&self) -> Decision {
        self.decision
    }

    /// One frame: predicts by the odometry increment (turned into the map frame by the
    /// heading), intersects with `evidence` and decides. `heading` is the frame's heading in
    /// the map frame, degrees, if known. Allocates nothing.
    pub fn step(
        &mut self,
        evidence: &PlaceDistribution,
        odometry: Odometry,
        heading: Option<f64>,
    ) -> Decision {
        self.predict(odometry, heading);
        let w = self.evidence_weight(odometry);
        self.intersect(evidence, w);
        self.decision
    }

    /// The power `w` this frame's evidence is taken to (see
    /// [`GridTrackConfig::evidence_length_m`]): the distance moved since evidence was last
    /// taken, in evidence lengths, at most `evidence_max_weight`; what the cap leaves is kept
    /// for the next frame. The first frame's evidence is taken whole.
    fn evidence_weight(&mut self, o: Odometry) -> f32 {
        let len = self.cfg.evidence_length_m;
        let ds = o.forward.hypot(o.left);
        let ds = if ds.is_finite() { ds } else { 0.0 };
        let Some(pending) = self.pending_evidence else {
            self.pending_evidence = Some(0.0);
            return 1.0;
        };
        if !(len > 0.0 && len.is_finite()) {
            return 1.0;
        }
        let cap = self.cfg.evidence_max_weight.max(0.0);
        let w = ((pending + ds) / len).min(cap);
        // The remainder the cap leaves is bounded too, so a jump in a log is forgotten.
        self.pending_evidence = Some((pending + ds - w * len).clamp(0.0, cap * len));
        w as f32
    }

    fn predict(&mut self, o: Odometry, heading: Option<f64>) {
        let finite = |v: f64| if v.is_finite() { v } else { 0.0 };
        let (dx, dy) = (finite(o.forward), finite(o.left));
        let dtheta = finite(o.turn);
        let now = heading.filter(|h| h.is_finite()).map(f64::to_radians);
        let (start, next) = carry_heading(self.heading, now, dtheta);
        self.heading = next;
        let ds = dx.hypot(dy);
        // `ds` is finite (its parts are): only a real move predicts.
        if ds <= 0.0 {
            return;
        }
        let mut flank = self.cfg.flank + self.cfg.flank_per_metre * ds;
        match start {
            Some(th) => {
                let (s, c) = th.sin_cos();
                let rx = self.remainder.0 + c * dx - s * dy;
                let ry = self.remainder.1 + s * dx + c * dy;
                let cells = |r: f64| (r / self.cell).round().clamp(-MAX_SHIFT, MAX_SHIFT);
                let (sx, sy) = (cells(rx), cells(ry));
                self.remainder = (rx - sx * self.cell, ry - sy * self.cell);
                if !(self.remainder.0.abs() <= self.cell && self.remainder.1.abs() <= self.cell) {
                    self.remainder = (0.0, 0.0);
                }
                self.shift(sx as i64, sy as i64);
            }
            // No direction: blur by the whole distance instead.
            None => flank += ds,
        }
        self.pending_flank += flank;
        if self.pending_flank >= self.cell {
            let p = Profile {
                core: 0.0,
                flank: (self.pending_flank / self.cell) as f32,
            };
            self.dilate(p);
            self.pending_flank = 0.0;
        }
    }

    /// Moves the plane by `(sx, sy)` cells; cells entering from outside get 0 (the floor lifts
    /// them in the evidence step). Row-major, the move is one shift of the whole buffer by
    /// `sy·nx + sx`: a cell carried across a row's end is one that entered from the side, so
    /// it is zeroed with the rows that entered.
    fn shift(&mut self, sx: i64, sy: i64) {
        if sx == 0 && sy == 0 {
            return;
        }
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        if sx.abs() >= nx || sy.abs() >= ny {
            self.g.fill(0.0);
            return;
        }
        let len = self.g.len();
        let off = (sy * nx + sx).unsigned_abs() as usize;
        if sy * nx + sx > 0 {
            self.g.copy_within(..len - off, off);
        } else {
            self.g.copy_within(off.., 0);
        }
        let (nx, sxa) = (self.nx, sx.unsigned_abs() as usize);
        let entered_rows = sy.unsigned_abs() as usize * nx;
        if sy > 0 {
            self.g[..entered_rows].fill(0.0);
        } else if sy < 0 {
            self.g[len - entered_rows..].fill(0.0);
        }
        if sxa > 0 {
            for row in self.g.chunks_exact_mut(nx) {
                let side = if sx > 0 {
                    &mut row[..sxa]
                } else {
                    &mut row[nx - sxa..]
                };
                side.fill(0.0);
            }
        }
    }

    /// Sup-min dilation by the square element with profile `p` along both axes: the element
    /// `min(B(u), B(v)) = B(max(|u|, |v|))` is the sup-min sum of a row and a column element.
    fn dilate(&mut self, p: Profile) {
        // No clamping pass: every cell is in [0, 1] here (the start's 1 and floor, the
        // normalisation's output, the 0 of a cell that entered).
        debug_assert!(self.g.iter().all(|v| (0.0..=1.0).contains(v)));
        // Offsets k with B(k) > 0: k < flank (core 0).
        let reach = if p.flank > 0.0 {
            (p.flank.ceil() as usize).saturating_sub(1)
        } else {
            0
        };
        if reach == 0 {
            return;
        }
        if reach <= LEVELS {
            self.levels(p, reach, true);
            self.levels(p, reach, false);
            return;
        }
        let nx = self.nx;
        for row in self.g.chunks_exact_mut(nx) {
            let out = &mut self.line_out[..nx];
            dilate_line(row, out, p, &mut self.deque);
            row.copy_from_slice(out);
        }
        let ny = self.ny;
        for c in 0..nx {
            for (r, v) in self.line[..ny].iter_mut().enumerate() {
                *v = self.g[r * nx + c];
            }
            dilate_line(
                &self.line[..ny],
                &mut self.line_out[..ny],
                p,
                &mut self.deque,
            );
            for (r, &v) in self.line_out[..ny].iter().enumerate() {
                self.g[r * nx + c] = v;
            }
        }
    }

    /// One 1-D pass by levels along rows (`along_rows`) or columns, reaching `reach` cells:
    /// with `g₀` the input, `M_k = max(M_{k−1}, g₀(x − k), g₀(x + k))` and
    /// `out = max_k min(M_k, B(k))`. Samples past the grid's edge count as 0, so along rows a
    /// neighbour stays in its row.
    fn levels(&mut self, p: Profile, reach: usize, along_rows: bool) {
        if along_rows {
            self.levels_along_rows(p, reach);
        } else {
            self.levels_along_columns(p, reach);
        }
    }

    /// [`GridTracker::levels`] along rows, a row at a time: `g₀` and `M_k` are row buffers
    /// (in L1), the row itself is the output (it starts as `M₀ = g₀`, `B(0) = 1`).
    fn levels_along_rows(&mut self, p: Profile, reach: usize) {
        let nx = self.nx;
        let reach = reach.min(nx.saturating_sub(1));
        let (g0, m) = (&mut self.line[..nx], &mut self.line_out[..nx]);
        for row in self.g.chunks_exact_mut(nx) {
            g0.copy_from_slice(row);
            m.copy_from_slice(row);
            for k in 1..=reach {
                max_into(&mut m[k..], &g0[..nx - k]);
                max_into(&mut m[..nx - k], &g0[k..]);
                max_min_into(row, m, p.at(k as f32));
            }
        }
    }

    /// [`GridTracker::levels`] along columns, an output row at a time, top down: `M_k` for row
    /// `r` is the maximum of its input rows `r − k ..= r + k`. The rows below are still input;
    /// the `reach` rows above, already output, are kept as they were in a ring of rows
    /// (`scratch`), so the plane is not copied.
    fn levels_along_columns(&mut self, p: Profile, reach: usize) {
        let (nx, ny) = (self.nx, self.ny);
        let reach = reach.min(ny.saturating_sub(1));
        if reach == 0 {
            return;
        }
        let ring = &mut self.scratch[..reach * nx];
        let (g0, m) = (&mut self.line[..nx], &mut self.line_out[..nx]);
        for r in 0..ny {
            let (done, below) = self.g.split_at_mut((r + 1) * nx);
            let row = &mut done[r * nx..];
            g0.copy_from_slice(row);
            m.copy_from_slice(row);
            for k in 1..=reach {
                if r >= k {
                    let up = (r - k) % reach;
                    max_into(m, &ring[up * nx..(up + 1) * nx]);
                }
                if r + k < ny {
                    max_into(m, &below[(k - 1) * nx..k * nx]);
                }
                max_min_into(row, m, p.at(k as f32));
            }
            ring[(r % reach) * nx..(r % reach + 1) * nx].copy_from_slice(g0);
        }
    }

    fn intersect(&mut self, evidence: &PlaceDistribution, w: f32) {
        let max_support = self.evidence_factors(evidence, w);
        let h = self.multiply_runs();
        self.normalise(h);
        self.necessities();
        let hd = f64::from(h);
        self.dist.height = if hd.is_finite() { hd.min(1.0) } else { 0.0 };
        self.dist.inconsistency = 1.0 - self.dist.height;
        let now = decide(&self.dist, self.params);
        self.decision = held(self.decision, now, &self.dist, self.hold);
        self.decision = unless_unsupported(self.decision, max_support, self.min_support, |k| {
            degree_at(&evidence.support, k, 0.0)
        });
    }

    /// Copies the evidence's support and exclusion and sets each place's cell factor (and the
    /// between-places one) for `w` lengths of travel; returns the evidence's largest support.
    fn evidence_factors(&mut self, evidence: &PlaceDistribution, w: f32) -> f64 {
        let n = self.n;
        let mut max_support = 0.0f64;
        for j in 0..n {
            let a = degree_at(&evidence.support, j, 0.0);
            max_support = max_support.max(a);
            self.dist.support[j] = a;
            self.dist.exclusion[j] = degree_at(&evidence.exclusion, j, 0.0);
            // The evidence factor of place j's cells, kept in `possibility` until the places
            // pass below overwrites it.
            self.dist.possibility[j] = degree_at(&evidence.possibility, j, 1.0).max(self.bias);
        }
        self.relative_evidence(max_support);
        // The evidence of `w` lengths of travel: each factor to the power `w` (w = 1 is the
        // frame's evidence as it is; bit for bit, as `powf(1)` is exact).
        for ((f, &e), &r) in self
            .factor
            .iter_mut()
            .zip(&self.dist.possibility)
            .zip(&self.reliance)
        {
            *f = (e as f32).powf(w * r);
        }
        if let Some(f) = self.factor.get_mut(n) {
            *f = (((1.0 - max_support).max(self.bias)) as f32).powf(w);
        }
        max_support
    }

    /// Caps each surveyed place's evidence factor (in `dist.possibility`) by its support
    /// relative to the largest, floored at `relative_floor` (see [`GridTrackConfig`]). A frame
    /// without support says nothing here.
    fn relative_evidence(&mut self, max_support: f64) {
        let floor = clamp_degree(self.cfg.relative_floor);
        if floor >= 1.0 || max_support <= 0.0 {
            return;
        }
        let places = self.dist.possibility.iter_mut().zip(&self.dist.support);
        for ((e, &a), _) in places.zip(&self.surveyed).filter(|(_, &s)| s) {
            *e = e.min((a / max_support).max(floor)).max(self.bias);
        }
    }

    /// Multiplies each run by its factor and keeps the run's largest value, in one sweep;
    /// returns the plane's largest value. Normalising is monotone, so a run's largest value
    /// afterwards is the normalised one of this, and the plane needs no third pass. Maxima as
    /// selects (`scale_max_by`), not `f32::max`, whose NaN rule keeps the loops from
    /// vectorising (no cell is NaN: every factor is finite).
    fn multiply_runs(&mut self) -> f32 {
        let b = self.bias as f32;
        let mut h = 0.0f32;
        for (top, &(start, end, l)) in self.run_top.iter_mut().zip(&self.runs) {
            let f = self.factor.get(l).copied().unwrap_or(b);
            *top = scale_max_by(&mut self.g[start..end], f);
            h = if *top > h { *top } else { h };
        }
        h
    }

    /// Divides the plane by its height `h` (floored at `cfg.floor`; an empty or broken plane
    /// becomes all-possible) and reads each place's possibility off its runs' maxima.
    fn normalise(&mut self, h: f32) {
        let floor = self.cfg.floor as f32;
        let normal = h > 0.0 && h.is_finite();
        let inv = if normal { 1.0 / h } else { 0.0 };
        let norm = |v: f32| {
            let x = v * inv;
            let x = if x > floor { x } else { floor };
            if x < 1.0 {
                x
            } else {
                1.0
            }
        };
        if normal {
            for v in &mut self.g {
                *v = norm(*v);
            }
        } else {
            self.g.fill(1.0);
        }
        self.top.fill(0.0);
        for (&m, &(_, _, l)) in self.run_top.iter().zip(&self.runs) {
            let m = if normal { norm(m) } else { 1.0 };
            if let Some(t) = self.top.get_mut(l) {
                *t = if m > *t { m } else { *t };
            }
        }
        for (p, &t) in self.dist.possibility_raw.iter_mut().zip(&self.top) {
            *p = f64::from(t);
        }
        self.between = f64::from(self.top.get(self.n).copied().unwrap_or(0.0));
        self.dist
            .possibility
            .copy_from_slice(&self.dist.possibility_raw);
    }

    /// N_j = 1 − max(max_{k≠j} π_k, π_∅): the two largest π suffice.
    fn necessities(&mut self) {
        let (mut first, mut second, mut best) = (self.between, self.between, usize::MAX);
        for (k, &p) in self.dist.possibility.iter().enumerate() {
            if p > first {
                second = first;
                first = p;
                best = k;
            } else if p > second {
                second = p;
            }
        }
        for (k, nk) in self.dist.necessity.iter_mut().enumerate() {
            let other = if k == best { second } else { first };
            *nk = 1.0 - other;
        }
    }
}

/// `dst = max(dst, src)` element-wise, the maximum as a select: no cell is NaN (every cell is
/// in [0, 1] at a dilation), and `f32::max`'s NaN rule keeps the loop from vectorising.
fn max_into(dst: &mut [f32], src: &[f32]) {
    for (d, &s) in dst.iter_mut().zip(src) {
        *d = if s > *d { s } else { *d };
    }
}

/// `out = max(out, min(m, b))` element-wise, as selects (see [`max_into`]).
fn max_min_into(out: &mut [f32], m: &[f32], b: f32) {
    for (o, &mv) in out.iter_mut().zip(m) {
        let cut = if mv < b { mv } else { b };
        *o = if cut > *o { cut } else { *o };
    }
}
