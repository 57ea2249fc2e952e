//! `lplace compare` end to end: every method on a hand-made stream whose answer is known (a
//! robot standing still among three landmarks), TUM files one per method that parse back, the
//! three output formats, the sweeps and their plot, exit codes for bad specs and malformed
//! lines, `--help`; then real MRCLAM robot 1, and `scripts/mrclam_table.py` against compare's own
//! figures (both skipped when the data set is absent).

use crate::support::landmarks::{self, frame};
use crate::support::{lplace, mrclam_dir};
use lplace::io::tum::read_tum;
use std::path::PathBuf;

/// A fresh directory for this file's tests.
fn scratch(name: &str) -> PathBuf {
    crate::support::scratch("cli_compare", name)
}

/// A directory with the tiny map (landmarks only) and a stream of `n` frames one second apart.
fn setup(name: &str, n: usize) -> (PathBuf, PathBuf, PathBuf) {
    let d = scratch(name);
    let lines: Vec<String> = (0..n).map(|k| frame(k as f64)).collect();
    let (map, stream) = landmarks::write(&d, false, &lines);
    (d, map, stream)
}

const METHODS: [&str; 4] = ["fpg", "pf:500", "pf:2000", "rmcl"];

#[test]
fn every_method_finds_a_robot_standing_among_three_landmarks() {
    // Three minutes: PF(500) with seed 1 first locks onto a wrong pose (500 particles over
    // 30 m² and all headings leave none near the truth) and needs random injection to recover,
    // which took 44 s or 89 s depending on the filter's tuning. What is checked: every method
    // gets a fix within the stream, is right from then on, and ends at the truth.
    let (d, map, stream) = setup("still", 180);
    let tums = d.join("tum");
    let out = lplace()
        .arg("compare")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .arg("--tum-dir")
        .arg(&tums)
        .args(["--format", "json"])
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
    let rows = v["methods"].as_array().unwrap();
    let names: Vec<&str> = rows.iter().map(|r| r["method"].as_str().unwrap()).collect();
    assert_eq!(names, METHODS, "default --methods");
    for r in rows {
        assert_eq!(r["frames"].as_u64(), Some(180), "{r}");
        // The truth is (1, 1) in every frame; every method must get there and stay.
        let rmse = r["ate"]["rmse"].as_f64().unwrap_or(f64::INFINITY);
        assert!(rmse < 0.25, "{r}");
        let fix = r["first_fix"].as_f64().unwrap_or(f64::INFINITY);
        assert!(fix < 179.0, "{r}");
        assert!(r["time_per_step_us"].as_f64().unwrap() > 0.0, "{r}");
    }
    // Every frame has readings, so each R-MCL estimate is either sampled or a fallback.
    let rmcl = &rows[3]["rmcl"];
    let made = rmcl["sampled"].as_u64().unwrap() + rmcl["fallbacks"].as_u64().unwrap();
    assert_eq!(made, 180, "{rmcl}");
    assert!(rows[0]["rmcl"].is_null());
    for (m, file) in METHODS
        .iter()
        .zip(["fpg.tum", "pf-500.tum", "pf-2000.tum", "rmcl.tum"])
    {
        let poses = read_tum(std::io::BufReader::new(
            std::fs::File::open(tums.join(file)).unwrap(),
        ))
        .unwrap();
        assert_eq!(poses.len(), 180, "{m}");
        let last = poses[179];
        assert!((last.t - 179.0).abs() < 1e-9, "{m}: {last:?}");
        assert!(
            (last.x - 1.0).hypot(last.y - 1.0) < 0.25,
            "{m} ends at {last:?}"
        );
    }
}

