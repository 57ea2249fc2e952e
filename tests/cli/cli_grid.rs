//! `lplace grid` and `lplace extract --from mrclam` end to end: small hand-written streams and
//! data set directories (TUM output parses back, exit codes, malformed lines reported with
//! their file and line), then real MRCLAM robot 1 (skipped when the data set is absent).

use crate::support::landmarks::{self, frame};
use crate::support::lplace;
use lplace::io::record::FrameRecord;
use lplace::io::tum::read_tum;
use std::path::{Path, PathBuf};

/// A fresh directory for this file's tests.
fn scratch(name: &str) -> PathBuf {
    crate::support::scratch("cli_grid", name)
}

/// A directory with the tiny map (with its place) and a stream of `lines`.
fn setup(name: &str, lines: &[String]) -> (PathBuf, PathBuf, PathBuf) {
    let d = scratch(name);
    let (map, stream) = landmarks::write(&d, true, lines);
    (d, map, stream)
}

#[test]
fn grid_writes_a_tum_trajectory_that_parses_back() {
    let lines: Vec<String> = (0..5).map(|k| frame(k as f64 * 1.5)).collect();
    let (d, map, stream) = setup("ok", &lines);
    let tum = d.join("out.tum");
    let svg = d.join("svg");
    let out = lplace()
        .arg("grid")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .arg("--tum")
        .arg(&tum)
        .arg("--svg")
        .arg(&svg)
        .args(["--format", "json"])
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
    assert!(v["ate"]["rmse"].as_f64().unwrap() < 0.15, "{v}");
    assert_eq!(v["first_fix"].as_f64(), Some(0.0), "{v}");
    let poses = read_tum(
        std::fs::File::open(&tum)
            .map(std::io::BufReader::new)
            .unwrap(),
    )
    .unwrap();
    assert_eq!(poses.len(), 5);
    let last = poses[4];
    assert!(
        (last.x - 1.0).abs() < 0.15 && (last.y - 1.0).abs() < 0.15,
        "{last:?}"
    );
    assert!((last.t - 6.0).abs() < 1e-9);
    let drawn = std::fs::read_dir(&svg).unwrap().count();
    assert!(drawn >= 1, "no SVG frame drawn");
}

#[test]
fn malformed_stream_lines_are_reported_and_give_exit_3() {
    let mut lines: Vec<String> = (0..4).map(|k| frame(k as f64)).collect();
    lines.insert(1, "{not json".to_string());
    let (_d, map, stream) = setup("bad", &lines);
    let out = lplace()
        .arg("grid")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .assert()
        .code(3)
        .get_output()
        .clone();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("s.jsonl:2:"), "{err}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("ATE"));
}

/// Runs `lplace grid --json` on `lines` and returns (exit code, scores, stderr).
fn grid_json(name: &str, lines: &[String]) -> (i32, serde_json::Value, String) {
    let (_d, map, stream) = setup(name, lines);
    let out = lplace()
        .arg("grid")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args(["--format", "json"])
        .output()
        .unwrap();
    let v = serde_json::from_slice(&out.stdout).unwrap();
    let code = out.status.code().unwrap_or(-1);
    (code, v, String::from_utf8_lossy(&out.stderr).into_owned())
}

/// Lines of stderr other than the one naming the landmark map.
fn problems(err: &str) -> usize {
    err.lines()
        .filter(|l| !l.starts_with("landmarks: "))
        .count()
}

#[test]
fn grid_rejects_a_degree_above_one_with_its_line_and_exit_3() {
    let mut lines: Vec<String> = (0..4).map(|k| frame(k as f64)).collect();
    lines[2] = lines[2].replacen(r#""degree":1.0"#, r#""degree":1.5"#, 1);
    let (code, v, err) = grid_json("degree", &lines);
    assert_eq!(code, 3, "{err}");
    // The first percept of `frame` is A's range; the whole record (line 3) is skipped.
    assert!(
        err.contains("s.jsonl:3: percept `landmark_range(A)`: degree 1.5 is outside [0, 1]"),
        "{err}"
    );
    assert_eq!(problems(&err), 1, "{err}");
    assert_eq!(v["frames"], 3, "{v}");
    assert_eq!(v["rejected_lines"], 1, "{v}");
}

#[test]
fn grid_rejects_time_going_backwards_with_its_line_and_exit_3() {
    let mut lines: Vec<String> = (0..4).map(|k| frame(k as f64)).collect();
    lines.insert(3, frame(0.5));
    let (code, v, err) = grid_json("backwards", &lines);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains("s.jsonl:4: time goes backwards: t = 0.5 after t = 2"),
        "{err}"
    );
    assert_eq!(problems(&err), 1, "{err}");
    assert_eq!(v["frames"], 4, "{v}");
    assert_eq!(v["rejected_lines"], 1, "{v}");
}

