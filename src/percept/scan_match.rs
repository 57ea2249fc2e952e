//! The motion of the robot between two consecutive scans, measured on the scans by a
//! point-to-line ICP: used by [`super::compass::CompassTracker`] for the turn (and the
//! translation) of its prediction in place of the odometry's (`compass.scan_match`). Depends
//! on the scans' points in the robot frame, [`Pose2`] and `nalgebra` only.
//!
//! # Method
//! The previous scan is the reference: every kept beam (one per `beam_deg`) whose two
//! neighbours about a degree away on either side are valid, near and on one line with it
//! carries the unit normal of that line. The current scan's kept points `q` are moved by the
//! motion estimate `(t, θ)` and paired with the nearest reference point `p` within a gate (a
//! grid of cells `min_pair_m` wide: a query looks at the cells within the gate of its own);
//! each pair's residual is the distance to the reference's line, `r = n · (R(θ) q + t − p)`. A damped Gauss–Newton step
//! on `(t_x, t_y, θ)` minimises `Σ w r²` with Cauchy weights `w = 1 / (1 + (r/σ)²)`
//! (`σ = max_rms_m`: a pair far off the line, clutter or a wall seen only from one side,
//! weighs little). The gate shrinks from `max_pair_m` to `min_pair_m` over the first
//! iterations, so that a start a metre off still finds its pairs and the end pairs only
//! points that belong together.
//!
//! Odometry can turn 30° wrong between two scans (the CSAIL log), and from so far off the
//! pairs of an ICP lead it astray; so it starts from the odometry's motion *and* from each
//! candidate turn of the scans' own line-direction correlation
//! ([`super::scan_rotation::rotation_candidates`]), each with the odometry's translation (a
//! start within 2° of an earlier one is skipped), and keeps a start that converged over one
//! that did not, then the one that ends with the most points on a reference line.
//!
//! # Acceptance
//! A match is taken only when it converged (the last step moved less than 1 cm and 0.1°), at
//! least `min_overlap` of the current scan's kept points lie within `min_pair_m` of a reference
//! point and within `2σ` of its line, their weighted RMS residual is at most `max_rms_m`, and
//! the normals constrain every direction of the motion: the smallest eigenvalue of the normal
//! matrix (per unit weight, the turn in metres at the points' RMS distance) is at least
//! `min_constraint` (a corridor's parallel walls leave the motion along it free; a round room
//! seen from its centre, the turn), or, when only its turn is used, the turn alone
//! ([`Match::turn_constraint`]). Otherwise the caller keeps the odometry.

use nalgebra::{Matrix3, SymmetricEigen, Vector3};

use crate::core::angle::wrap_pi;
use crate::core::Pose2;

/// Parameters of the match (from [`super::compass::CompassConfig`]'s `scan_match_*` keys).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MatchParams {
    /// Most Gauss–Newton iterations per start.
    pub iterations: usize,
    /// Pairing gate of the first iteration, metres.
    pub max_pair_m: f64,
    /// Pairing gate of the last iterations and of the overlap, metres.
    pub min_pair_m: f64,
    /// Largest accepted weighted RMS residual, metres; also the Cauchy scale `σ`.
    pub max_rms_m: f64,
    /// Least share of the current scan's kept points on a reference line.
    pub min_overlap: f64,
    /// Least smallest eigenvalue of the normal matrix per unit weight.
    pub min_constraint: f64,
}

/// A match of the current scan onto the previous one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Match {
    /// The robot's motion: the current pose in the previous pose's frame (as an odometry
    /// increment).
    pub motion: Pose2,
    /// Weighted RMS point-to-line residual of the pairs, metres.
    pub rms: f64,
    /// Share of the current scan's kept points on a reference line.
    pub overlap: f64,
    /// Smallest eigenvalue of the normal matrix per unit weight.
    pub constraint: f64,
    /// How well the normals constrain the turn alone, per unit weight: `1 / (H⁻¹)_θθ` of the
    /// normal matrix `H` per unit weight (slightly damped), the turn in metres at the points'
    /// RMS distance. A corridor constrains its turn though not the motion along it.
    pub turn_constraint: f64,
    /// Whether the last step was below the convergence threshold.
    pub converged: bool,
}

