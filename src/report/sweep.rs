//! The sweep plot of `lplace compare`: error against a perturbation level, one line per method,
//! in side-by-side panels (added noise, kept fraction) sharing one y axis so that the panels
//! can be compared at a glance. Levels are categorical (evenly spaced, labelled), as in paper
//! 001's Figs. 4–5. The title names what was evaluated (data set, robot), and the y axis spans
//! the data rather than starting at 0. Pure: it returns the SVG text and does no I/O. Depends
//! on [`super::axis`] for the ticks and [`super::plot`]'s escaping.

use std::fmt::Write as _;

use super::axis::{format_tick, Ticks};
use super::plot::xml_escape;

/// One method's values at a panel's levels; `None` where it has none (e.g. never got a fix),
/// which breaks the line there.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend label.
    pub name: String,
    /// One value per level (extra values are ignored, missing ones are gaps).
    pub values: Vec<Option<f64>>,
}

/// One panel: a perturbation's levels along x.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// Title above the panel.
    pub title: String,
    /// Tick label of each level, left to right.
    pub levels: Vec<String>,
    /// The lines.
    pub series: Vec<Series>,
}

/// Line colours, in series order (colour-blind-safe Okabe–Ito palette); the same method gets
/// the same colour in every panel as long as the series come in the same order.
const COLOURS: [&str; 8] = [
    "#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#000000", "#f0e442",
];

/// Dash patterns, in series order, so that lines that coincide (R-MCL on the grid's values)
/// still show both colours.
const DASHES: [&str; 4] = ["none", "7 4", "2 3", "10 3 2 3"];

/// Renders `panels` side by side under `title` with a shared y axis labelled `y_label`. The
/// axis runs between round ticks a little below the smallest and a little above the largest
/// finite value (from 0 only when the values come near 0), so that differences between the
/// methods fill the height. Non-finite values are treated as missing.
///
/// # Example
/// ```
/// use lplace::report::sweep::{svg, Panel, Series};
/// let p = Panel {
///     title: "noise".into(),
///     levels: vec!["0".into(), "1".into()],
///     series: vec![Series { name: "fpg".into(), values: vec![Some(0.2), None] }],
/// };
/// let s = svg(&[p], "robot 1", "ATE RMSE [m]");
/// assert!(s.starts_with("<svg") && s.contains("fpg") && s.ends_with("</svg>\n"));
/// ```
pub fn svg(panels: &[Panel], title: &str, y_label: &str) -> String {
    let (pw, ph) = (360.0, 260.0); // panel plot area
    let (left, top, gap, bottom) = (64.0, 80.0, 48.0, 64.0);
    let n = panels.len().max(1) as f64;
    let width = left + n * pw + (n - 1.0) * gap + 20.0;
    let height = top + ph + bottom;
    let ticks = y_ticks(panels);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="12">"##
    );
    let _ = writeln!(
        s,
        r##"<rect width="{width}" height="{height}" fill="white"/><text class="title" x="{left}" y="20" font-size="14">{}</text>"##,
        xml_escape(title)
    );
    // Legend: the series names of the first panel (all panels show the same methods).
    if let Some(first) = panels.first() {
        legend(&mut s, first, left, 42.0);
    }
    let _ = writeln!(
        s,
        r##"<text transform="translate(16 {}) rotate(-90)" text-anchor="middle">{}</text>"##,
        top + ph / 2.0,
        xml_escape(y_label)
    );
    for (pi, panel) in panels.iter().enumerate() {
        let area = Area {
            x0: left + pi as f64 * (pw + gap),
            top,
            pw,
            ph,
            ticks,
            m: panel.levels.len().max(1),
        };
        draw_panel(&mut s, panel, &area);
    }
    s.push_str("</svg>\n");
    s
}

