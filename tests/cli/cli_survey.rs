//! End-to-end tests of `lplace survey` on hand-worked streams over the bundled office map: the
//! written map (nearest-rank quantiles worked by hand), the per-place lines, first visits, `-o`,
//! and every error exit.

use crate::support::{lplace, scratch};
use std::path::{Path, PathBuf};

const OFFICE_MAP: &str = include_str!("../../maps/office.map");
/// P0's declared expectations, which a fit replaces.
const P0_PARAMS: &str = "param A = 204.0; param L = 4.92;";

/// The office map with P0's parameters fitted to `params` from `scans` scans: the ranges in
/// place of the written values, and the count added before P0's closing brace.
fn p0_written(params: &str, scans: usize) -> String {
    OFFICE_MAP.replacen(
        &format!("{P0_PARAMS}\n}}"),
        &format!("{params}\n param scans = {scans}; }}"),
        1,
    )
}

/// A record at `place` seeing the beacon at angle `a`, distance `l`, after moving `dx` metres.
fn record(t: f64, dx: f64, place: &str, a: f64, l: f64) -> String {
    format!(
        r#"{{"version":1,"t":{t},"odometry":{{"dx":{dx},"dy":0,"dtheta":0}},"percepts":[{{"name":"beacon_angle","value":{a},"degree":1}},{{"name":"beacon_distance","value":{l},"degree":1}}],"truth":{{"place":"{place}"}}}}"#
    )
}

/// Ten frames at P0 with angles 10, 20, …, 100 and distances 1.0, 1.1, …, 1.9, standing still.
fn p0_lines() -> Vec<String> {
    (0..10)
        .map(|k| {
            let k = f64::from(k);
            record(k * 0.1, 0.0, "P0", 10.0 * (k + 1.0), 1.0 + 0.1 * k)
        })
        .collect()
}

fn write(dir: &Path, name: &str, lines: &[String]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, lines.join("\n") + "\n").expect("scratch is writable");
    p
}

/// `lplace survey` over the bundled office map and rules, the stream still to be named.
fn survey_office() -> assert_cmd::Command {
    let mut c = lplace();
    c.args([
        "survey",
        "--map",
        "maps/office.map",
        "--rules",
        "rules/office.lpl",
    ]);
    c
}

fn survey(stream: &Path, extra: &[&str]) -> (Option<i32>, String, String) {
    let out = survey_office()
        .arg(stream)
        .args(extra)
        .output()
        .expect("runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn writes_the_nearest_rank_range_and_nothing_else() {
    let dir = scratch("cli_survey", "hand");
    let stream = write(&dir, "p0.jsonl", &p0_lines());
    let (code, out, err) = survey(&stream, &[]);
    assert_eq!(code, Some(0), "{err}");
    // lo = v[⌊0.1·9⌋] = v[0], hi = v[⌊0.9·9⌋] = v[8].
    let want = p0_written("param A = 10.00 .. 90.00; param L = 1.00 .. 1.80;", 10);
    assert_ne!(want, OFFICE_MAP);
    assert_eq!(out, want);
    // Spread: the median of the widths {0.8, 80} is the second of the pair.
    assert_eq!(err, "survey: P0: 10 scan(s), median spread 80.00\n");
    // Other quantiles, and a warning under --min-scans.
    let (code, out, err) = survey(&stream, &["--quantiles", "0.5", "1", "--min-scans", "11"]);
    assert_eq!(code, Some(0), "{err}");
    // lo = v[⌊0.5·9⌋] = v[4], hi = v[9].
    let want = p0_written("param A = 50.00 .. 100.00; param L = 1.40 .. 1.90;", 10);
    assert_eq!(out, want);
    assert_eq!(
        err,
        "survey: P0: 10 scan(s), median spread 50.00  WARNING: few scans, the fit is unreliable\n"
    );
    // -o writes the same bytes.
    let target = dir.join("out.map");
    let (code, out, _) = survey(&stream, &["-o", target.to_str().expect("utf-8")]);
    assert_eq!((code, out.as_str()), (Some(0), ""));
    let written = std::fs::read_to_string(&target).expect("written");
    assert_eq!(
        written,
        p0_written("param A = 10.00 .. 90.00; param L = 1.00 .. 1.80;", 10)
    );
}

#[test]
fn first_visits_fit_on_the_first_and_score_the_later_ones() {
    let dir = scratch("cli_survey", "first");
    let mut lines = p0_lines();
    // Five frames at P1, 1 m apart, then a second visit to P0 (> 2 m later) with far-off values
    // that a first-visit fit must not see.
    for k in 0..5 {
        lines.push(record(2.0 + f64::from(k), 1.0, "P1", 170.0, 4.6));
    }
    for k in 0..5 {
        lines.push(record(8.0 + f64::from(k), 0.0, "P0", 300.0, 9.0));
    }
    let stream = write(&dir, "visits.jsonl", &lines);
    let (code, out, err) = survey(&stream, &["--fit", "first-visits"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.contains("param A = 10.00 .. 90.00; param L = 1.00 .. 1.80;"),
        "{out}"
    );
    assert!(
        out.contains("param A = 170.00 .. 170.00; param L = 4.60 .. 4.60;"),
        "{out}"
    );
    let err_lines: Vec<&str> = err.lines().collect();
    assert_eq!(err_lines.len(), 3, "{err}");
    assert!(err_lines[0].starts_with("survey: P0: 10 scan(s)"));
    // P0's later readings (300°, 9 m) all lie outside its first-visit ranges (10–90°,
    // 1–1.8 m); P1 is not visited again, and its warning is its five scans.
    assert!(
        err_lines[0]
            .ends_with("WARNING: most readings of the later visits lie outside the fitted ranges"),
        "{err}"
    );
    assert!(err_lines[1].starts_with("survey: P1: 5 scan(s)"));
    assert!(
        err_lines[1].ends_with("WARNING: few scans, the fit is unreliable"),
        "{err}"
    );
    // The later visit is P0's second: its 5 frames are the held-out ones.
    assert!(
        err_lines[2].starts_with("survey: later visits (held out): 5 scan(s) at a place"),
        "{err}"
    );
    // Fitting on every frame sees the second visit: 15 values at P0, lo = v[⌊0.1·14⌋] = v[1],
    // hi = v[⌊0.9·14⌋] = v[12], one of the 300s (9.0 m).
    let (_, all, _) = survey(&stream, &[]);
    assert!(
        all.contains("param A = 20.00 .. 300.00; param L = 1.10 .. 9.00;"),
        "{all}"
    );
}

#[test]
fn errors_exit_with_their_codes_and_say_where() {
    let dir = scratch("cli_survey", "errors");
    let mut lines = p0_lines();
    lines.insert(3, "{not json".to_owned());
    let stream = write(&dir, "bad-line.jsonl", &lines);
    let (code, out, err) = survey(&stream, &[]);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.starts_with(&format!("{}:4:2: not JSON", stream.display())),
        "{err}"
    );
    assert!(out.contains("param A = 10.00 .. 90.00;"));

    let good = write(&dir, "p0.jsonl", &p0_lines());
    let (code, _, err) = survey(&good, &["--quantiles", "0.9", "0.1"]);
    assert_eq!(
        (code, err.as_str()),
        (Some(2), "error: --quantiles LO HI needs 0 ≤ LO ≤ HI ≤ 1\n")
    );

    let csv = dir.join("labels.csv");
    std::fs::write(&csv, "t,place\n0,P0\nlater,P1\n").expect("written");
    let (code, _, err) = survey(&good, &["--labels", csv.to_str().expect("utf-8")]);
    assert_eq!(code, Some(2));
    assert_eq!(err, format!("{}:3: expected `t,place`\n", csv.display()));

    // A place the map does not declare cannot be written (in a record's truth the reader
    // rejects it, as `eval` does; from a labels file it reaches the fit).
    let stray = dir.join("stray.csv");
    std::fs::write(&stray, "t,place\n0,Nowhere\n").expect("written");
    let (code, out, err) = survey(&good, &["--labels", stray.to_str().expect("utf-8")]);
    assert_eq!((code, out.as_str()), (Some(2), ""));
    assert!(
        err.contains("place `Nowhere` was fitted but the map does not declare it"),
        "{err}"
    );

    let rules = dir.join("none.lpl");
    std::fs::write(&rules, "percept w(value, time);\n").expect("written");
    let out = lplace()
        .args(["survey", "--map", "maps/office.map", "--rules"])
        .arg(&rules)
        .arg(&good)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("nothing to fit"));

    let map = dir.join("bad.map");
    std::fs::write(&map, "map m;\nplace P0 at (0, ;\n").expect("written");
    let out = lplace()
        .args(["survey", "--rules", "rules/office.lpl", "--map"])
        .arg(&map)
        .arg(&good)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains(&format!("{}:2:", map.display())));

    let (code, _, _) = survey(&dir.join("absent.jsonl"), &[]);
    assert_eq!(code, Some(1));
}

