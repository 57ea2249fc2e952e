//! The pictures of `lplace eval` checked by structure, not by copy: each SVG is well formed
//! (every element closed, in order), the run display has a legend with a swatch per mark and
//! readable truth bands, the trajectory has a metre scale bar, the stream's file name as its
//! title, and place labels that do not overlap even for places a few centimetres apart.

use crate::support::lplace;
use std::path::PathBuf;

fn temp(name: &str, text: &str) -> PathBuf {
    let p = std::env::temp_dir().join(format!("lplace-cli-pic-{}-{name}", std::process::id()));
    std::fs::write(&p, text).expect("temp file is writable");
    p
}

/// The elements of an SVG as (name, attributes text, content up to the next tag); panics unless
/// every start tag is closed by its end tag in order (or is self-closing).
fn elements(svg: &str) -> Vec<(String, String, String)> {
    let mut open: Vec<String> = Vec::new();
    let mut out = Vec::new();
    let mut rest = svg.trim();
    assert!(rest.starts_with("<svg"), "not an SVG document");
    while let Some(lt) = rest.find('<') {
        let gt = rest[lt..].find('>').expect("every tag is closed by `>`") + lt;
        let tag = &rest[lt + 1..gt];
        let after = &rest[gt + 1..];
        let content = after.split('<').next().unwrap_or("").to_string();
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(
                open.pop().as_deref(),
                Some(name.trim()),
                "mismatched </{name}>"
            );
        } else {
            let name: String = tag
                .chars()
                .take_while(|c| !c.is_whitespace() && *c != '/')
                .collect();
            assert!(!name.is_empty(), "empty tag");
            out.push((name.clone(), tag.to_string(), content));
            if !tag.ends_with('/') {
                open.push(name);
            }
        }
        rest = after;
    }
    assert!(open.is_empty(), "unclosed elements: {open:?}");
    assert!(rest.trim().is_empty(), "text after the root element");
    out
}

/// The value of attribute `name` in a tag's text.
fn attr(tag: &str, name: &str) -> Option<f64> {
    let key = format!(" {name}=\"");
    let at = tag.find(&key)? + key.len();
    tag[at..].split('"').next()?.parse().ok()
}

/// The robot at P1 of the office, with a true pose (see cli_eval's AT_P1 for the degrees).
const AT_P1: &str = r#"{"version":1,"t":0.0,"percepts":[{"name":"beacon_angle","value":167.0,"degree":0.9},{"name":"beacon_distance","value":4.5,"degree":0.8},{"name":"sonar_wall","args":["North"],"degree":0.9},{"name":"laser_wall","args":["West"],"degree":0.8}],"truth":{"place":"P1","pose":[0.5,3.5,0.0]}}"#;

#[test]
fn run_display_has_a_legend_with_swatches_and_truth_bands() {
    let s = temp("plot.jsonl", &format!("{AT_P1}\n{AT_P1}\n"));
    let out = temp("plot.svg", "");
    lplace()
        .arg("eval")
        .arg(&s)
        .arg("--svg")
        .arg(&out)
        .args(["--only-summary", "--summary", "none"])
        .assert()
        .success();
    let svg = std::fs::read_to_string(&out).expect("SVG written");
    let els = elements(&svg);
    let swatches = els
        .iter()
        .filter(|(n, t, _)| n == "rect" && t.contains("class=\"swatch\""))
        .count();
    assert_eq!(swatches, 4, "Π, N, chosen, truth");
    for word in ["Π (possibility)", "N (necessity)", "chosen", "truth"] {
        assert!(
            els.iter().any(|(n, _, c)| n == "text" && c == word),
            "legend: {word}"
        );
    }
    // The truth is P1 in both frames: one band as tall as the row's strips (not a 2-px tick).
    let bands: Vec<&String> = els
        .iter()
        .filter(|(n, t, _)| n == "rect" && t.contains("fill=\"#d62728\"") && !t.contains("swatch"))
        .map(|(_, t, _)| t)
        .collect();
    assert_eq!(bands.len(), 1, "{bands:?}");
    assert!(
        attr(bands[0], "height").unwrap_or(0.0) >= 20.0,
        "{}",
        bands[0]
    );
    // The title names the stream by its file name, not the scratch folder it lies in.
    let title = &els.iter().find(|(n, _, _)| n == "text").expect("a title").2;
    assert!(title.ends_with("plot.jsonl"), "{title}");
    assert!(!title.contains('/') && !title.contains('\\'), "{title}");
}

/// Label boxes as the picture's 11-px font sets them (at most 7 px a character, a line 12 px).
fn label_boxes(els: &[(String, String, String)]) -> Vec<(String, f64, f64, f64)> {
    els.iter()
        .filter(|(n, t, _)| n == "text" && t.contains("class=\"place-label\""))
        .map(|(_, t, c)| {
            let half = 3.5 * c.chars().count() as f64;
            (
                c.clone(),
                attr(t, "x").expect("x"),
                attr(t, "y").expect("y"),
                half,
            )
        })
        .collect()
}

#[test]
fn trajectory_has_scale_bar_title_and_separate_labels() {
    let root = env!("CARGO_MANIFEST_DIR");
    let office = std::fs::read_to_string(format!("{root}/maps/office.map")).expect("office map");
    // P4 moved 5 cm from P3: their labels would print on top of each other.
    let moved = office.replace(
        "place P4 doorway in R1 at (5.5, 2.0)",
        "place P4 doorway in R1 at (4.55, 2.0)",
    );
    assert_ne!(moved, office, "the office map still has P4 at (5.5, 2.0)");
    let map = temp("close.map", &moved);
    let s = temp("walk.jsonl", &format!("{AT_P1}\n"));
    let out = temp("walk.svg", "");
    lplace()
        .arg("eval")
        .arg(&s)
        .arg("--map")
        .arg(&map)
        .args(["--rules", &format!("{root}/rules/office.lpl")])
        .arg("--trajectory-svg")
        .arg(&out)
        .args(["--only-summary", "--summary", "none"])
        .assert()
        .success();
    let svg = std::fs::read_to_string(&out).expect("SVG written");
    let els = elements(&svg);
    let title = &els.iter().find(|(n, _, _)| n == "text").expect("a title").2;
    assert!(
        title.ends_with("walk.jsonl: decisions along the true trajectory"),
        "{title}"
    );
    assert!(!title.contains('/') && !title.contains('\\'), "{title}");
    // The office's places span 10.2 m, 12.2 m with the margins: at 20 px/m, a 2 m bar (the
    // longest 1-2-5 length under a fifth of that) of 40 px, labelled.
    let g = els
        .iter()
        .position(|(n, t, _)| n == "g" && t.contains("class=\"scale-bar\""))
        .expect("a scale bar");
    let line = &els[g + 1];
    assert_eq!(line.0, "line");
    let len = attr(&line.1, "x2").unwrap_or(0.0) - attr(&line.1, "x1").unwrap_or(0.0);
    assert!((len - 40.0).abs() < 0.5, "bar {len} px");
    assert!(els.iter().any(|(n, _, c)| n == "text" && c == "2 m"));
    let labels = label_boxes(&els);
    assert_eq!(labels.len(), 8);
    for (i, a) in labels.iter().enumerate() {
        for b in &labels[i + 1..] {
            let apart = (a.1 - b.1).abs() >= a.3 + b.3 || (a.2 - b.2).abs() >= 11.0;
            assert!(apart, "labels {} and {} overlap: {a:?} {b:?}", a.0, b.0);
        }
    }
}
