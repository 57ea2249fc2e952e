//! The rotation of the robot between two scans, from the scans alone: no right angles needed.
//! Used by [`super::compass::CompassTracker`] in place of the odometry's turn between two scans
//! (`compass.scan_rotation`). Depends on nothing but the scans' points in the robot frame.
//!
//! Every pair of valid scan points `stride` beams apart and at most `max_gap_m` apart is a short
//! wall segment; its direction, as a line (modulo 180°), votes with its length into a histogram
//! of 1° bins, smoothed over ±`smooth_deg` (circular). When the robot turns by `Δ`, every wall
//! turns by `−Δ` in its frame, so the current histogram is the previous one shifted by `−Δ`:
//! the turn is the shift `s` maximising the normalised circular cross-correlation
//! `ρ(s) = Σ_b cur[b] · prev[b + s] / (‖cur‖ ‖prev‖)`, searched in whole degrees within
//! `±window` of the odometry's turn and refined by a parabola through the peak and its two
//! neighbours. Curved walls, furniture and clutter vote too: what they share from scan to scan
//! turns with the robot as well, so a lab without one right angle still gives its turn.
//!
//! The estimate is refused (and the odometry's turn kept) when the correlation has no clear
//! peak: the peak lies on the edge of the window (the true one may lie beyond), the
//! correlation varies by less than `min_contrast` over the window (a round room seen from its
//! centre, or clutter whose directions are spread evenly, looks the same however the robot
//! turns), or another local maximum at least [`SECOND_PEAK`] of the peak's height above the
//! window's floor lies more than twice the smoothing away from it (two turns explain the scans
//! alike). Lines fold modulo 180°, so the window must stay under 90°: a rectangular room's
//! histogram repeats every 90° and a window of ±35° holds one of its peaks.

/// Bins of the line-direction histogram: 1° each over 180°.
pub const BINS: usize = 180;

/// A second local maximum this high (as a share of the peak's height above the window's
/// lowest correlation) makes the peak ambiguous.
pub const SECOND_PEAK: f64 = 0.8;

/// The scan's short wall segments into `out`: for every pair of valid points `stride` beams
/// apart (at least one), its length and direction in degrees (`atan2`), unless it is longer
/// than `max_gap_m` or shorter than 1e-6 m. Computed once per scan for [`line_histogram_of`]
/// and the compass's wall orientation, which vote with the same segments.
///
/// # Complexity
/// `O(n)` in the number of points; no allocation beyond `out`'s growth.
pub fn segments(
    points: &[Option<(f64, f64)>],
    stride: usize,
    max_gap_m: f64,
    out: &mut Vec<(f64, f64)>,
) {
    out.clear();
    let stride = stride.max(1);
    for (a, b) in points.iter().zip(points.iter().skip(stride)) {
        let (Some(a), Some(b)) = (a, b) else {
            continue;
        };
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = dx.hypot(dy);
        // A NaN length is kept (the orientation counts it, the histogram does not).
        if len > max_gap_m || len < 1e-6 {
            continue;
        }
        out.push((len, dy.atan2(dx).to_degrees()));
    }
}

/// The length-weighted, smoothed histogram of the scan's segment directions modulo 180° into
/// `out` (see the module docs); `false` (and `out` zero) when the scan has no segment.
///
/// # Complexity
/// `O(n)` in the number of points plus `O(BINS · smooth)`; allocates the segments (the
/// tracker reuses them through [`line_histogram_of`]).
pub fn line_histogram(
    points: &[Option<(f64, f64)>],
    stride: usize,
    max_gap_m: f64,
    smooth_deg: f64,
    out: &mut [f64; BINS],
) -> bool {
    let mut found = Vec::new();
    segments(points, stride, max_gap_m, &mut found);
    line_histogram_of(&found, max_gap_m, smooth_deg, out)
}