impl Match {
    /// Whether the match passes every test of the module docs' "Acceptance"; with
    /// `turn_only`, the constraint test is on the turn alone (its translation is not used).
    pub fn accepted(&self, p: &MatchParams, turn_only: bool) -> bool {
        let constraint = if turn_only {
            self.turn_constraint
        } else {
            self.constraint
        };
        self.fits(p) && constraint >= p.min_constraint
    }

    /// Whether the match passes every test but the constraint's: it converged onto the
    /// reference's lines (its turn is measured, though the walls may leave its motion free).
    pub fn fits(&self, p: &MatchParams) -> bool {
        self.converged && self.rms <= p.max_rms_m && self.overlap >= p.min_overlap
    }
}

/// The reference scan (points with normals, robot frame) and its grid; the current scan's
/// points. Buffers are reused from scan to scan.
#[derive(Debug, Clone, Default)]
pub struct ScanMatcher {
    ref_points: Vec<(f64, f64)>,
    ref_normals: Vec<(f64, f64)>,
    grid: Grid,
    cur: Vec<(f64, f64)>,
    cur_normals: Vec<(f64, f64)>,
    has_ref: bool,
}

/// Convergence: a step below a centimetre and a tenth of a degree.
const STEP_M: f64 = 1e-2;
const STEP_RAD: f64 = 1.75e-3;

impl ScanMatcher {
    /// Forgets the reference (the next scan has nothing to be matched onto).
    pub fn reset(&mut self) {
        self.has_ref = false;
    }

    /// Takes the current scan (`points`, robot frame, `None` = no return; every `keep`-th
    /// beam, normals from the beams `span` away), matches it onto the previous scan from the
    /// motion `guess` and from `guess` turned to each of `turns` (radians, the whole turn),
    /// and keeps it as the next reference. The best start's match, accepted or not; `None`
    /// without a reference, a finite guess or any pair.
    pub fn step(
        &mut self,
        points: &[Option<(f64, f64)>],
        keep: usize,
        span: usize,
        guess: Option<&Pose2>,
        turns: &[f64],
        p: &MatchParams,
    ) -> Option<Match> {
        with_normals(points, keep, span, &mut self.cur, &mut self.cur_normals);
        let finite = guess.filter(|g| g.x.is_finite() && g.y.is_finite() && g.theta.is_finite());
        let result = match finite {
            Some(g) if self.has_ref && !self.cur.is_empty() => {
                let starts = std::iter::once(g.theta).chain(turns.iter().copied());
                // A start within 2° of an earlier one ends where it does.
                let mut tried = [f64::NAN; 9];
                starts
                    .filter(|t| t.is_finite())
                    .enumerate()
                    .filter(|&(k, t)| {
                        let again = tried.iter().any(|u| wrap_pi(t - u).abs() < 0.035);
                        if let Some(slot) = tried.get_mut(k) {
                            *slot = t;
                        }
                        !again
                    })
                    .map(|(_, t)| t)
                    .filter_map(|theta| self.refine(Pose2 { theta, ..*g }, p))
                    .max_by(|a, b| {
                        (a.converged, a.overlap)
                            .partial_cmp(&(b.converged, b.overlap))
                            .unwrap_or(std::cmp::Ordering::Equal)
                    })
            }
            _ => None,
        };
        // The current scan becomes the reference (only its points with a normal are indexed:
        // a pair needs the reference's line).
        std::mem::swap(&mut self.ref_points, &mut self.cur);
        std::mem::swap(&mut self.ref_normals, &mut self.cur_normals);
        self.has_ref = !self.ref_points.is_empty();
        self.grid
            .build(&self.ref_points, &self.ref_normals, p.min_pair_m);
        result
    }

