//! The pictures of `lplace eval` checked by structure, not by copy: each SVG is well formed
//! (every element closed, in order), the run display has a legend with a swatch per mark and
//! readable truth bands, the trajectory has a metre scale bar, the stream's file name as its
//! title, and place labels that do not overlap even for places a few centimetres apart.

use crate::support::{landmarks, lplace};
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

/// `(x, y)` of each `landmark … at (x, y) id N` line of a map text, in id order.
fn map_landmarks(map: &str) -> Vec<(f64, f64)> {
    let mut out: Vec<(u32, f64, f64)> = map
        .lines()
        .filter_map(|l| {
            let l = l.trim().strip_prefix("landmark ")?;
            let (at, id) = l.split_once(") id ")?;
            let (x, y) = at.split_once("at (")?.1.split_once(',')?;
            Some((
                id.trim_end_matches(';').trim().parse().ok()?,
                x.trim().parse().ok()?,
                y.trim().parse().ok()?,
            ))
        })
        .collect();
    out.sort_by_key(|m| m.0);
    out.into_iter().map(|(_, x, y)| (x, y)).collect()
}

/// The `viewBox="0 0 W H"` of an SVG's root element.
fn view_box(els: &[(String, String, String)]) -> (f64, f64) {
    let root = &els[0].1;
    let vb = root.split("viewBox=\"").nth(1).expect("a viewBox");
    let n: Vec<f64> = vb
        .split('"')
        .next()
        .unwrap_or("")
        .split_whitespace()
        .map(|v| v.parse().expect("a number"))
        .collect();
    assert_eq!(&n[..2], &[0.0, 0.0], "{root}");
    (n[2], n[3])
}

/// A linear map value → pixel fitted through the axis's tick labels: each label (class `cls`)
/// follows its tick mark, a line whose `coord` (x1 or y1) is the value's position. Every label
/// is checked to lie on the fitted line, so the ticks are evenly spaced in metres.
fn axis_fit(els: &[(String, String, String)], cls: &str, coord: &str) -> (f64, f64) {
    let ticks: Vec<(f64, f64)> = els
        .windows(2)
        .filter(|w| w[1].0 == "text" && w[1].1.contains(&format!("class=\"{cls}\"")))
        .map(|w| {
            assert_eq!(w[0].0, "line", "a tick mark before {}", w[1].2);
            let v: f64 = w[1].2.parse().expect("a tick label is a number of metres");
            (v, attr(&w[0].1, coord).expect("tick position"))
        })
        .collect();
    assert!(ticks.len() >= 2, "{cls}: {ticks:?}");
    let (a, b) = (ticks[0], ticks[ticks.len() - 1]);
    let k = (b.1 - a.1) / (b.0 - a.0);
    for t in &ticks {
        assert!(
            (a.1 + k * (t.0 - a.0) - t.1).abs() < 0.2,
            "{cls}: {ticks:?}"
        );
    }
    (k, a.1 - k * a.0)
}

/// The elements from the `<g class="{cls}">` start tag to the next `<g>`.
fn group<'a>(els: &'a [(String, String, String)], cls: &str) -> &'a [(String, String, String)] {
    let at = els
        .iter()
        .position(|(n, t, _)| n == "g" && t.contains(&format!("class=\"{cls}\"")))
        .unwrap_or_else(|| panic!("a group of class {cls}"));
    let end = els[at + 1..]
        .iter()
        .position(|(n, _, _)| n == "g")
        .map_or(els.len(), |e| at + 1 + e);
    &els[at + 1..end]
}