#[test]
fn table_csv_sweeps_and_plot() {
    let (d, map, stream) = setup("formats", 12);
    let table = lplace()
        .arg("compare")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args(["--methods", "fpg,pf:200", "--kidnap-at", "mid"])
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let table = String::from_utf8(table).unwrap();
    assert!(
        table.starts_with("| method | frames | ATE RMSE [m]"),
        "{table}"
    );
    assert!(table.contains("\n| fpg | 12 | "), "{table}");
    assert!(table.contains("\n| pf:200 | 12 | "), "{table}");
    assert!(
        table.contains("kidnap injected 6.0 s after the first frame"),
        "{table}"
    );

    let svg = d.join("sweep.svg");
    let csv = lplace()
        .arg("compare")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args(["--methods", "fpg", "--format", "csv", "--sweep", "both"])
        .arg("--svg")
        .arg(&svg)
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let csv = String::from_utf8(csv).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    // Header, one main row, 5 noise levels and 4 kept fractions.
    assert_eq!(lines.len(), 1 + 1 + 5 + 4, "{csv}");
    let cols = lines[0].split(',').count();
    assert!(lines.iter().all(|l| l.split(',').count() == cols), "{csv}");
    assert!(lines[1].starts_with("fpg,main,0,0,1,"), "{csv}");
    assert!(
        lines.iter().any(|l| l.starts_with("fpg,sparsity,0,0,0.1,")),
        "{csv}"
    );
    // Noise 0 and keep 100 % are the unperturbed stream: same ATE as the main run.
    let ate = |l: &str| l.split(',').nth(5).unwrap().to_string();
    assert_eq!(ate(lines[1]), ate(lines[2]), "{csv}");
    assert_eq!(ate(lines[1]), ate(lines[7]), "{csv}");
    let picture = std::fs::read_to_string(&svg).unwrap();
    assert!(picture.starts_with("<svg") && picture.contains("readings kept"));
    assert!(picture.contains(">fpg<"), "legend names the method");
}

#[test]
fn same_seed_same_numbers() {
    let (_d, map, stream) = setup("seed", 10);
    let run = |seed: &str| {
        let out = lplace()
            .arg("compare")
            .arg("--map")
            .arg(&map)
            .arg(&stream)
            .args([
                "--methods",
                "pf:100,rmcl",
                "--format",
                "json",
                "--seed",
                seed,
            ])
            .args(["--sweep", "sparsity"])
            .assert()
            .code(0)
            .get_output()
            .stdout
            .clone();
        let mut v: serde_json::Value = serde_json::from_slice(&out).unwrap();
        // Wall time differs between runs; everything else must not.
        for r in v["methods"].as_array_mut().unwrap() {
            r["wall_s"] = serde_json::Value::Null;
            r["time_per_step_us"] = serde_json::Value::Null;
        }
        v
    };
    assert_eq!(run("7"), run("7"));
}

#[test]
fn bad_specs_and_flags_exit_2_with_a_message() {
    let (_d, map, stream) = setup("bad_spec", 3);
    for (spec, says) in [
        ("fpg,kalman", "unknown method `kalman`"),
        ("pf:zero", "particle count"),
        ("pf:0", "particle count"),
    ] {
        let out = lplace()
            .arg("compare")
            .arg("--map")
            .arg(&map)
            .arg(&stream)
            .args(["--methods", spec])
            .assert()
            .code(2)
            .get_output()
            .clone();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{spec}: {err}");
    }
    let out = lplace()
        .arg("compare")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args(["--methods", "fpg,pf:10,fpg"])
        .assert()
        .code(2)
        .get_output()
        .clone();
    assert!(String::from_utf8_lossy(&out.stderr).contains("given twice"));
    lplace()
        .arg("compare")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args(["--kidnap-at", "soon"])
        .assert()
        .code(2);
    lplace()
        .arg("compare")
        .arg(&stream)
        .args(["--svg", "x.svg"])
        .assert()
        .code(2);
    lplace()
        .arg("compare")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args(["--format", "xml"])
        .assert()
        .code(2);
    lplace().arg("compare").assert().code(2);
    // An output directory that cannot be made (under a file): exit 1, naming it.
    let out = lplace()
        .arg("compare")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args(["--methods", "fpg", "--tum-dir"])
        .arg(stream.join("tum"))
        .assert()
        .code(1)
        .get_output()
        .clone();
    assert!(String::from_utf8_lossy(&out.stderr).contains("s.jsonl"));
}

#[test]
fn malformed_lines_are_reported_with_their_number_and_give_exit_3() {
    let (d, map, _) = setup("malformed", 0);
    let mut lines: Vec<String> = (0..5).map(|k| frame(k as f64)).collect();
    lines.insert(2, "{\"version\":1,\"t\":".to_string());
    let stream = d.join("broken.jsonl");
    std::fs::write(&stream, lines.join("\n") + "\n").unwrap();
    let out = lplace()
        .arg("compare")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args(["--methods", "fpg"])
        .assert()
        .code(3)
        .get_output()
        .clone();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("broken.jsonl:3:"), "{err}");
    // The good frames were still compared.
    assert!(String::from_utf8_lossy(&out.stdout).contains("| fpg | 5 |"));
}

#[test]
fn help_explains_methods_and_wall_time() {
    let out = lplace()
        .args(["compare", "--help"])
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let help = String::from_utf8(out).unwrap();
    for needle in [
        "--methods",
        "pf:N",
        "rmcl",
        "wall time",
        "--sweep",
        "--tum-dir",
    ] {
        assert!(help.contains(needle), "{needle}: {help}");
    }
}