    /// Gauss–Newton from `start` (see the module docs).
    fn refine(&self, start: Pose2, p: &MatchParams) -> Option<Match> {
        let mut x = Vector3::new(start.x, start.y, start.theta);
        let scale = rms_distance(&self.cur).max(1e-3);
        let mut converged = false;
        let mut last = None;
        let mut previous = Vector3::zeros();
        for k in 0..p.iterations.max(1) {
            let gate = (p.max_pair_m * 0.6f64.powi(k as i32)).max(p.min_pair_m);
            let sys = self.normal_equations(&x, gate, scale, p.max_rms_m);
            if sys.weight <= 0.0 {
                return None;
            }
            // Levenberg damping: a direction the normals leave free does not move.
            let damped = sys.h + Matrix3::identity() * (1e-6 * sys.weight);
            let step = damped.cholesky()?.solve(&(-sys.g));
            let mut step = Vector3::new(step.x, step.y, step.z / scale);
            // A step back against the previous one is the pairs flipping between two
            // solutions: halve it, so that they settle between them.
            if step.dot(&previous) < 0.0 {
                step *= 0.5;
            }
            previous = step;
            x += step;
            last = Some(sys);
            let small = step.x.hypot(step.y) < STEP_M && step.z.abs() < STEP_RAD;
            if small && gate <= p.min_pair_m {
                converged = true;
                break;
            }
        }
        let sys = self.normal_equations(&x, p.min_pair_m, scale, p.max_rms_m);
        let h = if sys.weight > 0.0 { sys.h } else { last?.h };
        let (constraint, turn_constraint) = constraints(&h, sys.weight);
        Some(Match {
            motion: Pose2 {
                x: x.x,
                y: x.y,
                theta: wrap_pi(x.z),
            },
            rms: (sys.residual / sys.weight.max(1e-12)).sqrt(),
            overlap: sys.inliers as f64 / self.cur.len().max(1) as f64,
            constraint,
            turn_constraint,
            converged,
        })
    }

    /// The weighted normal equations of the point-to-line residuals at `x = (t_x, t_y, θ)`,
    /// the turn scaled to metres at `scale`; pairs within `gate` only.
    fn normal_equations(&self, x: &Vector3<f64>, gate: f64, scale: f64, sigma: f64) -> System {
        let (s, c) = x.z.sin_cos();
        let mut sum = Sums::default();
        for &(qx, qy) in &self.cur {
            let (rx, ry) = (c * qx - s * qy, s * qx + c * qy);
            let (px, py) = (rx + x.x, ry + x.y);
            let Some(j) = self.grid.nearest(&self.ref_points, px, py, gate) else {
                continue;
            };
            let (n, (ax, ay)) = (self.ref_normals[j], self.ref_points[j]);
            if n == (0.0, 0.0) {
                continue;
            }
            let r = n.0 * (px - ax) + n.1 * (py - ay);
            let w = 1.0 / (1.0 + (r / sigma).powi(2));
            sum.add([n.0, n.1, (n.1 * rx - n.0 * ry) / scale], w, r);
            sum.inliers += usize::from(r.abs() <= 2.0 * sigma);
        }
        sum.system()
    }
}

/// The running sums of [`ScanMatcher::normal_equations`]: the six distinct entries of the
/// symmetric `Σ w J Jᵀ` (each `(Jᵢ Jⱼ) w` added as `J Jᵀ w` adds it, so the matrix is the
/// same bit for bit with half the work).
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    h: [f64; 6],
    g: [f64; 3],
    weight: f64,
    residual: f64,
    inliers: usize,
}

impl Sums {
    /// Adds one pair: its Jacobian row `j`, weight `w` and residual `r`.
    fn add(&mut self, j: [f64; 3], w: f64, r: f64) {
        let h = &mut self.h;
        h[0] += j[0] * j[0] * w;
        h[1] += j[0] * j[1] * w;
        h[2] += j[0] * j[2] * w;
        h[3] += j[1] * j[1] * w;
        h[4] += j[1] * j[2] * w;
        h[5] += j[2] * j[2] * w;
        let wr = w * r;
        for (g, ji) in self.g.iter_mut().zip(j) {
            *g += ji * wr;
        }
        self.weight += w;
        self.residual += w * r * r;
    }

    fn system(&self) -> System {
        let h = &self.h;
        System {
            h: Matrix3::new(h[0], h[1], h[2], h[1], h[3], h[4], h[2], h[4], h[5]),
            g: Vector3::from(self.g),
            weight: self.weight,
            residual: self.residual,
            inliers: self.inliers,
        }
    }
}

/// Normal equations of one iteration and what they sum.
#[derive(Debug, Clone, Copy, Default)]
struct System {
    h: Matrix3<f64>,
    g: Vector3<f64>,
    weight: f64,
    residual: f64,
    inliers: usize,
}

