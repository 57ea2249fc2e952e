//! Expectations from a floor-plan description (issue 18): the free range a 2-D laser should
//! read from a place towards each compass direction, derived from the place's extent and its
//! `wall`/`open`/`door` statements, for maps no log has been fitted to. Offered to rules as the
//! map-derived parameter `free(D)` (ln metres, as the extractor's `free_range` percept), the way
//! `range(L)` falls back to the distance to a landmark; a `param free(D) = …;` written in the
//! place (by hand or by `lplace survey`) overrides it.
//!
//! The ranges, from anywhere in the extent (a reading from its far side runs the extent's whole
//! length):
//! - `wall D`: from [`NEAR_M`] (against the wall) to the extent's length along `D` plus
//!   [`WALL_SLACK_M`] (the wall stands a little beyond the extent's edge);
//! - `door D`: from [`NEAR_M`] (a jamb) to [`FAR_M`] (through the opening);
//! - `open D`: from [`OPEN_NEAR_M`] to [`FAR_M`];
//! - a diagonal between two plain walls: as a wall, along the diagonal; a diagonal next to an
//!   opening or a door, or a direction the description does not mention, anything from
//!   [`NEAR_M`] to [`FAR_M`].
//!
//! A place with no `wall`/`open`/`door` statement has no derived `free`.
//!
//! An `open` side's range holds from anywhere in the extent only if the corridor beyond spans
//! the side; [`side_reached`] measures how much of it the adjoining places' boxes cover, and
//! `lplace check` warns below half (such a side is a `door`).

use super::place::{Expected, Extent, Place};
use crate::core::compass::DIRECTIONS;

/// The shortest free range expected anywhere: a robot keeps about this far from a wall.
pub const NEAR_M: f64 = 0.3;
/// How far beyond the extent's edge a wall is taken to stand, at most.
pub const WALL_SLACK_M: f64 = 1.5;
/// The shortest free range along an open branch (a corridor going on).
pub const OPEN_NEAR_M: f64 = 3.0;
/// The longest free range: the extractor's default cap (`compass.cap_m`).
pub const FAR_M: f64 = 15.0;

/// What the description says about one cardinal direction.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Side {
    Wall,
    Door,
    Open,
    Unsaid,
}

fn side(place: &Place, dir: &str) -> Side {
    if place.open(dir) > 0.0 {
        Side::Open
    } else if place.door(dir) > 0.0 {
        Side::Door
    } else if place.wall(dir) > 0.0 {
        Side::Wall
    } else {
        Side::Unsaid
    }
}

/// The expected free range towards compass direction `dir` (ln metres), or `None` when the
/// place is not described (no wall, opening or door) or `dir` is not a compass direction.
pub fn free_range(place: &Place, dir: &str) -> Option<Expected> {
    if place.walls.is_empty() && place.opens.is_empty() && place.doors.is_empty() {
        return None;
    }
    let &(_, deg) = DIRECTIONS.iter().find(|(n, _)| *n == dir)?;
    let cardinal = |a: f64| {
        let k = (a.rem_euclid(360.0) / 90.0).round() as usize % 4;
        side(place, DIRECTIONS[k].0)
    };
    let is_diagonal = deg % 90.0 != 0.0;
    let kind = if is_diagonal {
        match (cardinal(deg - 45.0), cardinal(deg + 45.0)) {
            (Side::Wall, Side::Wall) => Side::Wall,
            _ => Side::Unsaid,
        }
    } else {
        cardinal(deg)
    };
    let (lo, hi) = match kind {
        Side::Wall => (NEAR_M, chord(place, deg) + WALL_SLACK_M),
        Side::Open => (OPEN_NEAR_M, FAR_M),
        Side::Door | Side::Unsaid => (NEAR_M, FAR_M),
    };
    let hi = hi.min(FAR_M);
    Some(Expected {
        lo: lo.ln(),
        hi: hi.max(lo).ln(),
    })
}

/// Extents whose facing edges lie this close adjoin (about a wall's thickness), metres.
pub const ADJOINING_M: f64 = 0.5;

/// The share of place `at`'s side towards cardinal direction `dir` along which the plain boxes
/// of other places adjoin it, in `[0, 1]`; `None` when `dir` is not cardinal, `at` is not a
/// plain box, or nothing adjoins that side (a corridor going on beyond the map says nothing).
/// An `open` side expects a long view from anywhere in the extent ([`free_range`]), which
/// holds only where the corridor beyond spans the side; one reaching along less than half of
/// it is an opening in a wall, a `door`.
pub fn side_reached(places: &[Place], at: usize, dir: &str) -> Option<f64> {
    let plain = |p: &Place| match (p.extent, &p.outline) {
        (Extent::Box { x0, y0, x1, y1 }, None) => {
            Some((x0.min(x1), y0.min(y1), x0.max(x1), y0.max(y1)))
        }
        _ => None,
    };
    let (x0, y0, x1, y1) = plain(places.get(at)?)?;
    // (this side's coordinate, its span along the side, and per neighbour the same two).
    let (edge, lo, hi) = match dir {
        "East" => (x1, y0, y1),
        "West" => (x0, y0, y1),
        "North" => (y1, x0, x1),
        "South" => (y0, x0, x1),
        _ => return None,
    };
    let mut reached = 0.0;
    let mut any = false;
    for (k, q) in places.iter().enumerate() {
        let Some((a0, b0, a1, b1)) = plain(q).filter(|_| k != at) else {
            continue;
        };
        let (facing, along) = match dir {
            "East" => (a0, (b0, b1)),
            "West" => (a1, (b0, b1)),
            "North" => (b0, (a0, a1)),
            _ => (b1, (a0, a1)),
        };
        let overlap = hi.min(along.1) - lo.max(along.0);
        if (facing - edge).abs() <= ADJOINING_M && overlap > 0.0 {
            reached += overlap;
            any = true;
        }
    }
    let side = hi - lo;
    (any && side > 0.0).then(|| (reached / side).min(1.0))
}

/// The longest straight run across the place's extent along `deg` (its bounding box for a
/// rotated box or polygon; the diameter for a disc).
fn chord(place: &Place, deg: f64) -> f64 {
    match place.extent {
        Extent::Radius(r) => 2.0 * r.max(0.0),
        Extent::Box { x0, y0, x1, y1 } => {
            let (s, c) = deg.to_radians().sin_cos();
            let (w, h) = ((x1 - x0).abs(), (y1 - y0).abs());
            let along_x = if c.abs() > 1e-12 {
                w / c.abs()
            } else {
                f64::INFINITY
            };
            let along_y = if s.abs() > 1e-12 {
                h / s.abs()
            } else {
                f64::INFINITY
            };
            along_x.min(along_y)
        }
    }
}