#[test]
fn mrclam_robot1_grid_and_small_pf() {
    let Some(dir) = mrclam_dir() else {
        return;
    };
    let out = lplace()
        .arg("compare")
        .arg("--from-dir")
        .arg(&dir)
        .args([
            "--robot",
            "1",
            "--methods",
            "fpg,pf:500,rmcl",
            "--format",
            "json",
        ])
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
    let rows = v["methods"].as_array().unwrap();
    assert_eq!(rows.len(), 3);
    // The grid's figure on robot 1 is docs/grid.md's (measured by `lplace grid`): the same
    // driver must give the same number here.
    let fpg = &rows[0];
    assert_eq!(fpg["frames"].as_u64(), Some(2745), "{fpg}");
    let rmse = fpg["ate"]["rmse"].as_f64().unwrap();
    assert!((rmse - 0.221).abs() < 0.0005, "{fpg}");
    // The common window starts at the latest first fix, the same for every row, and holds
    // no more frames than any row's own window.
    let latest = rows
        .iter()
        .map(|r| r["first_fix"].as_f64().unwrap())
        .fold(f64::NEG_INFINITY, f64::max);
    for r in rows {
        let from = r["common_from"].as_f64().unwrap();
        assert!((from - latest).abs() < 1e-6, "{r}");
        assert!(
            r["ate_common"]["count"].as_u64() <= r["ate"]["count"].as_u64(),
            "{r}"
        );
    }
    for r in rows {
        // Every method localizes robot 1 to well under the 15 m × 8 m arena's scale.
        let rmse = r["ate"]["rmse"].as_f64().unwrap_or(f64::INFINITY);
        assert!(rmse < 1.0, "{r}");
    }
}

/// Runs `lplace compare` with `args`; returns (exit code, stdout, stderr).
fn compare<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> (i32, String, String) {
    let out = lplace().arg("compare").args(args).output().unwrap();
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (
        out.status.code().unwrap_or(-1),
        text(&out.stdout),
        text(&out.stderr),
    )
}

#[test]
fn compare_names_its_map_and_warns_when_the_map_names_no_reading() {
    // The tiny MRCLAM directory's robot 1 sees subject 6 only; the tiny map has ids 1–3.
    let d = crate::support::mrclam::tiny_dir(&scratch("no_match"), "10.0 0.0 0.0\n11.5 0.0 0.0\n");
    let map = d.join("tiny.map");
    std::fs::write(&map, landmarks::tiny_map(false)).unwrap();
    let from_dir = [
        "--from-dir".as_ref(),
        d.as_os_str(),
        "--robot".as_ref(),
        "1".as_ref(),
        "--methods".as_ref(),
        "fpg".as_ref(),
    ];
    let mut args = vec!["--map".as_ref(), map.as_os_str()];
    args.extend(from_dir);
    let (code, _, err) = compare(&args);
    assert_eq!(code, 3, "{err}");
    let said = format!("landmarks: {} (3 landmarks)", map.display());
    assert!(err.lines().any(|l| l == said), "{err}");
    assert!(
        err.contains("warning: no reading names a landmark of the map"),
        "{err}"
    );
    // Without --map, the directory's own survey, which has subject 6: no warning.
    let survey = d.join("Landmark_Groundtruth.dat");
    std::fs::write(&survey, "6 2.0 0.0 0.001 0.001\n").unwrap();
    let (code, _, err) = compare(&from_dir);
    assert_eq!(code, 0, "{err}");
    let said = format!("landmarks: {} (1 landmark)", survey.display());
    assert!(err.lines().any(|l| l == said), "{err}");
}

