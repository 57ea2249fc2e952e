//! The command line's conventions (issue 21, issue 16 rows 8–10): outputs checked before any
//! work, never over an input, written atomically, with the right verb; one spelling per idea
//! with the old ones noted; batch evaluation; completions, man page and `LPLACE_DATA`.

use crate::support::{lplace, scratch};
use std::path::Path;

/// The robot at P1 of the office, truth P1: decided P1 with N = 0.608 (worked by hand in
/// `cli_eval.rs`, `AT_P1`).
const AT_P1: &str = r#"{"version":1,"t":0.0,"percepts":[{"name":"beacon_angle","value":167.0,"degree":0.9},{"name":"beacon_distance","value":4.5,"degree":0.8},{"name":"sonar_wall","args":["North"],"degree":0.9},{"name":"laser_wall","args":["West"],"degree":0.8}],"truth":{"place":"P1"}}"#;

/// No percepts, truth between places: disoriented (every α = 0, N = 0).
const EMPTY: &str = r#"{"version":1,"t":0.1,"percepts":[],"truth":{"place":null}}"#;

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("scratch is writable");
    p
}

fn stderr_of(out: &std::process::Output) -> String {
    // Paths of this machine's scratch folder vary; messages are compared without them.
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn an_output_over_an_input_is_refused_and_the_input_kept() {
    let d = scratch("conventions", "over-input");
    let s = write(&d, "s.jsonl", &format!("{AT_P1}\n"));
    // The same file through another spelling (`dir/../dir/s.jsonl`) is still the input.
    let other = d.join("..").join("over-input").join("s.jsonl");
    for (flag, path) in [("--svg", &s), ("--trajectory-svg", &other), ("-o", &s)] {
        let out = lplace()
            .arg("eval")
            .arg(&s)
            .arg(flag)
            .arg(path)
            .output()
            .expect("runs");
        assert_eq!(out.status.code(), Some(2), "{flag}");
        let err = stderr_of(&out);
        assert!(
            err.contains("it is an input of this command (STREAM)"),
            "{err}"
        );
        assert!(
            out.stdout.is_empty(),
            "no decision printed before the check"
        );
        assert_eq!(
            std::fs::read_to_string(&s).expect("kept"),
            format!("{AT_P1}\n")
        );
    }
    // simulate -o over its own --map.
    let map = d.join("office.map");
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("maps/office.map"),
        &map,
    )
    .expect("copies");
    let before = std::fs::read(&map).expect("reads");
    let out = lplace()
        .args(["simulate", "--steps", "5", "--map"])
        .arg(&map)
        .arg("-o")
        .arg(&map)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr_of(&out).contains("(--map); refusing to write over it"));
    assert_eq!(std::fs::read(&map).expect("reads"), before);
}

