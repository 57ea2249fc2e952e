//! The map-file parser: pest pairs of `grammar/map.pest` → [`MapFile`] with spans, recovering at
//! item level like the rule parser. Nothing is validated here beyond the grammar and finite
//! numbers; `map::Map::from_ast` checks names, lengths and degrees.
//!
//! Depends on pest (through `grammar` and `recover`), `ast`, `span` and `diagnostic`.

use super::ast::*;
use super::diagnostic::{Diagnostic, DiagnosticKind};
use super::grammar::{map_label, MapGrammar, MapRule as R};
use super::recover::{pair_number, pair_span, parse_items};
use super::span::{Ident, Span, Spanned};
use pest::iterators::Pair;

/// Parses a map file. On failure returns every syntax error found (sorted by position).
///
/// ```
/// let map = lplace::syntax::parse_map("map m; place A corner at (0, 0); place B corner at (1, 0) {}\npath A -- B;").unwrap();
/// assert_eq!(map.items.len(), 3);
/// ```
pub fn parse_map(text: &str) -> Result<MapFile, Vec<Diagnostic>> {
    let mut name: Option<Ident> = None;
    let mut items = Vec::new();
    let mut diags = Vec::new();
    let syntax = parse_items::<MapGrammar, R>(text, R::item_entry, map_label, |pair, base| {
        let mut b = Builder {
            base,
            diags: &mut diags,
        };
        if pair.as_rule() == R::map_name {
            let span = b.span(&pair);
            if let Some(n) = pair.into_inner().nth(1) {
                if name.is_some() {
                    b.diags
                        .push(Diagnostic::error(DiagnosticKind::DuplicateMapName, span));
                } else {
                    name = Some(b.ident(&n));
                }
            }
        } else if let Some(item) = b.item(pair) {
            items.push(item);
        }
    });
    diags.extend(syntax);
    if diags.is_empty() {
        Ok(MapFile { name, items })
    } else {
        diags.sort_by_key(|d| d.span.start);
        Err(diags)
    }
}

struct Builder<'d> {
    base: usize,
    diags: &'d mut Vec<Diagnostic>,
}

