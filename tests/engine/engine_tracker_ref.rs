//! The tracker against a straightforward reference of the formulas in its module docs: `R_ij`
//! through `Similarity::degree` per pair, the blur, intersection, conflict union and anchor
//! revision as plain loops over `i` and `j`. The tracker evaluates the same formulas in a
//! restructured order (gates as arrays, branch-free rows, terms hoisted out of the pair loops);
//! max and min select exactly, so on random maps, configurations, evidence and odometry every
//! decision and every degree must be bit-for-bit the reference's, frame after frame.
//!
//! With headings, the reference's displacement gate is the distance between the two extents
//! written out per kind (disc–disc, disc–box, box–box), where the tracker treats every extent as
//! a rounded box: the two must agree on every pair.
//!
//! The reference reads every pair from an all-pairs table (`Map::path_length` per pair); the
//! tracker keeps only the pairs within its horizon, from bounded searches, sorted by length,
//! and visits a window of them: a random horizon (none, 0, or cutting the small maps' paths)
//! checks that what it leaves out is exactly what has `R_ij = 0`.

use lplace::core::Odometry;
use lplace::engine::tracker::{Tracker, TrackerConfig, TrackerState};
use lplace::logic::{
    clamp_degree, decide, Decision, DecisionParams, Disoriented, Normalisation, PlaceDistribution,
    Similarity, TNorm,
};
use lplace::map::{Extent, Map};
use lplace::syntax::parse_map;
use proptest::prelude::*;

/// The reference tracker: the module docs' formulas, one pair at a time.
struct Reference {
    cfg: TrackerConfig,
    params: DecisionParams,
    /// `L'_ij` (infinite where there is no path).
    length: Vec<Vec<f64>>,
    shape: Vec<Vec<Similarity>>,
    anchor: Vec<f64>,
    since: Vec<f64>,
    /// Displacement since each anchor, `None` where unknown.
    disp: Vec<Option<[f64; 2]>>,
    /// Heading of the last frame, radians.
    heading: Option<f64>,
    extents: Vec<((f64, f64), Extent)>,
    dist: PlaceDistribution,
    /// `pred_j` of the last step, every anchor's terms in it.
    pred: Vec<f64>,
    /// The place decided in the last step, if any (for `hold`).
    last: Option<usize>,
}

/// Distance from point `p` to the box `[x0, x1] × [y0, y1]` (0 inside).
fn point_box(p: (f64, f64), x0: f64, y0: f64, x1: f64, y1: f64) -> f64 {
    let dx = (x0 - p.0).max(p.0 - x1).max(0.0);
    let dy = (y0 - p.1).max(p.1 - y1).max(0.0);
    dx.hypot(dy)
}

/// Distance between extent `a` (at `pa`) moved by `d` and extent `b` (at `pb`); 0 if they meet.
fn gap(pa: (f64, f64), a: Extent, d: [f64; 2], pb: (f64, f64), b: Extent) -> f64 {
    let sorted =
        |x0: f64, y0: f64, x1: f64, y1: f64| (x0.min(x1), y0.min(y1), x0.max(x1), y0.max(y1));
    match (a, b) {
        (Extent::Radius(ra), Extent::Radius(rb)) => {
            let c = (pa.0 + d[0], pa.1 + d[1]);
            (point_box(c, pb.0, pb.1, pb.0, pb.1) - ra.max(0.0) - rb.max(0.0)).max(0.0)
        }
        (Extent::Radius(ra), Extent::Box { x0, y0, x1, y1 }) => {
            let c = (pa.0 + d[0], pa.1 + d[1]);
            let (x0, y0, x1, y1) = sorted(x0, y0, x1, y1);
            (point_box(c, x0, y0, x1, y1) - ra.max(0.0)).max(0.0)
        }
        (Extent::Box { x0, y0, x1, y1 }, Extent::Radius(rb)) => {
            let (x0, y0, x1, y1) = sorted(x0, y0, x1, y1);
            let (x0, x1, y0, y1) = (x0 + d[0], x1 + d[0], y0 + d[1], y1 + d[1]);
            (point_box(pb, x0, y0, x1, y1) - rb.max(0.0)).max(0.0)
        }
        (
            Extent::Box { x0, y0, x1, y1 },
            Extent::Box {
                x0: u0,
                y0: v0,
                x1: u1,
                y1: v1,
            },
        ) => {
            let (x0, y0, x1, y1) = sorted(x0, y0, x1, y1);
            let (u0, v0, u1, v1) = sorted(u0, v0, u1, v1);
            let (x0, x1, y0, y1) = (x0 + d[0], x1 + d[0], y0 + d[1], y1 + d[1]);
            let gx = (u0 - x1).max(x0 - u1).max(0.0);
            let gy = (v0 - y1).max(y0 - v1).max(0.0);
            gx.hypot(gy)
        }
    }
}

