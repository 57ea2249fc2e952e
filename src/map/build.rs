//! Building a [`Map`] from a parsed map file, with every check a map file can fail on its own:
//! duplicate names (places, rooms and landmarks share one namespace), unknown rooms, paths to
//! unknown places, self and duplicate paths, negative lengths and radii, degrees outside
//! `[0, 1]`, swapped box corners and features written twice in one place. All problems are
//! reported, not just the first.

use super::outline::Outline;
use super::place::{corner_key, Expected, Extent, Landmark, Place, Room, DEFAULT_RADIUS};
use super::{Map, PathInfo};
use crate::syntax::ast::{self, Feature, LandmarkKind, MapFile, MapItem};
use crate::syntax::diagnostic::{Diagnostic, DiagnosticKind};
use crate::syntax::span::{Span, Spanned};
use petgraph::graph::{NodeIndex, UnGraph};
use std::collections::BTreeMap;

fn degree_ok(d: &Option<Spanned<f64>>, diags: &mut Vec<Diagnostic>) -> f64 {
    match d {
        None => 1.0,
        Some(s) if (0.0..=1.0).contains(&s.node) => s.node,
        Some(s) => {
            diags.push(Diagnostic::error(
                DiagnosticKind::DegreeOutOfRange { value: s.node },
                s.span,
            ));
            s.node.clamp(0.0, 1.0)
        }
    }
}

impl Map {
    /// Builds the map model from a parsed map file, or returns every problem found.
    ///
    /// ```
    /// use lplace::map::Map;
    /// let ast = lplace::syntax::parse_map("place A corner at (0, 0); place B corner at (3, 4);\npath A -- B;").unwrap();
    /// let map = Map::from_ast(&ast).unwrap();
    /// assert_eq!(map.path_length(0, 1), 5.0); // no length given: Euclidean distance
    /// ```
    pub fn from_ast(file: &MapFile) -> Result<Map, Vec<Diagnostic>> {
        let mut diags = Vec::new();
        let MapStatements {
            axis_deg,
            start,
            kinds,
        } = map_statements(file, &mut diags);
        let (mut rooms, landmarks, place_decls) = declare_items(file, &mut diags);
        let mut places = Vec::with_capacity(place_decls.len());
        for p in place_decls {
            check_kind(p, kinds.as_deref(), &mut diags);
            places.push(build_place(p, &mut rooms, places.len(), &mut diags));
        }
        let graph = build_graph(file, &places, &mut diags);
        if !diags.is_empty() {
            diags.sort_by_key(|d| d.span.start);
            return Err(diags);
        }
        Ok(Map {
            name: file.name.as_ref().map(|n| n.node.clone()),
            axis_deg,
            start,
            kinds,
            places,
            rooms,
            landmarks,
            graph,
        })
    }
}

/// What the map says as a whole, besides its places, rooms and paths.
struct MapStatements {
    axis_deg: Option<f64>,
    start: Option<(f64, f64)>,
    kinds: Option<Vec<String>>,
}

/// The building axis, the start and the kinds domain: each at most once, the axis within ±45°
/// (every wall direction has one representative there, so two spellings of one axis cannot
/// differ).
fn map_statements(file: &MapFile, diags: &mut Vec<Diagnostic>) -> MapStatements {
    let mut axis: Option<(f64, Span)> = None;
    let mut start: Option<((f64, f64), Span)> = None;
    let mut kinds: Option<(Vec<String>, Span)> = None;
    let twice = |what: &'static str, span: Span, first: Span| {
        Diagnostic::error(DiagnosticKind::DuplicateMapStatement { what }, span)
            .with_related(first, "first given here")
    };
    for item in &file.items {
        match item {
            MapItem::Axis(a) => {
                let v = a.degrees.node;
                if !(-45.0..=45.0).contains(&v) {
                    diags.push(Diagnostic::error(
                        DiagnosticKind::AxisOutOfRange { value: v },
                        a.degrees.span,
                    ));
                }
                match axis {
                    Some((_, first)) => diags.push(twice("axis", a.span, first)),
                    None => axis = Some((v.clamp(-45.0, 45.0), a.span)),
                }
            }
            MapItem::Start(s) => match start {
                Some((_, first)) => diags.push(twice("start", s.span, first)),
                None => start = Some((s.position.node, s.span)),
            },
            MapItem::Kinds(k) => {
                let mut names: BTreeMap<&str, Span> = BTreeMap::new();
                for n in &k.kinds {
                    if let Some(first) = names.insert(&n.node, n.span) {
                        let d = DiagnosticKind::DuplicateName {
                            what: "kind",
                            name: n.node.clone(),
                        };
                        diags.push(
                            Diagnostic::error(d, n.span).with_related(first, "first listed here"),
                        );
                    }
                }
                match kinds {
                    Some((_, first)) => diags.push(twice("kinds", k.span, first)),
                    None => {
                        let list = k.kinds.iter().map(|n| n.node.clone()).collect();
                        kinds = Some((list, k.span));
                    }
                }
            }
            _ => {}
        }
    }
    MapStatements {
        axis_deg: axis.map(|a| a.0),
        start: start.map(|s| s.0),
        kinds: kinds.map(|k| k.0),
    }
}

