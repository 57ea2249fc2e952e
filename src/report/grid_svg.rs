//! One frame of the Fuzzy Position Grid (paper 000, figs. 3/5) as a picture a robotics engineer
//! can read without the source: the belief plane shaded on the possibility colour scale within
//! the grid's outlined extent, the landmarks with their ids, the true pose (when known) and the
//! estimate, inside x/y axes in metres with round ticks, a legend with the colour scale and
//! every mark, a metre scale bar, and the time in the title. The drawn area covers the whole
//! grid, every landmark and the marks, with a margin, so nothing is clipped. Pure: it returns
//! the SVG text and does no I/O. Depends on `grid` (the plane), `core` (poses) and
//! [`super::axis`].

use std::fmt::Write as _;

use super::axis::{format_tick, possibility_level, scale_bar, Ticks, POSSIBILITY_FILL};
use super::plot::xml_escape;
use crate::core::Pose2;
use crate::grid::{FuzzyGrid, LandmarkTable};

/// Longest side of the plotted area, pixels.
const PLOT_PX: f64 = 560.0;
/// Most blocks drawn across the plane: a block shows its brightest cell, so files stay small.
const MAX_BLOCKS: usize = 120;
/// Pixels left of, above, below and right of the plotted area (axes, title, legend).
const LEFT: f64 = 64.0;
const TOP: f64 = 66.0;
const BOTTOM: f64 = 48.0;
const LEGEND_W: f64 = 210.0;
/// Height of the legend column, pixels: the picture is at least this tall below `TOP`.
const LEGEND_H: f64 = 200.0;

const LANDMARK: &str = "#000000";
const TRUTH: &str = "#d7191c";
const ESTIMATE: &str = "#1a9641";
const HEADING: &str = "#e66101";
const EXTENT: &str = "#888888";

/// The frame `t` seconds after the first: the grid `g`, the map's landmarks and the true pose,
/// titled with `what` was run (data set, robot).
///
/// # Example
/// ```
/// use lplace::grid::{FuzzyGrid, GridConfig, Landmark, LandmarkTable};
/// let table = LandmarkTable::new(vec![Landmark { id: 1, x: 0.0, y: 0.0 }]).unwrap();
/// let g = FuzzyGrid::new(GridConfig::default(), [-1.0, -1.0, 1.0, 1.0]).unwrap();
/// let s = lplace::report::grid_svg::svg(&g, &table, None, 2.0, "demo");
/// assert!(s.starts_with("<svg") && s.contains("t = 2.0 s") && s.ends_with("</svg>\n"));
/// ```
pub fn svg(
    g: &FuzzyGrid,
    table: &LandmarkTable,
    truth: Option<Pose2>,
    t: f64,
    what: &str,
) -> String {
    let est = g.estimate();
    let v = View::fit(g, table, truth, (f64::from(est.x), f64::from(est.y)));
    let (w, h) = (v.width(), v.height());
    let mut s = String::new();
    let _ = writeln!(
        s,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.1} {h:.1}" font-family="sans-serif" font-size="11">"##
    );
    let _ = writeln!(
        s,
        r##"<rect width="100%" height="100%" fill="white"/><text class="title" x="{LEFT}" y="18" font-size="14">Fuzzy Position Grid at t = {t:.1} s from the first frame</text><text x="{LEFT}" y="34">{}</text><text x="{LEFT}" y="50" fill="#555">estimate ({:.2} m, {:.2} m), reliability {:.2}; cells {} m, {} × {}</text>"##,
        xml_escape(what),
        est.x,
        est.y,
        est.reliability,
        format_tick(f64::from(g.cell_size())),
        g.nx(),
        g.ny()
    );
    axes(&mut s, &v);
    belief(&mut s, g, &v);
    marks(&mut s, table, truth, &est, &v);
    legend(&mut s, &v, truth.is_some());
    s.push_str("</svg>\n");
    s
}

/// Metres to pixels: the plotted area `[x0, x1] × [y0, y1]` (metres) drawn `scale` pixels per
/// metre from (`LEFT`, `TOP`), y up.
struct View {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
    scale: f64,
}

