//! `lplace report`: the page's content against hand-derived figures and `lplace eval`, its exit
//! codes, and the page opened in a real headless Chromium (no console message, charts drawn).

use crate::support::{lplace, scratch};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).expect("the page was written")
}

/// The office recording's page (bundled map, rules, recording; graph tracker).
fn office_page(dir: &Path, extra: &[&str]) -> PathBuf {
    let out = dir.join("report.html");
    lplace()
        .arg("report")
        .args(extra)
        .arg("-o")
        .arg(&out)
        .assert()
        .success();
    out
}

#[test]
fn office_page_has_the_summary_confusion_and_charts() {
    let dir = scratch("report", "office");
    let page = read(&office_page(&dir, &[]));
    assert!(page.starts_with("<!DOCTYPE html>"));
    // README: 2,500 frames, 1,168 at a place, 764 right and 36 wrong with tracking. By hand:
    // decided 800 / 1168 = 68.5 %, right 764 / 800 = 95.5 %, confidently wrong 0.
    for want in [
        "<th class=\"l\">frames</th><td>2500</td>",
        "<th class=\"l\">frames at a place</th><td>1168</td>",
        "<td>68.5 %</td>",
        "<td>95.5 %</td>",
        "<td>0.0 %</td>",
        "<h3>Confusion matrix</h3>",
        "<h3>Place possibilities and necessities over time</h3>",
        "<h3>Trajectory</h3>",
    ] {
        assert!(page.contains(want), "missing {want}");
    }
    // The office run kidnaps twice (README).
    assert!(page.contains("<th class=\"l\">kidnaps</th><td>2</td>"));
    // One run: no overview table; the graph tracker: no belief pictures.
    assert_eq!(page.matches("<section").count(), 1);
    assert!(!page.contains("class=\"overview\"") && !page.contains("Grid tracker belief"));
    assert!(!page.contains("<script") && !page.contains("https://"));
}

#[test]
fn confusion_matrix_rows_add_up_to_the_frames() {
    // Every frame is in one row of the confusion matrix: the sum of its cells is the frame
    // count, and the diagonal is the 764 right decisions of the README.
    let dir = scratch("report", "confusion");
    let page = read(&office_page(&dir, &[]));
    let table = page
        .split("<table class=\"confusion\">")
        .nth(1)
        .and_then(|t| t.split("</table>").next())
        .expect("a confusion table");
    let mut total = 0u64;
    let mut diagonal = 0u64;
    for (i, row) in table.split("</tr>").skip(1).enumerate() {
        let cells: Vec<u64> = row
            .split("</td>")
            .filter_map(|c| c.rsplit('>').next()?.trim().parse().ok())
            .collect();
        total += cells.iter().sum::<u64>();
        // Rows and columns list the places in the same order; the row `none` has no diagonal.
        if !row.contains(">none<") {
            diagonal += cells.get(i).copied().unwrap_or(0);
        }
    }
    assert_eq!(total, 2500);
    assert_eq!(diagonal, 764);
}

#[test]
fn several_runs_get_an_overview_and_one_section_each() {
    let dir = scratch("report", "several");
    let out = dir.join("two.html");
    lplace()
        .args([
            "report",
            "recordings/office.jsonl",
            "recordings/office.jsonl",
            "--no-track",
        ])
        .arg("--output")
        .arg(&out)
        .assert()
        .success();
    let page = read(&out);
    assert_eq!(page.matches("<section").count(), 2);
    assert!(page.contains("class=\"overview\""));
    assert!(page.contains("href=\"#run-0\"") && page.contains("href=\"#run-1\""));
    // Tracking off: README's 816 right and 61 wrong of 1,168 → decided 75.1 %, right 93.0 %.
    assert_eq!(
        page.matches("<td>75.1 %</td>").count(),
        4,
        "overview twice, sections twice"
    );
    assert!(page.contains("<td>93.0 %</td>"));
}

#[test]
fn rejected_records_are_reported_counted_and_exit_3() {
    let dir = scratch("report", "rejected");
    let stream = dir.join("bad.jsonl");
    std::fs::write(
        &stream,
        "{\"percepts\":[]}\n{not json\n{\"percepts\":[{\"name\":\"nope\",\"degree\":1}]}\n",
    )
    .expect("scratch is writable");
    let out = dir.join("bad.html");
    lplace()
        .arg("report")
        .arg(&stream)
        .arg("-o")
        .arg(&out)
        .assert()
        .code(3)
        .stderr(predicates::str::contains("bad.jsonl:2:"))
        .stderr(predicates::str::contains("bad.jsonl:3:"));
    let page = read(&out);
    assert!(page.contains("<th class=\"l\">rejected records</th><td>2</td>"));
    // No truth at all: no confusion matrix and no trajectory, said so.
    assert!(!page.contains("Confusion matrix"));
    assert!(page.contains("No true poses in this run"));
}