/// A place whose kind is not in the declared domain (when the map declares one) is reported.
fn check_kind(p: &ast::PlaceDecl, kinds: Option<&[String]>, diags: &mut Vec<Diagnostic>) {
    if let Some(kinds) = kinds {
        if !kinds.contains(&p.kind.node) {
            diags.push(Diagnostic::error(
                DiagnosticKind::UndeclaredKind {
                    name: p.kind.node.clone(),
                },
                p.kind.span,
            ));
        }
    }
}

/// The file's rooms, landmarks and place declarations, each name declared once: places, rooms
/// and landmarks share one namespace, and a name defined again is reported and left out.
fn declare_items<'f>(
    file: &'f MapFile,
    diags: &mut Vec<Diagnostic>,
) -> (Vec<Room>, Vec<Landmark>, Vec<&'f ast::PlaceDecl>) {
    // Name → first definition.
    let mut names: BTreeMap<String, Span> = BTreeMap::new();
    let mut declare =
        |id: &Spanned<String>, what: &'static str, diags: &mut Vec<Diagnostic>| -> bool {
            if let Some(first) = names.get(id.node.as_str()) {
                diags.push(
                    Diagnostic::error(
                        DiagnosticKind::DuplicateName {
                            what,
                            name: id.node.clone(),
                        },
                        id.span,
                    )
                    .with_related(*first, "first defined here"),
                );
                false
            } else {
                names.insert(id.node.clone(), id.span);
                true
            }
        };
    let mut rooms = Vec::new();
    let mut landmarks = Vec::new();
    let mut place_decls: Vec<&ast::PlaceDecl> = Vec::new();
    for item in &file.items {
        match item {
            MapItem::Room(r) => {
                if declare(&r.name, "room", diags) {
                    rooms.push(Room {
                        name: r.name.node.clone(),
                        label: r.label.as_ref().map(|l| l.node.clone()),
                        places: Vec::new(),
                    });
                }
            }
            MapItem::Landmark(l) => {
                let what = match l.kind {
                    LandmarkKind::Beacon => "beacon",
                    LandmarkKind::Landmark => "landmark",
                };
                if let Some(id) = l.id.as_ref().filter(|i| u32::try_from(i.node).is_err()) {
                    diags.push(Diagnostic::error(
                        DiagnosticKind::BadLandmarkId { value: id.node },
                        id.span,
                    ));
                }
                if declare(&l.name, what, diags) {
                    landmarks.push(Landmark {
                        name: l.name.node.clone(),
                        beacon: l.kind == LandmarkKind::Beacon,
                        position: l.position.node,
                        id: l.id.as_ref().map(|i| i.node),
                    });
                }
            }
            MapItem::Place(p) => {
                if declare(&p.name, "place", diags) {
                    place_decls.push(p);
                }
            }
            MapItem::Path(_) | MapItem::Axis(_) | MapItem::Start(_) | MapItem::Kinds(_) => {}
        }
    }
    (rooms, landmarks, place_decls)
}

/// The path graph over `places` (node `i` is place `i`), from the file's `path` items.
fn build_graph(
    file: &MapFile,
    places: &[Place],
    diags: &mut Vec<Diagnostic>,
) -> UnGraph<usize, PathInfo> {
    let mut graph = UnGraph::<usize, PathInfo>::with_capacity(places.len(), 0);
    for i in 0..places.len() {
        graph.add_node(i);
    }
    let mut seen: BTreeMap<(usize, usize), Span> = BTreeMap::new();
    // Names are unique by now (`declare_items`); a map, not a scan per path end, so that
    // building stays O(paths · log places) on large maps.
    let index: BTreeMap<&str, usize> = places
        .iter()
        .enumerate()
        .map(|(i, p)| (p.name.as_str(), i))
        .collect();
    for item in &file.items {
        let MapItem::Path(path) = item else { continue };
        if let Some((a, b, info)) = path_edge(path, places, &index, &mut seen, diags) {
            graph.add_edge(NodeIndex::new(a), NodeIndex::new(b), info);
        }
    }
    graph
}

