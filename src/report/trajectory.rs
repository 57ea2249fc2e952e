//! The result of a run drawn over the map: each place's extent (box or disc, labelled), the
//! paths between place centres, and the corrected trajectory as one dot per frame coloured by
//! the decision — right (green), wrong (red) or disoriented (grey) — under a title with the
//! counts, with a metre scale bar below. Place labels are moved off each other greedily (places
//! closer than a label's width would print their names on top of each other). Pure: it returns
//! the SVG text and does no I/O. Depends on `map`, and on [`super::axis`] for the bar.

use std::fmt::Write as _;

use super::axis::scale_bar;
use super::plot::xml_escape;
use crate::map::{Extent, Map};

/// How one frame's decision compares with the truth.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// A place was chosen and it is the true one.
    Right,
    /// A place was chosen and it is not the true one (or the robot is at no place).
    Wrong,
    /// No place was chosen.
    Disoriented,
}

impl Verdict {
    fn colour(self) -> &'static str {
        match self {
            Verdict::Right => "#1a9641",
            Verdict::Wrong => "#d7191c",
            Verdict::Disoriented => "#999999",
        }
    }
}

/// One frame of the picture: the corrected pose (metres, map frame) and the verdict.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrajectoryPoint {
    /// x, metres.
    pub x: f64,
    /// y, metres.
    pub y: f64,
    /// The verdict.
    pub verdict: Verdict,
}

/// Renders `points` over `map`'s places as an SVG document, `scale` pixels per metre (values
/// that are not finite and positive fall back to 20). Non-finite points are left out. The map's
/// y axis points up, so y is flipped.
///
/// # Example
/// ```
/// use lplace::report::trajectory::{svg, TrajectoryPoint, Verdict};
/// let map = lplace::engine::Engine::office().unwrap().map().clone();
/// let s = svg(&map, &[TrajectoryPoint { x: 0.5, y: 0.5, verdict: Verdict::Right }], 40.0, "demo");
/// assert!(s.starts_with("<svg") && s.contains("P0") && s.contains("#1a9641"));
/// ```
pub fn svg(map: &Map, points: &[TrajectoryPoint], scale: f64, title: &str) -> String {
    let scale = if scale.is_finite() && scale > 0.0 {
        scale
    } else {
        20.0
    };
    let (x0, y0, x1, y1) = bounds(map, points);
    let m = 1.0;
    let (x0, y0, x1, y1) = (x0 - m, y0 - m, x1 + m, y1 + m);
    let header = 40.0;
    let footer = 34.0;
    let w = (x1 - x0) * scale;
    let h = (y1 - y0) * scale + header + footer;
    let c = Canvas {
        x0,
        y1,
        scale,
        header,
    };
    let mut s = String::new();
    // Writing to a String cannot fail; the results are ignored for that reason.
    let _ = writeln!(
        s,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.1} {h:.1}" font-family="sans-serif" font-size="11">"##
    );
    let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="white"/>"##);
    let counts = |v: Verdict| points.iter().filter(|p| p.verdict == v).count();
    let _ = writeln!(
        s,
        r##"<text x="8" y="16" font-size="14">{}</text><text x="8" y="32"><tspan fill="{}">● right {}</tspan>  <tspan fill="{}">● wrong {}</tspan>  <tspan fill="{}">● disoriented {}</tspan></text>"##,
        xml_escape(title),
        Verdict::Right.colour(),
        counts(Verdict::Right),
        Verdict::Wrong.colour(),
        counts(Verdict::Wrong),
        Verdict::Disoriented.colour(),
        counts(Verdict::Disoriented)
    );
    draw_map(&mut s, map, &c);
    for p in points {
        if p.x.is_finite() && p.y.is_finite() {
            let _ = writeln!(
                s,
                r##"<circle cx="{:.1}" cy="{:.1}" r="2.2" fill="{}"/>"##,
                c.px(p.x),
                c.py(p.y),
                p.verdict.colour()
            );
        }
    }
    let mut placed: Vec<LabelBox> = Vec::new();
    for p in map.places() {
        let (x, y) = (c.px(p.pose.0), c.py(p.pose.1));
        let b = place_label(x, y, &p.name, &placed);
        let _ = writeln!(
            s,
            r##"<text class="place-label" x="{:.1}" y="{:.1}" text-anchor="middle" fill="#08306b">{}</text>"##,
            b.x,
            b.y,
            xml_escape(&p.name)
        );
        placed.push(b);
    }
    scale_bar(&mut s, 10.0, h - footer / 2.0, x1 - x0, scale);
    s.push_str("</svg>\n");
    s
}

/// A label's anchor (middle of its baseline, pixels) and its estimated size: labels are 11 px
/// sans-serif, whose characters average under 7 px.
#[derive(Debug, Clone, Copy)]
pub(super) struct LabelBox {
    pub(super) x: f64,
    pub(super) y: f64,
    half_width: f64,
}

