//! Surveying a building: from a run whose frames carry the true place, fit each place's
//! expected values of the percepts the rules compare with map parameters, and write them into
//! the map text **by editing the parameters' spans only** (comments, walls, layout and every
//! other byte stay as written). Library code behind `lplace survey`.
//! Depends on `io::record` (frames), `syntax` (the map's and rules' ASTs with their spans) and,
//! to score a map on frames, `engine` (the evaluator and the trackers); not on the command line.
//!
//! # What is fitted
//! The rules say which percept feeds which parameter: an atom `free_range(r, d, free_i(d), t)`
//! compares the percept `free_range` with the place's parameter `free`, keyed by the percept's
//! own argument `d` ([`links_from_rules`]). For each place and each `(parameter, key)`, the
//! values the percept took on the frames inside the place are sorted and the expectation is the
//! range from the `lo`-th to the `hi`-th quantile (nearest rank: index `⌊q·(n − 1)⌋`; 10th to
//! 90th percentile by default), written `param free(North) = lo .. hi;`. Each fitted place
//! also gets `param scans = n;`, the frames its fit stands on: the grid tracker takes less of
//! the evidence of a place fitted from few scans (`engine::grid_tracker`, `evidence_scans`).
//!
//! # Visits
//! A visit to a place is a stretch of frames in it; it ends once the robot has travelled
//! `visit_gap_m` (odometry) without a frame in the place, so jitter across a boundary does not
//! start new visits. [`Protocol::FirstVisits`] fits on each place's first visit only, so that
//! the later visits are held-out data.
//!
//! # One survey, end to end
//! [`Survey`] (in `run`) is the whole of `lplace survey` below the command line: from the
//! texts of the map and rules and the records of the run to the written map text, the
//! per-place report and, for first-visit fits, the score on the later visits. The command line
//! and the Python binding both call it; they only read files and print.

use std::collections::BTreeMap;

use crate::engine::grid_tracker::SCANS_PARAM;
use crate::io::record::{FrameRecord, Odometry};
use crate::io::stream::FrameMeta;
use crate::logic::Decision;
use crate::report::run::StreamRun;
use crate::syntax::ast::{Feature, Formula, MapFile, MapItem, RuleFile, RuleItem, Term};

mod run;

pub use run::{
    label_frames, nearest_label, parse_labels, LabelRow, PlaceReport, Records, Survey,
    SurveyOutcome, Truth,
};

/// A percept feeding a map parameter (from the rules).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct ParamLink {
    /// The percept's name (`free_range`).
    pub percept: String,
    /// The parameter's name in the map (`free`).
    pub param: String,
    /// Whether the parameter is keyed by the percept's arguments (`free(North)`).
    pub keyed: bool,
}

/// Which frames a fit uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Protocol {
    /// Every frame with a place.
    All,
    /// Each place's first visit only.
    FirstVisits,
}

/// Parameters of a survey.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurveyConfig {
    /// Lower quantile of the expectation (default 0.1).
    pub lo: f64,
    /// Upper quantile (default 0.9).
    pub hi: f64,
    /// Odometry distance outside a place that ends a visit, metres (default 2).
    pub visit_gap_m: f64,
    /// Places fitted from fewer frames are warned about (default 10).
    pub min_scans: usize,
}

impl Default for SurveyConfig {
    fn default() -> Self {
        SurveyConfig {
            lo: 0.1,
            hi: 0.9,
            visit_gap_m: 2.0,
            min_scans: 10,
        }
    }
}

/// One fitted parameter of a place.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamFit {
    /// Parameter name.
    pub name: String,
    /// Key constant, for keyed parameters.
    pub key: Option<String>,
    /// Lower and upper end of the expected range.
    pub lo: f64,
    /// See `lo`.
    pub hi: f64,
    /// Values it was fitted from.
    pub samples: usize,
}