#[test]
fn compare_gives_the_first_fix_on_the_logs_clock_and_writes_the_kidnapped_run() {
    let d = scratch("fix_clock");
    let t0 = 5000.5;
    let lines: Vec<String> = (0..30).map(|k| frame(t0 + k as f64)).collect();
    let (map, stream) = landmarks::write(&d, false, &lines);
    let (plain, kidnapped) = (d.join("plain"), d.join("kidnapped"));
    let run = |dir: &PathBuf, extra: &[&str]| {
        let mut a = vec![
            "--map".as_ref(),
            map.as_os_str(),
            stream.as_os_str(),
            "--methods".as_ref(),
            "fpg".as_ref(),
            "--tum-dir".as_ref(),
            dir.as_os_str(),
        ];
        a.extend(extra.iter().map(std::ffi::OsStr::new));
        let (code, out, err) = compare(&a);
        assert_eq!(code, 0, "{err}");
        let poses = read_tum(std::io::BufReader::new(
            std::fs::File::open(dir.join("fpg.tum")).unwrap(),
        ))
        .unwrap();
        (out, poses)
    };
    let (out, plain) = run(&plain, &["--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let row = &v["methods"][0];
    let after = row["first_fix"].as_f64().expect("a fix");
    let at = row["first_fix_t"].as_f64().expect("a fix time");
    assert!((at - t0 - after).abs() < 1e-6, "{row}");
    // The CSV carries the same instant, by its header's name (the fpg row is the first).
    let (csv, _) = run(&d.join("csv"), &["--format", "csv"]);
    let mut lines = csv.lines();
    let col = lines
        .next()
        .unwrap()
        .split(',')
        .position(|h| h == "first_fix_t");
    let cell = lines
        .next()
        .unwrap()
        .split(',')
        .nth(col.expect("a first_fix_t column"));
    let csv_at: f64 = cell.unwrap().parse().expect("a number");
    assert!((csv_at - at).abs() < 1e-9, "{csv}");
    let (table, kidnapped) = run(&kidnapped, &["--kidnap-at", "10", "--kidnap-by", "0,2,0"]);
    let said = format!("first fix on the log's clock (evo_ape --t_start): fpg t = {at:.3}");
    assert!(table.lines().any(|l| l == said), "{table}");
    let most = plain
        .iter()
        .zip(&kidnapped)
        .map(|(p, q)| (p.x - q.x).hypot(p.y - q.y))
        .fold(0.0, f64::max);
    assert!(most > 0.5, "the kidnap is not in the TUM file ({most} m)");
}

#[test]
fn start_at_truth_fixes_at_the_first_frame_and_refuses_rmcl() {
    // The truth of the first frame is (1, 1), where the robot stands: both methods start there
    // (fix at 0 s), and stay (they see three landmarks read exactly).
    let (_d, map, stream) = setup("start", 5);
    let out = lplace()
        .arg("compare")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args([
            "--methods",
            "fpg,pf:500",
            "--start-at-truth",
            "--format",
            "json",
        ])
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
    for r in v["methods"].as_array().unwrap() {
        assert_eq!(r["first_fix"].as_f64(), Some(0.0), "{r}");
        // Within a cell and a half of the truth (0.1 m cells: the grid's estimate is a centre of
        // gravity of cells), every frame.
        assert!(r["ate"]["max"].as_f64().unwrap() < 0.15, "{r}");
    }
    // R-MCL has no pose to start from: a flag error, exit 2.
    lplace()
        .arg("compare")
        .arg("--map")
        .arg(&map)
        .arg(&stream)
        .args(["--methods", "fpg,rmcl", "--start-at-truth"])
        .assert()
        .code(2)
        .stderr(predicates::str::contains("rmcl cannot start from a pose"));
}

/// Each method's common-window ATE from `lplace compare --format csv` (unperturbed runs), with
/// `extra` arguments (configurations).
fn common_window_ates(
    dir: &std::path::Path,
    methods: &str,
    (robot, seed): (u32, u32),
    extra: &[&std::ffi::OsStr],
) -> Vec<f64> {
    let (robot, seed) = (robot.to_string(), seed.to_string());
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "--from-dir".as_ref(),
        dir.as_os_str(),
        "--robot".as_ref(),
        robot.as_ref(),
        "--methods".as_ref(),
        methods.as_ref(),
        "--seed".as_ref(),
        seed.as_ref(),
        "--format".as_ref(),
        "csv".as_ref(),
    ];
    args.extend(extra);
    let (code, out, err) = compare(&args);
    assert_eq!(code, 0, "{err}");
    let mut lines = out.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "ate_common_rmse_m")
        .unwrap();
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| f[1] == "main")
        .map(|f| f[col].parse().unwrap())
        .collect()
}

/// The numbers of the Markdown row whose first cell is `label`.
fn table_row(text: &str, label: &str) -> Vec<f64> {
    let line = text
        .lines()
        .find(|l| l.starts_with(&format!("| {label} |")))
        .unwrap_or_else(|| panic!("no row {label}: {text}"));
    line.split('|')
        .skip(2)
        .filter(|c| !c.trim().is_empty())
        .map(|c| c.trim().trim_matches('*').parse().unwrap())
        .collect()
}

/// `python3 scripts/mrclam_table.py ARGS` from the crate's root.
fn mrclam_table<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> std::process::Output {
    python_script("mrclam_table.py", args)
}