/// The y axis's ticks: the finite values' range padded by 5 % of its span on each side (by a
/// tenth of the value when they are all equal), the lower end kept at or above 0 when every
/// value is (errors are never negative).
fn y_ticks(panels: &[Panel]) -> Ticks {
    let values = panels
        .iter()
        .flat_map(|p| &p.series)
        .flat_map(|s| s.values.iter().flatten())
        .copied()
        .filter(|v| v.is_finite());
    let (min, max) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    if !(min.is_finite() && max.is_finite()) {
        return Ticks::cover(0.0, 1.0, 5);
    }
    let pad = match max - min {
        d if d > 0.0 => 0.05 * d,
        _ if max == 0.0 => 0.5,
        _ => 0.1 * max.abs(),
    };
    let lo = if min >= 0.0 {
        (min - pad).max(0.0)
    } else {
        min - pad
    };
    Ticks::cover(lo, max + pad, 5)
}

/// One panel's plot area in pixels, its y ticks (whose ends are the area's bottom and top)
/// and its number of level slots.
struct Area {
    x0: f64,
    top: f64,
    pw: f64,
    ph: f64,
    ticks: Ticks,
    m: usize,
}

impl Area {
    fn y_of(&self, v: f64) -> f64 {
        let (lo, hi) = (self.ticks.lo, self.ticks.hi);
        self.top + self.ph * (hi - v) / (hi - lo)
    }

    /// Levels sit at the centres of `m` equal slots.
    fn x_of(&self, k: usize) -> f64 {
        self.x0 + self.pw * (k as f64 + 0.5) / self.m as f64
    }
}

/// A line sample and name per series, in a row at height `y`.
fn legend(s: &mut String, panel: &Panel, left: f64, y: f64) {
    for (k, ser) in panel.series.iter().enumerate() {
        let x = left + 110.0 * k as f64;
        let c = COLOURS[k % COLOURS.len()];
        let d = DASHES[k % DASHES.len()];
        let _ = writeln!(
            s,
            r##"<line x1="{x}" y1="{y}" x2="{}" y2="{y}" stroke="{c}" stroke-width="2.5" stroke-dasharray="{d}"/><text x="{}" y="{}">{}</text>"##,
            x + 24.0,
            x + 30.0,
            y + 4.0,
            xml_escape(&ser.name)
        );
    }
}

/// One panel: its frame, title, y ticks, level labels and lines.
fn draw_panel(s: &mut String, panel: &Panel, a: &Area) {
    let (x0, top, pw, ph) = (a.x0, a.top, a.pw, a.ph);
    let _ = writeln!(
        s,
        r##"<rect x="{x0}" y="{top}" width="{pw}" height="{ph}" fill="none" stroke="#444"/>"##
    );
    let _ = writeln!(
        s,
        r##"<text x="{}" y="{}" text-anchor="middle" font-weight="bold">{}</text>"##,
        x0 + pw / 2.0,
        top - 10.0,
        xml_escape(&panel.title)
    );
    for v in a.ticks.values() {
        let y = a.y_of(v);
        let _ = writeln!(
            s,
            r##"<line x1="{x0}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#ddd"/><text class="y-tick" x="{}" y="{:.1}" text-anchor="end" font-size="10">{}</text>"##,
            x0 + pw,
            x0 - 4.0,
            y + 3.0,
            format_tick(v)
        );
    }
    for (k, label) in panel.levels.iter().enumerate() {
        let _ = writeln!(
            s,
            r##"<text x="{:.1}" y="{}" text-anchor="middle" font-size="10">{}</text>"##,
            a.x_of(k),
            top + ph + 16.0,
            xml_escape(label)
        );
    }
    for (si, ser) in panel.series.iter().enumerate() {
        draw_series(s, ser, si, a);
    }
}