/// The smallest eigenvalue of the normal matrix `h` per unit of the weight, and how well
/// it constrains the turn alone (see [`Match::turn_constraint`]); zeros without weight.
fn constraints(h: &Matrix3<f64>, weight: f64) -> (f64, f64) {
    if !(weight > 0.0 && weight.is_finite()) {
        return (0.0, 0.0);
    }
    let per = h / weight;
    let smallest = SymmetricEigen::new(per)
        .eigenvalues
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    // A little damping keeps the inverse finite when a translation is free.
    let turn = (per + Matrix3::identity() * 1e-3)
        .try_inverse()
        .map_or(0.0, |inv| 1.0 / inv[(2, 2)]);
    (smallest.max(0.0), turn.max(0.0))
}

/// Root-mean-square distance of `points` from the origin.
fn rms_distance(points: &[(f64, f64)]) -> f64 {
    if points.is_empty() {
        return 0.0;
    }
    let s: f64 = points.iter().map(|p| p.0 * p.0 + p.1 * p.1).sum();
    (s / points.len() as f64).sqrt()
}

/// Every `keep`-th valid point of `points` into `out`, with in `normals` the unit normal of
/// the line through its neighbours `span` beams away, or `(0, 0)` when they are missing, far
/// (more than 0.3 m, or five times the spacing of the pair) or not on one line with it.
fn with_normals(
    points: &[Option<(f64, f64)>],
    keep: usize,
    span: usize,
    out: &mut Vec<(f64, f64)>,
    normals: &mut Vec<(f64, f64)>,
) {
    out.clear();
    normals.clear();
    let span = span.max(1);
    for (i, p) in points.iter().enumerate().step_by(keep.max(1)) {
        let Some(&(px, py)) = p.as_ref().filter(|p| p.0.is_finite() && p.1.is_finite()) else {
            continue;
        };
        out.push((px, py));
        let a = i
            .checked_sub(span)
            .and_then(|k| points.get(k))
            .copied()
            .flatten();
        let b = points.get(i + span).copied().flatten();
        normals.push(match (a, b) {
            (Some(a), Some(b)) => line_normal(a, (px, py), b),
            _ => (0.0, 0.0),
        });
    }
}

/// The unit normal of the line `a`–`b` when `p` lies on it between them (within 2 cm plus 5 %
/// of their distance) and both are within 0.3 m of `p`; `(0, 0)` otherwise.
fn line_normal(a: (f64, f64), p: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = dx.hypot(dy);
    // Squared, not `hypot` (a library call, the scan's costliest step here).
    let near = |q: (f64, f64)| (q.0 - p.0).powi(2) + (q.1 - p.1).powi(2) <= 0.3 * 0.3;
    if !(len > 1e-6 && len.is_finite() && near(a) && near(b)) {
        return (0.0, 0.0);
    }
    let n = (-dy / len, dx / len);
    let off = (n.0 * (p.0 - a.0) + n.1 * (p.1 - a.1)).abs();
    if off <= 0.02 + 0.05 * len {
        n
    } else {
        (0.0, 0.0)
    }
}

/// A uniform grid over the reference points, each cell listing its points, so that the
/// nearest point within a gate is in the cells within the gate of the query's cell (the
/// 3 × 3 around it when the gate is a cell wide).
#[derive(Debug, Clone, Default)]
struct Grid {
    origin: (f64, f64),
    cell: f64,
    /// `1 / cell`.
    per_cell: f64,
    dims: (usize, usize),
    /// Per cell, where its points start in `order` (one more entry than cells).
    start: Vec<u32>,
    order: Vec<u32>,
}

/// Most cells along a side (a scan 80 m across at 0.5 m cells has 160).
const MAX_CELLS: usize = 256;

