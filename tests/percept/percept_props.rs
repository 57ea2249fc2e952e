//! Property tests of the percept layer: the total-least-squares fit is exact
//! on collinear points, invariant under rigid motions, handles vertical
//! lines, and turns every degenerate input into a typed error; no extractor
//! panics or emits a degree outside [0, 1] whatever the sensor data.

use std::f64::consts::{FRAC_PI_2, PI};

use lplace::core::Pose2;
use lplace::percept::beacon::{beacon_from_image, BeaconConfig};
use lplace::percept::image::BinaryImage;
use lplace::percept::laser_line::{from_scan, LaserLineConfig, LaserScratch};
use lplace::percept::scan::ScanView;
use lplace::percept::sonar_wall::{SensorMount, SonarWall, SonarWallConfig};
use lplace::percept::{fit_line, ExtractConfig, LineFitError, PerceptRecord, ScanExtractor, Side};
use nalgebra::{Point2, Rotation2, Vector2};
use proptest::prelude::*;

/// Difference of two line angles modulo π, in [0, π/2].
fn line_angle_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(PI);
    d.min(PI - d)
}

fn valid(r: &PerceptRecord) -> bool {
    (0.0..=1.0).contains(&r.degree)
        && (0.0..=1.0).contains(&r.delta)
        && (r.degree + r.delta - 1.0).abs() < 1e-12
        && r.value.map_or(true, f64::is_finite)
}