fn radius(e: Extent) -> f64 {
    match e {
        Extent::Radius(r) => r.max(0.0),
        Extent::Box { x0, y0, x1, y1 } => 0.25 * ((x1 - x0).abs() + (y1 - y0).abs()),
    }
}

impl Reference {
    fn new(map: &Map, params: DecisionParams, cfg: TrackerConfig) -> Reference {
        let places = map.places();
        let n = places.len();
        let length: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        if i == j {
                            0.0
                        } else {
                            let l = map.path_length(i, j)
                                - radius(places[i].extent)
                                - radius(places[j].extent);
                            l.max(0.0)
                        }
                    })
                    .collect()
            })
            .collect();
        let shape = length
            .iter()
            .map(|row| {
                row.iter()
                    .map(|&l| {
                        let l = if l.is_finite() { l } else { 0.0 };
                        Similarity::new(
                            2.0 * (cfg.tolerance + cfg.tolerance_rel * l),
                            cfg.slope + cfg.slope_rel * l,
                            1.0,
                            0.0,
                            None,
                        )
                    })
                    .collect()
            })
            .collect();
        Reference {
            cfg,
            params,
            length,
            shape,
            anchor: vec![1.0; n],
            since: vec![0.0; n],
            disp: vec![Some([0.0; 2]); n],
            heading: None,
            extents: places
                .iter()
                .map(|p| ((p.pose.0, p.pose.1), p.extent))
                .collect(),
            dist: PlaceDistribution::new(n),
            pred: vec![1.0; n],
            last: None,
        }
    }

    fn reach(&self, i: usize, j: usize) -> f64 {
        // Either gate looks only at places within the horizon along the graph (issue 16);
        // places with no path at all are beyond every horizon.
        let l = self.length[i][j];
        if !(l.is_finite() && l <= self.cfg.horizon_m) {
            return 0.0;
        }
        if let Some(d) = self.disp[i] {
            let ((pa, a), (pb, b)) = (self.extents[i], self.extents[j]);
            let s = self.since[i];
            let shape = Similarity::new(
                2.0 * (self.cfg.tolerance_d + self.cfg.tolerance_d_rel * s),
                self.cfg.slope_d + self.cfg.slope_d_rel * s,
                1.0,
                0.0,
                None,
            );
            return shape.degree(gap(pa, a, d, pb, b), 0.0);
        }
        let l = self.length[i][j];
        if l.is_finite() {
            self.shape[i][j].degree(self.since[i], l)
        } else {
            0.0
        }
    }

    fn step(
        &mut self,
        evidence: &PlaceDistribution,
        odo: Odometry,
        heading: Option<f64>,
    ) -> Decision {
        let n = self.anchor.len();
        let get = |v: &[f64], j: usize, missing: f64| clamp_degree(*v.get(j).unwrap_or(&missing));
        let e: Vec<f64> = (0..n).map(|j| get(&evidence.possibility, j, 1.0)).collect();
        let alpha: Vec<f64> = (0..n).map(|j| get(&evidence.support, j, 0.0)).collect();
        let beta: Vec<f64> = (0..n).map(|j| get(&evidence.exclusion, j, 0.0)).collect();
        let b = clamp_degree(self.cfg.bias);
        let t = self.cfg.tnorm;
        let ds = odo.forward.hypot(odo.left);
        let ds = if ds.is_finite() { ds } else { 0.0 };
        for s in &mut self.since {
            *s = (*s + ds).min(1e9);
        }
        // The increment in the map frame, by the heading it started from.
        let dtheta = odo.turn;
        let now = heading
            .filter(|h| self.cfg.use_heading && h.is_finite())
            .map(f64::to_radians);
        let start = self
            .heading
            .or_else(|| now.filter(|_| dtheta.is_finite()).map(|h| h - dtheta));
        if ds > 0.0 {
            for d in &mut self.disp {
                *d = match (*d, start) {
                    (Some(v), Some(th)) => {
                        let (sn, cs) = th.sin_cos();
                        let wx = cs * odo.forward - sn * odo.left;
                        let wy = sn * odo.forward + cs * odo.left;
                        Some([(v[0] + wx).clamp(-1e9, 1e9), (v[1] + wy).clamp(-1e9, 1e9)])
                    }
                    _ => None,
                };
            }
        }
        self.heading = now.or_else(|| {
            self.heading
                .map(|h| h + dtheta)
                .filter(|h| h.is_finite())
                .map(|h| h.rem_euclid(std::f64::consts::TAU))
        });
        let pred: Vec<f64> = (0..n)
            .map(|j| {
                (0..n)
                    .map(|i| self.anchor[i].min(self.reach(i, j)))
                    .fold(0.0, f64::max)
            })
            .collect();
        self.pred = pred.clone();
        let mut c: Vec<f64> = (0..n).map(|j| t.apply(pred[j].max(b), e[j])).collect();
        let h = c.iter().copied().fold(0.0, f64::max);
        if h < self.cfg.conflict {
            c = (0..n).map(|j| pred[j].max(e[j])).collect();
        }
        self.dist.support = alpha.clone();
        self.dist.exclusion = beta;
        self.dist.possibility_raw = c;
        self.dist.height = h;
        self.dist.inconsistency = 1.0 - h;
        self.dist.normalise(self.cfg.normalisation);
        let max_support = alpha.iter().copied().fold(0.0, f64::max);
        let revised: Vec<f64> = (0..n)
            .map(|i| {
                let agree = (0..n)
                    .map(|j| self.reach(i, j).min(self.dist.possibility[j].min(e[j])))
                    .fold(0.0, f64::max);
                let compat = (1.0 - max_support).max(agree);
                t.apply(self.anchor[i], compat.max(b))
            })
            .collect();
        self.anchor = revised;
        for (j, &a) in alpha.iter().enumerate() {
            if a >= self.cfg.anchor_support {
                self.anchor[j] = self.dist.possibility[j];
                self.since[j] = 0.0;
                self.disp[j] = Some([0.0; 2]);
            }
        }
        let top = self.anchor.iter().copied().fold(0.0, f64::max);
        if top > 0.0 {
            self.anchor.iter_mut().for_each(|m| *m /= top);
        } else {
            self.anchor.fill(1.0);
            self.since.fill(0.0);
            self.disp.fill(Some([0.0; 2]));
        }
        let mut d = decide(&self.dist, self.params);
        // Hysteresis: the last place stays while N ≥ hold (less the decision's tie tolerance),
        // unless the frame is inconsistent or names a place of its own.
        if let (Some(p), Decision::Disoriented(why)) = (self.last, d) {
            let n = self.dist.necessity[p];
            let inconsistent = matches!(why, Disoriented::Inconsistent { .. });
            if self.cfg.hold < 1.0 && !inconsistent && n >= self.cfg.hold - 1e-9 {
                d = Decision::Place {
                    place: p,
                    necessity: n,
                };
            }
        }
        let d = match d {
            Decision::Place { place, .. } if max_support < self.cfg.min_support => {
                Decision::Disoriented(Disoriented::NothingAboveThreshold {
                    best: place,
                    support: alpha[place],
                })
            }
            d => d,
        };
        self.last = d.place();
        d
    }
}

