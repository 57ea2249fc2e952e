//! Extractors on synthetic scenes of known geometry. Every expected number is
//! derived in the comments from the geometry, not taken from the code.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use lplace::core::Pose2;
use lplace::percept::beacon::{beacon_from_image, helix_row, BeaconConfig, BeaconError};
use lplace::percept::image::BinaryImage;
use lplace::percept::laser_line::{
    eq3_from_points, from_image, from_scan, LaserLineConfig, LaserScratch, PivotRule,
};
use lplace::percept::scan::ScanView;
use lplace::percept::sonar_wall::{SensorMount, SonarWall, SonarWallConfig};
use lplace::percept::{ExtractConfig, PerceptKind, ScanExtractor, Side};
use nalgebra::Point2;

/// Deterministic uniform noise in [−1, 1) (xorshift64*), so tests never flake.
struct Noise(u64);
impl Noise {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        (x as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// Casts 181 beams (1° apart, −90°…+90°) from the origin at segments.
fn cast(segments: &[(Point2<f64>, Point2<f64>)]) -> Vec<f64> {
    (0..181)
        .map(|i| {
            let b = -FRAC_PI_2 + (i as f64).to_radians();
            let d = nalgebra::Vector2::new(b.cos(), b.sin());
            let mut best = 81.91; // CARMEN's "no return"
            for (a, c) in segments {
                let e = c - a;
                // Solve t·d = a + s·e.
                let det = d.x * (-e.y) - d.y * (-e.x);
                if det.abs() < 1e-12 {
                    continue;
                }
                let t = (a.x * (-e.y) - a.y * (-e.x)) / det;
                let s = (d.x * a.y - d.y * a.x) / det;
                if t > 0.0 && (0.0..=1.0).contains(&s) && t < best {
                    best = t;
                }
            }
            best
        })
        .collect()
}

const STEP: f64 = PI / 180.0;

#[test]
fn perfect_front_wall_gives_zero_delta_f() {
    // Wall x = 2 across the whole front: every point has depth b = 2, slope 0,
    // dispersion 0 → δ_f = 0; its distance from the robot is 2 m. Both halves
    // of a straight wall have the same slope → |M2 − M3| = 0 → δ_c = 1.
    let ranges = cast(&[(Point2::new(2.0, -10.0), Point2::new(2.0, 10.0))]);
    let out = from_scan(
        &ranges,
        -FRAC_PI_2,
        STEP,
        0.0,
        &LaserLineConfig::default(),
        &mut LaserScratch::default(),
    );
    assert!(out.delta_front < 1e-9, "{}", out.delta_front);
    assert!((out.wall_distance.unwrap() - 2.0).abs() < 1e-9);
    assert!((out.delta_corner - 1.0).abs() < 1e-9);
    let [wall, corner] = out.records();
    assert_eq!(wall.kind, PerceptKind::LaserWall);
    assert!(wall.degree > 1.0 - 1e-9);
    assert!(corner.degree < 1e-9);
}

#[test]
fn oblique_wall_delta_f_equals_its_slope() {
    // Wall through (2, 0) turned by 10°: its depth changes by tan 10° ≈ 0.1763
    // per metre of lateral travel → |M1| = tan 10°, S1 = 0 → δ_f = tan 10°.
    let a = 10f64.to_radians();
    let dir = nalgebra::Vector2::new(a.sin(), a.cos());
    let p0 = Point2::new(2.0, 0.0);
    let ranges = cast(&[(p0 - dir * 10.0, p0 + dir * 10.0)]);
    let out = from_scan(
        &ranges,
        -FRAC_PI_2,
        STEP,
        0.0,
        &LaserLineConfig::default(),
        &mut LaserScratch::default(),
    );
    assert!(
        (out.delta_front - a.tan()).abs() < 1e-9,
        "{}",
        out.delta_front
    );
}

#[test]
fn perfect_v_corner_gives_zero_delta_c() {
    // Convex corner (vertex nearest the robot) at (2, 0), walls going away
    // at ±45°: depth b = 2 + |a| → M2 = −1, M3 = +1, |M2 − M3| = 2 ≥ 1.1 and
    // S2 = S3 = 0 → δ_c = 0; corner 2 m away.
    let v = Point2::new(2.0, 0.0);
    let ranges = cast(&[(v, Point2::new(8.0, 6.0)), (v, Point2::new(8.0, -6.0))]);
    let out = from_scan(
        &ranges,
        -FRAC_PI_2,
        STEP,
        0.0,
        &LaserLineConfig::default(),
        &mut LaserScratch::default(),
    );
    assert!(out.delta_corner < 1e-9, "{}", out.delta_corner);
    assert!((out.corner_distance.unwrap() - 2.0).abs() < 1e-9);
    // The single line through a V is poor: δ_f saturates.
    assert_eq!(out.delta_front, 1.0);
}

#[test]
fn concave_corner_needs_the_farthest_pivot() {
    // Robot facing into a room corner at (3, 0), walls coming back at ±45°:
    // b = 3 − |a|. With the farthest pivot, M2 = +1, M3 = −1 → δ_c = 0.
    // With the nearest pivot the pivot is at the sector edge and one side
    // holds a single beam → no L3 → δ_c = 1.
    let v = Point2::new(3.0, 0.0);
    let ranges = cast(&[(v, Point2::new(-1.0, 4.0)), (v, Point2::new(-1.0, -4.0))]);
    let far = LaserLineConfig {
        pivot: PivotRule::Farthest,
        ..Default::default()
    };
    let out = from_scan(
        &ranges,
        -FRAC_PI_2,
        STEP,
        0.0,
        &far,
        &mut LaserScratch::default(),
    );
    assert!(out.delta_corner < 1e-9, "{}", out.delta_corner);
    assert!((out.corner_distance.unwrap() - 3.0).abs() < 1e-9);
    let near = from_scan(
        &ranges,
        -FRAC_PI_2,
        STEP,
        0.0,
        &LaserLineConfig::default(),
        &mut LaserScratch::default(),
    );
    assert_eq!(near.delta_corner, 1.0);
}

#[test]
fn uniform_noise_raises_dispersion_as_expected() {
    // Wall b = 2 with depth noise uniform on [−h, h]: variance h²/3, so
    // S1 ≈ h/√3. With h = 3 cm, S1 ≈ 1.732 cm → δ_f ≈ |M1| + 0.1732, M1 ≈ 0.
    // 4000 points: the sample variance of U[−h,h] is within ~2% of h²/3.
    let h = 0.03;
    let mut noise = Noise(0x9E37_79B9_7F4A_7C15);
    let mut pts: Vec<_> = (0..4000)
        .map(|i| Point2::new(-2.0 + i as f64 * 0.001, 2.0 + h * noise.next()))
        .collect();
    let pivot = pts[2000];
    let out = eq3_from_points(&mut pts, pivot, 0.01, 5);
    let s1 = out.l1.unwrap().rms_dispersion;
    assert!(
        (s1 - h / 3f64.sqrt()).abs() < 0.02 * h / 3f64.sqrt(),
        "S1 = {s1}"
    );
    assert!(
        (out.delta_front - 0.1732).abs() < 0.01,
        "{}",
        out.delta_front
    );
    // Doubling h doubles S1 and therefore the dispersion term of δ_f.
    let mut pts2: Vec<_> = (0..4000)
        .map(|i| Point2::new(-2.0 + i as f64 * 0.001, 2.0 + 2.0 * h * noise.next()))
        .collect();
    let out2 = eq3_from_points(&mut pts2, pivot, 0.01, 5);
    let ratio = out2.l1.unwrap().rms_dispersion / s1;
    assert!((ratio - 2.0).abs() < 0.06, "ratio {ratio}");
}

#[test]
fn laser_line_from_images() {
    // The paper's V, vertex lowest in the image (largest row):
    // v = 25 − |u − 20| for u in 0..=40. Slopes dv/du = +1 left, −1 right,
    // pixels exactly on both lines → δ_c = 0, pivot (20, 25).
    let mut img = BinaryImage::new(41, 30).unwrap();
    for u in 0..41usize {
        img.set(u, 25 - u.abs_diff(20), true);
    }
    let out = from_image(&img, 5, &mut LaserScratch::default());
    assert!(out.delta_corner < 1e-12, "{}", out.delta_corner);
    assert_eq!(out.pivot.unwrap(), Point2::new(20.0, 25.0));
    // L1 through the symmetric V is horizontal (Σ(u−ū)(v−v̄) = 0 and the u
    // spread 140 px² exceeds the v spread), so S1 is the std of v:
    // k = u − 20, mean|k| = 420/41, mean k² = 5740/41 = 140,
    // S1² = 140 − (420/41)² ≈ 35.06 → S1 ≈ 5.921 px → δ_f = S1/10 ≈ 0.5921.
    let s1 = (140.0f64 - (420.0f64 / 41.0).powi(2)).sqrt();
    assert!(
        (out.delta_front - s1 / 10.0).abs() < 1e-12,
        "{}",
        out.delta_front
    );
    assert!((s1 / 10.0 - 0.5921).abs() < 1e-4);
}

#[test]
fn sonar_wall_straight_and_noisy_walls() {
    // Robot drives along +x at y = 0 with a wall at y = 1.5 to its left,
    // one reading every 0.25 m. Perfect wall: Δ = 0 → δ_w = 0, distance 1.5.
    let cfg = SonarWallConfig::default();
    let mount = SensorMount {
        x: 0.0,
        y: 0.0,
        angle: FRAC_PI_2,
    };
    let mut w = SonarWall::new(Side::Left, cfg).unwrap();
    for k in 0..12 {
        w.push(
            Pose2 {
                x: 0.25 * k as f64,
                y: 0.0,
                theta: 0.0,
            },
            &mount,
            1.5,
        );
    }
    let out = w.evaluate(&Pose2 {
        x: 2.75,
        y: 0.0,
        theta: 0.0,
    });
    assert!(out.delta < 1e-9);
    assert!((out.distance.unwrap() - 1.5).abs() < 1e-9);
    let rec = out.record();
    assert_eq!(rec.arg, lplace::percept::PerceptArg::Side(Side::Left));

    // Same drive heading along +y (θ = 90°): the left sensor now looks along
    // −x, the wall is x = −1.5; the world-frame placement must give the same fit.
    let mut w = SonarWall::new(Side::Left, cfg).unwrap();
    for k in 0..8 {
        w.push(
            Pose2 {
                x: 0.0,
                y: 0.3 * k as f64,
                theta: FRAC_PI_2,
            },
            &mount,
            1.5,
        );
    }
    let out = w.evaluate(&Pose2 {
        x: 0.0,
        y: 2.1,
        theta: FRAC_PI_2,
    });
    let fit = out.fit.unwrap();
    assert!(
        fit.slope.is_none(),
        "a wall along y is vertical in the world frame"
    );
    assert!(
        (fit.offset - 1.5).abs() < 1e-9,
        "normal (−1,0)·(−1.5, y) = 1.5"
    );
    assert!(out.delta < 1e-9);

    // Range noise uniform on [−h, h], h = 0.06 m, wall parallel to the
    // motion: orthogonal noise std h/√3 ≈ 0.0346 m, so with Δmax = 0.1 m
    // δ_w ≈ 0.35 on average over many 8-point windows (a single window of 8
    // is noisy and the fit absorbs ~2 degrees of freedom: E[Δ²] = (8−2)/8·h²/3
    // → √0.75·0.346 ≈ 0.30).
    let mut noise = Noise(42);
    let mut w = SonarWall::new(Side::Left, cfg).unwrap();
    let (mut sum, mut n) = (0.0, 0);
    for k in 0..4000 {
        w.push(
            Pose2 {
                x: 0.25 * k as f64,
                y: 0.0,
                theta: 0.0,
            },
            &mount,
            1.5 + 0.06 * noise.next(),
        );
        if k >= 8 {
            let d = w
                .evaluate(&Pose2 {
                    x: 0.25 * k as f64,
                    y: 0.0,
                    theta: 0.0,
                })
                .delta;
            sum += d * d;
            n += 1;
        }
    }
    let rms_delta = (sum / n as f64).sqrt();
    assert!((rms_delta - 0.30).abs() < 0.02, "rms δ_w = {rms_delta}");
}

#[test]
fn scan_extractor_corridor() {
    // Corridor along +x, walls at y = ±1, robot on the axis moving 0.3 m per
    // scan: after 8 scans both side walls are perfect lines 1 m away → δ_w = 0.
    let mut ex = ScanExtractor::new(ExtractConfig::default()).unwrap();
    let mut last = None;
    for k in 0..10 {
        let x = 0.3 * k as f64;
        let ranges = cast(&[
            (Point2::new(-50.0, 1.0), Point2::new(50.0, 1.0)),
            (Point2::new(-50.0, -1.0), Point2::new(50.0, -1.0)),
        ]);
        last = Some(ex.step(&ScanView {
            pose: Pose2 {
                x,
                y: 0.0,
                theta: 0.0,
            },
            ranges: &ranges,
            first_bearing: -FRAC_PI_2,
            bearing_step: STEP,
            laser_offset_x: 0.0,
        }));
    }
    let recs = last.unwrap();
    assert_eq!(recs[2].arg, lplace::percept::PerceptArg::Side(Side::Left));
    assert!(
        recs[2].degree > 1.0 - 1e-9 && recs[3].degree > 1.0 - 1e-9,
        "{recs:?}"
    );
    assert!((recs[2].value.unwrap() - 1.0).abs() < 1e-9);
    // Ahead, the corridor walls run away from the robot: no front wall.
    assert!(recs[0].degree < 0.05, "{:?}", recs[0]);
}

/// Draws the synthetic beacon: cuts as full rows, helix one pixel per column.
fn draw_beacon(theta: f64, top_rows: &[usize], bottom_row: usize) -> BinaryImage {
    let mut img = BinaryImage::new(100, 70).unwrap();
    let (u0, u1) = (30usize, 70usize);
    for u in u0..=u1 {
        for &v in top_rows {
            img.set(u, v, true);
        }
        img.set(u, bottom_row, true);
    }
    let vt = top_rows.iter().sum::<usize>() as f64 / top_rows.len() as f64;
    let sep = bottom_row as f64 - vt;
    for u in u0..=u1 {
        let v = helix_row(theta, u as f64, 50.0, 20.0, vt, sep, 1.0).round() as usize;
        if v > *top_rows.last().unwrap() && v < bottom_row {
            img.set(u, v, true);
        }
    }
    img
}

#[test]
fn beacon_perfect_image() {
    // Cuts at rows 10 and 50 over columns 30..=70: axis 50, radius 20,
    // separation 40 px; distance = 500 px · 0.20 m / 40 px = 2.5 m. Cuts are
    // exact rows → δ_s1 = δ_s2 = 0 → β_d = 0. The helix was drawn with
    // θ = 1.0 rad, rounded to whole rows (≤ 0.5 px error): β_θ ≤ 0.5²/3² ≈ 0.028.
    let img = draw_beacon(1.0, &[10], 50);
    let out = beacon_from_image(&img, &BeaconConfig::default()).unwrap();
    assert_eq!(
        (out.axis_u, out.radius_px, out.separation_px),
        (50.0, 20.0, 40.0)
    );
    assert!((out.distance - 2.5).abs() < 1e-12);
    assert_eq!(out.beta_d, 0.0);
    assert!(out.beta_theta <= 0.25 / 9.0 + 1e-12, "{}", out.beta_theta);
    // One row of helix height is 2π/40 rad of θ; rounding allows ±0.5 row.
    let err = (out.angle.unwrap() - 1.0 + PI).rem_euclid(TAU) - PI;
    assert!(
        err.abs() < 0.5 * TAU / 40.0 + TAU / 360.0,
        "θ = {:?}",
        out.angle
    );
    let [a, d] = out.records();
    assert_eq!(
        (a.kind, d.kind),
        (PerceptKind::BeaconAngle, PerceptKind::BeaconDistance)
    );
    assert!((d.value.unwrap() - 2.5).abs() < 1e-12 && d.degree == 1.0);
}

#[test]
fn beacon_thick_cut_raises_beta_d() {
    // Top cut two rows thick (10 and 11): its line is v = 10.5 and every
    // pixel is 0.5 px from it → S1 = 0.5 → δ_s1 = 0.5/2 = 0.25 = β_d.
    // Separation 50 − 10.5 = 39.5 px → distance 100/39.5 m.
    let img = draw_beacon(2.0, &[10, 11], 50);
    let out = beacon_from_image(&img, &BeaconConfig::default()).unwrap();
    assert!((out.delta_cuts[0] - 0.25).abs() < 1e-12);
    assert!((out.beta_d - 0.25).abs() < 1e-12);
    assert!((out.distance - 100.0 / 39.5).abs() < 1e-12);
}

#[test]
fn beacon_without_cuts_is_a_typed_error() {
    let mut img = BinaryImage::new(20, 20).unwrap();
    assert_eq!(
        beacon_from_image(&img, &BeaconConfig::default()),
        Err(BeaconError::Empty)
    );
    for u in 0..20 {
        img.set(u, 3, true);
    }
    assert_eq!(
        beacon_from_image(&img, &BeaconConfig::default()),
        Err(BeaconError::CutsNotFound { bands: 1 })
    );
}