/// Everything fitted for one place.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaceFit {
    /// The place.
    pub place: String,
    /// Frames used.
    pub scans: usize,
    /// Its parameters, sorted by name and key.
    pub params: Vec<ParamFit>,
}

impl PlaceFit {
    /// The median width `hi − lo` of the place's fitted ranges: how spread its readings are.
    pub fn spread(&self) -> f64 {
        let mut w: Vec<f64> = self.params.iter().map(|p| p.hi - p.lo).collect();
        w.sort_by(f64::total_cmp);
        w.get(w.len() / 2).copied().unwrap_or(0.0)
    }
}

/// Why a survey could not be made or its map not written.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SurveyError {
    /// The map or the rules do not parse, or the written map does not load with the rules
    /// (first-visit scoring): every diagnostic, with the file to render them against.
    #[error(transparent)]
    Load(#[from] crate::engine::LoadError),
    /// Quantiles outside `0 ≤ lo ≤ hi ≤ 1` (or NaN).
    #[error("quantiles need 0 ≤ lo ≤ hi ≤ 1, not {lo} and {hi}")]
    Quantiles {
        /// Lower quantile given.
        lo: f64,
        /// Upper quantile given.
        hi: f64,
    },
    /// No rule links a percept with a place parameter.
    #[error("{rules}: no rule compares a percept with a place parameter (such as `free_i(d)`): nothing to fit")]
    NothingToFit {
        /// The rule file's name.
        rules: String,
    },
    /// A row of a labels CSV that is neither `t,place` nor a header.
    #[error("line {line}: expected `t,place`")]
    LabelRow {
        /// 1-based line.
        line: usize,
    },
    /// A fitted place is not declared in the map.
    #[error("place `{place}` was fitted but the map does not declare it")]
    UnknownPlace {
        /// The place.
        place: String,
    },
    /// A declaration's span does not lie on the text (the AST is not this text's).
    #[error("the map's syntax tree does not match its text at byte {at}")]
    SpanMismatch {
        /// Where.
        at: usize,
    },
}

/// The percept → parameter links of a rule file: every atom with an argument `x_i` or
/// `x_i(Key)` (a place parameter other than `P_i`, `R_i`) links the atom's name to `x`; keyed
/// when written with a key. Sorted, without duplicates.
pub fn links_from_rules(rules: &RuleFile) -> Vec<ParamLink> {
    let mut out = Vec::new();
    for item in &rules.items {
        if let RuleItem::Rule(r) = item {
            collect_links(&r.body.node, &mut out);
        }
    }
    out.sort();
    out.dedup();
    out
}

fn collect_links(f: &Formula, out: &mut Vec<ParamLink>) {
    match f {
        Formula::Atom(a) => {
            for arg in &a.args {
                if let Term::PlaceRef { name, key } = &arg.node {
                    if name != "P" && name != "R" {
                        out.push(ParamLink {
                            percept: a.name.node.clone(),
                            param: name.clone(),
                            keyed: key.is_some(),
                        });
                    }
                }
            }
        }
        Formula::Degree(_) => {}
        Formula::Not(x) | Formula::Weighted(x, _) => collect_links(&x.node, out),
        Formula::And(xs) | Formula::Times(xs) | Formula::Or(xs) => {
            for x in xs {
                collect_links(&x.node, out);
            }
        }
        Formula::Implies(a, b) => {
            collect_links(&a.node, out);
            collect_links(&b.node, out);
        }
    }
}

/// Per frame, its place (`labels[k]`) and which visit to that place it belongs to (0 = the
/// first), `None` outside every place. `labels` gives each frame's true place.
pub fn visits(frames: &[FrameRecord], labels: &[Option<String>], gap_m: f64) -> Vec<Option<u32>> {
    // Per place: (visits so far, odometer when last seen).
    let mut seen: BTreeMap<&str, (u32, f64)> = BTreeMap::new();
    let mut odometer = 0.0;
    let mut out = Vec::with_capacity(frames.len());
    for (f, label) in frames.iter().zip(labels) {
        if let Some(o) = &f.odometry {
            let ds = o.dx.hypot(o.dy);
            if ds.is_finite() {
                odometer += ds;
            }
        }
        let Some(place) = label.as_deref() else {
            out.push(None);
            continue;
        };
        let entry = seen.entry(place).or_insert((0, odometer));
        if odometer - entry.1 > gap_m {
            entry.0 += 1;
        }
        entry.1 = odometer;
        out.push(Some(entry.0));
    }
    out
}

