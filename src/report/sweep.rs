//! The sweep plot of `lplace compare`: error against a perturbation level, one line per method,
//! in side-by-side panels (added noise, kept fraction) sharing one y axis so that the panels
//! can be compared at a glance. Levels are categorical (evenly spaced, labelled), as in paper
//! 001's Figs. 4–5. Pure: it returns the SVG text and does no I/O. Depends on nothing but
//! [`super::plot`]'s escaping.

use std::fmt::Write as _;

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

/// A "nice" upper bound for an axis from 0 to `max`: 1, 2, 2.5 or 5 times a power of ten (so
/// that the five tick steps are round numbers too).
fn nice_ceiling(max: f64) -> f64 {
    if !(max.is_finite() && max > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(max.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|v| *v >= max)
        .unwrap_or(10.0 * p)
}

/// Renders `panels` side by side with a shared y axis labelled `y_label`, from 0 to a rounded
/// maximum of the finite values. Non-finite values are treated as missing.
///
/// # Example
/// ```
/// use lplace::report::sweep::{svg, Panel, Series};
/// let p = Panel {
///     title: "noise".into(),
///     levels: vec!["0".into(), "1".into()],
///     series: vec![Series { name: "fpg".into(), values: vec![Some(0.2), None] }],
/// };
/// let s = svg(&[p], "ATE RMSE [m]");
/// assert!(s.starts_with("<svg") && s.contains("fpg") && s.ends_with("</svg>\n"));
/// ```
pub fn svg(panels: &[Panel], y_label: &str) -> String {
    let (pw, ph) = (360.0, 260.0); // panel plot area
    let (left, top, gap, bottom) = (64.0, 56.0, 48.0, 64.0);
    let n = panels.len().max(1) as f64;
    let width = left + n * pw + (n - 1.0) * gap + 20.0;
    let height = top + ph + bottom;
    let ymax = nice_ceiling(
        panels
            .iter()
            .flat_map(|p| &p.series)
            .flat_map(|s| s.values.iter().flatten())
            .copied()
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max),
    );
    let mut s = String::new();
    let _ = writeln!(
        s,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="12">"##
    );
    let _ = writeln!(
        s,
        r##"<rect width="{width}" height="{height}" fill="white"/>"##
    );
    // Legend: the series names of the first panel (all panels show the same methods).
    if let Some(first) = panels.first() {
        legend(&mut s, first, left);
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
            ymax,
            m: panel.levels.len().max(1),
        };
        draw_panel(&mut s, panel, &area);
    }
    s.push_str("</svg>\n");
    s
}

/// One panel's plot area in pixels, its y range `[0, ymax]` and its number of level slots.
struct Area {
    x0: f64,
    top: f64,
    pw: f64,
    ph: f64,
    ymax: f64,
    m: usize,
}

impl Area {
    fn y_of(&self, v: f64) -> f64 {
        self.top + self.ph * (1.0 - v / self.ymax)
    }

    /// Levels sit at the centres of `m` equal slots.
    fn x_of(&self, k: usize) -> f64 {
        self.x0 + self.pw * (k as f64 + 0.5) / self.m as f64
    }
}

/// A line sample and name per series, in a row at the top.
fn legend(s: &mut String, panel: &Panel, left: f64) {
    for (k, ser) in panel.series.iter().enumerate() {
        let x = left + 110.0 * k as f64;
        let c = COLOURS[k % COLOURS.len()];
        let d = DASHES[k % DASHES.len()];
        let _ = writeln!(
            s,
            r##"<line x1="{x}" y1="16" x2="{}" y2="16" stroke="{c}" stroke-width="2.5" stroke-dasharray="{d}"/><text x="{}" y="20">{}</text>"##,
            x + 24.0,
            x + 30.0,
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
    for t in 0..=5 {
        let v = a.ymax * t as f64 / 5.0;
        let y = a.y_of(v);
        let _ = writeln!(
            s,
            r##"<line x1="{x0}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" text-anchor="end" font-size="10">{}</text>"##,
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

/// A tick value with no more digits than it needs.
fn format_tick(v: f64) -> String {
    let t = format!("{v:.3}");
    t.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_ceiling_rounds_up_to_1_2_2half_5() {
        assert_eq!(nice_ceiling(0.0), 1.0);
        assert_eq!(nice_ceiling(f64::NAN), 1.0);
        assert!((nice_ceiling(0.28) - 0.5).abs() < 1e-12);
        assert!((nice_ceiling(1.2) - 2.0).abs() < 1e-12);
        assert!((nice_ceiling(2.0) - 2.0).abs() < 1e-12);
        assert!((nice_ceiling(2.06) - 2.5).abs() < 1e-12);
        assert!((nice_ceiling(7.0) - 10.0).abs() < 1e-12);
    }

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
        let s = svg(&[p], "y");
        assert_eq!(s.matches("<polyline").count(), 1);
        assert_eq!(s.matches("<circle").count(), 2);
        assert!(s.contains("a&lt;b"));
        // 2.0 is the top of the axis: its dot sits on the panel's top edge (y = 56).
        assert!(s.contains(r#"cy="56.0""#), "{s}");
    }
}