impl View {
    /// The area holding the grid's extent, every landmark, the truth and the estimate, grown
    /// by 5 % of its longer side and a cell.
    fn fit(g: &FuzzyGrid, table: &LandmarkTable, truth: Option<Pose2>, est: (f64, f64)) -> View {
        let s = f64::from(g.cell_size());
        let (gx, gy) = g.origin();
        let (gx, gy) = (f64::from(gx), f64::from(gy));
        let mut b = [gx, gy, gx + g.nx() as f64 * s, gy + g.ny() as f64 * s];
        let marks = table.landmarks().iter();
        let points = marks.map(|m| (f64::from(m.x), f64::from(m.y)));
        for (x, y) in points.chain(truth.map(|p| (p.x, p.y))).chain([est]) {
            if x.is_finite() && y.is_finite() {
                b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
            }
        }
        let side = (b[2] - b[0]).max(b[3] - b[1]).max(s);
        let m = 0.05 * side + s;
        let (x0, y0, x1, y1) = (b[0] - m, b[1] - m, b[2] + m, b[3] + m);
        View {
            x0,
            y0,
            x1,
            y1,
            scale: PLOT_PX / (x1 - x0).max(y1 - y0),
        }
    }

    fn px(&self, x: f64) -> f64 {
        LEFT + (x - self.x0) * self.scale
    }

    fn py(&self, y: f64) -> f64 {
        TOP + (self.y1 - y) * self.scale
    }

    /// The plotted area's size, pixels.
    fn plot_w(&self) -> f64 {
        (self.x1 - self.x0) * self.scale
    }

    fn plot_h(&self) -> f64 {
        (self.y1 - self.y0) * self.scale
    }

    fn width(&self) -> f64 {
        LEFT + self.plot_w() + 24.0 + LEGEND_W
    }

    fn height(&self) -> f64 {
        TOP + self.plot_h().max(LEGEND_H) + BOTTOM
    }
}

