//! Stream evaluation for Python: a whole stream at once ([`evaluate_columns`], reading ahead on
//! a second thread like `lplace eval`), or batch by batch ([`StreamBatches`], one thread, for
//! writing Parquet as it goes). Both step frames through the crate's [`StreamRun`], the loop
//! `lplace eval` uses, and hand back plain columns that `lplace/_eval.py` turns into a
//! `pyarrow.Table`.

use crate::engine::PyEngine;
use lplace::engine::tracker::TrackerConfig;
use lplace::engine::Frame;
use lplace::io::stream::{
    read_records, FrameMeta, LineError, ReadOutcome, Record, StreamFormat, StreamReader, Threads,
};
use lplace::logic::{Decision, Disoriented};
use lplace::report::summary::reason_name;
use lplace::report::StreamRun;
use numpy::PyArray1;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::io::BufRead;

/// Reason names in the order of the `reason` codes (the summary's names).
pub(crate) const REASONS: [&str; 4] = [
    "nothing_above_threshold",
    "too_close",
    "inconsistent",
    "no_places",
];

/// The code of a disoriented decision's reason: its index in [`REASONS`].
pub(crate) fn reason_code(why: &Disoriented) -> i8 {
    let name = reason_name(why);
    REASONS
        .iter()
        .position(|r| *r == name)
        .map_or(-1, |i| i as i8)
}

/// One column per decision field, one entry per accepted frame; rejections beside them.
#[derive(Default)]
struct EvalColumns {
    line: Vec<u64>,
    t: Vec<f64>,
    place: Vec<i32>,
    necessity: Vec<f64>,
    inconsistency: Vec<f64>,
    reason: Vec<i8>,
    truth: Vec<i32>,
    truth_known: Vec<bool>,
    rejected_line: Vec<u64>,
    rejected_column: Vec<Option<usize>>,
    rejected_kind: Vec<&'static str>,
    rejected_message: Vec<String>,
}

impl EvalColumns {
    fn len(&self) -> usize {
        self.line.len()
    }

    fn push(&mut self, d: Decision, inconsistency: f64, meta: &FrameMeta) {
        self.line.push(meta.line);
        self.t.push(meta.t.unwrap_or(f64::NAN));
        match d {
            Decision::Place { place, necessity } => {
                self.place.push(i32::try_from(place).unwrap_or(-1));
                self.necessity.push(necessity);
                self.reason.push(-1);
            }
            Decision::Disoriented(why) => {
                self.place.push(-1);
                self.necessity.push(f64::NAN);
                self.reason.push(reason_code(&why));
            }
        }
        self.inconsistency.push(inconsistency);
        let truth = meta
            .truth_place
            .filter(|_| meta.truth_known)
            .and_then(|k| i32::try_from(k).ok());
        self.truth.push(truth.unwrap_or(-1));
        self.truth_known.push(meta.truth_known);
    }

    fn reject(&mut self, e: &LineError) {
        self.rejected_line.push(e.line);
        self.rejected_column.push(e.reason.column());
        self.rejected_kind.push(e.reason.kind());
        self.rejected_message.push(e.reason.message());
    }

    fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let out = PyDict::new(py);
        out.set_item("line", PyArray1::from_vec(py, self.line))?;
        out.set_item("t", PyArray1::from_vec(py, self.t))?;
        out.set_item("place", PyArray1::from_vec(py, self.place))?;
        out.set_item("necessity", PyArray1::from_vec(py, self.necessity))?;
        out.set_item("inconsistency", PyArray1::from_vec(py, self.inconsistency))?;
        out.set_item("reason", PyArray1::from_vec(py, self.reason))?;
        out.set_item("truth", PyArray1::from_vec(py, self.truth))?;
        out.set_item("truth_known", PyArray1::from_vec(py, self.truth_known))?;
        out.set_item("rejected_line", self.rejected_line)?;
        out.set_item("rejected_column", self.rejected_column)?;
        out.set_item("rejected_kind", self.rejected_kind)?;
        out.set_item("rejected_message", self.rejected_message)?;
        Ok(out)
    }
}

/// The input of an evaluation: a file, or the bytes of a stream given in memory.
fn open_input(
    path: Option<std::path::PathBuf>,
    data: Option<Vec<u8>>,
    format: Option<&str>,
) -> PyResult<(Box<dyn BufRead + Send + Sync>, StreamFormat)> {
    let format = match format {
        Some("jsonl") => Some(StreamFormat::JsonLines),
        Some("csv") => Some(StreamFormat::Csv),
        None => None,
        Some(other) => {
            return Err(PyValueError::new_err(format!(
                "format must be \"jsonl\" or \"csv\", not {other:?}"
            )))
        }
    };
    match (path, data) {
        (Some(p), None) => {
            let f = std::fs::File::open(&p)?;
            if f.metadata()?.is_dir() {
                return Err(PyOSError::new_err(format!(
                    "{}: is a directory",
                    p.display()
                )));
            }
            let format = format.unwrap_or_else(|| StreamFormat::from_path(&p));
            Ok((
                Box::new(std::io::BufReader::with_capacity(1 << 16, f)),
                format,
            ))
        }
        (None, Some(bytes)) => Ok((
            Box::new(std::io::Cursor::new(bytes)),
            format.unwrap_or(StreamFormat::JsonLines),
        )),
        _ => Err(PyValueError::new_err("give exactly one of path and data")),
    }
}

