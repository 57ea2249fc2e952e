//! The MRCLAM reader on hand-written lines, the TUM round trip, and the grid
//! on real MRCLAM robot 1 data (skipped when the data set is absent).

use crate::support::mrclam_dir;
use lplace::grid::place::survey_landmarks;
use lplace::grid::GridConfig;
use lplace::io::mrclam::*;
use lplace::io::tum::{read_tum, write_tum, TumError, TumPose};
use lplace::localize::grid::run;
use lplace::localize::RunOptions;

fn codes() -> Barcodes {
    read_barcodes("# c\n# c\n1 5\n6 63\n7 81\n".as_bytes()).unwrap()
}

#[test]
fn malformed_lines_name_their_line() {
    let e = read_odometry("# header\n10.0 0.1 0.0\n10.1 0.1\n".as_bytes()).unwrap_err();
    assert!(
        matches!(
            e,
            MrclamError::Malformed {
                file: FileKind::Odometry,
                line: 3,
                problem: LineProblem::FieldCount {
                    expected: 3,
                    found: 2
                }
            }
        ),
        "{e}"
    );
    let e = read_groundtruth("1.0 2.0 x 0.1\n".as_bytes()).unwrap_err();
    assert!(
        matches!(
            e,
            MrclamError::Malformed {
                line: 1,
                problem: LineProblem::NotANumber { column: 3, .. },
                ..
            }
        ),
        "{e}"
    );
    let e = read_measurements("\n# c\n5.0 63 nan 0.1\n".as_bytes(), &codes()).unwrap_err();
    assert!(
        matches!(
            e,
            MrclamError::Malformed {
                line: 3,
                problem: LineProblem::NonFinite { column: 3 },
                ..
            }
        ),
        "{e}"
    );
    let e = read_measurements("5.0 63 -1.0 0.1\n".as_bytes(), &codes()).unwrap_err();
    assert!(
        matches!(
            e,
            MrclamError::Malformed {
                line: 1,
                problem: LineProblem::NegativeRange,
                ..
            }
        ),
        "{e}"
    );
    let e = read_odometry("2.0 0 0\n1.0 0 0\n".as_bytes()).unwrap_err();
    assert!(
        matches!(
            e,
            MrclamError::Malformed {
                line: 2,
                problem: LineProblem::TimeGoesBack { .. },
                ..
            }
        ),
        "{e}"
    );
    let e = read_barcodes("1 5.5\n".as_bytes()).unwrap_err();
    assert!(
        matches!(
            e,
            MrclamError::Malformed {
                line: 1,
                problem: LineProblem::NotANumber { column: 2, .. },
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("line 1"));
}

#[test]
fn misread_barcodes_are_dropped_and_counted() {
    let m = read_measurements(
        "1.0 63 2.0 0.1\n1.0 34 1.0 0.0\n2.0 52 1.0 0.0\n2.0 34 1.0 0.0\n3.0 5 1.5 0.2\n"
            .as_bytes(),
        &codes(),
    )
    .unwrap();
    assert_eq!(m.rows.len(), 2);
    assert_eq!((m.rows[0].subject, m.rows[1].subject), (6, 1));
    assert_eq!(m.misread, 3);
    assert_eq!(m.misread_barcodes.get(&34), Some(&2));
}

#[test]
fn merge_integrates_odometry_and_interpolates_truth() {
    // 1 m/s straight for 1 s, then a quarter turn in place over 1 s at π/2 rad/s.
    let odo = read_odometry("0.0 1.0 0.0\n1.0 0.0 1.5707963\n2.0 0.0 0.0\n".as_bytes()).unwrap();
    let meas = read_measurements("1.0 63 2.0 0.1\n1.0 81 3.0 -0.1\n".as_bytes(), &codes()).unwrap();
    let truth = read_groundtruth("0.0 0 0 3.0\n2.0 2 4 -3.0\n".as_bytes()).unwrap();
    let opts = MergeOptions {
        max_frame_gap: 10.0,
        max_truth_gap: 5.0,
    };
    let f = merge(&odo, &meas.rows, &truth, &opts);
    let times: Vec<f64> = f.iter().map(|f| f.t).collect();
    assert_eq!(times, vec![0.0, 1.0, 2.0]);
    assert_eq!(f[1].observations.len(), 2);
    assert!((f[1].odometry.forward - 1.0).abs() < 1e-9 && f[1].odometry.left.abs() < 1e-9);
    assert!((f[2].odometry.turn - std::f64::consts::FRAC_PI_2).abs() < 1e-6);
    let t1 = f[1].truth.unwrap();
    assert!((t1.x - 1.0).abs() < 1e-9 && (t1.y - 2.0).abs() < 1e-9);
    // Heading interpolated the short way across ±π: 3.0 → −3.0 passes π.
    assert!(
        (t1.theta.abs() - std::f64::consts::PI).abs() < 0.01,
        "{t1:?}"
    );
    // A gap of 0.3 s gives intermediate odometry-only frames.
    let f = merge(
        &odo,
        &meas.rows,
        &truth,
        &MergeOptions {
            max_frame_gap: 0.3,
            max_truth_gap: 5.0,
        },
    );
    assert!(f
        .windows(2)
        .all(|w| w[1].t - w[0].t <= 0.3 + 1e-9 && w[1].t > w[0].t));
}

#[test]
fn a_corrupt_far_future_time_does_not_explode_the_stream() {
    let odo = read_odometry("0.0 0.1 0.0\n1e12 0.1 0.0\n".as_bytes()).unwrap();
    let f = merge(&odo, &[], &[], &MergeOptions::default());
    assert!(f.len() < 10, "{} frames", f.len());
    assert!(f.windows(2).all(|w| w[1].t > w[0].t));
}

#[test]
fn tum_round_trip_and_errors() {
    let p = [
        TumPose {
            t: 1248446182.116,
            x: 1.5,
            y: -2.0,
            yaw: -3.0,
        },
        TumPose {
            t: 1248446183.0,
            x: 0.0,
            y: 0.0,
            yaw: 3.1,
        },
    ];
    let mut buf = Vec::new();
    write_tum(&mut buf, &p).unwrap();
    let text = String::from_utf8(buf.clone()).unwrap();
    assert!(text.starts_with("1248446182.116000 1.500000 -2.000000 0 0 0 "));
    let back = read_tum(buf.as_slice()).unwrap();
    for (a, b) in p.iter().zip(&back) {
        assert!(
            (a.t - b.t).abs() < 1e-6 && (a.x - b.x).abs() < 1e-6 && (a.yaw - b.yaw).abs() < 1e-6
        );
    }
    let e = read_tum("# c\n1 2 3 4 5 6 7\n".as_bytes()).unwrap_err();
    assert!(matches!(
        e,
        TumError::Malformed {
            line: 2,
            found: 7,
            ..
        }
    ));
}

#[test]
fn mrclam_robot1_ate_is_locked_in() {
    let Some(dir) = mrclam_dir() else {
        return;
    };
    let data = lplace::io::mrclam_dir::load(&dir, &[1]).unwrap();
    assert!(data.skipped.is_empty(), "{:?}", data.skipped);
    assert_eq!(data.survey().unwrap().len(), 15);
    let table = survey_landmarks(data.survey().unwrap()).unwrap();
    let frames = data.robots.into_iter().next().unwrap().frames;
    let cfg = GridConfig::from_ron(include_str!("../../config/grid-mrclam.ron")).unwrap();
    let rep = run(&table, &cfg, frames, &RunOptions::default()).unwrap();
    let ate = rep.ate.expect("a fix and truth");
    eprintln!("robot 1: {ate:?}, first fix {:?}", rep.first_fix);
    // Measured 0.221 m RMSE / 0.171 m median / 0.78 m max, fix after 3.5 s (0.213 / 0.163 /
    // 0.55 m with config/grid-mrclam-hard.ron, the file before issue 20's robustness work;
    // 0.280 / 0.229 / 0.757 m before the retuning). Bounds: that retuning's figure, 0.213 m,
    // plus twice 0.021 m, the change that rounding the landmark survey to the millimetre caused
    // (docs/grid.md) — so the test still fails on the figures before the retuning. The max keeps its old bound, 1 m: nine of the config's ten
    // tuning neighbours stayed within 0.80 m, one reached 1.36 m, so the max is not stable
    // enough to lock tighter.
    assert!(ate.rmse < 0.26, "{ate:?}");
    assert!(ate.median < 0.21, "{ate:?}");
    assert!(ate.max < 1.0, "{ate:?}");
    assert!(rep.first_fix.unwrap().after < 10.0);
    assert_eq!(rep.rejected, 0);
}

/// config/grid-mrclam-classes.ron is config/grid-mrclam-accurate.ron with the cells moved along
/// their heading classes and nothing else, as its header and docs/compare.md compare them.
#[test]
fn the_classes_file_is_the_accurate_file_with_cell_motion() {
    use lplace::grid::CellMotion;
    let accurate =
        GridConfig::from_ron(include_str!("../../config/grid-mrclam-accurate.ron")).unwrap();
    let classes =
        GridConfig::from_ron(include_str!("../../config/grid-mrclam-classes.ron")).unwrap();
    assert_eq!(accurate.cell_motion, CellMotion::Plane);
    assert!(matches!(
        classes.cell_motion,
        CellMotion::HeadingClasses { bins: 16, .. }
    ));
    assert_eq!(
        GridConfig {
            cell_motion: CellMotion::Plane,
            ..classes
        },
        accurate
    );
}