/// Fits every place with frames under `protocol` (see the module docs). Places are in name
/// order; within a place, parameters by name and key.
pub fn fit(
    frames: &[FrameRecord],
    labels: &[Option<String>],
    links: &[ParamLink],
    protocol: Protocol,
    cfg: &SurveyConfig,
) -> Vec<PlaceFit> {
    let visit = visits(frames, labels, cfg.visit_gap_m);
    type Values = BTreeMap<(String, Option<String>), Vec<f64>>;
    let mut per_place: BTreeMap<&str, (usize, Values)> = BTreeMap::new();
    for ((f, label), v) in frames.iter().zip(labels).zip(&visit) {
        let (Some(place), Some(v)) = (label.as_deref(), v) else {
            continue;
        };
        if protocol == Protocol::FirstVisits && *v > 0 {
            continue;
        }
        let (scans, values) = per_place.entry(place).or_default();
        *scans += 1;
        for p in &f.percepts {
            let Some(value) = p.value.filter(|v| v.is_finite()) else {
                continue;
            };
            for link in links.iter().filter(|l| l.percept == p.name) {
                let key = link.keyed.then(|| p.args.join(", "));
                values
                    .entry((link.param.clone(), key))
                    .or_default()
                    .push(value);
            }
        }
    }
    per_place
        .into_iter()
        .map(|(place, (scans, values))| PlaceFit {
            place: place.to_owned(),
            scans,
            params: values
                .into_iter()
                .map(|((name, key), mut v)| {
                    v.sort_by(f64::total_cmp);
                    let at = |q: f64| {
                        let i = (q * (v.len() - 1) as f64).floor().max(0.0) as usize;
                        v.get(i).copied().unwrap_or(0.0)
                    };
                    ParamFit {
                        name,
                        key,
                        lo: at(cfg.lo),
                        hi: at(cfg.hi),
                        samples: v.len(),
                    }
                })
                .collect(),
        })
        .collect()
}

/// Per fitted place (in the order of `fits`), how its fit holds on the place's later visits:
/// `(within, readings)`, the readings of fitted parameters taken on frames of visits after the
/// first (gap `gap_m`, as [`visits`]) and how many of them lie within the fitted range. `None`
/// for a place never visited again. A fit from one visit holds only what that visit saw; this
/// says how much of the next visits that is.
pub fn later_within(
    frames: &[FrameRecord],
    labels: &[Option<String>],
    links: &[ParamLink],
    fits: &[PlaceFit],
    gap_m: f64,
) -> Vec<Option<(usize, usize)>> {
    let visit = visits(frames, labels, gap_m);
    let index: BTreeMap<&str, usize> = fits
        .iter()
        .enumerate()
        .map(|(k, f)| (f.place.as_str(), k))
        .collect();
    let mut out = vec![None; fits.len()];
    for ((f, label), v) in frames.iter().zip(labels).zip(&visit) {
        let (Some(&k), Some(1..)) = (label.as_deref().and_then(|p| index.get(p)), v) else {
            continue;
        };
        let (Some(fit), Some(slot)) = (fits.get(k), out.get_mut(k)) else {
            continue;
        };
        let (within, readings) = slot.get_or_insert((0, 0));
        for p in &f.percepts {
            let Some(value) = p.value.filter(|v| v.is_finite()) else {
                continue;
            };
            for link in links.iter().filter(|l| l.percept == p.name) {
                let key = link.keyed.then(|| p.args.join(", "));
                let range = fit
                    .params
                    .iter()
                    .find(|q| q.name == link.param && q.key == key);
                if let Some(q) = range {
                    *readings += 1;
                    *within += usize::from((q.lo..=q.hi).contains(&value));
                }
            }
        }
    }
    out
}