/// A random map text: places on a line-ish layout with radius or box extents, random paths
/// (some with explicit lengths; some places unreachable).
fn map_text() -> impl Strategy<Value = String> {
    let place = (
        0u32..40,
        0u32..40,
        prop::option::of(0u32..30),
        any::<bool>(),
    );
    (
        prop::collection::vec(place, 1..9),
        prop::collection::vec((0usize..9, 0usize..9, prop::option::of(1u32..200)), 0..16),
    )
        .prop_map(|(places, paths)| {
            let n = places.len();
            let mut text = String::new();
            for (k, (x, y, r, boxed)) in places.iter().enumerate() {
                let (x, y) = (f64::from(*x) / 2.0, f64::from(*y) / 2.0);
                text.push_str(&format!("place N{k} junction at ({x}, {y})"));
                match (r, boxed) {
                    (Some(r), false) => {
                        text.push_str(&format!(" extent radius {}", f64::from(*r) / 10.0))
                    }
                    (Some(r), true) => {
                        let h = f64::from(*r) / 10.0;
                        text.push_str(&format!(
                            " extent box ({}, {}, {}, {})",
                            x - h,
                            y - h / 2.0,
                            x + h,
                            y + h
                        ));
                    }
                    (None, _) => {}
                }
                text.push_str(";\n");
            }
            let mut seen = std::collections::BTreeSet::new();
            for (a, b, w) in paths {
                let (a, b) = (a % n, b % n);
                if a == b || !seen.insert((a.min(b), a.max(b))) {
                    continue;
                }
                match w {
                    Some(w) => text.push_str(&format!(
                        "path N{a} -- N{b} length {};\n",
                        f64::from(w) / 10.0
                    )),
                    None => text.push_str(&format!("path N{a} -- N{b};\n")),
                }
            }
            text
        })
}

