//! Place outlines that are not axis-aligned boxes: boxes turned about their centre and polygons.
//! A place with an outline keeps its bounding box as its [`Extent`](super::Extent) (what the
//! metric trackers lay cells over) and answers membership by the outline itself. Checks a
//! polygon can fail on its own: not closed, fewer than three distinct corners or no area, edges
//! that cross.

use crate::syntax::diagnostic::DiagnosticKind;

/// A closed outline: its vertices in order, the closing vertex not repeated.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Outline {
    /// Vertices in order around the outline.
    pub vertices: Vec<(f64, f64)>,
}

impl Outline {
    /// The box `(x0, y0, x1, y1)` turned by `degrees` counter-clockwise about its centre.
    pub fn rotated_box(x0: f64, y0: f64, x1: f64, y1: f64, degrees: f64) -> Outline {
        let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let (s, c) = degrees.to_radians().sin_cos();
        let turn = |x: f64, y: f64| {
            let (dx, dy) = (x - cx, y - cy);
            (cx + c * dx - s * dy, cy + s * dx + c * dy)
        };
        Outline {
            vertices: vec![turn(x0, y0), turn(x1, y0), turn(x1, y1), turn(x0, y1)],
        }
    }

    /// The outline of a polygon written with its first vertex repeated at the end, or what is
    /// wrong with it.
    pub fn polygon(written: &[(f64, f64)]) -> Result<Outline, DiagnosticKind> {
        let (Some(&first), Some(&last)) = (written.first(), written.last()) else {
            return Err(DiagnosticKind::DegeneratePolygon { count: 0 });
        };
        if written.len() < 2 || first != last {
            return Err(DiagnosticKind::PolygonNotClosed {
                x0: first.0,
                y0: first.1,
                x1: last.0,
                y1: last.1,
            });
        }
        let mut vertices: Vec<(f64, f64)> = written[..written.len() - 1].to_vec();
        vertices.dedup();
        let outline = Outline { vertices };
        let n = outline.vertices.len();
        if n < 3 || outline.area() <= 0.0 {
            return Err(DiagnosticKind::DegeneratePolygon { count: n });
        }
        if let Some((a, b)) = outline.crossing() {
            return Err(DiagnosticKind::SelfCrossingPolygon {
                first: a + 1,
                second: b + 1,
            });
        }
        Ok(outline)
    }

    /// The unsigned area (shoelace formula).
    pub fn area(&self) -> f64 {
        let n = self.vertices.len();
        let twice: f64 = (0..n)
            .map(|i| {
                let (a, b) = (self.vertices[i], self.vertices[(i + 1) % n]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum();
        0.5 * twice.abs()
    }

    /// The smallest axis-aligned box `(x0, y0, x1, y1)` holding the outline.
    pub fn bounds(&self) -> (f64, f64, f64, f64) {
        self.vertices.iter().fold(
            (
                f64::INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
            ),
            |(x0, y0, x1, y1), &(x, y)| (x0.min(x), y0.min(y), x1.max(x), y1.max(y)),
        )
    }

    /// True if `(x, y)` is inside the outline or on its boundary.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        let n = self.vertices.len();
        let mut inside = false;
        for i in 0..n {
            let (a, b) = (self.vertices[i], self.vertices[(i + 1) % n]);
            if on_segment(a, b, (x, y)) {
                return true;
            }
            // Crossing count of a ray towards +x; the half-open test on y counts a vertex once.
            if (a.1 > y) != (b.1 > y) {
                let xc = a.0 + (y - a.1) * (b.0 - a.0) / (b.1 - a.1);
                if x < xc {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// The first pair of non-adjacent edges (by index; edge `i` runs from vertex `i` to the
    /// next) that touch or cross, if any.
    fn crossing(&self) -> Option<(usize, usize)> {
        let n = self.vertices.len();
        let edge = |i: usize| (self.vertices[i], self.vertices[(i + 1) % n]);
        for i in 0..n {
            for j in i + 1..n {
                let adjacent = j == i + 1 || (i == 0 && j == n - 1);
                if !adjacent && segments_meet(edge(i), edge(j)) {
                    return Some((i, j));
                }
            }
        }
        None
    }
}

/// Twice the signed area of the triangle `a b c` (positive when counter-clockwise).
fn orient(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> f64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

fn on_segment(a: (f64, f64), b: (f64, f64), p: (f64, f64)) -> bool {
    orient(a, b, p) == 0.0
        && a.0.min(b.0) <= p.0
        && p.0 <= a.0.max(b.0)
        && a.1.min(b.1) <= p.1
        && p.1 <= a.1.max(b.1)
}

fn segments_meet(s: ((f64, f64), (f64, f64)), t: ((f64, f64), (f64, f64))) -> bool {
    let (a, b) = s;
    let (c, d) = t;
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    on_segment(a, b, c) || on_segment(a, b, d) || on_segment(c, d, a) || on_segment(c, d, b)
}