#[test]
fn grid_takes_other_robots_as_unknown_subjects_and_rejects_undeclared_names() {
    // Ids 1–3 are the tiny map's landmarks, so `extract` would call robots 4 and 5 by name.
    let robot = r#"{"name":"landmark_range","args":["Robot4"],"value":2.0,"degree":1.0},{"name":"landmark_bearing","args":["Robot4"],"value":10.0,"degree":1.0},"#;
    let stranger = r#"{"name":"landmark_range","args":["Robot1"],"value":2.0,"degree":1.0},"#;
    let mut lines: Vec<String> = (0..4).map(|k| frame(k as f64)).collect();
    lines[1] = lines[1].replacen(r#""percepts":["#, &format!(r#""percepts":[{robot}"#), 1);
    let (code, v, err) = grid_json("robots", &lines);
    assert_eq!(code, 0, "{err}");
    assert_eq!(v["frames"], 4, "{v}");
    assert_eq!(v["unknown"], 1, "{v}");
    assert_eq!(v["other_robots"], 1, "{v}");
    lines[2] = lines[2].replacen(r#""percepts":["#, &format!(r#""percepts":[{stranger}"#), 1);
    let (code, v, err) = grid_json("stranger", &lines);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains("s.jsonl:3: unknown percept `landmark_range(Robot1)`"),
        "{err}"
    );
    assert_eq!(v["frames"], 3, "{v}");
}

#[test]
fn bad_arguments_and_missing_files_have_their_exit_codes() {
    let lines = vec![frame(0.0)];
    let (d, map, stream) = setup("args", &lines);
    lplace()
        .arg("grid")
        .arg("--map")
        .arg(&map)
        .arg(d.join("absent.jsonl"))
        .assert()
        .code(1);
    lplace()
        .arg("grid")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args(["--cell", "0"])
        .assert()
        .code(2);
    lplace()
        .arg("grid")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args(["--kidnap-at", "soon"])
        .assert()
        .code(2);
    lplace().arg("grid").assert().code(2);
}

/// The shared tiny MRCLAM directory (`tests/support/mrclam.rs`) in this file's scratch space.
fn mrclam_dir(name: &str, odometry: &str) -> PathBuf {
    crate::support::mrclam::tiny_dir(&scratch(name), odometry)
}

#[test]
fn extract_mrclam_reports_malformed_lines_and_misreads() {
    let d = mrclam_dir(
        "mrclam_bad",
        "# t v w\n10.0 0.0 0.0\n10.5 zero 0.0\n11.0 0.0\n11.5 0.0 0.0\n",
    );
    let out = lplace()
        .args(["extract", "--from", "mrclam"])
        .arg(&d)
        .args(["--robot", "1"])
        .assert()
        .code(3)
        .get_output()
        .clone();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("Robot1_Odometry.dat:3: column 2"), "{err}");
    assert!(err.contains("Robot1_Odometry.dat:4: "), "{err}");
    assert!(err.contains("1 misread barcode(s) dropped [34×1]"), "{err}");
    let text = String::from_utf8(out.stdout).unwrap();
    let recs: Vec<FrameRecord> = text
        .lines()
        .map(|l| FrameRecord::parse(l).unwrap())
        .collect();
    assert!(!recs.is_empty());
    let seen = recs.iter().find(|r| !r.percepts.is_empty()).unwrap();
    // Landmark 6 is L6 in the bundled map.
    assert_eq!(seen.percepts[0].name, "landmark_range");
    assert_eq!(seen.percepts[0].args, vec!["L6".to_string()]);
    assert_eq!(seen.percepts[1].value, Some(0.0));
}

#[test]
fn extract_mrclam_clean_and_argument_errors() {
    let d = mrclam_dir("mrclam_ok", "10.0 0.0 0.0\n11.5 0.0 0.0\n");
    lplace()
        .args(["extract", "--from", "mrclam"])
        .arg(&d)
        .args(["--robot", "1"])
        .assert()
        .code(0);
    lplace()
        .args(["extract", "--from", "mrclam"])
        .arg(&d)
        .assert()
        .code(2);
    lplace()
        .args(["extract", "--from", "mrclam"])
        .arg(&d)
        .args(["--robot", "2"])
        .assert()
        .code(1);
}