/// Checks one `lplace grid --svg` picture drawn over `marks` (metres, id order): metre axes
/// that agree with where the landmarks are drawn, a legend with the possibility scale and
/// every mark, a scale bar as long as it says, and every belief cell and landmark inside the
/// viewBox.
fn check_grid_picture(svg: &str, marks: &[(f64, f64)]) {
    let els = elements(svg);
    let (w, h) = view_box(&els);
    let inside =
        |x: f64, y: f64| (-0.01..=w + 0.01).contains(&x) && (-0.01..=h + 0.01).contains(&y);
    let (kx, bx) = axis_fit(&els, "x-tick", "x1");
    let (ky, by) = axis_fit(&els, "y-tick", "y1");
    // Metres are square on the page, y up.
    assert!(kx > 0.0 && (ky + kx).abs() < 0.01 * kx, "{kx} {ky}");
    let dots: Vec<(f64, f64, f64)> = els
        .iter()
        .filter(|(n, t, _)| n == "circle" && t.contains("class=\"landmark\""))
        .map(|(_, t, _)| {
            (
                attr(t, "cx").unwrap(),
                attr(t, "cy").unwrap(),
                attr(t, "r").unwrap(),
            )
        })
        .collect();
    assert_eq!(dots.len(), marks.len());
    for (&(x, y), &(cx, cy, r)) in marks.iter().zip(&dots) {
        assert!(
            (kx * x + bx - cx).abs() < 0.2 && (ky * y + by - cy).abs() < 0.2,
            "{x},{y}"
        );
        assert!(
            inside(cx - r, cy - r) && inside(cx + r, cy + r),
            "landmark {x},{y} clipped"
        );
    }
    let cells: Vec<&(String, String, String)> = group(&els, "belief")
        .iter()
        .filter(|e| e.0 == "rect")
        .collect();
    assert!(!cells.is_empty(), "no belief drawn");
    for (_, t, _) in cells
        .iter()
        .copied()
        .chain(els.iter().filter(|e| e.1.contains("class=\"extent\"")))
    {
        let (x, y) = (attr(t, "x").unwrap(), attr(t, "y").unwrap());
        let (cw, ch) = (attr(t, "width").unwrap(), attr(t, "height").unwrap());
        assert!(inside(x, y) && inside(x + cw, y + ch), "clipped: {t}");
    }
    let legend = group(&els, "legend");
    let ramp: Vec<f64> = legend
        .iter()
        .filter(|(n, t, _)| n == "rect" && t.contains("class=\"swatch\""))
        .map(|(_, t, _)| attr(t, "fill-opacity").unwrap())
        .collect();
    assert!(
        ramp.len() >= 5 && ramp.windows(2).all(|p| p[0] < p[1]),
        "{ramp:?}"
    );
    let words: Vec<&str> = els
        .iter()
        .filter(|e| e.0 == "text")
        .map(|e| e.2.as_str())
        .collect();
    for word in ["0", "1", "landmark (id)", "estimate", "x [m]", "y [m]"] {
        assert!(words.contains(&word), "no text {word}");
    }
    let bar = group(&els, "scale-bar");
    let len = attr(&bar[0].1, "x2").unwrap() - attr(&bar[0].1, "x1").unwrap();
    let label = els
        .iter()
        .skip_while(|(n, t, _)| !(n == "g" && t.contains("scale-bar")))
        .find(|e| e.0 == "text")
        .expect("the bar's label");
    let metres: f64 = label.2.trim_end_matches(" m").parse().expect("N m");
    assert!(
        (len - metres * kx).abs() < 0.5,
        "bar {len} px for {metres} m"
    );
}

#[test]
fn grid_frames_have_metre_axes_a_legend_and_nothing_clipped() {
    let d = crate::support::scratch("cli_pictures", "grid");
    let map = d.join("tiny.map");
    std::fs::write(&map, landmarks::tiny_map(true)).unwrap();
    let lines: Vec<String> = (0..5)
        .map(|k| landmarks::frame_at(k as f64 * 1.5, (1.0, 1.0)))
        .collect();
    let stream = d.join("s.jsonl");
    std::fs::write(&stream, lines.join("\n") + "\n").unwrap();
    // A grid smaller than the landmarks' spread: they must still be drawn, not clipped.
    let config = d.join("small.ron");
    std::fs::write(&config, "(bounds: Some((0.5, 0.5, 2.0, 1.5)))\n").unwrap();
    for (name, extra) in [("default", None), ("small", Some(&config))] {
        let svg = d.join(name);
        let mut cmd = lplace();
        cmd.arg("grid")
            .arg("--map")
            .arg(&map)
            .arg(&stream)
            .arg("--svg")
            .arg(&svg);
        if let Some(c) = extra {
            cmd.arg("--config").arg(c);
        }
        cmd.assert().success();
        // The first picture is of the first frame at least 0.5 s after the first: t = 1.5 s.
        let first = std::fs::read_to_string(svg.join("grid-000.svg")).expect("a picture");
        let els = elements(&first);
        let title = els
            .iter()
            .find(|e| e.1.contains("class=\"title\""))
            .expect("a title");
        assert!(title.2.contains("t = 1.5 s"), "{}", title.2);
        assert!(
            els.iter().any(|e| e.2 == "data set grid, stream s.jsonl"),
            "the input is named: {first}"
        );
        assert!(
            els.iter().any(|e| e.2 == "true pose"),
            "the stream has truth"
        );
        for f in std::fs::read_dir(&svg).unwrap() {
            let text = std::fs::read_to_string(f.unwrap().path()).unwrap();
            check_grid_picture(&text, &map_landmarks(&landmarks::tiny_map(true)));
        }
    }
}

