//! Single-source shortest path lengths, bounded by a distance (Dijkstra with a binary heap).
//!
//! Depends only on petgraph's graph type. The tracker asks, once per place, for the places
//! within the distance its gates can use ([`crate::map::Map::path_lengths_within`]); a single pair
//! ([`crate::map::Map::path_length`]) stops as soon as the target is settled. Replaces the
//! all-pairs matrix (issue 16): time and memory now grow with what is asked for, not with
//! `|V|²` or `|V|³`.

use petgraph::graph::{NodeIndex, UnGraph};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A heap entry: tentative distance and node, smallest distance first (ties: smaller node).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Entry(f64, usize);

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        // Reversed: `BinaryHeap` is a max-heap. Distances are never NaN (lengths are checked
        // non-negative and finite by the map builder), and `total_cmp` orders them as `<` does.
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Reusable buffers for bounded searches over one graph, so that a search from every node
/// costs no allocation per search beyond its result.
#[derive(Debug, Clone, Default)]
pub struct BoundedDijkstra {
    /// Best known distance per node; `INFINITY` outside the current search.
    dist: Vec<f64>,
    /// Nodes whose `dist` the current search set (reset to `INFINITY` afterwards).
    touched: Vec<usize>,
    heap: BinaryHeap<Entry>,
}

impl BoundedDijkstra {
    /// Empty buffers; they grow to the graph's size on first use.
    pub fn new() -> BoundedDijkstra {
        BoundedDijkstra::default()
    }

    /// Every node whose shortest path length from `source` is at most `bound`, with that length,
    /// sorted by node index; `source` itself at 0. `length` gives an edge's length, which must be
    /// non-negative (a negative or NaN length is taken as 0 and +∞ respectively, so the search
    /// still ends). Parallel edges keep the shortest. A `source` out of range gives nothing; a
    /// NaN `bound` is taken as 0.
    ///
    /// Lengths are summed along each path from `source` outwards.
    ///
    /// # Complexity
    ///
    /// Time `O((V_b + E_b) log V_b)` and memory `O(V_b)` beyond the buffers (`O(|V|)` once), where
    /// `V_b`, `E_b` are the nodes within `bound` and their edges.
    ///
    /// # Example
    ///
    /// ```
    /// use lplace::map::dijkstra::BoundedDijkstra;
    /// use petgraph::graph::UnGraph;
    ///
    /// let mut g = UnGraph::<(), f64>::new_undirected();
    /// let (a, b, c) = (g.add_node(()), g.add_node(()), g.add_node(()));
    /// g.add_edge(a, b, 1.0);
    /// g.add_edge(b, c, 2.0);
    /// g.add_edge(a, c, 5.0);
    /// let mut search = BoundedDijkstra::new();
    /// assert_eq!(search.within(&g, 0, 10.0, |&w| w), vec![(0, 0.0), (1, 1.0), (2, 3.0)]);
    /// assert_eq!(search.within(&g, 0, 2.0, |&w| w), vec![(0, 0.0), (1, 1.0)]);
    /// ```
    pub fn within<N, E>(
        &mut self,
        graph: &UnGraph<N, E>,
        source: usize,
        bound: f64,
        length: impl Fn(&E) -> f64,
    ) -> Vec<(usize, f64)> {
        let mut out = Vec::new();
        self.search(graph, source, bound, None, &length, |v, d| out.push((v, d)));
        out.sort_unstable_by_key(|&(v, _)| v);
        out
    }

    /// The shortest path length from `source` to `target`, `INFINITY` when there is no path or
    /// either is out of range. Stops when `target` is settled.
    ///
    /// # Complexity
    ///
    /// Time `O((V_d + E_d) log V_d)`, `V_d`, `E_d` the nodes no farther than `target` and their
    /// edges.
    pub fn between<N, E>(
        &mut self,
        graph: &UnGraph<N, E>,
        source: usize,
        target: usize,
        length: impl Fn(&E) -> f64,
    ) -> f64 {
        let mut found = f64::INFINITY;
        self.search(
            graph,
            source,
            f64::INFINITY,
            Some(target),
            &length,
            |v, d| {
                if v == target {
                    found = d;
                }
            },
        );
        found
    }

    /// The search itself: calls `settled(node, distance)` once per node within `bound`, in
    /// order of distance; stops after `stop_at` is settled.
    fn search<N, E>(
        &mut self,
        graph: &UnGraph<N, E>,
        source: usize,
        bound: f64,
        stop_at: Option<usize>,
        length: &impl Fn(&E) -> f64,
        mut settled: impl FnMut(usize, f64),
    ) {
        let n = graph.node_count();
        if source >= n {
            return;
        }
        if self.dist.len() < n {
            self.dist.resize(n, f64::INFINITY);
        }
        let bound = if bound.is_nan() { 0.0 } else { bound };
        self.heap.clear();
        self.set(source, 0.0);
        self.heap.push(Entry(0.0, source));
        while let Some(Entry(d, v)) = self.heap.pop() {
            if d > self.dist[v] {
                continue; // a stale entry: `v` was reached more cheaply since
            }
            settled(v, d);
            if stop_at == Some(v) {
                break;
            }
            for e in graph.edges(NodeIndex::new(v)) {
                use petgraph::visit::EdgeRef;
                let w = length(e.weight());
                let w = if w.is_nan() {
                    f64::INFINITY
                } else {
                    w.max(0.0)
                };
                let u = if e.source().index() == v {
                    e.target().index()
                } else {
                    e.source().index()
                };
                let du = d + w;
                if du <= bound && du < self.dist[u] {
                    self.set(u, du);
                    self.heap.push(Entry(du, u));
                }
            }
        }
        for &v in &self.touched {
            self.dist[v] = f64::INFINITY;
        }
        self.touched.clear();
    }

    fn set(&mut self, v: usize, d: f64) {
        if self.dist[v] == f64::INFINITY {
            self.touched.push(v);
        }
        self.dist[v] = d;
    }
}
