//! The map model: places (with their expected walls, corners and parameters), rooms, beacons and
//! landmarks, and the topological graph of paths between places, searched for shortest path
//! lengths on demand ([`dijkstra`]). Built once from a checked map file ([`Map::from_ast`]) and then only read: the checker
//! resolves names against it, the compiler reads walls and parameters from it, the tracker reads
//! path lengths, the metric layer reads extents.
//!
//! Depends on `syntax::ast` (its input), `syntax::diagnostic` (its errors) and petgraph. Places
//! keep declaration order: a place's index is its id everywhere in lplace.

mod build;
pub mod dijkstra;
pub mod expect;
mod outline;
mod place;

pub use outline::Outline;
pub use place::{Expected, Extent, Landmark, Place, Room, DEFAULT_RADIUS};

use dijkstra::BoundedDijkstra;
use petgraph::graph::{NodeIndex, UnGraph};
use serde::{Deserialize, Serialize};

/// What a path between two places records.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PathInfo {
    /// Length in metres (the Euclidean distance of the poses when the file gives none).
    pub length: f64,
    /// Heading in degrees from the first-written end to the other, when given.
    pub heading: Option<f64>,
}

/// A loaded map. See the module docs.
#[derive(Debug, Clone)]
pub struct Map {
    name: Option<String>,
    /// `axis D;`: the building's wall direction in degrees (mod 90°), within ±45°.
    axis_deg: Option<f64>,
    start: Option<(f64, f64)>,
    /// `kinds {…};`: the declared place kinds, in source order.
    kinds: Option<Vec<String>>,
    places: Vec<Place>,
    rooms: Vec<Room>,
    landmarks: Vec<Landmark>,
    /// Node weight = place index; node `i` is place `i`.
    graph: UnGraph<usize, PathInfo>,
}

/// A serialisable overview of a map (for `lplace check --format json` and reports).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapSummary {
    /// `map name;`, if given.
    pub name: Option<String>,
    /// Place names in id order.
    pub places: Vec<String>,
    /// Room names in declaration order.
    pub rooms: Vec<String>,
    /// Landmark names in declaration order.
    pub landmarks: Vec<String>,
    /// Paths as `(from, to, length)`, sorted by place ids.
    pub paths: Vec<(String, String, f64)>,
}

impl Map {
    /// The map's name (`map name;`), if given.
    pub fn name(&self) -> Option<&str> {
        self.name.as_deref()
    }

    /// The building's axis (`axis D;`): the direction its walls run in, degrees in ±45°.
    pub fn axis_deg(&self) -> Option<f64> {
        self.axis_deg
    }

    /// Where the runs evaluated with this map begin (`start (x, y);`), map frame, metres.
    pub fn start(&self) -> Option<(f64, f64)> {
        self.start
    }

    /// The declared place kinds (`kinds {…};`), if the map declares them.
    pub fn kinds(&self) -> Option<&[String]> {
        self.kinds.as_deref()
    }

    /// Places in declaration order (index = place id).
    pub fn places(&self) -> &[Place] {
        &self.places
    }

    /// Index of the place called `name`.
    pub fn place_index(&self, name: &str) -> Option<usize> {
        self.places.iter().position(|p| p.name == name)
    }

    /// Rooms in declaration order.
    pub fn rooms(&self) -> &[Room] {
        &self.rooms
    }

    /// Index of the room called `name`.
    pub fn room_index(&self, name: &str) -> Option<usize> {
        self.rooms.iter().position(|r| r.name == name)
    }

    /// Beacons and landmarks in declaration order.
    pub fn landmarks(&self) -> &[Landmark] {
        &self.landmarks
    }

    /// Index of the beacon or landmark called `name`.
    pub fn landmark_index(&self, name: &str) -> Option<usize> {
        self.landmarks.iter().position(|l| l.name == name)
    }

    /// The topological graph (node `i` carries place index `i`).
    pub fn graph(&self) -> &UnGraph<usize, PathInfo> {
        &self.graph
    }

    /// Shortest path length between places `i` and `j` over the graph: 0 for `i == j`,
    /// `f64::INFINITY` when unreachable or when either index is out of range. One search
    /// (see [`BoundedDijkstra::between`]); for many pairs from one place use
    /// [`Map::path_lengths_within`].
    pub fn path_length(&self, i: usize, j: usize) -> f64 {
        let n = self.places.len();
        if i >= n || j >= n {
            return f64::INFINITY;
        }
        BoundedDijkstra::new().between(&self.graph, i, j, |p| p.length)
    }

    /// Every place whose shortest path length from place `i` is at most `bound`, with that
    /// length, sorted by place id (`i` itself at 0; nothing when `i` is out of range). `search`
    /// holds the buffers, reused across calls (see [`BoundedDijkstra::within`]).
    pub fn path_lengths_within(
        &self,
        i: usize,
        bound: f64,
        search: &mut BoundedDijkstra,
    ) -> Vec<(usize, f64)> {
        search.within(&self.graph, i, bound, |p| p.length)
    }