/// One `path` item as an edge between place indices, or `None` (reported) when it names an
/// unknown place, joins a place to itself, repeats a path (`seen` holds the earlier ones) or
/// has a negative length. Without a length, the distance between the place centres.
fn path_edge(
    path: &ast::PathDecl,
    places: &[Place],
    index: &BTreeMap<&str, usize>,
    seen: &mut BTreeMap<(usize, usize), Span>,
    diags: &mut Vec<Diagnostic>,
) -> Option<(usize, usize, PathInfo)> {
    let ends = [&path.from, &path.to].map(|e| {
        let i = index.get(e.node.as_str()).copied();
        if i.is_none() {
            diags.push(Diagnostic::error(
                DiagnosticKind::PathToUnknownPlace {
                    name: e.node.clone(),
                },
                e.span,
            ));
        }
        i
    });
    let [Some(a), Some(b)] = ends else {
        return None;
    };
    if a == b {
        diags.push(Diagnostic::error(
            DiagnosticKind::SelfPath {
                name: path.from.node.clone(),
            },
            path.span,
        ));
        return None;
    }
    let key = (a.min(b), a.max(b));
    if let Some(first) = seen.get(&key) {
        diags.push(
            Diagnostic::error(
                DiagnosticKind::DuplicatePath {
                    from: path.from.node.clone(),
                    to: path.to.node.clone(),
                },
                path.span,
            )
            .with_related(*first, "first path here"),
        );
        return None;
    }
    seen.insert(key, path.span);
    let length = match &path.length {
        Some(l) if l.node == 0.0 => {
            diags.push(Diagnostic::error(
                DiagnosticKind::ZeroLength { value: l.node },
                l.span,
            ));
            return None;
        }
        Some(l) if l.node < 0.0 => {
            diags.push(Diagnostic::error(
                DiagnosticKind::NegativeLength {
                    what: "length",
                    value: l.node,
                },
                l.span,
            ));
            return None;
        }
        Some(l) => l.node,
        None => {
            let (pa, pb) = (places[a].pose, places[b].pose);
            (pa.0 - pb.0).hypot(pa.1 - pb.1)
        }
    };
    let heading = path.heading.as_ref().map(|h| h.node);
    Some((a, b, PathInfo { length, heading }))
}

fn build_place(
    p: &ast::PlaceDecl,
    rooms: &mut [Room],
    id: usize,
    diags: &mut Vec<Diagnostic>,
) -> Place {
    let room = place_room(p, rooms, id, diags);
    let (extent, outline) = place_extent(p, diags);
    let mut place = Place {
        name: p.name.node.clone(),
        kind: p.kind.node.clone(),
        room,
        pose: p.pose.node,
        extent,
        outline,
        walls: BTreeMap::new(),
        opens: BTreeMap::new(),
        doors: BTreeMap::new(),
        corners: BTreeMap::new(),
        params: BTreeMap::new(),
        span: p.span,
        direction_spans: Vec::new(),
    };
    let mut sides = BTreeMap::new();
    for f in &p.features {
        check_sides(f, &mut sides, diags);
        add_feature(&mut place, f, diags);
    }
    // A door is an opening in a wall: the wall is there on either side of it.
    for (dir, d) in &place.doors {
        place.walls.entry(dir.clone()).or_insert(*d);
    }
    place
}

/// Reports `open D` written with `wall D` or `door D` in one place (`sides`: the first
/// statement about each direction so far).
fn check_sides<'f>(
    f: &'f Feature,
    sides: &mut BTreeMap<&'f str, (&'static str, Span)>,
    diags: &mut Vec<Diagnostic>,
) {
    let (what, dir, span) = match f {
        Feature::Wall { dir, span, .. } => ("wall", dir, *span),
        Feature::Open { dir, span, .. } => ("open", dir, *span),
        Feature::Door { dir, span, .. } => ("door", dir, *span),
        _ => return,
    };
    match sides.get(dir.node.as_str()) {
        Some(&(first, first_span)) if (first == "open") != (what == "open") => {
            let kind = DiagnosticKind::ContradictoryDirection {
                dir: dir.node.clone(),
                first,
                second: what,
            };
            diags.push(Diagnostic::error(kind, span).with_related(first_span, "written here"));
        }
        Some(_) => {}
        None => {
            sides.insert(&dir.node, (what, span));
        }
    }
}

/// The index of the place's room, with place `id` added to that room's places; `None` when it
/// names none, or an unknown one (reported).
fn place_room(
    p: &ast::PlaceDecl,
    rooms: &mut [Room],
    id: usize,
    diags: &mut Vec<Diagnostic>,
) -> Option<usize> {
    let r = p.room.as_ref()?;
    match rooms.iter().position(|x| x.name == r.node) {
        Some(i) => {
            rooms[i].places.push(id);
            Some(i)
        }
        None => {
            diags.push(Diagnostic::error(
                DiagnosticKind::UnknownRoom {
                    name: r.node.clone(),
                },
                r.span,
            ));
            None
        }
    }
}

