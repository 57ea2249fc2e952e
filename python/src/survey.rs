//! `lplace.survey`: the crate's [`Survey`] (what `lplace survey` runs) on files or bytes given
//! from Python, with its results handed back as plain values (the written map text, the
//! per-place report as columns, the held-out score as a dict) and rejected stream lines returned
//! rather than printed.

use crate::errors::check_error;
use lplace::engine::tracker::TrackerConfig;
use lplace::engine::{FileRole, LoadError, OFFICE_MAP, OFFICE_RULES};
use lplace::io::stream::StreamFormat;
use lplace::survey::{
    parse_labels, LabelRow, Protocol, Records, Survey, SurveyConfig, SurveyError, Truth,
};
use lplace::syntax::diagnostic::SourceFile;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// A text file as the command line reads it: not UTF-8 is a diagnostic (`CheckError`).
fn read_source(py: Python<'_>, path: &PathBuf, role: FileRole) -> PyResult<SourceFile> {
    let bytes = std::fs::read(path)?;
    match SourceFile::from_bytes(path.display().to_string(), bytes) {
        (file, None) => Ok(file),
        (file, Some(d)) => Err(check_error(
            py,
            &LoadError {
                role,
                file,
                diagnostics: vec![d],
            },
        )),
    }
}

/// A survey error as the exception the package raises for it.
fn survey_error(py: Python<'_>, map_name: &str, e: SurveyError) -> PyErr {
    match e {
        SurveyError::Load(e) => check_error(py, &e),
        SurveyError::UnknownPlace { .. } | SurveyError::SpanMismatch { .. } => {
            PyValueError::new_err(format!("{map_name}: {e}"))
        }
        other => PyValueError::new_err(other.to_string()),
    }
}

/// The ground truth: `labels_path` (a CSV `t,place`), `labels_rows` (pairs), or the records'.
fn label_rows(
    labels_path: Option<PathBuf>,
    labels_rows: Option<Vec<(f64, Option<String>)>>,
) -> PyResult<Option<Vec<LabelRow>>> {
    match (labels_path, labels_rows) {
        (Some(_), Some(_)) => Err(PyValueError::new_err(
            "give labels as a path or as rows, not both",
        )),
        (Some(path), None) => {
            let text = std::fs::read_to_string(&path)?;
            parse_labels(&text).map(Some).map_err(|e| match e {
                SurveyError::LabelRow { line } => {
                    PyValueError::new_err(format!("{}:{line}: expected `t,place`", path.display()))
                }
                other => PyValueError::new_err(other.to_string()),
            })
        }
        (None, Some(rows)) => Ok(Some(
            rows.into_iter()
                .map(|(t, place)| LabelRow { t, place })
                .collect(),
        )),
        (None, None) => Ok(None),
    }
}

/// The records of the stream at `path` (CSV by its extension) or in `data` (JSON Lines), read
/// by the survey's stream reader, as `lplace survey` reads them.
fn records(survey: &Survey, path: Option<PathBuf>, data: Option<Vec<u8>>) -> PyResult<Records> {
    match (path, data) {
        (Some(p), None) => {
            let f = std::fs::File::open(&p)?;
            let format = StreamFormat::from_path(&p);
            Ok(survey.read_records(std::io::BufReader::new(f), format)?)
        }
        (None, Some(bytes)) => {
            Ok(survey.read_records(std::io::Cursor::new(bytes), StreamFormat::JsonLines)?)
        }
        _ => Err(PyValueError::new_err("give exactly one of path and data")),
    }
}