#[test]
fn mrclam_robot1_grid_pictures_are_readable() {
    let Some(dir) = crate::support::mrclam_dir() else {
        return;
    };
    let d = crate::support::scratch("cli_pictures", "mrclam_grid");
    let svg = d.join("svg");
    lplace()
        .arg("grid")
        .arg("--from-dir")
        .arg(&dir)
        .args(["--robot", "1"])
        .arg("--svg")
        .arg(&svg)
        .assert()
        .success();
    let root = env!("CARGO_MANIFEST_DIR");
    let map = std::fs::read_to_string(format!("{root}/maps/mrclam.map")).expect("bundled map");
    let marks = map_landmarks(&map);
    assert!(marks.len() >= 10, "{marks:?}");
    let set = dir.file_name().unwrap().to_string_lossy().into_owned();
    let mut drawn = 0;
    for f in std::fs::read_dir(&svg).unwrap() {
        let text = std::fs::read_to_string(f.unwrap().path()).unwrap();
        check_grid_picture(&text, &marks);
        let what = format!(">data set {set}, robot 1<");
        assert!(text.contains(&what), "{what} is not a heading");
        drawn += 1;
    }
    assert_eq!(drawn, 6, "one picture per time of `--svg`");
}

/// The y tick values of a sweep picture and its title.
fn sweep_axis(svg: &str) -> (Vec<f64>, String) {
    let els = elements(svg);
    let ticks = els
        .iter()
        .filter(|(n, t, _)| n == "text" && t.contains("class=\"y-tick\""))
        .map(|e| e.2.parse().expect("a tick label is a number"))
        .collect();
    let title = els
        .iter()
        .find(|e| e.1.contains("class=\"title\""))
        .map(|e| e.2.clone())
        .expect("a title");
    (ticks, title)
}

/// Checks that the y ticks cover `values` and, when the values are far from 0 (the largest at
/// most twice the smallest), that the axis starts at no less than half the smallest.
fn check_sweep_axis(ticks: &[f64], values: &[f64]) {
    let lo = ticks.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = ticks.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert!(!values.is_empty());
    assert!(lo <= min && hi >= max, "axis {lo}..{hi}, data {min}..{max}");
    if max <= 2.0 * min {
        assert!(lo >= 0.5 * min, "axis from {lo} for data from {min}");
    }
}

/// The ATE RMSE column of `lplace compare --format csv`'s sweep rows (the plotted values).
fn sweep_values(csv: &str) -> Vec<f64> {
    let header: Vec<&str> = csv.lines().next().unwrap_or("").split(',').collect();
    let col = header
        .iter()
        .position(|c| *c == "ate_rmse_m")
        .expect("an ate_rmse_m column");
    csv.lines()
        .skip(1)
        .filter(|l| !l.split(',').nth(1).is_some_and(|s| s == "main"))
        .filter_map(|l| l.split(',').nth(col)?.parse().ok())
        .collect()
}

#[test]
fn sweep_axis_fits_the_data_and_the_title_names_the_data_set() {
    let d = crate::support::scratch("cli_pictures", "set-west");
    let map = d.join("tiny.map");
    std::fs::write(&map, landmarks::tiny_map(true)).unwrap();
    // The truth half a metre east of where the readings put the robot: every error is about
    // 0.5 m, far from 0.
    let lines: Vec<String> = (0..12)
        .map(|k| landmarks::frame_at(k as f64, (1.5, 1.0)))
        .collect();
    let stream = d.join("robot9.jsonl");
    std::fs::write(&stream, lines.join("\n") + "\n").unwrap();
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
    let values = sweep_values(&String::from_utf8(csv).unwrap());
    assert!(values.iter().all(|v| *v > 0.3), "{values:?}");
    let (ticks, title) = sweep_axis(&std::fs::read_to_string(&svg).unwrap());
    check_sweep_axis(&ticks, &values);
    assert!(
        title.contains("set-west") && title.contains("robot9.jsonl"),
        "{title}"
    );
    assert!(!title.contains('/') && !title.contains('\\'), "{title}");
}

#[test]
fn mrclam_robot1_sweep_names_data_set_and_robot() {
    let Some(dir) = crate::support::mrclam_dir() else {
        return;
    };
    let d = crate::support::scratch("cli_pictures", "mrclam_sweep");
    let svg = d.join("sweep.svg");
    let csv = lplace()
        .arg("compare")
        .arg("--from-dir")
        .arg(&dir)
        .args(["--robot", "1", "--methods", "fpg", "--format", "csv"])
        .args(["--sweep", "sparsity", "--svg"])
        .arg(&svg)
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let values = sweep_values(&String::from_utf8(csv).unwrap());
    let (ticks, title) = sweep_axis(&std::fs::read_to_string(&svg).unwrap());
    check_sweep_axis(&ticks, &values);
    let set = dir.file_name().unwrap().to_string_lossy().into_owned();
    assert!(title.contains(&set) && title.contains("robot 1"), "{title}");
}

