//! Paper 003's run-time display (Fig. 3) unrolled over time, as a hand-written SVG: one row per
//! place, a strip of its possibility Π (light) above a strip of its necessity N (dark) along the
//! frames over a pale red band where it was the truth, and a black bar where it was chosen; a
//! legend with a swatch per mark above the rows.
//!
//! Memory stays flat on any run length: [`RunPlot`] keeps at most [`MAX_COLUMNS`] columns; when
//! they are full, neighbouring columns are merged pairwise (max of the degrees, the later
//! decision) and each column covers twice as many frames. Depends on `logic` only.

use crate::logic::{Decision, PlaceDistribution};
use std::fmt::Write as _;

/// Most columns kept (and drawn).
pub const MAX_COLUMNS: usize = 1024;

const NONE: u32 = u32::MAX;

/// Degrees and decisions of a run, reduced to at most [`MAX_COLUMNS`] columns.
#[derive(Debug, Clone)]
pub struct RunPlot {
    places: Vec<String>,
    /// Frames per stored column.
    bucket: u64,
    frames: u64,
    /// Per column, per place: max Π and max N.
    pos: Vec<f32>,
    nec: Vec<f32>,
    chosen: Vec<u32>,
    truth: Vec<u32>,
    /// Frames in the column being filled (the last one).
    fill: u64,
    title: String,
}

impl RunPlot {
    /// An empty plot for these places.
    pub fn new(places: Vec<String>, title: impl Into<String>) -> RunPlot {
        let n = places.len();
        RunPlot {
            places,
            bucket: 1,
            frames: 0,
            pos: Vec::with_capacity(MAX_COLUMNS * n),
            nec: Vec::with_capacity(MAX_COLUMNS * n),
            chosen: Vec::with_capacity(MAX_COLUMNS),
            truth: Vec::with_capacity(MAX_COLUMNS),
            fill: 0,
            title: title.into(),
        }
    }

    fn columns(&self) -> usize {
        self.chosen.len()
    }

    /// Adds one frame.
    pub fn push(&mut self, dist: &PlaceDistribution, decision: Decision, truth: Option<usize>) {
        let n = self.places.len();
        if self.fill == 0 || self.fill >= self.bucket {
            if self.columns() == MAX_COLUMNS {
                self.halve();
            }
            self.pos.extend(std::iter::repeat(0.0).take(n));
            self.nec.extend(std::iter::repeat(0.0).take(n));
            self.chosen.push(NONE);
            self.truth.push(NONE);
            self.fill = 0;
        }
        let c = self.columns() - 1;
        for k in 0..n {
            let p = dist.possibility.get(k).copied().unwrap_or(0.0) as f32;
            let q = dist.necessity.get(k).copied().unwrap_or(0.0) as f32;
            self.pos[c * n + k] = self.pos[c * n + k].max(p);
            self.nec[c * n + k] = self.nec[c * n + k].max(q);
        }
        self.chosen[c] = decision.place().map_or(NONE, |p| p as u32);
        self.truth[c] = truth.map_or(NONE, |p| p as u32);
        self.fill += 1;
        self.frames += 1;
    }

    /// Merges columns pairwise; the bucket doubles.
    fn halve(&mut self) {
        let n = self.places.len();
        let cols = self.columns();
        let half = cols / 2;
        for c in 0..half {
            let (a, b) = (2 * c, 2 * c + 1);
            for k in 0..n {
                self.pos[c * n + k] = self.pos[a * n + k].max(self.pos[b * n + k]);
                self.nec[c * n + k] = self.nec[a * n + k].max(self.nec[b * n + k]);
            }
            self.chosen[c] = self.chosen[b];
            self.truth[c] = self.truth[b];
        }
        self.pos.truncate(half * n);
        self.nec.truncate(half * n);
        self.chosen.truncate(half);
        self.truth.truncate(half);
        self.bucket *= 2;
        // The last kept column is complete; the next push starts a new one.
        self.fill = self.bucket;
    }

    /// The SVG document.
    pub fn to_svg(&self) -> String {
        let n = self.places.len();
        let cols = self.columns().max(1);
        let (left, top, row_h, width) = (56.0, 40.0, 28.0, 1000.0);
        let g = Layout {
            left,
            row_h,
            width,
            w: width / cols as f64,
        };
        let height = top + row_h * n as f64 + 60.0;
        let mut s = String::new();
        let _ = writeln!(
            s,
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{height}" viewBox="0 0 {} {height}" font-family="sans-serif" font-size="12">"##,
            left + width + 20.0,
            left + width + 20.0
        );
        let _ = writeln!(
            s,
            r##"<rect width="100%" height="100%" fill="white"/><text x="{left}" y="18" font-size="14">{}</text>"##,
            xml_escape(&self.title)
        );
        legend(&mut s, left, 24.0, self.frames, self.bucket);
        for (k, name) in self.places.iter().enumerate() {
            self.place_row(&mut s, &g, k, name, top + row_h * k as f64);
        }
        self.frame_axis(&mut s, &g, top + row_h * n as f64 + 8.0);
        s
    }

