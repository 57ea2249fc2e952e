//! The eight compass directions by which laser percepts and floor-plan descriptions name a
//! side of a place, with their map-frame angles (degrees counter-clockwise from +x).
//!
//! One table for the extractor (`percept::compass`, which emits `free_range(D)` in this order)
//! and for the expectations derived from a map (`map::expect`), which cannot see each other.

/// The four cardinal directions first (what the extractor's `directions: 4` emits), then the
/// diagonals; `DIRECTIONS[k]` for `k < 4` lies at `90·k` degrees.
pub const DIRECTIONS: [(&str, f64); 8] = [
    ("East", 0.0),
    ("North", 90.0),
    ("West", 180.0),
    ("South", 270.0),
    ("NorthEast", 45.0),
    ("NorthWest", 135.0),
    ("SouthWest", 225.0),
    ("SouthEast", 315.0),
];
