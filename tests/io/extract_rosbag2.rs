//! `lplace extract --from rosbag2` against `--from carmen` on the same data: the Intel log and a
//! ROS 2 bag written from it by an independent writer (`tests/rosbag/make_bag.py`, the
//! `rosbags` library from PyPI; `.ci/run` makes the bags). Same frame count, percepts within
//! 1e-9. Plus the bad-message bags (exit 3, topic and log time reported) and broken files
//! (no panic).
//!
//! The bags are looked for in `$LPLACE_ROSBAG` (a directory holding `intel/` and `errors/`),
//! else `target/rosbag`; the log in `$LPLACE_DATA` or `../shared/data`. Each test skips with a
//! message when what it needs is absent.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use lplace::io::record::FrameRecord;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn bag_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("LPLACE_ROSBAG")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(ROOT).join("target/rosbag"));
    dir.is_dir().then_some(dir)
}

fn intel_log() -> Option<PathBuf> {
    let data = std::env::var_os("LPLACE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(ROOT).join("../shared/data"));
    let log = data.join("carmen-corrected-logs/intel-corrected.log");
    log.is_file().then_some(log)
}

/// Runs `lplace extract ARGS`, returning the exit code, the frames and stderr.
fn extract(args: &[&str]) -> (i32, Vec<FrameRecord>, String) {
    let out = Command::cargo_bin("lplace")
        .unwrap()
        .current_dir(ROOT)
        .arg("extract")
        .args(args)
        .output()
        .unwrap();
    let stdout = String::from_utf8(out.stdout).unwrap();
    let frames = stdout
        .lines()
        .map(|l| FrameRecord::parse(l).expect("extract writes valid records"))
        .collect();
    let code = out.status.code().unwrap_or(-1);
    (
        code,
        frames,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    a == b || (a - b).abs() <= tol || (a.is_nan() && b.is_nan())
}

#[test]
fn bag_gives_the_frames_of_the_carmen_log() {
    let (Some(bags), Some(log)) = (bag_dir(), intel_log()) else {
        eprintln!(
            "SKIP: no rosbag test bags (run tests/rosbag/make_bag.py, see .ci/run) or no Intel log"
        );
        return;
    };
    let bag = bags.join("intel");
    let common = ["--map", "maps/intel.map", "--config", "config/intel.ron"];
    let log = log.to_str().unwrap();
    let (code_c, carmen, _) = extract(&[&["--from", "carmen", log][..], &common].concat());
    let (code_r, ros, err) =
        extract(&[&["--from", "rosbag2", bag.to_str().unwrap()][..], &common].concat());
    assert_eq!((code_c, code_r), (0, 0), "{err}");
    assert_eq!(carmen.len(), 910);
    assert_eq!(ros.len(), carmen.len(), "same number of frames");
    let mut worst = 0.0f64;
    for (k, (c, r)) in carmen.iter().zip(&ros).enumerate() {
        assert!(close(c.t.unwrap(), r.t.unwrap(), 1e-6), "frame {k}: t");
        match (c.odometry, r.odometry) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                for (x, y) in [(a.dx, b.dx), (a.dy, b.dy), (a.dtheta, b.dtheta)] {
                    assert!(close(x, y, 1e-9), "frame {k}: odometry {a:?} vs {b:?}");
                }
            }
            other => panic!("frame {k}: odometry {other:?}"),
        }
        assert_eq!(
            c.heading.is_some(),
            r.heading.is_some(),
            "frame {k}: heading"
        );
        if let (Some(a), Some(b)) = (c.heading, r.heading) {
            assert!(close(a, b, 1e-9), "frame {k}: heading {a} vs {b}");
        }
        let (tc, tr) = (c.truth.clone().unwrap(), r.truth.clone().unwrap());
        assert_eq!(tc.place, tr.place, "frame {k}: truth place");
        for (x, y) in tc.pose.unwrap().iter().zip(tr.pose.unwrap()) {
            assert!(close(*x, y, 1e-9), "frame {k}: truth pose");
        }
        assert_eq!(
            c.percepts.len(),
            r.percepts.len(),
            "frame {k}: percept count"
        );
        for (p, q) in c.percepts.iter().zip(&r.percepts) {
            assert_eq!((&p.name, &p.args), (&q.name, &q.args), "frame {k}");
            assert!(
                close(p.degree, q.degree, 1e-9),
                "frame {k}: {} degree {} vs {}",
                p.name,
                p.degree,
                q.degree
            );
            assert_eq!(
                p.value.is_some(),
                q.value.is_some(),
                "frame {k}: {} value",
                p.name
            );
            if let (Some(a), Some(b)) = (p.value, q.value) {
                assert!(close(a, b, 1e-9), "frame {k}: {} value {a} vs {b}", p.name);
                worst = worst.max((a - b).abs());
            }
            worst = worst.max((p.degree - q.degree).abs());
        }
    }
    eprintln!("910 frames; largest percept difference {worst:e}");
}