#[test]
fn bad_inputs_exit_with_the_documented_codes() {
    let dir = scratch("report", "codes");
    lplace()
        .args(["report", "no/such/stream.jsonl"])
        .assert()
        .code(1)
        .stderr(predicates::str::contains("no/such/stream.jsonl"));
    let ron = dir.join("t.ron");
    std::fs::write(&ron, "(bogus: 1)").expect("scratch is writable");
    lplace()
        .arg("report")
        .arg("--tracker")
        .arg(&ron)
        .assert()
        .code(2);
    lplace()
        .args([
            "report",
            "--tracker",
            "config/intel-tracker.ron",
            "--no-track",
        ])
        .assert()
        .code(2);
    lplace()
        .args(["report", "--map", "tests/corpus/several_errors.lpl"])
        .assert()
        .code(2);
    // Without -o the page goes to stdout; `-` reads the stream from stdin.
    let office = std::fs::read("recordings/office.jsonl").expect("the bundled recording");
    lplace()
        .args(["report", "-", "--no-track"])
        .write_stdin(office)
        .assert()
        .success()
        .stdout(predicates::str::starts_with("<!DOCTYPE html>"))
        .stdout(predicates::str::contains("<h2>&lt;stdin&gt;</h2>"));
    // A page that cannot be written: exit 1, naming the file.
    lplace()
        .args(["report", "--no-track", "-o"])
        .arg(dir.join("no-such-dir").join("r.html"))
        .assert()
        .code(1)
        .stderr(predicates::str::contains("r.html"));
}

// ---- the page in a real browser ------------------------------------------------------------

/// Set (by `.ci/run`) to make a missing Chromium a failure instead of a skip.
const REQUIRE: &str = "LPLACE_REQUIRE_BROWSER";

/// The Chromium binary: `$LPLACE_CHROMIUM`, else Debian's `/usr/bin/chromium`; `None` (after
/// saying why) when absent and not required.
fn chromium() -> Option<PathBuf> {
    let path = std::env::var_os("LPLACE_CHROMIUM")
        .map_or_else(|| PathBuf::from("/usr/bin/chromium"), PathBuf::from);
    if path.exists() {
        return Some(path);
    }
    assert!(
        std::env::var_os(REQUIRE).is_none(),
        "{REQUIRE} is set but there is no Chromium at {} (apt-get install chromium)",
        path.display()
    );
    eprintln!(
        "SKIPPED: no Chromium at {} (apt-get install chromium, or set LPLACE_CHROMIUM)",
        path.display()
    );
    None
}

/// What Chromium made of a page: its console messages (each logged as `CONSOLE` on stderr)
/// and the screenshot's RGB pixels.
struct Rendered {
    console: Vec<String>,
    pixels: Vec<[u8; 3]>,
}

/// Opens `page` in headless Chromium with a fresh profile and screenshots 1200×`height` pixels.
fn render(browser: &Path, page: &Path, dir: &Path, height: u32) -> Rendered {
    let profile = dir.join("profile");
    let _ = std::fs::remove_dir_all(&profile);
    std::fs::create_dir_all(&profile).expect("scratch is writable");
    let shot = dir.join("shot.png");
    let _ = std::fs::remove_file(&shot);
    let url = format!(
        "file://{}",
        page.canonicalize().expect("the page exists").display()
    );
    let child = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--window-size=1200,{height}"))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(url)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("chromium starts");
    let output = wait_at_most(child, Duration::from_secs(180));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success() && shot.exists(),
        "chromium failed ({}):\n{stderr}",
        output.status
    );
    Rendered {
        console: stderr
            .lines()
            .filter(|l| l.contains(":CONSOLE"))
            .map(str::to_string)
            .collect(),
        pixels: decode_png(&shot),
    }
}

/// Waits for `child`, killing it after `limit` (a hung browser must not hang the suite).
fn wait_at_most(mut child: std::process::Child, limit: Duration) -> std::process::Output {
    let start = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(_)) => break,
            Ok(None) if start.elapsed() < limit => std::thread::sleep(Duration::from_millis(100)),
            _ => {
                let _ = child.kill();
                break;
            }
        }
    }
    child.wait_with_output().expect("chromium's output")
}

fn decode_png(path: &Path) -> Vec<[u8; 3]> {
    let file = std::fs::File::open(path).expect("the screenshot exists");
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::normalize_to_color8());
    let mut reader = decoder.read_info().expect("a PNG screenshot");
    let mut buf = vec![0; reader.output_buffer_size().expect("a sane size")];
    let info = reader.next_frame(&mut buf).expect("one frame");
    let channels = info.color_type.samples();
    buf[..info.buffer_size()]
        .chunks_exact(channels)
        .map(|c| match c {
            [g] | [g, _] => [*g, *g, *g],
            [r, g, b, ..] => [*r, *g, *b],
            _ => [255, 255, 255],
        })
        .collect()
}

/// Pixels that are not the white page and not grey (text, rules, table borders are grey): the
/// charts' colours, and the shaded table cells.
fn coloured(pixels: &[[u8; 3]]) -> usize {
    pixels
        .iter()
        .filter(|p| {
            let hi = p.iter().copied().max().unwrap_or(0);
            let lo = p.iter().copied().min().unwrap_or(0);
            hi - lo > 40
        })
        .count()
}

