//! A laser log's scans drawn at the poses the log gives them: the picture a floor plan is read
//! off (docs/new-building.md, step 2) and a map's places are checked against. In a corrected
//! log (or one written by your SLAM) those poses are the corrected ones, so the scans add up to
//! the building's walls; in a raw log they are the odometry's and the walls smear as it drifts.
//!
//! Each beam's end point counts a hit in a square cell of `cell` metres; cells with at least
//! `min_hits` hits are drawn (one rectangle per run of them along a row, so the picture stays a
//! few megabytes for a whole floor), under a metre grid labelled in the log's frame — the
//! coordinates a map's `box`, `rotated` and `polygon` extents are written in — with the poses
//! as a line from a green start dot, and the map's place outlines (rotated boxes and polygons
//! as the map reads them, so what is drawn is what ground truth uses) with their names.
//! Beams at or beyond `max_range` are no return ("no return" is coded 32–82 m by the CARMEN
//! logs) and count nothing. Pure: scans in, SVG text out; no I/O. Depends on `io::carmen` for
//! the scan, `map` for the outlines and [`super::axis`] for the grid and the scale bar.
//!
//! # Bounds
//! At most [`MAX_CELLS`] distinct cells are kept (a floor of 140 m × 140 m at 0.1 m); a hit in
//! a further cell is counted in [`ScanPicture::dropped`], never stored. The line of poses keeps
//! at most [`MAX_POSES`] of them, evenly thinned. The picture spans the poses and the map's
//! places, and the hits at most [`REACH`] beyond them (a beam through a window or a glass door
//! hits things far outside).
//!
//! # Complexity
//! `O(n log c)` per scan of `n` beams with `c` cells kept; the picture `O(c)`.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use super::axis::{format_tick, nice_step, scale_bar};
use super::plot::xml_escape;
use super::trajectory::{place_label, LabelBox};
use crate::io::carmen::LaserScan;
use crate::map::{Extent, Map};

/// Most distinct cells a picture keeps.
pub const MAX_CELLS: usize = 2_000_000;

/// Most poses the line of poses keeps.
pub const MAX_POSES: usize = 50_000;

/// How far beyond the poses and the map's places hits are drawn, metres.
pub const REACH: f64 = 10.0;

/// Why a picture cannot be set up.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PictureError {
    /// The cell size is not a finite length of at least a centimetre.
    #[error("cell size {0} m: must be a finite length of at least 0.01 m")]
    Cell(f64),
    /// The no-return range is not finite and positive.
    #[error("maximum range {0} m: must be finite and positive")]
    Range(f64),
}

/// How the picture is drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct PictureStyle {
    /// Least hits for a cell to be drawn (1 draws every hit; 2 or more hides stray beams and
    /// people walking by).
    pub min_hits: u32,
    /// Pixels per metre (values that are not finite and positive fall back to 20).
    pub scale: f64,
    /// The line above the picture.
    pub title: String,
}

/// The hits of the scans added so far, and the poses they were taken from.
#[derive(Debug, Clone)]
pub struct ScanPicture {
    cell: f64,
    max_range: f64,
    /// Hits per cell, keyed (row, column) so that iteration runs along the rows.
    hits: BTreeMap<(i32, i32), u32>,
    poses: Vec<(f64, f64)>,
    /// Keep every `stride`-th pose (doubled whenever the line is full).
    stride: usize,
    scans: usize,
    dropped: u64,
}

impl ScanPicture {
    /// An empty picture with cells of `cell` metres and beams at or beyond `max_range` metres
    /// taken for no return.
    ///
    /// # Errors
    /// [`PictureError`] for a cell under 0.01 m or a range that is not finite and positive.
    pub fn new(cell: f64, max_range: f64) -> Result<ScanPicture, PictureError> {
        if !(cell.is_finite() && cell >= 0.01) {
            return Err(PictureError::Cell(cell));
        }
        if !(max_range.is_finite() && max_range > 0.0) {
            return Err(PictureError::Range(max_range));
        }
        Ok(ScanPicture {
            cell,
            max_range,
            hits: BTreeMap::new(),
            poses: Vec::new(),
            stride: 1,
            scans: 0,
            dropped: 0,
        })
    }

