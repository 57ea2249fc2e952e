//! `lplace report`'s page: one self-contained HTML document for one evaluated run or a set of
//! runs. Per run: the summary, the per-place confusion matrix, paper 003's run display unrolled
//! over time (each place's Π and N per frame, [`RunPlot`]), the true trajectory coloured by the
//! decision ([`crate::report::trajectory`]) and, with the metric grid tracker, its belief plane
//! at a few moments ([`belief`]). With several runs, a table compares them first.
//!
//! The pictures are inline SVG written here and in the sibling modules; the page loads nothing
//! (no script, no style sheet, no font, no image from anywhere), so it opens offline and can be
//! mailed as one file. [`RunRecorder`] is fed one frame at a time with bounded memory: the
//! trajectory keeps at most [`MAX_POINTS`] points (every other one is dropped when full, and
//! from then on every second, fourth, … frame is kept), so a long run still makes a page a
//! browser opens.

pub mod belief;

use std::fmt::Write as _;

use crate::engine::grid_tracker::GridTracker;
use crate::io::stream::FrameMeta;
use crate::logic::{Decision, PlaceDistribution};
use crate::map::Map;
use crate::report::plot::{xml_escape, RunPlot};
use crate::report::summary::{Summary, TruthSummary};
use crate::report::trajectory::{self, TrajectoryPoint, Verdict};
use belief::{BeliefSampler, BeliefSnapshot};

/// Most trajectory points drawn per run.
pub const MAX_POINTS: usize = 20_000;

/// What the last frame left, kept so that the final belief plane can be labelled.
#[derive(Debug, Clone, Default)]
struct LastFrame {
    line: u64,
    t: Option<f64>,
    truth: Option<(f64, f64)>,
    decided: Option<usize>,
}

/// Collects what the page shows of one run, frame by frame.
#[derive(Debug, Clone)]
pub struct RunRecorder {
    name: String,
    places: Vec<String>,
    plot: RunPlot,
    points: Vec<TrajectoryPoint>,
    /// Keep one frame with a true pose in this many.
    point_stride: u64,
    posed: u64,
    beliefs: BeliefSampler,
    last: Option<LastFrame>,
}

impl RunRecorder {
    /// A recorder for a run called `name` (the stream, as the user named it) over `places`.
    pub fn new(name: impl Into<String>, places: Vec<String>) -> RunRecorder {
        let name = name.into();
        RunRecorder {
            plot: RunPlot::new(
                places.clone(),
                format!("{name}: Π (light) and N (dark) per place"),
            ),
            name,
            places,
            points: Vec::new(),
            point_stride: 1,
            posed: 0,
            beliefs: BeliefSampler::default(),
            last: None,
        }
    }

    /// Adds one stepped frame: the distribution the decision `d` was drawn from, the frame's
    /// meta data, and the grid tracker when there is one.
    pub fn push(
        &mut self,
        dist: &PlaceDistribution,
        d: Decision,
        meta: &FrameMeta,
        grid: Option<&GridTracker>,
    ) {
        self.plot.push(dist, d, meta.truth_place);
        let truth = meta.truth_pose.map(|p| (p[0], p[1]));
        if let Some((x, y)) = truth {
            let verdict = match d.place() {
                None => Verdict::Disoriented,
                Some(k) if meta.truth_known && meta.truth_place == Some(k) => Verdict::Right,
                Some(_) => Verdict::Wrong,
            };
            self.push_point(TrajectoryPoint { x, y, verdict });
        }
        if let Some(g) = grid {
            if self.beliefs.wants_next() {
                let name = d.place().and_then(|k| self.places.get(k)).cloned();
                self.beliefs
                    .push(BeliefSnapshot::of(g, meta.line, meta.t, truth, name));
            }
        }
        self.last = Some(LastFrame {
            line: meta.line,
            t: meta.t,
            truth,
            decided: d.place(),
        });
    }

    /// Keeps every `point_stride`-th point; when full, halves the points and the rate.
    fn push_point(&mut self, p: TrajectoryPoint) {
        let keep = self.posed % self.point_stride == 0;
        self.posed += 1;
        if !keep {
            return;
        }
        if self.points.len() == MAX_POINTS {
            let mut i = 0;
            self.points.retain(|_| {
                i += 1;
                i % 2 == 1
            });
            self.point_stride *= 2;
            if (self.posed - 1) % self.point_stride != 0 {
                return;
            }
        }
        self.points.push(p);
    }

