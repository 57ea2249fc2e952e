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
//! membership evaluations). With a bearing: O(cells) angle-set
//! intersections, written branch-free (every case computed, one selected)
//! so that they vectorise with `atan2` and the range factor. Blocks of four
//! cells whose headings are all unknown skip the intersection and the atan2:
//! such a cell takes the observation's set, which it forgets again if it
//! falls under the floor, so its observed heading is computed when the
//! update is settled, and only if it stays above (after a few products, a
//! few cells near the peak). Inputs outside the ranges the branch-free path
//! assumes (a bearing beyond ±π, a heading centre outside [−π, π], an
//! observation set as wide as the circle) take the scalar path row by row;
//! both give the same floats (unit-tested), except that a cell whose
//! unknown heading is forgotten again keeps its old θ and α (the set is the
//! full circle either way).
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

use super::cells::{as_block, blend, fmax, fmin, raw_max, scale_max_by, SETTLE_BLOCK};
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

/// `v.floor()` through a truncating conversion: SSE2 has no rounding
/// instruction, so `f32::floor` is a library call, four per row of every
/// range update. The same value except the sign of a zero result (which
/// [`to_col`] does not see); from 2²³ on every float is an integer, and NaN
/// stays NaN.
#[inline(always)]
fn floor(v: f32) -> f32 {
    if v.abs() < 8_388_608.0 {
        let t = v as i32 as f32;
        if t > v {
            t - 1.0
        } else {
            t
        }
    } else {
        v
    }
}

/// `v.ceil()` as [`floor`] does it.
#[inline(always)]
fn ceil(v: f32) -> f32 {
    -floor(-v)
}

/// Columns of a row at vertical distance `dy` from the landmark where the
/// range trapezoid (support radii `r_in..r_out` around the landmark at `lx`)
/// can be above its bias: `c_lo..c_hi` minus the hole `h_lo..h_hi`
/// (`h_lo = h_hi` when the row misses the hole). Cells outside get exactly
/// the bias; the bounds carry a cell of margin for rounding.
#[allow(clippy::too_many_arguments)]
fn annulus_cols(
    x0: f32,
    s: f32,
    nx: usize,
    lx: f32,
    dy: f32,
    r_out: f32,
    r_in: f32,
) -> (usize, usize, usize, usize) {
    let col_of = |x: f32| (x - x0) / s - 0.5; // fractional column of a centre
    let ox = (r_out * r_out - dy * dy).max(0.0).sqrt();
    // Column bounds are clamped as floats, so huge readings cannot overflow
    // an integer.
    let c_lo = to_col(floor(col_of(lx - ox)) - 1.0, 0, nx);
    let c_hi = to_col(ceil(col_of(lx + ox)) + 2.0, 0, nx); // exclusive

    // The hole of the annulus (cells certainly closer than r_in).
    let (mut h_lo, mut h_hi) = (c_lo, c_lo);
    if dy.abs() < r_in {
        let ix = (r_in * r_in - dy * dy).max(0.0).sqrt();
        let a = to_col(ceil(col_of(lx - ix)) + 1.0, c_lo, c_hi);
        let b = to_col(floor(col_of(lx + ix)), a, c_hi);
        (h_lo, h_hi) = (a, b);
    }
    (c_lo, c_hi, h_lo, h_hi)
}

