//! Issue 16 row 6: the MRCLAM reader keeps every good line around bad ones, judges a time by
//! both its neighbours, and reads a file with many bad lines in one pass.

use lplace::io::mrclam::{self, LineProblem, MrclamError};
use lplace::io::mrclam_dir;

/// `n` odometry lines at 10 Hz from t = 100 s.
fn odometry(n: usize) -> Vec<String> {
    (0..n)
        .map(|i| format!("{:.3} 0.1 0.0", 100.0 + i as f64 * 0.1))
        .collect()
}

fn lines_of(errors: &[MrclamError]) -> Vec<usize> {
    errors.iter().map(MrclamError::line).collect()
}

#[test]
fn a_time_far_ahead_is_the_outlier_not_the_lines_after_it() {
    let mut lines = odometry(50);
    lines[9] = "9100.900 0.1 0.0".into();
    let got = mrclam::read_odometry_lenient((lines.join("\n") + "\n").as_bytes()).unwrap();
    assert_eq!(lines_of(&got.skipped), [10]);
    assert!(matches!(
        got.skipped[0],
        MrclamError::Malformed {
            problem: LineProblem::TimeOutlier { .. },
            ..
        }
    ));
    assert_eq!(got.value.len(), 49);
    assert!(got.value.windows(2).all(|w| w[0].t <= w[1].t));
}

#[test]
fn a_time_far_behind_is_the_one_rejected() {
    let mut lines = odometry(20);
    lines[4] = "1.000 0.1 0.0".into();
    let got = mrclam::read_odometry_lenient((lines.join("\n") + "\n").as_bytes()).unwrap();
    assert_eq!(lines_of(&got.skipped), [5]);
    assert_eq!(got.value.len(), 19);
}

/// Every other line bad: all reported in line order, every good line kept. (The reader used to
/// re-read the whole file per bad line and gave up after 1,000.)
#[test]
fn thousands_of_bad_lines_are_each_reported_in_one_pass() {
    let mut lines = odometry(6000);
    for (i, l) in lines.iter_mut().enumerate() {
        if i % 2 == 1 {
            *l = if i % 4 == 1 {
                "x 0 0".into()
            } else {
                "1 2".into()
            };
        }
    }
    let text = lines.join("\n") + "\n";
    let t = std::time::Instant::now();
    let got = mrclam::read_odometry_lenient(text.as_bytes()).unwrap();
    let took = t.elapsed();
    assert_eq!(got.skipped.len(), 3000);
    assert_eq!(
        lines_of(&got.skipped),
        (1..=3000).map(|k| 2 * k).collect::<Vec<_>>()
    );
    assert_eq!(got.value.len(), 3000);
    // Linear: well under a second even on a loaded machine (quadratic took minutes).
    assert!(took.as_secs_f64() < 2.0, "{took:?}");
}

#[test]
fn a_byte_order_mark_and_a_non_utf8_line_are_handled_per_line() {
    let mut bytes = b"\xEF\xBB\xBF# t v w\n10.0 0.1 0.0\n".to_vec();
    bytes.extend_from_slice(b"10.5 0.\xff 0.0\n11.0 0.1 0.0\n");
    let got = mrclam::read_odometry_lenient(&bytes[..]).unwrap();
    assert_eq!(lines_of(&got.skipped), [3]);
    assert_eq!(got.value.len(), 2);
}

/// The directory loader reports the bad lines of every file with their paths.
#[test]
fn the_directory_loader_keeps_the_lines_after_a_corrupt_time() {
    let dir = crate::support::scratch("io_mrclam", "corrupt_time");
    let mut lines = odometry(30);
    lines[2] = "2100.200 0.1 0.0".into();
    crate::support::mrclam::tiny_dir(&dir, &(lines.join("\n") + "\n"));
    let d = mrclam_dir::load(&dir, &[1]).unwrap();
    assert_eq!(d.skipped.len(), 1);
    assert!(d.skipped[0].path.ends_with("Robot1_Odometry.dat"));
    assert_eq!(d.skipped[0].error.line(), 3);
    let frames = &d.robots[0].frames;
    assert!((frames.last().unwrap().t - 102.9).abs() < 1e-9);
}

/// A line of 2 MiB without a break (a corrupt block) is one bad line: reported with its number
/// and skipped, the lines around it kept, and never held whole.
#[test]
fn an_overlong_line_is_one_skipped_line() {
    let mut bytes = b"10.0 0.1 0.0\n".to_vec();
    bytes.extend(vec![b'7'; 2 << 20]);
    bytes.extend_from_slice(b"\n11.0 0.1 0.0\n");
    let got = mrclam::read_odometry_lenient(&bytes[..]).unwrap();
    assert_eq!(lines_of(&got.skipped), [2]);
    assert!(
        got.skipped[0].to_string().contains("longer than"),
        "{}",
        got.skipped[0]
    );
    assert_eq!(got.value.len(), 2);
}