fn config() -> impl Strategy<Value = TrackerConfig> {
    let unit = || prop_oneof![Just(0.0), Just(1.0), 0.0..=1.0f64];
    let len = || prop_oneof![Just(0.0), 0.0..3.0f64];
    let tnorm = prop_oneof![
        Just(TNorm::Min),
        Just(TNorm::Product),
        Just(TNorm::Lukasiewicz)
    ];
    let norm = prop_oneof![Just(Normalisation::Min), Just(Normalisation::Product)];
    (
        (unit(), tnorm, len(), len(), len(), len()),
        // hold: off (1) half the time.
        (
            unit(),
            unit(),
            norm,
            unit(),
            prop_oneof![Just(1.0), 0.0..=1.0f64],
        ),
        (any::<bool>(), len(), len(), len(), len()),
        // The horizon: usually past every path of these small maps, sometimes cutting them.
        prop_oneof![Just(f64::INFINITY), Just(0.0), 0.0..8.0f64],
    )
        .prop_map(
            |(
                (bias, tnorm, tolerance, tolerance_rel, slope, slope_rel),
                (anchor_support, min_support, normalisation, conflict, hold),
                (use_heading, tolerance_d, tolerance_d_rel, slope_d, slope_d_rel),
                horizon_m,
            )| {
                TrackerConfig {
                    bias,
                    tnorm,
                    tolerance,
                    tolerance_rel,
                    slope,
                    slope_rel,
                    anchor_support,
                    min_support,
                    hold,
                    normalisation,
                    conflict,
                    use_heading,
                    tolerance_d,
                    tolerance_d_rel,
                    slope_d,
                    slope_d_rel,
                    evidence_length_m: 0.0,
                    horizon_m,
                    grid: None,
                }
            },
        )
}

/// A degree as evidence may carry it: usually in range, sometimes out of it or NaN.
fn degree() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => 0.0..=1.0f64,
        1 => Just(0.0),
        1 => Just(1.0),
        1 => prop_oneof![Just(f64::NAN), Just(-0.5), Just(1.5), Just(f64::INFINITY)],
    ]
}

/// One frame's motion: an odometry step (usually a fraction of a metre, sometimes large or
/// not finite), a turn and a heading (usually known, sometimes missing or not finite).
type Motion = (f64, f64, f64, Option<f64>);

/// One frame: evidence vectors (of the map's length, or sometimes too short or long) and its
/// motion.
fn frame() -> impl Strategy<Value = (Vec<f64>, Vec<f64>, Vec<f64>, Motion)> {
    let v = || prop::collection::vec(degree(), 0..10);
    let step = prop_oneof![
        8 => -1.0..1.0f64,
        1 => -30.0..30.0f64,
        1 => prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(0.0)],
    ];
    let heading = prop_oneof![
        6 => (-400.0..400.0f64).prop_map(Some),
        2 => Just(None),
        1 => Just(Some(f64::NAN)),
    ];
    let turn = prop_oneof![4 => -90.0..90.0f64, 1 => Just(f64::INFINITY)];
    (v(), v(), v(), (step.clone(), step, turn, heading))
}