    /// The run's section of the page, given its summary, its map and the grid tracker's final
    /// state (if any).
    pub fn finish(self, summary: Summary, map: &Map, grid: Option<&GridTracker>) -> RunPage {
        let last = match (grid, &self.last) {
            (Some(g), Some(l)) => Some(BeliefSnapshot::of(
                g,
                l.line,
                l.t,
                l.truth,
                l.decided.and_then(|k| self.places.get(k)).cloned(),
            )),
            _ => None,
        };
        let beliefs = self.beliefs.finish(last);
        let trajectory = (!self.points.is_empty()).then(|| {
            trajectory::svg(
                map,
                &self.points,
                20.0,
                &format!("{}: decisions along the true trajectory", self.name),
            )
        });
        RunPage {
            name: self.name,
            summary,
            run_display: self.plot.to_svg(),
            trajectory,
            beliefs: beliefs
                .iter()
                .map(|b| (caption(b), belief::svg(b, map)))
                .collect(),
        }
    }
}

/// The caption of a belief picture.
fn caption(b: &BeliefSnapshot) -> String {
    let t = b.t.map_or(String::new(), |t| format!(", t = {t:.1} s"));
    let d = b.decided.as_deref().unwrap_or("disoriented");
    format!("line {}{t}: decided {d}", b.line)
}

/// One run's section, ready to be written.
#[derive(Debug, Clone)]
pub struct RunPage {
    /// The run's name (its stream).
    pub name: String,
    /// Its summary (as `lplace eval --summary json`).
    pub summary: Summary,
    /// Paper 003's run display over time, SVG.
    pub run_display: String,
    /// The true trajectory coloured by decision, SVG; `None` without true poses.
    pub trajectory: Option<String>,
    /// Belief planes of the grid tracker: caption and SVG.
    pub beliefs: Vec<(String, String)>,
}

/// What the page says about how the runs were made, as (name, value) lines.
pub type Setup = Vec<(String, String)>;

const STYLE: &str = "body{font-family:sans-serif;margin:1.5em auto;max-width:1120px;color:#222;padding:0 1em}\
h1{font-size:1.5em}h2{font-size:1.25em;border-top:1px solid #ccc;padding-top:.8em;margin-top:2em}h3{font-size:1.05em}\
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}\
th{background:#f3f3f3}td.l,th.l{text-align:left}svg{max-width:100%;height:auto}\
figure{margin:.5em 0}figcaption{font-size:.9em;color:#555}.beliefs{display:flex;flex-wrap:wrap;gap:1em}\
.confusion td,.confusion th{padding:1px 3px;font-size:.85em}.note{color:#555;font-size:.9em}.wide{overflow-x:auto}";

/// The whole page for `runs`, titled `title`, with `setup` listed under the title.
pub fn page(title: &str, setup: &Setup, runs: &[RunPage]) -> String {
    let mut s = String::new();
    let t = xml_escape(title);
    let _ = write!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <link rel=\"icon\" href=\"data:,\">\n<title>{t}</title>\n<style>{STYLE}</style>\n\
         </head>\n<body>\n<h1>{t}</h1>\n"
    );
    if !setup.is_empty() {
        s.push_str("<table class=\"setup\">\n");
        for (k, v) in setup {
            let _ = writeln!(
                s,
                "<tr><th class=\"l\">{}</th><td class=\"l\">{}</td></tr>",
                xml_escape(k),
                xml_escape(v)
            );
        }
        s.push_str("</table>\n");
    }
    if runs.len() > 1 {
        overview(&mut s, runs);
    }
    for (i, r) in runs.iter().enumerate() {
        run_section(&mut s, i, r);
    }
    s.push_str("</body>\n</html>\n");
    s
}

/// `a / b` as a percentage with one decimal, `-` when `b` is 0.
fn pct(a: u64, b: u64) -> String {
    if b == 0 {
        "-".into()
    } else {
        format!("{:.1} %", 100.0 * a as f64 / b as f64)
    }
}