/// [`line_histogram`] from the scan's [`segments`] (with the same `max_gap_m`).
///
/// # Complexity
/// `O(n)` in the number of segments plus `O(BINS · smooth)`; no allocation.
pub fn line_histogram_of(
    segments: &[(f64, f64)],
    max_gap_m: f64,
    smooth_deg: f64,
    out: &mut [f64; BINS],
) -> bool {
    let mut raw = [0.0f64; BINS];
    let mut total = 0.0;
    for &(len, deg) in segments {
        if !(1e-6..=max_gap_m).contains(&len) {
            continue;
        }
        let deg = deg.rem_euclid(180.0);
        raw[(deg as usize).min(BINS - 1)] += len;
        total += len;
    }
    out.fill(0.0);
    if !(total > 0.0 && total.is_finite()) {
        return false;
    }
    let w = smooth_deg.round().clamp(0.0, 45.0) as usize;
    for (c, o) in out.iter_mut().enumerate() {
        // c − w … c + w, circular: c + BINS − w … c + BINS + w modulo BINS.
        *o = (c + BINS - w..=c + BINS + w)
            .map(|k| raw[k % BINS])
            .sum::<f64>();
    }
    true
}

/// The robot's turn (radians, counter-clockwise) from the scan of histogram `prev` to that of
/// `cur`, searched within `±window_deg` of `around` (radians, the odometry's turn); `None` when
/// the correlation has no clear peak there (see the module docs).
///
/// # Complexity
/// `O(BINS · window)`; no allocation.
pub fn rotation_between(
    prev: &[f64; BINS],
    cur: &[f64; BINS],
    around: f64,
    window_deg: f64,
    min_contrast: f64,
    smooth_deg: f64,
) -> Option<f64> {
    let (start, rho, n) = correlation(prev, cur, around, window_deg)?;
    let rho = &rho[..n];
    let best = peak_of(rho, smooth_deg, min_contrast)?;
    // The vertex of the parabola through the peak and its neighbours (both exist: the peak is
    // inside the window), within half a degree of it.
    let (l, m, r) = (rho[best - 1], rho[best], rho[best + 1]);
    let curv = l - 2.0 * m + r;
    let offset = if curv < 0.0 {
        (0.5 * (l - r) / curv).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    Some((start as f64 + best as f64 + offset).to_radians())
}

/// The normalised correlation `ρ(s)` of the module docs for the whole-degree shifts
/// `start … start + n − 1` around `around` (radians) within `±window_deg`: `(start, ρ, n)`;
/// `None` when either histogram is empty or `around` is not finite.
fn correlation(
    prev: &[f64; BINS],
    cur: &[f64; BINS],
    around: f64,
    window_deg: f64,
) -> Option<(i64, [f64; 2 * 89 + 1], usize)> {
    let norm =
        (cur.iter().map(|v| v * v).sum::<f64>() * prev.iter().map(|v| v * v).sum::<f64>()).sqrt();
    let centre = around.to_degrees();
    if !(norm > 0.0 && norm.is_finite() && centre.is_finite()) {
        return None;
    }
    let half = window_deg.round().clamp(1.0, 89.0) as i64;
    // Shifts centre − half … centre + half, whole degrees.
    let start = centre.round() as i64 - half;
    let mut rho = [0.0f64; 2 * 89 + 1];
    let n = (2 * half + 1) as usize;
    for (j, r) in rho.iter_mut().enumerate().take(n) {
        let s = (start + j as i64).rem_euclid(BINS as i64) as usize;
        *r = cur
            .iter()
            .enumerate()
            .map(|(b, v)| v * prev[(b + s) % BINS])
            .sum::<f64>()
            / norm;
    }
    Some((start, rho, n))
}

/// Up to `out.len()` candidate turns (radians) from the scan of histogram `prev` to that of
/// `cur` within `±window_deg` of `around`: the local maxima of the correlation inside the
/// window, highest first, each at least half as high above the window's floor as the
/// highest. Unlike [`rotation_between`] it takes ambiguous peaks too: the caller tells them
/// apart (the scan matcher, by the points). Returns how many were written.
pub fn rotation_candidates(
    prev: &[f64; BINS],
    cur: &[f64; BINS],
    around: f64,
    window_deg: f64,
    out: &mut [f64],
) -> usize {
    let Some((start, rho, n)) = correlation(prev, cur, around, window_deg) else {
        return 0;
    };
    let rho = &rho[..n];
    let floor = rho.iter().copied().fold(f64::INFINITY, f64::min);
    let mut peaks: Vec<(usize, f64)> = (1..n.saturating_sub(1))
        .filter(|&j| rho[j] > rho[j - 1] && rho[j] >= rho[j + 1])
        .map(|j| (j, rho[j]))
        .collect();
    peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
    let top = peaks.first().map_or(floor, |p| p.1);
    let mut k = 0;
    for &(j, height) in peaks.iter().take(out.len()) {
        if height - floor < 0.5 * (top - floor) {
            break;
        }
        out[k] = (start as f64 + j as f64).to_radians();
        k += 1;
    }
    k
}

/// The index of the one clear peak of `rho`, if it has one (see the module docs).
fn peak_of(rho: &[f64], smooth_deg: f64, min_contrast: f64) -> Option<usize> {
    let n = rho.len();
    let (best, top) = rho
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let floor = rho.iter().copied().fold(f64::INFINITY, f64::min);
    let rise = top - floor;
    if best == 0 || best + 1 >= n || rise.is_nan() || rise < min_contrast {
        return None;
    }
    let apart = 2.0 * smooth_deg.max(0.0) + 1.0;
    let rival = (1..n - 1).any(|j| {
        let local = rho[j] >= rho[j - 1] && rho[j] >= rho[j + 1];
        local
            && (j as f64 - best as f64).abs() > apart
            && rho[j] - floor >= SECOND_PEAK * (top - floor)
    });
    (!rival).then_some(best)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The points of a 180° scan of 181 beams 1° apart (−90° … 90°) whose range along robot
    /// bearing `b` (radians) is `range(b)`.
    fn scan(range: impl Fn(f64) -> f64) -> Vec<Option<(f64, f64)>> {
        (0..=180)
            .map(|i| {
                let b = (f64::from(i) - 90.0).to_radians();
                let r = range(b);
                r.is_finite().then(|| (r * b.cos(), r * b.sin()))
            })
            .collect()
    }

    /// Range to the walls of a 6 m × 4 m room from a robot 1 m east and 0.5 m north of its
    /// centre, heading `yaw` (radians) in the room's frame.
    fn room(yaw: f64) -> impl Fn(f64) -> f64 {
        move |b: f64| {
            let (s, c) = (b + yaw).sin_cos();
            let (px, py) = (1.0, 0.5);
            let tx = if c > 1e-12 {
                (3.0 - px) / c
            } else if c < -1e-12 {
                (-3.0 - px) / c
            } else {
                f64::INFINITY
            };
            let ty = if s > 1e-12 {
                (2.0 - py) / s
            } else if s < -1e-12 {
                (-2.0 - py) / s
            } else {
                f64::INFINITY
            };
            tx.min(ty)
        }
    }

    fn hist(points: &[Option<(f64, f64)>]) -> [f64; BINS] {
        let mut h = [0.0; BINS];
        assert!(line_histogram(points, 1, 0.2, 3.0, &mut h));
        h
    }

    fn turn(prev: &[f64; BINS], cur: &[f64; BINS], odometry_deg: f64) -> Option<f64> {
        rotation_between(prev, cur, odometry_deg.to_radians(), 35.0, 0.1, 3.0).map(f64::to_degrees)
    }

    #[test]
    fn a_rotated_room_gives_its_turn_whatever_the_odometry_says() {
        // The robot turns from 10° to 32° on the spot: 22°, every wall at −22° in its frame.
        let prev = hist(&scan(room(10f64.to_radians())));
        let cur = hist(&scan(room(32f64.to_radians())));
        for odometry in [0.0, 22.0, 40.0, 50.0] {
            let t = turn(&prev, &cur, odometry).expect("a clear peak");
            assert!((t - 22.0).abs() < 1.0, "odometry {odometry}: {t}");
        }
        // Turning back is the opposite turn.
        let back = turn(&cur, &prev, -30.0).expect("a clear peak");
        assert!((back + 22.0).abs() < 1.0, "{back}");
    }

    #[test]
    fn a_curved_wall_and_one_straight_wall_give_the_turn() {
        // A round room of radius 3 m centred 1 m behind the robot, cut by a straight wall 2 m
        // to its left (y = 2 in the room's frame): no right angle anywhere. The robot turns
        // 15° on the spot (from −5° to 10°); odometry says 35°.
        let world = |yaw: f64| {
            move |b: f64| {
                let (s, c) = (b + yaw).sin_cos();
                // Ray from (0, 0) against the circle |p − (−1, 0)| = 3: t² + 2t·c − 8 = 0.
                let circle = -c + (c * c + 8.0).sqrt();
                let wall = if s > 1e-12 { 2.0 / s } else { f64::INFINITY };
                circle.min(wall)
            }
        };
        let prev = hist(&scan(world(-5f64.to_radians())));
        let cur = hist(&scan(world(10f64.to_radians())));
        let t = turn(&prev, &cur, 35.0).expect("a clear peak");
        assert!((t - 15.0).abs() < 1.5, "{t}");
    }

    #[test]
    fn no_structure_falls_back_to_the_odometry() {
        // A round room seen from its centre: segment k joins beams k − 90° and k − 89°, so its
        // direction is k + 0.5° (mod 180°) and its length the same for every k — one vote per
        // bin, a flat histogram, the same for every turn.
        let round = hist(&scan(|_| 3.0));
        let spread = round.iter().fold(0.0f64, |m, v| m.max(v - round[0]).abs());
        assert!(spread < 1e-9, "{spread}");
        assert_eq!(turn(&round, &round, 10.0), None);
        // No valid return at all: no histogram.
        let mut h = [1.0; BINS];
        assert!(!line_histogram(&scan(|_| f64::NAN), 1, 0.2, 3.0, &mut h));
        assert!(h.iter().all(|&v| v == 0.0));
        assert_eq!(rotation_between(&h, &round, 0.0, 35.0, 0.1, 3.0), None);
    }

    #[test]
    fn a_peak_on_the_window_edge_or_doubled_is_refused() {
        // One wall direction at 90° before, at 50° now: the correlation ρ(s) is prev[50 + s],
        // a spike at a 40° turn.
        let mut prev = [0.0; BINS];
        let mut cur = [0.0; BINS];
        prev[90] = 1.0;
        cur[50] = 1.0;
        let t = rotation_between(&prev, &cur, 30f64.to_radians(), 35.0, 0.1, 0.0).unwrap();
        assert!((t.to_degrees() - 40.0).abs() < 1e-9);
        // A ramp prev[b] = b up to 90°: within ±35° of 0, ρ(s) = (50 + s)/‖…‖ rises to the
        // window's edge, where the true peak may lie beyond.
        let mut ramp = [0.0; BINS];
        for (b, v) in ramp.iter_mut().enumerate().take(91) {
            *v = b as f64;
        }
        assert_eq!(rotation_between(&ramp, &cur, 0.0, 35.0, 0.1, 0.0), None);
        // Two equal directions 20° apart in the current scan: turns of 40° and 20° explain it.
        cur[70] = 1.0;
        assert_eq!(
            rotation_between(&prev, &cur, 30f64.to_radians(), 35.0, 0.1, 0.0),
            None
        );
    }

    #[test]
    fn candidates_hold_every_clear_turn_highest_first() {
        // Two wall directions in the previous scan (90° and 30°, the first twice as long), one
        // at 50° now: turns of 40° and −20° both explain it, the 40° one better.
        let mut prev = [0.0; BINS];
        let mut cur = [0.0; BINS];
        prev[90] = 2.0;
        prev[30] = 1.0;
        cur[50] = 1.0;
        let mut out = [0.0; 3];
        let n = rotation_candidates(&prev, &cur, 10f64.to_radians(), 35.0, &mut out);
        let got: Vec<f64> = out[..n].iter().map(|t| t.to_degrees().round()).collect();
        assert_eq!(got, vec![40.0, -20.0]);
        // The second is under half the first's height above the floor: left out.
        prev[30] = 0.4;
        let n = rotation_candidates(&prev, &cur, 10f64.to_radians(), 35.0, &mut out);
        assert_eq!(n, 1);
        // No room for any, or no histogram: none.
        assert_eq!(rotation_candidates(&prev, &cur, 0.0, 35.0, &mut []), 0);
        let empty = [0.0; BINS];
        assert_eq!(rotation_candidates(&empty, &cur, 0.0, 35.0, &mut out), 0);
        assert_eq!(
            rotation_candidates(&prev, &cur, f64::NAN, 35.0, &mut out),
            0
        );
    }
}
