//! The metric place tracker (`engine::grid_tracker`): hand-worked frames on small maps (carried
//! by odometry, relocalized after a kidnap, held back between places, blurred without a
//! heading), and a brute-force reference of the module docs' formulas — per-cell loops, the
//! dilation as an explicit sup-min over the square element — that it must match on random maps
//! and frames.

use lplace::core::Odometry;
use lplace::engine::grid_tracker::{GridTrackConfig, GridTracker};
use lplace::engine::tracker::TrackerConfig;
use lplace::logic::{clamp_degree, Decision, DecisionParams, PlaceDistribution};
use lplace::map::Map;
use lplace::syntax::parse_map;
use proptest::prelude::*;

fn map(text: &str) -> Map {
    Map::from_ast(&parse_map(text).expect("map parses")).expect("map builds")
}

/// Two boxes in a row: A = [0, 2] × [0, 1], B = [2, 4] × [0, 1].
fn row_of_two() -> Map {
    map("place A corridor at (1, 0.5) extent box (0, 0, 2, 1);
         place B corridor at (3, 0.5) extent box (2, 0, 4, 1);
         path A -- B;")
}

/// Cells of 0.5 m and no margin, so that the grid is exactly the boxes; no blur unless asked.
fn config(flank_per_metre: f64) -> TrackerConfig {
    TrackerConfig {
        bias: 0.05,
        min_support: 0.2,
        grid: Some(GridTrackConfig {
            cell_size: 0.5,
            margin: 0.0,
            flank: 0.0,
            flank_per_metre,
            floor: 0.001,
            evidence_length_m: 0.0,
            evidence_max_weight: 1.0,
            evidence_scans: 10.0,
            relative_floor: 1.0,
            start_radius: 1.0,
        }),
        ..TrackerConfig::default()
    }
}

const PARAMS: DecisionParams = DecisionParams {
    threshold: 0.5,
    margin: 0.1,
};

fn evidence(support: &[f64], possibility: &[f64]) -> PlaceDistribution {
    let mut d = PlaceDistribution::new(support.len());
    d.support = support.to_vec();
    d.possibility = possibility.to_vec();
    d
}

fn east(dx: f64) -> Odometry {
    Odometry {
        forward: dx,
        left: 0.0,
        turn: 0.0,
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-6
}

#[test]
fn the_belief_moves_with_the_robot() {
    let m = row_of_two();
    let mut t = GridTracker::new(&m, PARAMS, &config(0.0));
    assert_eq!(t.geometry().0, 8, "8 columns of 0.5 m over x ∈ [0, 4]");
    // Frame 1, evidence for A: A's cells × 1, B's × 0.2; h = 1. π_A = 1, π_B = 0.2, nothing
    // between places: N_A = 1 − 0.2 = 0.8 → A.
    let d = t.step(&evidence(&[0.8, 0.0], &[1.0, 0.2]), east(0.0), Some(0.0));
    assert_eq!(d.place(), Some(0));
    let dist = t.distribution();
    assert!(close(dist.possibility[1], 0.2) && close(dist.necessity[0], 0.8));
    // Frame 2, 1 m east (2 columns), evidence both places share: columns 2–5 hold A's old 1,
    // 6–7 B's old 0.2, 0–1 entered empty and are floored. π_A = π_B = 1: N = 0, disoriented.
    let shared = evidence(&[0.4, 0.4], &[1.0, 1.0]);
    let d = t.step(&shared, east(1.0), Some(0.0));
    assert!(matches!(d, Decision::Disoriented(_)), "{d:?}");
    assert!(close(t.distribution().necessity[1], 0.0));
    // Frame 3, 1 m further: columns 4–7 hold 1, columns 2–3 the floor 0.001: π_A = 0.001,
    // N_B = 0.999 → B.
    let d = t.step(&shared, east(1.0), Some(0.0));
    assert_eq!(d.place(), Some(1));
    assert!(close(t.distribution().possibility[0], 0.001));
    assert!(close(t.distribution().necessity[1], 0.999));
}

/// π_B after a first frame with no information and then `steps` frames of `metres` each,
/// with no heading (blurred, not moved: by less than a cell's reach here) and evidence for A
/// (A × 1, B × 0.25), evidence taken per `length` metres (0: per frame).
fn pi_b_after(steps: usize, metres: f64, length: f64) -> f64 {
    let mut cfg = config(0.0);
    if let Some(g) = cfg.grid.as_mut() {
        g.evidence_length_m = length;
    }
    let mut t = GridTracker::new(&row_of_two(), PARAMS, &cfg);
    t.step(&evidence(&[0.4, 0.4], &[1.0, 1.0]), east(0.0), None);
    for _ in 0..steps {
        t.step(&evidence(&[0.8, 0.0], &[1.0, 0.25]), east(metres), None);
    }
    t.distribution().possibility[1]
}

#[test]
fn evidence_is_taken_per_metre_not_per_frame() {
    // Per 0.5 m: two frames 0.25 m apart take B's 0.25 at w = 0.5 each, 0.25^0.5 · 0.25^0.5 =
    // 0.25, as one frame 0.5 m on does (w = 1); four frames 0.125 m apart, 0.25 too.
    assert!(close(pi_b_after(1, 0.5, 0.5), 0.25));
    assert!(close(pi_b_after(2, 0.25, 0.5), 0.25));
    assert!(close(pi_b_after(4, 0.125, 0.5), 0.25));
    // Per frame, the denser log is the surer one: 0.25² and 0.25⁴.
    assert!(close(pi_b_after(2, 0.25, 0.0), 0.0625));
    assert!(close(pi_b_after(4, 0.125, 0.0), 0.25f64.powi(4)));
    // Standing still takes no evidence; 2 m in one frame is still one look (w capped at 1).
    assert!(close(pi_b_after(3, 0.0, 0.5), 1.0));
    assert!(close(pi_b_after(1, 2.0, 0.5), 0.25));
}

/// B's possibility after one frame standing still with evidence `support` and `possibility`
/// (Π'), A surveyed from 1000 scans and B from `scans` (`None`: no `param scans`), the grid's
/// settings changed by `set`.
fn pi_b_surveyed(
    scans: Option<u32>,
    set: impl Fn(&mut GridTrackConfig),
    support: [f64; 2],
    possibility: [f64; 2],
) -> f64 {
    let b = scans.map_or(";".to_owned(), |n| format!(" {{ param scans = {n}; }}"));
    let m = map(&format!(
        "place A corridor at (1, 0.5) extent box (0, 0, 2, 1) {{ param scans = 1000; }}
         place B corridor at (3, 0.5) extent box (2, 0, 4, 1){b}
         path A -- B;"
    ));
    let mut cfg = config(0.0);
    if let Some(g) = cfg.grid.as_mut() {
        set(g);
    }
    let mut t = GridTracker::new(&m, PARAMS, &cfg);
    t.step(&evidence(&support, &possibility), east(0.0), None);
    t.distribution().possibility[1]
}

/// B's possibility after one frame against it (Π'_B = 0.25) with `evidence_scans`.
fn pi_b_with_scans(scans: Option<u32>, evidence_scans: f64) -> f64 {
    let set = |g: &mut GridTrackConfig| g.evidence_scans = evidence_scans;
    pi_b_surveyed(scans, set, [0.8, 0.0], [1.0, 0.25])
}

#[test]
fn a_place_fitted_from_few_scans_takes_a_share_of_its_evidence() {
    // A (1000 scans) is the evidence's best place, factor 1 whatever its share. B's 0.25 is
    // taken to n / (n + 10): 10 scans, 0.25^0.5 = 0.5; 30 scans, 0.25^0.75; 0 scans, none.
    assert!(close(pi_b_with_scans(Some(10), 10.0), 0.5));
    assert!(close(pi_b_with_scans(Some(30), 10.0), 0.25f64.powf(0.75)));
    assert!(close(pi_b_with_scans(Some(0), 10.0), 1.0));
    // A place without a count (described, or written by hand), or `evidence_scans = 0`: whole.
    assert!(close(pi_b_with_scans(None, 10.0), 0.25));
    assert!(close(pi_b_with_scans(Some(10), 0.0), 0.25));
}

/// B's possibility after one frame whose normalised possibilities leave A and B alike (Π' = 1
/// each: the drowned frame) while their supports are `support`, evidence taken whole.
fn pi_b_relative(relative_floor: f64, scans_b: Option<u32>, support: [f64; 2]) -> f64 {
    let set = |g: &mut GridTrackConfig| {
        g.evidence_scans = 0.0;
        g.relative_floor = relative_floor;
    };
    pi_b_surveyed(scans_b, set, support, [1.0, 1.0])
}

#[test]
fn a_surveyed_place_that_fits_worse_than_the_best_loses_down_to_the_relative_floor() {
    // B's support is 0.2 / 0.8 = 0.25 of the best: its factor is min(1, max(floor, 0.25)).
    assert!(close(pi_b_relative(0.5, Some(50), [0.8, 0.2]), 0.5));
    assert!(close(pi_b_relative(0.1, Some(50), [0.8, 0.2]), 0.25));
    // 1 turns it off; B equal to the best loses nothing.
    assert!(close(pi_b_relative(1.0, Some(50), [0.8, 0.2]), 1.0));
    assert!(close(pi_b_relative(0.1, Some(50), [0.8, 0.8]), 1.0));
    // Only surveyed places take it (B described keeps Π'), and a frame without support says
    // nothing.
    assert!(close(pi_b_relative(0.1, None, [0.8, 0.2]), 1.0));
    assert!(close(pi_b_relative(0.1, Some(50), [0.0, 0.0]), 1.0));
}

/// The decision after one frame standing still that tells A and B apart in nothing, on the row
/// of two with `start` (if any) and `start_radius`.
fn first_decision(start: Option<(f64, f64)>, radius: f64) -> (Decision, Vec<f64>) {
    let s = start.map_or(String::new(), |(x, y)| format!("start ({x}, {y});"));
    let m = map(&format!(
        "{s} place A corridor at (1, 0.5) extent box (0, 0, 2, 1);
         place B corridor at (3, 0.5) extent box (2, 0, 4, 1);
         path A -- B;"
    ));
    let mut cfg = config(0.0);
    if let Some(g) = cfg.grid.as_mut() {
        g.start_radius = radius;
    }
    let mut t = GridTracker::new(&m, PARAMS, &cfg);
    let d = t.step(&evidence(&[0.4, 0.4], &[1.0, 1.0]), east(0.0), Some(0.0));
    (d, t.distribution().possibility.clone())
}

#[test]
fn the_belief_starts_at_the_maps_start() {
    // Cells of 0.5 m: centres x = 0.25, 0.75, …, y = 0.25, 0.75. Within 0.5 m of (0.75, 0.5)
    // lie (0.75, 0.25) and (0.75, 0.75), both in A (0.25 m away; (0.25, 0.25) is 0.56 m): A's
    // cells start at 1, B's at the floor 0.001, so N_A = 0.999.
    let (d, pi) = first_decision(Some((0.75, 0.5)), 0.5);
    assert_eq!(d.place(), Some(0));
    assert!(close(pi[0], 1.0) && close(pi[1], 0.001), "{pi:?}");
    // A radius reaching both places (the whole row is within 3.3 m) starts from ignorance.
    let (d, pi) = first_decision(Some((2.0, 0.5)), 3.3);
    assert!(matches!(d, Decision::Disoriented(_)), "{d:?}");
    assert!(close(pi[0], 1.0) && close(pi[1], 1.0));
    // No start, or one whose radius holds no cell centre (off the grid): total ignorance.
    for (start, radius) in [
        (None, 1.0),
        (Some((10.0, 10.0)), 1.0),
        (Some((0.5, 0.5)), 0.1),
    ] {
        let (d, pi) = first_decision(start, radius);
        assert!(matches!(d, Decision::Disoriented(_)), "{start:?}: {d:?}");
        assert!(close(pi[0], 1.0) && close(pi[1], 1.0));
    }
}

#[test]
fn a_kidnapped_robot_relocalizes_through_the_floor() {
    let m = row_of_two();
    let mut t = GridTracker::new(&m, PARAMS, &config(0.0));
    // Long evidence for A: A = 1, B at the floor 0.001 (0.2 each frame, floored).
    for _ in 0..20 {
        t.step(&evidence(&[0.8, 0.0], &[1.0, 0.2]), east(0.0), Some(0.0));
    }
    assert!(close(t.distribution().possibility[1], 0.001));
    // Now the evidence says B: A's cells × 0.2, B's × 1. With B = x < 0.2 the height is A's 0.2
    // (Inc = 0.8), so B grows fivefold a frame: 0.005 and 0.025 (N_A = 1 − x clears Inc by more
    // than the 0.1 margin: A), 0.125 (N_A − Inc = 0.075: disoriented), 0.625 (N_A = 0.375:
    // disoriented); then B's 0.625 is the height: A = 0.2/0.625 = 0.32, B = 1, N_B = 0.68,
    // Inc = 0.375 → B.
    let kidnapped = evidence(&[0.0, 0.8], &[0.2, 1.0]);
    let mut got = Vec::new();
    for _ in 0..5 {
        got.push(t.step(&kidnapped, east(0.0), Some(0.0)).place());
    }
    assert_eq!(got, vec![Some(0), Some(0), None, None, Some(1)]);
    assert!(close(t.distribution().possibility[0], 0.32));
    assert!(close(t.distribution().necessity[1], 0.68));
}

#[test]
fn a_belief_between_places_makes_no_place_necessary() {
    // A = [0, 1] × [0, 1], B = [3, 4] × [0, 1]: the columns over (1, 3) are between places.
    let m = map("place A corner at (0.5, 0.5) extent box (0, 0, 1, 1);
                 place B corner at (3.5, 0.5) extent box (3, 0, 4, 1);");
    let mut t = GridTracker::new(&m, PARAMS, &config(0.0));
    assert_eq!(t.cell_place(0, 0), Some(0));
    assert_eq!(t.cell_place(3, 0), None);
    assert_eq!(t.cell_place(7, 0), Some(1));
    // No evidence at all: every cell keeps 1, π_∅ = 1, so N = 0 everywhere.
    t.step(&evidence(&[0.0, 0.0], &[1.0, 1.0]), east(0.0), Some(0.0));
    assert!(close(t.between_places(), 1.0));
    assert!(close(t.distribution().necessity[0], 0.0));
    // Evidence for A (support 0.9): A's cells × 1, B's × 0.1, the cells between × max(b,
    // 1 − 0.9) = 0.1. N_A = 1 − max(0.1, 0.1) = 0.9.
    let d = t.step(&evidence(&[0.9, 0.0], &[1.0, 0.1]), east(0.0), Some(0.0));
    assert_eq!(d.place(), Some(0));
    assert!(close(t.between_places(), 0.1));
    assert!(close(t.distribution().necessity[0], 0.9));
    // Weaker evidence for A (support 0.3): the cells between keep 1 − 0.3 = 0.7, B's 0.1, so
    // N_A = 1 − 0.7 = 0.3: the robot may well be between the two, no place is chosen (without
    // the between-places world N_A would be 1 − 0.1 = 0.9).
    let mut t = GridTracker::new(&m, PARAMS, &config(0.0));
    let d = t.step(&evidence(&[0.3, 0.0], &[1.0, 0.1]), east(0.0), Some(0.0));
    assert!(matches!(d, Decision::Disoriented(_)), "{d:?}");
    assert!(close(t.between_places(), 0.7));
    assert!(close(t.distribution().necessity[0], 0.3));
}

#[test]
fn a_decided_place_is_held_until_its_necessity_falls_under_hold() {
    let m = row_of_two();
    let run = |hold: f64| {
        let cfg = TrackerConfig {
            hold,
            ..config(0.0)
        };
        let mut t = GridTracker::new(&m, PARAMS, &cfg);
        let mut out = Vec::new();
        // Standing still; support 0.3 each frame (≥ min_support 0.2, < θ).
        // 1: A's cells × 1, B's × 0.4: N_A = 0.6 ≥ 0.5, chosen.
        // 2: A × 0.75 → 0.75, B 0.4 → normalised by 0.75: π_B = 0.5333, N_A = 0.4667 < θ
        //    (Inc = 0.25).
        // 3: A × 0.5 → 0.5, B × 1 → 0.5333: π_B = 1, π_A = 0.9375, N_A = 0.
        for possibility in [[1.0, 0.4], [0.75, 1.0], [0.5, 1.0]] {
            let d = t.step(&evidence(&[0.3, 0.3], &possibility), east(0.0), Some(0.0));
            out.push((d.place(), t.distribution().necessity[0]));
        }
        out
    };
    let near = |a: f64, b: f64| (a - b).abs() < 1e-5;
    let off = run(1.0);
    let on = run(0.4);
    for (k, want) in [0.6, 1.0 - 0.4 / 0.75, 0.0].into_iter().enumerate() {
        assert!(
            near(off[k].1, want) && near(on[k].1, want),
            "frame {k}: {off:?} {on:?}"
        );
    }
    assert_eq!(
        off.iter().map(|f| f.0).collect::<Vec<_>>(),
        [Some(0), None, None]
    );
    // With hold 0.4, frame 2's N_A = 0.4667 keeps A; frame 3's 0 does not.
    assert_eq!(
        on.iter().map(|f| f.0).collect::<Vec<_>>(),
        [Some(0), Some(0), None]
    );
    // A hold above the frame's necessity keeps nothing.
    assert_eq!(run(0.5)[1].0, None);
}

#[test]
fn without_a_heading_the_belief_is_blurred_not_moved() {
    let m = row_of_two();
    let mut t = GridTracker::new(&m, PARAMS, &config(0.0));
    t.step(&evidence(&[0.8, 0.0], &[1.0, 0.2]), east(0.0), None);
    // 1 m with no heading known: no shift, a blur of flank 1 m = 2 columns instead. B's first
    // column (1 column from A's last) gets max(0.2, min(1, 1 − 1/2)) = 0.5, the next ones keep
    // 0.2 (1 − 2/2 = 0). Shared evidence: π_A = 1, π_B = 0.5.
    t.step(&evidence(&[0.4, 0.4], &[1.0, 1.0]), east(1.0), None);
    assert!(close(t.distribution().possibility[0], 1.0));
    assert!(close(t.distribution().possibility[1], 0.5));
    let b = t.belief();
    assert!(close(f64::from(b[4]), 0.5) && close(f64::from(b[5]), 0.2));
}

#[test]
fn a_map_without_places_has_a_tracker_that_never_decides() {
    let m = map("landmark L at (0, 0) id 1;");
    let mut t = GridTracker::new(&m, PARAMS, &config(0.1));
    let d = t.step(
        &PlaceDistribution::new(0),
        east(f64::NAN),
        Some(f64::INFINITY),
    );
    assert!(matches!(d, Decision::Disoriented(_)));
}

// ---- brute-force reference ----------------------------------------------------------------

/// The module docs' formulas, cell by cell.
struct Reference {
    cfg: GridTrackConfig,
    bias: f64,
    nx: usize,
    ny: usize,
    cell: f64,
    label: Vec<Option<usize>>,
    g: Vec<f64>,
    heading: Option<f64>,
    remainder: (f64, f64),
    pending: f64,
    possibility: Vec<f64>,
    necessity: Vec<f64>,
    between: f64,
}

impl Reference {
    fn new(t: &GridTracker, n: usize, cfg: &TrackerConfig) -> Reference {
        let (nx, ny, cell, _) = t.geometry();
        Reference {
            cfg: cfg.grid.unwrap_or_default(),
            bias: clamp_degree(cfg.bias),
            nx,
            ny,
            cell,
            label: (0..nx * ny).map(|k| t.cell_place(k % nx, k / nx)).collect(),
            g: vec![1.0; nx * ny],
            heading: None,
            remainder: (0.0, 0.0),
            pending: 0.0,
            possibility: vec![0.0; n],
            necessity: vec![0.0; n],
            between: 1.0,
        }
    }

    fn step(&mut self, ev: &PlaceDistribution, o: Odometry, heading: Option<f64>) {
        let fin = |v: f64| if v.is_finite() { v } else { 0.0 };
        let (dx, dy, dth) = (fin(o.forward), fin(o.left), fin(o.turn));
        let now = heading.filter(|h| h.is_finite()).map(f64::to_radians);
        let start = self.heading.or(now.map(|h| h - dth));
        self.heading = now.or(self
            .heading
            .map(|h| (h + dth).rem_euclid(std::f64::consts::TAU)));
        let ds = dx.hypot(dy);
        if ds > 0.0 {
            let mut flank = self.cfg.flank + self.cfg.flank_per_metre * ds;
            if let Some(th) = start {
                let rx = self.remainder.0 + th.cos() * dx - th.sin() * dy;
                let ry = self.remainder.1 + th.sin() * dx + th.cos() * dy;
                let sx = (rx / self.cell).round();
                let sy = (ry / self.cell).round();
                self.remainder = (rx - sx * self.cell, ry - sy * self.cell);
                let (nx, ny) = (self.nx as i64, self.ny as i64);
                let mut moved = vec![0.0; self.g.len()];
                for r in 0..ny {
                    for c in 0..nx {
                        let (sr, sc) = (r - sy as i64, c - sx as i64);
                        if (0..ny).contains(&sr) && (0..nx).contains(&sc) {
                            moved[(r * nx + c) as usize] = self.g[(sr * nx + sc) as usize];
                        }
                    }
                }
                self.g = moved;
            } else {
                flank += ds;
            }
            self.pending += flank;
            if self.pending >= self.cell {
                let f = self.pending / self.cell;
                let old: Vec<f64> = self.g.iter().map(|v| v.clamp(0.0, 1.0)).collect();
                for r in 0..self.ny {
                    for c in 0..self.nx {
                        let mut best = 0.0f64;
                        for rr in 0..self.ny {
                            for cc in 0..self.nx {
                                let d = (r.abs_diff(rr)).max(c.abs_diff(cc)) as f64;
                                let b = (1.0 - d / f).max(0.0);
                                best = best.max(old[rr * self.nx + cc].min(b));
                            }
                        }
                        self.g[r * self.nx + c] = best;
                    }
                }
                self.pending = 0.0;
            }
        }
        let n = self.possibility.len();
        let get = |v: &[f64], j: usize, miss: f64| clamp_degree(v.get(j).copied().unwrap_or(miss));
        let max_support = (0..n).map(|j| get(&ev.support, j, 0.0)).fold(0.0, f64::max);
        let mut h = 0.0f64;
        for (v, l) in self.g.iter_mut().zip(&self.label) {
            let e = match l {
                Some(j) => get(&ev.possibility, *j, 1.0),
                None => 1.0 - max_support,
            };
            *v *= e.max(self.bias);
            h = h.max(*v);
        }
        for v in &mut self.g {
            *v = if h > 0.0 {
                (*v / h).max(self.cfg.floor).min(1.0)
            } else {
                1.0
            };
        }
        self.possibility.fill(0.0);
        self.between = 0.0;
        for (&v, l) in self.g.iter().zip(&self.label) {
            match l {
                Some(j) => self.possibility[*j] = self.possibility[*j].max(v),
                None => self.between = self.between.max(v),
            }
        }
        for j in 0..n {
            let other = (0..n)
                .filter(|&k| k != j)
                .map(|k| self.possibility[k])
                .fold(self.between, f64::max);
            self.necessity[j] = 1.0 - other;
        }
    }
}

/// A random map of up to five boxes and discs on a 6 m × 4 m patch.
fn map_text() -> impl Strategy<Value = String> {
    let place = (0u32..12, 0u32..8, 1u32..8, 1u32..6, any::<bool>());
    prop::collection::vec(place, 1..6).prop_map(|places| {
        let mut text = String::new();
        for (k, (x, y, w, h, disc)) in places.into_iter().enumerate() {
            let (x, y, w, h) = (
                f64::from(x) / 2.0,
                f64::from(y) / 2.0,
                f64::from(w) / 2.0,
                f64::from(h) / 2.0,
            );
            if disc {
                text.push_str(&format!(
                    "place N{k} room at ({x}, {y}) extent radius {w};\n"
                ));
            } else {
                text.push_str(&format!(
                    "place N{k} room at ({x}, {y}) extent box ({x}, {y}, {}, {});\n",
                    x + w,
                    y + h
                ));
            }
        }
        text
    })
}

fn degree() -> impl Strategy<Value = f64> {
    prop_oneof![8 => 0.0..=1.0f64, 1 => Just(0.0), 1 => Just(f64::NAN)]
}

type FrameCase = (Vec<f64>, Vec<f64>, (f64, f64, f64), Option<f64>);

fn frame() -> impl Strategy<Value = FrameCase> {
    let step =
        prop_oneof![6 => -0.8..0.8f64, 2 => Just(0.0), 1 => Just(f64::NAN), 1 => -8.0..8.0f64];
    let heading = prop_oneof![6 => (-360.0..360.0f64).prop_map(Some), 2 => Just(None)];
    (
        prop::collection::vec(degree(), 0..7),
        prop::collection::vec(degree(), 0..7),
        (step.clone(), step, -60.0..60.0f64),
        heading,
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn grid_tracker_matches_reference(
        text in map_text(),
        flank in 0.0..0.6f64,
        flank_per_metre in 0.0..0.5f64,
        floor in prop_oneof![Just(0.0), 0.0..0.05f64],
        bias in 0.0..0.3f64,
        frames in prop::collection::vec(frame(), 1..30),
    ) {
        let m = map(&text);
        let n = m.places().len();
        let cfg = TrackerConfig {
            bias,
            grid: Some(GridTrackConfig { cell_size: 0.5, margin: 0.5, flank, flank_per_metre, floor, evidence_length_m: 0.0, evidence_max_weight: 8.0, evidence_scans: 10.0, relative_floor: 1.0, start_radius: 1.0 }),
            ..TrackerConfig::default()
        };
        let mut fast = GridTracker::new(&m, PARAMS, &cfg);
        let mut slow = Reference::new(&fast, n, &cfg);
        for (k, (support, possibility, (dx, dy, dtheta), heading)) in frames.into_iter().enumerate() {
            let ev = evidence(&support, &possibility);
            let odo = Odometry {
                forward: dx,
                left: dy,
                turn: dtheta.to_radians(),
            };
            fast.step(&ev, odo, heading);
            slow.step(&ev, odo, heading);
            for (i, (&a, &b)) in fast.belief().iter().zip(&slow.g).enumerate() {
                prop_assert!((f64::from(a) - b).abs() < 1e-4, "frame {k} cell {i}: {a} vs {b}");
            }
            let d = fast.distribution();
            for j in 0..n {
                prop_assert!((d.possibility[j] - slow.possibility[j]).abs() < 1e-4, "frame {k}: π");
                prop_assert!((d.necessity[j] - slow.necessity[j]).abs() < 1e-4, "frame {k}: N");
                prop_assert!((0.0..=1.0).contains(&d.necessity[j]));
            }
            prop_assert!((fast.between_places() - slow.between).abs() < 1e-4);
        }
    }
}

proptest! {
    /// Every cell is labelled with the first place whose extent holds its centre, as a plain
    /// test of every place at every cell finds it: overlapping boxes, rotated boxes, polygons
    /// and discs, cells of 0.1–1 m.
    #[test]
    fn each_cell_is_labelled_with_the_first_place_holding_its_centre(
        shapes in proptest::collection::vec(
            (0u8..4, -5.0f64..5.0, -5.0f64..5.0, 0.05f64..4.0, 0.05f64..4.0, -90.0f64..90.0),
            1..7,
        ),
        cell in 0.1f64..1.0,
    ) {
        let mut text = String::new();
        for (k, &(kind, x, y, w, h, turn)) in shapes.iter().enumerate() {
            let extent = match kind {
                0 => format!("box ({}, {}, {}, {})", x, y, x + w, y + h),
                1 => format!("box ({}, {}, {}, {}) rotated {turn}", x, y, x + w, y + h),
                2 => format!("polygon (({x}, {y}), ({}, {y}), ({}, {}), ({x}, {y}))", x + w, x, y + h),
                _ => format!("radius {w}"),
            };
            text += &format!("place P{k} room at ({x}, {y}) extent {extent};\n");
        }
        let m = map(&text);
        let cfg = TrackerConfig {
            grid: Some(GridTrackConfig { cell_size: cell, ..GridTrackConfig::default() }),
            ..TrackerConfig::default()
        };
        let t = GridTracker::new(&m, PARAMS, &cfg);
        let (nx, ny, side, origin) = t.geometry();
        for r in 0..ny {
            let cy = origin.1 + (r as f64 + 0.5) * side;
            for c in 0..nx {
                let cx = origin.0 + (c as f64 + 0.5) * side;
                let first = m.places().iter().position(|p| p.contains(cx, cy));
                prop_assert_eq!(t.cell_place(c, r), first, "cell ({}, {})", c, r);
            }
        }
    }
}