/// The figures a place recogniser is judged by: decided and confidently wrong over the frames
/// at a place, right over the decided ones (the same as `lplace eval`'s summary line).
fn headline(t: &TruthSummary) -> [String; 3] {
    let decided = t.correct + t.wrong;
    [
        pct(decided, t.at_place),
        pct(t.correct, decided),
        pct(t.confidently_wrong, t.at_place),
    ]
}

/// One row per run.
fn overview(s: &mut String, runs: &[RunPage]) {
    s.push_str(
        "<h2>Runs</h2>\n<table class=\"overview\">\n<tr><th class=\"l\">run</th><th>frames</th>\
         <th>rejected</th><th>at a place</th><th>decided</th><th>right of decided</th>\
         <th>confidently wrong</th></tr>\n",
    );
    for (i, r) in runs.iter().enumerate() {
        let sm = &r.summary;
        let cols = match &sm.truth {
            Some(t) => {
                let [a, b, c] = headline(t);
                format!(
                    "<td>{}</td><td>{a}</td><td>{b}</td><td>{c}</td>",
                    t.at_place
                )
            }
            None => "<td>-</td><td>-</td><td>-</td><td>-</td>".into(),
        };
        let _ = writeln!(
            s,
            "<tr><td class=\"l\"><a href=\"#run-{i}\">{}</a></td><td>{}</td><td>{}</td>{cols}</tr>",
            xml_escape(&r.name),
            sm.frames,
            sm.rejected
        );
    }
    s.push_str("</table>\n");
}

/// A run's section: summary, confusion matrix, run display, trajectory, beliefs.
fn run_section(s: &mut String, i: usize, r: &RunPage) {
    let _ = writeln!(
        s,
        "<section id=\"run-{i}\">\n<h2>{}</h2>",
        xml_escape(&r.name)
    );
    summary_table(s, &r.summary);
    if let Some(t) = &r.summary.truth {
        confusion(s, t);
    }
    let _ = writeln!(
        s,
        "<h3>Place possibilities and necessities over time</h3>\n<figure class=\"chart\">\n{}\
         <figcaption>Paper 003's run display unrolled over the frames: per place, Π (light) \
         above N (dark); a black bar where the place was chosen, a pale red band where it \
         was the truth.</figcaption>\n</figure>",
        r.run_display
    );
    match &r.trajectory {
        Some(svg) => {
            let _ = writeln!(
                s,
                "<h3>Trajectory</h3>\n<figure class=\"chart\">\n{svg}<figcaption>The true \
                 poses, one dot per frame: green right, red wrong, grey \
                 disoriented.</figcaption>\n</figure>"
            );
        }
        None => s.push_str("<p class=\"note\">No true poses in this run: no trajectory.</p>\n"),
    }
    if !r.beliefs.is_empty() {
        s.push_str(
            "<h3>Grid tracker belief</h3>\n<p class=\"note\">The metric tracker's possibility \
             per cell (white 0, dark blue 1) over the place extents; the red ring is the true \
             position.</p>\n<div class=\"beliefs\">\n",
        );
        for (cap, svg) in &r.beliefs {
            let _ = writeln!(
                s,
                "<figure class=\"chart\">\n{svg}<figcaption>{}</figcaption>\n</figure>",
                xml_escape(cap)
            );
        }
        s.push_str("</div>\n");
    }
    s.push_str("</section>\n");
}

/// The counts of the summary.
fn summary_table(s: &mut String, sm: &Summary) {
    s.push_str("<h3>Summary</h3>\n<table class=\"summary\">\n");
    let mut row = |k: &str, v: String| {
        let _ = writeln!(
            s,
            "<tr><th class=\"l\">{k}</th><td>{}</td></tr>",
            xml_escape(&v)
        );
    };
    row("frames", sm.frames.to_string());
    row("tracking", if sm.tracking { "on" } else { "off" }.into());
    row("decided", sm.decided.to_string());
    for (why, n) in &sm.disoriented {
        row(&format!("disoriented: {why}"), n.to_string());
    }
    row("rejected records", sm.rejected.to_string());
    if let Some(t) = &sm.truth {
        let [a, b, c] = headline(t);
        row("frames at a place", t.at_place.to_string());
        row("decided (of frames at a place)", a);
        row("right (of decided)", b);
        row("confidently wrong, N ≥ 0.9 (of frames at a place)", c);
        row(
            "between places (a place decided)",
            format!("{} ({})", t.between_places, t.between_decided),
        );
        if t.kidnaps > 0 {
            row("kidnaps", t.kidnaps.to_string());
            row(
                "frames to recover: mean, worst",
                format!(
                    "{}, {}",
                    t.mean_recovery_frames
                        .map_or("-".into(), |m| format!("{m:.1}")),
                    t.max_recovery_frames
                        .map_or("never".into(), |m| m.to_string())
                ),
            );
        }
    }
    s.push_str("</table>\n");
}