/// The tracker configuration from RON text, else the rule file's `tracker { … }` block (or
/// the defaults), as `lplace eval`; `track = False` turns tracking off.
fn tracker_config(
    track: bool,
    ron: Option<&str>,
    engine: &lplace::engine::Engine,
) -> PyResult<Option<TrackerConfig>> {
    if !track {
        return Ok(None);
    }
    match ron {
        None => Ok(Some(engine.tracker_config())),
        Some(text) => TrackerConfig::from_ron(text)
            .map(Some)
            .map_err(|e| PyValueError::new_err(e.to_string())),
    }
}

/// Evaluates a whole stream (`path`, or `data` in memory) with the GIL released, reading ahead
/// on a second thread when there is a core for it. Returns the columns (see `EvalColumns`),
/// plus `summary_json` (`lplace eval --summary json`'s text) and `places`.
#[pyfunction]
#[pyo3(signature = (engine, path = None, data = None, format = None, track = true, tracker = None, read_ahead = true))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn evaluate_columns<'py>(
    py: Python<'py>,
    engine: &PyEngine,
    path: Option<std::path::PathBuf>,
    data: Option<Vec<u8>>,
    format: Option<&str>,
    track: bool,
    tracker: Option<&str>,
    read_ahead: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let (input, format) = open_input(path, data, format)?;
    let mut run = StreamRun::new(
        engine.engine.clone(),
        tracker_config(track, tracker, &engine.engine)?,
    );
    let reader = StreamReader::new(input, run.schema(), format);
    let threads = if read_ahead {
        Threads::available()
    } else {
        Threads::One
    };
    let result = py.allow_threads(|| {
        let mut cols = EvalColumns::default();
        read_records(
            reader,
            threads,
            |_| {},
            |e| e,
            |record| {
                match record {
                    Record::Rejected(e) => {
                        run.reject(&e.reason);
                        cols.reject(&e);
                    }
                    Record::Frame(frame, meta) => {
                        let d = run.step(frame, meta);
                        cols.push(d, run.distribution().inconsistency, meta);
                    }
                }
                Ok(())
            },
        )
        .map(|()| cols)
    });
    let cols = result?;
    let summary = serde_json::to_string_pretty(&run.summary())
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let out = cols.into_dict(py)?;
    out.set_item("summary_json", summary)?;
    out.set_item("places", run.places().to_vec())?;
    Ok(out)
}

/// A stream evaluated batch by batch on the calling thread (GIL released per batch), so that a
/// caller can write each batch out before reading the next: memory stays flat on any length.
#[pyclass(module = "lplace._lplace")]
pub struct StreamBatches {
    reader: StreamReader<Box<dyn BufRead + Send + Sync>>,
    run: StreamRun,
    frame: Frame,
    meta: FrameMeta,
    done: bool,
}

#[pymethods]
impl StreamBatches {
    #[new]
    #[pyo3(signature = (engine, path = None, data = None, format = None, track = true, tracker = None))]
    fn new(
        engine: &PyEngine,
        path: Option<std::path::PathBuf>,
        data: Option<Vec<u8>>,
        format: Option<&str>,
        track: bool,
        tracker: Option<&str>,
    ) -> PyResult<Self> {
        let (input, format) = open_input(path, data, format)?;
        let run = StreamRun::new(
            engine.engine.clone(),
            tracker_config(track, tracker, &engine.engine)?,
        );
        let reader = StreamReader::new(input, run.schema(), format);
        let frame = Frame::new(reader.schema().slots());
        Ok(StreamBatches {
            reader,
            run,
            frame,
            meta: FrameMeta::default(),
            done: false,
        })
    }

    /// Place names, in the order of the `place` and `truth` codes.
    #[getter]
    fn places(&self) -> Vec<String> {
        self.run.places().to_vec()
    }

    /// The next batch of at most `max_frames` frames (and the rejections met on the way) as
    /// columns, or `None` when the stream has ended.
    fn next_batch<'py>(
        &mut self,
        py: Python<'py>,
        max_frames: usize,
    ) -> PyResult<Option<Bound<'py, PyDict>>> {
        if self.done {
            return Ok(None);
        }
        let max = max_frames.max(1);
        let (reader, run, frame, meta) = (
            &mut self.reader,
            &mut self.run,
            &mut self.frame,
            &mut self.meta,
        );
        let (cols, end) = py.allow_threads(|| {
            let mut cols = EvalColumns::default();
            while cols.len() < max {
                match reader.next_frame(frame, meta) {
                    Ok(ReadOutcome::Frame) => {
                        let d = run.step(frame, meta);
                        cols.push(d, run.distribution().inconsistency, meta);
                    }
                    Ok(ReadOutcome::Rejected(e)) => {
                        run.reject(&e.reason);
                        cols.reject(&e);
                    }
                    Ok(ReadOutcome::End) => return (cols, Some(Ok(()))),
                    Err(e) => return (cols, Some(Err(e))),
                }
            }
            (cols, None)
        });
        match end {
            Some(Err(e)) => {
                self.done = true;
                return Err(e.into());
            }
            Some(Ok(())) => self.done = true,
            None => {}
        }
        if self.done && cols.len() == 0 && cols.rejected_line.is_empty() {
            return Ok(None);
        }
        cols.into_dict(py).map(Some)
    }

    /// The summary so far, as `lplace eval --summary json` prints it.
    fn summary_json(&self) -> PyResult<String> {
        serde_json::to_string_pretty(&self.run.summary())
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }
}
