//! The map model: the office example's structure and path lengths, the geometric fallback of
//! `range`/`bearing` parameters worked by hand, extents, and all-pairs shortest paths against a
//! brute-force Bellman–Ford on random small graphs.

use lplace::map::{Extent, Map, DEFAULT_RADIUS};
use lplace::syntax::parse_map;
use proptest::prelude::*;

fn map(text: &str) -> Map {
    Map::from_ast(&parse_map(text).expect("map parses")).expect("map builds")
}

fn office() -> Map {
    map(include_str!("../../maps/office.map"))
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

#[test]
fn office_structure() {
    let m = office();
    assert_eq!(m.name(), Some("office"));
    assert_eq!(m.places().len(), 8);
    assert_eq!(m.rooms().len(), 2);
    assert_eq!(m.landmarks().len(), 1);
    assert!(m.landmarks()[0].beacon);
    assert_eq!(m.place_index("P3"), Some(3));
    assert_eq!(m.room_index("R1"), Some(1));
    assert_eq!(m.landmark_index("B0"), Some(0));
    assert_eq!(m.rooms()[0].places, vec![0, 1, 2, 3]);
    assert_eq!(m.rooms()[1].places, vec![4, 5, 6, 7]);
    assert_eq!(m.places()[4].room, Some(1));
    assert_eq!(m.neighbours(3), vec![0, 2, 4]);
}

#[test]
fn office_path_lengths() {
    let m = office();
    let p = |n: &str| m.place_index(n).expect("place exists");
    assert!(close(m.path_length(p("P0"), p("P1")), 3.0));
    // P0 → P2: via P1 is 3 + 4 = 7, via P3 is 4.3 + 1.5 = 5.8.
    assert!(close(m.path_length(p("P0"), p("P2")), 5.8));
    // P1 → P6: P1-P2-P3-P4-P7-P6 = 4 + 1.5 + 1 + 1.5 + 4 = 12 beats the routes through P0 or P5 (13.8).
    assert!(close(m.path_length(p("P1"), p("P6")), 12.0));
    assert!(close(m.path_length(p("P6"), p("P1")), 12.0));
    assert_eq!(m.path_length(2, 2), 0.0);
    assert_eq!(m.path_length(0, 99), f64::INFINITY);
}

#[test]
fn office_walls_corners_params() {
    let m = office();
    assert_eq!(m.wall(0, "South"), 1.0);
    assert_eq!(m.wall(0, "North"), 0.0);
    assert_eq!(m.wall(3, "East"), 0.5);
    assert_eq!(m.corner(0, "South", "West"), 1.0);
    assert_eq!(m.corner(0, "West", "South"), 1.0, "order-insensitive");
    assert_eq!(m.corner(3, "North", "East"), 0.0);
    assert_eq!(m.param(0, "A", None), Some(204.0));
    assert_eq!(m.param(1, "L", None), Some(4.61));
    assert_eq!(m.param(1, "Q", None), None);
    assert_eq!(m.wall(99, "South"), 0.0);
    assert_eq!(m.param(99, "A", None), None);
}

#[test]
fn range_and_bearing_fall_back_to_geometry() {
    let m = map("landmark L at (4, 5) id 1;
                 landmark S at (1, -2);
                 place A corner at (1, 1) { param range(S) = 2.5; }
                 place B corner at (4, 1, 90);");
    // A = (1, 1) to L = (4, 5): a 3-4-5 triangle.
    assert!(close(
        m.param(0, "range", Some("L")).expect("geometry"),
        5.0
    ));
    let bearing = m.param(0, "bearing", Some("L")).expect("geometry");
    assert!(close(bearing, 4f64.atan2(3.0).to_degrees()), "{bearing}"); // ≈ 53.13°
                                                                        // Straight down (−y) is 270°, not −90°.
    assert!(close(
        m.param(0, "bearing", Some("S")).expect("geometry"),
        270.0
    ));
    // Written explicitly: the file wins over geometry.
    assert_eq!(m.param(0, "range", Some("S")), Some(2.5));
    // B = (4, 1) to L = (4, 5): due North, 4 m; the place heading is not subtracted.
    assert!(close(
        m.param(1, "range", Some("L")).expect("geometry"),
        4.0
    ));
    assert!(close(
        m.param(1, "bearing", Some("L")).expect("geometry"),
        90.0
    ));
    // Only range and bearing, only for landmarks.
    assert_eq!(m.param(0, "height", Some("L")), None);
    assert_eq!(m.param(0, "range", Some("Nowhere")), None);
    assert!(m.defines_param("range", Some("L")));
    assert!(!m.defines_param("range", None));
}

#[test]
fn extents() {
    let m = map("place A corner at (0, 0);
                 place B corner at (0, 0) extent radius 2;
                 place C doorway at (0, 0) extent box (-1, -2, 1, 2);");
    assert_eq!(m.places()[0].extent, Extent::Radius(DEFAULT_RADIUS));
    assert!(m.places()[0].contains(0.3, 0.3));
    assert!(!m.places()[0].contains(0.4, 0.4));
    assert!(m.places()[1].contains(1.2, 1.2));
    assert!(m.places()[2].contains(1.0, -2.0));
    assert!(!m.places()[2].contains(1.1, 0.0));
}

#[test]
fn a_path_without_length_takes_the_euclidean_distance() {
    let m = map(
        "place A corner at (0, 0); place B corner at (3, 4); place C corner at (30, 40);
                 path A -- B; path B -- C length 1;",
    );
    assert!(close(m.path_length(0, 1), 5.0));
    assert!(close(m.path_length(0, 2), 6.0));
    assert_eq!(m.path(1, 2).map(|p| p.length), Some(1.0));
    let s = m.summary();
    assert_eq!(
        s.paths,
        vec![("A".into(), "B".into(), 5.0), ("B".into(), "C".into(), 1.0)]
    );
}

#[test]
fn unreachable_places_are_infinitely_far() {
    let m = map("place A corner at (0, 0); place B corner at (1, 0); place C corner at (2, 0); path A -- B;");
    assert_eq!(m.path_length(0, 2), f64::INFINITY);
    assert!(m.neighbours(2).is_empty());
}

/// Bellman–Ford from every node: the slow, obviously correct reference.
fn bellman_ford(n: usize, edges: &[(usize, usize, f64)]) -> Vec<f64> {
    let mut all = vec![f64::INFINITY; n * n];
    for s in 0..n {
        let d = &mut all[s * n..(s + 1) * n];
        d[s] = 0.0;
        for _ in 0..n {
            for &(a, b, w) in edges {
                if d[a] + w < d[b] {
                    d[b] = d[a] + w;
                }
                if d[b] + w < d[a] {
                    d[a] = d[b] + w;
                }
            }
        }
    }
    all
}

/// A map of `n` junctions with a path per distinct pair of `raw` (lengths in tenths of a metre,
/// ends taken modulo `n`), and the same edges for the reference.
fn random_graph(n: usize, raw: &[(usize, usize, u32)]) -> (Map, Vec<(usize, usize, f64)>) {
    let mut text = String::new();
    for i in 0..n {
        text.push_str(&format!("place N{i} junction at ({i}, 0);\n"));
    }
    let mut seen = std::collections::BTreeSet::new();
    let mut edges = Vec::new();
    for &(a, b, w) in raw {
        let (a, b) = (a % n, b % n);
        if a == b || !seen.insert((a.min(b), a.max(b))) {
            continue;
        }
        let w = f64::from(w) / 10.0;
        text.push_str(&format!("path N{a} -- N{b} length {w};\n"));
        edges.push((a, b, w));
    }
    (map(&text), edges)
}

proptest! {
    #[test]
    fn shortest_paths_match_bellman_ford(
        n in 1usize..8,
        raw in prop::collection::vec((0usize..8, 0usize..8, 1u32..100), 0..20),
    ) {
        let (m, edges) = random_graph(n, &raw);
        let want = bellman_ford(n, &edges);
        for i in 0..n {
            for j in 0..n {
                let (got, exp) = (m.path_length(i, j), want[i * n + j]);
                prop_assert!(got == exp || (got - exp).abs() < 1e-9, "{i}->{j}: {got} vs {exp}");
            }
        }
    }
}

proptest! {
    /// The tracker's bounded searches (issue 16) against the all-pairs reference: exactly the
    /// places within the bound, at the reference's lengths. Bounds fall between multiples of
    /// 0.1 m, so that no path sits on a bound where rounding could decide. Lengths start at
    /// 0.1 m: a path of length 0 is a diagnostic (issue 16 row 13).
    #[test]
    fn bounded_searches_match_bellman_ford(
        n in 1usize..10,
        raw in prop::collection::vec((0usize..10, 0usize..10, 1u32..60), 0..30),
        bound in 0u32..150,
    ) {
        let (m, edges) = random_graph(n, &raw);
        let want = bellman_ford(n, &edges);
        let bound = f64::from(bound) / 10.0 + 0.05;
        let mut search = lplace::map::dijkstra::BoundedDijkstra::new();
        for i in 0..n {
            let got = m.path_lengths_within(i, bound, &mut search);
            let exp: Vec<usize> = (0..n).filter(|&j| want[i * n + j] <= bound).collect();
            let got_ids: Vec<usize> = got.iter().map(|&(j, _)| j).collect();
            prop_assert_eq!(&got_ids, &exp, "from N{} within {}", i, bound);
            for (j, l) in got {
                prop_assert!((l - want[i * n + j]).abs() < 1e-9, "{i}->{j}: {l}");
            }
        }
        prop_assert!(m.path_lengths_within(n, bound, &mut search).is_empty());
    }
}

/// Parallel edges keep the shorter, and a search stops at its bound (hand-worked).
#[test]
fn bounded_search_hand_worked() {
    use lplace::map::dijkstra::BoundedDijkstra;
    use petgraph::graph::UnGraph;
    let mut g = UnGraph::<(), f64>::new_undirected();
    let v: Vec<_> = (0..4).map(|_| g.add_node(())).collect();
    g.add_edge(v[0], v[1], 4.0);
    g.add_edge(v[0], v[1], 1.5); // parallel, shorter
    g.add_edge(v[1], v[2], 1.0);
    g.add_edge(v[2], v[3], 10.0);
    let mut s = BoundedDijkstra::new();
    assert_eq!(
        s.within(&g, 0, 3.0, |&w| w),
        vec![(0, 0.0), (1, 1.5), (2, 2.5)]
    );
    assert_eq!(s.within(&g, 3, 0.0, |&w| w), vec![(3, 0.0)]);
    assert_eq!(s.between(&g, 0, 3, |&w| w), 12.5);
    assert_eq!(s.between(&g, 2, 2, |&w| w), 0.0);
    assert_eq!(s.between(&g, 0, 9, |&w| w), f64::INFINITY);
}