    /// The places joined to place `i` by a path, sorted by id, without duplicates.
    pub fn neighbours(&self, i: usize) -> Vec<usize> {
        if i >= self.places.len() {
            return Vec::new();
        }
        let mut v: Vec<usize> = self
            .graph
            .neighbors(NodeIndex::new(i))
            .filter_map(|n| self.graph.node_weight(n).copied())
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// The path written directly between places `i` and `j`, if any.
    pub fn path(&self, i: usize, j: usize) -> Option<PathInfo> {
        let n = self.places.len();
        if i >= n || j >= n {
            return None;
        }
        self.graph
            .find_edge(NodeIndex::new(i), NodeIndex::new(j))
            .and_then(|e| self.graph.edge_weight(e).copied())
    }

    /// Degree of the wall in direction `dir` at place `place` (0 when there is none).
    pub fn wall(&self, place: usize, dir: &str) -> f64 {
        self.places.get(place).map_or(0.0, |p| p.wall(dir))
    }

    /// Degree of `open D` towards `dir` at place `place` (0 when none).
    pub fn open(&self, place: usize, dir: &str) -> f64 {
        self.places.get(place).map_or(0.0, |p| p.open(dir))
    }

    /// Degree of `door D` towards `dir` at place `place` (0 when none).
    pub fn door(&self, place: usize, dir: &str) -> f64 {
        self.places.get(place).map_or(0.0, |p| p.door(dir))
    }

    /// Degree of the corner between `d1` and `d2` at place `place`, in either order (0 when
    /// there is none).
    pub fn corner(&self, place: usize, d1: &str, d2: &str) -> f64 {
        self.places.get(place).map_or(0.0, |p| p.corner(d1, d2))
    }

    /// A place parameter: `param(i, "A", None)` for `param A = …;`, `param(i, "range",
    /// Some("Yellow"))` for `param range(Yellow) = …;`.
    ///
    /// When not written explicitly, `range` and `bearing` keyed by a landmark fall back to
    /// geometry: the distance in metres from the place's position to the landmark, and the
    /// direction in degrees in `[0, 360)` from the place to the landmark, measured in the map
    /// frame (0° along +x, counter-clockwise; the place's heading is *not* subtracted).
    /// `free` keyed by a compass direction falls back to the free range the place's extent
    /// and its `wall`/`open`/`door` statements imply ([`expect`]).
    pub fn param(&self, place: usize, name: &str, key: Option<&str>) -> Option<f64> {
        self.expected(place, name, key).map(|e| e.centre())
    }

    /// A place parameter as written — a value or a range — with the same geometric fallbacks
    /// as [`Map::param`] (which give single values).
    pub fn expected(&self, place: usize, name: &str, key: Option<&str>) -> Option<Expected> {
        let p = self.places.get(place)?;
        if let Some(v) = p.expected(name, key) {
            return Some(v);
        }
        if name == "free" {
            return expect::free_range(p, key?);
        }
        let l = self.landmarks.get(self.landmark_index(key?)?)?;
        let (dx, dy) = (l.position.0 - p.pose.0, l.position.1 - p.pose.1);
        match name {
            "range" => Some(Expected::value(dx.hypot(dy))),
            "bearing" => Some(Expected::value(dy.atan2(dx).to_degrees().rem_euclid(360.0))),
            _ => None,
        }
    }

    /// True if some place defines parameter `name` (with `key`), explicitly or — for
    /// `range`/`bearing` keyed by a landmark — through geometry.
    pub fn defines_param(&self, name: &str, key: Option<&str>) -> bool {
        (0..self.places.len()).any(|i| self.param(i, name, key).is_some())
    }

    /// A serialisable overview.
    pub fn summary(&self) -> MapSummary {
        let mut paths: Vec<(usize, usize, f64)> = self
            .graph
            .edge_indices()
            .filter_map(|e| {
                let (a, b) = self.graph.edge_endpoints(e)?;
                let (a, b) = (a.index().min(b.index()), a.index().max(b.index()));
                Some((a, b, self.graph.edge_weight(e)?.length))
            })
            .collect();
        paths.sort_by_key(|x| (x.0, x.1));
        MapSummary {
            name: self.name.clone(),
            places: self.places.iter().map(|p| p.name.clone()).collect(),
            rooms: self.rooms.iter().map(|r| r.name.clone()).collect(),
            landmarks: self.landmarks.iter().map(|l| l.name.clone()).collect(),
            paths: paths
                .into_iter()
                .map(|(a, b, l)| (self.places[a].name.clone(), self.places[b].name.clone(), l))
                .collect(),
        }
    }
}
