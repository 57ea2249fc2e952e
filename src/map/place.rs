//! Places, rooms and landmarks of the map model, with the per-place lookups (walls, corners,
//! parameters, extent membership). Depends only on `syntax::span` (to point back at the map file).

use super::outline::Outline;
use crate::syntax::span::Span;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Radius in metres of a place written without `extent`: a disc of 0.5 m around its pose.
pub const DEFAULT_RADIUS: f64 = 0.5;

/// The region of the metric frame a place covers.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Extent {
    /// A disc of this radius (metres) around the place's position.
    Radius(f64),
    /// An axis-aligned box.
    Box {
        /// Lower x.
        x0: f64,
        /// Lower y.
        y0: f64,
        /// Upper x.
        x1: f64,
        /// Upper y.
        y1: f64,
    },
}

/// A value a place expects: one number, or a range of equally expected values (`lo .. hi`,
/// written `param free(North) = 0.4 .. 1.9;`), as a place that is a whole corridor expects
/// different readings along its length. A similarity compares a reading with it by the
/// distance to the nearest point of the range (see [`crate::logic::Similarity::degree_within`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Expected {
    /// Lower end (the value itself for a single number).
    pub lo: f64,
    /// Upper end, `≥ lo`.
    pub hi: f64,
}

impl Expected {
    /// A single expected value.
    pub fn value(v: f64) -> Expected {
        Expected { lo: v, hi: v }
    }

    /// The middle of the range.
    pub fn centre(&self) -> f64 {
        0.5 * (self.lo + self.hi)
    }

    /// Half the range's width (0 for a single value).
    pub fn half_width(&self) -> f64 {
        0.5 * (self.hi - self.lo)
    }
}

/// A place of the map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Place {
    /// Name (`P0`).
    pub name: String,
    /// Kind word (`corner`, `doorway`, …).
    pub kind: String,
    /// Index of its room, if it is in one.
    pub room: Option<usize>,
    /// Approximate pose: x, y in metres, optional heading in degrees.
    pub pose: (f64, f64, Option<f64>),
    /// Region covered; [`Extent::Radius`]`(`[`DEFAULT_RADIUS`]`)` when the file gives none.
    /// For a rotated box or a polygon, the bounding box of [`Place::outline`].
    pub extent: Extent,
    /// The exact region when it is a rotated box or a polygon (membership reads it).
    pub outline: Option<Outline>,
    /// Walls by direction, with their degree (a `door D` line implies `wall D`).
    pub walls: BTreeMap<String, f64>,
    /// Directions written `open D` (nothing blocks the view), with their degree.
    pub opens: BTreeMap<String, f64>,
    /// Directions written `door D` (an opening in the wall that way), with their degree.
    pub doors: BTreeMap<String, f64>,
    /// Corners by (direction, direction) with the two names in sorted order, with their degree.
    pub corners: BTreeMap<(String, String), f64>,
    /// Parameters by (name, key).
    pub params: BTreeMap<(String, Option<String>), Expected>,
    /// The place's declaration in the map file.
    #[serde(skip)]
    pub span: Span,
    /// Every direction written in a `wall` or `corner` line, with its span (for cross-checking
    /// against the rule file's `Dir` domain).
    #[serde(skip)]
    pub direction_spans: Vec<(String, Span)>,
}

impl Place {
    /// Degree of the wall towards `dir` (0 when none).
    pub fn wall(&self, dir: &str) -> f64 {
        self.walls.get(dir).copied().unwrap_or(0.0)
    }

    /// Degree of the corner between `d1` and `d2`, in either order (0 when none).
    pub fn corner(&self, d1: &str, d2: &str) -> f64 {
        let key = corner_key(d1, d2);
        self.corners.get(&key).copied().unwrap_or(0.0)
    }

    /// A parameter written explicitly in the place's body (the middle of a range).
    pub fn param(&self, name: &str, key: Option<&str>) -> Option<f64> {
        self.expected(name, key).map(|e| e.centre())
    }

    /// A parameter written explicitly in the place's body, as the value or range written.
    pub fn expected(&self, name: &str, key: Option<&str>) -> Option<Expected> {
        self.params
            .get(&(name.to_string(), key.map(str::to_string)))
            .copied()
    }

    /// Degree of `open D` towards `dir` (0 when none).
    pub fn open(&self, dir: &str) -> f64 {
        self.opens.get(dir).copied().unwrap_or(0.0)
    }

    /// Degree of `door D` towards `dir` (0 when none).
    pub fn door(&self, dir: &str) -> f64 {
        self.doors.get(dir).copied().unwrap_or(0.0)
    }

    /// True if the point `(x, y)` lies in the place's extent (boundary included).
    pub fn contains(&self, x: f64, y: f64) -> bool {
        if let Some(o) = &self.outline {
            return o.contains(x, y);
        }
        match self.extent {
            Extent::Radius(r) => (x - self.pose.0).hypot(y - self.pose.1) <= r,
            Extent::Box { x0, y0, x1, y1 } => x0 <= x && x <= x1 && y0 <= y && y <= y1,
        }
    }
}

/// The order-insensitive key of a corner.
pub(crate) fn corner_key(d1: &str, d2: &str) -> (String, String) {
    if d1 <= d2 {
        (d1.to_string(), d2.to_string())
    } else {
        (d2.to_string(), d1.to_string())
    }
}

/// A room: a named group of places.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Room {
    /// Name (`R0`).
    pub name: String,
    /// Free-text label.
    pub label: Option<String>,
    /// Indices of its places, in id order.
    pub places: Vec<usize>,
}

/// A beacon or landmark.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Landmark {
    /// Name (`B0`, `Yellow`).
    pub name: String,
    /// True when declared with `beacon` (paper 003's structured beacon).
    pub beacon: bool,
    /// Position in metres.
    pub position: (f64, f64),
    /// Identifier the sensors report.
    pub id: Option<i64>,
}