/// The place's extent ([`DEFAULT_RADIUS`] when none is written) and, for a rotated box or a
/// polygon, its outline (the extent is then the outline's bounding box); a negative radius,
/// swapped box corners and a polygon that does not close or has no area are reported.
fn place_extent(p: &ast::PlaceDecl, diags: &mut Vec<Diagnostic>) -> (Extent, Option<Outline>) {
    let Some(e) = &p.extent else {
        return (Extent::Radius(DEFAULT_RADIUS), None);
    };
    let outline = match &e.node {
        ast::Extent::RotatedBox { corners, degrees } => {
            let (x0, y0, x1, y1) = *corners;
            check_box(x0, y0, x1, y1, e.span, diags);
            Some(Outline::rotated_box(x0, y0, x1, y1, degrees.node))
        }
        ast::Extent::Polygon(vertices) => {
            let xy: Vec<(f64, f64)> = vertices.iter().map(|v| v.node).collect();
            match Outline::polygon(&xy) {
                Ok(o) => Some(o),
                Err(kind) => {
                    let span = match kind {
                        DiagnosticKind::PolygonNotClosed { .. } => vertices.last().map(|v| v.span),
                        _ => None,
                    };
                    diags.push(Diagnostic::error(kind, span.unwrap_or(e.span)));
                    return (Extent::Radius(DEFAULT_RADIUS), None);
                }
            }
        }
        _ => None,
    };
    if let Some(o) = outline {
        let (x0, y0, x1, y1) = o.bounds();
        return (Extent::Box { x0, y0, x1, y1 }, Some(o));
    }
    let extent = match e.node {
        ast::Extent::Radius(r) => {
            if r < 0.0 {
                diags.push(Diagnostic::error(
                    DiagnosticKind::NegativeLength {
                        what: "radius",
                        value: r,
                    },
                    e.span,
                ));
            }
            Extent::Radius(r.max(0.0))
        }
        ast::Extent::Box(x0, y0, x1, y1) => {
            check_box(x0, y0, x1, y1, e.span, diags);
            Extent::Box { x0, y0, x1, y1 }
        }
        // Handled above.
        ast::Extent::RotatedBox { .. } | ast::Extent::Polygon(_) => Extent::Radius(DEFAULT_RADIUS),
    };
    (extent, None)
}

/// Box corners in the wrong order are reported.
fn check_box(x0: f64, y0: f64, x1: f64, y1: f64, span: Span, diags: &mut Vec<Diagnostic>) {
    for (lo, hi) in [(x0, x1), (y0, y1)] {
        if lo > hi {
            diags.push(Diagnostic::error(
                DiagnosticKind::InvalidBox { low: lo, high: hi },
                span,
            ));
        }
    }
}

/// Adds one wall, opening, door, corner or parameter to `place`; one written twice is reported.
fn add_feature(place: &mut Place, f: &Feature, diags: &mut Vec<Diagnostic>) {
    let dup = |what: &'static str, name: String, span: Span| {
        Diagnostic::error(DiagnosticKind::DuplicateFeature { what, name }, span)
    };
    match f {
        Feature::Open { dir, degree, span } | Feature::Door { dir, degree, span } => {
            let d = degree_ok(degree, diags);
            place.direction_spans.push((dir.node.clone(), dir.span));
            let (what, set) = match f {
                Feature::Open { .. } => ("open", &mut place.opens),
                _ => ("door", &mut place.doors),
            };
            if set.insert(dir.node.clone(), d).is_some() {
                diags.push(dup(what, dir.node.clone(), *span));
            }
        }
        Feature::Wall { dir, degree, span } => {
            let d = degree_ok(degree, diags);
            place.direction_spans.push((dir.node.clone(), dir.span));
            if place.walls.insert(dir.node.clone(), d).is_some() {
                diags.push(dup("wall", dir.node.clone(), *span));
            }
        }
        Feature::Corner {
            d1,
            d2,
            degree,
            span,
        } => {
            let d = degree_ok(degree, diags);
            place.direction_spans.push((d1.node.clone(), d1.span));
            place.direction_spans.push((d2.node.clone(), d2.span));
            let key = corner_key(&d1.node, &d2.node);
            if place.corners.insert(key, d).is_some() {
                diags.push(dup("corner", format!("{} {}", d1.node, d2.node), *span));
            }
        }
        Feature::Param {
            name,
            key,
            value,
            upper,
            span,
        } => {
            let k = (name.node.clone(), key.as_ref().map(|k| k.node.clone()));
            let hi = upper.as_ref().map_or(value.node, |u| u.node);
            if hi < value.node {
                diags.push(Diagnostic::error(
                    DiagnosticKind::EmptyRange {
                        low: value.node,
                        high: hi,
                    },
                    *span,
                ));
            }
            let expected = Expected {
                lo: value.node,
                hi: hi.max(value.node),
            };
            if place.params.insert(k, expected).is_some() {
                diags.push(dup("param", name.node.clone(), *span));
            }
        }
    }
}