/// A CARMEN log of a robot at `(x, 0)`, x = 0, 1, 2, facing +x, whose 180 beams all read 2 m
/// (a round room around each pose), then a FLASER line cut short.
fn round_room_log() -> String {
    let mut log = String::from("PARAM robot_frontlaser_offset 0.0 nohost 0\n");
    for k in 0..3 {
        let ranges = vec!["2.0"; 180].join(" ");
        log.push_str(&format!(
            "FLASER 180 {ranges} {k}.0 0.0 0.0 {k}.0 0.0 0.0 {k}.5 host {k}.5\n"
        ));
    }
    log.push_str("FLASER 180 1.0 2.0\n");
    log
}

#[test]
fn draw_pictures_a_log_with_its_places_and_reports_bad_lines() {
    let log = temp("room.log", &round_room_log());
    let map = temp(
        "room.map",
        "map m; place A corridor at (1, 0) extent box (0, -1, 2, 1); \
         place B corridor at (4, 0) extent box (3, -1, 5, 1) rotated 30; path A -- B;",
    );
    let svg = log.with_extension("svg");
    let out = lplace()
        .args(["draw"])
        .arg(&log)
        .arg("--map")
        .arg(&map)
        .arg("-o")
        .arg(&svg)
        .arg("--min-hits")
        .arg("1")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    // The short line is reported with its number and skipped; the three scans are drawn.
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(err.contains("line 5"), "{err}");
    assert!(err.contains("3 of 3 scan(s) drawn"), "{err}");
    let text = std::fs::read_to_string(&svg).unwrap();
    let els = elements(&text);
    // One rectangle per run of cells: the three circles of radius 2 cross rows many times,
    // each run at most one circle's width.
    let hits: Vec<&(String, String, String)> = els
        .iter()
        .skip_while(|e| !e.1.contains("class=\"hits\""))
        .skip(1)
        .take_while(|e| e.0 == "rect")
        .collect();
    assert!(hits.len() > 20, "{} hit rectangles", hits.len());
    let width = attr(&els[0].1, "width").unwrap();
    for (_, tag, _) in &hits {
        let (x, w) = (attr(tag, "x").unwrap(), attr(tag, "width").unwrap());
        assert!(x >= 0.0 && x + w <= width && w <= 4.1 * 20.0 + 0.1, "{tag}");
    }
    // A's box is a rect, B's rotated box a polygon; both named.
    let places: Vec<_> = els
        .iter()
        .skip_while(|e| !e.1.contains("class=\"places\""))
        .skip(1)
        .take(2)
        .map(|e| e.0.as_str())
        .collect();
    assert_eq!(places, ["rect", "polygon"]);
    for name in ["A", "B"] {
        assert!(els
            .iter()
            .any(|e| e.1.contains("place-label") && e.2 == name));
    }
    // Over its own input, or with a cell under a centimetre: refused before anything is read.
    for bad in [
        vec!["-o".to_string(), log.display().to_string()],
        vec![
            "-o".into(),
            svg.display().to_string(),
            "--cell".into(),
            "0".into(),
        ],
        vec![
            "-o".into(),
            svg.display().to_string(),
            "--every".into(),
            "0".into(),
        ],
    ] {
        let out = lplace().arg("draw").arg(&log).args(&bad).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{bad:?}");
    }
    assert_eq!(std::fs::read_to_string(&log).unwrap(), round_room_log());
    for p in [log, map, svg] {
        let _ = std::fs::remove_file(p);
    }
}

#[test]
fn draw_of_the_intel_log_outlines_every_place_of_its_floor_plan() {
    let log = crate::support::data_dir().join("carmen-corrected-logs/intel-corrected.log");
    if !log.is_file() {
        eprintln!("SKIP: {} not found (set LPLACE_DATA)", log.display());
        return;
    }
    let svg = std::env::temp_dir().join(format!("lplace-draw-intel-{}.svg", std::process::id()));
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let out = lplace()
        .arg("draw")
        .arg(&log)
        .arg("--map")
        .arg(repo.join("maps/intel-plan.map"))
        .arg("-o")
        .arg(&svg)
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    let labels = elements(&text)
        .into_iter()
        .filter(|e| e.1.contains("place-label"))
        .count();
    let places = std::fs::read_to_string(repo.join("maps/intel-plan.map"))
        .unwrap()
        .lines()
        .filter(|l| l.trim_start().starts_with("place "))
        .count();
    assert!(places >= 19, "{places}");
    assert_eq!(labels, places);
    assert!(text.contains("910 of 910 scans"));
    let _ = std::fs::remove_file(svg);
}
