//! The metric grid tracker's belief plane at a few moments of a run, and its picture.
//!
//! [`BeliefSampler`] keeps at most [`MAX_SNAPSHOTS`] copies of the plane, evenly spread over
//! the run without knowing its length in advance: it copies every `stride`-th frame and, when
//! full, drops every other copy and doubles the stride (so memory is bounded on any length).
//! The last frame's plane is added at the end. [`svg`] draws one copy: the cells shaded by
//! their possibility, the place extents outlined and named, the true position marked.

use std::fmt::Write as _;

use crate::engine::grid_tracker::GridTracker;
use crate::map::{Extent, Map};
use crate::report::axis::{possibility_level, POSSIBILITY_FILL};
use crate::report::plot::xml_escape;

/// Most belief planes kept per run (the last frame's comes on top).
pub const MAX_SNAPSHOTS: usize = 5;

/// Widest picture of a plane, pixels.
const MAX_WIDTH: f64 = 560.0;

/// The belief plane of one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct BeliefSnapshot {
    /// 1-based line of the frame in its stream.
    pub line: u64,
    /// The frame's time, seconds, if given.
    pub t: Option<f64>,
    /// Cells along x and y.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
    /// Cell side, metres.
    pub cell: f64,
    /// Lower-left corner of the grid, metres.
    pub origin: (f64, f64),
    /// Possibility per cell, row-major from the lower-left corner.
    pub belief: Vec<f32>,
    /// The true position, metres, if the frame has one.
    pub truth: Option<(f64, f64)>,
    /// The place decided at this frame, by name; `None` when disoriented.
    pub decided: Option<String>,
}

impl BeliefSnapshot {
    /// A copy of `grid`'s plane, taken after the frame at `line` was stepped.
    pub fn of(
        grid: &GridTracker,
        line: u64,
        t: Option<f64>,
        truth: Option<(f64, f64)>,
        decided: Option<String>,
    ) -> BeliefSnapshot {
        let (nx, ny, cell, origin) = grid.geometry();
        BeliefSnapshot {
            line,
            t,
            nx,
            ny,
            cell,
            origin,
            belief: grid.belief().to_vec(),
            truth,
            decided,
        }
    }
}

/// Evenly spread copies of the belief plane over a run of unknown length.
#[derive(Debug, Clone)]
pub struct BeliefSampler {
    kept: Vec<BeliefSnapshot>,
    stride: u64,
    frames: u64,
}

impl Default for BeliefSampler {
    fn default() -> Self {
        BeliefSampler {
            kept: Vec::new(),
            stride: 1,
            frames: 0,
        }
    }
}

impl BeliefSampler {
    /// Whether the next frame is one to copy (call once per frame, before [`Self::push`]).
    pub fn wants_next(&mut self) -> bool {
        let wanted = self.frames % self.stride == 0;
        self.frames += 1;
        wanted
    }

    /// Keeps a copy asked for by [`Self::wants_next`].
    pub fn push(&mut self, snapshot: BeliefSnapshot) {
        if self.kept.len() == MAX_SNAPSHOTS {
            // Frames 0, s, 2s, … are kept; after this, 0, 2s, 4s, … and the stride is 2s.
            let mut i = 0;
            self.kept.retain(|_| {
                i += 1;
                i % 2 == 1
            });
            self.stride *= 2;
            if (self.frames - 1) % self.stride != 0 {
                return;
            }
        }
        self.kept.push(snapshot);
    }

    /// The copies in frame order, with `last` (the final frame's plane) appended unless it is
    /// the last copy already.
    pub fn finish(mut self, last: Option<BeliefSnapshot>) -> Vec<BeliefSnapshot> {
        if let Some(l) = last {
            if self.kept.last().map(|k| k.line) != Some(l.line) {
                self.kept.push(l);
            }
        }
        self.kept
    }
}