#[test]
fn mrclam_robot1_extract_then_grid() {
    let Some(dir) = crate::support::mrclam_dir() else {
        return;
    };
    let d = scratch("real");
    let out = lplace()
        .args(["extract", "--from", "mrclam"])
        .arg(&dir)
        .args(["--robot", "1"])
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let stream = d.join("r1.jsonl");
    std::fs::write(&stream, out).unwrap();
    let out = lplace()
        .arg("grid")
        .arg(&stream)
        .args(["--config"])
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("config/grid-mrclam.ron"))
        .arg("--tum")
        .arg(d.join("r1.tum"))
        .args(["--kidnap-at", "mid", "--format", "json"])
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
    // Measured 0.221 m, first fix 3.45 s, recovery 2.8 s (docs/grid.md); the RMSE bound is
    // tests/grid_mrclam.rs's, which the configuration before the retuning (0.280 m) fails.
    assert!(v["ate"]["rmse"].as_f64().unwrap() < 0.26, "{v}");
    assert!(v["first_fix"].as_f64().unwrap() < 5.0, "{v}");
    assert!(v["recovery"].as_f64().unwrap() < 15.0, "{v}");
}

/// Runs `lplace grid` with `args`; returns (exit code, stdout, stderr).
fn grid<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> (i32, String, String) {
    let out = lplace().arg("grid").args(args).output().unwrap();
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (
        out.status.code().unwrap_or(-1),
        text(&out.stdout),
        text(&out.stderr),
    )
}

/// Reads a TUM file back.
fn tum(path: &Path) -> Vec<lplace::io::tum::TumPose> {
    read_tum(std::io::BufReader::new(std::fs::File::open(path).unwrap())).unwrap()
}

#[test]
fn grid_says_which_landmark_map_it_uses() {
    let (_d, map, stream) = setup("which_map", &[frame(0.0), frame(1.0)]);
    let (code, _, err) = grid(&["--map".as_ref(), map.as_os_str(), stream.as_os_str()]);
    assert_eq!(code, 0, "{err}");
    let said = format!("landmarks: {} (3 landmarks)", map.display());
    assert!(err.lines().any(|l| l == said), "{err}");
    // A data set directory without its survey: the bundled map (15 landmarks, ids 6–20).
    let d = mrclam_dir("which_map_dir", "10.0 0.0 0.0\n11.5 0.0 0.0\n");
    let from_dir = [
        "--from-dir".as_ref(),
        d.as_os_str(),
        "--robot".as_ref(),
        "1".as_ref(),
    ];
    let (code, _, err) = grid(&from_dir);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.lines()
            .any(|l| l == "landmarks: maps/mrclam.map (bundled) (15 landmarks)"),
        "{err}"
    );
}

#[test]
fn grid_from_dir_reads_the_directorys_own_survey() {
    // Robot 1 of the tiny directory sees subject 6 (barcode 63) twice.
    let d = mrclam_dir("own_survey", "10.0 0.0 0.0\n11.5 0.0 0.0\n");
    let survey = d.join("Landmark_Groundtruth.dat");
    let row = |s: u32, x: f64| format!("{s} {x} 0.0 0.001 0.001\n");
    std::fs::write(&survey, row(6, 2.0) + &row(7, 5.0)).unwrap();
    let args = [
        "--from-dir".as_ref(),
        d.as_os_str(),
        "--robot".as_ref(),
        "1".as_ref(),
        "--format".as_ref(),
        "json".as_ref(),
    ];
    let (code, out, err) = grid(&args);
    assert_eq!(code, 0, "{err}");
    let said = format!("landmarks: {} (2 landmarks)", survey.display());
    assert!(err.lines().any(|l| l == said), "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["unknown"], 0, "{v}");
    // A survey without subject 6 (which the bundled map has): no reading names one of its
    // landmarks, so the run ends with a warning and exit 3.
    std::fs::write(&survey, row(7, 5.0)).unwrap();
    let (code, out, err) = grid(&args);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains("warning: no reading names a landmark of the map"),
        "{err}"
    );
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["unknown"], 2, "{v}");
    assert_eq!(v["rejected_lines"], 0, "{v}");
}

