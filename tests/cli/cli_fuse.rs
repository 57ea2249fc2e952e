//! `lplace fuse` end to end: help, exit codes for bad flags and missing files, malformed data
//! lines reported with their file and line, and (when MRCLAM is present) a short real run.

use crate::support::{lplace, mrclam_dir};
use std::path::Path;

#[test]
fn help_names_the_flags() {
    let out = lplace().args(["fuse", "--help"]).assert().success();
    let text = String::from_utf8(out.get_output().stdout.clone()).unwrap();
    for flag in [
        "--from-dir",
        "--object",
        "--all",
        "--config",
        "--coop-config",
        "--until",
        "--format",
    ] {
        assert!(text.contains(flag), "{flag} missing from:\n{text}");
    }
}

#[test]
fn bad_flags_exit_2_and_missing_files_exit_1() {
    lplace().args(["fuse"]).assert().code(2);
    lplace()
        .args(["fuse", "--from-dir", ".", "--object", "9"])
        .assert()
        .code(2);
    lplace()
        .args(["fuse", "--from-dir", ".", "--object", "1", "--all"])
        .assert()
        .code(2);
    lplace()
        .args(["fuse", "--from-dir", ".", "--until", "-3"])
        .assert()
        .code(2);
    let missing = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_fuse_no_such_dir");
    lplace()
        .args(["fuse", "--from-dir"])
        .arg(&missing)
        .assert()
        .code(1);
}

#[test]
fn a_malformed_line_is_reported_and_exits_3() {
    let Some(src) = mrclam_dir() else {
        return;
    };
    // A copy of the data set in the scratch directory with one broken odometry line.
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_fuse_broken");
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    for e in std::fs::read_dir(&src).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "dat") {
            std::fs::copy(&p, d.join(p.file_name().unwrap())).unwrap();
        }
    }
    let odo = d.join("Robot3_Odometry.dat");
    let mut text = std::fs::read_to_string(&odo).unwrap();
    text.insert_str(text.find("\n1").unwrap() + 1, "1248446190.0 zero 0.0\n");
    std::fs::write(&odo, text).unwrap();
    let out = lplace()
        .args(["fuse", "--until", "30", "--format", "csv", "--from-dir"])
        .arg(&d)
        .assert()
        .code(3);
    let err = String::from_utf8(out.get_output().stderr.clone()).unwrap();
    assert!(err.contains("Robot3_Odometry.dat:5:"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn mrclam_json_has_every_object_and_the_overall_summary() {
    let Some(dir) = mrclam_dir() else {
        return;
    };
    let out = lplace()
        .args(["fuse", "--until", "120", "--format", "json", "--from-dir"])
        .arg(&dir)
        .assert()
        .success();
    let v: serde_json::Value = serde_json::from_slice(&out.get_output().stdout).unwrap();
    assert_eq!(v["per_object"].as_array().unwrap().len(), 5);
    assert!(v["overall"]["events"].as_u64().unwrap() > 0);
    assert!(v.get("events").is_none());
    let out = lplace()
        .args([
            "fuse", "--until", "120", "--object", "4", "--format", "json", "--events",
        ])
        .arg("--from-dir")
        .arg(&dir)
        .assert()
        .success();
    let v: serde_json::Value = serde_json::from_slice(&out.get_output().stdout).unwrap();
    assert_eq!(v["per_object"].as_array().unwrap().len(), 1);
    assert_eq!(v["per_object"][0]["object"], 4);
    assert!(v["events"]
        .as_array()
        .unwrap()
        .iter()
        .all(|e| e["object"] == 4));
    // The table form prints the same run.
    let out = lplace()
        .args(["fuse", "--until", "120", "--object", "4", "--from-dir"])
        .arg(&dir)
        .assert()
        .success();
    let text = String::from_utf8(out.get_output().stdout.clone()).unwrap();
    assert!(
        text.starts_with("| object |") && text.contains("| robot 4 |"),
        "{text}"
    );
}