/// Steps every frame through `run` — the per-frame loop of `lplace eval`: the engine,
/// conditioned on the record's `region` when it names one, then the run's tracker — and returns
/// the decisions, one per frame. Percepts a frame cannot use are left out of it.
pub fn decide_all(run: &mut StreamRun, frames: &[FrameRecord]) -> Vec<Decision> {
    let schema = run.schema();
    let mut frame = run.engine().new_frame();
    let mut rejected = Vec::new();
    frames
        .iter()
        .enumerate()
        .map(|(k, rec)| {
            rejected.clear();
            rec.fill(run.engine().percepts(), &mut frame, &mut rejected);
            let truth = rec.truth.as_ref();
            let meta = FrameMeta {
                line: k as u64 + 1,
                t: rec.t,
                odometry: rec.odometry.unwrap_or_default(),
                heading: rec.heading,
                truth_known: truth.is_some(),
                truth_place: truth
                    .and_then(|t| t.place.as_deref())
                    .and_then(|p| schema.place(p)),
                truth_pose: truth.and_then(|t| t.pose),
                region: rec
                    .region
                    .as_deref()
                    .and_then(|r| schema.region(r.as_bytes())),
                restart: None,
            };
            run.step(&frame, &meta)
        })
        .collect()
}

/// How a map does on some frames: of those at a place, how many were decided, how many of those
/// right, how many confidently wrong (necessity ≥ [`crate::report::summary::CONFIDENT`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Score {
    /// Frames scored whose truth is a place.
    pub at_place: u64,
    /// … on which a place was decided.
    pub decided: u64,
    /// … the right one.
    pub right: u64,
    /// … a wrong one with necessity ≥ 0.9.
    pub confidently_wrong: u64,
}

impl Score {
    /// `decided / at_place`.
    pub fn decided_rate(&self) -> f64 {
        self.decided as f64 / self.at_place.max(1) as f64
    }
    /// `right / decided`.
    pub fn right_of_decided(&self) -> f64 {
        self.right as f64 / self.decided.max(1) as f64
    }
    /// `confidently_wrong / at_place`.
    pub fn confidently_wrong_rate(&self) -> f64 {
        self.confidently_wrong as f64 / self.at_place.max(1) as f64
    }

    /// Scores the frames `k` with `keep(k)`: `decisions[k]` against `truth[k]` (a place index).
    pub fn of(
        decisions: &[Decision],
        truth: &[Option<usize>],
        keep: impl Fn(usize) -> bool,
    ) -> Score {
        let mut s = Score::default();
        for (k, (d, t)) in decisions.iter().zip(truth).enumerate() {
            let Some(t) = t else { continue };
            if !keep(k) {
                continue;
            }
            s.at_place += 1;
            if let Decision::Place { place, necessity } = *d {
                s.decided += 1;
                if place == *t {
                    s.right += 1;
                } else if necessity >= crate::report::summary::CONFIDENT {
                    s.confidently_wrong += 1;
                }
            }
        }
        s
    }
}

impl std::fmt::Display for Score {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} scan(s) at a place: decided {:.1} %, right of decided {:.1} %, confidently wrong {:.1} %",
            self.at_place,
            100.0 * self.decided_rate(),
            100.0 * self.right_of_decided(),
            100.0 * self.confidently_wrong_rate()
        )
    }
}

