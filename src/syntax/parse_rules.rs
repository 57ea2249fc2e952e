//! The rule-file parser: pest pairs of `grammar/rules.pest` → [`RuleFile`] with spans. Syntax
//! errors are recovered from at item level (see `recover`), so every broken item of a file is
//! reported. Nothing is resolved here: names stay strings, numbers stay as written (apart from
//! rejecting non-finite ones); the checker does the rest.
//!
//! Depends on pest (through `grammar` and `recover`), `ast`, `span` and `diagnostic`.

use super::ast::*;
use super::diagnostic::{Diagnostic, DiagnosticKind};
use super::grammar::{rules_label, RulesGrammar, RulesRule as R};
use super::recover::{pair_number, pair_span, parse_items};
use super::span::{Ident, Span, Spanned};
use pest::iterators::{Pair, Pairs};

/// Parses a rule file. On failure returns every syntax error found (sorted by position).
///
/// ```
/// let file = lplace::syntax::parse_rules("predicate p(time); |- (q(t) -> p(t), 0.5);").unwrap();
/// assert_eq!(file.items.len(), 2);
/// ```
pub fn parse_rules(text: &str) -> Result<RuleFile, Vec<Diagnostic>> {
    let mut items = Vec::new();
    let mut diags = Vec::new();
    let syntax = parse_items::<RulesGrammar, R>(text, R::item_entry, rules_label, |pair, base| {
        let mut b = Builder {
            base,
            diags: &mut diags,
        };
        if let Some(item) = b.item(pair) {
            items.push(item);
        }
    });
    diags.extend(syntax);
    if diags.is_empty() {
        Ok(RuleFile { items })
    } else {
        diags.sort_by_key(|d| d.span.start);
        Err(diags)
    }
}

/// Parses one formula of the rule language on its own (what `--query` takes: sets of places
/// combined with `!`, `&`, `(+)`). On failure returns the syntax errors.
///
/// ```
/// let f = lplace::syntax::parse_rules::parse_query("!EastWing & in_room(R0)").unwrap();
/// assert!(matches!(f.node, lplace::syntax::ast::Formula::And(_)));
/// ```
pub fn parse_query(text: &str) -> Result<Spanned<Formula>, Vec<Diagnostic>> {
    if let Some(d) = super::recover::nesting_check(text) {
        return Err(vec![d]);
    }
    let mut diags = Vec::new();
    let pairs = match super::recover::parse_detailed::<RulesGrammar, R>(R::query, text) {
        Ok(p) => p,
        Err(e) => return Err(vec![super::recover::syntax_error(text, 0, &e, rules_label)]),
    };
    let mut b = Builder {
        base: 0,
        diags: &mut diags,
    };
    let f = pairs
        .flat_map(|q| q.into_inner())
        .find(|x| x.as_rule() == R::formula)
        .and_then(|x| b.formula(x));
    match f {
        Some(f) if diags.is_empty() => Ok(f),
        _ => {
            if diags.is_empty() {
                diags.push(internal("empty query", Span::new(0, text.len())));
            }
            Err(diags)
        }
    }
}

/// Turns the pairs of one item into AST nodes, shifting spans by `base`.
pub(crate) struct Builder<'d> {
    pub(crate) base: usize,
    pub(crate) diags: &'d mut Vec<Diagnostic>,
}

/// The internal-error diagnostic for a structure the grammar should have excluded.
fn internal(what: &'static str, span: Span) -> Diagnostic {
    Diagnostic::error(DiagnosticKind::Internal { what }, span)
}