impl Grid {
    /// Indexes the points that have a normal (only they can make a pair).
    fn build(&mut self, points: &[(f64, f64)], normals: &[(f64, f64)], gate: f64) {
        let (mut lo, mut hi) = ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN));
        let lined = |i: usize| normals.get(i).is_some_and(|n| *n != (0.0, 0.0));
        for (_, &(x, y)) in points.iter().enumerate().filter(|(i, _)| lined(*i)) {
            lo = (lo.0.min(x), lo.1.min(y));
            hi = (hi.0.max(x), hi.1.max(y));
        }
        self.start.clear();
        self.order.clear();
        if !(lo.0 <= hi.0 && gate > 0.0 && gate.is_finite()) {
            self.dims = (0, 0);
            return;
        }
        let span = (hi.0 - lo.0).max(hi.1 - lo.1);
        self.cell = gate.max(span / (MAX_CELLS - 1) as f64);
        self.per_cell = 1.0 / self.cell;
        self.origin = lo;
        let side = |d: f64| ((d / self.cell) as usize + 1).min(MAX_CELLS);
        self.dims = (side(hi.0 - lo.0), side(hi.1 - lo.1));
        let cells = self.dims.0 * self.dims.1;
        self.start.resize(cells + 1, 0);
        let index: Vec<usize> = (0..points.len())
            .map(|i| match lined(i) {
                true => self.cell_of(points[i].0, points[i].1),
                false => usize::MAX,
            })
            .collect();
        for &c in index.iter().filter(|&&c| c != usize::MAX) {
            self.start[c + 1] += 1;
        }
        for c in 0..cells {
            self.start[c + 1] += self.start[c];
        }
        let mut fill = self.start.clone();
        self.order.resize(self.start[cells] as usize, 0);
        for (i, &c) in index.iter().enumerate().filter(|(_, &c)| c != usize::MAX) {
            self.order[fill[c] as usize] = i as u32;
            fill[c] += 1;
        }
    }

    /// The cell of a point inside the grid's bounds (clamped to them).
    fn cell_of(&self, x: f64, y: f64) -> usize {
        let cx = (((x - self.origin.0) / self.cell).max(0.0) as usize).min(self.dims.0 - 1);
        let cy = (((y - self.origin.1) / self.cell).max(0.0) as usize).min(self.dims.1 - 1);
        cy * self.dims.0 + cx
    }

    /// Updates `best` with the points of cells `a..b` (one run of `order`). Inlined: as a
    /// call it spills the query's registers, a third of the pairing's instructions.
    #[inline(always)]
    fn scan_run(&self, points: &[(f64, f64)], a: usize, b: usize, q: (f64, f64), best: &mut Best) {
        let (a, b) = (self.start[a] as usize, self.start[b] as usize);
        for (k, &i) in (a..b).zip(&self.order[a..b]) {
            let (px, py) = points[i as usize];
            let d2 = (px - q.0).powi(2) + (py - q.1).powi(2);
            if d2 < best.d2 || (d2 == best.d2 && k >= best.k) {
                *best = Best { d2, k, found: true };
            }
        }
    }

    /// The index of the point of `points` nearest to `(x, y)` within `gate`, if any; of
    /// equally near points, the one latest in `order` (as a scan of the rows upwards would
    /// keep). The rows are searched outwards from the query's, each side only while the row's
    /// nearest edge is not farther than the best point so far.
    fn nearest(&self, points: &[(f64, f64)], x: f64, y: f64, gate: f64) -> Option<usize> {
        if self.dims.0 == 0 || !(x.is_finite() && y.is_finite()) {
            return None;
        }
        // Times the reciprocal (a division is the query's slowest step): a coordinate a
        // rounding off moves no point across the margins below, so the answer is the same.
        let fx = (x - self.origin.0) * self.per_cell;
        let fy = (y - self.origin.1) * self.per_cell;
        let reach = gate / self.cell + 1.0;
        let (w, h) = (self.dims.0 as f64, self.dims.1 as f64);
        if fx < -reach || fy < -reach || fx >= w + reach || fy >= h + reach {
            return None;
        }
        let (cx, cy) = (floor(fx), floor(fy));
        // Cells within the gate of the query's cell: one ring when cells are as wide as it.
        let ring = (gate / self.cell).ceil().clamp(1.0, 8.0) as i64;
        let (w, h) = (self.dims.0 as i64, self.dims.1 as i64);
        let (x0, x1) = ((cx - ring).max(0), (cx + ring).min(w - 1));
        let (y0, y1) = ((cy - ring).max(0), (cy + ring).min(h - 1));
        if x0 > x1 || y0 > y1 {
            return None;
        }
        let mut best = Best {
            d2: gate * gate,
            k: 0,
            found: false,
        };
        let row = |gy: i64, best: &mut Best| {
            // The points of a row's cells x0..=x1 lie together in `order`, cell after cell.
            let (a, b) = ((gy * w + x0) as usize, (gy * w + x1) as usize + 1);
            self.scan_run(points, a, b, (x, y), best);
        };
        // A row's points are at least its edge's distance from the query, less a margin far
        // above the rounding of their cells (1e-6 cells); a row beyond the best is skipped.
        let beyond = |cells: f64, best: &Best| {
            let d = (cells - 1e-6).max(0.0) * self.cell;
            d * d > best.d2
        };
        let first = cy.clamp(y0, y1);
        row(first, &mut best);
        let (mut down, mut up) = (first - 1, first + 1);
        loop {
            let more_down = down >= y0 && !beyond(fy - (down + 1) as f64, &best);
            if more_down {
                row(down, &mut best);
                down -= 1;
            }
            let more_up = up <= y1 && !beyond(up as f64 - fy, &best);
            if more_up {
                row(up, &mut best);
                up += 1;
            }
            if !(more_down || more_up) {
                break;
            }
        }
        best.found.then(|| self.order[best.k] as usize)
    }
}