/// Equal degrees: bit for bit, except that a zero may come out with the other sign (the tracker
/// skips rows of zero gates, and `max(+0, −0)` may give either), which no comparison and no
/// output can tell apart.
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || a == b || (a.is_nan() && b.is_nan())
}

fn same_all(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same(*x, *y))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn tracker_matches_reference(
        text in map_text(),
        cfg in config(),
        threshold in 0.0..=1.0f64,
        margin in 0.0..0.5f64,
        frames in prop::collection::vec(frame(), 1..60),
        full_length in prop::collection::vec(any::<bool>(), 60),
    ) {
        let map = Map::from_ast(&parse_map(&text).expect("map parses")).expect("map builds");
        let n = map.places().len();
        let params = DecisionParams { threshold, margin };
        let mut fast = Tracker::new(&map, params, cfg);
        let mut slow = Reference::new(&map, params, cfg);
        for (k, (alpha, beta, pi, (dx, dy, dtheta, heading))) in frames.into_iter().enumerate() {
            let mut ev = PlaceDistribution::new(n);
            if full_length[k] {
                // Evidence of the map's length, as the engine gives it.
                let fit = |v: Vec<f64>| (0..n).map(|j| v.get(j).copied().unwrap_or(0.5)).collect();
                ev.support = fit(alpha);
                ev.exclusion = fit(beta);
                ev.possibility = fit(pi);
            } else {
                ev.support = alpha;
                ev.exclusion = beta;
                ev.possibility = pi;
            }
            let odo = Odometry {
                forward: dx,
                left: dy,
                turn: dtheta.to_radians(),
            };
            let got = fast.step(&ev, odo, heading);
            let want = slow.step(&ev, odo, heading);
            prop_assert_eq!(got, want, "frame {}", k);
            let d = fast.distribution();
            prop_assert!(same_all(&d.possibility, &slow.dist.possibility), "frame {k}: Π {:?} vs {:?}", d.possibility, slow.dist.possibility);
            prop_assert!(same_all(&d.necessity, &slow.dist.necessity), "frame {k}: N");
            prop_assert!(same_all(&d.possibility_raw, &slow.dist.possibility_raw), "frame {k}: raw");
            prop_assert!(same(d.inconsistency, slow.dist.inconsistency), "frame {k}: Inc");
            let TrackerState { anchor, since, .. } = fast.state();
            prop_assert!(same_all(&anchor, &slow.anchor), "frame {k}: anchors {:?} vs {:?}", anchor, slow.anchor);
            prop_assert!(same_all(&since, &slow.since), "frame {k}: distances");
            // The blur leaves out the anchors below the floor; what it shows has them all.
            prop_assert!(same_all(&fast.predicted(), &slow.pred), "frame {k}: pred {:?} vs {:?}", fast.predicted(), slow.pred);
        }
    }
}

/// The bundled office map and a hand-made walk: a place seen, 2 m of odometry, then evidence for
/// a neighbour, one for a far place — the reference and the tracker agree on each frame.
#[test]
fn office_walk_matches_reference() {
    let map = Map::from_ast(&parse_map(include_str!("../../maps/office.map")).expect("parses"))
        .expect("builds");
    let n = map.places().len();
    let params = DecisionParams {
        threshold: 0.5,
        margin: 0.1,
    };
    let cfg = TrackerConfig::default();
    let mut fast = Tracker::new(&map, params, cfg);
    let mut slow = Reference::new(&map, params, cfg);
    for k in 0..200usize {
        let mut ev = PlaceDistribution::new(n);
        let at = (k / 25) % n;
        ev.support[at] = 0.9;
        ev.possibility.fill(0.2);
        ev.possibility[at] = 1.0;
        let odo = Odometry {
            forward: 0.3,
            left: 0.05,
            turn: 0.0,
        };
        // Headings on the second half: the displacement gates take over.
        let heading = (k >= 100).then_some(30.0);
        assert_eq!(
            fast.step(&ev, odo, heading),
            slow.step(&ev, odo, heading),
            "frame {k}"
        );
        assert!(same_all(
            &fast.distribution().possibility,
            &slow.dist.possibility
        ));
    }
}
