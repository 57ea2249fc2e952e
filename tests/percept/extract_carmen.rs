//! `io::carmen_stream` and `lplace extract` on hand-written CARMEN lines: one frame per scan,
//! odometry increments from the ODOM chain, truth from a tiny map worked out by hand, malformed
//! lines reported with their line numbers (exit 3).

use lplace::io::carmen_stream::{convert, CarmenFramer};
use lplace::io::record::FrameRecord;
use lplace::map::Map;
use lplace::percept::ExtractConfig;
use lplace::syntax::parse_map;

/// A 180-beam scan line: all ranges `r`, corrected pose (x, y, θ rad), timestamp `t`.
fn flaser(r: f64, x: f64, y: f64, th: f64, t: f64) -> String {
    let ranges = vec![format!("{r}"); 180].join(" ");
    format!("FLASER 180 {ranges} {x} {y} {th} {x} {y} {th} {t} pippo {t}")
}

/// Two places: A a box around the origin, B a disc of radius 1 at (5, 0). Worked by hand:
/// pose (0.5, 0.2) is in A only; (4.5, 0.5) is 0.71 m from B's centre, in B; (2.5, 0) in neither.
const TINY_MAP: &str = "map tiny;
place A corridor at (0, 0) extent box (-1, -1, 1, 1) { param W = 2; }
place B junction at (5, 0) extent radius 1 { param W = 3; }
path A -- B length 5;";

fn tiny_map() -> Map {
    let ast = parse_map(TINY_MAP).expect("the tiny map parses");
    Map::from_ast(&ast).expect("the tiny map is valid")
}

fn log() -> String {
    [
        "# a comment".to_owned(),
        "PARAM robot_frontlaser_offset 0.0 nohost 0".to_owned(),
        "ODOM 0 0 0 0 0 0 0.1 pippo 0.1".to_owned(),
        flaser(2.0, 0.5, 0.2, 0.0, 1.0),
        // The chain restarts at the scan pose, then the robot drives 1 m forward and turns 90° left.
        "ODOM 0.5 0.2 0 0 0 0 0 pippo 0".to_owned(),
        "NEFF 12".to_owned(),
        "ODOM 1.5 0.2 1.5707963267948966 0 0 0 1.5 pippo 1.5".to_owned(),
        flaser(2.0, 4.5, 0.5, std::f64::consts::FRAC_PI_2, 2.0),
        flaser(2.0, 2.5, 0.0, std::f64::consts::PI, 3.0),
    ]
    .join("\n")
        + "\n"
}

fn run(text: &str, map: Option<&Map>) -> (Vec<FrameRecord>, Vec<usize>) {
    let mut framer = CarmenFramer::new(ExtractConfig::default(), map.map(Map::places))
        .expect("default config is valid");
    let (mut frames, mut bad) = (Vec::new(), Vec::new());
    convert(
        text.as_bytes(),
        &mut framer,
        |f| {
            frames.push(f);
            Ok::<(), ()>(())
        },
        |e| bad.push(e.line()),
    )
    .expect("collecting frames cannot fail");
    (frames, bad)
}

#[test]
fn one_frame_per_scan_with_odometry_and_hand_worked_truth() {
    let map = tiny_map();
    let (frames, bad) = run(&log(), Some(&map));
    assert!(bad.is_empty());
    assert_eq!(frames.len(), 3);
    // First frame: no previous scan, so no odometry.
    assert_eq!(frames[0].odometry, None);
    assert_eq!(frames[0].t, Some(1.0));
    // Second: (last ODOM before it) ⊖ (first scan's odom pose) = 1 m forward, 90° left.
    let o = frames[1].odometry.expect("second frame has odometry");
    assert!((o.dx - 1.0).abs() < 1e-9 && o.dy.abs() < 1e-9 && (o.dtheta - 90.0).abs() < 1e-9);
    // Third: no ODOM in between, so the two scans' odom poses: from (4.5, 0.5, 90°) to
    // (2.5, 0, 180°) is 0.5 m back... in the robot frame: forward = Δy = −0.5, left = −Δx = 2.
    let o = frames[2].odometry.expect("third frame has odometry");
    assert!(
        (o.dx + 0.5).abs() < 1e-9 && (o.dy - 2.0).abs() < 1e-9 && (o.dtheta - 90.0).abs() < 1e-9
    );
    let truth: Vec<Option<&str>> = frames
        .iter()
        .map(|f| f.truth.as_ref().and_then(|t| t.place.as_deref()))
        .collect();
    assert_eq!(truth, vec![Some("A"), Some("B"), None]);
    let pose = frames[1].truth.as_ref().and_then(|t| t.pose).expect("pose");
    assert!((pose[0] - 4.5).abs() < 1e-12 && (pose[2] - 90.0).abs() < 1e-9);
}