impl Builder<'_> {
    /// The span of `p` in the whole file, without trailing whitespace (see `parse_rules`).
    fn span(&self, p: &Pair<'_, R>) -> Span {
        pair_span(self.base, p)
    }

    fn ident(&self, p: &Pair<'_, R>) -> Ident {
        Spanned::new(p.as_str().to_string(), self.span(p))
    }

    fn number(&mut self, p: &Pair<'_, R>) -> Spanned<f64> {
        pair_number(self.base, p, self.diags)
    }

    fn numbers(&mut self, p: Pair<'_, R>) -> Vec<f64> {
        p.into_inner()
            .filter(|x| x.as_rule() == R::number)
            .map(|x| self.number(&x).node)
            .collect()
    }

    fn internal(&mut self, what: &'static str, span: Span) {
        self.diags
            .push(Diagnostic::error(DiagnosticKind::Internal { what }, span));
    }

    fn item(&mut self, p: Pair<'_, R>) -> Option<MapItem> {
        let span = self.span(&p);
        let kind = p.as_rule();
        let children: Vec<Pair<'_, R>> = p.into_inner().collect();
        if kind == R::axis_decl {
            let n = children.iter().find(|x| x.as_rule() == R::number)?;
            let degrees = self.number(n);
            return Some(MapItem::Axis(AxisDecl { degrees, span }));
        }
        if kind == R::start_decl {
            let point = children.iter().find(|x| x.as_rule() == R::point)?.clone();
            let pspan = self.span(&point);
            let xy = self.numbers(point);
            let position = Spanned::new((xy.first().copied()?, xy.get(1).copied()?), pspan);
            return Some(MapItem::Start(StartDecl { position, span }));
        }
        let idents: Vec<Ident> = children
            .iter()
            .filter(|x| x.as_rule() == R::ident)
            .map(|x| self.ident(x))
            .collect();
        let Some(name) = idents.first().cloned() else {
            self.internal("item without name", span);
            return None;
        };
        match kind {
            R::kinds_decl => Some(MapItem::Kinds(KindsDecl {
                kinds: idents,
                span,
            })),
            R::room_decl => {
                let label = children.iter().find(|x| x.as_rule() == R::string).map(|s| {
                    let text = s.clone().into_inner().next().map_or("", |t| t.as_str());
                    Spanned::new(text.to_string(), self.span(s))
                });
                Some(MapItem::Room(RoomDecl { name, label, span }))
            }
            R::landmark_decl => self.landmark(&children, name, span).map(MapItem::Landmark),
            R::place_decl => self.place(&children, &idents, span).map(MapItem::Place),
            R::path_decl => self.path(&children, &idents, span).map(MapItem::Path),
            _ => {
                self.internal("unexpected item", span);
                None
            }
        }
    }

    /// A `landmark` or `beacon` item from its parts; `None` when they are incomplete.
    fn landmark(
        &mut self,
        children: &[Pair<'_, R>],
        name: Ident,
        span: Span,
    ) -> Option<LandmarkDecl> {
        let kind = if children.first().map(|k| k.as_rule()) == Some(R::kw_beacon) {
            LandmarkKind::Beacon
        } else {
            LandmarkKind::Landmark
        };
        let point = children.iter().find(|x| x.as_rule() == R::point)?.clone();
        let pspan = self.span(&point);
        let xy = self.numbers(point);
        let position = Spanned::new((xy.first().copied()?, xy.get(1).copied()?), pspan);
        let id = match children.iter().find(|x| x.as_rule() == R::integer) {
            Some(i) => {
                let ispan = self.span(i);
                match i.as_str().parse::<i64>() {
                    Ok(v) => Some(Spanned::new(v, ispan)),
                    Err(_) => {
                        self.diags.push(Diagnostic::error(
                            DiagnosticKind::NumberOutOfRange {
                                text: i.as_str().to_string(),
                            },
                            ispan,
                        ));
                        None
                    }
                }
            }
            None => None,
        };
        Some(LandmarkDecl {
            kind,
            name,
            position,
            id,
            span,
        })
    }

    /// A `place` item from its parts (`idents`: name, kind, room); `None` when incomplete.
    fn place(
        &mut self,
        children: &[Pair<'_, R>],
        idents: &[Ident],
        span: Span,
    ) -> Option<PlaceDecl> {
        let name = idents.first().cloned()?;
        let Some(kind) = idents.get(1).cloned() else {
            self.internal("place without kind", span);
            return None;
        };
        let room = idents.get(2).cloned();
        let pose_pair = children.iter().find(|x| x.as_rule() == R::pose)?.clone();
        let pspan = self.span(&pose_pair);
        let v = self.numbers(pose_pair);
        let pose = Spanned::new(
            (v.first().copied()?, v.get(1).copied()?, v.get(2).copied()),
            pspan,
        );
        let extent = match children.iter().find(|x| x.as_rule() == R::extent) {
            Some(e) => Some(self.extent(e)?),
            None => None,
        };
        let mut features = Vec::new();
        if let Some(body) = children.iter().find(|x| x.as_rule() == R::place_body) {
            for f in body.clone().into_inner() {
                if let Some(f) = self.feature(f) {
                    features.push(f);
                }
            }
        }
        Some(PlaceDecl {
            name,
            kind,
            room,
            pose,
            extent,
            features,
            span,
        })
    }

    /// A place's `extent radius R` or `extent box (…)`; `None` when incomplete.
    fn extent(&mut self, e: &Pair<'_, R>) -> Option<Spanned<Extent>> {
        let espan = self.span(e);
        let inner = e
            .clone()
            .into_inner()
            .find(|x| x.as_rule() != R::kw_extent)?;
        let ext = match inner.as_rule() {
            R::box_extent => self.box_extent(inner)?,
            R::polygon => {
                let mut vertices = Vec::new();
                for pt in inner.into_inner().filter(|x| x.as_rule() == R::point) {
                    let pspan = self.span(&pt);
                    let xy = self.numbers(pt);
                    let v = (xy.first().copied()?, xy.get(1).copied()?);
                    vertices.push(Spanned::new(v, pspan));
                }
                Extent::Polygon(vertices)
            }
            _ => Extent::Radius(self.numbers(inner).first().copied()?),
        };
        Some(Spanned::new(ext, espan))
    }

    /// `box (x0, y0, x1, y1) [rotated D]`; `None` when incomplete.
    fn box_extent(&mut self, inner: Pair<'_, R>) -> Option<Extent> {
        let rotation = inner
            .clone()
            .into_inner()
            .find(|x| x.as_rule() == R::rotation);
        let v = self.numbers(inner);
        let corners = (
            v.first().copied()?,
            v.get(1).copied()?,
            v.get(2).copied()?,
            v.get(3).copied()?,
        );
        let Some(rotation) = rotation else {
            return Some(Extent::Box(corners.0, corners.1, corners.2, corners.3));
        };
        let n = rotation.into_inner().find(|x| x.as_rule() == R::number)?;
        let degrees = self.number(&n);
        Some(Extent::RotatedBox { corners, degrees })
    }

    /// A `path` item from its parts (`idents`: both ends); `None` when incomplete.
    fn path(&mut self, children: &[Pair<'_, R>], idents: &[Ident], span: Span) -> Option<PathDecl> {
        let from = idents.first().cloned()?;
        let Some(to) = idents.get(1).cloned() else {
            self.internal("path without second end", span);
            return None;
        };
        let mut length = None;
        let mut heading = None;
        let mut last_kw = None;
        for c in children {
            match c.as_rule() {
                R::kw_length | R::kw_heading => last_kw = Some(c.as_rule()),
                R::number => {
                    let n = self.number(c);
                    if last_kw == Some(R::kw_length) {
                        length = Some(n);
                    } else {
                        heading = Some(n);
                    }
                }
                _ => {}
            }
        }
        Some(PathDecl {
            from,
            to,
            length,
            heading,
            span,
        })
    }

    fn feature(&mut self, p: Pair<'_, R>) -> Option<Feature> {
        let span = self.span(&p);
        let kind = p.as_rule();
        let children: Vec<Pair<'_, R>> = p.into_inner().collect();
        let idents: Vec<Ident> = children
            .iter()
            .filter(|x| x.as_rule() == R::ident)
            .map(|x| self.ident(x))
            .collect();
        let numbers: Vec<Spanned<f64>> = children
            .iter()
            .filter(|x| x.as_rule() == R::number)
            .map(|n| self.number(n))
            .collect();
        let degree = numbers.first().cloned();
        match kind {
            R::wall => Some(Feature::Wall {
                dir: idents.first()?.clone(),
                degree,
                span,
            }),
            R::open => Some(Feature::Open {
                dir: idents.first()?.clone(),
                degree,
                span,
            }),
            R::door => Some(Feature::Door {
                dir: idents.first()?.clone(),
                degree,
                span,
            }),
            R::corner => Some(Feature::Corner {
                d1: idents.first()?.clone(),
                d2: idents.get(1)?.clone(),
                degree,
                span,
            }),
            R::param => Some(Feature::Param {
                name: idents.first()?.clone(),
                key: idents.get(1).cloned(),
                value: degree?,
                upper: numbers.get(1).cloned(),
                span,
            }),
            _ => {
                self.internal("unexpected feature", span);
                None
            }
        }
    }
}