fn non_background(pixels: &[[u8; 3]]) -> usize {
    pixels.iter().filter(|p| **p != [255, 255, 255]).count()
}

/// The page without its pictures: everything from `<svg` to `</svg>` removed.
fn without_svg(page: &str) -> String {
    let mut out = String::new();
    let mut rest = page;
    while let Some(i) = rest.find("<svg") {
        out.push_str(&rest[..i]);
        rest = rest[i..]
            .find("</svg>")
            .map_or("", |j| &rest[i + j + "</svg>".len()..]);
    }
    out.push_str(rest);
    out
}

#[test]
fn pages_load_without_console_messages_and_their_charts_render() {
    let Some(browser) = chromium() else { return };
    let dir = scratch("report", "browser");

    // The detector must be able to fail: a page that logs an error and throws is caught.
    let bad = dir.join("bad.html");
    std::fs::write(
        &bad,
        "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>b</title></head><body>\
         <script>console.error('deliberate'); notDefined();</script></body></html>",
    )
    .expect("scratch is writable");
    let r = render(&browser, &bad, &dir, 400);
    assert!(
        r.console.len() >= 2,
        "console not captured: {:?}",
        r.console
    );

    // The office page (graph tracker), and the same recording with the metric grid tracker,
    // which adds the belief pictures.
    for (name, extra) in [
        ("graph", vec![]),
        ("grid", vec!["--tracker", "config/intel-tracker.ron"]),
    ] {
        let sub = dir.join(name);
        std::fs::create_dir_all(&sub).expect("scratch is writable");
        let page = office_page(&sub, &extra);
        assert_eq!(read(&page).contains("Grid tracker belief"), name == "grid");
        renders_cleanly(&browser, &page, &sub, name);
    }
}

/// Opens `page` and its copy without pictures: no console message, a page that is not blank,
/// and charts that colour many more pixels than the text and tables alone.
fn renders_cleanly(browser: &Path, page: &Path, dir: &Path, name: &str) {
    let shown = render(browser, page, dir, 6000);
    assert!(
        shown.console.is_empty(),
        "{name}: console messages: {:?}",
        shown.console
    );
    let bare = dir.join("bare.html");
    std::fs::write(&bare, without_svg(&read(page))).expect("scratch is writable");
    let text_only = render(browser, &bare, dir, 6000);
    let (with, without) = (coloured(&shown.pixels), coloured(&text_only.pixels));
    eprintln!(
        "{name}: {} non-background pixels; coloured {with} with charts, {without} without",
        non_background(&shown.pixels)
    );
    assert!(
        non_background(&shown.pixels) > 100_000,
        "{name}: blank page"
    );
    assert!(
        with > without + 25_000,
        "{name}: charts did not render ({with} coloured pixels with them, {without} without)"
    );
}

/// The README's tutorial step: the Intel log → percept stream → HTML report, whose figures are
/// `lplace eval`'s on the same stream, opened in the browser when there is one.
#[test]
fn intel_run_to_its_html_report() {
    let log = crate::support::data_dir().join("carmen-corrected-logs/intel-corrected.log");
    if !log.exists() {
        eprintln!(
            "SKIPPED: no Intel log at {} (set LPLACE_DATA)",
            log.display()
        );
        return;
    }
    let dir = scratch("report", "intel");
    let stream = dir.join("intel.jsonl");
    let extracted = lplace()
        .args(["extract", "--from", "carmen"])
        .arg(&log)
        .args(["--map", "maps/intel.map", "--config", "config/intel.ron"])
        .output()
        .expect("extract runs");
    assert!(extracted.status.success());
    std::fs::write(&stream, &extracted.stdout).expect("scratch is writable");
    let model = [
        "--map",
        "maps/intel.map",
        "--rules",
        "rules/intel.lpl",
        "--tracker",
        "config/intel-tracker.ron",
    ];
    let page = dir.join("intel.html");
    lplace()
        .arg("report")
        .arg(&stream)
        .args(model)
        .arg("-o")
        .arg(&page)
        .assert()
        .success();
    let eval = lplace()
        .arg("eval")
        .arg(&stream)
        .args(model)
        .args(["--only-summary", "--summary", "json"])
        .output()
        .expect("eval runs");
    let summary: serde_json::Value =
        serde_json::from_slice(&eval.stdout).expect("eval's summary is JSON");
    let n = |k: &str| summary["truth"][k].as_u64().expect("a count");
    let (at, right, wrong) = (n("at_place"), n("correct"), n("wrong"));
    let pct = |a: u64, b: u64| format!("<td>{:.1} %</td>", 100.0 * a as f64 / b as f64);
    let html = read(&page);
    assert!(
        html.contains(&pct(right + wrong, at)),
        "decided differs from eval"
    );
    assert!(
        html.contains(&pct(right, right + wrong)),
        "right differs from eval"
    );
    assert!(html.contains("Grid tracker belief"));
    if let Some(browser) = chromium() {
        renders_cleanly(&browser, &page, &dir, "intel");
    }
}