/// The plane as an SVG picture over `map`'s place extents. The colour of a cell is its
/// possibility (white 0 to dark blue 1, in tenths); the true position is a red ring.
pub fn svg(snap: &BeliefSnapshot, map: &Map) -> String {
    let (nx, ny) = (snap.nx.max(1), snap.ny.max(1));
    let px = (MAX_WIDTH / nx as f64).clamp(1.0, 12.0);
    let cell = if snap.cell.is_finite() && snap.cell > 0.0 {
        snap.cell
    } else {
        1.0
    };
    // Map metres to the picture's cell units, y up.
    let to_x = |x: f64| (x - snap.origin.0) / cell;
    let to_y = |y: f64| ny as f64 - (y - snap.origin.1) / cell;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r##"<svg xmlns="http://www.w3.org/2000/svg" class="belief" width="{:.0}" height="{:.0}" viewBox="0 0 {nx} {ny}" font-family="sans-serif">"##,
        nx as f64 * px,
        ny as f64 * px
    );
    let _ = writeln!(
        s,
        r##"<rect width="{nx}" height="{ny}" fill="white" stroke="#bbbbbb" stroke-width="{:.3}"/>"##,
        1.0 / px
    );
    cells(&mut s, snap, nx, ny);
    let stroke = 1.0 / px;
    let font = (10.0 / px).max(0.5);
    for p in map.places() {
        let (x, y) = (to_x(p.pose.0), to_y(p.pose.1));
        match p.extent {
            Extent::Box { x0, y0, x1, y1 } => {
                let (a, b) = (to_x(x0.min(x1)), to_y(y0.max(y1)));
                let (w, h) = ((x1 - x0).abs() / cell, (y1 - y0).abs() / cell);
                let _ = writeln!(
                    s,
                    r##"<rect x="{a:.2}" y="{b:.2}" width="{w:.2}" height="{h:.2}" fill="none" stroke="#555555" stroke-width="{stroke:.3}"/>"##
                );
            }
            Extent::Radius(r) => {
                let _ = writeln!(
                    s,
                    r##"<circle cx="{x:.2}" cy="{y:.2}" r="{:.2}" fill="none" stroke="#555555" stroke-width="{stroke:.3}"/>"##,
                    r.max(0.0) / cell
                );
            }
        }
        let _ = writeln!(
            s,
            r##"<text x="{x:.2}" y="{y:.2}" font-size="{font:.2}" text-anchor="middle" fill="#333333">{}</text>"##,
            xml_escape(&p.name)
        );
    }
    if let Some((x, y)) = snap.truth {
        if x.is_finite() && y.is_finite() {
            let _ = writeln!(
                s,
                r##"<circle cx="{:.2}" cy="{:.2}" r="{:.2}" fill="none" stroke="#d7191c" stroke-width="{:.3}"/>"##,
                to_x(x),
                to_y(y),
                5.0 / px,
                2.0 / px
            );
        }
    }
    s.push_str("</svg>\n");
    s
}

/// The shaded cells, one rectangle per horizontal run of cells of one shade.
fn cells(s: &mut String, snap: &BeliefSnapshot, nx: usize, ny: usize) {
    let shade = possibility_level;
    for row in 0..ny {
        let mut col = 0;
        while col < nx {
            let level = shade(snap.belief.get(row * nx + col).copied().unwrap_or(0.0));
            let start = col;
            while col < nx
                && shade(snap.belief.get(row * nx + col).copied().unwrap_or(0.0)) == level
            {
                col += 1;
            }
            if level > 0 {
                let _ = writeln!(
                    s,
                    r##"<rect x="{start}" y="{}" width="{}" height="1" fill="{POSSIBILITY_FILL}" fill-opacity="{:.1}"/>"##,
                    ny - 1 - row,
                    col - start,
                    f64::from(level) / 10.0
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn snap(line: u64) -> BeliefSnapshot {
        BeliefSnapshot {
            line,
            t: None,
            nx: 2,
            ny: 1,
            cell: 1.0,
            origin: (0.0, 0.0),
            belief: vec![0.0, 1.0],
            truth: None,
            decided: None,
        }
    }

    /// Feeds `n` frames (line = frame index) and returns the lines kept.
    fn kept_after(n: u64) -> Vec<u64> {
        let mut s = BeliefSampler::default();
        for f in 0..n {
            if s.wants_next() {
                s.push(snap(f));
            }
        }
        s.finish(None).iter().map(|k| k.line).collect()
    }

    #[test]
    fn sampler_spreads_copies_evenly_and_stays_bounded() {
        // Worked by hand: 5 fit at stride 1; the 6th (frame 5) halves to {0, 2, 4} at stride
        // 2 and frame 5 is not a multiple of 2, so it is dropped; frames 6 and 8 fill up to 5;
        // frame 10 halves to {0, 4, 8} at stride 4; then 12, 16; frame 20 halves to {0, 8, 16}.
        assert_eq!(kept_after(5), vec![0, 1, 2, 3, 4]);
        assert_eq!(kept_after(6), vec![0, 2, 4]);
        assert_eq!(kept_after(10), vec![0, 2, 4, 6, 8]);
        assert_eq!(kept_after(11), vec![0, 4, 8]);
        assert_eq!(kept_after(21), vec![0, 8, 16]);
        for n in [1, 7, 100, 10_000] {
            let k = kept_after(n);
            assert!(!k.is_empty() && k.len() <= MAX_SNAPSHOTS, "{n}: {k:?}");
            assert!(k.windows(2).all(|w| w[0] < w[1]));
        }
    }

    #[test]
    fn the_last_frame_is_added_once() {
        let s = BeliefSampler::default();
        let got = s.finish(Some(snap(9)));
        assert_eq!(got.len(), 1);
        let mut s = BeliefSampler::default();
        assert!(s.wants_next());
        s.push(snap(0));
        assert_eq!(s.finish(Some(snap(0))).len(), 1);
    }

    #[test]
    fn cells_are_run_length_shaded() {
        let mut s = String::new();
        let mut b = snap(0);
        b.nx = 4;
        b.belief = vec![1.0, 1.0, 0.0, f32::NAN];
        cells(&mut s, &b, 4, 1);
        // One run of two full cells; the zero and the NaN draw nothing.
        assert_eq!(s.matches("<rect").count(), 1, "{s}");
        assert!(s.contains(r#"x="0" y="0" width="2""#), "{s}");
        assert!(s.contains(r#"fill-opacity="1.0""#), "{s}");
    }
}