/// Any f64, weighted towards the awkward ones.
fn wild_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -1e3..1e3f64,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(0.0),
        1 => prop::num::f64::ANY,
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn collinear_points_fit_exactly(
        ax in -1e3..1e3f64, ay in -1e3..1e3f64, phi in 0.0..PI,
        ts in prop::collection::vec(-50.0..50.0f64, 2..60),
    ) {
        let span = ts.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - ts.iter().cloned().fold(f64::INFINITY, f64::min);
        prop_assume!(span > 0.1);
        let d = Vector2::new(phi.cos(), phi.sin());
        let pts: Vec<_> = ts.iter().map(|&t| Point2::new(ax, ay) + d * t).collect();
        let f = fit_line(&pts).unwrap();
        // Coordinates up to ~1e3 carry ~1e-13 absolute rounding error.
        prop_assert!(f.rms_dispersion < 1e-9, "dispersion {}", f.rms_dispersion);
        prop_assert!(line_angle_gap(f.angle, phi) < 1e-9 / span.min(1.0) + 1e-9);
        // The anchor lies on the fitted line.
        prop_assert!(f.signed_distance(&Point2::new(ax, ay)).abs() < 1e-8);
        prop_assert!((f.direction.norm() - 1.0).abs() < 1e-12);
        prop_assert!(f.angle > -FRAC_PI_2 && f.angle <= FRAC_PI_2);
        prop_assert_eq!(f.count, pts.len());
    }

    #[test]
    fn fit_is_invariant_under_rigid_motion(
        phi in 0.0..PI,
        samples in prop::collection::vec((-10.0..10.0f64, -0.1..0.1f64), 3..60),
        alpha in -PI..PI, tx in -1e3..1e3f64, ty in -1e3..1e3f64,
    ) {
        let ts: Vec<f64> = samples.iter().map(|s| s.0).collect();
        let span = ts.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - ts.iter().cloned().fold(f64::INFINITY, f64::min);
        prop_assume!(span > 5.0);
        let d = Vector2::new(phi.cos(), phi.sin());
        let n = Vector2::new(-d.y, d.x);
        let pts: Vec<_> = samples.iter().map(|&(t, e)| Point2::origin() + d * t + n * e).collect();
        let rot = Rotation2::new(alpha);
        let moved: Vec<_> = pts.iter().map(|p| rot * p + Vector2::new(tx, ty)).collect();
        let f0 = fit_line(&pts).unwrap();
        let f1 = fit_line(&moved).unwrap();
        // Dispersion ≤ 0.1 here; translation by 1e3 costs ~1e-13 per coordinate.
        prop_assert!((f0.rms_dispersion - f1.rms_dispersion).abs() < 1e-9,
            "{} vs {}", f0.rms_dispersion, f1.rms_dispersion);
        prop_assert!((f0.rms_spread - f1.rms_spread).abs() < 1e-9);
        prop_assert!(line_angle_gap(f1.angle, f0.angle + alpha) < 1e-9);
        // The moved centroid is the moved centroid.
        let c = rot * f0.centroid + Vector2::new(tx, ty);
        prop_assert!((c - f1.centroid).norm() < 1e-9);
    }

    #[test]
    fn dispersion_of_any_cloud_is_rotation_invariant(
        pts in prop::collection::vec((-100.0..100.0f64, -100.0..100.0f64), 2..40),
        alpha in -PI..PI,
    ) {
        let pts: Vec<_> = pts.into_iter().map(|(x, y)| Point2::new(x, y)).collect();
        let rot = Rotation2::new(alpha);
        let moved: Vec<_> = pts.iter().map(|p| rot * p).collect();
        match (fit_line(&pts), fit_line(&moved)) {
            (Ok(a), Ok(b)) => {
                // Smaller eigenvalue of the scatter is rotation invariant even
                // when the direction is ill-conditioned.
                prop_assert!((a.rms_dispersion - b.rms_dispersion).abs() < 1e-7 * (1.0 + a.rms_spread));
            }
            (Err(_), _) | (_, Err(_)) => {}
        }
    }

    #[test]
    fn vertical_lines_have_no_slope(x in -1e4..1e4f64, ys in prop::collection::vec(-100.0..100.0f64, 2..30)) {
        let distinct = ys.iter().any(|&y| y != ys[0]);
        let pts: Vec<_> = ys.iter().map(|&y| Point2::new(x, y)).collect();
        match fit_line(&pts) {
            Ok(f) => {
                prop_assert!(distinct);
                prop_assert!(f.slope.is_none());
                prop_assert_eq!(f.angle, FRAC_PI_2);
                prop_assert!((f.offset + x).abs() < 1e-9 * (1.0 + x.abs()), "offset {} x {}", f.offset, x);
                prop_assert!(f.rms_dispersion < 1e-12);
            }
            Err(e) => {
                prop_assert!(!distinct);
                prop_assert_eq!(e, LineFitError::Coincident { count: pts.len() });
            }
        }
    }

    #[test]
    fn arbitrary_points_never_panic(pts in prop::collection::vec((wild_f64(), wild_f64()), 0..20)) {
        let pts: Vec<_> = pts.into_iter().map(|(x, y)| Point2::new(x, y)).collect();
        let any_bad = pts.iter().any(|p| !(p.x.is_finite() && p.y.is_finite()));
        match fit_line(&pts) {
            Ok(f) => {
                prop_assert!(!any_bad);
                prop_assert!(f.rms_dispersion.is_finite() && f.rms_dispersion >= 0.0);
                prop_assert!(f.offset.is_finite());
                prop_assert!((f.direction.norm() - 1.0).abs() < 1e-12);
            }
            Err(LineFitError::TooFewPoints { count }) => prop_assert!(count < 2),
            Err(LineFitError::NonFinite { index, .. }) => {
                prop_assert!(!(pts[index].x.is_finite() && pts[index].y.is_finite()));
            }
            Err(LineFitError::Coincident { .. }) | Err(LineFitError::Overflow { .. }) => {
                prop_assert!(!any_bad || pts.len() >= 2);
            }
        }
    }

    #[test]
    fn scan_extractors_never_panic(
        ranges in prop::collection::vec(wild_f64(), 0..200),
        first in wild_f64(), step in wild_f64(),
        poses in prop::collection::vec((wild_f64(), wild_f64(), wild_f64()), 1..6),
    ) {
        let mut ex = ScanExtractor::new(ExtractConfig::default()).unwrap();
        for (x, y, theta) in poses {
            let recs = ex.step(&ScanView {
                pose: Pose2 { x, y, theta },
                ranges: &ranges,
                first_bearing: first,
                bearing_step: step,
                laser_offset_x: 0.0,
            });
            for r in &recs {
                prop_assert!(valid(r), "{:?}", r);
            }
        }
        let out = from_scan(&ranges, first, step, 0.1, &LaserLineConfig::default(), &mut LaserScratch::default());
        for r in &out.records() {
            prop_assert!(valid(r));
        }
    }

    #[test]
    fn sonar_wall_never_panics(readings in prop::collection::vec((wild_f64(), wild_f64(), wild_f64(), wild_f64()), 0..40)) {
        let mut w = SonarWall::new(Side::Left, SonarWallConfig::default()).unwrap();
        let mount = SensorMount { x: 0.0, y: 0.1, angle: FRAC_PI_2 };
        for &(x, y, theta, r) in &readings {
            w.push(Pose2 { x, y, theta }, &mount, r);
            let rec = w.evaluate(&Pose2 { x, y, theta }).record();
            prop_assert!(valid(&rec), "{:?}", rec);
        }
    }

    #[test]
    fn pbm_and_beacon_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..300), w in 1usize..40, h in 1usize..40) {
        let _ = BinaryImage::from_pbm(&bytes);
        let mut framed = format!("P4 {w} {h}\n").into_bytes();
        framed.extend_from_slice(&bytes);
        if let Ok(img) = BinaryImage::from_pbm(&framed) {
            let cfg = BeaconConfig { angle_steps: 16, ..Default::default() };
            if let Ok(out) = beacon_from_image(&img, &cfg) {
                for r in &out.records() {
                    prop_assert!(valid(r));
                }
            }
        }
    }
}