/// Every `k`-th frame of `frames` (the first, the `k`-th, …), each with the odometry of the
/// frames it stands for composed into one increment: the same run logged `k` times more
/// sparsely. `k = 0` is taken as 1.
pub fn thin(frames: &[FrameRecord], k: usize) -> Vec<FrameRecord> {
    let k = k.max(1);
    let mut out = Vec::with_capacity(frames.len() / k + 1);
    let mut acc = Odometry::default();
    for (i, f) in frames.iter().enumerate() {
        if let Some(o) = &f.odometry {
            acc = compose(acc, *o);
        }
        if i % k == 0 {
            let mut kept = f.clone();
            if kept.odometry.is_some() || i > 0 {
                kept.odometry = Some(acc);
            }
            out.push(kept);
            acc = Odometry::default();
        }
    }
    out
}

/// `a ⊕ d` for odometry increments (metres, degrees): `d` is in the frame reached by `a`.
fn compose(a: Odometry, d: Odometry) -> Odometry {
    let (s, c) = a.dtheta.to_radians().sin_cos();
    Odometry {
        dx: a.dx + c * d.dx - s * d.dy,
        dy: a.dy + s * d.dx + c * d.dy,
        dtheta: a.dtheta + d.dtheta,
    }
}

/// The text of one fitted parameter, as the map grammar writes it.
fn param_text(p: &ParamFit) -> String {
    let key = p.key.as_ref().map_or(String::new(), |k| format!("({k})"));
    format!("param {}{key} = {:.2} .. {:.2};", p.name, p.lo, p.hi)
}