/// The nearest point so far: its squared distance and its place in [`Grid::order`].
#[derive(Debug, Clone, Copy)]
struct Best {
    d2: f64,
    k: usize,
    found: bool,
}

/// `v.floor()` for a finite `v` well within `i64` (the std call is a library call without
/// SSE4.1, a tenth of the pairing's cost).
fn floor(v: f64) -> i64 {
    let t = v as i64;
    if (t as f64) > v {
        t - 1
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn params() -> MatchParams {
        MatchParams {
            iterations: 20,
            max_pair_m: 1.0,
            min_pair_m: 0.2,
            max_rms_m: 0.05,
            min_overlap: 0.3,
            min_constraint: 0.01,
        }
    }

    /// Range from `(px, py)` along the map bearing `b` to the nearest of `walls` (segments).
    fn cast(px: f64, py: f64, b: f64, walls: &[[f64; 4]]) -> f64 {
        let (dx, dy) = (b.cos(), b.sin());
        walls
            .iter()
            .filter_map(|&[x0, y0, x1, y1]| {
                let (ex, ey) = (x1 - x0, y1 - y0);
                let den = dx * ey - dy * ex;
                if den.abs() < 1e-12 {
                    return None;
                }
                let t = ((x0 - px) * ey - (y0 - py) * ex) / den;
                let u = ((x0 - px) * dy - (y0 - py) * dx) / den;
                (t > 0.0 && (0.0..=1.0).contains(&u)).then_some(t)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// A 180° scan of 361 beams (0.5°) from the pose `(x, y, yaw)` among `walls`, each range
    /// disturbed by `noise(i)` metres; points in the robot frame, `None` beyond 40 m.
    fn scan(
        pose: (f64, f64, f64),
        walls: &[[f64; 4]],
        noise: impl Fn(usize) -> f64,
    ) -> Vec<Option<(f64, f64)>> {
        (0..361)
            .map(|i| {
                let b = -PI / 2.0 + i as f64 * PI / 360.0;
                let r = cast(pose.0, pose.1, pose.2 + b, walls) + noise(i);
                (r < 40.0).then(|| (r * b.cos(), r * b.sin()))
            })
            .collect()
    }

    /// An L-shaped room (8 m × 6 m with a 3 m × 2 m corner cut out) and a pillar.
    fn room() -> Vec<[f64; 4]> {
        vec![
            [-2.0, -3.0, 6.0, -3.0],
            [6.0, -3.0, 6.0, 1.0],
            [6.0, 1.0, 3.0, 1.0],
            [3.0, 1.0, 3.0, 3.0],
            [3.0, 3.0, -2.0, 3.0],
            [-2.0, 3.0, -2.0, -3.0],
            [1.0, -1.5, 1.4, -1.5],
            [1.4, -1.5, 1.4, -1.1],
        ]
    }

    /// Deterministic noise of about ±`amp` metres (a hash of the beam, no random source).
    fn jitter(amp: f64, seed: u64) -> impl Fn(usize) -> f64 {
        move |i| {
            let h = (i as u64 ^ seed).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11;
            amp * (2.0 * (h as f64 / (1u64 << 53) as f64) - 1.0)
        }
    }

    fn matched(
        first: &[Option<(f64, f64)>],
        second: &[Option<(f64, f64)>],
        guess: &Pose2,
        turns: &[f64],
    ) -> Option<Match> {
        let mut m = ScanMatcher::default();
        assert!(m.step(first, 2, 2, None, &[], &params()).is_none());
        m.step(second, 2, 2, Some(guess), turns, &params())
    }

    #[test]
    fn a_known_motion_in_a_room_is_recovered_from_a_wrong_odometry() {
        // The robot moves 0.6 m forward, 0.2 m left and turns 12°; ranges jitter by ±1 cm.
        let walls = room();
        let truth = Pose2 {
            x: 0.6,
            y: 0.2,
            theta: 12f64.to_radians(),
        };
        let a = scan((0.0, 0.0, 0.0), &walls, jitter(0.01, 1));
        let b = scan((truth.x, truth.y, truth.theta), &walls, jitter(0.01, 2));
        // Odometry 0.15 m and 6° off: within reach of the match from the odometry alone.
        let odometry = Pose2 {
            x: 0.5,
            y: 0.3,
            theta: 6f64.to_radians(),
        };
        let m = matched(&a, &b, &odometry, &[]).expect("a match");
        assert!(m.accepted(&params(), false), "{m:?}");
        // Tolerances: 2 cm and 0.3°, about the jitter's effect on a few hundred pairs.
        assert!((m.motion.x - truth.x).abs() < 0.02, "{m:?}");
        assert!((m.motion.y - truth.y).abs() < 0.02, "{m:?}");
        assert!(
            (m.motion.theta - truth.theta).abs() < 0.3f64.to_radians(),
            "{m:?}"
        );
    }

    #[test]
    fn a_candidate_turn_rescues_an_odometry_thirty_degrees_off() {
        let walls = room();
        let truth = Pose2 {
            x: 0.4,
            y: 0.0,
            theta: 35f64.to_radians(),
        };
        let a = scan((0.0, 0.0, 0.0), &walls, |_| 0.0);
        let b = scan((truth.x, truth.y, truth.theta), &walls, |_| 0.0);
        let odometry = Pose2 {
            theta: 5f64.to_radians(),
            ..truth
        };
        // The candidate is 2° off the truth, as a whole-degree correlation peak may be.
        let m = matched(&a, &b, &odometry, &[33f64.to_radians()]).expect("a match");
        assert!(m.accepted(&params(), false), "{m:?}");
        assert!(
            (m.motion.theta - truth.theta).abs() < 0.2f64.to_radians(),
            "{m:?}"
        );
    }

    #[test]
    fn degenerate_scans_are_refused() {
        let odometry = Pose2 {
            x: 0.5,
            y: 0.0,
            theta: 0.0,
        };
        // A corridor, 2 m wide and 200 m long: the motion along it is free.
        let corridor = [[-100.0, -1.0, 100.0, -1.0], [-100.0, 1.0, 100.0, 1.0]];
        let a = scan((0.0, 0.0, 0.0), &corridor, |_| 0.0);
        let b = scan((0.8, 0.0, 0.0), &corridor, |_| 0.0);
        let m = matched(&a, &b, &odometry, &[]).expect("pairs");
        assert!(!m.accepted(&params(), false), "{m:?}");
        // Its turn alone is constrained (a corridor's walls give its direction).
        assert!(m.turn_constraint > 0.01, "{m:?}");
        // One wall only, seen end-on: the same.
        let wall = [[-100.0, -1.0, 100.0, -1.0]];
        let a = scan((0.0, 0.0, 0.0), &wall, |_| 0.0);
        let b = scan((0.8, 0.0, 0.0), &wall, |_| 0.0);
        if let Some(m) = matched(&a, &b, &odometry, &[]) {
            assert!(!m.accepted(&params(), false), "{m:?}");
        }
        // Empty scans, no returns, NaN ranges and a NaN odometry: no match, no panic.
        let empty: Vec<Option<(f64, f64)>> = Vec::new();
        assert!(matched(&empty, &empty, &odometry, &[]).is_none());
        let nan = vec![Some((f64::NAN, 1.0)); 361];
        assert!(matched(&nan, &nan, &odometry, &[f64::NAN]).is_none());
        let none = vec![None; 361];
        assert!(matched(&none, &none, &odometry, &[]).is_none());
        let walls = room();
        let a = scan((0.0, 0.0, 0.0), &walls, |_| 0.0);
        let bad = Pose2 {
            x: f64::NAN,
            ..odometry
        };
        assert!(matched(&a, &a, &bad, &[]).is_none());
    }

    #[test]
    fn the_grid_finds_the_plain_nearest_point() {
        let points: Vec<(f64, f64)> = (0..200)
            .map(|i| {
                let t = f64::from(i) * 0.37;
                (5.0 * t.sin() + 0.1 * t, 3.0 * (1.3 * t).cos())
            })
            .collect();
        let normals = vec![(1.0, 0.0); points.len()];
        let mut grid = Grid::default();
        grid.build(&points, &normals, 0.2);
        for k in 0..300 {
            let (x, y) = (f64::from(k) * 0.05 - 7.0, f64::from(k % 17) * 0.4 - 3.5);
            for gate in [0.2, 0.5, 1.0] {
                let plain = points
                    .iter()
                    .enumerate()
                    .map(|(i, p)| (i, (p.0 - x).hypot(p.1 - y)))
                    .filter(|&(_, d)| d <= gate)
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|(i, _)| i);
                let found = grid.nearest(&points, x, y, gate);
                let dist = |i: Option<usize>| i.map(|i| (points[i].0 - x).hypot(points[i].1 - y));
                assert_eq!(dist(found), dist(plain), "({x}, {y}) within {gate}");
            }
        }
    }

    #[test]
    fn the_sums_are_the_full_outer_products_bit_for_bit() {
        // The plain form: J Jᵀ w and J (w r) added as 3 × 3 and 3 × 1 matrices.
        let (mut h, mut g) = (Matrix3::<f64>::zeros(), Vector3::<f64>::zeros());
        let (mut weight, mut residual) = (0.0, 0.0);
        let mut sums = Sums::default();
        let noise = jitter(1.0, 7);
        for k in 0..500 {
            let a = noise(3 * k) * 3.0;
            let j = [a.cos(), a.sin(), noise(3 * k + 1) * 40.0];
            let (r, w) = (noise(3 * k + 2) * 0.1, 1.0 / (1.0 + noise(k + 9).powi(2)));
            let jac = Vector3::from(j);
            h += jac * jac.transpose() * w;
            g += jac * (w * r);
            weight += w;
            residual += w * r * r;
            sums.add(j, w, r);
        }
        let sys = sums.system();
        let bits = |m: &[f64]| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(sys.h.as_slice()), bits(h.as_slice()));
        assert_eq!(bits(sys.g.as_slice()), bits(g.as_slice()));
        assert_eq!(sys.weight.to_bits(), weight.to_bits());
        assert_eq!(sys.residual.to_bits(), residual.to_bits());
    }

    #[test]
    fn of_equally_near_points_the_grid_keeps_the_last_in_its_order() {
        // A 0.1 m lattice, each node twice (exact ties), queried at nodes, edge midpoints and
        // cell centres (ties between two and four nodes) and off the lattice; the reference
        // reads every indexed point in the grid's order and keeps the last of the nearest,
        // as a scan of all rows upwards does.
        let mut points = Vec::new();
        for i in 0..30 {
            for j in 0..20 {
                let p = (f64::from(i) * 0.1 - 1.0, f64::from(j) * 0.1 + 0.5);
                points.extend([p, p]);
            }
        }
        let normals = vec![(0.0, 1.0); points.len()];
        let mut grid = Grid::default();
        grid.build(&points, &normals, 0.2);
        let order: Vec<usize> = grid.order.iter().map(|&i| i as usize).collect();
        let mut ties = 0;
        for k in 0..400 {
            let x = f64::from(k % 40) * 0.05 - 1.3;
            let y = f64::from(k / 40) * 0.05 * 3.0 + 0.37 * f64::from(k % 3) - 0.2;
            for gate in [0.2, 0.36, 1.0] {
                let d2 = |i: usize| (points[i].0 - x).powi(2) + (points[i].1 - y).powi(2);
                let reference = order
                    .iter()
                    .enumerate()
                    .filter(|&(_, &i)| d2(i) <= gate * gate)
                    .min_by(|a, b| d2(*a.1).total_cmp(&d2(*b.1)).then(b.0.cmp(&a.0)))
                    .map(|(_, &i)| i);
                if let Some(r) = reference {
                    ties += order.iter().filter(|&&i| d2(i) == d2(r)).count() / 2 - 1;
                }
                assert_eq!(
                    grid.nearest(&points, x, y, gate),
                    reference,
                    "({x}, {y}) {gate}"
                );
            }
        }
        // The queries do meet ties between distinct nodes (not only the duplicates).
        assert!(ties > 100, "{ties}");
    }
}