/// The confusion matrix, rows the truth, columns the decision; each cell shaded by its share of
/// the row (green on the diagonal, grey when disoriented, red elsewhere).
fn confusion(s: &mut String, t: &TruthSummary) {
    s.push_str(
        "<h3>Confusion matrix</h3>\n<p class=\"note\">Rows: the true place (none: between \
         places); columns: the decision. Cells are shaded by their share of the row.</p>\n\
         <div class=\"wide\"><table class=\"confusion\">\n<tr><th class=\"l\">truth \\ decided</th>",
    );
    for c in &t.confusion_columns {
        let _ = write!(s, "<th>{}</th>", xml_escape(c));
    }
    s.push_str("</tr>\n");
    for (i, r) in t.confusion_rows.iter().enumerate() {
        let total = t.confusion.row_total(i);
        let _ = write!(s, "<tr><th class=\"l\">{}</th>", xml_escape(r));
        for (c, n) in t.confusion_columns.iter().zip(t.confusion.row(i)) {
            let share = if total == 0 {
                0.0
            } else {
                n as f64 / total as f64
            };
            // Green right, grey disoriented (not wrong, just undecided), red wrong.
            let colour = match c.as_str() {
                _ if c == r => "26,150,65",
                "disoriented" => "120,120,120",
                _ => "215,25,28",
            };
            let _ = write!(
                s,
                "<td style=\"background:rgba({colour},{share:.2})\">{n}</td>"
            );
        }
        s.push_str("</tr>\n");
    }
    s.push_str("</table></div>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_escaped_and_nothing_is_fetched() {
        let summary = crate::report::summary::Tally::new(vec!["A".into()], false).finish();
        let run = RunPage {
            name: "<b>&run".into(),
            summary,
            run_display: "<svg></svg>".into(),
            trajectory: None,
            beliefs: vec![],
        };
        let setup = vec![("map".to_string(), "a<b".to_string())];
        let p = page("t & <t>", &setup, &[run.clone(), run]);
        assert!(p.contains("<title>t &amp; &lt;t&gt;</title>"));
        assert!(p.contains("&lt;b&gt;&amp;run"));
        assert!(p.contains("a&lt;b"));
        assert!(!p.contains("<b>"));
        // Self-contained: no external reference of any kind.
        for needle in ["http://", "https://", "src=", "<script", "@import", "url("] {
            let outside_svg_ns = p.replace("http://www.w3.org/2000/svg", "");
            assert!(!outside_svg_ns.contains(needle), "{needle}");
        }
    }

    #[test]
    fn a_long_trajectory_is_thinned_evenly() {
        let mut r = RunRecorder::new("r", vec!["A".into()]);
        let n = 3 * MAX_POINTS as u64 + 7;
        for i in 0..n {
            r.push_point(TrajectoryPoint {
                x: i as f64,
                y: 0.0,
                verdict: Verdict::Right,
            });
        }
        // Past 2 × MAX_POINTS the stride is 4: points 0, 4, 8, … up to n − 1.
        assert_eq!(r.point_stride, 4);
        assert_eq!(r.points.len() as u64, (n - 1) / 4 + 1);
        assert!(r
            .points
            .iter()
            .enumerate()
            .all(|(k, p)| p.x == (4 * k) as f64));
    }

    #[test]
    fn percentages_and_their_empty_case() {
        assert_eq!(pct(1, 3), "33.3 %");
        assert_eq!(pct(0, 0), "-");
    }
}