/// `text` (whose syntax tree is `ast`) with every fitted parameter written in, and each fitted
/// place's count of scans as `param scans = n;`: a parameter the place already has is replaced
/// in its span, a new one is added before the place's closing
/// brace (a place without braces gets them). Nothing else changes.
///
/// # Errors
/// [`SurveyError`] when a fitted place is not in the map or the spans do not fit the text.
pub fn write_params(text: &str, ast: &MapFile, fits: &[PlaceFit]) -> Result<String, SurveyError> {
    let places: BTreeMap<&str, _> = ast
        .items
        .iter()
        .filter_map(|i| match i {
            MapItem::Place(p) => Some((p.name.node.as_str(), p)),
            _ => None,
        })
        .collect();
    // (start, end, replacement), applied from the end so earlier spans stay valid.
    let mut edits: Vec<(usize, usize, String)> = Vec::new();
    for fit in fits {
        let decl = places
            .get(fit.place.as_str())
            .ok_or_else(|| SurveyError::UnknownPlace {
                place: fit.place.clone(),
            })?;
        let mut added = String::new();
        // The fitted ranges, then how many scans they stand on (the grid tracker weighs the
        // place's evidence by it).
        let texts = fit
            .params
            .iter()
            .map(|p| (p.name.as_str(), p.key.as_ref(), param_text(p)))
            .chain(std::iter::once((
                SCANS_PARAM,
                None,
                format!("param {SCANS_PARAM} = {};", fit.scans),
            )));
        for (param, param_key, written) in texts {
            let existing = decl.features.iter().find_map(|f| match f {
                Feature::Param {
                    name, key, span, ..
                } if name.node == param && key.as_ref().map(|k| &k.node) == param_key => {
                    Some((span.start, span.end))
                }
                _ => None,
            });
            match existing {
                Some((start, end)) => edits.push((start, end, written)),
                None => {
                    added.push(' ');
                    added.push_str(&written);
                }
            }
        }
        if added.is_empty() {
            continue;
        }
        let end = decl.span.end;
        match text.get(..end).and_then(|t| t.chars().next_back()) {
            Some('}') => edits.push((end - 1, end - 1, format!("{added} "))),
            Some(';') => edits.push((end - 1, end, format!(" {{{added} }}"))),
            _ => return Err(SurveyError::SpanMismatch { at: end }),
        }
    }
    edits.sort_by(|a, b| b.0.cmp(&a.0).then(b.1.cmp(&a.1)));
    let mut out = text.to_owned();
    for (start, end, with) in edits {
        if !(start <= end && out.is_char_boundary(start) && out.is_char_boundary(end)) {
            return Err(SurveyError::SpanMismatch { at: start });
        }
        out.replace_range(start..end, &with);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::record::{Odometry, PerceptRecord};
    use crate::syntax::{parse_map, parse_rules};

    fn frame(dx: f64, percepts: &[(&str, &str, f64)]) -> FrameRecord {
        FrameRecord {
            version: None,
            t: None,
            odometry: Some(Odometry {
                dx,
                dy: 0.0,
                dtheta: 0.0,
            }),
            heading: None,
            region: None,
            percepts: percepts
                .iter()
                .map(|&(name, arg, v)| PerceptRecord {
                    name: name.to_owned(),
                    args: if arg.is_empty() {
                        Vec::new()
                    } else {
                        vec![arg.to_owned()]
                    },
                    value: Some(v),
                    degree: 1.0,
                })
                .collect(),
            truth: None,
        }
    }

    #[test]
    fn links_come_from_the_rules_place_parameters() {
        let rules = parse_rules(
            "domain Dir = {North, South};\n\
             percept free_range(value, Dir, expect, time);\n\
             percept width(value, expect, time);\n\
             predicate fits(Dir, time);\n\
             |- (free_range(r, d, free_i(d), t) -> fits(d, t)) for all d in Dir;\n\
             |- (fits(North, t) * width(w, W_i, t)) -> at_place(P_i);\n",
        )
        .unwrap();
        let links = links_from_rules(&rules);
        let want = |p: &str, q: &str, keyed| ParamLink {
            percept: p.into(),
            param: q.into(),
            keyed,
        };
        assert_eq!(
            links,
            vec![want("free_range", "free", true), want("width", "W", false)]
        );
    }

    /// Percept `w` read against parameter `W`, unkeyed.
    fn w_link() -> [ParamLink; 1] {
        [ParamLink {
            percept: "w".into(),
            param: "W".into(),
            keyed: false,
        }]
    }

    /// Ten frames in A (values 1..=10, 0.1 m apart), three 1 m apart in B (value 50), then A
    /// again with `later`.
    fn a_b_a(later: &[f64]) -> (Vec<FrameRecord>, Vec<Option<String>>) {
        let mut frames = Vec::new();
        let mut labels = Vec::new();
        let a = (1..=10).map(f64::from).map(|v| (0.1, v, "A"));
        let b = std::iter::repeat((1.0, 50.0, "B")).take(3);
        let again = later.iter().map(|&v| (0.1, v, "A"));
        for (step, v, place) in a.chain(b).chain(again) {
            frames.push(frame(step, &[("w", "", v)]));
            labels.push(Some(place.to_owned()));
        }
        (frames, labels)
    }

    #[test]
    fn quantiles_by_nearest_rank_and_first_visits_hold_out_the_rest() {
        let links = w_link();
        // Ten frames in A (values 1..=10), 3 m elsewhere, five more in A (values 100).
        let (frames, labels) = a_b_a(&[100.0; 5]);
        let cfg = SurveyConfig::default();
        let v = visits(&frames, &labels, cfg.visit_gap_m);
        assert_eq!(v[9], Some(0));
        assert_eq!(v[10], Some(0));
        assert_eq!(v[13], Some(1));
        let first = fit(&frames, &labels, &links, Protocol::FirstVisits, &cfg);
        // A's first visit: 1..=10; ⌊0.1·9⌋ = 0 → 1, ⌊0.9·9⌋ = 8 → 9.
        assert_eq!(first[0].place, "A");
        assert_eq!(first[0].scans, 10);
        assert_eq!((first[0].params[0].lo, first[0].params[0].hi), (1.0, 9.0));
        // All frames: 1..=10 and five 100s (15 values): indices 1 and 12 → 2 and 100.
        let all = fit(&frames, &labels, &links, Protocol::All, &cfg);
        assert_eq!(all[0].scans, 15);
        assert_eq!((all[0].params[0].lo, all[0].params[0].hi), (2.0, 100.0));
    }

    #[test]
    fn later_visits_count_the_readings_within_the_first_visits_ranges() {
        let links = w_link();
        // A: first visit 1..=10 (fitted 1 .. 9), 3 m at B (one visit only), A again with five
        // readings of which 5 and 9 lie within 1 .. 9 (the ends count) and a NaN is no reading.
        let (frames, labels) = a_b_a(&[5.0, 100.0, 9.0, 0.5, 9.5, f64::NAN]);
        let cfg = SurveyConfig::default();
        let first = fit(&frames, &labels, &links, Protocol::FirstVisits, &cfg);
        assert_eq!((first[0].params[0].lo, first[0].params[0].hi), (1.0, 9.0));
        let later = later_within(&frames, &labels, &links, &first, cfg.visit_gap_m);
        assert_eq!(later, vec![Some((2, 5)), None]);
        // A parameter the fit does not have is no reading either.
        let other = [ParamLink {
            percept: "w".into(),
            param: "X".into(),
            keyed: false,
        }];
        let none = later_within(&frames, &labels, &other, &first, cfg.visit_gap_m);
        assert_eq!(none, vec![Some((0, 0)), None]);
    }

    #[test]
    fn thinning_composes_the_odometry() {
        // 1 m forward and a quarter turn left, then 1 m and 0.5 m forward: (1, 1.5) facing
        // North.
        let mut a = frame(1.0, &[]);
        a.odometry = Some(Odometry {
            dx: 1.0,
            dy: 0.0,
            dtheta: 90.0,
        });
        let frames = vec![frame(0.0, &[]), a, frame(1.0, &[]), frame(0.5, &[])];
        let t = thin(&frames, 3);
        assert_eq!(t.len(), 2);
        let o = t[1].odometry.unwrap();
        assert!(
            (o.dx - 1.0).abs() < 1e-12 && (o.dy - 1.5).abs() < 1e-12,
            "{o:?}"
        );
        assert!((o.dtheta - 90.0).abs() < 1e-12);
        assert_eq!(thin(&frames, 1), frames);
    }

    #[test]
    fn writing_edits_only_the_parameters() {
        let text = "// a comment\nmap m;\n\
                    place A corridor at (0, 0) extent box (0, 0, 2, 1) {\n    wall North; // kept\n    param W = 9 .. 9;\n}\n\
                    place B corridor at (3, 0) extent radius 1; // no body\n\
                    place C corridor at (5, 0) { wall South; }\n\
                    path A -- B;\n";
        let ast = parse_map(text).unwrap();
        let fit = |place: &str, key: Option<&str>| PlaceFit {
            place: place.into(),
            scans: 10,
            params: vec![ParamFit {
                name: if key.is_some() { "free" } else { "W" }.into(),
                key: key.map(Into::into),
                lo: 1.234,
                hi: 2.0,
                samples: 10,
            }],
        };
        let out = write_params(
            text,
            &ast,
            &[fit("A", None), fit("B", None), fit("C", Some("North"))],
        )
        .unwrap();
        let want = "// a comment\nmap m;\n\
                    place A corridor at (0, 0) extent box (0, 0, 2, 1) {\n    wall North; // kept\n    param W = 1.23 .. 2.00;\n param scans = 10; }\n\
                    place B corridor at (3, 0) extent radius 1 { param W = 1.23 .. 2.00; param scans = 10; } // no body\n\
                    place C corridor at (5, 0) { wall South;  param free(North) = 1.23 .. 2.00; param scans = 10; }\n\
                    path A -- B;\n";
        assert_eq!(out, want);
        // The result parses, and writing the same fit again changes nothing.
        let again = write_params(&out, &parse_map(&out).unwrap(), &[fit("A", None)]).unwrap();
        assert_eq!(again, out);
        assert!(matches!(
            write_params(text, &ast, &[fit("Z", None)]),
            Err(SurveyError::UnknownPlace { .. })
        ));
    }
}