#[test]
fn output_paths_are_checked_before_any_work_with_the_right_verb() {
    let out = lplace()
        .args(["simulate", "-o", "nodir/x.jsonl"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    insta::assert_snapshot!("simulate_no_folder", stderr_of(&out));
    // eval over the bundled recording: refused before the first decision is printed.
    let out = lplace()
        .args(["eval", "--svg", "nodir/p.svg"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    insta::assert_snapshot!("eval_no_folder", stderr_of(&out));
    let out = lplace()
        .args(["eval", "--svg", "src"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr_of(&out).contains("cannot write `src` (--svg): it is a folder"));
}

#[test]
fn outputs_replace_existing_files_whole() {
    let d = scratch("conventions", "replace");
    let target = write(&d, "x.jsonl", "old contents that are longer than nothing\n");
    let args = ["simulate", "--steps", "20", "--seed", "3"];
    let stdout = lplace().args(args).output().expect("runs").stdout;
    lplace()
        .args(args)
        .arg("-o")
        .arg(&target)
        .assert()
        .success();
    assert_eq!(std::fs::read(&target).expect("written"), stdout);
    let left: Vec<_> = std::fs::read_dir(&d).expect("lists").collect();
    assert_eq!(left.len(), 1, "no temporary file left beside the output");
    // eval -o: the decisions that would go to stdout, in the file.
    let s = write(&d, "s.jsonl", &format!("{AT_P1}\n{EMPTY}\n"));
    let o = d.join("decisions.jsonl");
    let printed = lplace()
        .arg("eval")
        .arg(&s)
        .args(["--summary", "none"])
        .output()
        .expect("runs")
        .stdout;
    let quiet = lplace()
        .arg("eval")
        .arg(&s)
        .args(["--summary", "none", "-o"])
        .arg(&o)
        .output()
        .expect("runs");
    assert!(quiet.status.success());
    assert!(quiet.stdout.is_empty());
    assert_eq!(std::fs::read(&o).expect("written"), printed);
}

#[test]
fn old_spellings_still_work_with_a_note() {
    let d = scratch("conventions", "old-spellings");
    let (old, new) = (d.join("old.svg"), d.join("new.svg"));
    let out = lplace()
        .args(["eval", "--only-summary", "--summary", "none", "--plot"])
        .arg(&old)
        .output()
        .expect("runs");
    assert!(out.status.success());
    assert!(stderr_of(&out).contains("note: --plot is deprecated: use --svg FILE"));
    let out = lplace()
        .args(["eval", "--only-summary", "--summary", "none", "--svg"])
        .arg(&new)
        .output()
        .expect("runs");
    assert!(out.status.success());
    assert!(out.stderr.is_empty(), "no note for the new spelling");
    assert_eq!(
        std::fs::read(&old).expect("drawn"),
        std::fs::read(&new).expect("drawn")
    );
    // grid --json: the note comes first, whatever happens next (here: no such stream).
    let out = lplace()
        .args(["grid", "no-such-stream.jsonl", "--json"])
        .output()
        .expect("runs");
    assert!(stderr_of(&out).starts_with("note: --json is deprecated: use --format json"));
    let out = lplace()
        .args(["grid", "no-such-stream.jsonl", "--json", "--format", "json"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2), "one spelling at a time");
}

/// Two streams in a folder, counted by hand: `a` is AT_P1 (truth P1, decided P1, N 0.608 <
/// 0.9 so not confidently wrong); `b` is EMPTY (truth between places, disoriented) and a line
/// that is not JSON (rejected). Total: 2 frames, 1 decided, 1 rejected, 1 at a place, 1
/// correct: accuracy 1.
#[test]
fn batch_over_a_folder_prints_a_row_per_stream_and_a_total() {
    let d = scratch("conventions", "batch");
    write(&d, "a.jsonl", &format!("{AT_P1}\n"));
    write(&d, "b.jsonl", &format!("{EMPTY}\nnot json\n"));
    write(&d, "notes.txt", "not a stream\n");
    let out = lplace()
        .arg("eval")
        .arg(&d)
        .args(["--no-track", "--format", "csv"])
        .output()
        .expect("runs");
    assert_eq!(
        out.status.code(),
        Some(3),
        "a rejected record anywhere: exit 3"
    );
    let text = String::from_utf8(out.stdout.clone()).expect("utf-8");
    let a = d.join("a.jsonl").display().to_string();
    let b = d.join("b.jsonl").display().to_string();
    assert_eq!(
        text,
        format!(
            "stream,frames,decided,rejected,at_place,correct,wrong,confidently_wrong,accuracy,wrong_rate\n\
             {a},1,1,0,1,1,0,0,1,0\n\
             {b},1,0,1,0,0,0,0,,\n\
             total,2,1,1,1,1,0,0,1,0\n"
        )
    );
    assert!(
        stderr_of(&out).contains("b.jsonl:2:"),
        "the rejected line is reported"
    );
    // The same two files named one by one give the same rows.
    let named = lplace()
        .arg("eval")
        .arg(d.join("a.jsonl"))
        .arg(d.join("b.jsonl"))
        .args(["--no-track", "--format", "csv"])
        .output()
        .expect("runs");
    assert_eq!(String::from_utf8(named.stdout).expect("utf-8"), text);
    // Per-frame pictures make no sense over several streams.
    let out = lplace()
        .arg("eval")
        .arg(&d)
        .args(["--svg", "x.svg"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr_of(&out).contains("--svg is about one stream's frames"));
}

#[test]
fn streams_are_found_under_lplace_data() {
    let d = scratch("conventions", "data");
    write(&d, "run.jsonl", &format!("{AT_P1}\n"));
    let out = lplace()
        .env("LPLACE_DATA", &d)
        .args(["eval", "run.jsonl", "--no-track", "--summary", "none"])
        .output()
        .expect("runs");
    assert!(out.status.success(), "{}", stderr_of(&out));
    assert!(String::from_utf8_lossy(&out.stdout).contains(r#""place":"P1""#));
}

#[test]
fn completions_and_man_page() {
    for shell in ["bash", "zsh", "fish", "elvish", "powershell"] {
        let out = lplace()
            .args(["completions", shell])
            .output()
            .expect("runs");
        assert!(out.status.success(), "{shell}");
        let text = String::from_utf8_lossy(&out.stdout);
        for word in ["eval", "compare", "trajectory-svg"] {
            assert!(text.contains(word), "{shell} completes {word}");
        }
    }
    let out = lplace().arg("man").output().expect("runs");
    assert!(out.status.success());
    let page = String::from_utf8_lossy(&out.stdout);
    assert!(page.contains(".TH lplace 1"));
    for sub in ["CHECK", "EVAL", "COMPARE", "FUSE"] {
        assert!(page.contains(&format!(".SH \"LPLACE {sub}\"")), "{sub}");
    }
    let out = lplace()
        .args(["completions", "tcsh"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn eval_help() {
    let out = lplace().args(["eval", "--help"]).output().expect("runs");
    assert!(out.status.success());
    insta::assert_snapshot!("eval_help", String::from_utf8_lossy(&out.stdout));
}

#[test]
fn check_never_calls_a_file_ok_and_then_blames_it() {
    let d = scratch("conventions", "check");
    let office = lplace::engine::OFFICE_MAP;
    // A wall direction the office rules' `Dir` domain does not have: the map parses, the
    // rules then find the problem in it.
    let bad = office.replacen("wall South; wall West;", "wall Sud; wall West;", 1);
    assert_ne!(bad, office);
    let map = write(&d, "bad2.map", &bad);
    let out = lplace()
        .arg("check")
        .arg(&map)
        .arg("rules/office.lpl")
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(!stdout.contains("bad2.map: ok"), "{stdout}");
    assert!(stderr_of(&out).contains("Sud"), "{}", stderr_of(&out));
    // Clean files: maps first, then rules, in that order; no note when the map is given.
    let out = lplace()
        .args(["check", "maps/office.map", "rules/office.lpl"])
        .output()
        .expect("runs");
    assert!(out.status.success());
    let stdout = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    assert!(lines[0].starts_with("maps/office.map: ok ("));
    assert!(lines[1].starts_with("rules/office.lpl: ok ("));
    assert!(out.stderr.is_empty());
    // Rules alone: checked against the bundled map, and said so.
    let out = lplace()
        .args(["check", "rules/office.lpl"])
        .output()
        .expect("runs");
    assert!(out.status.success());
    assert!(stderr_of(&out)
        .contains("note: no map given: checking the rules against the bundled office map"));
}

#[test]
fn kidnap_by_is_one_comma_separated_value() {
    let out = lplace().args(["grid", "--help"]).output().expect("runs");
    let help = String::from_utf8_lossy(&out.stdout);
    assert_eq!(help.matches("<DX,DY,DTHETA>").count(), 1, "{help}");
    assert!(!help.contains("85.94366926962348"), "{help}");
    assert!(help.contains("Default: 0,2,85.94 (1.5 rad)"), "{help}");
    // Parsed (the run then stops at the missing stream, exit 1, not a usage error).
    for value in ["0,1,45", "-1,0,-30"] {
        let out = lplace()
            .args(["grid", "no-such-stream.jsonl", "--kidnap-by", value])
            .output()
            .expect("runs");
        assert_eq!(out.status.code(), Some(1), "{value}: {}", stderr_of(&out));
        assert!(stderr_of(&out).contains("cannot read `no-such-stream.jsonl`"));
    }
}

/// A map with no corners is a map, not an error of the rules: the office rules that test
/// corners never fire on it, which `check` says as warnings (exit 0) located at those rules and
/// pointing at the map, and `eval` runs on it.
#[test]
fn a_map_without_corners_warns_and_runs() {
    let d = scratch("conventions", "no_corners");
    let office = lplace::engine::OFFICE_MAP;
    // Every `wall D;` and `corner A B;` statement removed: no place has a wall or a corner.
    let is_feature = |st: &str| {
        let t = st.trim_start();
        t.starts_with("wall ") || t.starts_with("corner ")
    };
    let plain: String = office
        .lines()
        .map(|l| {
            if l.contains("//") || !l.split(';').any(is_feature) {
                return l.to_string();
            }
            l.split(';')
                .filter(|st| !is_feature(st))
                .collect::<Vec<_>>()
                .join(";")
        })
        .collect::<Vec<_>>()
        .join("\n");
    assert!(
        !plain
            .lines()
            .any(|l| !l.contains("//") && l.split(';').any(is_feature)),
        "{plain}"
    );
    let map = write(&d, "plain.map", &plain);
    let out = lplace()
        .arg("check")
        .arg(&map)
        .arg("rules/office.lpl")
        .output()
        .expect("runs");
    let err = stderr_of(&out);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(!err.contains("error"), "{err}");
    // The rules that need a corner or a wall at the place: the corner derivation and the two
    // place rules built on corners and walls, found here from the rule file's text.
    let rules = lplace::engine::OFFICE_RULES;
    let corner_rule = 1 + rules
        .lines()
        .position(|l| l.trim_start().starts_with("|- ((sonar_wall(p1, d1, t)"))
        .expect("the corner rule");
    assert!(
        err.contains(&format!("rules/office.lpl:{corner_rule}:1")),
        "{err}"
    );
    assert!(err.contains("warning"), "{err}");
    assert!(err.contains("describe in the map"), "{err}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("warning(s) about this map"), "{stdout}");
    lplace()
        .arg("eval")
        .arg("--map")
        .arg(&map)
        .args([
            "--rules",
            "rules/office.lpl",
            "--no-track",
            "--summary",
            "none",
        ])
        .assert()
        .success();
}

/// A place without the parameters the rules read at the other places is accepted (a survey may
/// leave one unvisited) but named, as a warning located at the place in the map.
#[test]
fn a_place_without_the_rules_parameters_is_named() {
    let d = scratch("conventions", "lacks_params");
    let office = lplace::engine::OFFICE_MAP;
    let line = "param A = 116.6; param L = 1.12;";
    assert_eq!(office.matches(line).count(), 1, "P2's beacon signature");
    let map = write(&d, "np.map", &office.replacen(line, "", 1));
    let out = lplace()
        .arg("check")
        .arg(&map)
        .arg("rules/office.lpl")
        .output()
        .expect("runs");
    let err = stderr_of(&out);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let p2 = 1 + office
        .lines()
        .position(|l| l.starts_with("place P2 "))
        .expect("P2");
    assert!(err.contains(&format!("np.map:{p2}:1")), "{err}");
    assert!(err.contains("place `P2` has no A, L"), "{err}");
    // One warning: the other places have both.
    assert_eq!(err.matches("has no").count(), 1, "{err}");
    // The bundled map has every parameter at every place: nothing to say.
    let out = lplace()
        .args(["check", "maps/office.map", "rules/office.lpl"])
        .output()
        .expect("runs");
    assert!(out.stderr.is_empty(), "{}", stderr_of(&out));
}