/// `python3 scripts/NAME ARGS` from the crate's root.
fn python_script<S: AsRef<std::ffi::OsStr>>(name: &str, args: &[S]) -> std::process::Output {
    std::process::Command::new("python3")
        .arg(format!("scripts/{name}"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap()
}

/// `scripts/mrclam_table.py` (the README's MRCLAM table): its per-robot rows and its mean must
/// be the means of what `lplace compare` itself prints for those robots and seeds, computed here
/// from compare's CSV. Skipped without the data set or python3.
#[test]
fn the_mrclam_table_script_averages_what_compare_prints() {
    let Some(dir) = mrclam_with_python() else {
        return;
    };
    let methods = "fpg,pf:500";
    let runs: Vec<Vec<f64>> = [(1, 1), (1, 2), (2, 1), (2, 2)]
        .iter()
        .map(|&run| common_window_ates(&dir, methods, run, &[]))
        .collect();
    let mean = |xs: &[f64]| xs.iter().sum::<f64>() / xs.len() as f64;
    let robot = |k: usize, m: usize| mean(&[runs[2 * k][m], runs[2 * k + 1][m]]);
    let bin = assert_cmd::cargo::cargo_bin("lplace");
    let out = mrclam_table(&[
        "--data".as_ref(),
        dir.as_os_str(),
        "--robots".as_ref(),
        "1-2".as_ref(),
        "--seeds".as_ref(),
        "1,2".as_ref(),
        "--methods".as_ref(),
        methods.as_ref(),
        "--lplace".as_ref(),
        bin.as_os_str(),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}{err}");
    // The script prints three decimals.
    let near = |a: f64, b: f64| (a - b).abs() <= 0.0005 + 1e-9;
    for m in 0..2 {
        assert!(near(table_row(&text, "1")[m], robot(0, m)), "{text}");
        assert!(near(table_row(&text, "2")[m], robot(1, m)), "{text}");
        let both = mean(&[robot(0, m), robot(1, m)]);
        assert!(near(table_row(&text, "**mean**")[m], both), "{text}");
    }
    // A folder without the survey is refused with exit 2, before any run.
    let out = mrclam_table(&["--data".as_ref(), scratch("table_no_data").as_os_str()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("Landmark_Groundtruth.dat"));
}

/// MRCLAM dataset 7's folder when both it and `python3` are here (else says which is not,
/// for a skip).
fn mrclam_with_python() -> Option<std::path::PathBuf> {
    let dir = mrclam_dir()?;
    if std::process::Command::new("python3")
        .arg("--version")
        .output()
        .is_err()
    {
        eprintln!("SKIPPED: no python3 for the scripts");
        return None;
    }
    Some(dir)
}

/// `scripts/mrclam_fit.py`, in a small run (20 candidates, 2 segments): the file it writes is a
/// configuration `lplace compare` reads, and the whole-run figure in its header — computed by
/// the script from the TUM file and the stream's truth — is the mean of `lplace compare`'s own
/// common-window ATE for the grid beside the calibrated PF(2000), seeds 1–5.
#[test]
fn the_fit_script_scores_robot1_as_compare_does() {
    let Some(dir) = mrclam_with_python() else {
        return;
    };
    let out_file = scratch("fit").join("fitted.ron");
    let bin = assert_cmd::cargo::cargo_bin("lplace");
    let out = python_script(
        "mrclam_fit.py",
        &[
            "--data".as_ref(),
            dir.as_os_str(),
            "--seeds".as_ref(),
            "1".as_ref(),
            "--draws".as_ref(),
            "20".as_ref(),
            "--top".as_ref(),
            "2".as_ref(),
            "--segments".as_ref(),
            "2".as_ref(),
            "--out".as_ref(),
            out_file.as_os_str(),
            "--lplace".as_ref(),
            bin.as_os_str(),
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let text = std::fs::read_to_string(&out_file).unwrap();
    let claimed: f64 = text
        .split("whole run ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no whole-run figure in {text}"));
    let pf = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("config/pf-calibrated.ron");
    let extra = [
        "--config".as_ref(),
        out_file.as_os_str(),
        "--pf-config".as_ref(),
        pf.as_os_str(),
    ];
    let fpg: Vec<f64> = (1..=5)
        .map(|seed| common_window_ates(&dir, "fpg,pf:2000", (1, seed), &extra)[0])
        .collect();
    let mean = fpg.iter().sum::<f64>() / 5.0;
    // The header prints four decimals.
    assert!(
        (claimed - mean).abs() <= 0.00005 + 1e-9,
        "{claimed} against {mean}: {text}"
    );
}
