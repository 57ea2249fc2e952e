//! The scales the pictures share: round tick values along an axis ([`Ticks`], 1, 2, 2.5 or 5
//! times a power of ten, so that a reader can interpolate between labels), tick labels with no
//! more digits than they need, the metre scale bar, and the possibility colour scale (one blue,
//! shaded in tenths, for every belief picture). Pure text; depends on nothing.

use std::fmt::Write as _;

/// The smallest 1, 2, 2.5 or 5 × 10ⁿ at or above `raw` (1 when `raw` is not finite and
/// positive).
pub fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|v| *v >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0 * p)
}

/// Evenly spaced round tick values from `lo` to `hi` (both multiples of `step`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ticks {
    /// First tick, at or below the range's minimum.
    pub lo: f64,
    /// Last tick, at or above the range's maximum.
    pub hi: f64,
    /// Distance between ticks.
    pub step: f64,
}

impl Ticks {
    /// Round ticks covering `[min, max]` in about `count` steps (at least one). A range that is
    /// a point is widened by a tenth of its value (±0.5 at 0); non-finite ends give `[0, 1]`.
    pub fn cover(min: f64, max: f64, count: usize) -> Ticks {
        let (mut min, mut max) = if min.is_finite() && max.is_finite() {
            (min.min(max), min.max(max))
        } else {
            (0.0, 1.0)
        };
        if max - min <= 1e-12 * min.abs().max(1.0) {
            let d = if min == 0.0 { 0.5 } else { 0.1 * min.abs() };
            (min, max) = (min - d, max + d);
        }
        let step = nice_step((max - min) / count.max(1) as f64);
        Ticks {
            lo: (min / step + 1e-9).floor() * step,
            hi: (max / step - 1e-9).ceil() * step,
            step,
        }
    }

    /// The tick values, `lo` first.
    pub fn values(&self) -> Vec<f64> {
        let n = ((self.hi - self.lo) / self.step).round().max(0.0) as usize;
        (0..=n).map(|k| self.lo + self.step * k as f64).collect()
    }
}

/// A tick value with no more digits than it needs (at most three decimals, no `-0`).
pub fn format_tick(v: f64) -> String {
    let t = format!("{v:.3}");
    let t = t.trim_end_matches('0').trim_end_matches('.');
    if t == "-0" {
        "0".to_string()
    } else {
        t.to_string()
    }
}

/// The longest 1, 2 or 5 × 10ⁿ metres not over a fifth of `width_m` (a bar that reads at a
/// glance and never dominates the picture).
pub fn scale_bar_metres(width_m: f64) -> f64 {
    let target = (width_m / 5.0).max(1e-3);
    let base = 10f64.powf(target.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * base)
        .find(|l| *l <= target * (1.0 + 1e-9))
        .unwrap_or(base)
}

/// A metre scale bar for a picture `width_m` metres wide at `scale` pixels per metre: its left
/// end at `x`, its baseline at `y` pixels, labelled.
pub fn scale_bar(s: &mut String, x: f64, y: f64, width_m: f64, scale: f64) {
    let metres = scale_bar_metres(width_m);
    let (x0, x1) = (x, x + metres * scale);
    let label = if metres >= 1.0 {
        format!("{metres:.0} m")
    } else {
        format!("{metres} m")
    };
    let _ = writeln!(
        s,
        r##"<g class="scale-bar" stroke="black" stroke-width="2"><line x1="{x0:.1}" y1="{y:.1}" x2="{x1:.1}" y2="{y:.1}"/><line x1="{x0:.1}" y1="{:.1}" x2="{x0:.1}" y2="{y:.1}"/><line x1="{x1:.1}" y1="{:.1}" x2="{x1:.1}" y2="{y:.1}"/></g><text x="{:.1}" y="{:.1}">{label}</text>"##,
        y - 5.0,
        y - 5.0,
        x1 + 6.0,
        y + 4.0
    );
}

/// The colour of possibility: a cell of possibility `v` is drawn in it at opacity
/// `possibility_level(v) / 10`.
pub const POSSIBILITY_FILL: &str = "#08519c";

/// A possibility in tenths (0 to 10); not finite counts as 0. Tenths are as fine as an eye
/// tells shades apart, and runs of equal shade become one rectangle.
pub fn possibility_level(v: f32) -> u8 {
    if v.is_finite() {
        (v.clamp(0.0, 1.0) * 10.0).round() as u8
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_steps_are_1_2_2half_5() {
        assert_eq!(nice_step(0.0), 1.0);
        assert_eq!(nice_step(f64::NAN), 1.0);
        assert!((nice_step(0.28) - 0.5).abs() < 1e-12);
        assert!((nice_step(1.2) - 2.0).abs() < 1e-12);
        assert!((nice_step(2.0) - 2.0).abs() < 1e-12);
        assert!((nice_step(2.06) - 2.5).abs() < 1e-12);
        assert!((nice_step(7.0) - 10.0).abs() < 1e-12);
    }

    #[test]
    fn ticks_cover_the_range_on_multiples_of_the_step() {
        for (min, max) in [
            (0.0, 1.0),
            (2.13, 2.61),
            (-3.2, 7.9),
            (0.3, 0.3),
            (5.0, 1.0),
        ] {
            let t = Ticks::cover(min, max, 5);
            let (a, b) = (min.min(max), min.max(max));
            assert!(t.lo <= a && t.hi >= b, "{t:?} for {min}..{max}");
            // No more than one step of slack on either side (a point is widened first).
            if b > a {
                assert!(
                    a - t.lo < t.step + 1e-9 && t.hi - b < t.step + 1e-9,
                    "{t:?}"
                );
            }
            let v = t.values();
            assert!(v.len() >= 2 && v.len() <= 12, "{v:?}");
            for x in &v {
                let k = x / t.step;
                assert!(
                    (k - k.round()).abs() < 1e-6,
                    "{x} not a multiple of {}",
                    t.step
                );
            }
        }
        // 2.13..2.61 starts near the data, not at 0.
        assert!(Ticks::cover(2.13, 2.61, 5).lo >= 2.0);
        // A point is widened by a tenth of its size, so a positive value keeps a positive axis.
        assert!(Ticks::cover(0.3, 0.3, 5).lo > 0.0);
        assert_eq!(Ticks::cover(f64::NAN, 1.0, 5), Ticks::cover(0.0, 1.0, 5));
    }

    #[test]
    fn labels_and_bars() {
        assert_eq!(format_tick(2.5), "2.5");
        assert_eq!(format_tick(3.0), "3");
        assert_eq!(format_tick(-0.0001), "0");
        assert_eq!(format_tick(0.125), "0.125");
        assert_eq!(scale_bar_metres(12.2), 2.0);
        assert_eq!(scale_bar_metres(30.0), 5.0);
        assert!((scale_bar_metres(0.9) - 0.1).abs() < 1e-12);
        assert_eq!(possibility_level(0.04), 0);
        assert_eq!(possibility_level(0.96), 10);
        assert_eq!(possibility_level(f32::NAN), 0);
    }
}