#[test]
fn bad_records_are_rejected_by_line_as_eval_rejects_them() {
    let dir = scratch("cli_survey", "reader");
    let mut lines = p0_lines();
    // Line 3: a degree above 1; line 9: a time before the previous record's (0.6).
    let over = record(0.15, 0.0, "P0", 15.0, 1.05).replacen("\"degree\":1}", "\"degree\":1.5}", 1);
    lines.insert(2, over);
    lines.insert(8, record(0.25, 0.0, "P0", 500.0, 9.0));
    let stream = write(&dir, "bad.jsonl", &lines);
    // The time of line 8 as `p0_lines` writes it (k = 6).
    let previous = 6.0 * 0.1;
    let (code, out, err) = survey(&stream, &[]);
    assert_eq!(code, Some(3), "{err}");
    let name = stream.display();
    let reported: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with(&*name.to_string()))
        .collect();
    assert_eq!(
        reported,
        vec![
            format!("{name}:3: percept `beacon_angle`: degree 1.5 is outside [0, 1]"),
            format!("{name}:9: time goes backwards: t = 0.25 after t = {previous}"),
        ]
    );
    // Neither record reaches the fit: the map is the one the ten good records give.
    let clean = write(&dir, "clean.jsonl", &p0_lines());
    let (clean_code, clean_out, _) = survey(&clean, &[]);
    assert_eq!(clean_code, Some(0));
    assert_eq!(out, clean_out);
    // `eval` reads the same stream with the same reader: the same reports.
    let ev = lplace()
        .args([
            "eval",
            "--map",
            "maps/office.map",
            "--rules",
            "rules/office.lpl",
        ])
        .arg(&stream)
        .output()
        .expect("runs");
    assert_eq!(ev.status.code(), Some(3));
    let ev_err = String::from_utf8_lossy(&ev.stderr).into_owned();
    let ev_reported: Vec<&str> = ev_err
        .lines()
        .filter(|l| l.starts_with(&*name.to_string()))
        .collect();
    assert_eq!(ev_reported, reported);
    // `-` reads stdin, as for `eval`: the same map as from the file.
    let text = std::fs::read(&clean).expect("written above");
    let piped = survey_office()
        .arg("-")
        .write_stdin(text)
        .output()
        .expect("runs");
    assert_eq!(piped.status.code(), Some(0));
    assert_eq!(String::from_utf8_lossy(&piped.stdout), clean_out);
}
