//! Large generated maps for scale tests and benchmarks (issue 16): `n` places on a square lattice
//! 3 m apart, the office schema at every place (paper 003's Fig. 3 rules, `rules/office.lpl`),
//! a sparse graph of degree ≤ 6.
//!
//! # The layout
//! Place `i` sits at column `i mod w`, row `i div w` of a lattice `w = ⌈√n⌉` wide. Each 2 × 2
//! block of places is one room whose four places are its corners (walls and corner of that
//! side), so the office rules find the same kinds of evidence as in the office. Paths join each
//! place to its east and north neighbours, and, seeded, to its north-east diagonal neighbour
//! with probability ½: degree at most 4 + 2 = 6 (that diagonal out, and in from the south-west). One beacon stands in
//! the middle; `A` and `L` of each place are its direction (degrees, map frame) and distance from
//! the beacon, as in the office map.
//!
//! Deterministic: the same `n` and `seed` give byte-identical text. Depends on `core::rng`.

use crate::core::rng::SplitMix64;
use std::fmt::Write as _;

/// Spacing of the lattice, metres.
const SPACING: f64 = 3.0;

/// The text of a generated map with `n` places (see the module docs). Places are `P0 … P{n−1}`,
/// rooms `R0 …`, the beacon `B0`.
///
/// ```
/// use lplace::sim::large_map::lattice_office;
/// let text = lattice_office(100, 1);
/// let map = lplace::map::Map::from_ast(&lplace::syntax::parse_map(&text).unwrap()).unwrap();
/// assert_eq!(map.places().len(), 100);
/// assert!((0..100).all(|i| map.neighbours(i).len() <= 6));
/// ```
pub fn lattice_office(n: usize, seed: u64) -> String {
    let w = lattice_width(n);
    let mut rng = SplitMix64::new(seed);
    let mut out = String::with_capacity(n * 200);
    let _ = writeln!(out, "map lattice_{n};");
    let rooms = n.div_ceil(w).div_ceil(2) * w.div_ceil(2);
    for r in 0..rooms {
        let _ = writeln!(out, "room R{r};");
    }
    let rows = n.div_ceil(w).max(1);
    let beacon = (
        0.5 * SPACING * (w as f64 - 1.0),
        0.5 * SPACING * (rows as f64 - 1.0) + 0.5,
    );
    let _ = writeln!(out, "beacon B0 at ({:.1}, {:.1}) id 1;", beacon.0, beacon.1);
    for i in 0..n {
        write_place(&mut out, i, w, beacon);
    }
    for i in 0..n {
        let c = i % w;
        let mut join = |j: usize| {
            if j < n {
                let _ = writeln!(out, "path P{i} -- P{j};");
            }
        };
        if c + 1 < w {
            join(i + 1);
        }
        join(i + w);
        if c + 1 < w && rng.chance(0.5) {
            join(i + w + 1);
        }
    }
    out
}

/// Width of the lattice for `n` places: `⌈√n⌉` (at least 1).
fn lattice_width(n: usize) -> usize {
    let mut w = (n as f64).sqrt() as usize;
    while w * w < n {
        w += 1;
    }
    w.max(1)
}

/// Place `i`: a corner of its 2 × 2 room, with its beacon signature.
fn write_place(out: &mut String, i: usize, w: usize, beacon: (f64, f64)) {
    let (c, r) = (i % w, i / w);
    let room = (r / 2) * w.div_ceil(2) + c / 2;
    let (x, y) = (SPACING * c as f64, SPACING * r as f64);
    let ns = if r % 2 == 0 { "South" } else { "North" };
    let ew = if c % 2 == 0 { "West" } else { "East" };
    let (dx, dy) = (x - beacon.0, y - beacon.1);
    let a = dy.atan2(dx).to_degrees().rem_euclid(360.0);
    let l = dx.hypot(dy);
    let _ = writeln!(
        out,
        "place P{i} corner in R{room} at ({x:.1}, {y:.1}) extent radius 0.6 {{ \
         wall {ns}; wall {ew}; corner {ns} {ew}; param A = {a:.1}; param L = {l:.2}; }}"
    );
}