#[test]
fn a_map_that_names_no_reading_warns_and_exits_3() {
    // The tiny landmark map (ids 1–3) against the tiny MRCLAM directory (subject 6 only).
    let d = mrclam_dir("no_match", "10.0 0.0 0.0\n11.5 0.0 0.0\n");
    let map = d.join("tiny.map");
    std::fs::write(&map, landmarks::tiny_map(false)).unwrap();
    let mut args = vec![
        "--map".as_ref(),
        map.as_os_str(),
        "--from-dir".as_ref(),
        d.as_os_str(),
        "--robot".as_ref(),
        "1".as_ref(),
    ];
    let (code, out, err) = grid(&args);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains("warning: no reading names a landmark of the map"),
        "{err}"
    );
    assert!(out.contains("0 used"), "{out}");
    // The same map with a stream that does name its landmarks: no warning.
    let (_s, tiny, stream) = setup("no_match_ok", &[frame(0.0)]);
    args = vec!["--map".as_ref(), tiny.as_os_str(), stream.as_os_str()];
    let (code, _, err) = grid(&args);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("warning"), "{err}");
}

#[test]
fn grid_counts_other_robots_apart_from_unknown_subjects() {
    // Ids 1–3 are the tiny map's; robots 4 and 5 are `Robot4`/`Robot5`, id 7 is `S7`.
    let pair = |who: &str| {
        format!(
            r#"{{"name":"landmark_range","args":["{who}"],"value":2.0,"degree":1.0}},{{"name":"landmark_bearing","args":["{who}"],"value":10.0,"degree":1.0}},"#
        )
    };
    let mut lines: Vec<String> = (0..4).map(|k| frame(k as f64)).collect();
    let extra = [pair("Robot4"), pair("Robot5"), pair("S7")].concat();
    for l in &mut lines[1..3] {
        *l = l.replacen(r#""percepts":["#, &format!(r#""percepts":[{extra}"#), 1);
    }
    let (_d, map, stream) = setup("robots_apart", &lines);
    let (code, out, err) = grid(&["--map".as_ref(), map.as_os_str(), stream.as_os_str()]);
    assert_eq!(code, 0, "{err}");
    // Two frames with two robots and one stranger each.
    assert!(
        out.contains(" 4 of other robots, 2 of unknown subjects,"),
        "{out}"
    );
    let (_, v, _) = grid_json("robots_apart_json", &lines);
    assert_eq!(v["other_robots"], 4, "{v}");
    assert_eq!(v["unknown"], 6, "{v}");
}

/// The tiny world's stream over `n` frames one second apart from `t0`.
fn world(name: &str, t0: f64, n: usize) -> (PathBuf, PathBuf, PathBuf) {
    let lines: Vec<String> = (0..n).map(|k| frame(t0 + k as f64)).collect();
    setup(name, &lines)
}

#[test]
fn the_first_fix_is_also_given_on_the_logs_clock() {
    let t0 = 1_000_000.25;
    let (_d, map, stream) = world("fix_clock", t0, 5);
    let json = [
        "--map".as_ref(),
        map.as_os_str(),
        stream.as_os_str(),
        "--format".as_ref(),
        "json".as_ref(),
    ];
    let (_, out, err) = grid(&json);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let after = v["first_fix"].as_f64().expect("a fix");
    let at = v["first_fix_t"].as_f64().expect("a fix time");
    assert!((at - (t0 + after)).abs() < 1e-6, "{v} {err}");
    let (code, out, err) = grid(&["--map".as_ref(), map.as_os_str(), stream.as_os_str()]);
    assert_eq!(code, 0, "{err}");
    let said = format!("first fix: {after:.3} s (t = {:.3})", t0 + after);
    assert!(out.lines().any(|l| l == said), "{out}");
}

#[test]
fn truth_tum_holds_the_streams_truth_at_the_trajectorys_times() {
    // The robot stands at (1, 1) but its truth walks along x, so truth and estimate differ.
    let truth = |k: usize| (0.5 * k as f64, 2.0 - 0.25 * k as f64);
    let lines: Vec<String> = (0..6)
        .map(|k| landmarks::frame_at(10.0 + k as f64, truth(k)))
        .collect();
    let (d, map, stream) = setup("truth_tum", &lines);
    let (est, tru) = (d.join("est.tum"), d.join("truth.tum"));
    let args = [
        "--map".as_ref(),
        map.as_os_str(),
        stream.as_os_str(),
        "--tum".as_ref(),
        est.as_os_str(),
        "--truth-tum".as_ref(),
        tru.as_os_str(),
    ];
    let (code, _, err) = grid(&args);
    assert_eq!(code, 0, "{err}");
    let (est, tru) = (tum(&est), tum(&tru));
    assert_eq!(tru.len(), 6);
    let times = |p: &[lplace::io::tum::TumPose]| p.iter().map(|p| p.t).collect::<Vec<_>>();
    assert_eq!(times(&est), times(&tru));
    for (k, p) in tru.iter().enumerate() {
        let (x, y) = truth(k);
        assert!(
            (p.x - x).abs() < 1e-6 && (p.y - y).abs() < 1e-6,
            "{k}: {p:?}"
        );
        assert!(p.yaw.abs() < 1e-6, "{k}: {p:?}");
    }
    // Refused over an input, as --tum is.
    let (code, _, err) = grid(&[
        "--map".as_ref(),
        map.as_os_str(),
        stream.as_os_str(),
        "--truth-tum".as_ref(),
        stream.as_os_str(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--truth-tum"), "{err}");
}

#[test]
fn with_a_kidnap_the_tum_file_is_the_kidnapped_run() {
    let (d, map, stream) = world("kidnap_tum", 0.0, 30);
    let (plain, kidnapped) = (d.join("plain.tum"), d.join("kidnapped.tum"));
    let base = [map.as_os_str(), stream.as_os_str()];
    let run = |out: &Path, kidnap: &[&str]| {
        let mut a: Vec<&std::ffi::OsStr> = vec!["--map".as_ref()];
        a.extend(base);
        a.extend(["--tum".as_ref(), out.as_os_str()]);
        a.extend(kidnap.iter().map(std::ffi::OsStr::new));
        let (code, _, err) = grid(&a);
        assert_eq!(code, 0, "{err}");
        tum(out)
    };
    let plain = run(&plain, &[]);
    let kidnapped = run(&kidnapped, &["--kidnap-at", "10", "--kidnap-by", "0,2,0"]);
    assert_eq!(plain.len(), kidnapped.len());
    let moved =
        |p: &lplace::io::tum::TumPose, q: &lplace::io::tum::TumPose| (p.x - q.x).hypot(p.y - q.y);
    for (p, q) in plain.iter().zip(&kidnapped).filter(|(p, _)| p.t < 10.0) {
        assert!(moved(p, q) < 1e-9, "before the kidnap: {p:?} {q:?}");
    }
    let most = plain
        .iter()
        .zip(&kidnapped)
        .map(|(p, q)| moved(p, q))
        .fold(0.0, f64::max);
    assert!(most > 0.5, "the kidnap is not in the TUM file ({most} m)");
}

/// Data lines of an MRCLAM file, split into fields.
fn rows(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
        .collect()
}

#[test]
fn mrclam_robot1_from_dir_reads_its_survey_and_counts_other_robots() {
    let Some(dir) = crate::support::mrclam_dir() else {
        return;
    };
    let d = scratch("real_from_dir");
    let (own, bundled) = (d.join("own.tum"), d.join("bundled.tum"));
    let from_dir = |tum: &Path, map: Option<&str>| {
        let mut a = vec![
            "--from-dir".as_ref(),
            dir.as_os_str(),
            "--robot".as_ref(),
            "1".as_ref(),
        ];
        if let Some(m) = map {
            a.extend(["--map", m].map(std::ffi::OsStr::new));
        }
        a.extend([
            "--tum".as_ref(),
            tum.as_os_str(),
            "--format".as_ref(),
            "json".as_ref(),
        ]);
        let (code, out, err) = grid(&a);
        assert_eq!(code, 0, "{err}");
        (
            serde_json::from_str::<serde_json::Value>(&out).unwrap(),
            err,
        )
    };
    let (v, err) = from_dir(&own, None);
    let said = format!(
        "landmarks: {} (15 landmarks)",
        dir.join("Landmark_Groundtruth.dat").display()
    );
    assert!(err.lines().any(|l| l == said), "{err}");
    // The bundled map is the survey digit for digit: the same trajectory.
    from_dir(&bundled, Some("maps/mrclam.map"));
    assert_eq!(
        std::fs::read(&own).unwrap(),
        std::fs::read(&bundled).unwrap()
    );
    // Sightings of robots: Robot1_Measurement.dat's lines whose barcode is a robot's (subjects
    // 1–5 in Barcodes.dat).
    let robot_codes: Vec<f64> = rows(&dir.join("Barcodes.dat"))
        .iter()
        .filter(|r| (1.0..=5.0).contains(&r[0]))
        .map(|r| r[1])
        .collect();
    let sightings = rows(&dir.join("Robot1_Measurement.dat"))
        .iter()
        .filter(|r| robot_codes.contains(&r[1]))
        .count();
    assert!(sightings > 0);
    assert_eq!(v["other_robots"], sightings, "{v}");
    // The first fix on the log's clock: the first frame's time plus the fix's delay.
    let t0 = tum(&own)[0].t;
    let at = v["first_fix_t"].as_f64().unwrap();
    assert!(
        (at - t0 - v["first_fix"].as_f64().unwrap()).abs() < 1e-6,
        "{v}"
    );
}