    /// Adds one scan at its logged pose; `laser_offset` is the scanner's forward offset from
    /// the robot's origin (`PARAM robot_frontlaser_offset`). A scan whose pose is not finite is
    /// skipped whole.
    pub fn add(&mut self, scan: &LaserScan, laser_offset: f64) {
        let p = scan.pose;
        if !(p.x.is_finite() && p.y.is_finite() && p.theta.is_finite()) {
            return;
        }
        let offset = if laser_offset.is_finite() {
            laser_offset
        } else {
            0.0
        };
        if self.scans % self.stride == 0 {
            self.poses.push((p.x, p.y));
            if self.poses.len() >= MAX_POSES {
                // Keep every other pose: the line stays evenly thinned and bounded.
                let kept: Vec<(f64, f64)> = self.poses.iter().step_by(2).copied().collect();
                self.poses = kept;
                self.stride *= 2;
            }
        }
        self.scans += 1;
        let (s, c) = p.theta.sin_cos();
        let (sx, sy) = (p.x + c * offset, p.y + s * offset);
        let (first, step) = (scan.first_bearing(), scan.bearing_step());
        for (i, &r) in scan.ranges.iter().enumerate() {
            if !(r.is_finite() && r > 0.0 && r < self.max_range) {
                continue;
            }
            let (bs, bc) = (p.theta + first + step * i as f64).sin_cos();
            self.hit(sx + r * bc, sy + r * bs);
        }
    }

    fn hit(&mut self, x: f64, y: f64) {
        let (col, row) = ((x / self.cell).floor(), (y / self.cell).floor());
        let limit = f64::from(i32::MAX);
        if !(col.abs() < limit && row.abs() < limit) {
            self.dropped += 1;
            return;
        }
        let key = (row as i32, col as i32);
        if let Some(n) = self.hits.get_mut(&key) {
            *n = n.saturating_add(1);
        } else if self.hits.len() < MAX_CELLS {
            self.hits.insert(key, 1);
        } else {
            self.dropped += 1;
        }
    }

    /// Scans added (those with a finite pose).
    pub fn scans(&self) -> usize {
        self.scans
    }