#[test]
fn bad_messages_are_reported_counted_and_skipped() {
    let Some(bags) = bag_dir() else {
        eprintln!("SKIP: no rosbag test bags (run tests/rosbag/make_bag.py, see .ci/run)");
        return;
    };
    for (name, says) in [
        (
            "truncated_scan",
            "does not decode as sensor_msgs/msg/LaserScan",
        ),
        (
            "wrong_type",
            "message type geometry_msgs/msg/PoseStamped, expected sensor_msgs/msg/LaserScan",
        ),
    ] {
        let bag = bags.join("errors").join(name);
        let (code, frames, err) = extract(&["--from", "rosbag2", bag.to_str().unwrap()]);
        assert_eq!(code, 3, "{name}: {err}");
        assert_eq!(frames.len(), 4, "{name}: the four good scans of five");
        // Topic and log time (1.4 s, the third scan) of the bad message.
        assert!(err.contains("/scan at 1400000000 ns: "), "{name}: {err}");
        assert!(err.contains(says), "{name}: {err}");
        assert!(err.contains("1 bad message(s) skipped"), "{name}: {err}");
    }
}

#[test]
fn broken_files_are_errors_not_panics() {
    let Some(bags) = bag_dir() else {
        eprintln!("SKIP: no rosbag test bags (run tests/rosbag/make_bag.py, see .ci/run)");
        return;
    };
    let good = bags.join("errors/wrong_type/wrong_type.mcap");
    let bytes = std::fs::read(&good).unwrap();
    let dir = std::env::temp_dir().join(format!("lplace-rosbag2-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Cut anywhere: inside the header, a record, a chunk, the summary, the footer.
    for cut in [
        0,
        5,
        8,
        100,
        bytes.len() / 3,
        bytes.len() / 2,
        bytes.len() - 30,
        bytes.len() - 1,
    ] {
        let path = dir.join(format!("cut{cut}.mcap"));
        std::fs::write(&path, &bytes[..cut]).unwrap();
        let (code, _, err) = extract(&["--from", "rosbag2", path.to_str().unwrap()]);
        assert!(matches!(code, 2 | 3), "cut at {cut}: exit {code}: {err}");
        assert!(!err.contains("panicked"), "cut at {cut}: {err}");
    }
    // Not a bag at all; a directory of the sqlite3 storage.
    let (code, _, err) = extract(&["--from", "rosbag2", "maps/office.map"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("not a readable MCAP file"), "{err}");
    let sqlite = dir.join("sqlite_bag");
    std::fs::create_dir_all(&sqlite).unwrap();
    std::fs::write(
        sqlite.join("metadata.yaml"),
        "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n",
    )
    .unwrap();
    let (code, _, err) = extract(&["--from", "rosbag2", sqlite.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("\"sqlite3\" is not read"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