/// Runs a survey as `lplace survey` does. `map_path`/`rules_path` both `None` = the bundled
/// office; `tracker` is RON text. Returns a dict with `map_text`, the report columns `place`,
/// `scans`, `spread`, `warning`, `held_out` (a dict, or `None` unless `first_visits`) and the
/// rejected lines as `rejected_line`, `rejected_kind`, `rejected_message`.
#[pyfunction]
#[pyo3(signature = (map_path = None, rules_path = None, path = None, data = None, labels_path = None, labels_rows = None, first_visits = false, tracker = None, lo = 0.1, hi = 0.9, min_scans = 10))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn survey_run<'py>(
    py: Python<'py>,
    map_path: Option<PathBuf>,
    rules_path: Option<PathBuf>,
    path: Option<PathBuf>,
    data: Option<Vec<u8>>,
    labels_path: Option<PathBuf>,
    labels_rows: Option<Vec<(f64, Option<String>)>>,
    first_visits: bool,
    tracker: Option<&str>,
    lo: f64,
    hi: f64,
    min_scans: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let (map, rules) = match (&map_path, &rules_path) {
        (Some(m), Some(r)) => (
            read_source(py, m, FileRole::Map)?,
            read_source(py, r, FileRole::Rules)?,
        ),
        (None, None) => (
            SourceFile::new("maps/office.map", OFFICE_MAP),
            SourceFile::new("rules/office.lpl", OFFICE_RULES),
        ),
        _ => return Err(PyValueError::new_err("give both map and rules, or neither")),
    };
    let map_name = map.name.clone();
    let cfg = SurveyConfig {
        lo,
        hi,
        min_scans,
        ..SurveyConfig::default()
    };
    let survey = Survey::new(map, rules, cfg).map_err(|e| survey_error(py, &map_name, e))?;
    let records = records(&survey, path, data)?;
    let labels = label_rows(labels_path, labels_rows)?;
    let protocol = if first_visits {
        Protocol::FirstVisits
    } else {
        Protocol::All
    };
    // Without one, the rule file's `tracker { … }` block (or the defaults), as `lplace survey`.
    let tracker = match tracker {
        None => None,
        Some(text) => {
            Some(TrackerConfig::from_ron(text).map_err(|e| PyValueError::new_err(e.to_string()))?)
        }
    };
    let truth = labels.as_deref().map_or(Truth::Records, Truth::Labels);
    let outcome = py
        .allow_threads(|| survey.run(&records.frames, truth, protocol, tracker.as_ref()))
        .map_err(|e| survey_error(py, &map_name, e))?;
    let d = PyDict::new(py);
    d.set_item("map_text", &outcome.map_text)?;
    let r = &outcome.report;
    d.set_item(
        "place",
        r.iter().map(|p| p.place.as_str()).collect::<Vec<_>>(),
    )?;
    d.set_item("scans", r.iter().map(|p| p.scans).collect::<Vec<_>>())?;
    d.set_item("spread", r.iter().map(|p| p.spread).collect::<Vec<_>>())?;
    d.set_item("warning", r.iter().map(|p| p.warning()).collect::<Vec<_>>())?;
    let held = match &outcome.held_out {
        None => None,
        Some(s) => {
            let h = PyDict::new(py);
            h.set_item("at_place", s.at_place)?;
            h.set_item("decided", s.decided)?;
            h.set_item("right", s.right)?;
            h.set_item("confidently_wrong", s.confidently_wrong)?;
            h.set_item("decided_rate", s.decided_rate())?;
            h.set_item("right_of_decided", s.right_of_decided())?;
            h.set_item("confidently_wrong_rate", s.confidently_wrong_rate())?;
            h.set_item("text", s.to_string())?;
            Some(h)
        }
    };
    d.set_item("held_out", held)?;
    let rej = &records.rejected;
    d.set_item(
        "rejected_line",
        rej.iter().map(|e| e.line).collect::<Vec<_>>(),
    )?;
    d.set_item(
        "rejected_column",
        rej.iter().map(|e| e.reason.column()).collect::<Vec<_>>(),
    )?;
    d.set_item(
        "rejected_kind",
        rej.iter().map(|e| e.reason.kind()).collect::<Vec<_>>(),
    )?;
    let messages: Vec<String> = rej.iter().map(|e| e.reason.message()).collect();
    d.set_item("rejected_message", messages)?;
    Ok(d)
}
