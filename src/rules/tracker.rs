//! The `tracker { … }` block of a rule file: the tracker settings that go with a kind of sensor
//! (a rule file is written per sensor kind, not per building), so that `eval`, `report` and
//! `survey` need no tracker file. This module checks the keys and values against the fields of
//! the tracker configuration and their ranges; `engine::tracker` turns the checked settings
//! into its `TrackerConfig` (this layer sits below `engine` and cannot name it).

use crate::syntax::ast::{Setting, SettingValue, TrackerBlock};
use crate::syntax::diagnostic::{Diagnostic, DiagnosticKind};
use crate::syntax::span::Span;
use crate::syntax::suggest::suggest;
use std::collections::BTreeMap;

/// A checked tracker setting's value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TrackerValue {
    /// A number within the key's range.
    Number(f64),
    /// One of the key's words (`product`, `true`, …).
    Word(&'static str),
}

/// The checked `tracker { … }` block: each key given, with its value.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TrackerSettings {
    /// The settings outside `grid { … }`, by key.
    pub fields: BTreeMap<&'static str, TrackerValue>,
    /// The `grid { … }` block's settings, if the block is there (even empty: it asks for the
    /// grid tracker with its defaults).
    pub grid: Option<BTreeMap<&'static str, f64>>,
}

/// What a key accepts.
#[derive(Debug, Clone, Copy)]
enum Kind {
    /// A number in `[0, 1]`.
    Unit,
    /// A finite number `≥ 0`.
    Length,
    /// A finite number `> 0`.
    Positive,
    /// One of these words, as the diagnostic lists them.
    Words(&'static [&'static str], &'static str),
}

/// The keys of `tracker { … }`: the fields of `engine::tracker::TrackerConfig` but `grid`, with
/// the ranges its `validate` checks.
pub const TRACKER_KEYS: &[&str] = &[
    "bias",
    "tnorm",
    "tolerance",
    "tolerance_rel",
    "slope",
    "slope_rel",
    "anchor_support",
    "min_support",
    "hold",
    "normalisation",
    "conflict",
    "use_heading",
    "tolerance_d",
    "tolerance_d_rel",
    "slope_d",
    "slope_d_rel",
    "evidence_length_m",
    "horizon_m",
];

/// The keys of `grid { … }`: the fields of `engine::grid_tracker::GridTrackConfig`.
pub const GRID_KEYS: &[&str] = &[
    "cell_size",
    "margin",
    "flank",
    "flank_per_metre",
    "floor",
    "evidence_length_m",
    "evidence_max_weight",
    "evidence_scans",
    "relative_floor",
    "start_radius",
];

fn tracker_kind(key: &str) -> Kind {
    match key {
        "bias" | "anchor_support" | "min_support" | "hold" | "conflict" => Kind::Unit,
        "tnorm" => Kind::Words(
            &["min", "product", "lukasiewicz"],
            "min, product or lukasiewicz",
        ),
        "normalisation" => Kind::Words(&["min", "product"], "min or product"),
        "use_heading" => Kind::Words(&["true", "false"], "true or false"),
        _ => Kind::Length,
    }
}

fn grid_kind(key: &str) -> Kind {
    match key {
        "cell_size" => Kind::Positive,
        "floor" | "relative_floor" => Kind::Unit,
        _ => Kind::Length,
    }
}

/// Checks `block` (the first of the file's tracker blocks); problems go to `diags`.
pub(super) fn check_tracker(block: &TrackerBlock, diags: &mut Vec<Diagnostic>) -> TrackerSettings {
    let mut out = TrackerSettings {
        fields: settings(&block.settings, TRACKER_KEYS, tracker_kind, diags),
        grid: None,
    };
    for (i, (grid, span)) in block.grids.iter().enumerate() {
        if i > 0 {
            diags.push(duplicate("grid block", "grid", *span, block.grids[0].1));
            continue;
        }
        let values = settings(grid, GRID_KEYS, grid_kind, diags);
        let numbers = values.into_iter().filter_map(|(k, v)| match v {
            TrackerValue::Number(x) => Some((k, x)),
            TrackerValue::Word(_) => None,
        });
        out.grid = Some(numbers.collect());
    }
    out
}

fn duplicate(what: &'static str, name: &str, at: Span, first: Span) -> Diagnostic {
    Diagnostic::error(
        DiagnosticKind::DuplicateName {
            what,
            name: name.to_string(),
        },
        at,
    )
    .with_related(first, "first defined here")
}

/// The settings of one block whose keys are `keys`, each value checked against `kind(key)`.
fn settings(
    list: &[Setting],
    keys: &'static [&'static str],
    kind: fn(&str) -> Kind,
    diags: &mut Vec<Diagnostic>,
) -> BTreeMap<&'static str, TrackerValue> {
    let mut out = BTreeMap::new();
    let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
    for s in list {
        let written = s.key.node.as_str();
        let Some(key) = keys.iter().copied().find(|k| *k == written) else {
            diags.push(
                Diagnostic::error(
                    DiagnosticKind::UnknownTrackerSetting {
                        key: written.to_string(),
                    },
                    s.key.span,
                )
                .with_suggestion(suggest(written, keys.iter().copied())),
            );
            continue;
        };
        if let Some(first) = seen.get(key) {
            diags.push(duplicate("setting", key, s.key.span, *first));
            continue;
        }
        seen.insert(key, s.key.span);
        match value(&s.value.node, kind(key)) {
            Ok(v) => {
                out.insert(key, v);
            }
            Err(expected) => diags.push(Diagnostic::error(
                DiagnosticKind::BadTrackerValue {
                    key: key.to_string(),
                    expected,
                },
                s.value.span,
            )),
        }
    }
    out
}

/// The value if it fits `kind`, else what the key expects.
fn value(v: &SettingValue, kind: Kind) -> Result<TrackerValue, &'static str> {
    match (kind, v) {
        (Kind::Words(words, expected), SettingValue::Word(w)) => words
            .iter()
            .find(|x| **x == w.as_str())
            .map(|x| TrackerValue::Word(x))
            .ok_or(expected),
        (Kind::Words(_, expected), SettingValue::Number(_)) => Err(expected),
        (Kind::Unit, SettingValue::Number(x)) if (0.0..=1.0).contains(x) => {
            Ok(TrackerValue::Number(*x))
        }
        (Kind::Length, SettingValue::Number(x)) if x.is_finite() && *x >= 0.0 => {
            Ok(TrackerValue::Number(*x))
        }
        (Kind::Positive, SettingValue::Number(x)) if x.is_finite() && *x > 0.0 => {
            Ok(TrackerValue::Number(*x))
        }
        (Kind::Unit, _) => Err("a number in [0, 1]"),
        (Kind::Length, _) => Err("a finite number ≥ 0"),
        (Kind::Positive, _) => Err("a finite number > 0"),
    }
}