/// The frame of the plotted area, light grid lines at the round metre ticks, tick labels and
/// axis names.
fn axes(s: &mut String, v: &View) {
    let (l, t, w, h) = (LEFT, TOP, v.plot_w(), v.plot_h());
    let (r, b) = (l + w, t + h);
    // About one tick per 80 px: labels of a few digits never touch.
    let xt = Ticks::cover(v.x0, v.x1, (w / 80.0).round().max(2.0) as usize);
    let yt = Ticks::cover(v.y0, v.y1, (h / 80.0).round().max(2.0) as usize);
    let _ = writeln!(s, r##"<g class="axes" font-size="10">"##);
    for x in xt
        .values()
        .into_iter()
        .filter(|x| (v.x0..=v.x1).contains(x))
    {
        let p = v.px(x);
        let _ = writeln!(
            s,
            r##"<line x1="{p:.1}" y1="{t:.1}" x2="{p:.1}" y2="{b:.1}" stroke="#eeeeee"/><line x1="{p:.1}" y1="{b:.1}" x2="{p:.1}" y2="{:.1}" stroke="black"/><text class="x-tick" x="{p:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
            b + 4.0,
            b + 15.0,
            format_tick(x)
        );
    }
    for y in yt
        .values()
        .into_iter()
        .filter(|y| (v.y0..=v.y1).contains(y))
    {
        let p = v.py(y);
        let _ = writeln!(
            s,
            r##"<line x1="{l:.1}" y1="{p:.1}" x2="{r:.1}" y2="{p:.1}" stroke="#eeeeee"/><line x1="{:.1}" y1="{p:.1}" x2="{l:.1}" y2="{p:.1}" stroke="black"/><text class="y-tick" x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
            l - 4.0,
            l - 6.0,
            p + 3.5,
            format_tick(y)
        );
    }
    let _ = writeln!(
        s,
        r##"<rect x="{l:.1}" y="{t:.1}" width="{w:.1}" height="{h:.1}" fill="none" stroke="black"/><text x="{:.1}" y="{:.1}" text-anchor="middle" font-size="11">x [m]</text><text transform="translate(16 {:.1}) rotate(-90)" text-anchor="middle" font-size="11">y [m]</text></g>"##,
        l + w / 2.0,
        b + 32.0,
        t + h / 2.0
    );
}

/// The grid's extent (dashed) and its plane in blocks of at most [`MAX_BLOCKS`] across, each
/// drawn over its whole extent in the shade of its brightest cell; where that cell is likely
/// (≥ 0.5) and its heading set is narrower than a half turn, a short line along the set's centre
/// (every third block).
fn belief(s: &mut String, g: &FuzzyGrid, v: &View) {
    let (nx, ny) = (g.nx(), g.ny());
    let b = nx.max(ny).div_ceil(MAX_BLOCKS).max(1);
    let cell = f64::from(g.cell_size());
    let (ox, oy) = g.origin();
    let (ox, oy) = (f64::from(ox), f64::from(oy));
    let (w, h) = (nx as f64 * cell * v.scale, ny as f64 * cell * v.scale);
    let _ = writeln!(
        s,
        r##"<rect class="extent" x="{:.2}" y="{:.2}" width="{w:.2}" height="{h:.2}" fill="none" stroke="{EXTENT}" stroke-dasharray="4 3"/>"##,
        v.px(ox),
        v.py(oy + ny as f64 * cell)
    );
    let _ = writeln!(s, r##"<g class="belief" fill="{POSSIBILITY_FILL}">"##);
    let mut headings = String::new();
    for bj in 0..ny.div_ceil(b) {
        for bc in 0..nx.div_ceil(b) {
            let (cols, rows) = (
                bc * b..((bc + 1) * b).min(nx),
                bj * b..((bj + 1) * b).min(ny),
            );
            let (best, at) = rows
                .clone()
                .flat_map(|j| cols.clone().map(move |c| (c, j)))
                .map(|(c, j)| (g.possibility(c, j), (c, j)))
                .fold((0.0f32, (cols.start, rows.start)), |a, x| {
                    if x.0 > a.0 {
                        x
                    } else {
                        a
                    }
                });
            let level = possibility_level(best);
            if level == 0 {
                continue;
            }
            let (left, top) = (ox + cols.start as f64 * cell, oy + rows.end as f64 * cell);
            let _ = writeln!(
                s,
                r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill-opacity="{:.1}"/>"##,
                v.px(left),
                v.py(top),
                cols.len() as f64 * cell * v.scale,
                rows.len() as f64 * cell * v.scale,
                f64::from(level) / 10.0
            );
            if best >= 0.5 && bc % 3 == 0 && bj % 3 == 0 {
                heading_mark(&mut headings, g, at, b as f64 * cell, v);
            }
        }
    }
    let _ = writeln!(s, "</g>\n<g class=\"headings\">\n{headings}</g>");
}

/// A line from the centre of cell `at` along its heading set's centre, `2.5 × block` metres
/// long, when the set is narrower than a half turn.
fn heading_mark(s: &mut String, g: &FuzzyGrid, at: (usize, usize), block: f64, v: &View) {
    let Some(hs) = g.heading_set(at.0, at.1) else {
        return;
    };
    if hs.shape.core + 2.0 * hs.shape.slope >= std::f32::consts::PI {
        return;
    }
    let (cx, cy) = g.cell_center(at.0, at.1);
    let (cx, cy) = (f64::from(cx), f64::from(cy));
    let (l, th) = (2.5 * block, f64::from(hs.center));
    let _ = writeln!(
        s,
        r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{HEADING}" stroke-width="1"/>"##,
        v.px(cx),
        v.py(cy),
        v.px(cx + l * th.cos()),
        v.py(cy + l * th.sin())
    );
}

/// The landmarks (dots with their ids), the true pose (a ring with a heading line) and the
/// estimate (a cross).
fn marks(
    s: &mut String,
    table: &LandmarkTable,
    truth: Option<Pose2>,
    est: &crate::grid::Estimate,
    v: &View,
) {
    let _ = writeln!(s, r##"<g class="landmarks">"##);
    let dots: Vec<(f64, f64)> = table
        .landmarks()
        .iter()
        .map(|m| (v.px(f64::from(m.x)), v.py(f64::from(m.y))))
        .collect();
    let ids: Vec<String> = table.landmarks().iter().map(|m| m.id.to_string()).collect();
    let spots = label_spots(&dots, &ids);
    for (((x, y), id), (lx, ly)) in dots.iter().zip(&ids).zip(spots) {
        let _ = writeln!(
            s,
            r##"<circle class="landmark" cx="{x:.1}" cy="{y:.1}" r="4" fill="{LANDMARK}" stroke="white"/><text class="landmark-id" x="{lx:.1}" y="{ly:.1}" font-size="10">{id}</text>"##,
        );
    }
    let _ = writeln!(s, "</g>");
    if let Some(p) = truth.filter(|p| p.x.is_finite() && p.y.is_finite()) {
        let (x, y) = (v.px(p.x), v.py(p.y));
        let _ = writeln!(
            s,
            r##"<g class="truth" stroke="{TRUTH}" stroke-width="1.5" fill="none"><circle cx="{x:.1}" cy="{y:.1}" r="5"/><line x1="{x:.1}" y1="{y:.1}" x2="{:.1}" y2="{:.1}"/></g>"##,
            x + 12.0 * p.theta.cos(),
            y - 12.0 * p.theta.sin()
        );
    }
    let (x, y) = (v.px(f64::from(est.x)), v.py(f64::from(est.y)));
    let _ = writeln!(
        s,
        r##"<path class="estimate" d="M{:.1},{y:.1}h10M{x:.1},{:.1}v10" stroke="{ESTIMATE}" stroke-width="2"/>"##,
        x - 5.0,
        y - 5.0
    );
}

/// Width and height of a landmark id label, pixels (font size 10: a digit is about 6 px wide).
fn label_size(text: &str) -> (f64, f64) {
    (6.0 * text.chars().count() as f64, 10.0)
}

/// Where each dot's label goes (the text's baseline start): the first of eight spots around
/// the dot, then the same eight spots farther out, whose box touches no label placed before
/// and no dot — landmarks centimetres apart (MRCLAM's) would otherwise print their ids over
/// each other. When every spot is taken the first one is used.
///
/// # Complexity
///
/// O(n² · 24) for n dots; a map has tens of landmarks.
fn label_spots(dots: &[(f64, f64)], texts: &[String]) -> Vec<(f64, f64)> {
    type Box4 = [f64; 4];
    let meets = |a: &Box4, b: &Box4| a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3];
    let dot_boxes: Vec<Box4> = dots
        .iter()
        .map(|&(x, y)| [x - 4.0, y - 4.0, x + 4.0, y + 4.0])
        .collect();
    let mut taken: Vec<Box4> = Vec::with_capacity(dots.len());
    let mut spots = Vec::with_capacity(dots.len());
    for (&(x, y), text) in dots.iter().zip(texts) {
        let (w, h) = label_size(text);
        // Box corners (left, top) of the eight spots at ring distance `r` from the dot.
        let candidates = (0..3).flat_map(|ring| {
            let r = 5.0 + 10.0 * f64::from(ring);
            [
                (x + r, y - r - h / 2.0),
                (x + r, y - h / 2.0),
                (x + r, y + r - h / 2.0),
                (x - w / 2.0, y + r),
                (x - r - w, y + r - h / 2.0),
                (x - r - w, y - h / 2.0),
                (x - r - w, y - r - h / 2.0),
                (x - w / 2.0, y - r - h),
            ]
        });
        let free = |&(l, t): &(f64, f64)| {
            let b = [l, t, l + w, t + h];
            !taken.iter().chain(&dot_boxes).any(|o| meets(&b, o))
        };
        let (l, t) = candidates
            .clone()
            .find(free)
            .unwrap_or((x + 5.0, y - 5.0 - h / 2.0));
        taken.push([l, t, l + w, t + h]);
        // The text's baseline sits about 2 px above the box's bottom.
        spots.push((l, t + h - 2.0));
    }
    spots
}

/// The legend right of the plot: the possibility colour scale (a swatch per tenth, labelled
/// 0, 0.5 and 1), a sample of every mark with its meaning, and the metre scale bar.
fn legend(s: &mut String, v: &View, has_truth: bool) {
    let x = LEFT + v.plot_w() + 24.0;
    let mut y = TOP + 10.0;
    let _ = writeln!(
        s,
        r##"<g class="legend"><text x="{x:.1}" y="{y:.1}">possibility of the position</text>"##
    );
    for k in 1..=10 {
        let _ = write!(
            s,
            r##"<rect class="swatch" x="{:.1}" y="{:.1}" width="16" height="12" fill="{POSSIBILITY_FILL}" fill-opacity="{:.1}" stroke="#cccccc" stroke-width="0.5"/>"##,
            x + 16.0 * (k - 1) as f64,
            y + 6.0,
            f64::from(k) / 10.0
        );
    }
    for (k, label) in [(0.0, "0"), (5.0, "0.5"), (10.0, "1")] {
        let _ = write!(
            s,
            r##"<text x="{:.1}" y="{:.1}" text-anchor="middle" font-size="10">{label}</text>"##,
            x + 16.0 * k,
            y + 30.0
        );
    }
    y += 52.0;
    // Each sample drawn as in the plot, its baseline at the text's.
    let items = [
        (
            format!(r##"<circle cx="8" cy="-4" r="4" fill="{LANDMARK}" stroke="white"/>"##),
            "landmark (id)",
            true,
        ),
        (
            format!(
                r##"<g stroke="{TRUTH}" stroke-width="1.5" fill="none"><circle cx="8" cy="-4" r="5"/><line x1="8" y1="-4" x2="20" y2="-4"/></g>"##
            ),
            "true pose",
            has_truth,
        ),
        (
            format!(r##"<path d="M3,-4h10M8,-9v10" stroke="{ESTIMATE}" stroke-width="2"/>"##),
            "estimate",
            true,
        ),
        (
            format!(r##"<line x1="2" y1="-4" x2="18" y2="-4" stroke="{HEADING}"/>"##),
            "heading of a cell",
            true,
        ),
        (
            format!(
                r##"<rect x="2" y="-10" width="16" height="10" fill="none" stroke="{EXTENT}" stroke-dasharray="4 3"/>"##
            ),
            "extent of the grid",
            true,
        ),
    ];
    for (sample, word, shown) in items {
        if shown {
            let _ = writeln!(
                s,
                r##"<g transform="translate({x:.1} {y:.1})">{sample}</g><text x="{:.1}" y="{y:.1}">{word}</text>"##,
                x + 26.0
            );
            y += 20.0;
        }
    }
    scale_bar(s, x, y + 16.0, v.x1 - v.x0, v.scale);
    let _ = writeln!(s, "</g>");
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Label boxes from the spots as `label_spots` defines them (baseline 2 px above the bottom).
    fn boxes(spots: &[(f64, f64)], texts: &[String]) -> Vec<[f64; 4]> {
        spots
            .iter()
            .zip(texts)
            .map(|(&(l, base), t)| {
                let (w, h) = label_size(t);
                [l, base + 2.0 - h, l + w, base + 2.0]
            })
            .collect()
    }

    #[test]
    fn ids_of_landmarks_centimetres_apart_do_not_overlap() {
        // Five landmarks within a pixel of each other (MRCLAM has pairs 1–2 cm apart), one
        // apart, two-digit ids.
        let dots = [
            (100.0, 100.0),
            (100.4, 100.2),
            (100.8, 99.7),
            (99.5, 100.5),
            (100.1, 99.2),
            (300.0, 50.0),
        ];
        let texts: Vec<String> = (10..16).map(|k| k.to_string()).collect();
        let b = boxes(&label_spots(&dots, &texts), &texts);
        for i in 0..b.len() {
            for j in 0..i {
                let (p, q) = (b[i], b[j]);
                let apart = p[2] <= q[0] || q[2] <= p[0] || p[3] <= q[1] || q[3] <= p[1];
                assert!(apart, "labels {i} and {j} overlap: {p:?} {q:?}");
            }
            for &(x, y) in &dots {
                let off = b[i][2] <= x - 4.0 || x + 4.0 <= b[i][0];
                assert!(
                    off || b[i][3] <= y - 4.0 || y + 4.0 <= b[i][1],
                    "label {i} on a dot"
                );
            }
        }
        // A lone landmark keeps the first spot: up and right of its dot.
        assert!(b[5][0] > 300.0 && b[5][3] <= 50.0, "{:?}", b[5]);
    }
}
