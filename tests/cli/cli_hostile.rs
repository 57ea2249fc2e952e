//! Issue 16, hostile files given to the command line: a line of 70,000 characters, a flood of
//! 9,000 duplicate definitions, bytes that are not UTF-8, a byte-order mark. Each must end in a
//! diagnostic with a line number and exit 2 (never a panic, exit 101), in bounded time and output.

use super::support::{lplace, scratch};
use std::time::{Duration, Instant};

/// Runs `lplace check` on `name` holding `bytes`; returns (exit code, stdout, stderr, wall time).
fn check(name: &str, bytes: &[u8]) -> (i32, String, String, Duration) {
    let dir = scratch("hostile", name);
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("scratch is writable");
    let t = Instant::now();
    let out = lplace()
        .arg("check")
        .arg(&path)
        .output()
        .expect("lplace runs");
    let took = t.elapsed();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        took,
    )
}

#[test]
fn a_70000_character_line_is_an_excerpted_diagnostic_not_a_panic() {
    for name in ["long.lpl", "long.map"] {
        let text = format!("{}garbage;\n", " ".repeat(70_000));
        let (code, _, err, _) = check(name, text.as_bytes());
        assert_eq!(code, 2, "{name}: {err}");
        assert!(err.contains(":1:70001: error: syntax error"), "{err}");
        // The excerpt: the offending token, not the 70,000 blanks before it.
        assert!(err.contains("…"), "{err}");
        let mut excerpt = err.lines().filter(|l| l.starts_with("    "));
        assert!(excerpt.clone().count() >= 2, "{err}");
        assert!(excerpt.all(|l| l.chars().count() < 200), "{err}");
    }
}

#[test]
fn a_flood_of_diagnostics_is_capped_and_fast() {
    let text = format!("map m;{}\n", "room R;".repeat(9000));
    let (code, _, err, took) = check("flood.map", text.as_bytes());
    assert_eq!(code, 2);
    let shown = err.matches("is defined more than once").count();
    // Ten shown in full, then one line counting the other 8,989 (9,000 rooms, the first is fine).
    assert_eq!(shown, 11, "{err}");
    assert!(err.contains("… and 8989 more error of this kind"), "{err}");
    assert!(err.len() < 20_000, "{} bytes on stderr", err.len());
    // Was 14.9 s; now ~0.15 s here. The bound leaves room for a loaded machine.
    assert!(took < Duration::from_secs(5), "{took:?}");
}

#[test]
fn a_file_of_syntax_errors_stops_after_the_cap() {
    let text = "garbage;".repeat(20_000);
    let (code, _, err, took) = check("garbage.lpl", text.as_bytes());
    assert_eq!(code, 2);
    assert!(
        err.contains("100 syntax errors: stopped parsing here"),
        "{err}"
    );
    assert!(took < Duration::from_secs(5), "{took:?}");
}

#[test]
fn bytes_that_are_not_utf8_are_a_diagnostic_with_line_and_column() {
    for name in ["bad.map", "bad.lpl"] {
        let (code, _, err, _) = check(name, b"// fine\n\n   \xff x;\n");
        assert_eq!(code, 2, "{name}: {err}");
        assert!(err.contains("invalid UTF-8: byte 0xff"), "{err}");
        assert!(err.contains(&format!("{name}:3:4")), "{err}");
    }
}

#[test]
fn a_byte_order_mark_is_accepted() {
    let (code, out, err, _) = check("bom.map", b"\xEF\xBB\xBFmap m;\nroom R;\n");
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("1 rooms"), "{out}");
    let rules = std::fs::read("rules/office.lpl").expect("bundled rules");
    let (code, _, err, _) = check("bom.lpl", &[b"\xEF\xBB\xBF".as_slice(), &rules].concat());
    assert_eq!(code, 0, "{err}");
}

/// Copies MRCLAM's shared files and robot 1's into `dir`, with `edit` applied to robot 1's
/// odometry text.
fn mrclam_copy(src: &std::path::Path, dir: &std::path::Path, edit: impl Fn(&str) -> String) {
    for f in [
        "Barcodes.dat",
        "Landmark_Groundtruth.dat",
        "Robot1_Measurement.dat",
        "Robot1_Groundtruth.dat",
    ] {
        std::fs::copy(src.join(f), dir.join(f)).expect("scratch is writable");
    }
    let odo = std::fs::read_to_string(src.join("Robot1_Odometry.dat")).expect("data readable");
    std::fs::write(dir.join("Robot1_Odometry.dat"), edit(&odo)).expect("scratch is writable");
}

/// Row 6: one corrupt timestamp (`1248…` made `2248…` on line 100 of robot 1's real odometry)
/// is the one line rejected; the good lines after it are kept.
#[test]
fn one_corrupt_mrclam_timestamp_is_the_one_line_rejected() {
    let Some(src) = super::support::mrclam_dir() else {
        return;
    };
    let dir = scratch("hostile", "mrclam_time");
    mrclam_copy(&src, &dir, |odo| {
        let mut lines: Vec<String> = odo.lines().map(str::to_string).collect();
        assert!(lines[99].starts_with("1248"), "line 100 is a data line");
        lines[99].replace_range(0..1, "2");
        lines.join("\n") + "\n"
    });
    let out = lplace()
        .args(["grid", "--from-dir"])
        .arg(&dir)
        .args(["--robot", "1"])
        .output()
        .expect("lplace runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    let reported: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("Robot1_Odometry.dat:"))
        .collect();
    assert_eq!(reported.len(), 1, "{err}");
    assert!(reported[0].contains("Robot1_Odometry.dat:100:"), "{err}");
}