/// Series number `si` as polylines with dots.
fn draw_series(s: &mut String, ser: &Series, si: usize, a: &Area) {
    let c = COLOURS[si % COLOURS.len()];
    let d = DASHES[si % DASHES.len()];
    let pts: Vec<Option<(f64, f64)>> = ser
        .values
        .iter()
        .take(a.m)
        .enumerate()
        .map(|(k, v)| v.filter(|v| v.is_finite()).map(|v| (a.x_of(k), a.y_of(v))))
        .collect();
    // A polyline per run of present values, so a missing level leaves a gap.
    for run in pts.split(Option::is_none) {
        let run: Vec<(f64, f64)> = run.iter().flatten().copied().collect();
        if run.len() >= 2 {
            let path: Vec<String> = run.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
            let _ = writeln!(
                s,
                r##"<polyline points="{}" fill="none" stroke="{c}" stroke-width="2" stroke-dasharray="{d}"/>"##,
                path.join(" ")
            );
        }
        for (x, y) in run {
            let _ = writeln!(s, r##"<circle cx="{x:.1}" cy="{y:.1}" r="3" fill="{c}"/>"##);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaps_break_lines_and_every_value_gets_a_dot() {
        let p = Panel {
            title: "t".into(),
            levels: (0..4).map(|k| k.to_string()).collect(),
            series: vec![Series {
                name: "a<b".into(),
                values: vec![Some(1.0), Some(2.0), None, Some(f64::NAN)],
            }],
        };
        let s = svg(&[p], "robot <1>", "y");
        assert_eq!(s.matches("<polyline").count(), 1);
        assert_eq!(s.matches("<circle").count(), 2);
        assert!(s.contains("a&lt;b") && s.contains("robot &lt;1&gt;"));
    }

    /// The height of each y tick and its label's value, from the picture.
    fn tick_labels(s: &str) -> Vec<(f64, f64)> {
        s.lines()
            .filter_map(|l| {
                // The tick's grid line comes first on its line: its height is the tick's.
                let at = l.find(r#"class="y-tick""#)?;
                let y = l.split(r#"y1=""#).nth(1)?.split('"').next()?;
                let v = l[at..].split('>').nth(1)?.split('<').next()?;
                Some((y.parse().ok()?, v.parse().ok()?))
            })
            .collect()
    }

    #[test]
    fn the_y_axis_fits_the_data_not_zero() {
        let values = [2.13, 2.61, 2.4];
        let p = Panel {
            title: "t".into(),
            levels: (0..3).map(|k| k.to_string()).collect(),
            series: vec![Series {
                name: "m".into(),
                values: values.iter().map(|v| Some(*v)).collect(),
            }],
        };
        let s = svg(&[p], "title", "y");
        let ticks = tick_labels(&s);
        let lo = ticks.iter().map(|t| t.1).fold(f64::INFINITY, f64::min);
        let hi = ticks.iter().map(|t| t.1).fold(f64::NEG_INFINITY, f64::max);
        assert!(lo <= 2.13 && hi >= 2.61, "{ticks:?}");
        assert!(lo >= 0.5 * 2.13, "the axis starts at {lo}: {ticks:?}");
        // Each dot's height is where the tick labels' linear scale puts its value.
        let (a, b) = (ticks[0], ticks[ticks.len() - 1]);
        for v in values {
            let y = a.0 + (v - a.1) * (b.0 - a.0) / (b.1 - a.1);
            assert!(s.contains(&format!(r#"cy="{y:.1}""#)), "{v} at {y}: {s}");
        }
    }

    #[test]
    fn values_near_zero_keep_zero_and_none_give_a_unit_axis() {
        let p = |values: Vec<Option<f64>>| Panel {
            title: "t".into(),
            levels: vec!["a".into(), "b".into()],
            series: vec![Series {
                name: "m".into(),
                values,
            }],
        };
        let near = tick_labels(&svg(&[p(vec![Some(0.02), Some(0.9)])], "t", "y"));
        assert_eq!(near.first().map(|t| t.1), Some(0.0), "{near:?}");
        let none = tick_labels(&svg(&[p(vec![None, Some(f64::NAN)])], "t", "y"));
        assert_eq!(none.first().map(|t| t.1), Some(0.0), "{none:?}");
        assert_eq!(none.last().map(|t| t.1), Some(1.0), "{none:?}");
    }
}