    /// Hits left out: beyond [`MAX_CELLS`] distinct cells, or too far out to index.
    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    /// The centres (metres, x and y) of the cells with at least `min_hits` hits, row by row.
    pub fn occupied(&self, min_hits: u32) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.hits
            .iter()
            .filter(move |(_, &n)| n >= min_hits)
            .map(|(&(row, col), _)| {
                (
                    (f64::from(col) + 0.5) * self.cell,
                    (f64::from(row) + 0.5) * self.cell,
                )
            })
    }

    /// The picture as an SVG document, with `map`'s places over the scans when given.
    pub fn svg(&self, map: Option<&Map>, style: &PictureStyle) -> String {
        let scale = if style.scale.is_finite() && style.scale > 0.0 {
            style.scale
        } else {
            20.0
        };
        let (x0, y0, x1, y1) = self.bounds(map, style.min_hits);
        let c = Canvas {
            x0,
            y1,
            scale,
            left: 44.0,
            top: 58.0,
        };
        let (w, h) = (c.px(x1) + 16.0, c.py(y0) + 40.0);
        let mut s = String::new();
        // Writing to a String cannot fail; the results are ignored for that reason.
        let _ = writeln!(
            s,
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.1} {h:.1}" font-family="sans-serif" font-size="11">"##
        );
        let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="white"/>"##);
        let _ = writeln!(
            s,
            r##"<text x="8" y="16" font-size="14">{}</text><text x="8" y="32">metres in the log's frame; black: cells of {} m hit by at least {} beam(s); red: the poses, from the green dot</text>"##,
            xml_escape(&style.title),
            format_tick(self.cell),
            style.min_hits
        );
        grid(&mut s, &c, (x0, y0, x1, y1));
        self.draw_hits(&mut s, &c, style.min_hits, (x0, y0, x1, y1));
        self.draw_poses(&mut s, &c);
        if let Some(map) = map {
            draw_places(&mut s, map, &c);
        }
        scale_bar(&mut s, c.left, h - 16.0, x1 - x0, scale);
        s.push_str("</svg>\n");
        s
    }

    /// Runs of drawn cells along each row, one rectangle each; cells outside `(x0, y0, x1, y1)`
    /// are left out.
    fn draw_hits(&self, s: &mut String, c: &Canvas, min_hits: u32, area: (f64, f64, f64, f64)) {
        let (x0, y0, x1, y1) = area;
        let outside = |row: i32, col: i32| {
            let (x, y) = (f64::from(col) * self.cell, f64::from(row) * self.cell);
            x < x0 || x + self.cell > x1 || y < y0 || y + self.cell > y1
        };
        let _ = writeln!(s, r##"<g class="hits" fill="#222">"##);
        let mut run: Option<(i32, i32, i32)> = None; // (row, first column, last column)
        let flush = |s: &mut String, run: (i32, i32, i32)| {
            let (row, a, b) = run;
            let x = f64::from(a) * self.cell;
            let top = f64::from(row + 1) * self.cell;
            let _ = writeln!(
                s,
                r##"<rect x="{:.1}" y="{:.1}" width="{:.2}" height="{:.2}"/>"##,
                c.px(x),
                c.py(top),
                f64::from(b - a + 1) * self.cell * c.scale,
                self.cell * c.scale
            );
        };
        for (&(row, col), &n) in &self.hits {
            if n < min_hits || outside(row, col) {
                continue;
            }
            run = match run {
                Some((r, a, b)) if r == row && b.checked_add(1) == Some(col) => Some((r, a, col)),
                Some(done) => {
                    flush(s, done);
                    Some((row, col, col))
                }
                None => Some((row, col, col)),
            };
        }
        if let Some(done) = run {
            flush(s, done);
        }
        s.push_str("</g>\n");
    }

    fn draw_poses(&self, s: &mut String, c: &Canvas) {
        let Some(&(sx, sy)) = self.poses.first() else {
            return;
        };
        let _ = write!(
            s,
            r##"<polyline class="poses" fill="none" stroke="#d7191c" stroke-opacity="0.6" stroke-width="1" points=""##
        );
        for &(x, y) in &self.poses {
            let _ = write!(s, "{:.1},{:.1} ", c.px(x), c.py(y));
        }
        s.push_str("\"/>\n");
        let _ = writeln!(
            s,
            r##"<circle cx="{:.1}" cy="{:.1}" r="4" fill="#1a9641"/>"##,
            c.px(sx),
            c.py(sy)
        );
    }

    /// The box `(x0, y0, x1, y1)` drawn: the poses and the map's places, with the drawn cells
    /// at most [`REACH`] beyond them (a beam through a window or a glass door hits things far
    /// outside the building), grown by half a metre; the unit square when there is nothing.
    fn bounds(&self, map: Option<&Map>, min_hits: u32) -> (f64, f64, f64, f64) {
        let mut inner = Bounds::default();
        for &(x, y) in &self.poses {
            inner.grow(x, y);
        }
        for p in map.map(Map::places).unwrap_or(&[]) {
            match p.extent {
                Extent::Radius(r) => {
                    inner.grow(p.pose.0 - r, p.pose.1 - r);
                    inner.grow(p.pose.0 + r, p.pose.1 + r);
                }
                Extent::Box { x0, y0, x1, y1 } => {
                    inner.grow(x0, y0);
                    inner.grow(x1, y1);
                }
            }
        }
        let reach = inner
            .0
            .map(|(x0, y0, x1, y1)| (x0 - REACH, y0 - REACH, x1 + REACH, y1 + REACH));
        let mut all = Bounds(inner.0);
        for (x, y) in self.occupied(min_hits) {
            let inside = reach.map_or(true, |(x0, y0, x1, y1)| {
                (x0..=x1).contains(&x) && (y0..=y1).contains(&y)
            });
            if inside {
                all.grow(x - self.cell, y - self.cell);
                all.grow(x + self.cell, y + self.cell);
            }
        }
        match all.0 {
            Some((x0, y0, x1, y1)) => (x0 - 0.5, y0 - 0.5, x1 + 0.5, y1 + 0.5),
            None => (0.0, 0.0, 1.0, 1.0),
        }
    }
}