/// Pixels per character and line height assumed for a label.
const CHAR_PX: f64 = 7.0;
const LINE_PX: f64 = 12.0;

impl LabelBox {
    fn overlaps(&self, o: &LabelBox) -> bool {
        (self.x - o.x).abs() < self.half_width + o.half_width && (self.y - o.y).abs() < LINE_PX
    }
}

/// Where the label `name` of a place drawn at `(x, y)` goes: on the centre if that is free, else
/// the first free spot of a ring around it, else below every label it would hit (greedy: the
/// places' declaration order decides who keeps the centre).
pub(super) fn place_label(x: f64, y: f64, name: &str, placed: &[LabelBox]) -> LabelBox {
    let half_width = CHAR_PX * name.chars().count() as f64 / 2.0 + 1.0;
    let at = |dx: f64, dy: f64| LabelBox {
        x: x + dx,
        y: y + 4.0 + dy,
        half_width,
    };
    let side = half_width + 4.0;
    let ring = [
        (0.0, 0.0),
        (0.0, -LINE_PX),
        (0.0, LINE_PX),
        (side, 0.0),
        (-side, 0.0),
        (side, -LINE_PX),
        (-side, -LINE_PX),
        (side, LINE_PX),
        (-side, LINE_PX),
    ];
    let free = |b: &LabelBox| !placed.iter().any(|o| o.overlaps(b));
    if let Some(b) = ring.iter().map(|&(dx, dy)| at(dx, dy)).find(free) {
        return b;
    }
    // Lines below are a line apart and a label is under a line tall, so each placed label
    // blocks at most two of them: 2n + 1 lines hold a free one.
    let last = 2 * placed.len() + 2;
    (2..=last)
        .map(|k| at(0.0, LINE_PX * k as f64))
        .find(free)
        .unwrap_or_else(|| at(0.0, LINE_PX * last as f64))
}

/// The smallest box `(x0, y0, x1, y1)` holding every place extent and every finite point;
/// the unit square when there is nothing.
fn bounds(map: &Map, points: &[TrajectoryPoint]) -> (f64, f64, f64, f64) {
    let (mut x0, mut y0, mut x1, mut y1) =
        (f64::INFINITY, f64::INFINITY, -f64::INFINITY, -f64::INFINITY);
    let mut grow = |x: f64, y: f64| {
        if x.is_finite() && y.is_finite() {
            x0 = x0.min(x);
            y0 = y0.min(y);
            x1 = x1.max(x);
            y1 = y1.max(y);
        }
    };
    for p in map.places() {
        match p.extent {
            Extent::Radius(r) => {
                grow(p.pose.0 - r, p.pose.1 - r);
                grow(p.pose.0 + r, p.pose.1 + r);
            }
            Extent::Box { x0, y0, x1, y1 } => {
                grow(x0, y0);
                grow(x1, y1);
            }
        }
    }
    for p in points {
        grow(p.x, p.y);
    }
    if !x0.is_finite() {
        return (0.0, 0.0, 1.0, 1.0);
    }
    (x0, y0, x1, y1)
}

/// Metres to pixels: `x0` and `y1` are the drawn area's left and top edges (metres), `header`
/// the pixels above it; y is flipped.
struct Canvas {
    x0: f64,
    y1: f64,
    scale: f64,
    header: f64,
}

impl Canvas {
    fn px(&self, x: f64) -> f64 {
        (x - self.x0) * self.scale
    }

    fn py(&self, y: f64) -> f64 {
        (self.y1 - y) * self.scale + self.header
    }
}

/// The map beneath the trajectory: paths between place centres, then the place extents.
fn draw_map(s: &mut String, map: &Map, c: &Canvas) {
    for e in map.graph().edge_indices() {
        let Some((a, b)) = map.graph().edge_endpoints(e) else {
            continue;
        };
        let (Some(pa), Some(pb)) = (map.places().get(a.index()), map.places().get(b.index()))
        else {
            continue;
        };
        let _ = writeln!(
            s,
            r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#c6dbef" stroke-width="1.5"/>"##,
            c.px(pa.pose.0),
            c.py(pa.pose.1),
            c.px(pb.pose.0),
            c.py(pb.pose.1)
        );
    }
    for p in map.places() {
        match p.extent {
            Extent::Radius(r) => {
                let _ = writeln!(
                    s,
                    r##"<circle cx="{:.1}" cy="{:.1}" r="{:.1}" fill="#f2f2f2" fill-opacity="0.5" stroke="#555"/>"##,
                    c.px(p.pose.0),
                    c.py(p.pose.1),
                    r * c.scale
                );
            }
            Extent::Box { x0, y0, x1, y1 } => {
                let _ = writeln!(
                    s,
                    r##"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="#f2f2f2" fill-opacity="0.5" stroke="#555"/>"##,
                    c.px(x0),
                    c.py(y1),
                    (x1 - x0) * c.scale,
                    (y1 - y0) * c.scale
                );
            }
        }
    }
}
