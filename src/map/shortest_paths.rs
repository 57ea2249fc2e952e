//! All-pairs shortest path lengths over the topological graph (Floyd–Warshall).
//!
//! Depends only on petgraph. The map builder calls [`floyd_warshall`] once; the tracker then reads
//! `Map::path_length` in constant time at sensor rate.

use petgraph::graph::UnGraph;

/// All-pairs shortest path lengths of an undirected graph whose edges carry non-negative
/// lengths, as a row-major `n × n` matrix (`n` = number of nodes): entry `i * n + j` is the
/// length of a shortest path from node `i` to node `j`, `0` on the diagonal and
/// `f64::INFINITY` when `j` cannot be reached from `i`. Parallel edges keep the shortest.
///
/// # Complexity
///
/// Time `O(|V|³ + |E|)`, memory `O(|V|²)`. Maps have tens of places, so the cubic term is
/// negligible and the dense matrix gives constant-time lookups afterwards.
///
/// # Example
///
/// ```
/// use lplace::map::shortest_paths::floyd_warshall;
/// use petgraph::graph::UnGraph;
///
/// let mut g = UnGraph::<(), f64>::new_undirected();
/// let a = g.add_node(());
/// let b = g.add_node(());
/// let c = g.add_node(());
/// g.add_edge(a, b, 1.0);
/// g.add_edge(b, c, 2.0);
/// g.add_edge(a, c, 5.0);
/// let d = floyd_warshall(&g, |&w| w);
/// assert_eq!(d[0 * 3 + 2], 3.0); // a → b → c beats the direct 5.0
/// assert_eq!(d[2 * 3 + 0], 3.0);
/// ```
pub fn floyd_warshall<N, E>(graph: &UnGraph<N, E>, length: impl Fn(&E) -> f64) -> Vec<f64> {
    let n = graph.node_count();
    let mut d = vec![f64::INFINITY; n * n];
    for i in 0..n {
        d[i * n + i] = 0.0;
    }
    for e in graph.edge_indices() {
        if let (Some((a, b)), Some(w)) = (graph.edge_endpoints(e), graph.edge_weight(e)) {
            let (a, b) = (a.index(), b.index());
            let w = length(w);
            if w < d[a * n + b] {
                d[a * n + b] = w;
                d[b * n + a] = w;
            }
        }
    }
    for k in 0..n {
        for i in 0..n {
            let dik = d[i * n + k];
            if dik == f64::INFINITY {
                continue;
            }
            for j in 0..n {
                let via = dik + d[k * n + j];
                if via < d[i * n + j] {
                    d[i * n + j] = via;
                }
            }
        }
    }
    d
}