/// A column index as a float, through `i32`: the same value as `c as f32`
/// (columns are far below 2³¹), but SSE2 converts 32-bit integers four at a
/// time and 64-bit ones only one by one, which kept the per-cell loops from
/// vectorising well.
#[inline(always)]
fn col_f(c: usize) -> f32 {
    c as i32 as f32
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

/// Membership of a distance `dist` in the range trapezoid `t`: the value of
/// [`Trapezoid::linear`], NaN distance giving the bias as there, but written
/// branch-free (selects, no `f32::max`/`min`, whose NaN rules block SIMD) so
/// that loops calling it vectorise, sqrt included.
#[inline(always)]
fn range_member(t: &Trapezoid, dist: f32) -> f32 {
    let half = 0.5 * t.shape.core;
    let end = half + t.shape.slope;
    let has_flank = t.shape.slope > 0.0;
    let slope = if has_flank { t.shape.slope } else { 1.0 };
    let u = (dist - t.center).abs();
    let flank = 1.0 - (u - half) / slope;
    let flank = if has_flank && u < end { flank } else { 0.0 };
    let v = if u <= half {
        t.shape.height
    } else {
        t.shape.height * flank
    };
    if v > t.shape.bias {
        v
    } else {
        t.shape.bias
    }
}

/// Combines cells `first..first + row.len()` of a row (at squared vertical
/// distance `dy2` from the landmark) with the range membership
/// ([`range_member`], branch-free so that the loop vectorises).
#[inline]
fn ring(row: &mut [f32], first: usize, k: &Ring, dy2: f32, combine: Combine) {
    let member = |c: usize| {
        let dx = k.x0 + (col_f(c) + 0.5) * k.s - k.lx;
        range_member(&k.t, (dx * dx + dy2).sqrt())
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

/// `fast_atan2` written with selects only, so that a loop calling it
/// vectorises; same operations in the same order, hence the same floats.
#[inline(always)]
fn atan2_sel(y: f32, x: f32) -> f32 {
    let ax = x.abs();
    let ay = y.abs();
    let swap = ay > ax;
    let num = if swap { ax } else { ay };
    let den = if swap { ay } else { ax };
    let z = num / if den == 0.0 { 1.0 } else { den };
    let z2 = z * z;
    let a = z
        * (0.999_977_3
            + z2 * (-0.332_623_5
                + z2 * (0.193_543_5
                    + z2 * (-0.116_432_9 + z2 * (0.052_653_3 + z2 * -0.011_721_2)))));
    let a = if swap { FRAC_PI_2 - a } else { a };
    let a = if x < 0.0 { PI - a } else { a };
    let a = if y < 0.0 { -a } else { a };
    if den == 0.0 {
        0.0
    } else {
        a
    }
}

/// The next run of cells of a row (headings' cores `ds`) that the bearing
/// pass intersects, from cell `from` on: `(start, end)`, with the blocks of
/// [`LANES`] cells before `start` holding unknown headings only (`Δ ≥ 2π`),
/// and the run made of whole blocks each holding a known one, or of the
/// cells after the last whole block. `start = end = len` when none is left.
fn next_run(ds: &[f32], from: usize) -> (usize, usize) {
    let n = ds.len();
    let full = n - n % LANES;
    let unknown = |b0: usize| {
        ds[b0..b0 + LANES]
            .iter()
            .fold(true, |u, &d| u & (d >= 2.0 * PI))
    };
    let mut c = from;
    while c < full && unknown(c) {
        c += LANES;
    }
    let start = c;
    while c < n && (c >= full || !unknown(c)) {
        c = if c < full { c + LANES } else { n };
    }
    (start, c)
}

/// [`crate::core::angle::wrap_pi_f32`] for `a` in (−3π, 3π], with selects: there it takes the
/// same two branches and gives the same floats.
#[inline(always)]
fn wrap_near(a: f32) -> f32 {
    let a = if a > PI { a - 2.0 * PI } else { a };
    if a <= -PI {
        a + 2.0 * PI
    } else {
        a
    }
}

/// Width clamp of [`Trapezoid::new`]: ≥ 0, non-finite → 0.
#[inline(always)]
fn nonneg(v: f32) -> f32 {
    if v.abs() < f32::INFINITY {
        fmax(v, 0.0)
    } else {
        0.0
    }
}

/// `v` combined with the factor `f`: product, or minimum when `MIN` (a
/// select: `f32::min`'s NaN rule blocks SIMD).
#[inline(always)]
fn combine_with<const MIN: bool>(v: f32, f: f32) -> f32 {
    if MIN {
        if f < v {
            f
        } else {
            v
        }
    } else {
        v * f
    }
}

/// Cells per block of the bearing pass's intersection sweep: one SSE2
/// vector. Blocks of 8 skipped fewer cells and left up to 7 cells a row to
/// the full path, which made a 20×30 update slower than the scalar code.
const LANES: usize = 4;

/// Δ of a cell whose heading was unknown when the bearing pass met it: the
/// cell takes the observation's set in [`FuzzyGrid::bearing_settle`] if it
/// stays above the floor (under it, the set is forgotten anyway). No
/// heading set has it: widths are finite, at most 2π once intersected.
const PENDING: f32 = f32::INFINITY;

/// The observation's angle set without its centre, and its precomputed half
/// widths; height 1 (as [`super::SensorModel::around`] builds it).
#[derive(Clone, Copy)]
struct ObsSet {
    core: f32,
    slope: f32,
    bias: f32,
    /// Half width of the support, `core/2 + slope` (< π: see
    /// [`FuzzyGrid::bearing_pass`]).
    w0: f32,
}

/// One cell of the bearing update, branch-free: the heading set
/// `(theta, delta, alpha, bias)` (height 1) intersected with the
/// observation's set centred on `oc`, and the consistency of the two. It is
/// [`Trapezoid::intersect_with_consistency`] specialised to two sets of
/// height 1 whose observation support is narrower than the circle, every
/// branch turned into a select (both sides are computed), operation for
/// operation, so the floats are the same; the caller guarantees the ranges
/// under which [`wrap_near`] equals `wrap_pi`. A cell whose heading is
/// unknown (`delta ≥ 2π`) takes the observation's set with consistency 1.
/// Returns `(theta, delta, alpha, bias, consistency)`.
#[inline(always)]
fn bearing_cell(
    theta: f32,
    delta: f32,
    alpha: f32,
    ba: f32,
    oc: f32,
    o: ObsSet,
) -> (f32, f32, f32, f32, f32) {
    let d = wrap_near(oc - theta);
    let t = overlap_level(d.abs(), delta, alpha, o);
    let cons = fmax(
        fmax(fmax(t, fmin(ba, o.bias)), fmin(ba, 1.0)),
        fmin(1.0, o.bias),
    );
    let (c_lo, c_hi, fl_in) = inner_envelope(d, delta, alpha, t, o);
    let (e_lo, e_hi, fl_out) = outer_envelope(d, delta, alpha, o);
    let inner = t > 0.0;
    let (lo, hi, fl) = if inner {
        (c_lo, c_hi, fl_in)
    } else {
        (e_lo, e_hi, fl_out)
    };
    let bias = if inner {
        ba * o.bias
    } else {
        1.0 - (1.0 - ba) * (1.0 - o.bias)
    };
    let center = wrap_near(theta + 0.5 * (lo + hi));
    let center = if center.abs() < f32::INFINITY {
        center
    } else {
        0.0
    };
    let n_delta = nonneg(fmin(hi - lo, 2.0 * PI));
    let n_alpha = nonneg(fmin(fl, 2.0 * PI));
    let n_bias = if bias.abs() < f32::INFINITY {
        fmax(fmin(bias, 1.0), 0.0)
    } else {
        0.0
    };
    if delta >= 2.0 * PI {
        (oc, o.core, o.slope, ba * o.bias, 1.0)
    } else {
        (center, n_delta, n_alpha, n_bias, cons)
    }
}

/// [`bearing_cell`]'s overlap level `t` of the cell's set (`delta`,
/// `alpha`, height 1) and the observation's at centre distance `ad`
/// (`Trapezoid::overlap_level_at`, heights 1), as selects.
#[inline(always)]
fn overlap_level(ad: f32, delta: f32, alpha: f32, o: ObsSet) -> f32 {
    let wa_raw = 0.5 * delta + alpha;
    let wa_inf = wa_raw >= PI;
    // Cell support covers the circle: level where its cut still does.
    let hw1 = 0.5 * delta + alpha * 0.0;
    let lvl_raw = 1.0 - (PI - 0.5 * delta) / if alpha > 0.0 { alpha } else { 1.0 };
    let lvl_raw = fmax(fmin(lvl_raw, 1.0), 0.0);
    let la = if hw1 >= PI || alpha <= 0.0 {
        1.0
    } else {
        lvl_raw
    };
    let t_inf = fmax(fmin(fmin(la, 1.0), 1.0), 0.0);
    let reach = wa_raw + o.w0 - ad;
    let rate = alpha + o.slope;
    let cores = 0.5 * (delta + o.core) - ad;
    let by_rate = fmax(fmin(reach / if rate > 0.0 { rate } else { 1.0 }, 1.0), 0.0);
    let t_fin = if reach < 0.0 {
        0.0
    } else if cores >= 0.0 {
        1.0
    } else if rate > 0.0 {
        by_rate
    } else {
        0.0
    };
    if wa_inf {
        t_inf
    } else {
        t_fin
    }
}

/// [`bearing_cell`]'s inner envelope (overlapping sets, `t > 0`): the core
/// `(lo, hi)` relative to the cell's centre and the flank, as selects.
#[inline(always)]
fn inner_envelope(d: f32, delta: f32, alpha: f32, t: f32, o: ObsSet) -> (f32, f32, f32) {
    let wa_raw = 0.5 * delta + alpha;
    let inf_if = |w: f32| if w >= PI { f32::INFINITY } else { w };
    let ha_t = inf_if(0.5 * delta + alpha * (1.0 - t));
    let hb_t = inf_if(0.5 * o.core + o.slope * (1.0 - t));
    let wa = inf_if(wa_raw);
    let c_lo = fmax(0.0 - ha_t, d - hb_t);
    let c_hi = fmin(0.0 + ha_t, d + hb_t);
    let s_lo = fmax(0.0 - wa, d - o.w0);
    let s_hi = fmin(0.0 + wa, d + o.w0);
    let c_hi = fmax(c_hi, c_lo);
    let fl_in = fmax(fmin(c_lo - s_lo, s_hi - c_hi), 0.0);
    let fl_in = if fl_in.abs() < f32::INFINITY {
        fl_in
    } else {
        2.0 * PI
    };
    (c_lo, c_hi, fl_in)
}

/// [`bearing_cell`]'s outer envelope (disjoint sets, `t = 0`): the core
/// `(lo, hi)` relative to the cell's centre and the flank.
#[inline(always)]
fn outer_envelope(d: f32, delta: f32, alpha: f32, o: ObsSet) -> (f32, f32, f32) {
    let wa2 = 0.5 * delta;
    let wb2 = 0.5 * o.core;
    let e_lo = fmin(-wa2, d - wb2);
    let e_hi = fmax(wa2, d + wb2);
    let es_lo = fmin(-wa2 - alpha, d - wb2 - o.slope);
    let es_hi = fmax(wa2 + alpha, d + wb2 + o.slope);
    let fl_out = fmax(fmax(e_lo - es_lo, es_hi - e_hi), 0.0);
    (e_lo, e_hi, fl_out)
}

/// The observed heading of every cell of a row that the bearing pass
/// intersects, into `ocs`: runs of cells ([`next_run`]) — whole blocks of
/// [`LANES`] cells that hold a known heading, and the cells after the last
/// whole block. The blocks in between hold unknown headings only (Δ ≥ 2π:
/// most of a grid after a few products, see the floor in `Settle`).
/// `(x0, s, lx, dy)`: the grid's left edge, cell size, the landmark's x and
/// its y offset from the row.
#[inline(always)]
fn observed_headings(
    ocs: &mut [f32],
    ds: &[f32],
    (x0, s, lx, dy): (f32, f32, f32, f32),
    bearing: f32,
) {
    let n = ds.len();
    let mut c = 0;
    while c < n {
        let (a, b) = next_run(ds, c);
        for (i, oc) in ocs[a..b].iter_mut().enumerate() {
            let dx = lx - (x0 + (col_f(a + i) + 0.5) * s);
            *oc = wrap_near(atan2_sel(dy, dx) - bearing);
        }
        c = b;
    }
}

/// The range factor of every cell of a row into `fs` (1 without `RANGE`).
/// It is exactly the bias outside the annulus (as in `range_pass`): evaluate
/// it only on the annulus. Arguments as in [`observed_headings`].
#[inline(always)]
fn range_factors<const RANGE: bool>(
    fs: &mut [f32],
    rt: &Trapezoid,
    (x0, s, lx, dy): (f32, f32, f32, f32),
) {
    if !RANGE {
        fs.fill(1.0);
        return;
    }
    let n = fs.len();
    let w = 0.5 * rt.shape.core + rt.shape.slope;
    let r_out = rt.center + w;
    let r_in = (rt.center - w).max(0.0);
    fs.fill(rt.shape.bias);
    if dy.abs() <= r_out {
        let (c_lo, c_hi, h_lo, h_hi) = annulus_cols(x0, s, n, lx, dy, r_out, r_in);
        for (a, b) in [(c_lo, h_lo), (h_hi, c_hi)] {
            for (c, f) in fs[a..b].iter_mut().enumerate() {
                let dx = lx - (x0 + (col_f(a + c) + 0.5) * s);
                *f = range_member(rt, (dx * dx + dy * dy).sqrt());
            }
        }
    }
}

/// The kept pending cells' θ (the observed heading) and α (the
/// observation's slope) of a row after the bearing settle, over runs of
/// cells with a mark in `kept`. Arguments as in [`observed_headings`].
#[inline(always)]
fn kept_headings(
    kept: &[f32],
    ts: &mut [f32],
    als: &mut [f32],
    (x0, s, lx, dy): (f32, f32, f32, f32),
    bearing: f32,
    slope: f32,
) {
    let nx = kept.len();
    let mut c = 0;
    while c < nx {
        if kept[c] == 0.0 {
            c += 1;
            continue;
        }
        let start = c;
        while c < nx && kept[c] != 0.0 {
            c += 1;
        }
        for i in start..c {
            let dx = lx - (x0 + (col_f(i) + 0.5) * s);
            ts[i] = wrap_near(atan2_sel(dy, dx) - bearing);
            als[i] = slope;
        }
    }
}

impl Observation {
    /// Checks the reading's values — finite, range ≥ 0 — as every localizer must before it
    /// touches its belief.
    ///
    /// # Errors
    /// [`GridError::NonFinite`] or [`GridError::NegativeRange`], naming the landmark.
    pub fn check(&self) -> Result<(), GridError> {
        check_values(self.landmark, self.range, self.bearing)
    }
}

/// The value checks of a reading of landmark `landmark` (0 when the caller has no id).
fn check_values(landmark: u32, range: Option<f32>, bearing: Option<f32>) -> Result<(), GridError> {
    if let Some(r) = range {
        if !r.is_finite() {
            return Err(GridError::NonFinite {
                what: "range",
                landmark,
                value: r,
            });
        }
        if r < 0.0 {
            return Err(GridError::NegativeRange { landmark, range: r });
        }
    }
    if let Some(b) = bearing {
        if !b.is_finite() {
            return Err(GridError::NonFinite {
                what: "bearing",
                landmark,
                value: b,
            });
        }
    }
    Ok(())
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
        check_values(0, range, bearing)
    }

    /// Updates with a range reading `r` to a landmark at `(lx, ly)`. Returns
    /// the height of the plane before normalisation (1 − inconsistency).
    /// Rejects (and leaves the grid untouched on) non-finite or negative input.
    pub fn update_range(&mut self, lx: f32, ly: f32, r: f32) -> Result<f32, GridError> {
        Self::check_obs((lx, ly), Some(r), None)?;
        self.apply_pending();
        let raw = self.range_pass(lx, ly, r);
        Ok(self.finish_update_from(raw))
    }

    /// Updates with a bearing reading only (needs the heading sets).
    pub fn update_bearing(&mut self, lx: f32, ly: f32, bearing: f32) -> Result<f32, GridError> {
        Self::check_obs((lx, ly), None, Some(bearing))?;
        self.apply_pending();
        let raw = self.bearing_pass(lx, ly, None, bearing);
        Ok(self.bearing_settle(raw, lx, ly, bearing))
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
        let raw = self.bearing_pass(lx, ly, Some(r), bearing);
        Ok(self.bearing_settle(raw, lx, ly, bearing))
    }

    /// Updates with an [`Observation`] of a landmark from `table`.
    pub fn observe(&mut self, table: &LandmarkTable, obs: &Observation) -> Result<f32, GridError> {
        let m = table
            .get(obs.landmark)
            .ok_or(GridError::UnknownLandmark(obs.landmark))?;
        obs.check()?;
        match (obs.range, obs.bearing) {
            (Some(r), Some(b)) => self.update_range_bearing(m.x, m.y, r, b),
            (Some(r), None) => self.update_range(m.x, m.y, r),
            (None, Some(b)) => self.update_bearing(m.x, m.y, b),
            (None, None) => Ok(self.last_height),
        }
    }

    /// Combines the plane with the range reading; returns its
    /// [`super::cells::raw_max`], measured row by row while each row is in
    /// cache, for [`FuzzyGrid::finish_update_from`].
    fn range_pass(&mut self, lx: f32, ly: f32, r: f32) -> f32 {
        let t = self.cfg.range.around(r);
        let w = 0.5 * t.shape.core + t.shape.slope;
        let r_out = r + w;
        let r_in = (r - w).max(0.0);
        let s = self.cell;
        let bias = t.shape.bias;
        let combine = self.cfg.combine;
        let outside = |row: &mut [f32]| match combine {
            Combine::Product => row.iter_mut().for_each(|v| *v *= bias),
            Combine::Min => row.iter_mut().for_each(|v| *v = v.min(bias)),
        };
        let ring_ctx = Ring {
            x0: self.x0,
            lx,
            s,
            t,
        };
        let row_dy = |j: usize| self.y0 + (j as f32 + 0.5) * s - ly;
        let nx = self.nx;
        // The rows off the annulus before its first row and after its last
        // take the bias in one sweep each, the maximum taken in the same
        // sweep (product only: `f32::min` is not that select for NaN).
        let band = |j: usize| row_dy(j).abs() <= r_out;
        let (first, end) = match combine {
            Combine::Product => {
                let first = (0..self.ny).find(|&j| band(j)).unwrap_or(self.ny);
                let end = (first..self.ny).rev().find(|&j| band(j));
                (first, end.map_or(first, |j| j + 1))
            }
            Combine::Min => (0, self.ny),
        };
        let (above, rest) = self.h.split_at_mut(first * nx);
        let (across, below) = rest.split_at_mut((end - first) * nx);
        let mut raw = scale_max_by(above, bias).max(scale_max_by(below, bias));
        for (i, row) in across.chunks_exact_mut(nx).enumerate() {
            let dy = row_dy(first + i);
            if dy.abs() > r_out {
                outside(row);
                raw = raw.max(raw_max(row));
                continue;
            }
            let (c_lo, c_hi, h_lo, h_hi) = annulus_cols(self.x0, s, nx, lx, dy, r_out, r_in);
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
            raw = raw.max(raw_max(row));
        }
        raw
    }

    /// Combines the plane and the heading sets with the bearing (and range)
    /// reading; returns the plane's [`super::cells::raw_max`], measured row
    /// by row, for [`FuzzyGrid::finish_update_from`].
    fn bearing_pass(&mut self, lx: f32, ly: f32, range: Option<f32>, bearing: f32) -> f32 {
        let rt = range.map(|r| self.cfg.range.around(r));
        let obs = self.cfg.bearing.around(0.0);
        let o = ObsSet {
            core: obs.shape.core,
            slope: obs.shape.slope,
            bias: obs.shape.bias,
            w0: 0.5 * obs.shape.core + obs.shape.slope * 1.0,
        };
        // The branch-free path assumes what keeps every angle it wraps in
        // (−3π, 3π] and the observation's support off the full circle; any
        // other input (rare: configured or user-set) takes the scalar path.
        let fast = bearing.abs() <= PI && o.w0 < PI;
        let combine = self.cfg.combine;
        let mut raw = 0.0f32;
        for j in 0..self.ny {
            let lo = j * self.nx;
            let hi = lo + self.nx;
            let thetas = &self.theta[lo..hi];
            // Branch-free reduction, so the check itself vectorises.
            let in_range = thetas.iter().fold(true, |ok, &t| ok & (t.abs() <= PI));
            if !(fast && in_range) {
                self.bearing_row_scalar(j, lx, ly, rt, bearing);
                raw = raw.max(raw_max(&self.h[lo..hi]));
                continue;
            }
            match (rt, combine) {
                (Some(t), Combine::Product) => {
                    self.bearing_row::<true, false>(j, lx, ly, t, bearing, o)
                }
                (Some(t), Combine::Min) => self.bearing_row::<true, true>(j, lx, ly, t, bearing, o),
                (None, Combine::Product) => {
                    self.bearing_row::<false, false>(j, lx, ly, obs, bearing, o)
                }
                (None, Combine::Min) => self.bearing_row::<false, true>(j, lx, ly, obs, bearing, o),
            }
            raw = raw.max(raw_max(&self.h[lo..hi]));
        }
        raw
    }

    /// Settles a bearing update ([`super::cells::Settle`]; `raw` is the
    /// pass's raw maximum) and completes the cells left [`PENDING`]: their
    /// heading was unknown, so the observation's set is theirs (Δ, α, bias
    /// times the observation's, the observed heading θ), with consistency 1,
    /// which the pass already applied to `h`. A pending cell that falls
    /// under the floor forgets that set again (bias 1, Δ = 2π), as any cell
    /// there does; it alone keeps its old θ and α, which a full-circle set
    /// ignores. So the observed heading — the atan2 — is computed only for
    /// the pending cells that stay above the floor: a few near the peak
    /// once most of the grid sits at the floor. Returns the height.
    fn bearing_settle(&mut self, raw: f32, lx: f32, ly: f32, bearing: f32) -> f32 {
        let st = match self.settle_for(raw) {
            Ok(st) => st,
            Err(height) => return height,
        };
        let obs = self.cfg.bearing.around(0.0);
        let (nx, s, x0, y0) = (self.nx, self.cell, self.x0, self.y0);
        let FuzzyGrid {
            h,
            theta,
            delta,
            alpha,
            bias,
            work,
            ..
        } = self;
        let kept = &mut work.line[..nx];
        for j in 0..self.ny {
            let r = j * nx..(j + 1) * nx;
            // Every cell settled, the pending ones with the observation's
            // set; `kept` marks those that stay above the floor.
            let settle = |h: &mut f32, b: &mut f32, d: &mut f32, k: &mut f32| {
                let pend = *d == PENDING;
                let b_in = blend(pend, *b * obs.shape.bias, *b);
                let d_in = blend(pend, obs.shape.core, *d);
                if st.floor > 0.0 {
                    (*h, *b, *d) = st.cell(*h, b_in, d_in);
                    *k = blend(pend & (*d < 2.0 * PI), 1.0, 0.0);
                } else {
                    *h = st.height(*h);
                    (*b, *d) = (b_in, d_in);
                    *k = blend(pend, 1.0, 0.0);
                }
                *k != 0.0
            };
            let mut any = false;
            kept.fill(0.0); // the cells put at the floor stay unmarked
            let (hr, br, dr) = (
                &mut h[r.clone()],
                &mut bias[r.clone()],
                &mut delta[r.clone()],
            );
            let mut others = |h: &mut [f32], b: &mut [f32], d: &mut [f32], at: usize| {
                let k = &mut kept[at..at + h.len()];
                match (as_block(h), as_block(b), as_block(d), as_block(k)) {
                    // Fixed-length loop: the form that vectorises.
                    (Some(hb), Some(bb), Some(db), Some(kb)) => {
                        for i in 0..SETTLE_BLOCK {
                            any |= settle(&mut hb[i], &mut bb[i], &mut db[i], &mut kb[i]);
                        }
                    }
                    _ => {
                        let cells = h.iter_mut().zip(b.iter_mut()).zip(d.iter_mut());
                        for (((h, b), d), k) in cells.zip(k.iter_mut()) {
                            any |= settle(h, b, d, k);
                        }
                    }
                }
            };
            if st.floor > 0.0 {
                st.settle_chunks(hr, br, dr, others);
            } else {
                let blocks = (hr.chunks_mut(SETTLE_BLOCK))
                    .zip(br.chunks_mut(SETTLE_BLOCK))
                    .zip(dr.chunks_mut(SETTLE_BLOCK));
                for (i, ((hb, bb), db)) in blocks.enumerate() {
                    others(hb, bb, db, i * SETTLE_BLOCK);
                }
            }
            if !any {
                continue;
            }
            let dy = ly - (y0 + (j as f32 + 0.5) * s);
            let (ts, als) = (&mut theta[r.clone()], &mut alpha[r]);
            kept_headings(kept, ts, als, (x0, s, lx, dy), bearing, obs.shape.slope);
        }
        self.last_height
    }

    /// Row `j` of the bearing pass, every cell through the branch-free
    /// [`bearing_cell`] (and [`range_member`] when `RANGE`), so the loops
    /// vectorise, atan2 included. `MIN` selects [`Combine::Min`].
    ///
    /// Two sweeps keep few values live at once (one sweep spilled most of
    /// them): the first writes each cell's observed heading and range factor
    /// to the line buffers, the second intersects. Both go by runs of cells
    /// ([`next_run`]): blocks of [`LANES`] cells holding a known heading
    /// (and the cells after the last whole block) are intersected; a block
    /// whose headings are all unknown (`Δ ≥ 2π`: most of a grid after a few
    /// products, see the floor in [`super::cells::Settle`]) only takes its
    /// range factor and is left [`PENDING`] for
    /// [`FuzzyGrid::bearing_settle`], which gives it the observation's set
    /// — what [`bearing_cell`] would select for it — with the atan2 only
    /// where it is kept.
    #[inline(never)]
    fn bearing_row<const RANGE: bool, const MIN: bool>(
        &mut self,
        j: usize,
        lx: f32,
        ly: f32,
        rt: Trapezoid,
        bearing: f32,
        o: ObsSet,
    ) {
        let s = self.cell;
        let x0 = self.x0;
        let y = self.y0 + (j as f32 + 0.5) * s;
        let dy = ly - y;
        let n = self.nx;
        let lo = j * n;
        let FuzzyGrid {
            h,
            theta,
            delta,
            alpha,
            bias,
            work,
            ..
        } = self;
        let hs = &mut h[lo..lo + n];
        let ts = &mut theta[lo..lo + n];
        let ds = &mut delta[lo..lo + n];
        let als = &mut alpha[lo..lo + n];
        let bs = &mut bias[lo..lo + n];
        let ocs = &mut work.line[..n];
        let fs = &mut work.line_out[..n];
        observed_headings(ocs, ds, (x0, s, lx, dy), bearing);
        range_factors::<RANGE>(fs, &rt, (x0, s, lx, dy));
        // The unknown blocks between runs: consistency 1, and the set waits
        // for the settle pass (PENDING). The runs: every cell through the
        // intersection, in one loop over slices (the form the compiler
        // vectorises; per block of four it compiled lane by lane).
        let mut c = 0;
        while c < n {
            let (a, b) = next_run(ds, c);
            for (h, (d, &f)) in hs[c..a].iter_mut().zip(ds[c..a].iter_mut().zip(&fs[c..a])) {
                *d = PENDING;
                *h = combine_with::<MIN>(*h, f);
            }
            let cells = hs[a..b]
                .iter_mut()
                .zip(ts[a..b].iter_mut())
                .zip(ds[a..b].iter_mut())
                .zip(als[a..b].iter_mut())
                .zip(bs[a..b].iter_mut())
                .zip(ocs[a..b].iter().zip(&fs[a..b]));
            for (((((h, t), d), al), bi), (&oc, &f)) in cells {
                let (nt, nd, na, nb, cons) = bearing_cell(*t, *d, *al, *bi, oc, o);
                (*t, *d, *al, *bi) = (nt, nd, na, nb);
                *h = combine_with::<MIN>(*h, f * cons);
            }
            c = b;
        }
    }

    /// Row `j` of the bearing pass in plain scalar code, for the inputs the
    /// branch-free row does not cover.
    fn bearing_row_scalar(
        &mut self,
        j: usize,
        lx: f32,
        ly: f32,
        rt: Option<Trapezoid>,
        bearing: f32,
    ) {
        let obs = self.cfg.bearing.around(0.0);
        let s = self.cell;
        let combine = self.cfg.combine;
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
            o.center = crate::core::angle::wrap_pi_f32(fast_atan2(dy, dx) - bearing);
            if self.delta[i] >= 2.0 * PI {
                // Heading unknown: the intersection is the observation's
                // set and the consistency is 1 (exactly what
                // `intersect_angle` gives, without its work).
                self.theta[i] = o.center;
                self.delta[i] = o.shape.core;
                self.alpha[i] = o.shape.slope;
                self.bias[i] *= o.shape.bias;
                let v = &mut self.h[i];
                *v = match combine {
                    Combine::Product => *v * f,
                    Combine::Min => v.min(f),
                };
                continue;
            }
            let a = Trapezoid::raw(
                self.theta[i],
                self.delta[i],
                self.alpha[i],
                1.0,
                self.bias[i],
            );
            let (n, cons) = a.intersect_with_consistency(&o);
            f *= cons;
            self.theta[i] = n.center;
            self.delta[i] = n.shape.core;
            self.alpha[i] = n.shape.slope;
            self.bias[i] = n.shape.bias;
            let v = &mut self.h[i];
            *v = match combine {
                Combine::Product => *v * f,
                Combine::Min => v.min(f),
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whole bearing updates (the branch-free rows, then the settle pass
    /// that completes the cells left pending) must give the floats of the
    /// scalar rows followed by the plain settle, on every kind of heading
    /// set: unknown, wide enough that its support covers the circle,
    /// rectangles (no flank), disjoint and overlapping; with cells falling
    /// under the floor, with no floor, and with a bearing beyond ±π (scalar
    /// rows). One stated difference: a cell whose heading was unknown and
    /// that ends under the floor keeps its old θ and α (the reference gives
    /// it the observed heading before forgetting it); its set is the full
    /// circle in both.
    #[test]
    fn bearing_updates_match_scalar_rows() {
        use crate::grid::{Combine, GridConfig};
        let mut rnd = crate::grid::test_rng(987_654_321u32);
        let same = |x: f32, y: f32| x.to_bits() == y.to_bits();
        for combine in [Combine::Product, Combine::Min] {
            for floor in [1e-8, 0.0, 0.05] {
                for round in 0..8 {
                    let cfg = GridConfig {
                        combine,
                        floor,
                        ..GridConfig::default()
                    };
                    let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, 2.3, 1.7]).unwrap();
                    for j in 0..g.ny() {
                        for i in 0..g.nx() {
                            // Every third row all unknown, so that whole
                            // blocks are left pending by the pass.
                            let kind = if j % 3 == 0 { 0 } else { (rnd() * 6.0) as u32 };
                            let delta = match kind {
                                0 | 5 => 2.0 * PI,
                                1 => 2.0 * PI * rnd(),
                                2 => 4.0 + 2.0 * rnd(),
                                _ => 0.6 * rnd(),
                            };
                            let alpha = if rnd() < 0.2 {
                                0.0
                            } else {
                                3.0 * rnd() * rnd()
                            };
                            let t =
                                Trapezoid::new(PI * (2.0 * rnd() - 1.0), delta, alpha, 1.0, rnd());
                            g.set_heading_set(i, j, t);
                            let nx = g.nx();
                            // Some cells far under the floor after the update.
                            let h = if rnd() < 0.3 { 1e-9 * rnd() } else { rnd() };
                            g.possibilities_mut()[j * nx + i] = h;
                        }
                    }
                    let (lx, ly) = (3.0 * rnd() - 0.5, 3.0 * rnd() - 0.5);
                    let bearing = match round {
                        7 => 3.5, // beyond ±π: every row scalar
                        _ => PI * (2.0 * rnd() - 1.0),
                    };
                    let range = if round % 2 == 0 {
                        Some(2.0 * rnd())
                    } else {
                        None
                    };
                    let mut a = g.clone();
                    let raw = a.bearing_pass(lx, ly, range, bearing);
                    let ha = a.bearing_settle(raw, lx, ly, bearing);
                    let mut b = g.clone();
                    let rt = range.map(|r| g.cfg.range.around(r));
                    for j in 0..g.ny() {
                        b.bearing_row_scalar(j, lx, ly, rt, bearing);
                    }
                    let hb = b.finish_update();
                    let ctx = format!("{combine:?}, floor {floor}, round {round}");
                    assert!(same(ha, hb), "height {ha} vs {hb} ({ctx})");
                    for i in 0..g.h.len() {
                        assert!(
                            same(a.h[i], b.h[i]),
                            "h {i}: {} vs {} ({ctx})",
                            a.h[i],
                            b.h[i]
                        );
                        assert!(same(a.delta[i], b.delta[i]), "Δ {i} ({ctx})");
                        assert!(same(a.bias[i], b.bias[i]), "b {i} ({ctx})");
                        // θ and α as the reference's, or, only for a cell
                        // whose heading was unknown and is forgotten again,
                        // as they were.
                        let forgot = g.delta[i] >= 2.0 * PI && a.delta[i] >= 2.0 * PI;
                        let (ta, aa) = (a.theta[i], a.alpha[i]);
                        let as_ref = same(ta, b.theta[i]) && same(aa, b.alpha[i]);
                        let as_was = same(ta, g.theta[i]) && same(aa, g.alpha[i]);
                        assert!(as_ref || (forgot && as_was), "θ, α {i} ({ctx})");
                    }
                }
            }
        }
    }

    /// The range pass against every cell evaluated by
    /// [`Trapezoid::linear`], bit for bit: the annulus bounds, the rows
    /// off it taken in one sweep,
    /// for biases from 0 to 1, flat and steep flanks, landmarks inside and
    /// outside the grid, readings from 0 to beyond it, both combinations.
    #[test]
    fn range_pass_matches_every_cell() {
        use crate::grid::{Combine, GridConfig, SensorModel};
        let mut rnd = crate::grid::test_rng(31_337u32);
        for combine in [Combine::Product, Combine::Min] {
            for (bias, slope_abs, slope_rel) in [
                (0.1, 0.2, 0.15),
                (0.0, 0.05, 0.0),
                (0.5, 0.0, 0.0),
                (1.0, 0.3, 0.1),
                (0.02, 1.5, 0.4),
            ] {
                let range = SensorModel {
                    core_abs: 0.1,
                    core_rel: 0.05,
                    slope_abs,
                    slope_rel,
                    bias,
                };
                let cfg = GridConfig {
                    combine,
                    range,
                    ..GridConfig::default()
                };
                for _ in 0..6 {
                    let mut g = FuzzyGrid::new(cfg.clone(), [0.0, 0.0, 7.3, 4.9]).unwrap();
                    for v in g.h.iter_mut() {
                        *v = rnd();
                    }
                    let before = g.h.clone();
                    let (lx, ly) = (9.0 * rnd() - 1.0, 7.0 * rnd() - 1.0);
                    let r = 8.0 * rnd() * rnd();
                    let t = cfg.range.around(r);
                    g.range_pass(lx, ly, r);
                    for j in 0..g.ny {
                        for i in 0..g.nx {
                            let (x, y) = g.cell_center(i, j);
                            let (dx, dy) = (lx - x, ly - y);
                            let f = t.linear((dx * dx + dy * dy).sqrt());
                            let v = before[j * g.nx + i];
                            let want = match combine {
                                Combine::Product => v * f,
                                Combine::Min => v.min(f),
                            };
                            let got = g.h[j * g.nx + i];
                            assert_eq!(
                                got.to_bits(),
                                want.to_bits(),
                                "cell ({i}, {j}), landmark ({lx}, {ly}), r {r}, bias {bias}: {got} vs {want}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn floor_and_ceil_match_std() {
        let mut rnd = crate::grid::test_rng(8u32);
        let specials = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.5,
            -2.5,
            8_388_607.5,
            -8_388_607.5,
        ];
        let wide = [
            8_388_608.0,
            1e10,
            -1e10,
            f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        let vals = specials
            .into_iter()
            .chain(wide)
            .chain((0..5000).map(|_| (rnd() - 0.5) * 4e3));
        for v in vals {
            // Equal as numbers (a zero may differ in sign), NaN for NaN.
            assert_eq!(floor(v), v.floor(), "floor({v})");
            assert_eq!(ceil(v), v.ceil(), "ceil({v})");
        }
        assert!(floor(f32::NAN).is_nan() && ceil(f32::NAN).is_nan());
    }

    #[test]
    fn fast_atan2_matches_std() {
        let mut worst = 0.0f32;
        for i in -50..=50 {
            for j in -50..=50 {
                let (y, x) = (i as f32 * 0.37, j as f32 * 0.41);
                if x == 0.0 && y == 0.0 {
                    continue;
                }
                worst =
                    worst.max(crate::core::angle::wrap_pi_f32(fast_atan2(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(worst < 2e-5, "worst error {worst}");
    }
}