    /// Place `k`'s row at height `y`: its label and frame, its Π and N strips, its truth and
    /// chosen marks.
    fn place_row(&self, s: &mut String, g: &Layout, k: usize, name: &str, y: f64) {
        let (left, row_h, width) = (g.left, g.row_h, g.width);
        let _ = writeln!(
            s,
            r##"<text x="{}" y="{}" text-anchor="end">{}</text><rect x="{left}" y="{}" width="{width}" height="{}" fill="none" stroke="#ddd"/>"##,
            left - 6.0,
            y + row_h * 0.6,
            xml_escape(name),
            y + 3.0,
            row_h - 4.0
        );
        // The truth first, as a band behind the strips: a run reads as a shaded stretch.
        for (c, e, is_k) in self.runs(|c| self.truth[c] == k as u32) {
            if is_k {
                let _ = writeln!(
                    s,
                    r##"<rect x="{:.2}" y="{}" width="{:.2}" height="{}" fill="{TRUTH}" fill-opacity="0.22"/>"##,
                    left + g.w * c as f64,
                    y + 3.0,
                    g.w * (e - c) as f64,
                    row_h - 4.0
                );
            }
        }
        let n = self.places.len();
        for (values, colour, sy) in [
            (&self.pos, POSSIBILITY, y + 4.0),
            (&self.nec, NECESSITY, y + 14.0),
        ] {
            let q = |c: usize| (values[c * n + k].clamp(0.0, 1.0) * 20.0).round() as u32;
            // Runs of equal quantised degree become one rectangle: small files for long runs.
            for (c, e, level) in self.runs(q) {
                if level > 0 {
                    let _ = writeln!(
                        s,
                        r##"<rect x="{:.2}" y="{sy}" width="{:.2}" height="10" fill="{colour}" fill-opacity="{:.2}"/>"##,
                        left + g.w * c as f64,
                        g.w * (e - c) as f64,
                        level as f64 / 20.0
                    );
                }
            }
        }
        for (c, e, is_k) in self.runs(|c| self.chosen[c] == k as u32) {
            if is_k {
                let _ = writeln!(
                    s,
                    r##"<rect x="{:.2}" y="{}" width="{:.2}" height="3" fill="{CHOSEN}"/>"##,
                    left + g.w * c as f64,
                    y + 24.0,
                    g.w * (e - c) as f64
                );
            }
        }
    }

    /// Maximal runs `[start, end)` of columns on which `key` is equal, with that key.
    fn runs<K: PartialEq>(&self, key: impl Fn(usize) -> K) -> Vec<(usize, usize, K)> {
        let mut out = Vec::new();
        let mut c = 0;
        while c < self.columns() {
            let k = key(c);
            let mut e = c + 1;
            while e < self.columns() && key(e) == k {
                e += 1;
            }
            out.push((c, e, k));
            c = e;
        }
        out
    }

    /// The frame-number axis below the rows, at height `axis_y`.
    fn frame_axis(&self, s: &mut String, g: &Layout, axis_y: f64) {
        for i in 0..=5 {
            let x = g.left + g.width * i as f64 / 5.0;
            let frame = (self.frames as f64 * i as f64 / 5.0).round() as u64;
            let _ = writeln!(
                s,
                r##"<line x1="{x:.1}" y1="{}" x2="{x:.1}" y2="{}" stroke="#888"/><text x="{x:.1}" y="{}" text-anchor="middle">{frame}</text>"##,
                axis_y - 4.0,
                axis_y + 2.0,
                axis_y + 16.0
            );
        }
        let _ = writeln!(
            s,
            r##"<text x="{}" y="{}" text-anchor="middle" fill="#555">frame</text></svg>"##,
            g.left + g.width / 2.0,
            axis_y + 34.0
        );
    }
}

/// Colours of the marks, shared by the rows and the legend.
const POSSIBILITY: &str = "#3b7dd8";
const NECESSITY: &str = "#0b2a55";
const CHOSEN: &str = "#000000";
const TRUTH: &str = "#d62728";

/// The legend line at height `y` (top of the swatches): frames per column, then one swatch per
/// mark as it is drawn in the rows, each followed by its meaning.
fn legend(s: &mut String, left: f64, y: f64, frames: u64, bucket: u64) {
    let _ = write!(
        s,
        r##"<g class="legend"><text x="{left}" y="{}" fill="#555">{frames} frames, {bucket} per column</text>"##,
        y + 9.0
    );
    let items: [(&str, f64, f64, &str); 4] = [
        (POSSIBILITY, 1.0, 10.0, "Π (possibility)"),
        (NECESSITY, 1.0, 10.0, "N (necessity)"),
        (CHOSEN, 1.0, 3.0, "chosen"),
        (TRUTH, 0.22, 10.0, "truth"),
    ];
    // Text is about 7 px a character at 12 px: each item takes its swatch and its words.
    let mut x = left + 190.0;
    for (colour, opacity, h, label) in items {
        let _ = write!(
            s,
            r##"<rect class="swatch" x="{x:.1}" y="{:.1}" width="16" height="{h}" fill="{colour}" fill-opacity="{opacity}"/><text x="{:.1}" y="{}">{label}</text>"##,
            y + 10.0 - h,
            x + 20.0,
            y + 9.0
        );
        x += 20.0 + 7.0 * label.chars().count() as f64 + 16.0;
    }
    let _ = writeln!(s, "</g>");
}

/// Where [`RunPlot::to_svg`] draws: left margin, row height, plot width and column width (px).
struct Layout {
    left: f64,
    row_h: f64,
    width: f64,
    w: f64,
}

/// Escapes text for SVG content and attribute values.
pub(crate) fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