#[test]
fn a_segment_with_only_the_restating_odom_uses_the_scan_poses() {
    // Between the two scans the log has only the chain's restart (the first scan's pose again,
    // time 0): no raw odometry, while the robot turned 90° and moved 1 m. The increment is then
    // the two scans' odom poses', as with no ODOM at all — not zero.
    let text = [
        flaser(2.0, 0.5, 0.2, 0.0, 1.0),
        "ODOM 0.5 0.2 0 0 0 0 0 pippo 0".to_owned(),
        flaser(2.0, 1.5, 0.2, std::f64::consts::FRAC_PI_2, 2.0),
        // A real reading between the next two: the restart line before it changes nothing.
        "ODOM 1.5 0.2 1.5707963267948966 0 0 0 0 pippo 0".to_owned(),
        "ODOM 1.5 1.2 1.5707963267948966 0 0 0 2.5 pippo 2.5".to_owned(),
        flaser(2.0, 1.5, 1.3, std::f64::consts::FRAC_PI_2, 3.0),
    ]
    .join("\n")
        + "\n";
    let (frames, bad) = run(&text, None);
    assert!(bad.is_empty());
    let o = frames[1].odometry.expect("second frame has odometry");
    assert!((o.dx - 1.0).abs() < 1e-9 && o.dy.abs() < 1e-9 && (o.dtheta - 90.0).abs() < 1e-9);
    // From the ODOM chain (1 m forward), not the scan poses (1.1 m).
    let o = frames[2].odometry.expect("third frame has odometry");
    assert!((o.dx - 1.0).abs() < 1e-9 && o.dy.abs() < 1e-9 && o.dtheta.abs() < 1e-9);
}

#[test]
fn frames_carry_every_percept_and_valid_degrees() {
    let (frames, _) = run(&log(), None);
    let names: Vec<(String, Vec<String>)> = frames[0]
        .percepts
        .iter()
        .map(|p| (p.name.clone(), p.args.clone()))
        .collect();
    let want = [
        ("laser_wall", vec!["Front"]),
        ("laser_corner", vec!["Front"]),
        ("sonar_wall", vec!["Left"]),
        ("sonar_wall", vec!["Right"]),
        ("corridor_width", vec![]),
        ("side_openings", vec![]),
    ];
    assert_eq!(names.len(), want.len());
    for ((n, a), (wn, wa)) in names.iter().zip(want) {
        assert_eq!(n, wn);
        assert_eq!(a, &wa.iter().map(|s| s.to_string()).collect::<Vec<_>>());
    }
    assert!(frames[0].truth.is_none(), "no map, no truth");
    for f in &frames {
        for p in &f.percepts {
            assert!((0.0..=1.0).contains(&p.degree), "{p:?}");
        }
        // All ranges 2 m: 2 m to each side, a 4 m "corridor" with no openings.
        let w = f
            .percepts
            .iter()
            .find(|p| p.name == "corridor_width")
            .and_then(|p| p.value);
        assert_eq!(w, Some(4.0));
    }
}

#[test]
fn malformed_lines_are_reported_with_line_numbers_and_skipped() {
    let mut text = log();
    text.push_str("ODOM 1 2\n"); // line 10: too short
    text.push_str("FLASER 180 1 2 3\n"); // line 11: fewer beams than declared
    text.push_str("ODOM 1 x 0 0 0 0 5 pippo 5\n"); // line 12: not a number
    text.push_str(&flaser(2.0, 0.0, 0.0, 0.0, 6.0)); // line 13: fine
    text.push('\n');
    let (frames, bad) = run(&text, None);
    assert_eq!(bad, vec![10, 11, 12]);
    assert_eq!(
        frames.len(),
        4,
        "the good scan after the bad lines is still converted"
    );
}

/// The CLI: `lplace extract --from carmen LOG --map M` (skips until the subcommand is wired).
#[test]
fn cli_writes_json_lines_and_exits_3_on_malformed_lines() {
    use assert_cmd::Command;
    let help = Command::cargo_bin("lplace")
        .expect("binary")
        .arg("--help")
        .output()
        .expect("runs");
    if !String::from_utf8_lossy(&help.stdout).contains("extract") {
        eprintln!("SKIP: `lplace extract` is not wired into the command line yet");
        return;
    }
    let dir = std::env::temp_dir().join(format!("lplace-extract-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let map = dir.join("tiny.map");
    std::fs::write(&map, TINY_MAP).expect("write map");
    let good = dir.join("good.log");
    std::fs::write(&good, log()).expect("write log");
    let out = Command::cargo_bin("lplace")
        .expect("binary")
        .args(["extract", "--from", "carmen"])
        .arg(&good)
        .arg("--map")
        .arg(&map)
        .output()
        .expect("runs");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<FrameRecord> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| FrameRecord::parse(l).expect("each line is a frame record"))
        .collect();
    assert_eq!(lines.len(), 3);
    assert_eq!(
        lines[1].truth.as_ref().and_then(|t| t.place.as_deref()),
        Some("B")
    );

    let bad = dir.join("bad.log");
    std::fs::write(&bad, log() + "ODOM 1 2\n").expect("write log");
    let out = Command::cargo_bin("lplace")
        .expect("binary")
        .arg("extract")
        .arg(&bad)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(3));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("line 10"), "{err}");
    assert_eq!(String::from_utf8_lossy(&out.stdout).lines().count(), 3);
    let _ = std::fs::remove_dir_all(&dir);
}