impl Builder<'_> {
    /// The span of `p` in the whole file, without the trailing whitespace that pest's implicit
    /// whitespace handling leaves inside rules ending in a repetition.
    fn span(&self, p: &Pair<'_, R>) -> Span {
        pair_span(self.base, p)
    }

    fn ident(&self, p: &Pair<'_, R>) -> Ident {
        Spanned::new(p.as_str().to_string(), self.span(p))
    }

    fn number(&mut self, p: &Pair<'_, R>) -> Spanned<f64> {
        pair_number(self.base, p, self.diags)
    }

    /// The next child of `it`, or an internal error at `at`.
    fn next<'i>(
        &mut self,
        it: &mut pest::iterators::Pairs<'i, R>,
        at: Span,
        what: &'static str,
    ) -> Option<Pair<'i, R>> {
        let p = it.next();
        if p.is_none() {
            self.diags.push(internal(what, at));
        }
        p
    }

    fn item(&mut self, p: Pair<'_, R>) -> Option<RuleItem> {
        let span = self.span(&p);
        let kind = p.as_rule();
        let mut it = p.into_inner();
        match kind {
            R::logic_block => self.logic_block(it, span).map(RuleItem::Logic),
            R::tracker_block => self.tracker_block(it, span).map(RuleItem::Tracker),
            R::domain_decl => {
                it.next(); // keyword
                let name = self.next(&mut it, span, "domain without name")?;
                let name = self.ident(&name);
                let values = it.map(|v| self.ident(&v)).collect();
                Some(RuleItem::Domain(DomainDecl { name, values, span }))
            }
            R::similarity_decl => self.similarity(it, span).map(RuleItem::Similarity),
            R::percept_decl | R::predicate_decl => self.declaration(kind, it, span),
            R::rule => self.rule(span, it, None).map(RuleItem::Rule),
            R::region_decl => self.region(span, it),
            R::group_block => self.group(it, span),
            _ => {
                self.diags.push(internal("unexpected item", span));
                None
            }
        }
    }

    /// The settings of a `logic { … }` block.
    fn logic_block(&mut self, it: Pairs<'_, R>, span: Span) -> Option<LogicBlock> {
        let settings = self.settings(it)?;
        Some(LogicBlock { settings, span })
    }

    /// The settings of a `tracker { … }` block and of its `grid { … }` blocks.
    fn tracker_block(&mut self, it: Pairs<'_, R>, span: Span) -> Option<TrackerBlock> {
        let mut grids = Vec::new();
        let mut settings = Vec::new();
        for p in it {
            match p.as_rule() {
                R::setting => settings.push(self.setting(p)?),
                R::grid_settings => {
                    let gspan = self.span(&p);
                    grids.push((self.settings(p.into_inner())?, gspan));
                }
                _ => {}
            }
        }
        Some(TrackerBlock {
            settings,
            grids,
            span,
        })
    }

    /// The `key = value;` pairs among `it`.
    fn settings(&mut self, it: Pairs<'_, R>) -> Option<Vec<Setting>> {
        it.filter(|s| s.as_rule() == R::setting)
            .map(|s| self.setting(s))
            .collect()
    }

    /// One `key = value;`.
    fn setting(&mut self, s: Pair<'_, R>) -> Option<Setting> {
        let sspan = self.span(&s);
        let mut si = s.into_inner();
        let key = self.next(&mut si, sspan, "setting without key")?;
        let value = self.next(&mut si, sspan, "setting without value")?;
        let vspan = self.span(&value);
        let v = if value.as_rule() == R::number {
            SettingValue::Number(self.number(&value).node)
        } else {
            SettingValue::Word(value.as_str().to_string())
        };
        Some(Setting {
            key: self.ident(&key),
            value: Spanned::new(v, vspan),
        })
    }

    /// A `similarity NAME = SHAPE(field: value, …)` declaration.
    fn similarity(&mut self, mut it: Pairs<'_, R>, span: Span) -> Option<SimilarityDecl> {
        it.next();
        let name = self.next(&mut it, span, "similarity without name")?;
        let name = self.ident(&name);
        let shape = self.next(&mut it, span, "similarity without shape")?;
        let shape = self.ident(&shape);
        let mut fields = Vec::new();
        for f in it {
            let fspan = self.span(&f);
            let mut fi = f.into_inner();
            let k = self.next(&mut fi, fspan, "field without name")?;
            let v = self.next(&mut fi, fspan, "field without value")?;
            fields.push((self.ident(&k), self.number(&v)));
        }
        Some(SimilarityDecl {
            name,
            shape,
            fields,
            span,
        })
    }

    /// A `percept` or `predicate` declaration (`kind` says which).
    fn declaration(&mut self, kind: R, mut it: Pairs<'_, R>, span: Span) -> Option<RuleItem> {
        it.next();
        let name = self.next(&mut it, span, "declaration without name")?;
        let name = self.ident(&name);
        let mut roles = Vec::new();
        let mut similarity = None;
        for x in it {
            match x.as_rule() {
                R::roles => roles = x.into_inner().map(|r| self.role(&r)).collect(),
                _ => similarity = Some(self.ident(&x)),
            }
        }
        if kind == R::percept_decl {
            Some(RuleItem::Percept(PerceptDecl {
                name,
                roles,
                similarity,
                span,
            }))
        } else {
            Some(RuleItem::Predicate(PredicateDecl { name, roles, span }))
        }
    }

    /// A `group NAME { rules }` block: its rules carry the group's name.
    fn group(&mut self, mut it: Pairs<'_, R>, span: Span) -> Option<RuleItem> {
        it.next(); // keyword
        let name = self.next(&mut it, span, "group without name")?;
        let name = self.ident(&name);
        let mut rules = Vec::new();
        for r in it.filter(|r| r.as_rule() == R::rule) {
            let rspan = self.span(&r);
            rules.push(self.rule(rspan, r.into_inner(), Some(name.clone()))?);
        }
        Some(RuleItem::Group(GroupBlock { name, rules, span }))
    }

    /// A rule: its schemas (`for all …`) and its sequent; `group` names its evidence group.
    fn rule(&mut self, span: Span, it: Pairs<'_, R>, group: Option<Ident>) -> Option<Rule> {
        let mut schemas = Vec::new();
        let mut sequent = None;
        for x in it {
            match x.as_rule() {
                R::schema => schemas.push(self.schema(x)?),
                R::sequent => sequent = Some(self.sequent(x)?),
                _ => {}
            }
        }
        let Some((body, head, weight)) = sequent else {
            self.diags.push(internal("rule without sequent", span));
            return None;
        };
        Some(Rule {
            schemas,
            body,
            head,
            weight,
            group,
            span,
        })
    }

    /// `region Name = {…};` or `region Name = kind k;`, after the keyword.
    fn region(&mut self, span: Span, mut it: Pairs<'_, R>) -> Option<RuleItem> {
        it.next(); // keyword
        let name = self.next(&mut it, span, "region without name")?;
        let name = self.ident(&name);
        let body = self.next(&mut it, span, "region without places")?;
        let members = if body.as_rule() == R::region_kind {
            let Some(kind) = body.into_inner().find(|x| x.as_rule() == R::ident) else {
                self.diags.push(internal("region without kind", span));
                return None;
            };
            RegionMembers::Kind(self.ident(&kind))
        } else {
            RegionMembers::Places(body.into_inner().map(|v| self.ident(&v)).collect())
        };
        Some(RuleItem::Region(RegionDecl {
            name,
            members,
            span,
        }))
    }

    fn role(&self, p: &Pair<'_, R>) -> Spanned<ArgRole> {
        let role = match p.as_str() {
            "value" => ArgRole::Value,
            "expect" => ArgRole::Expect,
            "time" => ArgRole::Time,
            other => ArgRole::Domain(other.to_string()),
        };
        Spanned::new(role, self.span(p))
    }

    fn schema(&mut self, p: Pair<'_, R>) -> Option<Schema> {
        let span = self.span(&p);
        let mut vars = Vec::new();
        let mut source = None;
        for x in p.into_inner() {
            match x.as_rule() {
                R::schema_vars => vars = x.into_inner().map(|v| self.ident(&v)).collect(),
                R::schema_source => {
                    let xspan = self.span(&x);
                    let inner = self.next(&mut x.into_inner(), xspan, "empty schema source")?;
                    source = Some(match inner.as_rule() {
                        R::tuple_set => SchemaSource::Tuples(
                            inner
                                .into_inner()
                                .map(|t| {
                                    let tspan = self.span(&t);
                                    Spanned::new(
                                        t.into_inner().map(|v| self.ident(&v)).collect(),
                                        tspan,
                                    )
                                })
                                .collect(),
                        ),
                        _ => SchemaSource::Domain(self.ident(&inner)),
                    });
                }
                _ => {}
            }
        }
        let Some(source) = source else {
            self.diags.push(internal("schema without source", span));
            return None;
        };
        Some(Schema { vars, source, span })
    }

    #[allow(clippy::type_complexity)]
    fn sequent(
        &mut self,
        p: Pair<'_, R>,
    ) -> Option<(Spanned<Formula>, Literal, Option<Spanned<f64>>)> {
        let span = self.span(&p);
        let mut it = p.into_inner();
        let first = self.next(&mut it, span, "empty sequent")?;
        match first.as_rule() {
            R::sequent => {
                let (body, head, weight) = self.sequent(first)?;
                let outer = it.next().map(|w| self.number(&w));
                let weight = match (weight, outer) {
                    (Some(w), Some(o)) => {
                        self.diags
                            .push(Diagnostic::error(DiagnosticKind::DuplicateWeight, o.span));
                        Some(w)
                    }
                    (w, o) => w.or(o),
                };
                Some((body, head, weight))
            }
            _ => {
                // body ~ arrow ~ literal
                let disj = self.next(&mut first.into_inner(), span, "empty body")?;
                let body = self.formula(disj)?;
                let lit = it.find(|x| x.as_rule() == R::literal);
                let Some(lit) = lit else {
                    self.diags.push(internal("sequent without head", span));
                    return None;
                };
                let head = self.literal(lit)?;
                Some((body, head, None))
            }
        }
    }

    fn literal(&mut self, p: Pair<'_, R>) -> Option<Literal> {
        let span = self.span(&p);
        let mut negated = false;
        let mut atom = None;
        for x in p.into_inner() {
            match x.as_rule() {
                R::not_op => negated = true,
                _ => atom = Some(self.atom(x)),
            }
        }
        let Some(atom) = atom else {
            self.diags.push(internal("literal without atom", span));
            return None;
        };
        Some(Literal {
            negated,
            atom,
            span,
        })
    }

    fn atom(&mut self, p: Pair<'_, R>) -> Atom {
        let span = self.span(&p);
        let mut it = p.into_inner();
        let name = match it.next() {
            Some(n) => self.ident(&n),
            None => Spanned::new(String::new(), span),
        };
        let args = it
            .filter(|x| x.as_rule() == R::arglist)
            .flat_map(|x| x.into_inner())
            .map(|t| self.term(t))
            .collect();
        Atom { name, args, span }
    }

    fn term(&mut self, p: Pair<'_, R>) -> Spanned<Term> {
        let span = self.span(&p);
        let term = match p.as_rule() {
            R::place_ref => {
                let mut it = p.into_inner();
                let name = it.next().map_or("", |n| n.as_str());
                let name = name.strip_suffix("_i").unwrap_or(name).to_string();
                let key = it
                    .next()
                    .and_then(|k| k.into_inner().next())
                    .map(|k| k.as_str().to_string());
                Term::PlaceRef { name, key }
            }
            R::tuple => Term::Tuple(p.into_inner().map(|t| self.term(t)).collect()),
            R::number => Term::Number(self.number(&p).node),
            _ => {
                let s = p.as_str();
                if s == "t" {
                    Term::Time
                } else if s.starts_with(|c: char| c.is_ascii_uppercase()) {
                    Term::Const(s.to_string())
                } else {
                    Term::Var(s.to_string())
                }
            }
        };
        Spanned::new(term, span)
    }

    /// Converts any formula-level pair (`formula`, `disj`, `conj`, `times`, `unary`, `group`,
    /// `number`, `atom`).
    fn formula(&mut self, p: Pair<'_, R>) -> Option<Spanned<Formula>> {
        let span = self.span(&p);
        match p.as_rule() {
            R::formula => {
                // disj (arrow disj)*, right-associative.
                let mut parts = Vec::new();
                for x in p.into_inner().filter(|x| x.as_rule() != R::arrow) {
                    parts.push(self.formula(x)?);
                }
                let mut acc = parts.pop()?;
                while let Some(lhs) = parts.pop() {
                    let s = lhs.span.join(acc.span);
                    acc = Spanned::new(Formula::Implies(Box::new(lhs), Box::new(acc)), s);
                }
                Some(acc)
            }
            R::disj | R::conj | R::times => {
                let kind = p.as_rule();
                let mut parts = Vec::new();
                for x in p.into_inner().filter(|x| x.as_rule() != R::or_op) {
                    parts.push(self.formula(x)?);
                }
                if parts.len() == 1 {
                    return parts.pop();
                }
                let f = match kind {
                    R::disj => Formula::Or(parts),
                    R::conj => Formula::And(parts),
                    _ => Formula::Times(parts),
                };
                Some(Spanned::new(f, span))
            }
            R::unary => {
                let mut nots = Vec::new();
                let mut inner = None;
                for x in p.into_inner() {
                    if x.as_rule() == R::not_op {
                        nots.push(self.span(&x).start);
                    } else {
                        inner = Some(self.formula(x)?);
                    }
                }
                let mut acc = inner?;
                while let Some(start) = nots.pop() {
                    let s = Span::new(start, acc.span.end);
                    acc = Spanned::new(Formula::Not(Box::new(acc)), s);
                }
                Some(acc)
            }
            R::group => {
                let mut it = p.into_inner();
                let inner = self.next(&mut it, span, "empty group")?;
                let f = self.formula(inner)?;
                match it.next() {
                    Some(w) => {
                        let w = self.number(&w);
                        Some(Spanned::new(Formula::Weighted(Box::new(f), w), span))
                    }
                    None => Some(f),
                }
            }
            R::number => Some(Spanned::new(Formula::Degree(self.number(&p).node), span)),
            R::atom => Some(Spanned::new(Formula::Atom(self.atom(p)), span)),
            _ => {
                self.diags.push(internal("unexpected formula", span));
                None
            }
        }
    }
}