/// A running bounding box of finite points.
#[derive(Default)]
struct Bounds(Option<(f64, f64, f64, f64)>);

impl Bounds {
    fn grow(&mut self, x: f64, y: f64) {
        if !(x.is_finite() && y.is_finite()) {
            return;
        }
        self.0 = Some(match self.0 {
            None => (x, y, x, y),
            Some((x0, y0, x1, y1)) => (x0.min(x), y0.min(y), x1.max(x), y1.max(y)),
        });
    }
}

/// Metres to pixels: `x0` and `y1` are the drawn area's left and top edges (metres), `left`
/// and `top` the pixels before them; y is flipped.
struct Canvas {
    x0: f64,
    y1: f64,
    scale: f64,
    left: f64,
    top: f64,
}

impl Canvas {
    fn px(&self, x: f64) -> f64 {
        (x - self.x0) * self.scale + self.left
    }

    fn py(&self, y: f64) -> f64 {
        (self.y1 - y) * self.scale + self.top
    }
}

/// A metre grid over `(x0, y0, x1, y1)`: faint lines at least 10 px and 1 m apart, darker
/// labelled ones at least 60 px apart, labelled along the top and left edges.
fn grid(s: &mut String, c: &Canvas, (x0, y0, x1, y1): (f64, f64, f64, f64)) {
    let minor = nice_step((10.0 / c.scale).max(1.0));
    let major = nice_step((60.0 / c.scale).max(minor));
    let lines = |lo: f64, hi: f64, step: f64| {
        let first = (lo / step).ceil() as i64;
        let last = (hi / step).floor() as i64;
        (first..=last).map(move |k| k as f64 * step)
    };
    let _ = writeln!(s, r##"<g class="grid" stroke="#ddd" stroke-width="0.5">"##);
    for (step, colour) in [(minor, "#e6e6e6"), (major, "#aaa")] {
        for x in lines(x0, x1, step) {
            let _ = writeln!(
                s,
                r##"<line x1="{0:.1}" y1="{1:.1}" x2="{0:.1}" y2="{2:.1}" stroke="{colour}"/>"##,
                c.px(x),
                c.py(y1),
                c.py(y0)
            );
        }
        for y in lines(y0, y1, step) {
            let _ = writeln!(
                s,
                r##"<line x1="{1:.1}" y1="{0:.1}" x2="{2:.1}" y2="{0:.1}" stroke="{colour}"/>"##,
                c.py(y),
                c.px(x0),
                c.px(x1)
            );
        }
    }
    s.push_str("</g>\n");
    for x in lines(x0, x1, major) {
        let _ = writeln!(
            s,
            r##"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"##,
            c.px(x),
            c.top - 4.0,
            format_tick(x)
        );
    }
    for y in lines(y0, y1, major) {
        let _ = writeln!(
            s,
            r##"<text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"##,
            c.left - 4.0,
            c.py(y) + 4.0,
            format_tick(y)
        );
    }
}

/// The places' outlines (the rotated box or polygon when there is one, else the extent) and
/// their names, in blue over the scans.
fn draw_places(s: &mut String, map: &Map, c: &Canvas) {
    let _ = writeln!(
        s,
        r##"<g class="places" fill="#2171b5" fill-opacity="0.08" stroke="#2171b5" stroke-width="1.2">"##
    );
    for p in map.places() {
        match (&p.outline, p.extent) {
            (Some(o), _) => {
                let _ = write!(s, r##"<polygon points=""##);
                for &(x, y) in &o.vertices {
                    let _ = write!(s, "{:.1},{:.1} ", c.px(x), c.py(y));
                }
                s.push_str("\"/>\n");
            }
            (None, Extent::Box { x0, y0, x1, y1 }) => {
                let _ = writeln!(
                    s,
                    r##"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}"/>"##,
                    c.px(x0),
                    c.py(y1),
                    (x1 - x0) * c.scale,
                    (y1 - y0) * c.scale
                );
            }
            (None, Extent::Radius(r)) => {
                let _ = writeln!(
                    s,
                    r##"<circle cx="{:.1}" cy="{:.1}" r="{:.1}"/>"##,
                    c.px(p.pose.0),
                    c.py(p.pose.1),
                    r * c.scale
                );
            }
        }
    }
    s.push_str("</g>\n");
    let mut placed: Vec<LabelBox> = Vec::new();
    for p in map.places() {
        let b = place_label(c.px(p.pose.0), c.py(p.pose.1), &p.name, &placed);
        let _ = writeln!(
            s,
            r##"<text class="place-label" x="{:.1}" y="{:.1}" text-anchor="middle" fill="#08306b" font-weight="bold">{}</text>"##,
            b.x,
            b.y,
            xml_escape(&p.name)
        );
        placed.push(b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::Pose2;
    use std::f64::consts::PI;

    /// The range from `(x, y)` along `angle` to the inside of the box `[0, w] × [0, h]`.
    fn range_in_box(x: f64, y: f64, angle: f64, w: f64, h: f64) -> f64 {
        let (s, c) = angle.sin_cos();
        let mut t = f64::INFINITY;
        if c > 1e-12 {
            t = t.min((w - x) / c);
        }
        if c < -1e-12 {
            t = t.min(-x / c);
        }
        if s > 1e-12 {
            t = t.min((h - y) / s);
        }
        if s < -1e-12 {
            t = t.min(-y / s);
        }
        t
    }

    /// A 180-beam scan taken at `pose` inside the box, as a laser `offset` ahead of the origin.
    fn scan_in_box(pose: Pose2, offset: f64, w: f64, h: f64) -> LaserScan {
        let mut scan = LaserScan {
            ranges: Vec::new(),
            pose,
            odom_pose: pose,
            timestamp: 0.0,
        };
        let (sx, sy) = (
            pose.x + offset * pose.theta.cos(),
            pose.y + offset * pose.theta.sin(),
        );
        let step = crate::io::carmen::beam_step(180);
        scan.ranges = (0..180)
            .map(|i| range_in_box(sx, sy, pose.theta - PI / 2.0 + step * i as f64, w, h))
            .collect();
        scan
    }

    fn distance_to_walls(x: f64, y: f64, w: f64, h: f64) -> f64 {
        x.abs().min((w - x).abs()).min(y.abs()).min((h - y).abs())
    }

    #[test]
    fn the_hits_of_scans_in_a_room_lie_on_its_walls_and_cover_them() {
        let (w, h) = (6.0, 4.0);
        let mut pic = ScanPicture::new(0.1, 30.0).unwrap();
        // Four scans facing each way from points inside, the laser 0.2 m ahead.
        for (k, theta) in [0.0, PI / 2.0, PI, -PI / 2.0].into_iter().enumerate() {
            let pose = Pose2::new(2.0 + 0.5 * k as f64, 1.5 + 0.3 * k as f64, theta);
            pic.add(&scan_in_box(pose, 0.2, w, h), 0.2);
        }
        assert_eq!(pic.scans(), 4);
        let cells: Vec<(f64, f64)> = pic.occupied(1).collect();
        assert!(!cells.is_empty());
        // Every cell's centre is within half a diagonal of a wall (the end point is in it).
        for &(x, y) in &cells {
            assert!(distance_to_walls(x, y, w, h) <= 0.0708, "({x}, {y})");
        }
        // Every 0.5 m of each wall has a hit near it: the four scans together see all around.
        let near = |px: f64, py: f64| {
            cells
                .iter()
                .any(|&(x, y)| (x - px).abs() < 0.3 && (y - py).abs() < 0.3)
        };
        for k in 0..=12 {
            let x = 0.5 * k as f64;
            assert!(near(x, 0.0) && near(x, h), "x = {x}");
        }
        for k in 0..=8 {
            let y = 0.5 * k as f64;
            assert!(near(0.0, y) && near(w, y), "y = {y}");
        }
    }

    #[test]
    fn no_returns_and_bad_poses_count_nothing() {
        let mut pic = ScanPicture::new(0.1, 30.0).unwrap();
        let mut scan = scan_in_box(Pose2::new(1.0, 1.0, 0.0), 0.0, 3.0, 3.0);
        for r in scan.ranges.iter_mut().step_by(2) {
            *r = 81.91;
        }
        scan.ranges[1] = f64::NAN;
        scan.ranges[3] = -1.0;
        pic.add(&scan, 0.0);
        let counted: u32 = pic.hits.values().sum();
        // Odd beams only, less the two made invalid.
        assert_eq!(counted, 90 - 2);
        let before = pic.hits.clone();
        scan.pose = Pose2::new(f64::NAN, 0.0, 0.0);
        pic.add(&scan, 0.0);
        assert_eq!(pic.hits, before);
        assert_eq!(pic.scans(), 1);
    }

    #[test]
    fn cells_are_bounded_and_far_hits_dropped() {
        let mut pic = ScanPicture::new(0.01, 1e30).unwrap();
        let scan = LaserScan {
            ranges: vec![1e20; 3],
            pose: Pose2::new(0.0, 0.0, 0.0),
            odom_pose: Pose2::new(0.0, 0.0, 0.0),
            timestamp: 0.0,
        };
        pic.add(&scan, 0.0);
        assert_eq!(pic.dropped(), 3);
        assert!(pic.hits.is_empty());
        assert!(pic.svg(None, &style(1)).starts_with("<svg"));
    }

    fn style(min_hits: u32) -> PictureStyle {
        PictureStyle {
            min_hits,
            scale: 20.0,
            title: "t <&>".to_string(),
        }
    }

    #[test]
    fn runs_along_a_row_are_one_rectangle_each_and_the_title_is_escaped() {
        let mut pic = ScanPicture::new(0.5, 30.0).unwrap();
        // Row 0: columns 0, 1, 2 and 5 (two runs); row 2: column 1 twice (min_hits 2 keeps it).
        for (x, y) in [
            (0.1, 0.1),
            (0.6, 0.1),
            (1.1, 0.1),
            (2.6, 0.1),
            (0.6, 1.1),
            (0.7, 1.2),
        ] {
            pic.hit(x, y);
        }
        let one = pic.svg(None, &style(1));
        let hits = |svg: &str| {
            let g = svg.split(r#"<g class="hits""#).nth(1).unwrap_or("");
            let g = g.split("</g>").next().unwrap_or("");
            g.matches("<rect").count()
        };
        assert_eq!(hits(&one), 3);
        assert_eq!(hits(&pic.svg(None, &style(2))), 1);
        assert!(one.contains("t &lt;&amp;&gt;"));
        // The same hits give the same text.
        assert_eq!(one, pic.svg(None, &style(1)));
    }

    #[test]
    fn bad_settings_are_errors() {
        assert_eq!(
            ScanPicture::new(0.0, 30.0).unwrap_err(),
            PictureError::Cell(0.0)
        );
        assert!(matches!(
            ScanPicture::new(0.1, f64::INFINITY),
            Err(PictureError::Range(_))
        ));
    }

    #[test]
    fn the_poses_line_stays_bounded_and_keeps_the_start() {
        let mut pic = ScanPicture::new(0.1, 30.0).unwrap();
        let scan = |k: usize| LaserScan {
            ranges: vec![],
            pose: Pose2::new(k as f64 * 0.01, 0.0, 0.0),
            odom_pose: Pose2::new(0.0, 0.0, 0.0),
            timestamp: 0.0,
        };
        for k in 0..(3 * MAX_POSES) {
            pic.add(&scan(k), 0.0);
        }
        assert!(pic.poses.len() < MAX_POSES);
        assert!(pic.poses.len() >= MAX_POSES / 4);
        assert_eq!(pic.poses[0], (0.0, 0.0));
        assert_eq!(pic.scans(), 3 * MAX_POSES);
    }
}
